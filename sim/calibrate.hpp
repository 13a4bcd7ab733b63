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
///   runs both tests, side by side on two threads;
/// - K_Ic (with transgranular fracture on, the crack running through grains): the notched
///   beam's toughness is set by the grain-fracture criterion, a stress threshold K_Ic^cleavage
///   / sqrt(pi a), so it goes as a^-1/2 in the criterion's crack length a: each trial scales a
///   by (measured / target)^2. It runs after the strength loop, with its fit.
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
  /// sigma_f, Pa (four-point bending), compared with the bar's tension-face stress at its
  /// first crack from its mid-span section's statics (judged_value); needs sigma_t
  std::optional<double> flexural_strength;
  std::optional<double> toughness;         ///< K_Ic, Pa m^0.5 (SENB with [fracture])
};

struct CalibrationSetup {
  std::filesystem::path elastic;    ///< scenario of the elastic test (for E, nu)
  std::filesystem::path brazilian;  ///< scenario of the Brazilian test (for sigma_t)
  std::filesystem::path flexural;   ///< scenario of the four-point bending test (for sigma_f)
  std::filesystem::path senb;       ///< scenario of the SENB test (for K_Ic), with [fracture]
  CalibrationTargets targets;
  double tolerance = 0.02;          ///< relative, on each target (nu: relative to nu)
  /// Relative, on sigma_f; unset: `tolerance`. A coarse bar's strength moves by jumps of
  /// several per cent as the strengths change by one (the first break on its lower face
  /// becomes the peak or does not), which a tight tolerance may never meet.
  std::optional<double> flexural_tolerance;
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
  std::string loop;  ///< "elastic", "strength" or "toughness"
  /// bond.kbn, ... as set; fracture.crack_length in the scenario's length unit (as an
  /// override takes it)
  std::map<std::string, double> parameters;
  double measured = 0.0, measured_poisson = 0.0;
  double error = 0.0, error_poisson = 0.0;   ///< relative to the target
  /// Strength trials with a sigma_f target: the bar's judged_value (its tension-face stress
  /// at its first crack) and its error (NaN otherwise).
  double measured_flexural = NAN, error_flexural = NAN;
  double wall_seconds = 0.0;  ///< a disc and a bar side by side: the longer of the two
};

struct CalibrationResult {
  bool converged = false;
  /// The fit: bond.kbn, bond.kbs, bond.tbn, bond.tbs (the strengths of the best strength
  /// trial: the one whose largest error relative to its tolerance is smallest), and with a
  /// K_Ic target fracture.crack_length (in the SENB scenario's length unit)
  std::map<std::string, double> parameters;
  std::vector<CalibrationTrial> trials;      ///< in the order they ended
  double wall_seconds = 0.0;
  /// What the calibration found that a user must act on or know (empty: nothing), e.g. that
  /// the notched beam's K_Ic is carried by its bonds and what scale would fit it.
  std::string advice;
};

/// Runs the loops (see the file comment). Throws io::ScenarioError / std::runtime_error
/// for a scenario that is not the test it is given as.
CalibrationResult calibrate(const CalibrationSetup& setup);

/// calibration.csv: one row per trial.
std::string calibration_csv(const CalibrationResult& r);

}  // namespace cleave::sim
