// `cleave validate`: runs a DCB, ENF or MMB test of scenarios/validation/ on the cubic lattice
// and compares its load-deflection curve with the closed forms of corrected beam theory.

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "cleave_version.hpp"
#include "commands.hpp"
#include "io/plot.hpp"
#include "io/provenance.hpp"
#include "io/result_dir.hpp"
#include "io/scenario_writer.hpp"
#include "io/scenario.hpp"
#include "io/validation_scenario.hpp"
#include "validation/beam_test_rig.hpp"
#include "validation/cohesive_beam.hpp"
#include "run_control.hpp"

namespace cleave::app {

namespace fs = std::filesystem;

namespace {

const char* test_name(physics::BeamTestKind k) {
  switch (k) {
    case physics::BeamTestKind::dcb: return "DCB (mode I)";
    case physics::BeamTestKind::enf: return "ENF (mode II)";
    case physics::BeamTestKind::mmb: return "MMB (mixed mode)";
  }
  return "?";
}

/// The measured load-deflection curve as CSV.
std::string measured_csv(const std::vector<physics::BeamReading>& curve) {
  std::string csv = "step,time_s,delta_mm,load_N,crack_mm,process_zone_mm,kinetic_J,external_work_J\n";
  for (const auto& r : curve)
    csv += fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", r.step, r.time,
                       r.delta * 1e3, r.load, r.crack * 1e3, r.process_zone * 1e3, r.kinetic,
                       r.external_work);
  return csv;
}

/// The measured loads over [from, to] (for the split stage: the deflections its closed-form
/// comparison spanned) against the cohesive beam's curve.
physics::StageErrors cohesive_errors(const std::vector<physics::CohesiveBeamPoint>& czm,
                                     const std::vector<physics::BeamReading>& curve, int stage,
                                     double from, double to) {
  physics::StageErrors z;
  z.stage = stage;
  z.from = from;
  z.to = to;
  double sum = 0.0;
  for (const auto& r : curve) {
    if (r.delta < from || r.delta > to) continue;
    const double expected = physics::cohesive_load(czm, r.delta);
    if (!(expected > 0.0)) continue;
    const double err = std::abs(r.load - expected) / expected;
    sum += err;
    z.max_error = std::max(z.max_error, err);
    ++z.points;
  }
  if (z.points > 0) z.mean_error = sum / z.points;
  return z;
}

}  // namespace

int validate_command(const ValidateOptions& options) {
  install_stop_handlers();
  io::ValidationScenario v;
  try {
    v = io::load_validation_scenario(options.scenario);
  } catch (const io::ScenarioError& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 2;
  }
  const fs::path out = options.out.empty() ? fs::path("results") / v.name : options.out;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    fmt::print(stderr, "cleave: error: cannot create the result folder {}: {}\n", out.string(),
               ec.message());
    return 2;
  }
  auto say = [&](const std::string& s) {
    if (!options.quiet) fmt::print("{}\n", s);
  };
  // run.toml says "running" from here on; close() gives the final status and the files.
  io::ResultRecord record(out);
  io::Manifest& manifest = record.manifest;
  manifest.facts["cleave_version"] = CLEAVE_VERSION;
  manifest.facts["scenario"] = fs::absolute(options.scenario).string();
  manifest.provenance = io::library_versions();
  manifest.provenance["cleave_version"] = CLEAVE_VERSION;
  manifest.provenance["command"] = "validate";
  manifest.provenance["scenario"] = options.scenario.string();
  // The cubic lattice is regular and its run deterministic: nothing is drawn at random.
  manifest.provenance["seed"] = "none";
  manifest.provenance["started_utc"] = io::utc_now();
  try {
    fs::remove(out / io::kChecksumsName);
    const std::string input = io::read_file(options.scenario);
    manifest.provenance["scenario_sha256"] = io::sha256_hex(input);
    record.start();
    io::write_file_atomically(out / "scenario.toml", input);
    io::write_file_atomically(out / io::kScenarioAsRunName, io::validation_scenario_as_run(v));
    manifest.provenance["scenario_as_run"] = io::kScenarioAsRunName;
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    record.close_quietly(io::run_status::failed, e.what());
    return 2;
  }
  try {
    if (v.threads > 0) omp_set_num_threads(v.threads);
    physics::BeamTestRig rig(v.rig);
    const physics::BeamTest& test = rig.analytic();
    const auto& lat = rig.lattice();
    const double rate = v.rig.kind == physics::BeamTestKind::dcb ? 2.0 * v.rig.velocity
                                                                  : v.rig.velocity;
    // The steps it takes at full speed, plus the ramp's lost half.
    const double run_time = v.deflection / rate + 0.5 * v.rig.ramp_time;
    const auto expected_steps = static_cast<std::uint64_t>(std::ceil(run_time / rig.time_step()));
    const std::uint64_t every = std::max<std::uint64_t>(1, expected_steps / v.records);
    say(fmt::format("cleave validate: {} - {}", v.name, test_name(v.rig.kind)));
    say(fmt::format("  lattice    {} x {} x {} cubes of {:g} mm ({} bodies), {} links; weak "
                    "mid-plane, notch a0 = {:g} mm",
                    lat.def().nx, lat.def().ny, lat.def().nz, 2e3 * v.rig.radius, lat.size(),
                    lat.links().size(), v.rig.initial_crack * 1e3));
    say(fmt::format("  closed form L = {:g} mm, h = {:g} mm, B' = B - 2r = {:g} mm, chi_I = {:.4f}, "
                    "chi_II = {:.4f}{}",
                    test.L * 1e3, test.h * 1e3, (test.B - 2 * test.r) * 1e3,
                    physics::chi_I(test.E, test.nu), physics::chi_II(test.E, test.nu),
                    v.rig.kind == physics::BeamTestKind::mmb
                        ? fmt::format(", lever arm C = {:.3f} mm (beta = {:g})", test.C * 1e3,
                                      v.rig.mode_mix)
                        : std::string()));
    say(fmt::format("  time step  {:.4g} s ({:g} of critical); about {} steps to Delta = {:g} mm",
                    rig.time_step(), v.rig.dt_safety, expected_steps, v.deflection * 1e3));

    std::vector<physics::BeamReading> curve;
    curve.push_back(rig.reading());
    const auto start = std::chrono::steady_clock::now();
    auto last_report = start;
    const std::uint64_t limit = 3 * expected_steps + 1000;
    double max_ratio = 0.0;
    while (true) {
      if (const int sig = stop_signal()) {
        const std::string reason = fmt::format("stopped by {} at step {}", signal_name(sig), rig.steps());
        fmt::print(stderr, "cleave: {}; the result folder {} is marked interrupted\n", reason, out.string());
        io::write_file_atomically(out / "measured.csv", measured_csv(curve));
        manifest.provenance["ended_utc"] = io::utc_now();
        record.close_quietly(io::run_status::interrupted, reason);
        return exit_code_for_signal(sig);
      }
      rig.step();
      if (rig.steps() % every != 0) continue;
      physics::BeamReading r = rig.reading();
      if (!std::isfinite(r.load) || !std::isfinite(r.delta))
        throw std::runtime_error(fmt::format(
            "the lattice blew up at step {} (non-finite load); lower dynamics.dt_safety", r.step));
      curve.push_back(r);
      if (r.external_work > 0.0 && r.delta > 0.05 * v.deflection)
        max_ratio = std::max(max_ratio, r.kinetic / r.external_work);
      const auto now = std::chrono::steady_clock::now();
      if (!options.quiet && now - last_report > std::chrono::seconds(10)) {
        last_report = now;
        const double secs = std::chrono::duration<double>(now - start).count();
        const double frac = std::min(1.0, r.delta / v.deflection);
        fmt::print(stderr,
                   "  step {:>9}  Delta {:.4f} mm  P {:.4g} N  crack {:.2f} mm  {:.0f} steps/s  "
                   "{:.0f}%  ETA {:.0f} s\n",
                   r.step, r.delta * 1e3, r.load, r.crack * 1e3, r.step / secs, 100 * frac,
                   frac > 0 ? secs * (1 - frac) / frac : 0.0);
      }
      if (r.delta >= v.deflection) break;
      if (r.step > limit)
        throw std::runtime_error(fmt::format(
            "Delta reached only {:.4g} mm of {:.4g} mm after {} steps", r.delta * 1e3,
            v.deflection * 1e3, r.step));
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                            .count();
    const physics::BeamReading& fin = curve.back();

    // Measured curve.
    io::write_file_atomically(out / "measured.csv", measured_csv(curve));
    // Closed form.
    const auto analytic = physics::analytic_curve(test, v.deflection, 200);
    std::string acsv = "stage,delta_mm,load_N,crack_mm\n";
    for (const auto& p : analytic)
      acsv += fmt::format("{},{:.9g},{:.9g},{:.9g}\n", p.stage, p.delta * 1e3, p.load,
                          p.crack * 1e3);
    io::write_file_atomically(out / "analytic.csv", acsv);
    // The same beam theory with the weak plane's cohesive zone in place of LEFM's sharp tip
    // (validation/cohesive_beam.hpp): what the closed form says with the scenario's sigma_c.
    // Its plane has the lattice's G_c (one value for every mode mix, as the lattice's law).
    std::vector<physics::CohesiveBeamPoint> czm;
    std::string czm_note;
    try {
      physics::BeamTest one_gc = test;
      one_gc.g_Ic = one_gc.g_IIc = v.rig.material.g_c;
      switch (v.rig.kind) {
        case physics::BeamTestKind::dcb:
          czm = physics::cohesive_dcb_curve(one_gc, v.rig.material.sigma_c,
                                            v.rig.intact_length, v.deflection);
          break;
        case physics::BeamTestKind::enf:
          czm = physics::cohesive_enf_curve(one_gc, v.rig.material.sigma_c, v.deflection);
          break;
        case physics::BeamTestKind::mmb:
          czm = physics::cohesive_mmb_curve(one_gc, v.rig.material.sigma_c, v.deflection);
          break;
      }
      std::string ccsv = "delta_mm,load_N,crack_mm,process_zone_mm\n";
      for (const auto& p : czm)
        ccsv += fmt::format("{:.9g},{:.9g},{:.9g},{:.9g}\n", p.delta * 1e3, p.load,
                            p.crack * 1e3, p.process_zone * 1e3);
      io::write_file_atomically(out / "cohesive_beam.csv", ccsv);
    } catch (const std::exception& e) {
      czm.clear();
      czm_note = e.what();
    }

    // Errors per stage and the peak.
    bool pass = true;
    std::string ecsv =
        "stage,from_mm,to_mm,points,mean_rel_error,max_rel_error,tolerance,pass,slope_rel_error\n";
    say(fmt::format("  done       {} steps in {:.1f} s ({:.0f} steps/s); Delta = {:.4f} mm, "
                    "crack a = {:.2f} mm; kinetic/external work <= {:.2e} after 5% of the run",
                    fin.step, wall, fin.step / wall, fin.delta * 1e3, fin.crack * 1e3, max_ratio));
    const int split = physics::split_stage(v.rig.kind);
    std::string zcsv = "stage,from_mm,to_mm,points,mean_rel_error,max_rel_error\n";
    for (int stage : v.stages) {
      const physics::StageErrors e = physics::compare_with_closed_form(test, curve, stage, v.margin);
      if (!czm.empty() && e.points > 0) {
        // The same points against the cohesive beam (informative: the tolerances
        // are on the closed form).
        const physics::StageErrors z = cohesive_errors(czm, curve, stage, e.from, e.to);
        zcsv += fmt::format("{},{:.6g},{:.6g},{},{:.6f},{:.6f}\n", stage, z.from * 1e3,
                            z.to * 1e3, z.points, z.mean_error, z.max_error);
        say(fmt::format("  stage {}    against the cohesive beam (sigma_c = {:g} MPa): load error "
                        "mean {:.2f}%, max {:.2f}% over {} points",
                        stage, v.rig.material.sigma_c * 1e-6, 100 * z.mean_error,
                        100 * z.max_error, z.points));
      }
      // The split beam's stage is judged by its slope (the "stage III slope"); the
      // others by their loads.
      const bool ok = stage == split ? e.slope_error <= v.tolerance
                                     : e.points > 0 && (v.mean_measure ? e.mean_error
                                                                       : e.max_error) <= v.tolerance;
      pass = pass && ok;
      ecsv += fmt::format("{},{:.6g},{:.6g},{},{:.6f},{:.6f},{:g},{},{:.6f}\n", stage, e.from * 1e3,
                          e.to * 1e3, e.points, e.mean_error, e.max_error, v.tolerance,
                          ok ? "yes" : "no", e.slope_error);
      if (stage == split) {
        say(e.points == 0
                ? fmt::format("  stage {}    the crack never ran through the weak plane (a = {:.2f} "
                              "of {:.2f} mm): no split beam to compare FAIL",
                              stage, fin.crack * 1e3, physics::split_crack(test) * 1e3)
                : fmt::format("  stage {}    split beam, Delta {:.4f}-{:.4f} mm, {} points: slope "
                              "{:.4g} N/mm against {:.4g} N/mm, error {:.2f}% (tolerance {:g}%); "
                              "load error mean {:.2f}%, max {:.2f}% {}",
                              stage, e.from * 1e3, e.to * 1e3, e.points, e.slope * 1e-3,
                              1e-3 / physics::split_compliance(test), 100 * e.slope_error,
                              100 * v.tolerance, 100 * e.mean_error, 100 * e.max_error,
                              ok ? "PASS" : "FAIL"));
        manifest.facts[fmt::format("stage{}_slope_error", stage)] = fmt::format("{:.6f}", e.slope_error);
      } else {
        say(fmt::format("  stage {}    Delta {:.4f}-{:.4f} mm, {} points: load error mean {:.2f}%, "
                        "max {:.2f}% (tolerance {:g}% on the {}) {}",
                        stage, e.from * 1e3, std::min(e.to, fin.delta) * 1e3, e.points,
                        100 * e.mean_error, 100 * e.max_error, 100 * v.tolerance,
                        v.mean_measure ? "mean" : "max", ok ? "PASS" : "FAIL"));
      }
      manifest.facts[fmt::format("stage{}_max_error", stage)] = fmt::format("{:.6f}", e.max_error);
      manifest.facts[fmt::format("stage{}_mean_error", stage)] = fmt::format("{:.6f}", e.mean_error);
    }
    double apeak = 0.0, apeak_delta = 0.0;
    for (const auto& p : analytic)
      if (p.stage <= 2 && p.load > apeak) {
        apeak = p.load;
        apeak_delta = p.delta;
      }
    // The measured peak: the largest load up to twice the closed form's peak deflection (a
    // cohesive zone delays the peak; later stages, such as the ENF's stage III, may climb
    // higher again and are not this peak).
    double peak = 0.0, peak_delta = 0.0;
    for (const auto& r : curve)
      if (r.delta <= 2.0 * apeak_delta && r.load > peak) {
        peak = r.load;
        peak_delta = r.delta;
      }
    const double peak_error = std::abs(peak - apeak) / apeak;
    const bool peak_ok = v.peak_tolerance <= 0.0 || peak_error <= v.peak_tolerance;
    pass = pass && peak_ok;
    ecsv += fmt::format("peak,{:.6g},{:.6g},1,{:.6f},{:.6f},{:g},{},nan\n", peak_delta * 1e3,
                        apeak_delta * 1e3, peak_error, peak_error, v.peak_tolerance,
                        v.peak_tolerance <= 0.0 ? "not checked" : (peak_ok ? "yes" : "no"));
    say(fmt::format("  peak       {:.4g} N at {:.4f} mm; closed form {:.4g} N at {:.4f} mm: "
                    "{:.2f}%{}",
                    peak, peak_delta * 1e3, apeak, apeak_delta * 1e3, 100 * peak_error,
                    v.peak_tolerance <= 0.0
                        ? ""
                        : fmt::format(" (tolerance {:g}%) {}", 100 * v.peak_tolerance,
                                      peak_ok ? "PASS" : "FAIL")));
    io::write_file_atomically(out / "errors.csv", ecsv);
    if (!czm.empty()) {
      double zpeak = 0.0, zpeak_delta = 0.0;
      for (const auto& p : czm)  // as the measured peak: up to twice the closed form's deflection
        if (p.delta <= 2.0 * apeak_delta && p.load > zpeak) zpeak = p.load, zpeak_delta = p.delta;
      const double zerr = std::abs(peak - zpeak) / zpeak;
      zcsv += fmt::format("peak,{:.6g},{:.6g},1,{:.6f},{:.6f}\n", peak_delta * 1e3,
                          zpeak_delta * 1e3, zerr, zerr);
      say(fmt::format("  peak       cohesive beam {:.4g} N at {:.4f} mm: measured {:.2f}% off",
                      zpeak, zpeak_delta * 1e3, 100 * zerr));
      io::write_file_atomically(out / "errors_cohesive_beam.csv", zcsv);
    } else if (!czm_note.empty()) {
      say(fmt::format("  no cohesive beam: {}", czm_note));
    }

    // The picture: measured against closed form, stage by stage.
    io::Plot plot;
    plot.title = fmt::format("{}: {} - measured and corrected beam theory", v.name,
                             test_name(v.rig.kind));
    plot.x_label = v.rig.kind == physics::BeamTestKind::enf ? "load-point deflection Delta (mm)"
                                                            : "opening at the loaded end Delta (mm)";
    plot.y_label = "load P (N)";
    io::PlotSeries measured{"cleave (lattice, cohesive weak plane)", {}, {}, "", false, false, 2.0};
    for (const auto& r : curve) {
      measured.x.push_back(r.delta * 1e3);
      measured.y.push_back(r.load);
    }
    plot.series.push_back(measured);
    for (int stage = 1; stage <= 4; ++stage) {
      io::PlotSeries s{fmt::format("closed form, stage {}", stage), {}, {}, "", false, true, 1.5};
      for (const auto& p : analytic)
        if (p.stage == stage) {
          s.x.push_back(p.delta * 1e3);
          s.y.push_back(p.load);
        }
      if (s.x.size() > 1) plot.series.push_back(s);
    }
    if (!czm.empty()) {
      io::PlotSeries z{fmt::format("beam theory with the cohesive zone (sigma_c = {:g} MPa)",
                                   v.rig.material.sigma_c * 1e-6),
                       {}, {}, "", false, false, 1.5};
      for (const auto& p : czm) {
        z.x.push_back(p.delta * 1e3);
        z.y.push_back(p.load);
      }
      plot.series.push_back(z);
    }
    plot.markers.push_back({peak_delta * 1e3, peak, fmt::format("peak {:.3g} N", peak)});
    io::write_plot_svg(out / "load_deflection.svg", plot);

    manifest.facts["test"] = test_name(v.rig.kind);
    manifest.facts["bodies"] = std::to_string(lat.size());
    manifest.facts["links"] = std::to_string(lat.links().size());
    manifest.facts["steps"] = std::to_string(fin.step);
    manifest.facts["time_step_s"] = fmt::format("{:.9g}", rig.time_step());
    manifest.facts["wall_seconds"] = fmt::format("{:.3f}", wall);
    manifest.facts["steps_per_second"] = fmt::format("{:.1f}", fin.step / wall);
    manifest.facts["peak_load_N"] = fmt::format("{:.9g}", peak);
    manifest.facts["closed_form_peak_N"] = fmt::format("{:.9g}", apeak);
    manifest.facts["kinetic_over_work_max"] = fmt::format("{:.3e}", max_ratio);
    manifest.facts["validation"] = pass ? "pass" : "fail";
    manifest.provenance["ended_utc"] = io::utc_now();
    record.close(io::run_status::finished);
    say(fmt::format("  result     {} -> {} (measured.csv, analytic.csv, errors.csv, {}"
                    "load_deflection.svg)",
                    pass ? "PASS" : "FAIL", out.string(),
                    czm.empty() ? "" : "cohesive_beam.csv, errors_cohesive_beam.csv, "));
    return pass ? 0 : 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    manifest.provenance["ended_utc"] = io::utc_now();
    record.close_quietly(io::run_status::failed, e.what());
    return 2;
  }
}

}  // namespace cleave::app
