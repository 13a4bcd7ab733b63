/// \file
/// libFuzzer target: io::parse_validation_scenario on arbitrary text (the DCB/ENF/MMB
/// validation scenarios of scenarios/validation/). Expected for bad input:
/// io::ScenarioError; anything else escaping, a crash, a sanitizer report or a hang is a bug.

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/scenario.hpp"
#include "io/validation_scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    cleave::io::ValidationScenario s = cleave::io::parse_validation_scenario(text, "fuzz.toml");
    (void)s;
  } catch (const cleave::io::ScenarioError&) {
  }
  return 0;
}
