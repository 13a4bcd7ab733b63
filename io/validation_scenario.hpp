#pragma once
/// \file
/// Validation scenarios (scenarios/validation/*.toml): a DCB, ENF or MMB fracture test of
/// Chen et al. 2020 (seed 002, sec. 7) on the cubic lattice, and what its measured
/// load-deflection curve must meet against the closed forms. Same TOML conventions and errors
/// as io/scenario.hpp (ScenarioError with file, line, column and key).
///
///   [scenario]        name, description (optional); length_unit = "mm" (default; "m", "um")
///   [specimen]        test = "dcb" | "enf" | "mmb" (required)
///                     length (DCB: L; ENF, MMB: 2L), breadth (B), height (2h),
///                     initial_crack (a0), particle_radius (r): length unit, > 0, required;
///                     each of length, breadth, height a whole number of diameters 2r
///                     mode_mix = 0.5 (MMB only, required there: beta = G_II/G_T in (0, 1))
///                     bending_springs = 1 (>= 0: the links' bending springs as a multiple of
///                     E (2r)^3 / 12; 0 gives the paper's lattice, see physics/lattice/cubic_lattice.hpp)
///                     effective_areas = "tiled" (default: eq. 10's areas scaled to tile a
///                     plane, physics::tiled_areas) or "paper" (eq. 10 as it stands)
///                     intact_length = 0 (DCB only; length unit, a whole number of 2r: the
///                     beam goes on uncracked this far beyond the weak plane to the clamp)
///   [material]        young (Pa), poisson ([0, 0.25)), density (kg/m^3),
///                     cohesive_strength (Pa), fracture_energy (G_c of the weak plane, N/m):
///                     required; g_Ic, g_IIc (N/m, for the closed forms; default
///                     fracture_energy); contact_penalty (kappa, default 1);
///                     friction (crack faces, default 0)
///   [loading]         velocity (v0, m/s), ramp_time (t0, s, >= 0), deflection (length unit:
///                     the run ends when Delta reaches it): required
///   [dynamics]        dt_safety ((0, 1], default 0.9), global_damping (1/s, >= 0, default 0),
///                     threads (>= 0, default 0: all), records (rows of the curve, default 400)
///   [validation]      what the measured curve is judged against, and how closely:
///                     reference = "lefm" (default: the closed forms, eqs 59-70) or
///                     "cohesive_beam" (the same beam theory with the scenario's cohesive zone,
///                     validation/cohesive_beam.hpp);
///                     stage1 ... stage4 = { mean = 0.05, max = 0.08, slope = 0.05 }: the
///                     bounds on a stage's mean and largest relative load error, and (the split
///                     beam's stage only: DCB III, ENF IV) on its fitted slope; each key
///                     optional, at least one stage required;
///                     or, the older short form, stages = [1, 2] with tolerance (and measure =
///                     "max" (default) | "mean"): that bound on each listed stage (the split
///                     stage's on its slope);
///                     peak_tolerance (relative, default: not checked), margin ([0, 0.5),
///                     default 0.1: the part of each stage's deflection range left out at
///                     either end, where the cohesive zone blurs the sharp corners of LEFM)

#include <filesystem>
#include <string>
#include <vector>

#include "validation/beam_test_rig.hpp"

namespace cleave::io {

/// What a validation run's measured curve is judged against.
enum class Reference { lefm, cohesive_beam };

/// The bounds on one stage's relative load errors (0: that measure is not bounded).
struct StageCheck {
  int stage = 0;
  double mean = 0.0;   ///< on the mean error over the stage's points
  double max = 0.0;    ///< on every point's error
  double slope = 0.0;  ///< on the fitted slope of the split beam's stage
  bool operator==(const StageCheck&) const = default;
};

struct ValidationScenario {
  std::string source;  ///< file name, for messages
  std::string name, description;
  physics::BeamRigDef rig;
  double deflection = 0.0;  ///< m: the run ends when Delta reaches it
  int threads = 0;
  int records = 400;
  Reference reference = Reference::lefm;
  std::vector<StageCheck> checks;  ///< in stage order, one per checked stage
  double peak_tolerance = 0.0;     ///< 0: the peak load is not checked
  double margin = 0.1;
};

ValidationScenario parse_validation_scenario(const std::string& text, const std::string& source);
ValidationScenario load_validation_scenario(const std::filesystem::path& file);

/// The scenario as run: every key with the value used (defaults filled in), lengths in
/// metres (length_unit = "m"), numbers written so that they read back bit for bit; parsing
/// it gives a ValidationScenario equal to `v` (source aside).
std::string validation_scenario_as_run(const ValidationScenario& v);

}  // namespace cleave::io
