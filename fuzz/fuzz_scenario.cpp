/// \file
/// libFuzzer target: io::parse_scenario on arbitrary text.
/// Expected for bad input: io::ScenarioError (file, line, key). Anything else escaping --
/// another exception type, a crash, a sanitizer report, a hang -- is a bug.
/// The text is parsed as if it were the file scenarios/fuzz.toml, so [[mesh_grain]] tables
/// of the seeds resolve meshes/... against the repository's scenarios/ folder.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string source = std::string(CLEAVE_SOURCE_DIR) + "/scenarios/fuzz.toml";
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    cleave::io::Scenario s = cleave::io::parse_scenario(text, source);
    (void)s;
  } catch (const cleave::io::ScenarioError&) {
  }
  return 0;
}
