// Prescribed temperature fields T(x, y, z, t) (issue 23, item 1): the formulas a stage's
// temperature_field is written in (muparser behind io/field_expression.hpp), their lengths
// moved to metres for the scenario as run, and a run whose every grain follows a field of
// any shape in space and time.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include "io/field_expression.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"
#include "physics/dem/world.hpp"
#include "sim/simulation.hpp"

using namespace cleave;
namespace fs = std::filesystem;

namespace {

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "the scenario no longer holds: " << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string thermal_scenario() {
  return io::read_file(fs::path(CLEAVE_SOURCE_DIR) / "scenarios" / "thermal_microcracking.toml");
}

const std::string kCooling =
    "temperature_rate = -2960.0   # K/s: 1773 K to 293 K over the stage\ntemperature_target = 293.0\n";

}  // namespace

TEST(FieldExpression, EvaluatesArithmeticAndFunctionsAsWritten) {
  // Random points against the same formulas written in C++.
  const io::FieldExpression f("300 + 2*x - y^2 + sin(z)*t + exp(-t/4) * (x > 0 ? 1 : -1) + sqrt(abs(y)) + _pi");
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int i = 0; i < 200; ++i) {
    const double x = u(rng), y = u(rng), z = u(rng), t = u(rng);
    const double want = 300 + 2 * x - y * y + std::sin(z) * t + std::exp(-t / 4) * (x > 0 ? 1 : -1) +
                        std::sqrt(std::abs(y)) + M_PI;
    EXPECT_NEAR(f(x, y, z, t), want, 1e-12 * std::abs(want)) << x << " " << y << " " << z << " " << t;
  }
}

TEST(FieldExpression, TheDocumentsExamplesReadAndGiveWhatTheySay) {
  // docs/USER_GUIDE.md: a hot spot of 1773 K at the centre at t = 0, spreading and keeping
  // its heat (the integral of T - 293 over the plane is 740 pi at any t).
  const io::FieldExpression spot("293 + 740/(0.5 + 1e3*t) * exp(-(x^2 + y^2)/(0.5 + 1e3*t))");
  EXPECT_NEAR(spot(0, 0, 0, 0), 1773.0, 1e-9);
  for (const double t : {0.0, 1e-3, 5e-3}) {
    double heat = 0.0;
    const double h = 0.02;
    for (double x = -12; x <= 12; x += h)
      for (double y = -12; y <= 12; y += h) heat += (spot(x, y, 0, t) - 293) * h * h;
    EXPECT_NEAR(heat, 740 * M_PI, 1e-3 * 740 * M_PI) << t;
  }
  // A ripple on a cooling ramp: sin of x over a length.
  const io::FieldExpression ripple("1773 - 2e9*t*(1 + 0.1*sin(x/0.075))");
  EXPECT_NEAR(ripple(0.075 * M_PI / 2, 0, 0, 1e-7), 1773 - 200 * 1.1, 1e-9);
}

TEST(FieldExpression, RefusesAFormulaItCannotReadWithMuparsersReason) {
  for (const char* bad : {"300 + ", "300 + q*x", "sin(x", "foo(x)", ""}) {
    try {
      io::FieldExpression f(bad);
      ADD_FAILURE() << "accepted \"" << bad << "\"";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(std::string("\"") + bad + "\""), std::string::npos) << what;
      EXPECT_NE(what.find("the variables are x, y, z and t"), std::string::npos) << what;
    }
  }
}

TEST(FieldExpression, LengthsInMetresGiveTheSameFieldAtThePointInMetres) {
  // A formula in mm, rewritten for coordinates in metres, agrees with the original at the
  // same point; names that contain x, y or z (exp) and numbers with exponents stay whole.
  const std::string mm = "1773 - 2e3*t + 1.5e-1*x^2 - 4E+0*y*exp(-z/2) + max(x, 2.5e-2)";
  const std::string m = io::lengths_in_metres(mm, 1e-3);
  EXPECT_NE(m.find("exp("), std::string::npos) << m;
  EXPECT_NE(m.find("(x/0.001)"), std::string::npos) << m;
  const io::FieldExpression in_mm(mm), in_m(m);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 200; ++i) {
    const double x = u(rng), y = u(rng), z = u(rng), t = u(rng);
    const double want = in_mm(x, y, z, t);
    EXPECT_NEAR(in_m(x * 1e-3, y * 1e-3, z * 1e-3, t), want, 1e-12 * std::abs(want));
  }
  EXPECT_EQ(io::lengths_in_metres(mm, 1.0), mm);
}

TEST(PrescribedField, ScenarioKeysReadBackAndBadOnesAreRefusedAtTheirKey) {
  const std::string text = replace_once(thermal_scenario(), kCooling,
                                        "temperature_field = \"1773 - 2960*t + 10*x*y\"\nhold_cracks = true\n");
  const io::Scenario s = io::parse_scenario(text, "field.toml");
  const io::StageDef& cool = s.stages.at(1);
  EXPECT_EQ(cool.temperature_field, "1773 - 2960*t + 10*(x/0.001)*(y/0.001)");  // the file is in mm
  EXPECT_TRUE(cool.hold_cracks);
  // The scenario as run (in metres) reads back as the same scenario.
  const io::Scenario back = io::parse_scenario(io::scenario_to_toml(s), "as_run.toml");
  EXPECT_TRUE(io::scenario_differences(s, back).empty());

  auto refused = [&](const std::string& edited, const std::string& key, const std::string& says) {
    try {
      io::parse_scenario(edited, "bad.toml");
      ADD_FAILURE() << "accepted: " << key;
    } catch (const io::ScenarioError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
      EXPECT_GT(e.line(), 1) << e.what();
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused(replace_once(thermal_scenario(), kCooling, "temperature_field = \"1773 - \"\n"), "stage[2].temperature_field",
          "1773 - ");
  refused(replace_once(thermal_scenario(), "temperature_target = 293.0\n",
                       "temperature_target = 293.0\ntemperature_field = \"300\"\n"),
          "stage[2].temperature_field", "leave out temperature_rate");
  std::string unheated = replace_once(thermal_scenario(), kCooling, "temperature_field = \"300\"\n");
  unheated.erase(unheated.find("[thermal]"), unheated.find("[dynamics]") - unheated.find("[thermal]"));
  refused(unheated, "stage[2].temperature_field", "needs a [thermal] table");
  const std::string cohesive = replace_once(
      replace_once(thermal_scenario(), "tbn = 2000.0", "law = \"cohesive\"\nsigma_c = 2000.0\ng_c = 1e-3\n#"),
      "tbs = 1000.0", "# tbs");
  refused(replace_once(cohesive, kCooling, kCooling + "hold_cracks = true\n"), "stage[2].hold_cracks",
          "cohesive law's damage cannot be held");
}

TEST(PrescribedField, EveryGrainFollowsAFieldOfAnyShapeInSpaceAndTime) {
  // scenarios/thermal_microcracking.toml with its uniform cooling replaced by a field that is
  // neither uniform nor linear: T = 1773 - 2000 t (1 + 0.3 sin(x) cos(y/3)) + 20 z^2 (x, y,
  // z in mm, t in s). After each of three advances every grain's temperature is the formula
  // at its centroid at the end of the last step (the grains move a little in the step after
  // their temperature is set: within 0.01 K).
  const std::string formula = "1773 - 2000*t*(1 + 0.3*sin(x)*cos(y/3)) + 20*z^2";
  const std::string text = replace_once(thermal_scenario(), kCooling, "temperature_field = \"" + formula + "\"\n");
  sim::SimulationOptions o;
  o.out = fs::temp_directory_path() / "cleave_test_prescribed_field";
  fs::remove_all(o.out);  // a fixed path: an earlier test run's folder is not this run's
  o.quiet = true;
  auto run = sim::Simulation::from_text(text, "field.toml", o);
  run->start();
  run->advance_stage();  // bond
  const io::FieldExpression f(formula);
  const double dt = run->scenario().dynamics.dt;
  double spread = 0.0;
  for (int k = 0; k < 3; ++k) {
    run->advance(5000);
    const physics::World& world = run->dynamics()->world();
    const double t = static_cast<double>(5000 * (k + 1)) * dt;
    double lo = 1e300, hi = -1e300;
    for (const physics::BodyId id : world.body_ids()) {
      const Eigen::Vector3d x = world.state(id).x * 1e3;  // mm
      const double T = world.temperature(id);
      EXPECT_NEAR(T, f(x.x(), x.y(), x.z(), t), 0.01) << "grain " << world.info(id).grain_id << " at t = " << t;
      lo = std::min(lo, T);
      hi = std::max(hi, T);
    }
    spread = hi - lo;
  }
  EXPECT_GT(spread, 50.0);  // the field is far from uniform
}
