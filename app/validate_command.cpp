// `cleave validate`: runs a DCB, ENF or MMB test of scenarios/validation/ on the cubic lattice
// and compares its load-deflection curve with the closed forms of corrected beam theory.

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

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
  std::string csv =
      "step,time_s,delta_mm,load_N,crack_mm,process_zone_mm,kinetic_J,external_work_J,"
      "load_instant_N,delta_instant_mm\n";
  for (const auto& r : curve)
    csv += fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n",
                       r.step, r.time, r.delta * 1e3, r.load, r.crack * 1e3, r.process_zone * 1e3,
                       r.kinetic, r.external_work, r.load_instant, r.delta_instant * 1e3);
  return csv;
}

/// The measured loads over [from, to] (for the split stage: the deflections its closed-form
/// comparison spanned) against the cohesive beam's curve; for the split stage also the slope
/// of the line through the origin fitted to the measured points against the one fitted to the
/// cohesive beam's loads at the same deflections.
physics::StageErrors cohesive_errors(const std::vector<physics::CohesiveBeamPoint>& czm,
                                     const std::vector<physics::BeamReading>& curve, int stage,
                                     double from, double to, bool split) {
  physics::StageErrors z;
  z.stage = stage;
  z.from = from;
  z.to = to;
  double sum = 0.0, sxx = 0.0, sxy = 0.0, sxz = 0.0;
  for (const auto& r : curve) {
    if (!(r.delta >= from && r.delta <= to)) continue;
    const double expected = physics::cohesive_load(czm, r.delta);
    if (!(expected > 0.0)) continue;
    const double err = std::abs(r.load - expected) / expected;
    sum += err;
    z.max_error = std::max(z.max_error, err);
    sxx += r.delta * r.delta, sxy += r.delta * r.load, sxz += r.delta * expected;
    ++z.points;
  }
  if (z.points > 0) z.mean_error = sum / z.points;
  if (split && z.points > 0) {
    z.slope = sxy / sxx;
    z.slope_error = std::abs(sxy / sxz - 1.0);
  }
  return z;
}

/// Whether a stage's errors are within its bounds (none compared: not within).
bool within(const physics::StageErrors& e, const io::StageCheck& c) {
  if (e.points == 0) return false;
  if (c.mean > 0.0 && !(e.mean_error <= c.mean)) return false;
  if (c.max > 0.0 && !(e.max_error <= c.max)) return false;
  if (c.slope > 0.0 && !(e.slope_error <= c.slope)) return false;
  return true;
}

constexpr const char* kErrorsHeader =
    "stage,from_mm,to_mm,points,mean_rel_error,max_rel_error,slope_rel_error,mean_bound,"
    "max_bound,slope_bound,pass\n";

std::string bound_cell(double b) { return b > 0.0 ? fmt::format("{:g}", b) : std::string(); }

/// One row of errors.csv / errors_cohesive_beam.csv: the bounds and the verdict only in the
/// file of the reference the scenario is judged against (elsewhere empty and "-").
std::string error_row(const physics::StageErrors& e, const io::StageCheck& c, bool judged) {
  return fmt::format("{},{:.6g},{:.6g},{},{:.6f},{:.6f},{:.6f},{},{},{},{}\n", e.stage,
                     e.from * 1e3, e.to * 1e3, e.points, e.mean_error, e.max_error, e.slope_error,
                     judged ? bound_cell(c.mean) : "", judged ? bound_cell(c.max) : "",
                     judged ? bound_cell(c.slope) : "",
                     judged ? (within(e, c) ? "yes" : "no") : "-");
}

std::string describe(const physics::StageErrors& e, const io::StageCheck& c) {
  std::string s = fmt::format("Delta {:.4f}-{:.4f} mm, {} points: load error mean {:.2f}%, max {:.2f}%",
                              e.from * 1e3, e.to * 1e3, e.points, 100 * e.mean_error,
                              100 * e.max_error);
  if (std::isfinite(e.slope_error)) s += fmt::format(", slope {:.2f}%", 100 * e.slope_error);
  std::string bounds;
  for (auto [name, b] : {std::pair{"mean", c.mean}, {"max", c.max}, {"slope", c.slope}})
    if (b > 0.0) bounds += fmt::format("{}{} {:g}%", bounds.empty() ? "" : ", ", name, 100 * b);
  return s + fmt::format(" (bounds: {})", bounds);
}

/// The cohesive beam of the scenario: beam theory with its weak plane's cohesive law, the
/// lattice's G_c in every mode mix (one value, as the lattice's law).
std::vector<physics::CohesiveBeamPoint> scenario_cohesive_beam(const io::ValidationScenario& v,
                                                               const physics::BeamTest& test) {
  physics::BeamTest one_gc = test;
  one_gc.g_Ic = one_gc.g_IIc = v.rig.material.g_c;
  switch (v.rig.kind) {
    case physics::BeamTestKind::dcb:
      return physics::cohesive_dcb_curve(one_gc, v.rig.material.sigma_c, v.rig.intact_length,
                                         v.deflection);
    case physics::BeamTestKind::enf:
      return physics::cohesive_enf_curve(one_gc, v.rig.material.sigma_c, v.deflection);
    case physics::BeamTestKind::mmb:
      return physics::cohesive_mmb_curve(one_gc, v.rig.material.sigma_c, v.deflection);
  }
  return {};
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
  io::FolderPlan plan;
  try {
    plan =
        io::check_result_folder(out, io::FolderClaim{"validate", v.name, options.replace, false});
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "cleave: error: command line: {}\n", e.what());
    return 2;
  }
  std::error_code ec;
  try {
    io::clear_result_folder(out, plan);
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 1;
  }
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
  manifest.facts["scenario_name"] = v.name;
  manifest.provenance = io::library_versions();
  manifest.provenance["cleave_version"] = CLEAVE_VERSION;
  manifest.provenance["command"] = "validate";
  manifest.provenance["scenario"] = options.scenario.string();
  // The cubic lattice is regular and its run deterministic: nothing is drawn at random.
  manifest.provenance["seed"] = "none";
  manifest.provenance["started_utc"] = io::utc_now();
  try {
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
    const bool beam_only = options.cohesive_beam_only;
    if (beam_only && v.reference == io::Reference::cohesive_beam)
      throw std::invalid_argument(fmt::format(
          "{}: --cohesive-beam-only judges the cohesive beam against the closed forms, and this "
          "scenario's [validation] reference is the cohesive beam itself; use one whose "
          "reference is \"lefm\"",
          options.scenario.string()));
    // The lattice is built only when it runs (--cohesive-beam-only needs the closed form alone).
    const physics::BeamTest test = physics::beam_analytic(v.rig);
    std::optional<physics::BeamTestRig> built;
    if (!beam_only) built.emplace(v.rig);
    const physics::CubicLatticeDef grid = physics::beam_lattice(v.rig);
    const int bodies = grid.nx * grid.ny * grid.nz;
    const double rate = v.rig.kind == physics::BeamTestKind::dcb ? 2.0 * v.rig.velocity
                                                                  : v.rig.velocity;
    // The same beam theory with the weak plane's cohesive zone in place of LEFM's sharp tip
    // (validation/cohesive_beam.hpp): what the closed form says with the scenario's sigma_c.
    std::vector<physics::CohesiveBeamPoint> czm;
    std::string czm_note;
    try {
      czm = scenario_cohesive_beam(v, test);
    } catch (const std::exception& e) {
      czm.clear();
      czm_note = e.what();
    }
    if (czm.empty() && (beam_only || v.reference == io::Reference::cohesive_beam))
      throw std::runtime_error(fmt::format(
          "the scenario is judged against the cohesive beam, which cannot be solved for it: {}",
          czm_note));
    if (!czm.empty()) {
      std::string ccsv = "delta_mm,load_N,crack_mm,process_zone_mm\n";
      for (const auto& p : czm)
        ccsv += fmt::format("{:.9g},{:.9g},{:.9g},{:.9g}\n", p.delta * 1e3, p.load,
                            p.crack * 1e3, p.process_zone * 1e3);
      io::write_file_atomically(out / "cohesive_beam.csv", ccsv);
    }

    // The steps it takes at full speed, plus the ramp's lost half. The MMB's lever drives
    // its load point, which travels further than the end opens: as far as the cohesive
    // beam's lever moves by the end of the run (it follows the lattice within a few %).
    double travel = v.deflection;
    if (v.rig.kind == physics::BeamTestKind::mmb && !czm.empty() && czm.back().delta > 0.0)
      travel = czm.back().load_point * v.deflection / czm.back().delta;
    const double run_time = travel / rate + 0.5 * v.rig.ramp_time;
    const double dt = beam_only ? 0.0 : built->time_step();
    const auto expected_steps =
        beam_only ? std::uint64_t{0} : static_cast<std::uint64_t>(std::ceil(run_time / dt));
    const std::uint64_t every = std::max<std::uint64_t>(1, expected_steps / v.records);
    say(fmt::format("cleave validate: {} - {}{}", v.name, test_name(v.rig.kind),
                    beam_only ? " (the cohesive beam only: no lattice run)" : ""));
    say(fmt::format("  lattice    {} x {} x {} cubes of {:g} mm ({} bodies){}; weak "
                    "mid-plane, notch a0 = {:g} mm",
                    grid.nx, grid.ny, grid.nz, 2e3 * v.rig.radius, bodies,
                    beam_only ? std::string(", not built")
                              : fmt::format(", {} links", built->lattice().links().size()),
                    v.rig.initial_crack * 1e3));
    const physics::LatticeMaterial& mat = v.rig.material;
    say(fmt::format("  material   sigma_c = {:g} MPa, G_c = {:g} N/m: Hillerborg's length "
                    "E G_c / sigma_c^2 = {:.3g} mm (h = {:g} mm)",
                    mat.sigma_c * 1e-6, mat.g_c, mat.young * mat.g_c / (mat.sigma_c * mat.sigma_c) * 1e3,
                    test.h * 1e3));
    say(fmt::format("  closed form L = {:g} mm, h = {:g} mm, B' = B - 2r = {:g} mm, chi_I = {:.4f}, "
                    "chi_II = {:.4f}{}",
                    test.L * 1e3, test.h * 1e3, (test.B - 2 * test.r) * 1e3,
                    physics::chi_I(test.E, test.nu), physics::chi_II(test.E, test.nu),
                    v.rig.kind == physics::BeamTestKind::mmb
                        ? fmt::format(", lever arm C = {:.3f} mm (beta = {:g})", test.C * 1e3,
                                      v.rig.mode_mix)
                        : std::string()));
    if (!beam_only)
      say(fmt::format("  time step  {:.4g} s ({:g} of critical); about {} steps to Delta = {:g} mm",
                      dt, v.rig.dt_safety, expected_steps, v.deflection * 1e3));

    std::vector<physics::BeamReading> curve;
    double wall = 0.0, max_ratio = 0.0;
    if (beam_only) {
      // The cohesive beam stands in for the measured curve.
      for (std::size_t i = 0; i < czm.size(); ++i) {
        physics::BeamReading r;
        r.step = i;
        r.delta = czm[i].delta;
        r.load = r.load_instant = czm[i].load;
        r.delta_instant = czm[i].delta;
        r.crack = czm[i].crack;
        r.process_zone = czm[i].process_zone;
        curve.push_back(r);
      }
    } else {
      physics::BeamTestRig& rig = *built;
      curve.push_back(rig.reading());
      rig.restart_load_window();
      const auto start = std::chrono::steady_clock::now();
      auto last_report = start;
      const std::uint64_t limit = 3 * expected_steps + 1000;
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
        rig.restart_load_window();
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
      wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      io::write_file_atomically(out / "measured.csv", measured_csv(curve));
    }
    const physics::BeamReading& fin = curve.back();

    // Closed form.
    const auto analytic = physics::analytic_curve(test, v.deflection, 200);
    std::string acsv = "stage,delta_mm,load_N,crack_mm\n";
    for (const auto& p : analytic)
      acsv += fmt::format("{},{:.9g},{:.9g},{:.9g}\n", p.stage, p.delta * 1e3, p.load,
                          p.crack * 1e3);
    io::write_file_atomically(out / "analytic.csv", acsv);

    if (!beam_only)
      say(fmt::format("  done       {} steps in {:.1f} s ({:.0f} steps/s); Delta = {:.4f} mm, "
                      "crack a = {:.2f} mm; kinetic/external work <= {:.2e} after 5% of the run",
                      fin.step, wall, fin.step / wall, fin.delta * 1e3, fin.crack * 1e3, max_ratio));
    // Errors per stage against both references; the scenario's reference is judged.
    const bool by_czm = v.reference == io::Reference::cohesive_beam;
    say(fmt::format("  judged against {}", by_czm ? fmt::format("beam theory with the cohesive zone (sigma_c = {:g} MPa)", mat.sigma_c * 1e-6)
                                                 : std::string("the closed forms of LEFM (eqs 59-70)")));
    bool pass = true;
    const int split = physics::split_stage(v.rig.kind);
    std::string ecsv = kErrorsHeader, zcsv = kErrorsHeader;
    for (const io::StageCheck& check : v.checks) {
      const int stage = check.stage;
      const physics::StageErrors e = physics::compare_with_closed_form(test, curve, stage, v.margin);
      physics::StageErrors z;
      z.stage = stage;
      if (!czm.empty() && e.points > 0) z = cohesive_errors(czm, curve, stage, e.from, e.to, stage == split);
      const physics::StageErrors& judged = by_czm ? z : e;
      const bool ok = within(judged, check);
      pass = pass && ok;
      ecsv += error_row(e, check, !by_czm);
      if (!czm.empty() && !beam_only) zcsv += error_row(z, check, by_czm);
      if (judged.points == 0) {
        say(stage == split
                ? fmt::format("  stage {}    the crack never ran through the weak plane (a = {:.2f} "
                              "of {:.2f} mm): no split beam to compare FAIL",
                              stage, fin.crack * 1e3, physics::split_crack(test) * 1e3)
                : fmt::format("  stage {}    no point of the curve lies in this stage FAIL", stage));
      } else {
        say(fmt::format("  stage {}    {} {}", stage, describe(judged, check), ok ? "PASS" : "FAIL"));
        const physics::StageErrors& other = by_czm ? e : z;
        if (other.points > 0)
          say(fmt::format("             against {}: mean {:.2f}%, max {:.2f}%{}",
                          by_czm ? "LEFM" : "the cohesive beam", 100 * other.mean_error,
                          100 * other.max_error,
                          std::isfinite(other.slope_error)
                              ? fmt::format(", slope {:.2f}%", 100 * other.slope_error)
                              : std::string()));
      }
      if (stage == split && std::isfinite(judged.slope_error))
        manifest.facts[fmt::format("stage{}_slope_error", stage)] = fmt::format("{:.6f}", judged.slope_error);
      manifest.facts[fmt::format("stage{}_max_error", stage)] = fmt::format("{:.6f}", judged.max_error);
      manifest.facts[fmt::format("stage{}_mean_error", stage)] = fmt::format("{:.6f}", judged.mean_error);
    }
    double apeak = 0.0, apeak_delta = 0.0;
    for (const auto& p : analytic)
      if (p.stage <= 2 && p.load > apeak) {
        apeak = p.load;
        apeak_delta = p.delta;
      }
    // The measured peak: the largest load up to twice the closed form's peak deflection (a
    // cohesive zone delays the peak; later stages, such as the ENF's stage III, may climb
    // higher again and are not this peak). The cohesive beam's, the same way.
    const auto peak_of = [&](auto&& points) {
      std::pair<double, double> best{0.0, 0.0};  // load, delta
      for (const auto& p : points)
        if (p.delta <= 2.0 * apeak_delta && p.load > best.first) best = {p.load, p.delta};
      return best;
    };
    // Plain variables, not a structured binding: clang 14 cannot capture one in a lambda.
    const std::pair<double, double> measured_peak = peak_of(curve);
    const std::pair<double, double> cohesive_peak =
        czm.empty() ? std::pair{0.0, 0.0} : peak_of(czm);
    const double peak = measured_peak.first, peak_delta = measured_peak.second;
    const double zpeak = cohesive_peak.first, zpeak_delta = cohesive_peak.second;
    const double peak_error = std::abs(peak - apeak) / apeak;
    const double zpeak_error = zpeak > 0.0 ? std::abs(peak - zpeak) / zpeak : NAN;
    const double judged_peak_error = by_czm ? zpeak_error : peak_error;
    const bool peak_checked = v.peak_tolerance > 0.0;
    const bool peak_ok = !peak_checked || judged_peak_error <= v.peak_tolerance;
    pass = pass && peak_ok;
    const auto peak_row = [&](double reference_delta, double err, bool judged) {
      return fmt::format("peak,{:.6g},{:.6g},1,{:.6f},{:.6f},nan,,{},,{}\n", peak_delta * 1e3,
                         reference_delta * 1e3, err, err,
                         judged ? bound_cell(v.peak_tolerance) : "",
                         judged && peak_checked ? (peak_ok ? "yes" : "no") : "-");
    };
    ecsv += peak_row(apeak_delta, peak_error, !by_czm);
    if (!czm.empty() && !beam_only) zcsv += peak_row(zpeak_delta, zpeak_error, by_czm);
    say(fmt::format("  peak       {:.4g} N at {:.4f} mm; LEFM {:.4g} N at {:.4f} mm ({:.2f}%){}{}",
                    peak, peak_delta * 1e3, apeak, apeak_delta * 1e3, 100 * peak_error,
                    czm.empty() ? std::string()
                                : fmt::format("; cohesive beam {:.4g} N at {:.4f} mm ({:.2f}%)",
                                              zpeak, zpeak_delta * 1e3, 100 * zpeak_error),
                    peak_checked ? fmt::format(" (bound {:g}% on the {}) {}", 100 * v.peak_tolerance,
                                               by_czm ? "cohesive beam's" : "LEFM's",
                                               peak_ok ? "PASS" : "FAIL")
                                 : std::string()));
    if (!czm.empty()) {
      // How many cubes the process zone spans when the beam theory's load peaks: a zone of
      // fewer than a few cubes is not resolved by the lattice.
      for (const auto& p : czm)
        if (p.delta == zpeak_delta) {
          const double zone = p.process_zone - std::max(p.crack, test.a0);
          say(fmt::format("  process zone at the cohesive beam's peak: {:.3f} mm = {:.1f} cubes of 2r",
                          zone * 1e3, zone / (2.0 * v.rig.radius)));
          manifest.facts["process_zone_at_peak_mm"] = fmt::format("{:.6g}", zone * 1e3);
          break;
        }
    }
    io::write_file_atomically(out / "errors.csv", ecsv);
    if (!czm.empty() && !beam_only) io::write_file_atomically(out / "errors_cohesive_beam.csv", zcsv);
    else if (!czm_note.empty()) say(fmt::format("  no cohesive beam: {}", czm_note));

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
    if (!beam_only) plot.series.push_back(measured);
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
    manifest.facts["bodies"] = std::to_string(bodies);
    if (!beam_only) manifest.facts["links"] = std::to_string(built->lattice().links().size());
    manifest.facts["threads"] = std::to_string(omp_get_max_threads());
    manifest.facts["reference"] = by_czm ? "cohesive_beam" : "lefm";
    if (beam_only) manifest.facts["lattice"] = "not run (--cohesive-beam-only)";
    manifest.facts["steps"] = std::to_string(beam_only ? 0 : fin.step);
    if (!beam_only) manifest.facts["time_step_s"] = fmt::format("{:.9g}", dt);
    manifest.facts["wall_seconds"] = fmt::format("{:.3f}", wall);
    if (!beam_only) manifest.facts["steps_per_second"] = fmt::format("{:.1f}", fin.step / wall);
    manifest.facts["peak_load_N"] = fmt::format("{:.9g}", peak);
    manifest.facts["closed_form_peak_N"] = fmt::format("{:.9g}", apeak);
    // Relative to the reference the scenario is judged against, as its peak bound is.
    manifest.facts["peak_error"] = fmt::format("{:.6f}", judged_peak_error);
    manifest.facts["kinetic_over_work_max"] = fmt::format("{:.3e}", max_ratio);
    manifest.facts["validation"] = pass ? "pass" : "fail";
    manifest.provenance["ended_utc"] = io::utc_now();
    record.close(io::run_status::finished);
    say(fmt::format("  result     {} -> {} ({}analytic.csv, errors.csv, {}"
                    "load_deflection.svg)",
                    pass ? "PASS" : "FAIL", out.string(), beam_only ? "" : "measured.csv, ",
                    czm.empty() ? "" : beam_only ? "cohesive_beam.csv, " : "cohesive_beam.csv, errors_cohesive_beam.csv, "));
    return pass ? 0 : 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    manifest.provenance["ended_utc"] = io::utc_now();
    record.close_quietly(io::run_status::failed, e.what());
    return 2;
  }
}

}  // namespace cleave::app
