#pragma once
/// \file
/// Macroscopic measurements on a bonded specimen, as a laboratory takes them: a scenario
/// of the test is run (sim::Simulation) and its readings turned into the property a
/// handbook lists, by the standard formula (validation/standard_tests.hpp):
/// - `elastic`: a small-strain uniaxial test between two platens (the walls the last stage
///   moves). Stress = the platens' load over the specimen's section; strain from the
///   platens' approach over the specimen's height, and from the affine fit of the grains'
///   displacements in the middle half of the height (free of the platen contacts' give).
///   E is the slope of stress against strain, nu the slope of lateral against axial
///   strain, both by least squares over the last 70 % of the loading stage.
/// - `brazilian`: sigma_t = 2P/(pi D t) of the peak load of a disc.
/// - `flexural`: four-point bending, sigma_f = 3P (L - L_i) / (2 b d^2) of the peak load,
///   the spans read off the cylinder walls (the rollers the last stage moves load; the
///   others support).
/// - `senb`: a notched beam in three-point bending (S = 4W), K_Ic = P S / (B W^1.5) Y(a/W)
///   of ASTM C1421 at the peak load.
/// A lattice specimen's section is its cells': depth = rows x 1.5 r, thickness = layers x t,
/// width = the shortest row's cells, sqrt(3) r each (the width that carries a load along
/// y; see specimen_section), not the outline's.
/// The strength tests need the loading stage to end by its load drop: a peak at the end of
/// the stage's time is no strength, and is refused.

#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/simulation.hpp"
#include "validation/standard_tests.hpp"

namespace cleave::sim {

enum class Test { elastic, brazilian, flexural, senb };
const char* to_string(Test t);
/// "elastic", "brazilian", "flexural", "senb"; nothing for another name.
std::optional<Test> parse_test(std::string_view name);

/// One reading of the elastic test (compression positive).
struct ElasticSample {
  double time = 0.0;            ///< s, since the loading stage began
  double stress = 0.0;          ///< Pa, load over section
  double strain_platens = 0.0;  ///< the platens' approach over the height
  double strain_axial = 0.0;    ///< -eps_yy of the grains' affine fit
  double strain_lateral = 0.0;  ///< eps_xx of the fit
};

/// The specimen's section as the formulas read it (m).
struct Section {
  double width = 0.0;      ///< x: across the load (compression, Brazilian: the diameter)
  double depth = 0.0;      ///< y: along the load
  double thickness = 0.0;  ///< z: the prisms' length
  /// A notched beam's notch depth: the outline's, or on the lattice the rows it cut away
  /// from the bottom (the cells it touches go), x 1.5 r.
  double notch = 0.0;
};

struct Measurement {
  Test test = Test::elastic;
  /// E (Pa), sigma_t (Pa), sigma_f (Pa) or K_Ic (Pa m^0.5).
  double value = NAN;
  double poisson = NAN;        ///< elastic
  double young_platens = NAN;  ///< elastic: E from the platens' approach
  double peak_load = NAN;      ///< strength tests: N
  double peak_displacement = NAN;  ///< m
  Section section;
  /// The formula with its numbers, e.g. "sigma_t = 2P/(pi D t) = 2 x 812 N / (pi x ...)".
  std::string formula;
  std::vector<ElasticSample> samples;  ///< elastic
  /// Elastic, bonded lattice specimens: the honeycomb's closed form for the scenario's
  /// bond springs (validation/standard_tests.hpp), to compare with.
  std::optional<physics::HoneycombElasticity> closed_form;
  /// The largest ratio of kinetic energy to the work the walls did on the specimen over
  /// the loading stage's second half (strength tests: between half the time to the peak and
  /// the peak): how quasi-static the test was (small is good).
  double kinetic_ratio = NAN;
  /// Strength tests: what cracked first in the loading stage, "bond" (a grain boundary) or
  /// "grain" (a transgranular split; "grain" too when both came within one sample of the
  /// load), empty when nothing did. In a brittle test the first crack is the one that sets
  /// the peak: a notched beam whose first crack is a bond's has its K_Ic from the bonds,
  /// whatever the grains' criterion.
  std::string first_crack;
  /// Strength tests: the load on the last sample (1/4,000 of the loading stage) before the
  /// first crack (N), and the value its formula gives there: the crack-initiation reading,
  /// beside the peak's (the same when the first crack runs through). NaN without a crack.
  double first_crack_load = NAN;
  double value_at_first_crack = NAN;
  /// Four-point bending and the notched beam, from the statics of the section at mid-span
  /// (the notch's): the sagging moment M (N m, about the specimen's mean grain centroid) and
  /// the axial force N (N, tension positive) of the rollers' contact forces on the part left
  /// of it, each force where it acts, at the first crack's sample; and the value they give,
  /// the largest over the loading's samples (1/4,000 of the stage) and the first crack's:
  /// the tension face's sigma = 6 M / (b d^2) + N / (b d), or K_I = the SENB formula's with
  /// P S replaced by 4 M plus an edge-notched strip's K_I under N. The formulas assume
  /// vertical forces at the rollers' axes; a roller's friction, or a grain corner pushing
  /// off its apex, puts a couple against the bending and a push along the faces that only
  /// this reading sees (USER_GUIDE, "Reading a testing machine's load").
  double moment_at_first_crack = NAN;
  double axial_at_first_crack = NAN;
  double value_from_statics = NAN;
  double value_from_statics_at_first_crack = NAN;
  RunReport report;
};

/// The section of `specimen` (see the file comment).
Section specimen_section(const geometry::Specimen& specimen);

/// Runs the scenario (with `overrides`, "table.key=value") in `options.out` and measures.
/// Throws io::ScenarioError for a bad scenario and std::runtime_error when the scenario
/// is not such a test (no platens, wrong outline, no load drop, S/W far from 4), naming it.
Measurement measure(Test test, const std::filesystem::path& scenario, SimulationOptions options,
                    const std::vector<std::string>& overrides = {}, int samples = 25);

/// The value a test is judged by, against its preset, in a calibration and in a loading-rate
/// study. The bending tests are read at their first crack, as a brittle ceramic breaks at
/// its first: the lattice, a few grains deep, stops a crack where its path turns, and the
/// load that climbs on after it depends on the loading rate and which bonds go next
/// (USER_GUIDE, "Check that loading is quasi-static").
/// - four-point bending: the tension face's stress from the section's statics at the first
///   crack (value_from_statics_at_first_crack); the formula's peak also carries the
///   rollers' friction couple;
/// - the notched beam: K_Ic from the notched section's statics at the first crack
///   (value_from_statics_at_first_crack), for the same reason;
/// - the elastic test and the disc: `value`.
double judged_value(const Measurement& m);

/// Whether test `t` is judged at its first crack from its mid-span section's statics (the
/// bending tests) rather than by its formula's value.
bool judged_at_first_crack(Test t);

/// The measure.toml key of judged_value: "flexural_strength_Pa_from_statics_at_first_crack",
/// "k_ic_Pa_sqrt_m_from_statics_at_first_crack", or value_key.
std::string judged_key(Test t);

/// The key of the measured value in measure.toml and convergence.csv: "young_Pa",
/// "tensile_strength_Pa", "flexural_strength_Pa" or "k_ic_Pa_sqrt_m".
const char* value_key(Test t);

/// One run of a loading-rate study: the test with its loading stage at rate_scale times the
/// scenario's wall velocities (and its length over it).
struct RatePoint {
  double rate_scale = 1.0;
  double wall_speed = 0.0;     ///< m/s: the fastest loading wall's speed
  double value = NAN;          ///< the measured property (judged_value)
  double kinetic_ratio = NAN;  ///< Measurement::kinetic_ratio
  double change = NAN;         ///< value / previous run's value - 1 (NaN for the first)
  double wall_seconds = 0.0;
  std::filesystem::path out;   ///< its result folder
};

struct RateStudy {
  std::vector<RatePoint> points;
  double tolerance = 0.02;
  bool converged = false;  ///< the last halving changed the value by less than the tolerance
};

/// The quasi-static check of a test: runs it at rate_scale 1, 1/2, 1/4, ... (each in
/// options.out / "rate_<scale>") until one halving of the loading rate changes the measured
/// value by less than `tolerance`, or `max_runs` runs have been made. `on_point` is called
/// after each run. Throws as measure does.
RateStudy converge_loading_rate(Test test, const std::filesystem::path& scenario,
                                const SimulationOptions& options,
                                const std::vector<std::string>& overrides, double tolerance,
                                int max_runs, const std::function<void(const RatePoint&)>& on_point = {});

/// measure.toml's text and the elastic test's table and plot (written by measure into the
/// result folder): the value, the formula, the inputs.
std::string measurement_toml(const Measurement& m);

}  // namespace cleave::sim
