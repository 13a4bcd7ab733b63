/// \file
/// Calibration of bond parameters to macroscopic targets (see calibrate.hpp).

#include "sim/calibrate.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "io/scenario.hpp"

namespace cleave::sim {

namespace {

using Clock = std::chrono::steady_clock;

/// nu of the honeycomb at K_s / K_n = rho, and E t / K_n (validation/standard_tests.hpp).
double honeycomb_nu(double rho) { return (1.0 - rho) / (3.0 + rho); }
double honeycomb_e_per_kn(double rho) { return 2.0 * std::sqrt(3.0) * (1.0 + rho) / (3.0 + rho); }

struct Shared {
  explicit Shared(const CalibrationSetup& s) : setup(s) {}
  const CalibrationSetup& setup;
  /// The elastic scenario's time step and normal bond spring: a stiffer trial takes a
  /// step shorter by sqrt(k_bn / k_bn0), so that it stays as stable as the scenario.
  double dt0 = 0.0, kbn0 = 0.0;
  std::mutex mutex;
  std::atomic<int> next{1};
  CalibrationResult result;
};

std::vector<std::string> overrides_of(const std::map<std::string, double>& p) {
  std::vector<std::string> out = {"dynamics.threads=1"};
  for (const auto& [key, value] : p) out.push_back(fmt::format("{}={:.9g}", key, value));
  return out;
}

Measurement trial(Shared& sh, Test test, const std::filesystem::path& scenario,
                  const std::map<std::string, double>& p, CalibrationTrial& t) {
  t.number = sh.next++;
  t.parameters = p;
  std::vector<std::string> overrides = overrides_of(p);
  if (const auto kbn = p.find("bond.kbn"); kbn != p.end() && kbn->second > sh.kbn0 && sh.dt0 > 0.0) {
    overrides.push_back(fmt::format("dynamics.dt={:.6g}", sh.dt0 * std::sqrt(sh.kbn0 / kbn->second)));
  }
  SimulationOptions o;
  o.out = sh.setup.out / fmt::format("trial_{:03d}", t.number);
  o.quiet = true;
  // The trial folders are the calibration's own: a trial of another test there (an earlier
  // calibration that took other steps) is replaced; files cleave did not write still stop it.
  o.replace = true;
  const auto start = Clock::now();
  Measurement m = measure(test, scenario, o, overrides);
  t.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (m.report.status != RunReport::Status::finished) {
    throw std::runtime_error(fmt::format("calibration trial {} ({}) did not finish: {}", t.number,
                                         scenario.string(), m.report.message));
  }
  return m;
}

/// What trial `t` of `scenario` is judged by (judged_value); a bending test with no first
/// crack to read it at is an error.
double judged(const Measurement& m, const CalibrationTrial& t, const std::filesystem::path& scenario) {
  const double v = judged_value(m);
  if (!(v > 0.0)) {
    throw std::runtime_error(fmt::format("calibration trial {} ({}): no first crack to read its {} at", t.number,
                                         scenario.string(), to_string(m.test)));
  }
  return v;
}

void record(Shared& sh, const CalibrationTrial& t, const std::string& line) {
  std::lock_guard lock(sh.mutex);
  sh.result.trials.push_back(t);
  if (!sh.setup.quiet) fmt::print("  trial {:>3} {:<8} {}  ({:.0f} s)\n", t.number, t.loop, line, t.wall_seconds);
  std::fflush(stdout);
}

/// E and nu: springs from the closed form, then secant on k_bs / k_bn for nu and scaling
/// for E. Returns whether both came within the tolerance.
bool elastic_loop(Shared& sh, std::map<std::string, double> p, std::map<std::string, double>& fit) {
  const CalibrationSetup& s = sh.setup;
  const double E = *s.targets.young;
  double rho = p.at("bond.kbs") / p.at("bond.kbn");
  double prev_rho = NAN, prev_nu = NAN;
  for (int k = 0; k < s.max_trials; ++k) {
    CalibrationTrial t;
    t.loop = "elastic";
    const Measurement m = trial(sh, Test::elastic, s.elastic, p, t);
    t.measured = m.value;
    t.measured_poisson = m.poisson;
    t.error = m.value / E - 1.0;
    t.error_poisson = s.targets.poisson ? m.poisson / *s.targets.poisson - 1.0 : 0.0;
    record(sh, t,
           fmt::format("k_bn {:.5g} k_bs {:.5g}: E {:.4g} GPa ({:+.2f} %), nu {:.4f}{}", p["bond.kbn"],
                       p["bond.kbs"], m.value / 1e9, 100 * t.error, m.poisson,
                       s.targets.poisson ? fmt::format(" ({:+.2f} %)", 100 * t.error_poisson) : ""));
    const bool done = std::abs(t.error) <= s.tolerance && std::abs(t.error_poisson) <= s.tolerance;
    fit["bond.kbn"] = p["bond.kbn"];
    fit["bond.kbs"] = p["bond.kbs"];
    if (done) return true;
    double new_rho = rho;
    if (s.targets.poisson) {
      // The measured nu(rho) has the closed form's shape, shifted by the specimen's edges:
      // the secant of the last two trials, or the closed form's slope at the first.
      const double slope = std::isnan(prev_nu) || std::abs(rho - prev_rho) < 1e-12
                               ? -4.0 / ((3.0 + rho) * (3.0 + rho))
                               : (m.poisson - prev_nu) / (rho - prev_rho);
      new_rho = std::clamp(rho + (*s.targets.poisson - m.poisson) / slope, 0.0, 1.0);
      prev_rho = rho;
      prev_nu = m.poisson;
    }
    const double kbn = p["bond.kbn"] * (E / m.value) * honeycomb_e_per_kn(rho) / honeycomb_e_per_kn(new_rho);
    rho = new_rho;
    p["bond.kbn"] = kbn;
    p["bond.kbs"] = rho * kbn;
  }
  return false;
}

/// sigma_t: the bond strengths scaled by target over measured, their ratio kept. With a
/// sigma_f target as well, each trial also breaks the bar, and (ln t_bn, ln t_bs) move by
/// Broyden's method on (ln sigma_t, ln sigma_f): the first Jacobian says that sigma_t grows
/// with both strengths, half each, and sigma_f (the bar's first crack, on its tension face)
/// with t_bn alone (SiC's ratio study in
/// docs/USER_GUIDE.md, "Why the SiC model is as it is": from t_bs = t_bn up the bar breaks in tension and
/// the disc gains as t_bs^0.53); each trial's secant corrects it. Steps are at most a factor
/// e^0.5 per strength, so that no trial leaves the scenarios' reach by much.
bool strength_loop(Shared& sh, std::map<std::string, double> p, std::map<std::string, double>& fit) {
  const CalibrationSetup& s = sh.setup;
  const double target = *s.targets.tensile_strength;
  const std::optional<double> flexural = s.targets.flexural_strength;
  const double flexural_tolerance = s.flexural_tolerance.value_or(s.tolerance);
  double best = std::numeric_limits<double>::infinity();
  Eigen::Matrix2d jacobian;
  jacobian << 0.5, 0.5, 1.0, 0.0;
  Eigen::Vector2d prev_x = Eigen::Vector2d::Zero(), prev_f = Eigen::Vector2d::Zero();
  bool have_prev = false;
  for (int k = 0; k < s.max_trials; ++k) {
    CalibrationTrial t;
    t.loop = "strength";
    // The bar runs beside the disc, one thread each (each measurement has one thread).
    CalibrationTrial bar_trial;
    Measurement bar_m;
    std::exception_ptr bar_failure;
    std::thread bar_thread;
    if (flexural) {
      bar_thread = std::thread([&] {
        try {
          bar_m = trial(sh, Test::flexural, s.flexural, p, bar_trial);
        } catch (...) {
          bar_failure = std::current_exception();
        }
      });
    }
    std::exception_ptr disc_failure;
    Measurement m;
    try {
      m = trial(sh, Test::brazilian, s.brazilian, p, t);
    } catch (...) {
      disc_failure = std::current_exception();
    }
    if (bar_thread.joinable()) bar_thread.join();
    if (disc_failure) std::rethrow_exception(disc_failure);
    if (bar_failure) std::rethrow_exception(bar_failure);
    t.measured = m.value;
    t.error = m.value / target - 1.0;
    std::string bar;
    if (flexural) {
      t.wall_seconds = std::max(t.wall_seconds, bar_trial.wall_seconds);  // side by side
      // The bar's tension-face stress at its first crack from its mid-span section's
      // statics (judged_value): the formula's peak carries the rollers' friction couple and
      // moves with the loading rate; this reading does neither.
      t.measured_flexural = judged(bar_m, bar_trial, s.flexural);
      t.error_flexural = t.measured_flexural / *flexural - 1.0;
      bar = fmt::format(", sigma_f {:.4g} MPa ({:+.2f} %; the formula's peak {:.4g})", t.measured_flexural / 1e6,
                        100 * t.error_flexural, bar_m.value / 1e6);
    }
    record(sh, t, fmt::format("t_bn {:.5g} t_bs {:.5g}: sigma_t {:.4g} MPa ({:+.2f} %){}", p["bond.tbn"],
                              p["bond.tbs"], m.value / 1e6, 100 * t.error, bar));
    // The fit is the best trial so far (the largest of its errors relative to their
    // tolerances): a bar's strength responds to the strengths by jumps, so a later trial
    // is not always nearer.
    const double badness = std::max(std::abs(t.error) / s.tolerance,
                                    flexural ? std::abs(t.error_flexural) / flexural_tolerance : 0.0);
    if (badness < best) {
      best = badness;
      fit["bond.tbn"] = p["bond.tbn"];
      fit["bond.tbs"] = p["bond.tbs"];
    }
    if (badness <= 1.0) return true;
    if (!flexural) {
      p["bond.tbn"] *= target / m.value;
      p["bond.tbs"] *= target / m.value;
      continue;
    }
    const Eigen::Vector2d x(std::log(p["bond.tbn"]), std::log(p["bond.tbs"]));
    const Eigen::Vector2d f(std::log(m.value / target), std::log(t.measured_flexural / *flexural));
    if (have_prev) {
      const Eigen::Vector2d dx = x - prev_x, df = f - prev_f;
      if (dx.squaredNorm() > 1e-12) jacobian += (df - jacobian * dx) * dx.transpose() / dx.squaredNorm();
    }
    Eigen::Vector2d step = -jacobian.fullPivLu().solve(f);
    if (!step.allFinite() || std::abs(jacobian.determinant()) < 1e-6) step = Eigen::Vector2d::Constant(-f(0));
    step = step.cwiseMax(-0.5).cwiseMin(0.5);
    prev_x = x;
    prev_f = f;
    have_prev = true;
    p["bond.tbn"] = std::exp(x(0) + step(0));
    p["bond.tbs"] = std::exp(x(1) + step(1));
  }
  return false;
}

/// K_Ic: the transgranular criterion's crack length scaled by (measured / target)^2, the
/// bonds at the other loops' fit. `a` is in the scenario's length unit.
bool toughness_loop(Shared& sh, std::map<std::string, double> p, double a, std::map<std::string, double>& fit) {
  const CalibrationSetup& s = sh.setup;
  const double target = *s.targets.toughness;
  for (int k = 0; k < s.max_trials; ++k) {
    p["fracture.crack_length"] = a;
    CalibrationTrial t;
    t.loop = "toughness";
    const Measurement m = trial(sh, Test::senb, s.senb, p, t);
    // K_Ic at the first crack (judged_value): a crack that stops after it is the lattice's.
    t.measured = judged(m, t, s.senb);
    t.error = t.measured / target - 1.0;
    const bool through_bonds = m.first_crack == "bond";
    record(sh, t,
           fmt::format("crack length a {:.5g}: K_Ic {:.4g} MPa m^0.5 ({:+.2f} %), first crack: {}", a,
                       t.measured / 1e6, 100 * t.error, m.first_crack.empty() ? "none" : m.first_crack));
    fit["fracture.crack_length"] = a;
    if (std::abs(t.error) <= s.tolerance) {
      if (through_bonds) {
        sh.result.advice = fmt::format(
            "{}: K_Ic is within tolerance and carried by the grain boundaries (a bond broke before any "
            "grain split): the grain size sets it, and the crack length ({:.5g}) was kept as it is",
            s.senb.string(), a);
      }
      return true;
    }
    if (through_bonds) {
      // A bond broke first: the crack left the notch along grain boundaries,
      // and the crack length cannot move K_Ic. A bonded model's K_Ic goes as sigma
      // sqrt(grain size) (Potyondy and Cundall 2004); the strengths stay under a geometric
      // scaling, so the scale is what fits it.
      const double scale = (target / t.measured) * (target / t.measured);
      sh.result.advice = fmt::format(
          "{}: the notched beam cracked along its grain boundaries (a bond broke before any "
          "grain split), so its K_Ic ({:.4g} MPa m^0.5) is set by the grain size, not by the crack "
          "length. K_Ic through bonds goes as the square root of the model's length scale, "
          "which leaves E, nu and the strengths as they are: scale every test scenario by "
          "{:.4g} (tools/scale_scenario.py SCENARIO {:.4g} -o OUT) and calibrate again",
          s.senb.string(), t.measured / 1e6, scale, scale);
      return false;
    }
    // Eq. 3.23: K_I = sigma sqrt(pi a), so the splitting stress, and with it the beam's
    // K_Ic, goes as a^-1/2.
    a *= std::clamp((t.measured / target) * (t.measured / target), 1.0 / 16.0, 16.0);
  }
  return false;
}

}  // namespace

CalibrationResult calibrate(const CalibrationSetup& setup) {
  const auto start = Clock::now();
  Shared sh{setup};
  if (!setup.targets.young && !setup.targets.poisson && !setup.targets.tensile_strength &&
      !setup.targets.toughness) {
    throw std::invalid_argument("calibrate: no targets");
  }
  if (setup.targets.flexural_strength && !setup.targets.tensile_strength) {
    throw std::invalid_argument(
        "calibrate: a flexural strength target needs a tensile strength target too (sigma_f is "
        "fitted through t_bs / t_bn, sigma_t through the strengths' scale)");
  }
  if (setup.targets.flexural_strength && setup.flexural.empty()) {
    throw std::invalid_argument("calibrate: a flexural strength target needs a four-point bending scenario");
  }
  if (setup.targets.toughness && setup.senb.empty()) {
    throw std::invalid_argument("calibrate: a K_Ic target needs a SENB scenario");
  }
  if (setup.targets.poisson && !setup.targets.young) {
    throw std::invalid_argument("calibrate: a Poisson's ratio target needs an E target too");
  }
  // The first springs: the closed form for the targets on the elastic specimen.
  std::map<std::string, double> elastic_start, strength_start;
  if (setup.targets.young) {
    const io::Scenario sc = io::load_scenario(setup.elastic);
    if (!sc.bond.enabled) throw std::runtime_error(setup.elastic.string() + ": no [bond] to calibrate");
    if (sc.bond.params.law == physics::BondLaw::beam)
      throw std::runtime_error(setup.elastic.string() +
                               ": [bond] law: the elastic calibration fits kbn and kbs; a beam bond has none");
    const double ab = M_PI * sc.contact.dilation_radius * sc.contact.dilation_radius;
    sh.dt0 = sc.dynamics.dt;
    sh.kbn0 = sc.bond.params.kbn;
    const double rho0 = sc.bond.params.kbs / sc.bond.params.kbn;
    const double nu = setup.targets.poisson.value_or(honeycomb_nu(rho0));
    if (!(nu >= 0.0 && nu <= 1.0 / 3.0)) {
      throw std::invalid_argument(fmt::format(
          "calibrate: a honeycomb of normal and shear bond springs has 0 <= nu <= 1/3; the target is {}", nu));
    }
    const physics::BondSprings k =
        physics::honeycomb_springs(*setup.targets.young, nu, sc.specimen.outline.size.z());
    elastic_start = {{"bond.kbn", k.kn / ab}, {"bond.kbs", k.ks / ab}};
  }
  if (setup.targets.tensile_strength) {
    const io::Scenario sc = io::load_scenario(setup.brazilian);
    if (!sc.bond.enabled) throw std::runtime_error(setup.brazilian.string() + ": no [bond] to calibrate");
    if (sc.bond.params.criterion != physics::BondCriterion::limits || sc.bond.params.law == physics::BondLaw::beam)
      throw std::runtime_error(setup.brazilian.string() +
                               ": [bond] criterion: the strength calibration fits tbn and tbs (criterion = \"limits\")");
    strength_start = {{"bond.tbn", sc.bond.params.tbn}, {"bond.tbs", sc.bond.params.tbs}};
  }
  for (const auto& [key, value] : setup.start) {
    if (elastic_start.count(key)) elastic_start[key] = value;
    if (strength_start.count(key)) strength_start[key] = value;
  }
  std::map<std::string, double> elastic_fit, strength_fit;
  bool elastic_ok = true, strength_ok = true;
  std::exception_ptr failure;
  std::thread strength;
  if (setup.targets.tensile_strength) {
    strength = std::thread([&] {
      try {
        strength_ok = strength_loop(sh, strength_start, strength_fit);
      } catch (...) {
        failure = std::current_exception();
      }
    });
  }
  std::exception_ptr elastic_failure;
  if (setup.targets.young) {
    try {
      elastic_ok = elastic_loop(sh, elastic_start, elastic_fit);
    } catch (...) {
      elastic_failure = std::current_exception();
    }
  }
  if (strength.joinable()) strength.join();
  if (elastic_failure) std::rethrow_exception(elastic_failure);
  if (failure) std::rethrow_exception(failure);
  sh.result.converged = elastic_ok && strength_ok;
  sh.result.parameters = elastic_fit;
  sh.result.parameters.insert(strength_fit.begin(), strength_fit.end());
  if (setup.targets.toughness) {
    const io::Scenario sc = io::load_scenario(setup.senb);
    if (!sc.fracture.enabled) {
      throw io::ScenarioError(sc.source, 1, 1, "fracture",
                              "a K_Ic target is fitted through the transgranular criterion's crack "
                              "length: the SENB scenario needs a [fracture] table");
    }
    if (sc.fracture.params.criterion != physics::GrainCriterion::lefm) {
      throw io::ScenarioError(sc.source, 1, 1, "fracture.criterion",
                              "a K_Ic target is fitted through the crack length of criterion = \"lefm\"");
    }
    double a = sc.fracture.params.crack_length / io::length_unit_metres(sc.length_unit);
    if (const auto it = setup.start.find("fracture.crack_length"); it != setup.start.end()) a = it->second;
    // The bonds at the strength fit; the springs stay the scenario's: the beam is linear up
    // to the first split, so the load at which the splitting stress is reached does not
    // depend on E (and a stiffer spring would need the SENB's own shorter time step).
    std::map<std::string, double> bonds;
    for (const char* key : {"bond.tbn", "bond.tbs"}) {
      if (const auto it = strength_fit.find(key); it != strength_fit.end()) bonds[key] = it->second;
    }
    std::map<std::string, double> toughness_fit;
    const bool ok = toughness_loop(sh, bonds, a, toughness_fit);
    sh.result.converged = sh.result.converged && ok;
    sh.result.parameters.insert(toughness_fit.begin(), toughness_fit.end());
  }
  sh.result.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return sh.result;
}

std::string calibration_csv(const CalibrationResult& r) {
  std::string out =
      "trial,loop,kbn,kbs,tbn,tbs,crack_length,measured,measured_poisson,error,error_poisson,"
      "measured_flexural,error_flexural,wall_s\n";
  const auto get = [](const CalibrationTrial& t, const char* k) {
    const auto it = t.parameters.find(k);
    return it == t.parameters.end() ? std::string() : fmt::format("{:.9g}", it->second);
  };
  for (const auto& t : r.trials) {
    const bool bar = !std::isnan(t.measured_flexural);
    out += fmt::format("{},{},{},{},{},{},{},{:.9g},{},{:.6g},{},{},{},{:.2f}\n", t.number, t.loop,
                       get(t, "bond.kbn"), get(t, "bond.kbs"), get(t, "bond.tbn"), get(t, "bond.tbs"),
                       get(t, "fracture.crack_length"),
                       t.measured, t.loop == "elastic" ? fmt::format("{:.6g}", t.measured_poisson) : "",
                       t.error, t.loop == "elastic" ? fmt::format("{:.6g}", t.error_poisson) : "",
                       bar ? fmt::format("{:.9g}", t.measured_flexural) : "",
                       bar ? fmt::format("{:.6g}", t.error_flexural) : "", t.wall_seconds);
  }
  return out;
}

}  // namespace cleave::sim
