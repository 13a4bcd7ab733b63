#include "io/result_dir.hpp"

#include <fstream>
#include <sstream>
#include <toml++/toml.h>

namespace cleave::io {

void write_file_atomically(const std::filesystem::path& path, const std::string& content) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot open for writing");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw std::runtime_error(path.string() + ": write failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(path.string() + ": cannot rename into place: " + ec.message());
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot be read");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_manifest(const std::filesystem::path& dir, const Manifest& manifest) {
  toml::table facts;
  for (const auto& [k, v] : manifest.facts) facts.insert(k, v);
  toml::table root;
  root.insert("status", manifest.status);
  if (!manifest.reason.empty()) root.insert("reason", manifest.reason);
  root.insert("facts", std::move(facts));
  std::ostringstream out;
  out << "# cleave result manifest: written last; status = \"finished\" marks a complete run\n"
      << root << '\n';
  write_file_atomically(dir / kManifestName, out.str());
}

Manifest read_manifest(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / kManifestName;
  if (!std::filesystem::exists(path)) {
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
  if (const auto* facts = root["facts"].as_table()) {
    for (const auto& [k, v] : *facts) m.facts[std::string(k.str())] = v.value_or(std::string{});
  }
  return m;
}

}  // namespace cleave::io
