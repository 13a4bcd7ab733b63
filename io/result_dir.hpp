#pragma once
/// \file
/// Result folders: files written under a temporary name and renamed when complete, and a
/// manifest (`run.toml`) that says what state the run is in and what it wrote.
///
/// A run writes `run.toml` with status "running" before anything else, and again at the
/// end with its final status: "finished", "stopped" (its step limit, --max-steps, ran out
/// before its stages ended; `reason` names the step and the stage), "interrupted"
/// (SIGINT/SIGTERM, what was done so far is written) or "failed" (with `reason`). The final
/// manifest lists every file the run wrote with its size and SHA-256 (`[files]`, and `SHA256SUMS`
/// for `sha256sum -c`), and its `[provenance]` says what produced it (versions, seed, scenario as
/// run).

#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace cleave::io {

/// Writes `content` to `path` through `path.tmp` + rename, so a reader never sees a
/// half-written file under the final name. Throws std::runtime_error naming the file.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Reads a whole file; throws std::runtime_error naming the file when it cannot.
std::string read_file(const std::filesystem::path& path);

/// A scenario's name names its folder in results/: one plain component (no '/', '\\',
/// NUL or leading '.'), so that it cannot lead out of results/.
bool is_plain_folder_name(std::string_view name);

/// cleave writes only in a folder it owns. Refuses (std::invalid_argument, naming the folder
/// and why) the file system's root, the home folder, the working folder, something that is
/// not a folder, and a folder that holds files but no cleave manifest (another program's),
/// before anything is written or removed there. A new or empty folder, or an earlier cleave
/// result, passes.
void check_result_folder(const std::filesystem::path& out);

/// The statuses a result folder's manifest can hold.
namespace run_status {
inline constexpr const char* running = "running";        ///< written at the start
inline constexpr const char* finished = "finished";      ///< complete: every stage ran
/// The step limit (--max-steps) ran out before the stages ended: the files are whole and
/// consistent up to that step, but the scenario did not run to its end (`reason`: the step
/// and the stage; facts stopped_at_step, stopped_in_stage).
inline constexpr const char* stopped = "stopped";
inline constexpr const char* interrupted = "interrupted";  ///< stopped by SIGINT/SIGTERM
inline constexpr const char* failed = "failed";          ///< stopped by an error (`reason`)
}  // namespace run_status

/// One file of a result folder: its path relative to the folder ('/'-separated), its size
/// and its SHA-256 (lowercase hex).
struct FileRecord {
  std::string path;
  std::uintmax_t bytes = 0;
  std::string sha256;
};

/// What `run.toml` records: status (run_status), why a run failed or stopped, what produced
/// the result (`provenance`: versions, seed, scenario), plain string facts (counts,
/// results), and the files written.
struct Manifest {
  std::string status;
  std::string reason;
  std::map<std::string, std::string> provenance;
  std::map<std::string, std::string> facts;
  std::vector<FileRecord> files;
};

constexpr const char* kManifestName = "run.toml";
/// The file list in `sha256sum -c` format, written next to the manifest.
constexpr const char* kChecksumsName = "SHA256SUMS";

/// Writes `dir/run.toml` (atomically) as it is; `files` are written as given.
void write_manifest(const std::filesystem::path& dir, const Manifest& manifest);
/// Reads `dir/run.toml`; throws std::runtime_error when it is missing or malformed.
Manifest read_manifest(const std::filesystem::path& dir);

/// SHA-256 of bytes / of a file's content, lowercase hex (OpenSSL's libcrypto). The file
/// version throws std::runtime_error naming the file when it cannot be read.
std::string sha256_hex(std::string_view bytes);
std::string sha256_file(const std::filesystem::path& path);

/// Every regular file under `dir` last written at or after `since` (so files left by an
/// earlier run in the same folder are not passed off as this run's), except the manifest,
/// SHA256SUMS and `*.tmp` leftovers; sorted by path, each hashed.
std::vector<FileRecord> list_result_files(const std::filesystem::path& dir,
                                          std::filesystem::file_time_type since);

/// The life of one result folder's manifest: `start` writes it with status "running" and
/// remembers when; `close` lists and hashes the files written since then, writes
/// SHA256SUMS and the manifest with its final status. `manifest` may be filled in between.
class ResultRecord {
 public:
  explicit ResultRecord(std::filesystem::path dir) : dir_(std::move(dir)) {}
  Manifest manifest;

  /// Writes run.toml with status "running" (the provenance known so far).
  void start();
  /// start() for a run restarted from a checkpoint: files written since `since` (the
  /// interrupted run's start mark, `started()`) belong to the run.
  void resume(std::filesystem::file_time_type since);
  /// When start() was called (file-system clock); a checkpoint keeps it for resume().
  [[nodiscard]] std::filesystem::file_time_type started() const { return started_; }
  /// Lists and hashes the files written since start(), writes SHA256SUMS and run.toml with
  /// the final status (run_status::finished, stopped, interrupted or failed) and reason. Throws
  /// std::runtime_error when they cannot be written.
  void close(const std::string& status, const std::string& reason = {});
  /// close() for a run that is already failing: reports nothing, returns false on error.
  bool close_quietly(const std::string& status, const std::string& reason) noexcept;

 private:
  std::filesystem::path dir_;
  std::filesystem::file_time_type started_{};
};

}  // namespace cleave::io
