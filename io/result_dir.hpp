#pragma once
/// \file
/// Result folders: files written under a temporary name and renamed when complete, and a
/// manifest (`run.toml`) written last that says whether the run finished.

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

namespace cleave::io {

/// Writes `content` to `path` through `path.tmp` + rename, so a reader never sees a
/// half-written file under the final name. Throws std::runtime_error naming the file.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Reads a whole file; throws std::runtime_error naming the file when it cannot.
std::string read_file(const std::filesystem::path& path);

/// What `run.toml` records: status ("finished" or "failed"), why a run failed, and plain
/// string facts (cleave version, scenario, counts, files).
struct Manifest {
  std::string status;
  std::string reason;
  std::map<std::string, std::string> facts;
};

constexpr const char* kManifestName = "run.toml";

void write_manifest(const std::filesystem::path& dir, const Manifest& manifest);
/// Reads `dir/run.toml`; throws std::runtime_error when it is missing or malformed.
Manifest read_manifest(const std::filesystem::path& dir);

}  // namespace cleave::io
