#include "io/result_dir.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <cstdlib>
#include <array>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <toml++/toml.h>

namespace cleave::io {

namespace fs = std::filesystem;

void write_file_atomically(const fs::path& path, const std::string& content) {
  const fs::path tmp = path.string() + ".tmp";
  std::error_code ec;
  const auto give_up = [&](const std::string& why) {
    fs::remove(tmp, ec);  // no half-written file left behind
    throw std::runtime_error(path.string() + ": " + why);
  };
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot open for writing");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) give_up("write failed");
  }
  fs::rename(tmp, path, ec);
  if (ec) give_up("cannot rename into place: " + ec.message());
}

bool is_plain_folder_name(std::string_view name) {
  return !name.empty() && name.front() != '.' && name.find_first_of(std::string_view("/\\\0", 3)) == std::string_view::npos;
}

void check_result_folder(const fs::path& out) {
  std::error_code ec;
  const fs::path here = fs::weakly_canonical(fs::absolute(out), ec);
  const auto refuse = [&](const std::string& why) {
    throw std::invalid_argument("result folder " + out.string() + ": " + why +
                                "; give --out a new or empty folder (or an earlier cleave result)");
  };
  if (ec) refuse("cannot be resolved (" + ec.message() + ")");
  if (here == here.root_path()) refuse("is the file system's root");
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    if (here == fs::weakly_canonical(fs::path(home), ec)) refuse("is the home folder");
  }
  if (here == fs::weakly_canonical(fs::current_path(), ec)) refuse("is the working folder");
  if (!fs::exists(here, ec)) return;
  if (!fs::is_directory(here, ec)) refuse("exists and is not a folder");
  if (fs::is_empty(here, ec)) return;
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
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot be read");
  std::ostringstream ss;
  ss << in.rdbuf();
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
  if (!in) throw std::runtime_error(path.string() + ": cannot be read");
  Sha256 h;
  std::array<char, 1 << 16> buf;
  while (in) {
    in.read(buf.data(), buf.size());
    h.update(buf.data(), static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw std::runtime_error(path.string() + ": read failed");
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

void write_manifest(const fs::path& dir, const Manifest& manifest) {
  toml::table root;
  root.insert("status", manifest.status);
  if (!manifest.reason.empty()) root.insert("reason", manifest.reason);
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
  write_file_atomically(dir / kManifestName, out.str());
}

Manifest read_manifest(const fs::path& dir) {
  const fs::path path = dir / kManifestName;
  if (!fs::exists(path)) {
    throw std::runtime_error(dir.string() + " is not a cleave result folder (no " +
                             std::string(kManifestName) + ")");
  }
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

// ---- ResultRecord ---------------------------------------------------------------------------

void ResultRecord::start() {
  manifest.status = run_status::running;
  manifest.reason.clear();
  manifest.files.clear();
  write_manifest(dir_, manifest);
  // Files written from now on are this run's: the manifest's own time stamp is the mark
  // (the same file-system clock as theirs, so no skew between clocks).
  started_ = fs::last_write_time(dir_ / kManifestName);
}

void ResultRecord::resume(fs::file_time_type since) {
  manifest.status = run_status::running;
  manifest.reason.clear();
  manifest.files.clear();
  write_manifest(dir_, manifest);
  started_ = since;
}

void ResultRecord::close(const std::string& status, const std::string& reason) {
  manifest.status = status;
  manifest.reason = reason;
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
  try {  // at least the status, without the file list
    manifest.status = status;
    manifest.reason = reason;
    manifest.files.clear();
    write_manifest(dir_, manifest);
  } catch (...) {
  }
  return false;
}

}  // namespace cleave::io
