// `cleave measure TEST SCENARIO`: a macroscopic property of a bonded specimen measured as a
// laboratory would (sim/measure.hpp), printed with its formula and, when the scenario names a
// material preset, against the handbook value; written to DIR/measure.toml (and, for the
// elastic test, DIR/measure.csv and DIR/stress_strain.svg).

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>

#include "commands.hpp"
#include "io/material_library.hpp"
#include "io/plot.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "run_control.hpp"
#include "sim/measure.hpp"

namespace cleave::app {

namespace {

/// The preset's property the test measures, and its SI unit shown as the test prints it.
struct Reading {
  const char* key;
  const char* label;
  double scale;
  const char* unit;
};

Reading reading_of(sim::Test t) {
  switch (t) {
    case sim::Test::elastic: return {"young", "E", 1e9, "GPa"};
    case sim::Test::brazilian: return {"tensile_strength", "sigma_t", 1e6, "MPa"};
    case sim::Test::flexural: return {"flexural_strength", "sigma_f", 1e6, "MPa"};
    case sim::Test::senb: return {"k_ic", "K_Ic", 1e6, "MPa m^0.5"};
  }
  return {"", "", 1.0, ""};
}

void write_elastic_outputs(const sim::Measurement& m, const std::filesystem::path& out) {
  std::string csv = "time_s,stress_Pa,strain_platens,strain_axial,strain_lateral\n";
  io::PlotSeries grains{"grains (affine fit, middle half)", {}, {}, "", true};
  io::PlotSeries platens{"platens' approach", {}, {}, "", true};
  for (const auto& e : m.samples) {
    csv += fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", e.time, e.stress, e.strain_platens,
                       e.strain_axial, e.strain_lateral);
    grains.x.push_back(e.strain_axial * 1e6);
    grains.y.push_back(e.stress / 1e6);
    platens.x.push_back(e.strain_platens * 1e6);
    platens.y.push_back(e.stress / 1e6);
  }
  io::write_file_atomically(out / "measure.csv", csv);
  io::Plot plot;
  plot.title = fmt::format("uniaxial small-strain test: E = {:.4g} GPa (grains), {:.4g} GPa (platens), nu = {:.3f}",
                           m.value / 1e9, m.young_platens / 1e9, m.poisson);
  plot.x_label = "axial strain (1e-6)";
  plot.y_label = "stress (MPa)";
  plot.series = {grains, platens};
  if (m.closed_form && !m.samples.empty()) {
    io::PlotSeries law{"honeycomb closed form", {}, {}, "", false, true};
    const double top = m.samples.back().strain_axial;
    law.x = {0.0, top * 1e6};
    law.y = {0.0, m.closed_form->young * top / 1e6};
    plot.series.push_back(law);
  }
  io::write_plot_svg(out / "stress_strain.svg", plot);
}

/// Runs `body`; a bad scenario or argument is exit 2, a stop by signal its exit code, any
/// other failure 1, each with its message. Nothing when `body` went through.
std::optional<int> failed(const std::function<void()>& body) {
  try {
    body();
  } catch (const io::ScenarioError& e) {
    fmt::print(stderr, "cleave measure: error: {}\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "cleave measure: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    if (stop_signal() != 0) {
      fmt::print(stderr, "cleave measure: stopped by {}; nothing more measured\n", signal_name(stop_signal()));
      return exit_code_for_signal(stop_signal());
    }
    fmt::print(stderr, "cleave measure: error: {}\n", e.what());
    return 1;
  }
  return std::nullopt;
}

/// --converge: the loading-rate study, its table and its plot.
int converge_command(sim::Test test, const MeasureOptions& options, const sim::SimulationOptions& so) {
  const Reading r = reading_of(test);
  if (!options.quiet) {
    fmt::print("cleave measure {} --converge: {} at the scenario's loading rate, then half of it, "
               "until {} changes by less than {:g} %\n",
               options.test, options.scenario.string(), r.label, 100.0 * options.tolerance);
    if (test == sim::Test::flexural) {
      fmt::print("  ({}: the tension face's stress at the first crack, 6 M / (b d^2) + N / (b d) of the "
                 "mid-span section's moment and axial force)\n", r.label);
    } else if (test == sim::Test::senb) {
      fmt::print("  ({}: at the first crack, from the notched section's moment and axial force)\n", r.label);
    }
    fmt::print("  {:>10} {:>14} {:>14} {:>9} {:>12} {:>8}\n", "rate", "wall (mm/s)",
               fmt::format("{} ({})", r.label, r.unit), "change", "KE / work", "wall s");
    std::fflush(stdout);
  }
  // The study's folder is a result of its own: its run.toml lists every rate's folder and
  // the table, so that a later study of the same scenario replaces exactly that.
  std::optional<io::ResultRecord> record;
  sim::SimulationOptions in_folder = so;
  if (const auto code = failed([&] {
        const io::Scenario s = io::load_scenario(options.scenario);
        const std::filesystem::path root = so.out.empty() ? std::filesystem::path("results") / s.name : so.out;
        const io::FolderPlan plan = io::check_result_folder(root, io::FolderClaim{"measure", s.name, false, false});
        io::clear_result_folder(root, plan);
        std::filesystem::create_directories(root);
        record.emplace(root);
        record->manifest.provenance["cleave_version"] = sim::version();
        record->manifest.provenance["command"] = "measure";
        record->manifest.facts["cleave_version"] = sim::version();
        record->manifest.facts["scenario"] = options.scenario.string();
        record->manifest.facts["scenario_name"] = s.name;
        record->manifest.facts["test"] = options.test;
        record->start();
        in_folder.out = root;
        in_folder.replace = true;  // its run.toml is this process's, written just now
      }))
    return *code;
  sim::RateStudy study;
  if (const auto code = failed([&] {
        study = sim::converge_loading_rate(
            test, options.scenario, in_folder, options.sets, options.tolerance, options.max_runs,
            [&](const sim::RatePoint& p) {
              if (options.quiet) return;
              fmt::print("  {:>10g} {:>14.4g} {:>14.5g} {:>9} {:>12.2g} {:>8.1f}\n", p.rate_scale,
                         p.wall_speed * 1e3, p.value / r.scale,
                         std::isnan(p.change) ? std::string("-") : fmt::format("{:+.2f} %", 100.0 * p.change),
                         p.kinetic_ratio, p.wall_seconds);
              std::fflush(stdout);
            });
      })) {
    record->close_quietly(stop_signal() != 0 ? io::run_status::interrupted : io::run_status::failed,
                          stop_signal() != 0 ? fmt::format("stopped by {}", signal_name(stop_signal()))
                                              : std::string("a run of the study failed"));
    return *code;
  }
  const std::filesystem::path out = study.points.front().out.parent_path();
  std::string csv = fmt::format("rate_scale,wall_speed_m_per_s,{},change,kinetic_ratio,wall_seconds,folder\n",
                                sim::judged_key(test));
  io::PlotSeries values{fmt::format("{} at each loading rate", r.label), {}, {}, "", true};
  for (const auto& p : study.points) {
    csv += fmt::format("{:.9g},{:.9g},{:.9g},{},{:.6g},{:.3f},{}\n", p.rate_scale, p.wall_speed, p.value,
                       std::isnan(p.change) ? std::string("") : fmt::format("{:.6g}", p.change),
                       p.kinetic_ratio, p.wall_seconds, p.out.filename().string());
    values.x.push_back(p.wall_speed * 1e3);
    values.y.push_back(p.value / r.scale);
  }
  io::write_file_atomically(out / "convergence.csv", csv);
  io::Plot plot;
  plot.title = fmt::format("{} against the loading rate ({}: {:g} % between the last two)", r.label,
                           study.converged ? "converged" : "not converged",
                           100.0 * std::abs(study.points.back().change));
  plot.x_label = "loading wall speed (mm/s)";
  plot.y_label = fmt::format("{} ({})", r.label, r.unit);
  plot.series = {values};
  io::write_plot_svg(out / "convergence.svg", plot);
  const sim::RatePoint& last = study.points.back();
  if (study.converged) {
    fmt::print("  converged: {} = {:.5g} {} at {:.4g} mm/s ({:+.2f} % from twice that rate, within {:g} %)\n",
               r.label, last.value / r.scale, r.unit, last.wall_speed * 1e3, 100.0 * last.change,
               100.0 * options.tolerance);
  } else {
    fmt::print(stderr,
               "cleave measure: not converged after {} runs: the last halving of the rate changed {} by "
               "{:+.2f} % (tolerance {:g} %); start slower or allow more runs (--max-runs)\n",
               study.points.size(), r.label, 100.0 * last.change, 100.0 * options.tolerance);
  }
  record->manifest.facts["converged"] = study.converged ? "true" : "false";
  record->close(io::run_status::finished);
  fmt::print("  -> {}/convergence.csv, convergence.svg\n", out.string());
  return study.converged ? 0 : 1;
}

}  // namespace

int measure_command(const MeasureOptions& options) {
  const auto test = sim::parse_test(options.test);
  if (!test) {
    fmt::print(stderr, "cleave measure: unknown test '{}'; the tests are elastic, brazilian, "
                       "flexural, senb\n", options.test);
    return 2;
  }
  install_stop_handlers();
  sim::SimulationOptions so;
  so.out = options.out;
  so.quiet = true;
  so.stop_requested = [] { return stop_signal() != 0; };
  so.stop_reason = [] { return fmt::format("stopped by {}", signal_name(stop_signal())); };
  if (options.converge) return converge_command(*test, options, so);
  sim::Measurement m;
  if (const auto code = failed([&] {
        if (!options.quiet) {
          fmt::print("cleave measure {}: {} ...\n", options.test, options.scenario.string());
          std::fflush(stdout);
        }
        m = sim::measure(*test, options.scenario, so, options.sets);
      }))
    return *code;
  if (m.report.status == sim::RunReport::Status::interrupted) {
    fmt::print(stderr, "cleave measure: {}; nothing measured\n", m.report.message);
    return exit_code_for_signal(stop_signal());
  }
  if (m.report.status == sim::RunReport::Status::failed) {
    fmt::print(stderr, "cleave measure: error: the run failed: {}\n", m.report.message);
    return 1;
  }
  const std::filesystem::path out = m.report.out;
  const Reading r = reading_of(*test);
  std::string text = sim::measurement_toml(m);
  const double judged = sim::judged_value(m);
  const bool at_first_crack = sim::judged_at_first_crack(*test);
  std::string compare;
  try {
    const io::Scenario s = io::load_scenario(options.scenario);
    if (!s.material.preset_file.empty()) {
      const io::MaterialPreset preset = io::load_material(s.material.preset_file);
      const double want = preset.si(r.key);
      compare = fmt::format("  handbook {} of {}: {:.4g} {}; measured {:+.1f} % off{}", r.key, preset.name,
                            want / r.scale, r.unit, 100.0 * (judged / want - 1.0),
                            at_first_crack ? " (at the first crack)" : "");
      text += fmt::format("preset = \"{}\"\npreset_value = {:.9g}\njudged = \"{}\"\n", preset.name, want,
                          sim::judged_key(*test));
      if (*test == sim::Test::elastic) {
        const double nu = preset.si("poisson");
        compare += fmt::format("; handbook nu {:.3f}, measured {:+.3f} off", nu, m.poisson - nu);
        text += fmt::format("preset_poisson = {:.9g}\n", nu);
      }
    }
  } catch (const std::exception&) {  // the measurement stands without the comparison
  }
  io::write_file_atomically(out / "measure.toml", text);
  if (*test == sim::Test::elastic) write_elastic_outputs(m, out);
  // The run's manifest lists them too: a later measurement replaces them with the run.
  std::vector<std::string> written{"measure.toml"};
  if (*test == sim::Test::elastic)
    written.insert(written.end(), {"measure.csv", "stress_strain.svg"});
  try {
    io::add_to_manifest(out, written);
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave measure: warning: {}/run.toml does not list them: {}\n",
               out.string(), e.what());
  }
  fmt::print("  {} = {:.4g} {}", r.label, judged / r.scale, r.unit);
  if (*test == sim::Test::elastic) {
    fmt::print(", nu = {:.4f}; from the platens E = {:.4g} GPa", m.poisson, m.young_platens / 1e9);
  }
  if (at_first_crack) {
    // A bending test is judged at its first crack from the statics of its mid-span
    // section; the formula's peak is printed beside it.
    fmt::print(" at the first crack (a {}), from the mid-span section's statics: M = {:.5g} N m, N = {:.4g} N "
               "(the rollers' contact forces where they act), {}\n  the formula at the peak load reads {:.4g} {}:\n"
               "  {}\n",
               m.first_crack, m.moment_at_first_crack, m.axial_at_first_crack,
               *test == sim::Test::flexural ? "sigma = 6 M / (b d^2) + N / (b d)"
                                            : "K_I = the formula's with P S = 4 M, plus an edge-notched strip's under N",
               m.value / r.scale, r.unit, m.formula);
  } else {
    fmt::print("\n  {}\n", m.formula);
  }
  if (m.closed_form) {
    fmt::print("  honeycomb closed form for these bond springs: E = {:.4g} GPa ({:+.2f} %), nu = {:.4f}\n",
               m.closed_form->young / 1e9, 100.0 * (m.value / m.closed_form->young - 1.0),
               m.closed_form->poisson);
  }
  if (!compare.empty()) fmt::print("{}\n", compare);
  if (std::isfinite(m.value_at_first_crack)) {
    fmt::print("  first crack: a {}, at P = {:.5g} N, where the formula reads {:.4g} {}{}\n",
               m.first_crack, m.first_crack_load, m.value_at_first_crack / r.scale, r.unit,
               m.first_crack_load < 0.99 * m.peak_load ? " (the crack stopped; the load climbed on)" : "");
  }
  if (std::isfinite(m.value_from_statics)) {
    fmt::print("  from the mid-span section's statics: {:.4g} {} at most, {:.4g} {} at the first crack\n",
               m.value_from_statics / r.scale, r.unit, m.value_from_statics_at_first_crack / r.scale, r.unit);
  }
  if (std::isfinite(m.kinetic_ratio)) {
    fmt::print("  quasi-static: kinetic energy at most {:.2g} of the work done in the loading's second half\n",
               m.kinetic_ratio);
  }
  fmt::print("  -> {}/measure.toml\n", out.string());
  return 0;
}

}  // namespace cleave::app
