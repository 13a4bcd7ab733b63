#include "io/result_dir.hpp"
#include "io/budget.hpp"

#include <fcntl.h>
#include <openssl/evp.h>
#include <signal.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace cleave::io {

namespace fs = std::filesystem;

namespace {

/// "path: what: the system's reason".
std::runtime_error io_error(const fs::path& path, const std::string& what, int err) {
  return std::runtime_error(path.string() + ": " + what + ": " +
                            std::generic_category().message(err));
}

}  // namespace

void write_file_atomically(const fs::path& path, const std::string& content) {
  const fs::path tmp = path.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw io_error(path, "cannot open " + tmp.filename().string() + " for writing", errno);
  const auto give_up = [&](const std::string& what, int err) {
    ::close(fd);
    ::unlink(tmp.c_str());  // no half-written file left behind
    return io_error(path, what, err);
  };
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw give_up("cannot write", n < 0 ? errno : EIO);
    done += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw io_error(path, "cannot write", err);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw io_error(path, "cannot rename " + tmp.filename().string() + " into place", err);
  }
}

bool is_plain_folder_name(std::string_view name) {
  return !name.empty() && name.front() != '.' && name.find_first_of(std::string_view("/\\\0", 3)) == std::string_view::npos;
}

namespace {

/// The start time of process `pid` (field 22 of /proc/PID/stat), empty when unknown: with
/// the pid it names one process, whatever reuses the pid later.
std::string process_start(long pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(in, stat)) return {};
  const auto close = stat.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return {};
  std::istringstream fields(stat.substr(close + 2));
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i) {
    if (i == 22) return field;
  }
  return {};
}

std::string host_name() {
  std::array<char, 256> buf{};
  if (::gethostname(buf.data(), buf.size() - 1) != 0) return {};
  return buf.data();
}

/// cleave's writers write NAME.tmp (or a .cleave-tmp-* folder) and rename it into place:
/// one left over is an unfinished write of a killed run.
bool is_unfinished_write(const fs::directory_entry& e) {
  const std::string name = e.path().filename().string();
  std::error_code ec;
  if (e.is_symlink(ec)) return false;
  if (e.is_directory(ec)) return name.rfind(".cleave-tmp-", 0) == 0;
  return e.is_regular_file(ec) && e.path().extension() == ".tmp";
}

}  // namespace

bool recorded_process_alive(const std::string& host, const std::string& pid,
                            const std::string& pid_start) {
  if (pid.empty()) return false;         // an older manifest, or not running
  if (host != host_name()) return true;  // another machine's process: it cannot be asked
  long n = 0;
  try {
    n = std::stol(pid);
  } catch (const std::exception&) {
    return false;
  }
  // This very process: an earlier Simulation of it (Python) that was left unfinished.
  if (n == static_cast<long>(::getpid())) return false;
  if (n <= 0 || (::kill(static_cast<pid_t>(n), 0) != 0 && errno == ESRCH)) return false;
  const std::string now = process_start(n);
  return pid_start.empty() || now.empty() || now == pid_start;
}

FolderPlan check_result_folder(const fs::path& out, const FolderClaim& claim) {
  std::error_code ec;
  const fs::path here = fs::weakly_canonical(fs::absolute(out), ec);
  const auto refuse = [&](const std::string& why,
                          const std::string& advice =
                              "give --out a new or empty folder (or an earlier cleave result)") {
    throw std::invalid_argument("result folder " + out.string() + ": " + why + "; " + advice);
  };
  if (ec) refuse("cannot be resolved (" + ec.message() + ")");
  if (here == here.root_path()) refuse("is the file system's root");
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    if (here == fs::weakly_canonical(fs::path(home), ec)) refuse("is the home folder");
  }
  if (here == fs::weakly_canonical(fs::current_path(), ec)) refuse("is the working folder");
  FolderPlan plan;
  if (!fs::exists(here, ec)) return plan;
  if (!fs::is_directory(here, ec)) refuse("exists and is not a folder");
  if (fs::is_empty(here, ec)) return plan;
  bool ours = false;
  if (fs::is_regular_file(here / kManifestName, ec)) {
    std::ifstream in(here / kManifestName);
    std::string line;
    while (!ours && std::getline(in, line)) ours = line.rfind("cleave_version", 0) == 0;
  }
  if (!ours) {
    refuse("holds files but no cleave run.toml: it is not a cleave result, and cleave removes only what it "
           "wrote");
  }
  Manifest earlier;
  try {
    earlier = read_manifest(here);
  } catch (const std::exception& e) {
    refuse(std::string("its run.toml cannot be read (") + e.what() + ")",
           "move the folder away or choose another one");
  }
  const bool running = earlier.status == run_status::running;
  if (running && !earlier.pid.empty() && earlier.host != host_name()) {
    // Another machine's process cannot be asked (a shared file system, or a container
    // since replaced): the user says whether it is gone.
    if (!claim.replace) {
      refuse("a cleave process on host " + earlier.host + " (pid " + earlier.pid + ") may be writing it",
             "if that run is gone, pass --replace (Python: replace=True), or choose another folder");
    }
  } else if (running && recorded_process_alive(earlier.host, earlier.pid, earlier.pid_start)) {
    refuse("a cleave process (pid " + earlier.pid + " on " + earlier.host + ") is writing it now",
           "wait for it to end or stop it, or choose another folder");
  }

  // Unfinished writes of a killed run go, whatever else happens; nothing below them is read.
  std::vector<fs::path> others;
  for (auto it = fs::recursive_directory_iterator(here, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    const fs::path rel = it->path().lexically_relative(here);
    if (is_unfinished_write(*it)) {
      plan.leftovers.push_back(rel);
      if (it->is_directory(ec)) it.disable_recursion_pending();
    } else if (!it->is_directory(ec) || it->is_symlink(ec)) {
      others.push_back(rel);
    }
  }
  if (ec) refuse("cannot be listed (" + ec.message() + ")", "check its permissions");
  if (claim.restart) return plan;  // the run goes on in its folder: its files stay

  const std::string again = "continue it with `cleave restart " + out.string() + "`";
  const bool checkpoint = fs::is_regular_file(here / "checkpoint", ec);
  if (!claim.replace) {
    const std::string replace =
        "pass --replace (Python: replace=True) to replace it, or choose another folder";
    if (running) {
      refuse("holds a run that did not end (status running, its process gone)" +
                 std::string(checkpoint ? "; it has a checkpoint" : ""),
             checkpoint ? again + ", or " + replace : replace);
    }
    if (earlier.status == run_status::interrupted && checkpoint)
      refuse("holds an interrupted run with a checkpoint", again + ", or " + replace);
    const std::string command =
        earlier.provenance.count("command") ? earlier.provenance.at("command") : "";
    const std::string name =
        earlier.facts.count("scenario_name") ? earlier.facts.at("scenario_name") : "";
    if (command != claim.command || name != claim.scenario_name) {
      refuse("holds the result of another run (cleave " + (command.empty() ? "?" : command) +
                 " of scenario '" + (name.empty() ? "?" : name) + "', status " + earlier.status +
                 ")",
             replace);
    }
  }

  // What the earlier run wrote: its manifest's list, or for a run that did not close it the
  // files written since it started (what its close() would have listed).
  std::map<std::string, const FileRecord*> listed;
  for (const FileRecord& f : earlier.files) listed[f.path] = &f;
  const fs::file_time_type since =
      earlier.started_ticks != 0
          ? fs::file_time_type(fs::file_time_type::duration(earlier.started_ticks))
          : fs::last_write_time(here / kManifestName, ec);
  for (const fs::path& rel : others) {
    const std::string name = rel.generic_string();
    const fs::path path = here / rel;
    std::string why;
    if (name == kManifestName || name == kChecksumsName) {
      // the manifest's own files
    } else if (fs::is_symlink(fs::symlink_status(path, ec)) || !fs::is_regular_file(path, ec)) {
      why = "is not a plain file, and cleave writes only those";
    } else if (!earlier.files.empty()) {
      const auto it = listed.find(name);
      if (it == listed.end()) {
        why = "is not in its run.toml's [files]: the earlier cleave run did not write it";
      } else if (fs::file_size(path, ec) != it->second->bytes ||
                 sha256_file(path) != it->second->sha256) {
        why =
            "has changed since the earlier cleave run wrote it (its size or SHA-256 is not "
            "run.toml's)";
      }
    } else if (fs::last_write_time(path, ec) < since) {
      why =
          "is older than the earlier cleave run, which did not close its run.toml: it did not "
          "write it";
    }
    if (!why.empty()) {
      refuse("holds " + name + ", which " + why,
             "cleave removes only what it wrote: move that file away, or choose another folder");
    }
    plan.files.push_back(rel);
  }
  return plan;
}

void clear_result_folder(const fs::path& out, const FolderPlan& plan) {
  std::error_code ec;
  std::set<fs::path> parents;
  const auto drop = [&](const fs::path& rel, bool tree) {
    const fs::path p = out / rel;
    if (tree) {
      fs::remove_all(p, ec);
    } else {
      fs::remove(p, ec);
    }
    if (ec) throw io_error(p, "cannot remove it", ec.value());
    for (fs::path up = rel.parent_path(); !up.empty(); up = up.parent_path()) parents.insert(up);
  };
  for (const fs::path& rel : plan.leftovers) drop(rel, true);
  for (const fs::path& rel : plan.files) drop(rel, false);
  // The folders cleave made for them, deepest first, when nothing else is left in them.
  for (auto it = parents.rbegin(); it != parents.rend(); ++it) {
    const fs::path p = out / *it;
    if (fs::is_directory(p, ec) && fs::is_empty(p, ec)) fs::remove(p, ec);
  }
}

std::string read_file(const fs::path& path) {
  require_input_file(path);  // a FIFO or a device would block or never end
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error(path, "cannot be read", errno);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw io_error(path, "cannot be read", errno);
  return ss.str();
}

// ---- SHA-256 (OpenSSL EVP) ------------------------------------------------------------------

namespace {

/// An EVP SHA-256 context fed in pieces.
class Sha256 {
 public:
  Sha256() : ctx_(EVP_MD_CTX_new(), &EVP_MD_CTX_free) {
    if (!ctx_ || EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) != 1) {
      throw std::runtime_error("SHA-256: OpenSSL could not start a digest");
    }
  }
  void update(const void* data, std::size_t n) {
    if (EVP_DigestUpdate(ctx_.get(), data, n) != 1) throw std::runtime_error("SHA-256: update failed");
  }
  std::string hex() {
    std::array<unsigned char, EVP_MAX_MD_SIZE> md{};
    unsigned int n = 0;
    if (EVP_DigestFinal_ex(ctx_.get(), md.data(), &n) != 1) throw std::runtime_error("SHA-256: final failed");
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string out;
    for (unsigned int i = 0; i < n; ++i) {
      out += kDigits[md[i] >> 4];
      out += kDigits[md[i] & 15];
    }
    return out;
  }

 private:
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx_;
};

}  // namespace

std::string sha256_hex(std::string_view bytes) {
  Sha256 h;
  h.update(bytes.data(), bytes.size());
  return h.hex();
}

std::string sha256_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error(path, "cannot be read", errno);
  Sha256 h;
  std::array<char, 1 << 16> buf;
  while (in) {
    in.read(buf.data(), buf.size());
    h.update(buf.data(), static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw io_error(path, "cannot be read", errno);
  return h.hex();
}

std::vector<FileRecord> list_result_files(const fs::path& dir, fs::file_time_type since) {
  std::vector<FileRecord> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const fs::path rel = entry.path().lexically_relative(dir);
    const std::string name = rel.generic_string();
    if (name == kManifestName || name == kChecksumsName || rel.extension() == ".tmp") continue;
    if (entry.last_write_time() < since) continue;
    files.push_back({name, entry.file_size(), sha256_file(entry.path())});
  }
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
  return files;
}

// ---- the manifest ---------------------------------------------------------------------------

namespace {

std::string manifest_text(const Manifest& manifest) {
  toml::table root;
  root.insert("status", manifest.status);
  if (!manifest.reason.empty()) root.insert("reason", manifest.reason);
  if (manifest.started_ticks != 0) root.insert("started_file_time", manifest.started_ticks);
  if (manifest.status == run_status::running) {
    // Who is writing: a later run tells this live run from a killed one.
    const long pid = static_cast<long>(::getpid());
    root.insert("host", host_name());
    root.insert("pid", std::to_string(pid));
    root.insert("pid_start", process_start(pid));
  }
  toml::table provenance;
  for (const auto& [k, v] : manifest.provenance) provenance.insert(k, v);
  root.insert("provenance", std::move(provenance));
  toml::table facts;
  for (const auto& [k, v] : manifest.facts) facts.insert(k, v);
  root.insert("facts", std::move(facts));
  if (!manifest.files.empty()) {
    toml::array files;
    for (const FileRecord& f : manifest.files) {
      files.push_back(toml::table{{"path", f.path},
                                  {"bytes", static_cast<std::int64_t>(f.bytes)},
                                  {"sha256", f.sha256}});
    }
    root.insert("files", std::move(files));
  }
  std::ostringstream out;
  out << "# cleave result manifest: status = \"running\" while the run goes, then \"finished\", "
         "\"stopped\" (--max-steps), \"interrupted\" or \"failed\";\n# only \"finished\" marks a "
         "complete result. [[files]]: "
         "what the run wrote, with SHA-256 (also in SHA256SUMS).\n"
      << root << '\n';
  return out.str();
}

}  // namespace

void write_manifest(const fs::path& dir, const Manifest& manifest) {
  write_file_atomically(dir / kManifestName, manifest_text(manifest));
}

Manifest read_manifest(const fs::path& dir) {
  const fs::path path = dir / kManifestName;
  if (!fs::exists(path)) {
    throw std::runtime_error(dir.string() + " is not a cleave result folder (no " +
                             std::string(kManifestName) + ")");
  }
  require_input_file(path);
  toml::table root;
  try {
    root = toml::parse_file(path.string());
  } catch (const toml::parse_error& e) {
    throw std::runtime_error(path.string() + ":" + std::to_string(e.source().begin.line) + ": " +
                             std::string(e.description()));
  }
  Manifest m;
  m.status = root["status"].value_or(std::string{});
  m.reason = root["reason"].value_or(std::string{});
  m.started_ticks = root["started_file_time"].value_or(std::int64_t{0});
  m.host = root["host"].value_or(std::string{});
  m.pid = root["pid"].value_or(std::string{});
  m.pid_start = root["pid_start"].value_or(std::string{});
  if (m.status.empty()) throw std::runtime_error(path.string() + ": no status");
  for (auto [name, map] : {std::pair{"provenance", &m.provenance}, std::pair{"facts", &m.facts}}) {
    if (const auto* table = root[name].as_table()) {
      for (const auto& [k, v] : *table) (*map)[std::string(k.str())] = v.value_or(std::string{});
    }
  }
  if (const auto* files = root["files"].as_array()) {
    for (const auto& node : *files) {
      const auto* t = node.as_table();
      if (t == nullptr) {
        throw std::runtime_error(path.string() + ":" + std::to_string(node.source().begin.line) +
                                 ": key 'files': expected [[files]] tables");
      }
      FileRecord f;
      f.path = (*t)["path"].value_or(std::string{});
      f.bytes = static_cast<std::uintmax_t>((*t)["bytes"].value_or(std::int64_t{0}));
      f.sha256 = (*t)["sha256"].value_or(std::string{});
      m.files.push_back(std::move(f));
    }
  }
  return m;
}

void add_to_manifest(const fs::path& dir, const std::vector<std::string>& files) {
  Manifest m = read_manifest(dir);
  for (const std::string& name : files) {
    const fs::path path = dir / name;
    FileRecord f{name, fs::file_size(path), sha256_file(path)};
    const auto it = std::find_if(m.files.begin(), m.files.end(),
                                 [&](const FileRecord& r) { return r.path == name; });
    if (it != m.files.end()) {
      *it = std::move(f);
    } else {
      m.files.push_back(std::move(f));
    }
  }
  std::sort(m.files.begin(), m.files.end(),
            [](const auto& a, const auto& b) { return a.path < b.path; });
  std::string sums;
  for (const FileRecord& f : m.files) sums += f.sha256 + "  " + f.path + "\n";
  write_file_atomically(dir / kChecksumsName, sums);
  write_manifest(dir, m);
}

// ---- ResultRecord ---------------------------------------------------------------------------

void ResultRecord::start() {
  manifest.status = run_status::running;
  manifest.reason.clear();
  manifest.files.clear();
  manifest.started_ticks = 0;  // run.toml's own time, below
  write_manifest(dir_, manifest);
  // Files written from now on are this run's: the manifest's own time stamp is the mark
  // (the same file-system clock as theirs, so no skew between clocks).
  started_ = fs::last_write_time(dir_ / kManifestName);
}

void ResultRecord::resume(fs::file_time_type since) {
  manifest.status = run_status::running;
  manifest.reason.clear();
  manifest.files.clear();
  manifest.started_ticks = static_cast<std::int64_t>(since.time_since_epoch().count());
  write_manifest(dir_, manifest);
  started_ = since;
}

void ResultRecord::close(const std::string& status, const std::string& reason) {
  manifest.status = status;
  manifest.reason = reason;
  manifest.started_ticks = static_cast<std::int64_t>(started_.time_since_epoch().count());
  manifest.files = list_result_files(dir_, started_);
  std::string sums;
  for (const FileRecord& f : manifest.files) sums += f.sha256 + "  " + f.path + "\n";
  write_file_atomically(dir_ / kChecksumsName, sums);
  write_manifest(dir_, manifest);
}

bool ResultRecord::close_quietly(const std::string& status, const std::string& reason) noexcept {
  try {
    close(status, reason);
    return true;
  } catch (...) {
  }
  manifest.status = status;
  manifest.reason = reason;
  manifest.files.clear();
  try {  // at least the status, without the file list
    write_manifest(dir_, manifest);
    return false;
  } catch (...) {
  }
  try {
    // A full disk has no room for run.toml.tmp: overwrite run.toml in place with its gist,
    // no longer than its "running" text, so that it fits the blocks that text frees and
    // does not go on saying "running".
    Manifest gist;
    gist.status = status;
    gist.reason = reason.substr(0, 300);
    gist.started_ticks = manifest.started_ticks;
    for (const char* key : {"cleave_version", "command"}) {
      if (const auto it = manifest.provenance.find(key); it != manifest.provenance.end())
        gist.provenance.insert(*it);
    }
    for (const char* key : {"cleave_version", "scenario_name"}) {
      if (const auto it = manifest.facts.find(key); it != manifest.facts.end())
        gist.facts.insert(*it);
    }
    const std::string text = manifest_text(gist);
    const fs::path path = dir_ / kManifestName;
    std::error_code ec;
    const auto old_size = fs::file_size(path, ec);
    const int fd =
        ec || text.size() > old_size ? -1 : ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd >= 0) {
      std::size_t done = 0;
      while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
      }
      ::close(fd);
    }
  } catch (...) {
  }
  return false;
}

}  // namespace cleave::io
