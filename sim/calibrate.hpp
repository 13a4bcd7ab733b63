#pragma once
/// \file
/// Calibration of a bonded specimen's micro-parameters to macroscopic targets, using the
/// structure of the problem instead of a blind search:
/// - E and nu: the honeycomb's closed form (validation/standard_tests.hpp) gives the first
///   bond springs; then nu, a function of k_bs / k_bn alone, is corrected by a secant step
///   on that ratio, and E, proportional to the springs at a fixed ratio, by scaling both;
/// - sigma_t: proportional to the bond strengths at a fixed t_bs / t_bn, so each trial
///   scales them by target over measured;
/// - sigma_f (with sigma_t): a bar breaks in tension on its lower face (t_bn), a disc is split
///   by its bonds' shear as well (t_bs), so the two strengths are found together by Broyden's
///   method in log space from a first Jacobian of that structure. Each strength trial then
///   runs both tests.
/// The elastic and the strength trials do not depend on each other (a brittle bond breaks
/// at a force, whatever the spring), so the two loops run side by side, one thread each.
/// Every trial is a `sim::measure` of the test's scenario with the parameters as overrides;
/// the loops stop when every target is within its tolerance or after `max_trials`.

#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sim/measure.hpp"

namespace cleave::sim {

/// What the calibration aims at (SI); a target left out is not calibrated.
struct CalibrationTargets {
  std::optional<double> young;             ///< E, Pa
  std::optional<double> poisson;           ///< nu
  std::optional<double> tensile_strength;  ///< sigma_t, Pa (Brazilian)
  std::optional<double> flexural_strength; ///< sigma_f, Pa (four-point bending); needs sigma_t
};

struct CalibrationSetup {
  std::filesystem::path elastic;    ///< scenario of the elastic test (for E, nu)
  std::filesystem::path brazilian;  ///< scenario of the Brazilian test (for sigma_t)
  std::filesystem::path flexural;   ///< scenario of the four-point bending test (for sigma_f)
  CalibrationTargets targets;
  double tolerance = 0.02;          ///< relative, on each target (nu: relative to nu)
  int max_trials = 8;               ///< per loop
  std::filesystem::path out;        ///< trials go to out/trial_NNN
  /// Where to start instead of the closed form's springs and the scenario's strengths
  /// ("bond.kbn", "bond.kbs", "bond.tbn", "bond.tbs"; any of them).
  std::map<std::string, double> start;
  bool quiet = false;
};

/// One trial: what was set, what was measured.
struct CalibrationTrial {
  int number = 0;
  std::string loop;  ///< "elastic" or "strength"
  std::map<std::string, double> parameters;  ///< bond.kbn, ... as set
  double measured = 0.0, measured_poisson = 0.0;
  double error = 0.0, error_poisson = 0.0;   ///< relative to the target
  /// Strength trials with a sigma_f target: the bar's strength and its error (NaN otherwise).
  double measured_flexural = NAN, error_flexural = NAN;
  double wall_seconds = 0.0;
};

struct CalibrationResult {
  bool converged = false;
  std::map<std::string, double> parameters;  ///< the fit: bond.kbn, bond.kbs, bond.tbn, bond.tbs
  std::vector<CalibrationTrial> trials;      ///< in the order they ended
  double wall_seconds = 0.0;
};

/// Runs the loops (see the file comment). Throws io::ScenarioError / std::runtime_error
/// for a scenario that is not the test it is given as.
CalibrationResult calibrate(const CalibrationSetup& setup);

/// calibration.csv: one row per trial.
std::string calibration_csv(const CalibrationResult& r);

}  // namespace cleave::sim
