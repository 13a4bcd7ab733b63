// `cleave calibrate` (sim/calibrate.hpp) recovers known bond parameters: targets are made by
// measuring a specimen with known springs and strengths, the calibration starts far from
// them, and it must find them again within its tolerance's reach.

#include <gtest/gtest.h>

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
  o.quiet = true;
  std::vector<std::string> all = overrides;
  all.push_back("dynamics.threads=1");
  return sim::measure(test, kDir / file, o, all);
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
  // The truth: shear bonds twice as strong as normal ones, both weaker than the scenarios'.
  const double tbn = 0.8e12, tbs = 1.6e12;
  const std::vector<std::string> truth = {"bond.tbn=0.8e12", "bond.tbs=1.6e12"};
  const sim::Measurement b = measured(sim::Test::brazilian, "sic_brazilian.toml", "truth_fb", truth);
  const sim::Measurement f = measured(sim::Test::flexural, "sic_four_point.toml", "truth_ff", truth);
  sim::CalibrationSetup setup;
  setup.brazilian = kDir / "sic_brazilian.toml";
  setup.flexural = kDir / "sic_four_point.toml";
  setup.targets.tensile_strength = b.value;
  setup.targets.flexural_strength = f.value;
  setup.tolerance = 0.01;
  setup.quiet = true;
  setup.out = fs::temp_directory_path() / "cleave_test_calibrate_flexural";
  // Equal strengths, 50 % and 25 % off: the disc reads 6 % and the bar 25 % high there.
  setup.start = {{"bond.tbn", 1.2e12}, {"bond.tbs", 1.2e12}};
  const sim::CalibrationResult r = sim::calibrate(setup);
  ASSERT_TRUE(r.converged) << r.trials.size() << " trials";
  const sim::CalibrationTrial& last = r.trials.back();
  EXPECT_LE(std::abs(last.error), 0.01);
  EXPECT_LE(std::abs(last.error_flexural), 0.01);
  // The disc, split by its bonds' shear, pins t_bs; the bar's strength moves little with
  // t_bn near the truth (the break on its tension face is a discrete event), so t_bn is
  // found more loosely: both within the reach the two targets allow.
  EXPECT_NEAR(r.parameters.at("bond.tbs") / tbs, 1.0, 0.05);
  EXPECT_NEAR(r.parameters.at("bond.tbn") / tbn, 1.0, 0.15);
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
  // sic_senb.toml cracks through its grains (transgranular fracture on): its K_Ic goes as
  // a^-1/2 in the criterion's crack length a (eq. 3.23). The target is what a = 20 um gives;
  // the calibration starts at the scenario's 42 um and must find 20 um again.
  const sim::Measurement truth =
      measured(sim::Test::senb, "sic_senb.toml", "truth_senb", {"fracture.crack_length=0.02"});
  sim::CalibrationSetup setup;
  setup.senb = kDir / "sic_senb.toml";
  setup.targets.toughness = truth.value;
  setup.tolerance = 0.02;
  setup.quiet = true;
  setup.out = fs::temp_directory_path() / "cleave_test_calibrate_toughness";
  const sim::CalibrationResult r = sim::calibrate(setup);
  ASSERT_TRUE(r.converged) << r.trials.size() << " trials";
  EXPECT_LE(std::abs(r.trials.back().error), 0.02);
  EXPECT_NEAR(r.parameters.at("fracture.crack_length") / 0.02, 1.0, 0.08);
  EXPECT_LE(r.trials.size(), 3u) << "K_Ic ~ a^-1/2 should need one correction, two at most";
  for (const auto& t : r.trials) EXPECT_EQ(t.loop, "toughness");
}
