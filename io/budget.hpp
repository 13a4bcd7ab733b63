#pragma once
/// \file
/// Limits checked before cleave reads or builds anything large: input paths must be regular
/// files (a FIFO or a device would block or never end), and a specimen's grain count and
/// memory are estimated from its outline and grain size and refused above a limit (the
/// memory available now, or `--max-memory`) before a grain is allocated.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/specimen.hpp"
#include "io/scenario.hpp"

namespace cleave::io {

// ---- input files ------------------------------------------------------------------------

/// Why `path` cannot be read as an input file, or "" when it can: it must exist and be a
/// regular file once symbolic links are followed ("is a FIFO (named pipe)", "is a
/// directory", "does not exist", ...). Checked before opening, so that nothing blocks.
std::string input_file_problem(const std::filesystem::path& path);

/// Throws std::runtime_error "PATH: it REASON; cleave reads only regular files"
/// when input_file_problem finds one.
void require_input_file(const std::filesystem::path& path);

// ---- memory -----------------------------------------------------------------------------

/// The memory a specimen may take. `bytes` 0: no limit known (then only the grain cap holds).
struct MemoryLimit {
  std::uint64_t bytes = 0;
  std::string what;  ///< where it comes from, for messages ("--max-memory 4G", ...)
};

/// "4G", "512M", "1.5GiB", "300k", "1000000" (bytes): K, M, G, T are powers of 1024, an
/// optional trailing "B" or "iB" and any case allowed. Throws std::invalid_argument for
/// anything else, 0 or a size above 2^60.
std::uint64_t parse_memory_size(std::string_view text);

/// "3.2 GiB", "512 MiB", ... for messages.
std::string format_bytes(double bytes);

/// Sets the limit for this process (the CLI's --max-memory); `what` says where it comes from
/// ("--max-memory 4G"). Without it the limit is the memory available when a specimen is checked.
void set_memory_limit(std::uint64_t bytes, std::string what);

/// The limit in force: set_memory_limit's, else the memory available now (/proc/meminfo
/// MemAvailable, lowered to a cgroup's memory.max less its use; else the physical memory).
MemoryLimit memory_limit();

// ---- specimen estimate ------------------------------------------------------------------

/// At most this many grains in a specimen, whatever the memory (grain ids are 32-bit ints).
inline constexpr double kMaxGrains = 1e8;

/// Upper figures from peak RSS at two sizes each (cleave run, /usr/bin/time -v), so that a
/// run the estimate admits fits: the process itself; a grain of a run without [dynamics] (its
/// grain, slabs, meshes, tables); a grain of a dynamic run without contacts or bonds (the
/// same and its body); a contact point; a bond; a Voronoi or mesh grain's own exact cell and
/// slabs; a body of the validation's cubic lattice with its links.
inline constexpr double kBaseBytes = 64e6;
inline constexpr double kGrainBytes = 4e3;
inline constexpr double kBodyBytes = 6e3;
inline constexpr double kContactBytes = 520.0;
inline constexpr double kBondBytes = 700.0;
inline constexpr double kExactCellBytes = 72e3;
inline constexpr double kCubicBodyBytes = 2.5e3;
/// Contact points and bonds per grain a dense packing reaches (a bonded lattice of prisms,
/// its faces touching: 18.5 and 6.6 measured), assumed for the whole run.
inline constexpr double kContactsPerGrain = 20.0;
inline constexpr double kBondsPerGrain = 7.0;

/// The grains a honeycomb lattice specimen holds, from its outline and r, t alone (nothing is
/// built): rows and layers counted as honeycomb_sites places them, a disc by its area.
double lattice_grain_estimate(const geometry::SpecimenDef& def);

struct SpecimenEstimate {
  double grains = 0.0;
  double contacts = 0.0;
  double bonds = 0.0;
  double bytes = 0.0;
};

/// What the specimen of `s` will hold and take at its peak (grains, contact points, bonds,
/// bytes), before it is built.
SpecimenEstimate estimate_specimen(const Scenario& s);

/// A key that sets a specimen's size, where the file has it, as written.
struct SizeKey {
  std::string key;  ///< "specimen.size", "grain.r", ...
  SourcePosition at;
  std::string written;
};

/// Throws ScenarioError at the first of `keys` (their values all named) when the specimen
/// would hold no grain (a lattice outline smaller than a cell), more than kMaxGrains, or more
/// memory than memory_limit().
void check_specimen_budget(const Scenario& s, const std::vector<SizeKey>& keys);

/// The bytes the validation's cubic lattice of `bodies` bodies takes at its peak.
double cubic_lattice_bytes(double bodies);

}  // namespace cleave::io
