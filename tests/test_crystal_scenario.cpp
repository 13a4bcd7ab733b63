// [crystal], [[cleavage]] and the 3D orientation laws as a scenario writes them: what they
// set, every error naming its file, line and key, and the scenario as run read back equal.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "geometry/orientation.hpp"
#include "geometry/specimen.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"
#include "scenario_error_test.hpp"

using namespace cleave;
using namespace cleave::io;

namespace {

const std::string kVoronoi = R"([specimen]
shape = "voronoi"
size = [2, 2, 2]
grains = 6
)";

const std::string kMoving = R"(
[contact]
dilation_radius = 0.02
[contact.particle_particle]
kn = 1e5
[contact.particle_wall]
kn = 1e5
[dynamics]
dt = 1e-8
duration = 1e-6
)";

}  // namespace

TEST(CrystalScenario, CorundumWithFamilyToughnessesAndUniformOrientations) {
  const Scenario s = parse_scenario(kVoronoi + R"([crystal]
system = "trigonal"
c_over_a = 2.730
[[cleavage]]
planes = "{11-20}"
k_ic = "2.4 MPa m^0.5"
[[cleavage]]
planes = "{0001}"
k_ic = 4.5e6
planes_per_variant = 2
[fracture]
k_ic = 2.4e6
sigma_f_hyd = 0
crack_length = 0.1
)" + kMoving, "mem.toml");
  const auto& c = s.specimen.crystal;
  ASSERT_TRUE(c.enabled);
  EXPECT_EQ(c.lattice.system, geometry::CrystalSystem::trigonal);
  EXPECT_EQ(c.lattice.c_over_a, 2.730);
  ASSERT_EQ(c.families.size(), 2u);
  EXPECT_EQ(c.families[0].family.text, "{11-20}");
  EXPECT_NEAR(c.families[0].resistance, 1.0, 1e-15);
  EXPECT_NEAR(c.families[1].resistance, 4.5 / 2.4, 1e-15);
  EXPECT_EQ(c.families[1].planes_per_variant, 2);
  // With a crystal the orientations are uniform unless a law is named.
  EXPECT_EQ(s.specimen.orientation.law, geometry::OrientationLaw::uniform);
}

TEST(CrystalScenario, TexturesReadTheirAnglesInDegrees) {
  const Scenario p = parse_scenario(kVoronoi + R"([crystal]
system = "cubic"
[orientation]
law = "preferred"
euler = [10, 20, 30]
spread = 5
)", "mem.toml");
  EXPECT_EQ(p.specimen.orientation.law, geometry::OrientationLaw::preferred);
  EXPECT_EQ(p.specimen.orientation.euler_deg, (std::array<double, 3>{10, 20, 30}));
  EXPECT_EQ(p.specimen.orientation.spread_deg, 5.0);
  const Scenario f = parse_scenario(kVoronoi + R"([crystal]
system = "hexagonal"
c_over_a = 1.6
[orientation]
law = "fibre"
crystal_direction = [0, 0, 1]
specimen_axis = [1, 0, 0]
)", "mem.toml");
  EXPECT_EQ(f.specimen.orientation.law, geometry::OrientationLaw::fibre);
  EXPECT_EQ(f.specimen.orientation.specimen_axis, Eigen::Vector3d::UnitX());
}

TEST(CrystalScenario, AnOrientationFileGivesEachGrainItsBungeAngles) {
  const auto dir = std::filesystem::temp_directory_path() / ("cleave_crystal_scenario_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    std::ofstream o(dir / "grains.ori");
    o << "# phi1 Phi phi2\n";
    for (int g = 0; g < 6; ++g) o << 10 * g << " " << 20 + g << " " << 5 * g << "\n";
  }
  const std::string text = kVoronoi + "[crystal]\nsystem = \"cubic\"\n[orientation]\nlaw = \"file\"\nfile = \"grains.ori\"\n";
  {
    std::ofstream o(dir / "s.toml");
    o << text;
  }
  const Scenario s = load_scenario(dir / "s.toml");
  ASSERT_EQ(s.specimen.orientation.given.size(), 6u);
  constexpr double deg = M_PI / 180.0;
  EXPECT_TRUE(s.specimen.orientation.given[3].isApprox(geometry::from_bunge(30 * deg, 23 * deg, 15 * deg), 1e-15));
  const Scenario back = parse_scenario(scenario_to_toml(s), "as_run.toml");
  EXPECT_TRUE(scenario_differences(s, back).empty());
  std::filesystem::remove_all(dir);
}

TEST(CrystalScenario, BadCrystalInputNamesItsLineAndKey) {
  EXPECT_SCENARIO_ERROR(kVoronoi + "[[cleavage]]\nplanes = \"{100}\"\n", 5, "cleavage",
                        "need a [crystal] table");
  EXPECT_SCENARIO_ERROR(kVoronoi + "[crystal]\nsystem = \"monoclinic\"\n", 6, "crystal.system",
                        "cubic, hexagonal");
  EXPECT_SCENARIO_ERROR(kVoronoi + "[crystal]\nsystem = \"cubic\"\nc_over_a = 1.2\n", 7,
                        "crystal.c_over_a", "c = a");
  EXPECT_SCENARIO_ERROR(kVoronoi + "[crystal]\nsystem = \"hexagonal\"\n", 5, "crystal.c_over_a",
                        "missing required key");
  EXPECT_SCENARIO_ERROR(
      kVoronoi +
          "[crystal]\nsystem = \"trigonal\"\nc_over_a = 2.73\n[[cleavage]]\nplanes = \"{1-10}\"\n",
      9, "cleavage[1].planes", "Miller-Bravais");
  EXPECT_SCENARIO_ERROR(kVoronoi +
                            "[crystal]\nsystem = \"cubic\"\n[[cleavage]]\nplanes = "
                            "\"{100}\"\n[[cleavage]]\nplanes = \"{100}\"\n",
                        10, "cleavage[2].planes", "same family");
  EXPECT_SCENARIO_ERROR(
      kVoronoi + "[crystal]\nsystem = \"cubic\"\n[[cleavage]]\nplanes = \"{100}\"\nk_ic = 1e6\n", 7,
      "cleavage[1]", "needs a [fracture] table");
  EXPECT_SCENARIO_ERROR(kVoronoi + "[orientation]\nlaw = \"uniform\"\n", 6, "orientation.law",
                        "need a [crystal] table");
  EXPECT_SCENARIO_ERROR(
      kVoronoi + "[crystal]\nsystem = \"cubic\"\n[orientation]\nlaw = \"uniform\"\nangles = [0]\n",
      9, "orientation.angles", "honeycomb");
  EXPECT_SCENARIO_ERROR(kVoronoi +
                            "[crystal]\nsystem = \"cubic\"\n[orientation]\nlaw = "
                            "\"preferred\"\neuler = [0, 190, 0]\n",
                        9, "orientation.euler", "[0, 180]");
  EXPECT_SCENARIO_ERROR(
      kVoronoi + kMoving + "[thermal]\nalpha_a = 1e-6\nalpha_b = 2e-6\nalpha_c = 3e-6\n", 17,
      "thermal.alpha_b", "c_axis = \"crystal\"");
  EXPECT_SCENARIO_ERROR(kVoronoi + kMoving + "[thermal]\nc_axis = \"crystal\"\n", 16,
                        "thermal.c_axis", "[crystal]");
}

TEST(CrystalScenario, TheScenarioAsRunReadsBackEqual) {
  const Scenario s = parse_scenario(kVoronoi + R"([crystal]
system = "orthorhombic"
b_over_a = 1.02
c_over_a = 0.37
[[cleavage]]
planes = "{010}"
sigma_f = 3e8
[orientation]
law = "preferred"
euler = [10.5, 20, 30]
spread = 7.25
seed = 9
[fracture]
criterion = "rankine"
sigma_f = 2e8
[thermal]
alpha_a = -1.904e-6
alpha_b = 9.576e-6
alpha_c = 16.64e-6
)" + kMoving, "mem.toml");
  EXPECT_EQ(s.thermal.c_axis, ThermalDef::Axis::crystal);
  EXPECT_NEAR(s.specimen.crystal.families[0].resistance, 1.5, 1e-15);
  const std::string text = scenario_to_toml(s);
  const Scenario back = parse_scenario(text, "as_run.toml");
  const auto diff = scenario_differences(s, back);
  EXPECT_TRUE(diff.empty()) << (diff.empty() ? "" : diff.front()) << "\n" << text;
  EXPECT_EQ(scenario_to_toml(back), text);
}

TEST(CrystalScenario, ATessellationsOwnOrientationsBecomeTheGrainsCrystals) {
  // The hand-written two_halves.tess gives Bunge (90, 0, 0) and (0, 90, 0), passive: with a
  // [crystal] and no law, each grain's crystal is its cell's orientation.
  const auto dir = std::filesystem::temp_directory_path() / ("cleave_crystal_tess_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string tess = std::string(CLEAVE_SOURCE_DIR) + "/scenarios/tessellations/two_halves.tess";
  {
    std::ofstream o(dir / "s.toml");
    o << "[specimen]\nshape = \"tess\"\nfile = \"" << tess << "\"\n[crystal]\nsystem = \"cubic\"\n";
  }
  const Scenario s = load_scenario(dir / "s.toml");
  EXPECT_EQ(s.specimen.orientation.law, geometry::OrientationLaw::imported);
  const geometry::Specimen sp = geometry::build_specimen(s.specimen);
  ASSERT_EQ(sp.grains.size(), 2u);
  // (90, 0, 0): the crystal x axis along specimen y; (0, 90, 0): the crystal z axis along -y.
  EXPECT_TRUE((sp.grains[0].crystal * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_TRUE((sp.grains[1].crystal * Eigen::Vector3d::UnitZ()).isApprox(-Eigen::Vector3d::UnitY(), 1e-12));
  const Scenario back = parse_scenario(scenario_to_toml(s), "as_run.toml");
  EXPECT_TRUE(scenario_differences(s, back).empty());
  EXPECT_SCENARIO_ERROR(
      "[specimen]\nshape = \"voronoi\"\nsize = [1, 1, 1]\ngrains = 2\n[crystal]\nsystem = "
      "\"cubic\"\n"
      "[orientation]\nlaw = \"imported\"\n",
      8, "orientation.law", "has none");
  std::filesystem::remove_all(dir);
}

TEST(CrystalScenario, TheAluminaPresetGivesCorundumAndItsFamiliesToughness) {
  // materials/alumina.toml: corundum c/a = 12.9920 / 4.7588, Iwasa and Bradt's toughness
  // 2.4 (a), 2.4 (r), 3.1 (m), 4.5 (c) MPa m^0.5, read against [fracture] k_ic = 2.4 MPa m^0.5.
  const Scenario s = parse_scenario(kVoronoi + R"([crystal]
preset = "alumina"
[fracture]
k_ic = "2.4 MPa m^0.5"
sigma_f_hyd = 0
crack_length = 0.005
)" + kMoving, "mem.toml");
  const auto& c = s.specimen.crystal;
  EXPECT_EQ(c.lattice.system, geometry::CrystalSystem::trigonal);
  EXPECT_NEAR(c.lattice.c_over_a, 12.9920 / 4.7588, 1e-4);
  ASSERT_EQ(c.families.size(), 4u);
  const std::pair<const char*, double> want[] = {{"{11-20}", 2.4}, {"{10-12}", 2.4}, {"{10-10}", 3.1}, {"{0001}", 4.5}};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(c.families[i].family.text, want[i].first);
    EXPECT_NEAR(c.families[i].resistance, want[i].second / 2.4, 1e-12) << want[i].first;
  }
  // The scenario's own keys win over the preset's.
  const Scenario own = parse_scenario(kVoronoi + "[crystal]\npreset = \"alumina\"\nc_over_a = 2.5\n", "mem.toml");
  EXPECT_EQ(own.specimen.crystal.lattice.c_over_a, 2.5);
  EXPECT_SCENARIO_ERROR(kVoronoi + "[crystal]\npreset = \"sic_alpha\"\n", 6, "crystal.preset",
                        "has no [crystal] table");
}
