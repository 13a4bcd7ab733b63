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
/// half-written file under the final name. Throws std::runtime_error naming the file and the
/// system's reason ("No space left on device"); no `.tmp` is left behind.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Reads a whole file; throws std::runtime_error naming the file and the system's reason.
std::string read_file(const std::filesystem::path& path);

/// A scenario's name names its folder in results/: one plain component (no '/', '\\',
/// NUL or leading '.'), so that it cannot lead out of results/.
bool is_plain_folder_name(std::string_view name);

/// Who asks for a result folder: the new run's command and scenario, and what it may replace.
struct FolderClaim {
  std::string command = "run";  ///< as run.toml's provenance names it: run, sweep, validate
  std::string scenario_name;    ///< the new run's scenario name
  /// --replace: an earlier cleave result of another scenario or command, or a run that did
  /// not end (its process gone), may be replaced too. Files cleave did not write never are.
  bool replace = false;
  /// A restart continuing its own run in this folder: only unfinished writes are removed.
  bool restart = false;
};

/// What preparing a result folder removes, relative to it: the earlier cleave run's files
/// (its manifest's [files], run.toml and SHA256SUMS) and unfinished writes of a killed run
/// (`*.tmp` files and `.cleave-tmp-*` folders, which cleave's writers rename into place).
struct FolderPlan {
  std::vector<std::filesystem::path> files;
  std::vector<std::filesystem::path> leftovers;
};

/// cleave writes only in a folder it owns. Refuses (std::invalid_argument, naming the folder,
/// the file and why) before anything is written or removed: the file system's root, the home
/// folder, the working folder, something that is not a folder, a folder that holds files but
/// no cleave manifest (another program's), a run a live process is writing, and a file in an
/// earlier cleave result that its run did not write (not in its manifest, or changed since).
/// Without `claim.replace` also an earlier result of another scenario or command, an
/// interrupted run with a checkpoint (restart it) and a run that did not end. An earlier
/// finished, stopped or failed run of the same command and scenario is replaced. Returns what
/// clear_result_folder() then removes.
FolderPlan check_result_folder(const std::filesystem::path& out, const FolderClaim& claim);

/// Removes what `plan` lists below `out`, then the folders that held them and are now
/// empty. Throws std::runtime_error naming the path and the system's reason.
void clear_result_folder(const std::filesystem::path& out, const FolderPlan& plan);

/// Adds files written into a closed result folder after its run (a measurement's tables)
/// to its manifest and SHA256SUMS, so that they are the run's as well.
void add_to_manifest(const std::filesystem::path& dir, const std::vector<std::string>& files);

/// Whether a cleave process recorded in a `running` manifest (its host, pid and the pid's
/// start time) is alive on this machine. Another host's counts as alive; this very process
/// (an earlier Simulation of it left unfinished) does not.
bool recorded_process_alive(const std::string& host, const std::string& pid,
                            const std::string& pid_start);

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
  /// A restarted run's start mark (file-clock ticks; 0: run.toml's own time while running).
  std::int64_t started_ticks = 0;
  /// While `running`: the process writing the result (host, pid, pid's start time), so that
  /// a later run tells a live run from a killed one.
  std::string host, pid, pid_start;
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
