// A scenario cannot silently start wrong: the checks make_world runs before step 1
// (sim::check_start), the time step it advises, and walls placed by `gap`. Each refusal is
// checked for its file, line and key, and for a figure computed here from the geometry.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cli_helpers.hpp"
#include "geometry/specimen.hpp"
#include "io/mesh_grains.hpp"
#include "io/scenario.hpp"
#include "sim/world_assembly.hpp"

namespace cleave::io {
namespace {

namespace fs = std::filesystem;
using sim::advised_time_step;
using sim::check_start;
using sim::check_time_step;
using sim::make_world;
using sim::stable_time_step;
using sim::start_warnings;

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string shipped(const std::string& name) {
  return read_text(fs::path(CLEAVE_SOURCE_DIR) / "scenarios" / name);
}

/// `text` with the first `from` replaced by `to` (which must be there).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "no '" << from << "' in the text";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// `text` without any line that starts with `prefix`.
std::string without_lines(const std::string& text, const std::string& prefix) {
  std::stringstream in(text);
  std::string out, line;
  while (std::getline(in, line)) {
    if (line.rfind(prefix, 0) != 0) out += line + "\n";
  }
  return out;
}

/// The 1-based line on which `part` first appears.
int line_of(const std::string& text, const std::string& part) {
  const std::size_t at = text.find(part);
  EXPECT_NE(at, std::string::npos) << part;
  return 1 + static_cast<int>(
                 std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

/// The number that follows `before` in `text` (NaN when absent).
double number_after(const std::string& text, const std::string& before) {
  const std::size_t at = text.find(before);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(text.c_str() + at + before.size(), nullptr);
}

/// The brazilian_fracture disc (shipped: platens placed by gap) with grains of lattice side
/// r and grain side r_bar (mm), and the dilation and bond distance given, at a time step
/// the check accepts for any of them.
std::string disc(double r, double r_bar, double dilation = 0.05, double distance = 0.08) {
  std::string t = shipped("brazilian_fracture.toml");
  t = replaced(t, "r = 0.6 ", "r = " + std::to_string(r) + " ");
  t = replaced(t, "r_bar = 0.5 ", "r_bar = " + std::to_string(r_bar) + " ");
  t = replaced(t, "dilation_radius = 0.05", "dilation_radius = " + std::to_string(dilation));
  t = replaced(t, "distance = 0.08 ", "distance = " + std::to_string(distance) + " ");
  return replaced(t, "dt = 1.5e-5 ", "dt = 1e-6 ");
}

/// The same disc with its platens at fixed points (no gap), the bottom one's plane at y.
std::string disc_at_points(double bottom_y) {
  std::string t = without_lines(shipped("brazilian_fracture.toml"), "gap = ");
  return replaced(t, "point = [7.5, 0.04, 2.5]",
                  "point = [7.5, " + std::to_string(bottom_y) + ", 2.5]");
}

/// The ScenarioError that making the world of `text` throws (or none: empty key).
struct Refusal {
  std::string key, what;
  int line = 0;
};
Refusal refusal(const std::string& text, const std::string& source = "mem.toml") {
  const Scenario s = parse_scenario(text, source);
  const geometry::Specimen specimen = geometry::build_specimen(s.specimen);
  try {
    (void)make_world(s, specimen);
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.file(), source);
    EXPECT_NE(std::string(e.what()).find(source + ":" + std::to_string(e.line()) + ":"),
              std::string::npos)
        << e.what();
    return {e.key(), e.what(), e.line()};
  }
  return {};
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// ---- the time step ----------------------------------------------------------------------

TEST(TimeStepAdvice, TheStepTheRefusalAdvisesIsAcceptedWhenSet) {
  // Discs of five grain sizes and the drop test, each with a time step far too large: the
  // step the message advises, written into the file, must pass the same check. (A limit of
  // 3.9995e-06 s was advised as "4e-06" and then refused.)
  std::vector<std::pair<std::string, std::string>> cases;  // text, its dt line
  for (const double r : {0.3, 0.45, 0.6, 0.9, 1.2}) {
    std::string t = shipped("brazilian_fracture.toml");
    t = replaced(t, "r = 0.6 ", "r = " + std::to_string(r) + " ");
    t = replaced(t, "r_bar = 0.5 ", "r_bar = " + std::to_string(r * 5.0 / 6.0) + " ");
    t = replaced(t, "dilation_radius = 0.05", "dilation_radius = " + std::to_string(r / 12.0));
    t = replaced(t, "distance = 0.08 ", "distance = " + std::to_string(r * 0.08 / 0.6) + " ");
    cases.emplace_back(replaced(t, "dt = 1.5e-5 ", "dt = 1.0 "), "dt = 1.0 ");
  }
  cases.emplace_back(replaced(shipped("drop_test.toml"), "dt = 1.2e-6 ", "dt = 1.0 "), "dt = 1.0 ");
  for (const auto& [text, dt_line] : cases) {
    const Scenario s = parse_scenario(text, "mem.toml");
    const geometry::Specimen specimen = geometry::build_specimen(s.specimen);
    std::string what;
    try {
      check_time_step(s, specimen);
    } catch (const ScenarioError& e) {
      EXPECT_EQ(e.key(), "dynamics.dt");
      what = e.what();
    }
    ASSERT_FALSE(what.empty()) << "dt = 1 s was accepted";
    const std::size_t at = what.find("use dt <= ");
    ASSERT_NE(at, std::string::npos) << what;
    const std::string advice = what.substr(at + 10, what.find(' ', at + 10) - at - 10);
    const Scenario fixed =
        parse_scenario(replaced(text, dt_line, "dt = " + advice + " "), "mem.toml");
    EXPECT_NO_THROW(check_time_step(fixed, specimen)) << "advised " << advice << ": " << what;
    // Three significant digits: the advice is within 1 % of the limit, not a needless cut.
    EXPECT_GT(fixed.dynamics.dt, 0.99 * stable_time_step(fixed, specimen)) << advice;
  }
}

TEST(TimeStepAdvice, IsTheLargestThreeDigitDecimalNotAboveTheLimit) {
  for (const double limit : {3.9995e-6, 4e-6, 9.9996e-6, 1.00004e-5, 1.2345e-7, 7.777e-3}) {
    const std::string advice = advised_time_step(limit);
    const double a = std::strtod(advice.c_str(), nullptr);
    EXPECT_LE(a, limit) << advice;
    // One more in the third digit would be above it.
    const double unit = std::pow(10.0, std::floor(std::log10(a)) - 2.0);
    EXPECT_GT(a + unit * (1.0 + 1e-9), limit) << advice;
  }
  EXPECT_EQ(advised_time_step(3.9995e-6), "3.99e-06");
  EXPECT_EQ(advised_time_step(4e-6), "4e-06");
}

// ---- grains at the start ----------------------------------------------------------------

/// An unbonded box of honeycomb prisms (side 1 mm) on a floor, grain side r_bar.
std::string loose_box(double r_bar) {
  std::string t = shipped("drop_test.toml");
  t = replaced(t, "size = [12.0, 12.0, 4.0]", "size = [6.0, 6.0, 2.0]");
  return replaced(t, "r_bar = 0.9", "r_bar = " + std::to_string(r_bar));
}

TEST(StartChecks, GrainsPlacedIntoEachOtherWithoutBondsAreRefusedNamingTheGrainKeys) {
  // Side faces sqrt(3) (r - r_bar) apart, dilated surfaces overlapping by 2 x 0.05 mm less
  // that: r_bar = r overlaps by 0.1 mm, twice the dilation radius; r_bar = 0.99 by 0.0827 mm.
  for (const double r_bar : {1.0, 0.99}) {
    const std::string text = loose_box(r_bar);
    const Refusal e = refusal(text);
    EXPECT_EQ(e.key, "contact.dilation_radius") << r_bar;
    EXPECT_EQ(e.line, line_of(text, "dilation_radius = 0.05"));
    EXPECT_TRUE(has(e.what, "r - r_bar") && has(e.what, "dilation_radius")) << e.what;
    EXPECT_NEAR(number_after(e.what, "overlap by "), 0.1 - std::sqrt(3.0) * (1.0 - r_bar), 1e-4)
        << e.what;
  }
  // A packing pressed a little (0.0134 mm, under the 0.05 mm dilation) may start so; grains
  // apart certainly.
  EXPECT_EQ(refusal(loose_box(1.0 - 0.0866 / std::sqrt(3.0))).key, "");
  EXPECT_EQ(refusal(loose_box(0.9)).key, "");
}

TEST(StartChecks, MeshGrainsWhoseShapesIntersectAreRefused) {
  // The brick moved onto the first octahedron: no contact can resolve shapes that intersect.
  const std::string meshes = (fs::path(CLEAVE_SOURCE_DIR) / "scenarios/meshes").string();
  std::string text = shipped("mesh_grains.toml");
  text = replaced(text, "\"meshes/octahedron.obj\"", "\"" + meshes + "/octahedron.obj\"");
  text = replaced(text, "\"meshes/brick.obj\"", "\"" + meshes + "/brick.obj\"");
  text = replaced(text, "\"meshes/octahedron.obj\"", "\"" + meshes + "/octahedron.obj\"");
  EXPECT_EQ(refusal(text).key, "");
  // Refused when the scenario is read, at the brick's position (below, the closed form).
  try {
    (void)parse_scenario(replaced(text, "position = [1.2, 0.1, 1.3]", "position = [0.3, 0.0, 1.0]"),
                         "mem.toml");
    ADD_FAILURE() << "the brick inside the octahedron was accepted";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.key(), "mesh_grain[2].position");
    EXPECT_TRUE(has(e.what(), "intersect") && has(e.what(), "mesh_grain[1]")) << e.what();
  }
}

TEST(StartChecks, ABondDistanceShorterThanTheGapBetweenNeighboursIsRefusedWithTheGapNeeded) {
  // r = 1.2, r_bar = 1.0: neighbours' dilated side faces sqrt(3) x 0.2 - 2 x 0.05 = 0.2464 mm
  // apart, beyond the 0.08 mm bonding distance: no bond would form.
  const std::string text = disc(1.2, 1.0);
  const Refusal e = refusal(text);
  EXPECT_EQ(e.key, "stage[1].distance");
  EXPECT_EQ(e.line, line_of(text, "distance = 0.080000"));
  EXPECT_TRUE(has(e.what, "dilation_radius") && has(e.what, "r - r_bar")) << e.what;
  EXPECT_NEAR(number_after(e.what, "dilated surface is "), std::sqrt(3.0) * 0.2 - 0.1, 1e-4)
      << e.what;
  EXPECT_EQ(refusal(disc(1.2, 1.0, 0.05, 0.25)).key, "");
}

TEST(StartChecks, BondedGrainsThatStartOverlappingAreWarnedToScaleTheDilationAndDistance) {
  // r = 0.3, r_bar = 0.25 with the r = 0.6 disc's dilation: dilated side faces overlap by
  // 0.1 - 0.0866 mm. The bond stage stores it (no refusal), but the warning names the keys;
  // scaled with the grains (dilation 0.025, distance 0.04) the disc is the r = 0.6 one halved.
  for (const bool scaled : {false, true}) {
    const Scenario s =
        parse_scenario(scaled ? disc(0.3, 0.25, 0.025, 0.04) : disc(0.3, 0.25), "mem.toml");
    const geometry::Specimen specimen = geometry::build_specimen(s.specimen);
    EXPECT_NO_THROW((void)make_world(s, specimen));
    const std::vector<ScenarioError> warnings = start_warnings(s, specimen);
    ASSERT_EQ(warnings.size(), scaled ? 0u : 1u);
    if (scaled) continue;
    EXPECT_EQ(warnings[0].key(), "contact.dilation_radius");
    EXPECT_TRUE(has(warnings[0].what(), "distance")) << warnings[0].what();
  }
}

// ---- walls at the start -----------------------------------------------------------------

TEST(StartChecks, APlatenInsideTheDiscIsRefusedNamingItsPoint) {
  // The disc's lowest corners at y = 0.1 mm, dilated to 0.05 mm. A platen at 0.6 mm cuts
  // 0.5 mm into the grains themselves; one at 0.07 mm only 0.02 mm into their dilated skin,
  // but the approach stage waits for it to touch, and it already presses.
  for (const double y : {0.6, 0.07}) {
    const std::string text = disc_at_points(y);
    const Refusal e = refusal(text);
    EXPECT_EQ(e.key, "wall[1].point") << y;
    EXPECT_EQ(e.line, line_of(text, "point = [7.5, " + std::to_string(y)));
    EXPECT_TRUE(has(e.what, "'bottom'") && has(e.what, "gap")) << e.what;
    EXPECT_NEAR(number_after(e.what, "reaches "), y - 0.05, 1e-9) << e.what;
  }
  EXPECT_EQ(refusal(disc_at_points(0.04)).key, "");
}

TEST(StartChecks, AnApproachThatMovesAPlatenAwayIsRefusedAtItsVelocity) {
  const std::string text = replaced(shipped("brazilian_fracture.toml"), "bottom = [0.0, 1.0, 0.0]",
                                    "bottom = [0.0, -1.0, 0.0]");
  const Refusal e = refusal(text);
  EXPECT_EQ(e.key, "stage[2].wall_velocity.bottom");
  EXPECT_EQ(e.line, line_of(text, "bottom = [0.0, -1.0, 0.0]"));
  EXPECT_TRUE(has(e.what, "away from")) << e.what;
}

TEST(StartChecks, AnApproachTooShortToCloseTheGapIsRefusedWithTheTimeItNeeds) {
  // Platens 0.01 mm from the disc closing at 1 mm/s: 0.01 s. With a 0.03 s ramp the walls
  // cover v T^2 / (2 T_r) in T < T_r: 0.01 mm in sqrt(2 x 0.03 x 0.01) = 0.0245 s.
  const std::string base = shipped("brazilian_fracture.toml");
  const std::string approach = "until = \"walls_touch\"\ntime = 0.1\n";
  struct Case {
    std::string stage;
    double needed;
  };
  for (const Case& c : {Case{"until = \"walls_touch\"\ntime = 0.005\n", 0.01},
                        Case{"until = \"walls_touch\"\ntime = 0.02\nramp_time = 0.03\n",
                             std::sqrt(2 * 0.03 * 0.01)}}) {
    const std::string text = replaced(base, approach, c.stage);
    const Refusal e = refusal(text);
    EXPECT_EQ(e.key, "stage[2].time");
    EXPECT_EQ(e.line, line_of(text, c.stage) + 1);
    EXPECT_NEAR(number_after(e.what, "give it at least "), c.needed, 1e-3 * c.needed) << e.what;
  }
  EXPECT_EQ(refusal(replaced(base, approach, "until = \"walls_touch\"\ntime = 0.011\n")).key, "");
  EXPECT_EQ(
      refusal(replaced(base, approach, "until = \"walls_touch\"\ntime = 0.025\nramp_time = 0.03\n"))
          .key,
      "");
}

// ---- gap --------------------------------------------------------------------------------

TEST(WallGap, PlacesThePlatensTheGapFromTheDiscsOutermostDilatedCorners) {
  // brazilian_fracture's platens: gap = 0.01 mm from the disc's surface dilated by the
  // contact radius. A prism's corner 0 points along +y (App. A), so the disc reaches r_bar
  // beyond its lowest and highest lattice centres along y, and the dilation beyond that:
  // the platens' planes at y_min - r_bar - d - gap and y_max + r_bar + d + gap, whatever r.
  for (const auto& [r, r_bar, d] : {std::tuple{0.6, 0.5, 0.05}, std::tuple{0.3, 0.25, 0.025}}) {
    const Scenario s = parse_scenario(disc(r, r_bar, d, 2.0 * d), "mem.toml");
    const geometry::Specimen specimen = geometry::build_specimen(s.specimen);
    double lo = 1e9, hi = -1e9;
    for (const auto& g : specimen.grains) {
      lo = std::min(lo, g.site.centre.y());
      hi = std::max(hi, g.site.centre.y());
    }
    const physics::World world = make_world(s, specimen);
    const double mm = 1e-3;
    EXPECT_NEAR(world.walls()[0].origin.y(), lo - (r_bar + d + 0.01) * mm, 1e-15) << r;
    EXPECT_NEAR(world.walls()[1].origin.y(), hi + (r_bar + d + 0.01) * mm, 1e-15) << r;
    // The in-plane position is the point's.
    EXPECT_EQ(world.walls()[0].origin.x(), 7.5 * mm);
    EXPECT_EQ(world.walls()[0].origin.z(), 2.5 * mm);
  }
}

// ---- the command line -------------------------------------------------------------------

TEST(StartChecksCli, EachRefusalIsExitCode2WithTheFileLineAndKeyBeforeAnythingIsWritten) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleave_start_checks_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string base = shipped("brazilian_fracture.toml");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {disc_at_points(0.6), "wall[1].point"},
      {disc(1.2, 1.0), "stage[1].distance"},
      {replaced(base, "bottom = [0.0, 1.0, 0.0]", "bottom = [0.0, -1.0, 0.0]"),
       "stage[2].wall_velocity.bottom"},
      {replaced(base, "time = 0.1\n", "time = 0.005\n"), "stage[2].time"},
      {loose_box(1.0), "contact.dilation_radius"}};
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path file = dir / ("case" + std::to_string(i) + ".toml");
    std::ofstream(file) << cases[i].first;
    const fs::path out = dir / ("out" + std::to_string(i));
    const cleave::testing::CliOutcome o =
        cleave::testing::run_cleave("run " + file.string() + " --out " + out.string());
    EXPECT_EQ(o.code, 2) << o.output;
    EXPECT_TRUE(has(o.output, file.string() + ":")) << o.output;
    EXPECT_TRUE(has(o.output, "key '" + cases[i].second + "'")) << o.output;
    // Refused before the slabs and meshes.
    EXPECT_FALSE(fs::exists(out / "meshes")) << cases[i].second;
  }
  fs::remove_all(dir);
}

// Two mesh grains placed into each other (here the 2 m cube of tests/data/meshes twice,
// 1.5 m apart along x: their shapes overlap by 2 - 1.5 = 0.5 m, the distance that parts
// them) were accepted, and a first bond stage stored the overlap as the rest state. They
// are refused at the later grain's position, naming both grains and the depth.
TEST(StartChecks, MeshGrainsPlacedIntoEachOtherAreRefusedNamingBothAndTheDepth) {
  const fs::path meshes = fs::path(CLEAVE_SOURCE_DIR) / "tests" / "data" / "meshes";
  const auto scenario = [&](const std::string& position, bool bonded) {
    std::string text =
        "[scenario]\nlength_unit = \"m\"\n[specimen]\nshape = \"mesh\"\n"
        "[[mesh_grain]]\nfile = \"cube_triangulated.obj\"\n"
        "[[mesh_grain]]\nfile = \"cube_triangulated.obj\"\nposition = " +
        position + "\n";
    if (bonded)
      text +=
          "[contact]\ndilation_radius = 0.02\n[contact.particle_particle]\nkn = 5000.0\n"
          "[contact.particle_wall]\nkn = 5000.0\n[bond]\nkbn = 1e6\nkbs = 1e6\ntbn = 1e3\ntbs = "
          "1e3\n"
          "[dynamics]\ndt = 1e-6\ngravity = [0, 0, 0]\n[[stage]]\nname = \"bonding\"\nkind = "
          "\"bond\"\n"
          "distance = 0.05\n[[stage]]\nname = \"run\"\nsteps = 1\n";
    return text;
  };
  for (const bool bonded : {false, true}) {
    for (const auto& [position, depth] :
         {std::pair{"[1.5, 0, 0]", "0.5 m"}, {"[0, 0, 0]", "2 m"}}) {
      try {
        (void)parse_scenario(scenario(position, bonded), (meshes / "inline.toml").string());
        ADD_FAILURE() << "grains overlapping by " << depth << " were accepted";
      } catch (const ScenarioError& e) {
        EXPECT_EQ(e.key(), "mesh_grain[2].position") << e.what();
        EXPECT_EQ(e.line(), 9) << e.what();
        EXPECT_NE(
            e.message().find("grain 1 (cube_triangulated.obj) and grain 0 (cube_triangulated.obj, "
                             "mesh_grain[1]) intersect"),
            std::string::npos)
            << e.what();
        EXPECT_NE(e.message().find("reach " + std::string(depth) + " into each other"),
                  std::string::npos)
            << e.what();
      }
    }
  }
  // Face to face, 2 m apart: they touch and are accepted.
  EXPECT_NO_THROW(
      (void)parse_scenario(scenario("[2, 0, 0]", true), (meshes / "inline.toml").string()));
}

// The overlap measure against closed forms: unit cubes shifted by (0.3, 0.2, 0) overlap by
// 0.7 along x (the least axis); turned 45 degrees about z and shifted by 1.1 along x, a
// cube's corner reaches 0.5 + sqrt(2)/2 - 1.1 into the other.
TEST(StartChecks, ConvexOverlapIsTheDistanceThatPartsTwoCubes) {
  const auto cube = [](const Eigen::Matrix3d& turn, const Eigen::Vector3d& shift) {
    geometry::PolygonMesh m;
    for (int k = 0; k < 8; ++k)
      m.vertices.push_back(turn * (Eigen::Vector3d(k & 1, (k >> 1) & 1, (k >> 2) & 1) -
                                   Eigen::Vector3d::Constant(0.5)) +
                           shift);
    m.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return m;
  };
  const Eigen::Matrix3d none = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d turned =
      Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const geometry::PolygonMesh a = cube(none, Eigen::Vector3d::Zero());
  EXPECT_NEAR(convex_overlap(a, cube(none, {0.3, 0.2, 0.0})), 0.7, 1e-12);
  EXPECT_NEAR(convex_overlap(a, cube(turned, {1.1, 0.0, 0.0})), 0.5 + std::sqrt(0.5) - 1.1, 1e-12);
  EXPECT_LE(convex_overlap(a, cube(turned, {1.3, 0.0, 0.0})), 0.0);
  EXPECT_LE(convex_overlap(a, cube(none, {1.0, 0.0, 0.0})), 1e-12);  // face to face
}

}  // namespace
}  // namespace cleave::io
