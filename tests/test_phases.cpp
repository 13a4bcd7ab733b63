// Several phases ([[phase]], [[boundary]]): grains assigned by volume fraction, the
// boundary mixing rule against springs in series, each bond's factors and each grain's
// mass and expansion from its phases, the scenario's errors at their line and key, and a
// two-phase periodic cell's Young's modulus against the Hashin-Shtrikman bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "geometry/phases.hpp"
#include "geometry/rng.hpp"
#include "geometry/specimen.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"
#include "physics/dem/world.hpp"
#include "scenario_error_test.hpp"
#include "sim/dynamics.hpp"
#include "sim/phases.hpp"
#include "sim/world_assembly.hpp"

using namespace cleave;
using namespace cleave::io;
namespace fs = std::filesystem;

namespace {

/// Volume given to each phase.
std::vector<double> phase_volumes(const std::vector<double>& volumes, const std::vector<int>& phase,
                                  std::size_t phases) {
  std::vector<double> out(phases, 0.0);
  for (std::size_t g = 0; g < volumes.size(); ++g)
    out.at(static_cast<std::size_t>(phase[g])) += volumes[g];
  return out;
}

/// Grain volumes spread over two decades (log-uniform), as a polycrystal's may be.
std::vector<double> scattered_volumes(std::size_t n, std::uint64_t seed) {
  geometry::SplitMix64 rng(seed);
  std::vector<double> v;
  for (std::size_t i = 0; i < n; ++i) v.push_back(std::pow(10.0, 2.0 * rng.uniform()) * 1e-12);
  return v;
}

}  // namespace

TEST(PhaseAssignment, EachOfTwoPhasesReachesItsFractionWithinOneGrainsVolume) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const std::vector<double> volumes = scattered_volumes(300, seed);
    double total = 0.0, largest = 0.0;
    for (const double v : volumes) total += v, largest = std::max(largest, v);
    for (const double f : {0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0}) {
      const std::vector<double> fractions{1.0 - f, f};
      const std::vector<int> phase = geometry::assign_phases(volumes, fractions, seed);
      const std::vector<double> got = phase_volumes(volumes, phase, 2);
      for (std::size_t p = 0; p < 2; ++p) {
        EXPECT_LE(std::abs(got[p] - fractions[p] * total), largest * (1 + 1e-12))
            << "seed " << seed << " f " << f << " phase " << p;
      }
      // A phase of fraction 0 gets no grain.
      if (f == 0.0) EXPECT_EQ(got[1], 0.0);
      if (f == 1.0) EXPECT_EQ(got[0], 0.0);
    }
  }
}

TEST(PhaseAssignment, OfThreePhasesNoneGoesAboveItsTargetByMoreThanOneGrain) {
  const std::vector<double> volumes = scattered_volumes(500, 7);
  double total = 0.0, largest = 0.0;
  for (const double v : volumes) total += v, largest = std::max(largest, v);
  const std::vector<double> fractions{0.2, 0.3, 0.5};
  const std::vector<double> got =
      phase_volumes(volumes, geometry::assign_phases(volumes, fractions, 7), 3);
  for (std::size_t p = 0; p < 3; ++p) {
    // Above by at most one grain; below by at most the others' excess (n - 1 grains).
    EXPECT_LE(got[p] - fractions[p] * total, largest * (1 + 1e-12)) << p;
    EXPECT_LE(fractions[p] * total - got[p], 2.0 * largest * (1 + 1e-12)) << p;
  }
}

TEST(PhaseAssignment, AVoronoiSpecimensGrainsReachTheirFractionsByExactVolume) {
  geometry::SpecimenDef def;
  def.kind = geometry::SpecimenKind::voronoi;
  def.voronoi.size = Eigen::Vector3d(1e-3, 1e-3, 1e-3);
  def.voronoi.cells = 60;
  def.outline = geometry::Outline::box(1e-3, 1e-3, 1e-3);
  def.phase_fractions = {0.7, 0.3};
  const geometry::Specimen s = geometry::build_specimen(def);
  std::vector<double> volumes;
  std::vector<int> phase;
  double largest = 0.0;
  for (const geometry::Grain& g : s.grains) {
    volumes.push_back(s.shape_of(g).volume_approx());
    phase.push_back(g.phase);
    largest = std::max(largest, volumes.back());
  }
  const std::vector<double> got = phase_volumes(volumes, phase, 2);
  EXPECT_LE(std::abs(got[0] - 0.7e-9), largest);
  EXPECT_LE(std::abs(got[1] - 0.3e-9), largest);
  EXPECT_GT(got[1], 0.0);
}

TEST(BoundaryMixing, StiffnessOfTheTwoHalvesInSeriesStrengthOfTheWeaker) {
  PhaseDef glass, alumina;
  glass.stiffness = 0.2118;
  glass.strength = 50.0 / 380.0;
  alumina.stiffness = 1.0;
  alumina.strength = 1.0;
  const sim::BondFactors mixed = sim::mixed_boundary(glass, alumina);
  // A bond of two halves, each half as long as a whole bond of its phase (twice as stiff).
  const double series = 1.0 / (1.0 / (2.0 * glass.stiffness) + 1.0 / (2.0 * alumina.stiffness));
  EXPECT_NEAR(mixed.stiffness, series, 1e-15 * series);
  EXPECT_EQ(mixed.strength, glass.strength);
  // The same from either side; a [[boundary]] table wins over the mix.
  Scenario s;
  s.phases = {glass, alumina};
  EXPECT_EQ(sim::bond_factors(s, 1, 0).stiffness, mixed.stiffness);
  EXPECT_EQ(sim::bond_factors(s, 0, 0).stiffness, glass.stiffness);
  EXPECT_EQ(sim::bond_factors(s, 1, 1).strength, alumina.strength);
  BoundaryDef b;
  b.phases = {0, 1};
  b.stiffness = 0.5;
  b.strength = 0.25;
  s.boundaries = {b};
  EXPECT_EQ(sim::bond_factors(s, 1, 0).stiffness, 0.5);
  EXPECT_EQ(sim::bond_factors(s, 0, 1).strength, 0.25);
}

namespace {

/// A periodic cell of `grains` Voronoi grains, glass and alumina as in
/// scenarios/glass_alumina.toml (alumina fraction `f`), `steps` of uniaxial strain.
std::string two_phase_cell(double f, int grains, double size_mm, int steps,
                           const std::string& extra = "") {
  std::ostringstream o;
  o << R"([scenario]
name = "two_phase_cell"
length_unit = "mm"
[specimen]
shape = "voronoi"
size = [)"
    << size_mm << ", " << size_mm << ", " << size_mm << R"(]
grains = )"
    << grains << R"(
seed = 5
[material]
density = 3984.0
[[phase]]
name = "glass"
fraction = )"
    << 1.0 - f << R"(
density = 2500.0
alpha = 11.6e-6
stiffness = 0.2118
strength = 0.1316
[[phase]]
name = "alumina"
fraction = )"
    << f << R"(
preset = "alumina"
alpha = 7.6e-6
)" << extra
    << R"(
[contact]
dilation_radius = 0.002
[contact.particle_particle]
kn = 1e7
ks = 4e6
c_res = 2.0
mu_s = 0.3
[contact.particle_wall]
kn = 1e7
[bond]
kbn = 4.56e17
kbs = 1.90e17
criterion = "rankine"
sigma_f = 3.8e8
[thermal]
temperature = 1273.0
[periodic]
axes = ["x", "y", "z"]
[dynamics]
dt = 1.1e-10
gravity = [0.0, 0.0, 0.0]
local_damping = 0.7
frames = 0
[[stage]]
name = "bond"
kind = "bond"
distance = 0.001
[[stage]]
name = "E"
steps = )"
    << steps << R"(
cell_strain_rate = [303.0, 0.0, 0.0]
measure_modulus = true
hold_cracks = true
)";
  return o.str();
}

/// The 1-based line of the first line of `text` that starts with `start`, after line `after`.
int line_of(const std::string& text, const std::string& start, int after = 0) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (n > after && line.rfind(start, 0) == 0) return n;
  }
  return -1;
}

}  // namespace

TEST(PhaseScenario, ReadsEachPhaseAndWritesItBackAsRun) {
  const std::string text = two_phase_cell(0.25, 40, 0.3, 10, R"(
[[boundary]]
phases = ["alumina", "glass"]
stiffness = 0.3
strength = 0.1
)");
  const Scenario s = parse_scenario(text, "mem.toml");
  ASSERT_EQ(s.phases.size(), 2u);
  EXPECT_EQ(s.phases[0].name, "glass");
  EXPECT_EQ(s.phases[0].density, 2500.0);
  EXPECT_EQ(s.phases[1].density, 3984.0);  // materials/alumina.toml's 3.984 g/cm^3
  EXPECT_EQ(s.phases[0].alpha, 11.6e-6);
  EXPECT_EQ(s.phases[1].stiffness, 1.0);  // defaults
  EXPECT_EQ(s.specimen.phase_fractions, (std::vector<double>{0.75, 0.25}));
  ASSERT_EQ(s.boundaries.size(), 1u);
  EXPECT_EQ(s.boundaries[0].phases, (std::array<int, 2>{0, 1}));
  EXPECT_EQ(s.boundaries[0].stiffness, 0.3);
  const Scenario back = parse_scenario(scenario_to_toml(s), "as_run.toml");
  EXPECT_TRUE(scenario_differences(s, back).empty());
}

TEST(PhaseScenario, ErrorsNameTheLineAndKey) {
  const std::string good = two_phase_cell(0.25, 40, 0.3, 10);
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  // Fractions that do not sum to 1: at the last phase's fraction.
  const std::string sum = replaced("fraction = 0.25", "fraction = 0.2");
  EXPECT_SCENARIO_ERROR(sum, line_of(sum, "fraction = 0.2"), "phase[2].fraction", "sum to 0.95");
  const std::string above = replaced("fraction = 0.75", "fraction = 1.5");
  EXPECT_SCENARIO_ERROR(above, line_of(above, "fraction = 1.5"), "phase[1].fraction", "");
  const std::string twice = replaced("name = \"alumina\"", "name = \"glass\"");
  EXPECT_SCENARIO_ERROR(twice,
                        line_of(twice, "name = \"glass\"", line_of(twice, "fraction = 0.75")),
                        "phase[2].name", "phase[1] is named 'glass' too");
  const std::string unknown_key = replaced("alpha = 7.6e-6", "young = 340e9");
  EXPECT_SCENARIO_ERROR(unknown_key, line_of(unknown_key, "young"), "phase[2].young",
                        "accepted keys");
  const std::string preset = replaced("preset = \"alumina\"", "preset = \"corundum\"");
  EXPECT_SCENARIO_ERROR(preset, line_of(preset, "preset"), "phase[2].preset",
                        "no material 'corundum'");
  const std::string cold = replaced("[thermal]\ntemperature = 1273.0\n", "");
  EXPECT_SCENARIO_ERROR(cold, line_of(cold, "alpha = 11.6e-6"), "phase[1].alpha",
                        "needs a [thermal] table");
  // [[boundary]]: phases it names must exist, differ, and be joined once.
  const std::string b1 =
      good + "[[boundary]]\nphases = [\"glass\", \"zirconia\"]\nstiffness = 1.0\nstrength = 1.0\n";
  EXPECT_SCENARIO_ERROR(b1, line_of(b1, "phases = [\"glass\", \"zirconia\"]"), "boundary[1].phases",
                        "no [[phase]] is named 'zirconia'");
  const std::string b2 =
      good + "[[boundary]]\nphases = [\"glass\", \"glass\"]\nstiffness = 1.0\nstrength = 1.0\n";
  EXPECT_SCENARIO_ERROR(b2, line_of(b2, "phases = [\"glass\", \"glass\"]"), "boundary[1].phases",
                        "names one phase twice");
  const std::string b3 =
      good +
      "[[boundary]]\nphases = [\"glass\", \"alumina\"]\nstiffness = 1.0\nstrength = 1.0\n"
      "[[boundary]]\nphases = [\"alumina\", \"glass\"]\nstiffness = 1.0\nstrength = 1.0\n";
  EXPECT_SCENARIO_ERROR(b3, line_of(b3, "phases = [\"alumina\", \"glass\"]"), "boundary[2].phases",
                        "boundary[1] joins the same two phases");
  const std::string b4 = good + "[[boundary]]\nphases = [\"glass\", \"alumina\"]\nstrength = 1.0\n";
  EXPECT_SCENARIO_ERROR(b4, line_of(b4, "[[boundary]]"), "boundary[1].stiffness",
                        "missing required key");
  // A [[boundary]] without phases.
  std::string lone = good;
  while (lone.find("[[phase]]") != std::string::npos) {
    const auto at = lone.find("[[phase]]");
    lone.erase(at, lone.find("\n[contact]") - at);
  }
  lone += "[[boundary]]\nphases = [\"glass\", \"alumina\"]\nstiffness = 1.0\nstrength = 1.0\n";
  EXPECT_SCENARIO_ERROR(lone, line_of(lone, "[[boundary]]"), "boundary", "need [[phase]] tables");
}

TEST(PhaseWorld, EachGrainAndBondTakesItsPhases) {
  // Bonded: every bond's factors are its grains' phase pair's (the mix across phases), every
  // body's mass its phase's density times its volume, its expansion its phase's alpha.
  const Scenario s = parse_scenario(two_phase_cell(0.4, 140, 0.4, 10), "mem.toml");
  const geometry::Specimen specimen = geometry::build_specimen(s.specimen);
  const fs::path dir = fs::temp_directory_path() / "cleave_test_phase_world";
  fs::remove_all(dir);
  sim::Dynamics dynamics(s, specimen, dir, true);
  dynamics.advance_stage();  // the bond stage
  const physics::World& w = dynamics.world();
  ASSERT_GT(w.bonds().size(), 40u);
  const double glass = 0.2118, alumina = 1.0, mixed = 2.0 / (1.0 / glass + 1.0 / alumina);
  std::map<int, int> kinds;
  for (const physics::Bond& bd : w.bonds()) {
    const int pa =
        specimen.grains.at(static_cast<std::size_t>(w.slot_infos()[bd.a].grain_id)).phase;
    const int pb =
        specimen.grains.at(static_cast<std::size_t>(w.slot_infos()[bd.b].grain_id)).phase;
    ++kinds[pa + pb];
    const double stiffness = pa + pb == 0 ? glass : pa + pb == 2 ? alumina : mixed;
    const double strength = pa + pb == 2 ? 1.0 : 0.1316;
    EXPECT_NEAR(bd.stiffness, stiffness, 1e-15);
    EXPECT_EQ(bd.strength, strength);
  }
  EXPECT_EQ(kinds.size(), 3u);  // glass-glass, glass-alumina and alumina-alumina bonds
  for (const physics::BodyId id : w.body_ids()) {
    const geometry::Grain& g = specimen.grains.at(static_cast<std::size_t>(w.info(id).grain_id));
    const double rho = g.phase == 0 ? 2500.0 : 3984.0;
    EXPECT_NEAR(w.info(id).mass, rho * specimen.shape_of(g).volume_approx(),
                1e-9 * w.info(id).mass);
    const Eigen::Matrix3d alpha = w.expansion(id);
    const double a = g.phase == 0 ? 11.6e-6 : 7.6e-6;
    EXPECT_NEAR((alpha - a * Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-18);
  }
  fs::remove_all(dir);
}

namespace {

/// E and nu of a periodic cell of alumina fraction `f` (modulus.csv of its uniaxial strain
/// stage), the cell of scenarios/glass_alumina.toml at 140 grains. The contacts are made
/// soft against the bonds (k_n 1e5 N/m beside K_bn near 1e7), so the cell's stiffness is the
/// bonds' alone and scales with their stiffness factor.
std::pair<double, double> cell_modulus(double f, const fs::path& dir) {
  std::string text = two_phase_cell(f, 140, 0.4, 500);
  text.replace(text.find("kn = 1e7\nks = 4e6"), 17, "kn = 1e5\nks = 4e4");
  text.replace(text.find("kn = 1e7"), 8, "kn = 1e5");  // and the walls' (there are none)
  // The soft contacts let the step grow (stable up to 6.3e-10 s): 500 steps, 7 periods of
  // the lightest grain on its bonds.
  text.replace(text.find("dt = 1.1e-10"), 12, "dt = 6.0e-10");
  const Scenario s = parse_scenario(text, "mem.toml");
  const geometry::Specimen specimen = geometry::build_specimen(s.specimen);
  fs::remove_all(dir);
  (void)sim::run_dynamics(s, specimen, dir, true);
  std::ifstream in(dir / "modulus.csv");
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  std::vector<std::string> cells;
  std::stringstream ss(row);
  for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
  fs::remove_all(dir);
  return {std::stod(cells.at(5)), std::stod(cells.at(6))};
}

/// The Hashin-Shtrikman bounds on the Young's modulus of an isotropic two-phase mixture
/// (Hashin & Shtrikman 1963), phase 2 of volume fraction f2 the stiffer in K and G.
std::pair<double, double> hashin_shtrikman(double e1, double nu1, double e2, double nu2,
                                           double f2) {
  const double k1 = e1 / (3 * (1 - 2 * nu1)), g1 = e1 / (2 * (1 + nu1));
  const double k2 = e2 / (3 * (1 - 2 * nu2)), g2 = e2 / (2 * (1 + nu2));
  const double f1 = 1 - f2;
  const double kl = k1 + f2 / (1 / (k2 - k1) + 3 * f1 / (3 * k1 + 4 * g1));
  const double ku = k2 + f1 / (1 / (k1 - k2) + 3 * f2 / (3 * k2 + 4 * g2));
  const double gl =
      g1 + f2 / (1 / (g2 - g1) + 6 * f1 * (k1 + 2 * g1) / (5 * g1 * (3 * k1 + 4 * g1)));
  const double gu =
      g2 + f1 / (1 / (g1 - g2) + 6 * f2 * (k2 + 2 * g2) / (5 * g2 * (3 * k2 + 4 * g2)));
  auto young = [](double k, double g) { return 9 * k * g / (3 * k + g); };
  return {young(kl, gl), young(ku, gu)};
}

}  // namespace

TEST(TwoPhaseCell, YoungsModulusLiesBetweenTheHashinShtrikmanBounds) {
  // The alumina cell measured; the glass cell's E is its stiffness factor times that (its
  // bonds are the alumina's scaled, and they alone carry the cell), its nu the same.
  const fs::path dir = fs::temp_directory_path() / "cleave_test_two_phase_cell";
  const auto [e2, nu2] = cell_modulus(1.0, dir);
  const double e1 = 0.2118 * e2, nu1 = nu2;
  const auto [e, nu] = cell_modulus(0.5, dir);
  const auto [lower, upper] = hashin_shtrikman(e1, nu1, e2, nu2, 0.5);
  std::printf(
      "two-phase cell: E %.4g GPa (nu %.3f), HS %.4g .. %.4g GPa; alumina cell %.4g GPa (nu "
      "%.3f)\n",
      e * 1e-9, nu, lower * 1e-9, upper * 1e-9, e2 * 1e-9, nu2);
  EXPECT_GT(e, lower) << "E " << e << " HS " << lower << " .. " << upper << " (glass " << e1
                      << ", alumina " << e2 << ")";
  EXPECT_LT(e, upper) << "E " << e << " HS " << lower << " .. " << upper;
  // The bounds' own sanity: inside Voigt and Reuss.
  EXPECT_GT(lower, 1.0 / (0.5 / e1 + 0.5 / e2));
  EXPECT_LT(upper, 0.5 * (e1 + e2));
}
