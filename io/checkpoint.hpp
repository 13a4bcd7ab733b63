#pragma once
/// \file
/// Checkpoints of a dynamic run: everything needed to continue it bit for bit.
///
/// File layout (little-endian):
///   bytes 0..7    magic "CLEAVECK"
///   bytes 8..11   format version (kCheckpointVersion)
///   bytes 12..15  reserved (0)
///   bytes 16..23  payload length N
///   bytes 24..    payload (N bytes):
///                   meta: cleave version, scenario source and text, --max-steps, the
///                         result folder's start mark
///                   world: physics::World::save_state (bodies, forces, walls, bonds with
///                          stored overlaps, contact histories, pair offsets, Verlet list)
///                   book: present flag, then the FractureBook (exact shapes as the text of
///                         io/exact_store.hpp, exact planes as ExactPlane text, lineages,
///                         candidate planes, cuts made)
///                   run: the run loop's own state (sim/dynamics.cpp: stage, steps in
///                        it, histories written so far), opaque here
///   last 64 bytes SHA-256 of everything before it, lowercase hex
/// Exact numbers are written as exact rationals; doubles as their bit patterns.
///
/// Files are written to NAME.tmp, flushed to disk and renamed over NAME, so NAME is always
/// the last complete checkpoint. Reading checks length, magic, version and checksum before
/// decoding anything, and every error (CheckpointError) names the file and what is wrong:
/// "truncated at byte N", "checksum mismatch", "version 3 not supported".

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "physics/transgranular/fracture_book.hpp"
#include "physics/dem/world.hpp"

namespace cleave::io {

inline constexpr std::uint32_t kCheckpointVersion = 4;  // 2: each bond's strength factor;
                                                        // 3: crack areas and the cuts' times;
                                                        // 4: each bond's stiffness factor
inline constexpr std::string_view kCheckpointMagic = "CLEAVECK";
/// The checkpoint's name in a result folder.
inline constexpr const char* kCheckpointName = "checkpoint";

class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a checkpoint records about the run besides its state.
struct CheckpointMeta {
  std::string cleave_version;
  std::string scenario_source;  ///< the scenario's path as given (mesh grains resolve from it)
  std::string scenario_text;    ///< its content, as run
  std::uint64_t max_steps = 0;  ///< --max-steps of the run (0: none)
  /// The result folder's start mark (ResultRecord::started, file-clock ticks): files written
  /// since then belong to the run, before and after a restart.
  std::int64_t started_ticks = 0;
};

struct Checkpoint {
  CheckpointMeta meta;
  physics::World world;
  std::optional<physics::FractureBook> book;
  std::string run_state;  ///< the run loop's own state (sim/dynamics.cpp)
};

/// The bytes of a checkpoint file.
std::string encode_checkpoint(const CheckpointMeta& meta, const physics::World& world,
                              const physics::FractureBook* book, std::string_view run_state);
/// Decodes the bytes of a checkpoint file; `source` names it in errors.
Checkpoint decode_checkpoint(std::string_view bytes, const std::string& source);

/// Writes `bytes` to `file` through `file.tmp`, fsync and rename: `file` is either the old
/// checkpoint or the new one, never a partial one. Throws CheckpointError naming the file.
void write_checkpoint_file(const std::filesystem::path& file, std::string_view bytes);
/// Reads and decodes `file` (a checkpoint, or a result folder holding one).
Checkpoint read_checkpoint(const std::filesystem::path& file);
/// `path` itself, or `path/checkpoint` when `path` is a folder.
std::filesystem::path checkpoint_file(const std::filesystem::path& path);

}  // namespace cleave::io
