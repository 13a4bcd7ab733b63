// `cleave calibrate FILE [--target KEY=VALUE ...]`: the bond parameters that make a bonded
// specimen's measured E, nu, sigma_t and sigma_f hit their targets (sim/calibrate.hpp). Writes every
// trial to DIR/calibration.csv, the fit to DIR/calibration.toml and the errors per trial to
// DIR/calibration.svg.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "commands.hpp"
#include "io/calibration_file.hpp"
#include "io/material_library.hpp"
#include "io/plot.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/toml_text.hpp"
#include "sim/calibrate.hpp"
#include "sim/simulation.hpp"

namespace cleave::app {

int calibrate_command(const CalibrateOptions& options) {
  sim::CalibrationSetup setup;
  try {
    const io::CalibrationFile file = io::load_calibration(options.file);
    setup.elastic = file.elastic;
    setup.brazilian = file.brazilian;
    setup.flexural = file.flexural;
    setup.senb = file.senb;
    setup.tolerance = options.tolerance.value_or(file.tolerance);
    setup.flexural_tolerance = options.tolerance ? options.tolerance : file.flexural_tolerance;
    setup.max_trials = file.max_trials;
    if (!file.preset_file.empty()) {
      const io::MaterialPreset m = io::load_material(file.preset_file);
      if (!file.elastic.empty()) {
        setup.targets.young = m.si("young");
        setup.targets.poisson = m.si("poisson");
      }
      if (!file.brazilian.empty()) setup.targets.tensile_strength = m.si("tensile_strength");
      if (!file.flexural.empty()) setup.targets.flexural_strength = m.si("flexural_strength");
      if (!file.senb.empty()) setup.targets.toughness = m.si("k_ic");
    }
  } catch (const io::ScenarioError& e) {
    fmt::print(stderr, "cleave calibrate: error: {}\n", e.what());
    return 2;
  }
  for (const std::string& t : options.targets) {
    const auto eq = t.find('=');
    char* end = nullptr;
    const double v = eq == std::string::npos ? NAN : std::strtod(t.c_str() + eq + 1, &end);
    if (eq == std::string::npos || end == t.c_str() + eq + 1 || *end != '\0' || !std::isfinite(v) || !(v > 0.0)) {
      fmt::print(stderr, "cleave calibrate: error: --target '{}': expected KEY=VALUE with a positive number "
                         "(E=415e9, nu=0.16, sigma_t=250e6, sigma_f=359e6, K_Ic=3.1e6)\n", t);
      return 2;
    }
    // Each target: its key, where it goes and the test scenario that measures it.
    struct Target {
      const char* key;
      std::optional<double>* value;
      const char* test;
      const std::filesystem::path* scenario;
    };
    const Target targets[] = {
        {"E", &setup.targets.young, "elastic", &setup.elastic},
        {"nu", &setup.targets.poisson, "elastic", &setup.elastic},
        {"sigma_t", &setup.targets.tensile_strength, "brazilian", &setup.brazilian},
        {"sigma_f", &setup.targets.flexural_strength, "flexural", &setup.flexural},
        {"K_Ic", &setup.targets.toughness, "senb", &setup.senb},
    };
    const std::string key = t.substr(0, eq);
    const auto target = std::find_if(std::begin(targets), std::end(targets),
                                     [&](const Target& x) { return key == x.key; });
    if (target == std::end(targets)) {
      fmt::print(stderr, "cleave calibrate: error: --target '{}': unknown target '{}'; the targets are E "
                         "(Pa), nu, sigma_t (Pa), sigma_f (Pa) and K_Ic (Pa m^0.5)\n", t, key);
      return 2;
    }
    *target->value = v;
    if (target->scenario->empty()) {
      fmt::print(stderr, "cleave calibrate: error: --target {}: {} names no {} test scenario\n", key,
                 options.file.string(), target->test);
      return 2;
    }
  }
  setup.out = options.out.empty() ? std::filesystem::path("results") / (options.file.stem().string()) : options.out;
  setup.quiet = options.quiet;
  // The calibration's folder is a result of its own (its trials' folders and tables, listed
  // in its run.toml): checked and cleared as `cleave run` does before anything is written.
  const std::string name = options.file.stem().string();
  io::FolderPlan plan;
  try {
    plan = io::check_result_folder(setup.out, io::FolderClaim{"calibrate", name, false, false});
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "cleave calibrate: error: command line: {}\n", e.what());
    return 2;
  }
  io::ResultRecord record(setup.out);
  record.manifest.provenance["cleave_version"] = sim::version();
  record.manifest.provenance["command"] = "calibrate";
  record.manifest.facts["cleave_version"] = sim::version();
  record.manifest.facts["scenario"] = options.file.string();
  record.manifest.facts["scenario_name"] = name;
  try {
    io::clear_result_folder(setup.out, plan);
    std::filesystem::create_directories(setup.out);
    record.start();
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave calibrate: error: {}\n", e.what());
    return 1;
  }
  if (!options.quiet) {
    std::vector<std::string> t;
    if (setup.targets.young) t.push_back(fmt::format("E = {:.4g} GPa", *setup.targets.young / 1e9));
    if (setup.targets.poisson) t.push_back(fmt::format("nu = {:.4g}", *setup.targets.poisson));
    if (setup.targets.tensile_strength)
      t.push_back(fmt::format("sigma_t = {:.4g} MPa", *setup.targets.tensile_strength / 1e6));
    if (setup.targets.flexural_strength)
      t.push_back(fmt::format("sigma_f = {:.4g} MPa (the bar's first crack, from statics)",
                              *setup.targets.flexural_strength / 1e6));
    if (setup.targets.toughness)
      t.push_back(fmt::format("K_Ic = {:.4g} MPa m^0.5 (the notched beam's first crack, from statics)",
                              *setup.targets.toughness / 1e6));
    fmt::print("cleave calibrate: {} -> {}\n  targets: {}", options.file.string(), setup.out.string(),
               fmt::join(t, ", "));
    if (setup.targets.flexural_strength && setup.flexural_tolerance)
      fmt::print(" (each within {:g} %, sigma_f within {:g} %)\n", 100 * setup.tolerance,
                 100 * *setup.flexural_tolerance);
    else
      fmt::print(" (each within {:g} %)\n", 100 * setup.tolerance);
    std::fflush(stdout);
  }
  sim::CalibrationResult r;
  try {
    r = sim::calibrate(setup);
  } catch (const io::ScenarioError& e) {
    fmt::print(stderr, "cleave calibrate: error: {}\n", e.what());
    record.close_quietly(io::run_status::failed, e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "cleave calibrate: error: {}\n", e.what());
    record.close_quietly(io::run_status::failed, e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave calibrate: error: {}\n", e.what());
    record.close_quietly(io::run_status::failed, e.what());
    return 1;
  }
  io::write_file_atomically(setup.out / "calibration.csv", sim::calibration_csv(r));
  std::string toml = fmt::format("converged = {}\ntrials = {}\nwall_seconds = {:.1f}\ntolerance = {}\n",
                                 r.converged ? "true" : "false", r.trials.size(), r.wall_seconds,
                                 setup.tolerance);
  if (setup.targets.flexural_strength && setup.flexural_tolerance)
    toml += fmt::format("flexural_tolerance = {}\n", *setup.flexural_tolerance);
  if (!r.advice.empty()) toml += fmt::format("advice = {}\n", io::toml_basic_string(r.advice));
  toml += "\n[fit]   # set these in the test scenarios' [bond] (fracture.crack_length: in the SENB\n"
          "        # scenario's length unit, in its [fracture])\n";
  for (const auto& [key, value] : r.parameters) toml += fmt::format("\"{}\" = {:.9g}\n", key, value);
  io::write_file_atomically(setup.out / "calibration.toml", toml);
  io::Plot plot;
  plot.title = "calibration: error of each trial against its target";
  plot.x_label = "trial";
  plot.y_label = "measured / target - 1 (%)";
  io::PlotSeries e{"E", {}, {}, "", true}, nu{"nu", {}, {}, "", true}, st{"sigma_t", {}, {}, "", true},
      sf{"sigma_f", {}, {}, "", true}, kic{"K_Ic", {}, {}, "", true};
  for (const auto& t : r.trials) {
    if (t.loop == "toughness") {
      kic.x.push_back(t.number);
      kic.y.push_back(100 * t.error);
    } else if (t.loop == "elastic") {
      e.x.push_back(t.number);
      e.y.push_back(100 * t.error);
      if (setup.targets.poisson) {
        nu.x.push_back(t.number);
        nu.y.push_back(100 * t.error_poisson);
      }
    } else {
      st.x.push_back(t.number);
      st.y.push_back(100 * t.error);
      if (!std::isnan(t.error_flexural)) {
        sf.x.push_back(t.number);
        sf.y.push_back(100 * t.error_flexural);
      }
    }
  }
  for (auto* s : {&e, &nu, &st, &sf, &kic}) {
    if (!s->x.empty()) plot.series.push_back(*s);
  }
  plot.series.push_back({fmt::format("+{:g} %", 100 * setup.tolerance), {0.5, r.trials.size() + 0.5},
                         {100 * setup.tolerance, 100 * setup.tolerance}, "#999999", false, true});
  plot.series.push_back({fmt::format("-{:g} %", 100 * setup.tolerance), {0.5, r.trials.size() + 0.5},
                         {-100 * setup.tolerance, -100 * setup.tolerance}, "#999999", false, true});
  io::write_plot_svg(setup.out / "calibration.svg", plot);
  fmt::print("  {} after {} trial runs in {:.0f} s:", r.converged ? "converged" : "NOT converged",
             r.trials.size(), r.wall_seconds);
  for (const auto& [key, value] : r.parameters) fmt::print(" {} = {:.5g}", key, value);
  fmt::print("\n");
  if (!r.advice.empty()) fmt::print("  {}\n", r.advice);
  record.manifest.facts["converged"] = r.converged ? "true" : "false";
  record.close_quietly(io::run_status::finished, {});
  fmt::print("  -> {}/calibration.toml, calibration.csv, calibration.svg\n", setup.out.string());
  return r.converged ? 0 : 1;
}

}  // namespace cleave::app
