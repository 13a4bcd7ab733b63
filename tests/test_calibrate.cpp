// `cleave calibrate` (sim/calibrate.hpp) recovers known bond parameters: targets are made by
// measuring a specimen with known springs and strengths, the calibration starts far from
// them, and it must find them again within its tolerance's reach.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include <filesystem>

#include <fstream>

#include "io/calibration_file.hpp"
#include "io/scenario.hpp"
#include "sim/calibrate.hpp"

namespace fs = std::filesystem;
using namespace cleave;

namespace {
const fs::path kDir = fs::path(CLEAVE_SOURCE_DIR) / "scenarios/materials";

sim::Measurement measured(sim::Test test, const char* file, const std::string& tag,
                          const std::vector<std::string>& overrides) {
  sim::SimulationOptions o;
  o.out = fs::temp_directory_path() / ("cleave_test_calibrate_" + tag);
  fs::remove_all(o.out);  // a fixed path: an earlier test run's folder is not this run's
  o.quiet = true;
  std::vector<std::string> all = overrides;
  all.push_back("dynamics.threads=1");
  return sim::measure(test, kDir / file, o, all);
}
/// A copy of the scenario `file` without its [fracture] table, at time step `dt` (null:
/// the file's): the bonds alone, as the strength loop's structure is about them.
fs::path bonds_only(const char* file, const char* dt, const std::string& tag) {
  std::ifstream in(kDir / file);
  std::string line, text;
  bool skipping = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '[') skipping = line.rfind("[fracture]", 0) == 0;
    if (skipping) continue;
    if (dt != nullptr && line.rfind("dt = ", 0) == 0) line = std::string("dt = ") + dt;
    text += line + "\n";
  }
  const fs::path dir = fs::temp_directory_path() / ("cleave_test_calibrate_" + tag);
  fs::create_directories(dir);
  const fs::path out = dir / file;
  std::ofstream(out) << text;
  return out;
}
}  // namespace

TEST(MaterialTest, CalibrationRecoversKnownBondParametersFromTheirMeasuredValues) {
  // The truth: softer springs than SiC's, a lower shear ratio (nu near 0.25), weaker bonds.
  const double kbn = 2.5e18, kbs = 0.5e18, tbn = 0.9e12;
  const sim::Measurement e = measured(sim::Test::elastic, "sic_elastic.toml", "truth_e",
                                      {"bond.kbn=2.5e18", "bond.kbs=0.5e18"});
  const sim::Measurement b = measured(sim::Test::brazilian, "sic_brazilian.toml", "truth_b",
                                      {"bond.tbn=0.9e12", "bond.tbs=0.9e12"});
  sim::CalibrationSetup setup;
  setup.elastic = kDir / "sic_elastic.toml";
  setup.brazilian = kDir / "sic_brazilian.toml";
  setup.targets.young = e.value;
  setup.targets.poisson = e.poisson;
  setup.targets.tensile_strength = b.value;
  setup.tolerance = 0.005;
  setup.quiet = true;
  setup.out = fs::temp_directory_path() / "cleave_test_calibrate_run";
  fs::remove_all(setup.out);  // a fixed path: an earlier test run's folder is not this run's
  // Far from the truth: twice as stiff, the shear ratio 0.6 instead of 0.2, bonds 40 % strong.
  setup.start = {{"bond.kbn", 5e18}, {"bond.kbs", 3e18}, {"bond.tbn", 1.26e12}, {"bond.tbs", 1.26e12}};
  const sim::CalibrationResult r = sim::calibrate(setup);
  ASSERT_TRUE(r.converged) << r.trials.size() << " trials";
  EXPECT_NEAR(r.parameters.at("bond.kbn") / kbn, 1.0, 0.01);
  EXPECT_NEAR(r.parameters.at("bond.kbs") / kbs, 1.0, 0.04);
  EXPECT_NEAR(r.parameters.at("bond.tbn") / tbn, 1.0, 0.01);
  EXPECT_NEAR(r.parameters.at("bond.tbs") / tbn, 1.0, 0.01);
  EXPECT_LE(r.trials.size(), 10u) << "the linear structure should need few trials";
  for (const auto& t : r.trials) EXPECT_GT(t.wall_seconds, 0.0);
}

TEST(MaterialTest, CalibrationFindsTheShearToNormalStrengthRatioThatGivesAFlexuralStrength) {
  // The truth: shear bonds twice as strong as normal ones, the normal ones weaker than the
  // scenarios'. The disc and the bar of the SiC scenarios without grain fracture (which would
  // cleave the bar's tension face at the strengths this starts from).
  const double tbn = 0.8e12, tbs = 1.6e12;
  const std::vector<std::string> truth = {"bond.tbn=0.8e12", "bond.tbs=1.6e12", "dynamics.threads=1"};
  // The time steps of the scenarios before grain fracture was on (the bar's is the grains').
  const fs::path disc = bonds_only("sic_brazilian.toml", nullptr, "disc_bonds");
  const fs::path bar = bonds_only("sic_four_point.toml", "9.75e-10", "bar_bonds");
  sim::SimulationOptions o;
  o.quiet = true;
  o.out = fs::temp_directory_path() / "cleave_test_calibrate_truth_fb";
  fs::remove_all(o.out);  // a fixed path: an earlier test run's folder is not this run's
  const sim::Measurement b = sim::measure(sim::Test::brazilian, disc, o, truth);
  o.out = fs::temp_directory_path() / "cleave_test_calibrate_truth_ff";
  fs::remove_all(o.out);  // a fixed path: an earlier test run's folder is not this run's
  const sim::Measurement f = sim::measure(sim::Test::flexural, bar, o, truth);
  sim::CalibrationSetup setup;
  setup.brazilian = disc;
  setup.flexural = bar;
  setup.targets.tensile_strength = b.value;
  // The bar is judged by its bending stress at its first crack, from its mid-span moment.
  setup.targets.flexural_strength = sim::judged_value(f);
  // The calibration file's tolerance for SiC, 2 % on both: the bar is judged at its first
  // crack, one tension-face bond's break, which goes with t_bn (its peak moved by jumps).
  setup.tolerance = 0.02;
  setup.quiet = true;
  setup.out = fs::temp_directory_path() / "cleave_test_calibrate_flexural";
  fs::remove_all(setup.out);  // a fixed path: an earlier test run's folder is not this run's
  // Equal strengths, 50 % and 25 % off.
  setup.start = {{"bond.tbn", 1.2e12}, {"bond.tbs", 1.2e12}};
  const sim::CalibrationResult r = sim::calibrate(setup);
  ASSERT_TRUE(r.converged) << r.trials.size() << " trials";
  const sim::CalibrationTrial& last = r.trials.back();
  EXPECT_LE(std::abs(last.error), 0.02);
  EXPECT_LE(std::abs(last.error_flexural), 0.02);
  // The bar's first crack, a bond pulled apart on its tension face, pins t_bn; the disc,
  // split by its bonds' shear as well, then t_bs: each within the reach its target's
  // tolerance allows (the disc's strength goes about as the square root of t_bs).
  EXPECT_NEAR(r.parameters.at("bond.tbn") / tbn, 1.0, 0.03);
  EXPECT_NEAR(r.parameters.at("bond.tbs") / tbs, 1.0, 0.08);
  EXPECT_LE(r.trials.size(), 8u) << "Broyden's method on two logs should need few trials";
  for (const auto& t : r.trials) EXPECT_FALSE(std::isnan(t.measured_flexural));
}

TEST(CalibrationFile, AFlexuralTestWithoutABrazilianOneIsAnErrorNamingTheLineAndKey) {
  const fs::path dir = fs::temp_directory_path() / "cleave_test_calibration_file";
  fs::create_directories(dir);
  const fs::path file = dir / "bad.toml";
  std::ofstream(file) << "[calibration]\n"
                      << "elastic = \"" << (kDir / "sic_elastic.toml").string() << "\"\n"
                      << "flexural = \"" << (kDir / "sic_four_point.toml").string() << "\"\n";
  try {
    io::load_calibration(file);
    FAIL() << "a flexural test without a brazilian one was accepted";
  } catch (const io::ScenarioError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.key(), "calibration.flexural");
  }
  std::ofstream(file) << "[calibration]\n"
                      << "brazilian = \"" << (kDir / "sic_brazilian.toml").string() << "\"\n"
                      << "flexural = \"" << (kDir / "sic_four_point.toml").string() << "\"\n";
  const io::CalibrationFile ok = io::load_calibration(file);
  EXPECT_EQ(ok.flexural, kDir / "sic_four_point.toml");
}

TEST(MaterialTest, CalibrationFindsTheCrackLengthThatGivesANotchedBeamItsToughness) {
  // With a criterion crack length of 20 or 40 um, sic_senb.toml cracks through its grains
  // before its bonds: its K_Ic goes as a^-1/2 (eq. 3.23). The target is what a = 20 um
  // gives; the calibration starts at 40 um and must find 20 um again.
  const sim::Measurement truth =
      measured(sim::Test::senb, "sic_senb.toml", "truth_senb", {"fracture.crack_length=0.02"});
  ASSERT_EQ(truth.first_crack, "grain") << "the notch must crack through its grains at a = 20 um";
  sim::CalibrationSetup setup;
  setup.senb = kDir / "sic_senb.toml";
  setup.targets.toughness = sim::judged_value(truth);  // K_Ic at the first crack
  setup.tolerance = 0.02;
  setup.quiet = true;
  setup.start["fracture.crack_length"] = 0.04;
  setup.out = fs::temp_directory_path() / "cleave_test_calibrate_toughness";
  fs::remove_all(setup.out);  // a fixed path: an earlier test run's folder is not this run's
  const sim::CalibrationResult r = sim::calibrate(setup);
  ASSERT_TRUE(r.converged) << r.trials.size() << " trials";
  EXPECT_LE(std::abs(r.trials.back().error), 0.02);
  EXPECT_NEAR(r.parameters.at("fracture.crack_length") / 0.02, 1.0, 0.08);
  EXPECT_LE(r.trials.size(), 3u) << "K_Ic ~ a^-1/2 should need one correction, two at most";
  for (const auto& t : r.trials) EXPECT_EQ(t.loop, "toughness");
  EXPECT_TRUE(r.advice.empty()) << r.advice;
}

TEST(MaterialTest, CalibrationSaysWhatScaleFitsAToughnessTheGrainBoundariesCarry) {
  // The shipped sic_senb.toml cracks along its grain boundaries (a = 3 um: a bond breaks first, no grain splits
  // before the peak), so no crack length can move its K_Ic. Asked for 2.0 MPa m^0.5, the
  // calibration must stop after one trial, not converged, and name the scale that K ~
  // sqrt(scale) gives: (2.0 / measured)^2.
  sim::CalibrationSetup setup;
  setup.senb = kDir / "sic_senb.toml";
  setup.targets.toughness = 2.0e6;
  setup.tolerance = 0.02;
  setup.quiet = true;
  setup.out = fs::temp_directory_path() / "cleave_test_calibrate_toughness_bonds";
  fs::remove_all(setup.out);  // a fixed path: an earlier test run's folder is not this run's
  const sim::CalibrationResult r = sim::calibrate(setup);
  EXPECT_FALSE(r.converged);
  ASSERT_EQ(r.trials.size(), 1u);
  const double scale = std::pow(2.0e6 / r.trials[0].measured, 2);
  EXPECT_NE(r.advice.find("grain boundaries"), std::string::npos) << r.advice;
  EXPECT_NE(r.advice.find(fmt::format("{:.4g}", scale)), std::string::npos) << r.advice;
  EXPECT_NE(r.advice.find("scale_scenario.py"), std::string::npos) << r.advice;
}
