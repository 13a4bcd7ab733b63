/// \file
/// Calibration files (see calibration_file.hpp).

#include "io/calibration_file.hpp"

#include "io/material_library.hpp"
#include "io/toml_reader.hpp"

namespace cleave::io {

namespace {
using namespace toml_reader;
constexpr std::string_view kTables[] = {"calibration"};
constexpr std::string_view kKeys[] = {"preset", "elastic", "brazilian", "flexural", "senb", "tolerance", "flexural_tolerance", "max_trials"};
}  // namespace

CalibrationFile load_calibration(const std::filesystem::path& file) {
  const std::string source = file.string();
  const std::string text = read_scenario_text(file);
  const toml::table root = parse_root(text, source, kTables, "a calibration file");
  const TableReader t(source, "calibration", root.get_as<toml::table>("calibration"));
  if (t.table() == nullptr) throw ScenarioError(source, 1, 1, "calibration", "missing required table [calibration]");
  t.reject_unknown(kKeys);
  CalibrationFile c;
  c.source = source;
  const std::filesystem::path folder = file.parent_path();
  if (t.find("preset") != nullptr) {
    const std::string preset = t.string("preset");
    const auto found = resolve_material(preset, folder);
    if (!found) t.fail(*t.find("preset"), "preset", fmt::format("no material '{}' (`cleave materials` lists them)", preset));
    c.preset_file = found->string();
  }
  const std::pair<const char*, std::filesystem::path*> scenarios[] = {
      {"elastic", &c.elastic}, {"brazilian", &c.brazilian}, {"flexural", &c.flexural}, {"senb", &c.senb}};
  for (const auto& [key, path] : scenarios) {
    if (t.find(key) == nullptr) continue;
    const std::filesystem::path p = folder / t.string(key);
    if (!std::filesystem::is_regular_file(p)) {
      t.fail(*t.find(key), key, fmt::format("no scenario file {}", p.string()));
    }
    *path = p;
  }
  if (c.elastic.empty() && c.brazilian.empty() && c.senb.empty()) {
    t.fail_table("give the test scenarios to calibrate with: elastic = \"...\", brazilian = \"...\" "
                 "and/or senb = \"...\"");
  }
  if (!c.flexural.empty() && c.brazilian.empty()) {
    t.fail(*t.find("flexural"), "flexural",
           "a flexural test needs a brazilian one: sigma_f is fitted through t_bs / t_bn, with sigma_t");
  }
  c.tolerance = t.number("tolerance", Range{0.0, 0.5, true, true}, 0.02).value;
  c.max_trials = t.int_integer("max_trials", 1, 8);
  if (t.find("flexural_tolerance") != nullptr) {
    if (c.flexural.empty()) t.fail(*t.find("flexural_tolerance"), "flexural_tolerance", "there is no flexural test");
    c.flexural_tolerance = t.number("flexural_tolerance", Range{0.0, 0.5, true, true}, 0.02).value;
  }
  return c;
}

}  // namespace cleave::io
