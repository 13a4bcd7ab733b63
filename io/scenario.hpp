#pragma once
/// \file
/// Scenario files (TOML, parsed with toml++). A scenario maps onto plain definition
/// structs with documented defaults; unknown keys, wrong types and impossible values are
/// errors that name the file, line, column and key.

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "geometry/specimen.hpp"
#include "io/mesh_io.hpp"

namespace cleave::io {

/// A scenario error: `what()` reads "FILE:LINE:COL: key 'table.key': message". Without a
/// position (missing or unreadable file) it reads "FILE: message"; without a key (TOML
/// syntax errors) the "key '...': " part is left out.
class ScenarioError : public std::runtime_error {
 public:
  ScenarioError(std::string file, int line, int column, std::string key, std::string message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& key() const { return key_; }  ///< dotted path, e.g. "grain.r_bar"

 private:
  std::string file_;
  int line_;
  int column_;
  std::string key_;
};

struct SplitDef {
  /// Cuts leaving a fragment below this fraction of its parent's volume are refused.
  double min_fragment_fraction = 0.01;
};

struct OutputDef {
  MeshFormat mesh_format = MeshFormat::obj;
  MeshLayout mesh_layout = MeshLayout::scene;
};

struct Scenario {
  std::string source;            ///< file path (or a name for in-memory text)
  std::string name;              ///< [scenario] name, default: the file stem
  std::string description;       ///< [scenario] description
  std::string length_unit = "mm";  ///< unit of every length in the file: "m", "mm" or "um"
  geometry::SpecimenDef specimen;  ///< lengths converted to metres
  SplitDef split;
  OutputDef output;
};

/// Reads and validates a scenario file. Throws ScenarioError (file, line, key) for a
/// missing file, TOML syntax errors, unknown keys, wrong types and impossible values.
Scenario load_scenario(const std::filesystem::path& file);
/// The same for text in memory; `source` names it in errors.
Scenario parse_scenario(std::string_view text, const std::string& source);

}  // namespace cleave::io
