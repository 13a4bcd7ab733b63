// Scenario keys of polycrystals that are not the honeycomb lattice: log-normal Laguerre
// cells (shape "voronoi", sizes = "lognormal"), a Neper .tess (shape "tess") and a grain file
// (shape "grain_file"): values read back, exact volumes, and errors naming file, line, key.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "folder_test.hpp"
#include "geometry/specimen.hpp"
#include "geometry/voronoi.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"
#include "scenario_error_test.hpp"

using namespace cleave;
using namespace cleave::io;

namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

const std::string kTail = R"(
[material]
density = 3000
[contact]
dilation_radius = 0.01
[contact.particle_particle]
kn = 5.0
ks = 2.0
[contact.particle_wall]
kn = 5.0
)";

/// A scratch folder for each test (tests/folder_test.hpp).
class ImportedFiles : public cleave::testing::FolderTest {};

std::string two_halves() {
  std::ifstream in(CLEAVE_SOURCE_DIR "/scenarios/tessellations/two_halves.tess");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST(ImportedSpecimen, LognormalVoronoiKeysBuildExactLaguerreCellsAndReadBack) {
  const std::string text = R"([scenario]
length_unit = "mm"
[specimen]
shape = "voronoi"
size = [1, 1, 0.5]
grains = 25
seed = 4
sizes = "lognormal"
size_spread = 0.3
)" + kTail;
  const Scenario s = parse_scenario(text, "ln.toml");
  EXPECT_EQ(s.specimen.kind, geometry::SpecimenKind::voronoi);
  EXPECT_TRUE(s.specimen.voronoi.lognormal);
  EXPECT_DOUBLE_EQ(s.specimen.voronoi.size_spread, 0.3);
  EXPECT_EQ(s.specimen.voronoi.cells, 25);
  const geometry::Specimen sp = geometry::build_specimen(s.specimen);
  ASSERT_EQ(sp.grains.size(), 25u);
  EXPECT_EQ(
      geometry::total_volume(sp.shapes),
      geometry::exact_box(Eigen::Vector3d::Zero(), Eigen::Vector3d(1e-3, 1e-3, 0.5e-3)).volume());
  EXPECT_TRUE(scenario_differences(s, parse_scenario(scenario_to_toml(s), "again.toml")).empty());
}

TEST(ImportedSpecimen, SizeMeanSetsTheGrainCountFromTheBoxVolume) {
  const std::string text = R"([specimen]
shape = "voronoi"
size = [1, 1, 1]
sizes = "lognormal"
size_mean = 0.2
size_spread = 0.35
)" + kTail;
  const Scenario s = parse_scenario(text, "mean.toml");
  // n = V / E[pi d^3 / 6], E[d^3] = exp(3 mu + 9 sigma^2 / 2), sigma^2 = ln(1 + cv^2),
  // mu = ln(mean) - sigma^2 / 2 (lengths in mm, the default unit: the ratio is unitless).
  const double s2 = std::log(1.0 + 0.35 * 0.35), mu = std::log(0.2) - 0.5 * s2;
  EXPECT_EQ(s.specimen.voronoi.cells,
            static_cast<int>(std::round(1.0 / (kPi / 6.0 * std::exp(3.0 * mu + 4.5 * s2)))));
}

TEST(ImportedSpecimen, LognormalKeyErrorsNameTheirKeyAndLine) {
  const std::string head = "[specimen]\nshape = \"voronoi\"\nsize = [1, 1, 1]\ngrains = 5\n";
  {
    const std::string t = head + "size_spread = 0.3\n" + kTail;
    EXPECT_SCENARIO_ERROR_IN("e.toml", t, 5, "specimen.size_spread",
                             "applies to sizes = \"lognormal\"");
  }
  {
    const std::string t = head + "sizes = \"lognormal\"\nsize_mean = 0.3\n" + kTail;
    EXPECT_SCENARIO_ERROR_IN("e.toml", t, 6, "specimen.size_mean", "not both");
  }
  {
    const std::string t = head + "sizes = \"gaussian\"\n" + kTail;
    EXPECT_SCENARIO_ERROR_IN("e.toml", t, 5, "specimen.sizes", "lognormal");
  }
  {
    const std::string t = head + "sizes = \"lognormal\"\nsize_spread = -0.1\n" + kTail;
    EXPECT_SCENARIO_ERROR_IN("e.toml", t, 6, "specimen.size_spread", "");
  }
  {
    const std::string t =
        "[specimen]\nshape = \"voronoi\"\nsize = [1, 1, 1]\nsizes = \"lognormal\"\n" + kTail;
    EXPECT_SCENARIO_ERROR_IN("e.toml", t, 1, "specimen.grains", "size_mean");
  }
}

TEST_F(ImportedFiles, TessShapeReadsTheFileRelativeToTheScenarioWithItsScale) {
  write("two.tess", two_halves());
  const std::string text =
      "[specimen]\nshape = \"tess\"\nfile = \"two.tess\"\nscale = 2.0\n" + kTail;
  write("s.toml", text);
  const Scenario s = load_scenario(dir_ / "s.toml");
  EXPECT_EQ(s.specimen.kind, geometry::SpecimenKind::meshes);
  ASSERT_TRUE(s.tessellation.has_value());
  EXPECT_EQ(s.tessellation->shape, "tess");
  EXPECT_DOUBLE_EQ(s.tessellation->scale, 2e-3);  // 2 mm per file unit
  ASSERT_EQ(s.specimen.custom_grains.size(), 2u);
  EXPECT_EQ(s.specimen.custom_grains[0].name, "two.tess#1");
  // Two halves of a 2 mm cube, exactly.
  std::vector<geometry::ExactPolyhedron> shapes;
  for (const auto& g : s.specimen.custom_grains) shapes.push_back(g.shape);
  EXPECT_EQ(geometry::total_volume(shapes),
            geometry::exact_box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(2e-3)).volume());
  EXPECT_EQ(shapes[0].volume(), shapes[1].volume());
  ASSERT_EQ(s.specimen.orientations.size(), 2u);
  // Cell 1 is passive Bunge (90, 0, 0): crystal -> specimen = [[0, -1, 0], [1, 0, 0], [0, 0, 1]].
  Eigen::Matrix3d r1;
  r1 << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_LT((s.specimen.orientations[0].toRotationMatrix() - r1).norm(), 1e-12);
  EXPECT_NEAR(s.specimen.outline.size.x(), 2e-3, 1e-15);
  const geometry::Specimen sp = geometry::build_specimen(s.specimen);
  EXPECT_EQ(sp.grains.size(), 2u);
  const Scenario again = parse_scenario(scenario_to_toml(s), (dir_ / "again.toml").string());
  EXPECT_TRUE(scenario_differences(s, again).empty());
}

TEST_F(ImportedFiles, TessFileErrorsNameTheScenarioKeyAndTheFilesLine) {
  const std::string bad = [] {
    std::string t = two_halves();
    return t.replace(t.find("   3.4"), 6, "   9.9");
  }();
  write("bad.tess", bad);
  const std::string text = "[specimen]\nshape = \"tess\"\nfile = \"bad.tess\"\n" + kTail;
  const std::string source = (dir_ / "s.toml").string();
  EXPECT_SCENARIO_ERROR_IN(source, text, 3, "specimen.file", "bad.tess:3: format version 9.9");
  EXPECT_SCENARIO_ERROR_IN(source, "[specimen]\nshape = \"tess\"\nfile = \"none.tess\"\n" + kTail,
                           3, "specimen.file", "cannot open");
  EXPECT_SCENARIO_ERROR_IN(
      source, "[specimen]\nshape = \"tess\"\nfile = \"bad.tess\"\ngrains = 3\n" + kTail, 4,
      "specimen.grains", "does not apply to shape 'tess'");
  EXPECT_SCENARIO_ERROR_IN(source, "[specimen]\nshape = \"tess\"\n" + kTail, 1, "specimen.file",
                           "missing required key");
}

TEST_F(ImportedFiles, GrainFileShapeTilesTheBoxWithTheGivenVolumes) {
  write("grains.txt",
            "# x y z volume phi1 Phi phi2 (mm, mm^3, degrees)\n"
            "0.5 0.5 0.5 0.8 0 0 0\n"
            "1.5 0.5 0.5 1.2 90 0 0\n");
  const std::string text =
      "[specimen]\nshape = \"grain_file\"\nfile = \"grains.txt\"\nsize = [2, 1, 1]\n" + kTail;
  write("s.toml", text);
  const Scenario s = load_scenario(dir_ / "s.toml");
  ASSERT_EQ(s.specimen.custom_grains.size(), 2u);
  std::vector<geometry::ExactPolyhedron> shapes;
  for (const auto& g : s.specimen.custom_grains) shapes.push_back(g.shape);
  EXPECT_EQ(
      geometry::total_volume(shapes),
      geometry::exact_box(Eigen::Vector3d::Zero(), Eigen::Vector3d(2e-3, 1e-3, 1e-3)).volume());
  EXPECT_NEAR(shapes[0].volume().to_double(), 0.8e-9, 1e-3 * 0.8e-9);
  EXPECT_NEAR(shapes[1].volume().to_double(), 1.2e-9, 1e-3 * 1.2e-9);
  ASSERT_EQ(s.specimen.orientations.size(), 2u);
  const Scenario again = parse_scenario(scenario_to_toml(s), (dir_ / "again.toml").string());
  EXPECT_TRUE(scenario_differences(s, again).empty());
  write("short.txt", "0.5 0.5 0.5 0.8 0 0\n");
  EXPECT_SCENARIO_ERROR_IN(
      (dir_ / "t.toml").string(),
      "[specimen]\nshape = \"grain_file\"\nfile = \"short.txt\"\nsize = [2, 1, 1]\n" + kTail, 3,
      "specimen.file", "short.txt:1: expected 7 values");
}

TEST(ImportedSpecimen, PeriodicLognormalSpecimenTilesItsCellExactly) {
  const std::string text = R"([specimen]
shape = "voronoi"
size = [1, 1, 1]
grains = 20
sizes = "lognormal"
[periodic]
axes = ["x", "y"]
)" + kTail + R"(
[dynamics]
dt = 1e-6
duration = 1e-5
gravity = [0, 0, 0]
)";
  const Scenario s = parse_scenario(text, "p.toml");
  EXPECT_EQ(s.specimen.voronoi.periodic, (std::array<bool, 3>{true, true, false}));
  const geometry::Specimen sp = geometry::build_specimen(s.specimen);
  ASSERT_EQ(sp.grains.size(), 20u);
  EXPECT_EQ(geometry::total_volume(sp.shapes),
            geometry::exact_box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1e-3)).volume());
}
