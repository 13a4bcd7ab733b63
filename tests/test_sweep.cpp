// Parameter sweeps: --set parsing, the Cartesian product, keys written into the scenario, the
// Weibull fit against closed-form quantiles and against samples of a known distribution, and
// `cleave sweep` of a 4-seed Brazilian ensemble as a user runs it.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "cli_helpers.hpp"
#include "io/result_dir.hpp"
#include "io/sweep.hpp"

using namespace cleave::io;
namespace fs = std::filesystem;

TEST(SweepAxis, ListsAndIntegerRanges) {
  const SweepAxis a = parse_sweep_axis("bond.tbn=500, 1000,2e3");
  EXPECT_EQ(a.key, "bond.tbn");
  EXPECT_EQ(a.values, (std::vector<std::string>{"500", "1000", "2e3"}));
  const SweepAxis r = parse_sweep_axis("orientation.seed=3..7");
  EXPECT_EQ(r.values, (std::vector<std::string>{"3", "4", "5", "6", "7"}));
  EXPECT_EQ(parse_sweep_axis("stage[3].time=0.1").key, "stage[3].time");
}

TEST(SweepAxis, BadSpecificationsAreErrorsNamingThem) {
  for (const char* bad :
       {"bond.tbn", "=1", "bond.tbn=", "tbn=1", "bond.tbn=1,,2", "orientation.seed=5..2",
        "orientation.seed=a..3", "stage[0].time=1", "stage[x].time=1", "bond..tbn=1"}) {
    try {
      (void)parse_sweep_axis(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const SweepError& e) {
      EXPECT_NE(std::string(e.what()).find("--set"), std::string::npos) << e.what();
    }
  }
}

TEST(SweepPoints, CartesianProductLastAxisFastest) {
  const std::vector<SweepAxis> axes = {parse_sweep_axis("a.x=1,2"), parse_sweep_axis("b.y=p,q,r")};
  const auto points = sweep_points(axes);
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points[0], (SweepPoint{"1", "p"}));
  EXPECT_EQ(points[1], (SweepPoint{"1", "q"}));
  EXPECT_EQ(points[3], (SweepPoint{"2", "p"}));
  EXPECT_EQ(points[5], (SweepPoint{"2", "r"}));
  EXPECT_THROW(sweep_points(axes, 5), SweepError);
  EXPECT_THROW(sweep_points({axes[0], axes[0]}), SweepError);
  EXPECT_THROW(sweep_points({}), SweepError);
}

TEST(SweepPoints, ZippedAxesVaryTogetherAsOneFactorOfTheProduct) {
  // --set a.x=1,2 --zip b.y=p,q,r --zip c.z=4,5,6: 2 x 3 runs (not 2 x 3 x 3), each b.y with
  // the c.z of the same place in its list.
  std::vector<SweepAxis> axes = {parse_sweep_axis("a.x=1,2"), parse_sweep_axis("b.y=p,q,r"),
                                 parse_sweep_axis("c.z=4,5,6")};
  axes[1].zipped = axes[2].zipped = true;
  const auto points = sweep_points(axes);
  ASSERT_EQ(points.size(), 6u);
  const std::vector<SweepPoint> expected = {{"1", "p", "4"}, {"1", "q", "5"}, {"1", "r", "6"},
                                            {"2", "p", "4"}, {"2", "q", "5"}, {"2", "r", "6"}};
  EXPECT_EQ(points, expected);
  // Only zipped axes: as many runs as each has values.
  EXPECT_EQ(sweep_points({axes[1], axes[2]}).size(), 3u);
  // Unequal lengths are an error naming both keys.
  axes[2] = parse_sweep_axis("c.z=4,5");
  axes[2].zipped = true;
  try {
    (void)sweep_points(axes);
    ADD_FAILURE() << "zipped axes of 3 and 2 values were accepted";
  } catch (const SweepError& e) {
    EXPECT_NE(std::string(e.what()).find("--zip c.z has 2 values but --zip b.y has 3"),
              std::string::npos)
        << e.what();
  }
}

TEST(SweepPointErrors, NameTheValueAtItsKeyAndKeepTheFilesOwnLines) {
  const std::string text =
      "[specimen]\nshape = \"box\"\nsize = [6.0, 6.0, 2.0]\n[grain]\nr = 1.0\n"
      "r_bar = 0.9\nt = 1.0\n";
  const auto read = [&](const std::string& file_text, const std::vector<std::string>& overrides) {
    const auto [axes, point] = parse_overrides(overrides, "--set");
    std::vector<std::string> shown;
    for (const auto& o : overrides) shown.push_back("--set " + o);
    return read_sweep_point(file_text, "s.toml", axes, point, shown, "/");
  };
  EXPECT_EQ(read(text, {"grain.r_bar=0.5"}).specimen.r_bar, 0.5e-3);
  try {  // at the key the override sets: the override, no line
    (void)read(text, {"grain.r_bar=abc"});
    ADD_FAILURE();
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(
                  "--set grain.r_bar=abc: key 'grain.r_bar': expected a number", 0),
              0u)
        << e.what();
    EXPECT_EQ(e.file(), "s.toml");
    EXPECT_EQ(e.line(), 0);
    EXPECT_EQ(e.key(), "grain.r_bar");
  }
  try {  // the file's own error: its line
    (void)read(text + "colour = 1\n", {"grain.r_bar=0.5"});
    ADD_FAILURE();
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("s.toml:8:", 0), 0u) << e.what();
  }
  try {  // caused elsewhere: the file, the key and the override
    (void)read(text, {"grain.r=0.5"});
    ADD_FAILURE();
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("s.toml: key 'grain.r_bar': must not exceed", 0), 0u)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("(with --set grain.r=0.5)"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_overrides({"grain.r=1,2"}, "--set"), SweepError);
  EXPECT_THROW(parse_overrides({"grain.r=1", "grain.r=2"}, "--set"), SweepError);
}

TEST(ApplySweepPoint, SetsKeysWithTheirTypesCreatesTablesAndReachesStages) {
  const std::string text = R"(
[bond]
tbn = 1000.0
[[stage]]
name = "a"
time = 1.0
[[stage]]
name = "b"
time = 2.0
[[mesh_grain]]
file = "meshes/cube.obj"
)";
  const std::vector<SweepAxis> axes = {
      parse_sweep_axis("bond.tbn=1,2"), parse_sweep_axis("orientation.seed=7,8"),
      parse_sweep_axis("stage[2].time=0.25,0.5"), parse_sweep_axis("output.mesh_format=obj,stl")};
  const std::string out =
      apply_sweep_point(text, "s.toml", axes, {"2", "8", "0.5", "obj"}, "/data/base");
  const toml::table t = toml::parse(out);
  EXPECT_EQ(t["bond"]["tbn"].value<std::int64_t>(), 2);
  EXPECT_EQ(t["orientation"]["seed"].value<std::int64_t>(), 8);
  EXPECT_EQ(t["stage"][1]["time"].value<double>(), 0.5);
  EXPECT_EQ(t["stage"][0]["time"].value<double>(), 1.0);  // the other stage untouched
  EXPECT_EQ(t["stage"][1]["name"].value<std::string>(), "b");
  EXPECT_EQ(t["output"]["mesh_format"].value<std::string>(), "obj");
  EXPECT_EQ(t["mesh_grain"][0]["file"].value<std::string>(), "/data/base/meshes/cube.obj");

  EXPECT_THROW(apply_sweep_point(text, "s.toml", {parse_sweep_axis("stage[3].time=1")}, {"1"}, "/"),
               SweepError);
  EXPECT_THROW(apply_sweep_point(text, "s.toml", {parse_sweep_axis("bond.tbn.x=1")}, {"1"}, "/"),
               SweepError);
  EXPECT_THROW(apply_sweep_point("[bond\n", "s.toml", {parse_sweep_axis("bond.tbn=1")}, {"1"}, "/"),
               SweepError);
}

TEST(SweepAxis, ARatioKeyIsKeyOverReferenceWithNumericRatios) {
  const SweepAxis a = parse_sweep_axis("bond.tbn/fracture.sigma_f=0.1,1,10");
  EXPECT_EQ(a.key, "bond.tbn");
  EXPECT_EQ(a.reference, "fracture.sigma_f");
  EXPECT_EQ(a.name(), "bond.tbn/fracture.sigma_f");
  EXPECT_EQ(a.values, (std::vector<std::string>{"0.1", "1", "10"}));
  EXPECT_EQ(parse_sweep_axis("bond.tbn=1").name(), "bond.tbn");
  for (const char* bad : {"bond.tbn/fracture.sigma_f=0.1,abc", "bond.tbn/=1", "/bond.tbn=1",
                          "bond.tbn/fracture=1", "bond.tbn/a.b/c.d=1"})
    EXPECT_THROW((void)parse_sweep_axis(bad), SweepError) << bad;
}

// A ratio axis writes ratio x the reference's value: the file's, or the value another axis
// gives it (set first), with a unit kept; the expected values are the products of the
// numbers in the text.
TEST(ApplySweepPoint, ARatioKeyIsTheRatioTimesItsReferenceAfterTheOtherKeys) {
  const std::string text =
      "[bond]\ntbn = 1000.0\ntbs = 1000\n[fracture]\ncriterion = \"rankine\"\nsigma_f = 3.0e8\n"
      "[thermal]\nalpha = \"8e-6 1/K\"\n";
  const auto apply = [&](const std::vector<std::string>& specs, const SweepPoint& point,
                         std::vector<std::string>* absolute = nullptr) {
    std::vector<SweepAxis> axes;
    for (const auto& spec : specs) axes.push_back(parse_sweep_axis(spec));
    return toml::parse(apply_sweep_point(text, "s.toml", axes, point, "/", absolute));
  };
  std::vector<std::string> absolute;
  const toml::table a = apply({"bond.tbn/fracture.sigma_f=0.1"}, {"0.1"}, &absolute);
  EXPECT_DOUBLE_EQ(*a["bond"]["tbn"].value<double>(), 0.1 * 3.0e8);
  ASSERT_EQ(absolute.size(), 1u);
  EXPECT_DOUBLE_EQ(std::stod(absolute[0]), 0.1 * 3.0e8);
  // The reference swept too: the ratio multiplies each run's value, whatever the order.
  const toml::table b =
      apply({"bond.tbn/fracture.sigma_f=2", "fracture.sigma_f=5e7"}, {"2", "5e7"});
  EXPECT_DOUBLE_EQ(*b["bond"]["tbn"].value<double>(), 2 * 5e7);
  // An integer reference and an integral product stay an integer; a unit is kept.
  const toml::table c =
      apply({"bond.tbn/bond.tbs=3", "thermal.alpha_c/thermal.alpha=2"}, {"3", "2"}, &absolute);
  EXPECT_EQ(c["bond"]["tbn"].value<std::int64_t>(), 3000);
  EXPECT_EQ(c["thermal"]["alpha_c"].value<std::string>(), "1.6e-05 1/K");
  EXPECT_EQ(absolute[1], "1.6e-05 1/K");
  // A reference missing from the file, or not a number: the key, the file (and its line).
  try {
    (void)apply({"bond.tbn/fracture.k_ic=1"}, {"1"});
    ADD_FAILURE();
  } catch (const SweepError& e) {
    EXPECT_NE(std::string(e.what()).find("fracture.k_ic is not in s.toml"), std::string::npos)
        << e.what();
  }
  try {
    (void)apply({"bond.tbn/fracture.criterion=1"}, {"1"});
    ADD_FAILURE();
  } catch (const SweepError& e) {
    EXPECT_NE(
        std::string(e.what()).find("fracture.criterion at s.toml:5 is \"rankine\", not a number"),
        std::string::npos)
        << e.what();
  }
}

// The derived reference fracture.cleavage_strength: sigma_f of the stress criteria, and for
// lefm the stress whose K_I = sigma sqrt(pi a) (eq. 3.23) is K_Ic, with a's unit applied.
TEST(ApplySweepPoint, ARatioOfTheCleavageStrengthIsInPascals) {
  const std::string base = cleave::testing::drop_scenario("cs", "duration = 1e-5\n");
  const auto tbn = [&](const std::string& fracture, const std::string& ratio) {
    const std::vector<SweepAxis> axes = {
        parse_sweep_axis("bond.tbn/fracture.cleavage_strength=" + ratio)};
    const toml::table t =
        toml::parse(apply_sweep_point(base + fracture, "s.toml", axes, {ratio}, "/"));
    return *t["bond"]["tbn"].value<std::string>();
  };
  const auto pascals = [](const std::string& text) {
    EXPECT_TRUE(text.ends_with(" Pa")) << text;
    return std::stod(text);
  };
  // LEFM: K_Ic = 2 MPa sqrt(m), a = 0.1 mm -> sigma = 2e6 / sqrt(pi 1e-4) = 112.84 MPa.
  const double lefm = pascals(
      tbn("\n[fracture]\nsigma_f_hyd = 0.0\nk_ic = 2.0e6\ncrack_length = \"0.1 mm\"\n", "0.5"));
  EXPECT_NEAR(lefm, 0.5 * 2.0e6 / std::sqrt(M_PI * 1e-4), 1e-9 * lefm);
  EXPECT_NEAR(lefm, 0.5 * 112.837916709551e6, 1e-6 * lefm);
  const double rankine =
      pascals(tbn("\n[fracture]\ncriterion = \"rankine\"\nsigma_f = 3.0e8\n", "3"));
  EXPECT_DOUBLE_EQ(rankine, 9.0e8);
  // Read from [fracture] alone: a point whose other keys are not valid yet (a ratio axis sets
  // them after this one) still has its reference.
  EXPECT_NO_THROW(
      (void)tbn("\n[fracture]\nk_ic = 2.0e6\ncrack_length = 0.1\n[bond]\nkbn = -1.0\n", "1"));
  // A missing constant is named.
  try {
    (void)tbn("\n[fracture]\nk_ic = 2.0e6\n", "1");
    ADD_FAILURE();
  } catch (const SweepError& e) {
    EXPECT_NE(std::string(e.what()).find("fracture.crack_length"), std::string::npos) << e.what();
  }
  // No [fracture]: no strength to be relative to.
  try {
    (void)tbn("", "1");
    ADD_FAILURE();
  } catch (const SweepError& e) {
    EXPECT_NE(std::string(e.what()).find("no [fracture] table"), std::string::npos) << e.what();
  }
}

TEST(SampleStats, MeanAndSampleStandardDeviationOfAKnownSet) {
  // 2, 4, 4, 4, 5, 5, 7, 9: mean 5, squares about it 32, so sd = sqrt(32 / 7) with n - 1.
  const SampleStats s = sample_stats({2, 4, 4, 4, 5, 5, 7, 9, NAN});
  EXPECT_EQ(s.count, 8u);
  EXPECT_DOUBLE_EQ(s.mean, 5.0);
  EXPECT_DOUBLE_EQ(s.stddev, std::sqrt(32.0 / 7.0));
  const SampleStats one = sample_stats({3.5});
  EXPECT_EQ(one.count, 1u);
  EXPECT_DOUBLE_EQ(one.mean, 3.5);
  EXPECT_TRUE(std::isnan(one.stddev));
  EXPECT_EQ(sample_stats({NAN}).count, 0u);
}

TEST(ReplicateMeans, OneRowPerCombinationOverItsCountedRuns) {
  const std::vector<std::string> header = {"run", "a", "seed", "status", "x", "note"};
  const std::vector<std::vector<std::string>> rows = {
      {"run_001", "1", "1", "finished", "1.0", "p"}, {"run_002", "1", "2", "finished", "3.0", "q"},
      {"run_003", "1", "3", "failed", "100", "r"},   {"run_004", "2", "1", "finished", "2"},
      {"run_005", "2", "2", "finished", ""},         {"run_006", "2", "3", "finished", "10"}};
  const std::vector<bool> counted = {true, true, false, true, true, true};
  std::istringstream csv(replicate_means_csv(header, rows, {1}, {4}, counted));
  std::vector<std::string> lines;
  for (std::string line; std::getline(csv, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "a,runs,counted,x_mean,x_sd,x_n");
  // a = 1: 1 and 3 (the failed run left out): mean 2, sd sqrt(((1-2)^2 + (3-2)^2) / 1).
  EXPECT_EQ(lines[1], "1,3,2,2," + fmt::format("{:.9g}", std::sqrt(2.0)) + ",2");
  // a = 2: 2 and 10 (an empty cell is no number): mean 6, sd sqrt((16 + 16) / 1).
  EXPECT_EQ(lines[2], "2,3,3,6," + fmt::format("{:.9g}", std::sqrt(32.0)) + ",2");
}

TEST(WeibullFit, RecoversModulusAndScaleFromExactQuantiles) {
  // Strengths at exactly the plotting positions' quantiles s_i = s0 (-ln(1 - F_i))^(1/m) lie
  // on the regression line: the fit returns m and s0 to round-off, with R^2 = 1.
  for (double m : {2.5, 8.0, 20.0})
    for (std::size_t n : {3u, 10u, 40u}) {
      const double s0 = 37.5;
      std::vector<double> s;
      for (std::size_t i = n; i >= 1; --i)  // any order
        s.push_back(s0 * std::pow(-std::log(1.0 - median_rank(i, n)), 1.0 / m));
      const WeibullFit fit = fit_weibull(s);
      EXPECT_NEAR(fit.modulus, m, 1e-9 * m);
      EXPECT_NEAR(fit.scale, s0, 1e-9 * s0);
      EXPECT_NEAR(fit.r_squared, 1.0, 1e-12);
      EXPECT_TRUE(std::is_sorted(fit.sorted.begin(), fit.sorted.end()));
    }
}

TEST(WeibullFit, EstimatesAKnownDistributionFromSamples) {
  std::mt19937_64 rng(20261201);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double m = 10.0, s0 = 50.0;
  std::vector<double> s;
  for (int i = 0; i < 4000; ++i) s.push_back(s0 * std::pow(-std::log(1.0 - u(rng)), 1.0 / m));
  const WeibullFit fit = fit_weibull(s);
  EXPECT_NEAR(fit.modulus, m, 0.05 * m);
  EXPECT_NEAR(fit.scale, s0, 0.01 * s0);
  EXPECT_GT(fit.r_squared, 0.98);
}

TEST(WeibullFit, RefusesWhatCannotBeFitted) {
  EXPECT_THROW(fit_weibull({1.0, 2.0}), SweepError);
  EXPECT_THROW(fit_weibull({1.0, -2.0, 3.0}), SweepError);
  EXPECT_THROW(fit_weibull({2.0, 2.0, 2.0}), SweepError);
}

TEST(SizeEffect, WeakestLinkSamplesGiveTheExponentTwoOverTheWeibullModulus) {
  // Discs of fixed thickness: the volume grows as D^2, so weakest-link strengths of modulus m
  // scale as D^(-2/m): s = s0 (D / D0)^(-2/m) (-ln(1 - U))^(1/m). Drawn at three diameters,
  // the fit recovers the exponent, the pooled modulus and each size's own modulus.
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double m = 8.0, s0 = 250e6;
  std::vector<std::pair<double, double>> runs;
  for (const double d : {4.0, 8.0, 16.0})
    for (int i = 0; i < 3000; ++i)
      runs.emplace_back(
          d, s0 * std::pow(d / 4.0, -2.0 / m) * std::pow(-std::log(1.0 - u(rng)), 1.0 / m));
  const SizeEffect e = fit_size_effect(runs);
  ASSERT_EQ(e.groups.size(), 3u);
  EXPECT_EQ(e.groups.front().size, 4.0);
  EXPECT_EQ(e.groups.back().size, 16.0);
  EXPECT_NEAR(e.exponent, 2.0 / m, 0.03 * 2.0 / m);
  ASSERT_TRUE(e.pooled.has_value());
  EXPECT_NEAR(e.pooled->modulus, m, 0.05 * m);
  for (const SizeGroup& g : e.groups) {
    ASSERT_TRUE(g.weibull.has_value());
    EXPECT_NEAR(g.weibull->modulus, m, 0.07 * m) << g.size;
    // The mean of a Weibull variable: s0' Gamma(1 + 1/m).
    const double expected = s0 * std::pow(g.size / 4.0, -2.0 / m) * std::tgamma(1.0 + 1.0 / m);
    EXPECT_NEAR(g.mean, expected, 0.01 * expected) << g.size;
  }
  EXPECT_NEAR(e.prefactor * std::pow(4.0, -e.exponent), e.groups.front().mean,
              0.02 * e.groups.front().mean);
}

TEST(SizeEffect, RefusesOneSizeAndNonPositiveValues) {
  EXPECT_THROW(fit_size_effect({{4.0, 1.0}, {4.0, 2.0}}), SweepError);
  EXPECT_THROW(fit_size_effect({{4.0, 1.0}, {-8.0, 2.0}}), SweepError);
  EXPECT_THROW(fit_size_effect({{4.0, 1.0}, {8.0, 0.0}}), SweepError);
}

namespace {

using Outcome = cleave::testing::CliOutcome;
using cleave::testing::run_cleave;

}  // namespace

TEST(SweepCommand, FourSeedsWriteOneRowPerRunAndTheWeibullFit) {
  const fs::path dir = fs::temp_directory_path() / ("cleave_sweep_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string scenario = std::string(CLEAVE_SOURCE_DIR) + "/tests/data/sweep_brazilian.toml";
  const Outcome o =
      run_cleave("sweep " + scenario + " --set orientation.seed=1..4 --jobs 2 -o " + dir.string());
  ASSERT_EQ(o.code, 0) << o.output;
  const auto rows = cleave::testing::read_csv_cells(dir / "summary.csv");
  ASSERT_EQ(rows.size(), 5u);  // header + 4 runs
  const auto& h = rows[0];
  const auto col = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(h.begin(), h.end(), name) - h.begin());
  };
  ASSERT_LT(col("strength_Pa"), h.size());
  std::vector<double> strengths;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_EQ(rows[r][col("orientation.seed")], std::to_string(r));
    EXPECT_EQ(rows[r][col("status")], "finished");
    // Each row is what that run's own manifest says.
    const Manifest m = read_manifest(dir / rows[r][0]);
    EXPECT_EQ(m.facts.at("brazilian_strength_Pa"), rows[r][col("strength_Pa")]);
    EXPECT_EQ(m.facts.at("intergranular_breaks"), rows[r][col("bonds_broken")]);
    strengths.push_back(std::stod(rows[r][col("strength_Pa")]));
  }
  // The fit written is the fit of the strengths in the table.
  const WeibullFit fit = fit_weibull(strengths);
  const Manifest sweep = read_manifest(dir);
  EXPECT_EQ(sweep.status, "finished");
  EXPECT_NEAR(std::stod(sweep.facts.at("weibull_modulus")), fit.modulus, 1e-5 * fit.modulus);
  EXPECT_EQ(cleave::testing::read_csv_cells(dir / "weibull.csv").size(), 5u);
  EXPECT_TRUE(fs::exists(dir / "weibull.svg"));
  fs::remove_all(dir);
}

TEST(SweepCommand, AKeyTheScenarioCannotTakeStopsBeforeAnyRun) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleave_sweep_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string scenario = std::string(CLEAVE_SOURCE_DIR) + "/tests/data/sweep_brazilian.toml";
  const Outcome o = run_cleave("sweep " + scenario + " --set bond.nonsense=1,2 -o " + dir.string());
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("nonsense"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(dir / "run_001"));
  const Outcome r = run_cleave("sweep " + scenario + " --set orientation.seed=9..1");
  EXPECT_EQ(r.code, 2) << r.output;
  fs::remove_all(dir);
}

TEST(SweepCommand, ZippedKeysMakeNRunsWithTheirValuesPaired) {
  // --zip orientation.seed=1,2,3 --zip grain.r_bar=0.5,0.55,0.52: three runs, not nine, each
  // scenario holding the pair of the same place; summary.csv has a column per key.
  const fs::path dir =
      fs::temp_directory_path() / ("cleave_sweep_zip_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string scenario = std::string(CLEAVE_SOURCE_DIR) + "/tests/data/sweep_brazilian.toml";
  const Outcome o =
      run_cleave("sweep -q " + scenario +
                 " --zip orientation.seed=1,2,3 --zip grain.r_bar=0.5,0.55,0.52 --max-steps 5 "
                 "--jobs 2 -o " +
                 dir.string());
  ASSERT_EQ(o.code, 0) << o.output;
  const auto rows = cleave::testing::read_csv_cells(dir / "summary.csv");
  ASSERT_EQ(rows.size(), 4u);  // header + 3 runs
  const auto& h = rows[0];
  const auto col = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(h.begin(), h.end(), name) - h.begin());
  };
  ASSERT_LT(col("orientation.seed"), h.size());
  ASSERT_LT(col("grain.r_bar"), h.size());
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"1", "0.5"}, {"2", "0.55"}, {"3", "0.52"}};
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_EQ(rows[r][col("orientation.seed")], pairs[r - 1].first);
    EXPECT_EQ(rows[r][col("grain.r_bar")], pairs[r - 1].second);
    const toml::table run = toml::parse_file((dir / "scenarios" / (rows[r][0] + ".toml")).string());
    EXPECT_EQ(run["orientation"]["seed"].value<std::int64_t>(), std::stoll(pairs[r - 1].first));
    EXPECT_EQ(run["grain"]["r_bar"].value<double>(), std::stod(pairs[r - 1].second));
  }
  EXPECT_EQ(read_manifest(dir).facts.at("zip.grain.r_bar"), "0.5,0.55,0.52");
  // Unequal lists: a usage error before any run.
  const fs::path bad = dir / "bad";
  const Outcome b = run_cleave("sweep -q " + scenario +
                               " --zip orientation.seed=1,2,3 --zip grain.r_bar=0.5,0.55 "
                               "-o " +
                               bad.string());
  EXPECT_EQ(b.code, 2) << b.output;
  EXPECT_NE(b.output.find("--zip grain.r_bar has 2 values but --zip orientation.seed has 3"),
            std::string::npos)
      << b.output;
  EXPECT_FALSE(fs::exists(bad / "run_001"));
  // A value the scenario cannot take is named as given.
  const Outcome v =
      run_cleave("sweep -q " + scenario + " --set bond.tbn=1000,abc -o " + bad.string());
  EXPECT_EQ(v.code, 2) << v.output;
  EXPECT_NE(v.output.find("--set bond.tbn=abc: key 'bond.tbn'"), std::string::npos) << v.output;
  fs::remove_all(dir);
}

TEST(SweepCommand, RunsCutByMaxStepsAreStoppedRowsNotFailuresAndStayOutOfTheFit) {
  // Five steps cannot reach the load drop of a Brazilian test: every run is stopped, as
  // asked. The sweep is not a failure (exit 0) but says stopped, and no strength is fitted.
  const fs::path dir =
      fs::temp_directory_path() / ("cleave_sweep_cut_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string scenario = std::string(CLEAVE_SOURCE_DIR) + "/tests/data/sweep_brazilian.toml";
  const Outcome o =
      run_cleave("sweep " + scenario + " --set orientation.seed=1..3 --max-steps 5 --jobs 2 -o " +
                 dir.string());
  ASSERT_EQ(o.code, 0) << o.output;
  EXPECT_NE(o.output.find("3 stopped by --max-steps"), std::string::npos) << o.output;
  const auto rows = cleave::testing::read_csv_cells(dir / "summary.csv");
  ASSERT_EQ(rows.size(), 4u);  // header + 3 runs
  const auto& h = rows[0];
  const auto status = static_cast<std::size_t>(std::find(h.begin(), h.end(), "status") - h.begin());
  ASSERT_LT(status, h.size());
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_EQ(rows[r][status], "stopped");
    EXPECT_EQ(read_manifest(dir / rows[r][0]).status, "stopped");
  }
  const Manifest sweep = read_manifest(dir);
  EXPECT_EQ(sweep.status, "stopped");
  EXPECT_EQ(sweep.facts.at("runs_failed"), "0");
  EXPECT_EQ(sweep.facts.at("runs_stopped"), "3");
  EXPECT_EQ(sweep.facts.count("weibull_modulus"), 0u);
  EXPECT_FALSE(fs::exists(dir / "weibull.csv"));
  fs::remove_all(dir);
}

namespace {

/// Column `name` of a summary's header (its size when missing).
std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

/// A scratch folder for one test, removed at its end.
struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& name)
      : dir(fs::temp_directory_path() /
            ("cleave_sweep_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  fs::path write(const std::string& file, const std::string& text) const {
    std::ofstream(dir / file) << text;
    return dir / file;
  }
};

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

// The coarse DCB judged by beam theory with its cohesive zone against LEFM's stage I within 5 %:
// Hillerborg's length E G_c / sigma_c^2 is 6.4 mm (six arm thicknesses) at 70 MPa, far from a
// sharp crack (fails), and 0.40 mm at 280 MPa (passes; tests/test_validation.cpp). A sweep over
// `validate` gives one row per run with that verdict and the errors it is judged by.
TEST(SweepCommand, OverValidateEachRowCarriesItsVerdictAndTheErrorsJudged) {
  const Scratch s("validate");
  std::string text =
      read_text(std::string(CLEAVE_SOURCE_DIR) + "/scenarios/validation/dcb_coarse.toml");
  text = text.substr(0, text.find("[validation]")) + "[validation]\nstage1 = { max = 0.05 }\n";
  const fs::path file = s.write("dcb.toml", text);
  const fs::path out = s.dir / "out";
  const Outcome o = run_cleave("sweep -q " + file.string() +
                               " --command validate --cohesive-beam-only --jobs 2"
                               " --set material.cohesive_strength=70e6,280e6 -o " +
                               out.string());
  ASSERT_EQ(o.code, 0) << o.output;  // a fail verdict is a result, not a failed run
  const auto rows = cleave::testing::read_csv_cells(out / "summary.csv");
  ASSERT_EQ(rows.size(), 3u);  // header + 2 runs
  const auto& h = rows[0];
  for (const char* c : {"material.cohesive_strength", "status", "verdict", "stage1_max_error",
                        "stage1_mean_error", "peak_error"})
    ASSERT_LT(column(h, c), h.size()) << c;
  EXPECT_EQ(rows[1][column(h, "material.cohesive_strength")], "70e6");
  EXPECT_EQ(rows[1][column(h, "status")], "finished");
  EXPECT_EQ(rows[1][column(h, "verdict")], "fail");
  EXPECT_GT(std::stod(rows[1][column(h, "stage1_max_error")]), 0.05);
  EXPECT_EQ(rows[2][column(h, "verdict")], "pass");
  EXPECT_LT(std::stod(rows[2][column(h, "stage1_max_error")]), 0.02);
  const Manifest m = read_manifest(out);
  EXPECT_EQ(m.status, "finished");
  EXPECT_EQ(m.facts.at("command"), "validate");
  EXPECT_EQ(m.facts.at("validations_failed"), "1");
  // Each child was a validation: its own folder says so.
  EXPECT_EQ(read_manifest(out / "run_001").provenance.at("command"), "validate");
}

// bond.tbn set as a multiple of the cleavage criterion's strength: each run's bond.tbn is the
// ratio times fracture.sigma_f as the scenario file writes it (read here from its text), and
// summary.csv has the ratio and the absolute value side by side.
TEST(SweepCommand, ARatioKeyIsTheRatioTimesTheReferenceInTheScenarioFile) {
  const Scratch s("ratio");
  std::string text = read_text(std::string(CLEAVE_SOURCE_DIR) + "/tests/data/sweep_brazilian.toml");
  const auto fracture = text.find("[fracture]");
  const auto end = text.find("[split]");
  ASSERT_NE(fracture, std::string::npos);
  text.replace(fracture, end - fracture,
               "[fracture]\ncriterion = \"rankine\"\nsigma_f = 2.5e3\ncheck_every = 10\n\n");
  const fs::path file = s.write("rankine.toml", text);
  // The strength as written, read from the text (not from cleave).
  const auto at = text.find("sigma_f = ");
  const double sigma_f = std::stod(text.substr(at + 10, text.find('\n', at) - at - 10));
  const fs::path out = s.dir / "out";
  const Outcome o = run_cleave("sweep -q " + file.string() +
                               " --set bond.tbn/fracture.sigma_f=0.1,10 --set bond.tbs=800,1200"
                               " --max-steps 2 --jobs 2 -o " +
                               out.string());
  ASSERT_EQ(o.code, 0) << o.output;
  const auto rows = cleave::testing::read_csv_cells(out / "summary.csv");
  ASSERT_EQ(rows.size(), 5u);  // a product: 2 x 2 runs
  const auto& h = rows[0];
  const std::size_t ratio = column(h, "bond.tbn/fracture.sigma_f"), tbn = column(h, "bond.tbn");
  ASSERT_LT(ratio, h.size());
  ASSERT_LT(tbn, h.size());
  EXPECT_EQ(tbn, ratio + 1);
  const double ratios[] = {0.1, 0.1, 10, 10};
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_DOUBLE_EQ(std::stod(rows[r][ratio]), ratios[r - 1]);
    EXPECT_NEAR(std::stod(rows[r][tbn]), ratios[r - 1] * sigma_f, 1e-12 * sigma_f);
    const toml::table run = toml::parse_file((out / "scenarios" / (rows[r][0] + ".toml")).string());
    EXPECT_NEAR(*run["bond"]["tbn"].value<double>(), ratios[r - 1] * sigma_f, 1e-12 * sigma_f);
  }
  EXPECT_EQ(read_manifest(out).facts.at("set.bond.tbn/fracture.sigma_f"), "0.1,10");
  // A reference the file does not write, or one that is no number: usage errors naming the
  // key and the file (and its line), before any run.
  const fs::path bad = s.dir / "bad";
  const Outcome missing = run_cleave("sweep -q " + file.string() +
                                     " --set bond.tbn/fracture.k_ic=1 -o " + bad.string());
  EXPECT_EQ(missing.code, 2) << missing.output;
  EXPECT_NE(missing.output.find("fracture.k_ic is not in " + file.string()), std::string::npos)
      << missing.output;
  const int name_line =
      1 + static_cast<int>(std::count(text.begin(), text.begin() + text.find("name = "), '\n'));
  const Outcome text_ref = run_cleave("sweep -q " + file.string() +
                                      " --set bond.tbn/scenario.name=1 -o " + bad.string());
  EXPECT_EQ(text_ref.code, 2) << text_ref.output;
  EXPECT_NE(
      text_ref.output.find("scenario.name at " + file.string() + ":" + std::to_string(name_line)),
      std::string::npos)
      << text_ref.output;
  EXPECT_FALSE(fs::exists(bad / "run_001"));
}

// --seeds 3 with two values of a key: 2 x 3 runs, the seed the fastest; --zip of two 2-value
// keys with --seeds 3: 2 x 3 runs, not 2 x 2 x 3. summary_mean.csv: a row per combination, its
// mean and sample standard deviation of each numeric result, here checked against the rows
// of summary.csv.
TEST(SweepCommand, SeedsAreAReplicateAxisWithMeansPerCombination) {
  const Scratch s("seeds");
  const fs::path file =
      s.write("drop.toml", cleave::testing::drop_scenario("drop", "duration = 3e-5\nframes = 1\n"));
  const fs::path out = s.dir / "out";
  const Outcome o = run_cleave("sweep -q " + file.string() +
                               " --set grain.r_bar=0.8,0.9 --seeds 3 --column dynamics_steps"
                               " --jobs 2 -o " +
                               out.string());
  ASSERT_EQ(o.code, 0) << o.output;
  const auto rows = cleave::testing::read_csv_cells(out / "summary.csv");
  ASSERT_EQ(rows.size(), 7u);
  const auto& h = rows[0];
  const std::size_t rbar = column(h, "grain.r_bar"), seed = column(h, "orientation.seed"),
                    wall = column(h, "wall_s");
  ASSERT_LT(seed, h.size());
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_EQ(rows[r][rbar], r <= 3 ? "0.8" : "0.9");
    EXPECT_EQ(rows[r][seed], std::to_string((r - 1) % 3 + 1));
    // --column: a fact of each run's run.toml; the drop lasts 3e-5 s of 1.2e-6 s steps.
    EXPECT_EQ(rows[r][column(h, "dynamics_steps")], "25");
    const toml::table run = toml::parse_file((out / "scenarios" / (rows[r][0] + ".toml")).string());
    EXPECT_EQ(run["orientation"]["seed"].value<std::int64_t>(), (r - 1) % 3 + 1);
  }
  const auto means = cleave::testing::read_csv_cells(out / "summary_mean.csv");
  ASSERT_EQ(means.size(), 3u);  // header + 2 combinations
  const auto& mh = means[0];
  EXPECT_EQ(column(mh, "orientation.seed"), mh.size());
  ASSERT_LT(column(mh, "wall_s_mean"), mh.size());
  for (std::size_t g = 1; g < means.size(); ++g) {
    EXPECT_EQ(means[g][column(mh, "grain.r_bar")], g == 1 ? "0.8" : "0.9");
    EXPECT_EQ(means[g][column(mh, "runs")], "3");
    EXPECT_EQ(means[g][column(mh, "wall_s_n")], "3");
    double x[3], mean = 0.0, squares = 0.0;
    for (int i = 0; i < 3; ++i) mean += (x[i] = std::stod(rows[3 * (g - 1) + i + 1][wall])) / 3.0;
    for (double v : x) squares += (v - mean) * (v - mean);
    EXPECT_NEAR(std::stod(means[g][column(mh, "wall_s_mean")]), mean, 1e-6);
    EXPECT_NEAR(std::stod(means[g][column(mh, "wall_s_sd")]), std::sqrt(squares / 2.0), 1e-6);
    EXPECT_EQ(means[g][column(mh, "dynamics_steps_mean")], "25");
    EXPECT_EQ(means[g][column(mh, "dynamics_steps_sd")], "0");
  }
  EXPECT_EQ(read_manifest(out).facts.at("seeds"), "3");
  // Zipped keys are one factor: 2 x 3 runs.
  const fs::path zip = s.dir / "zip";
  const Outcome z = run_cleave("sweep -q " + file.string() +
                               " --zip grain.r_bar=0.85,0.9 --zip grain.t_bar=0.9,0.85 --seeds 3"
                               " --jobs 2 -o " +
                               zip.string());
  ASSERT_EQ(z.code, 0) << z.output;
  EXPECT_EQ(cleave::testing::read_csv_cells(zip / "summary.csv").size(), 7u);
  EXPECT_EQ(cleave::testing::read_csv_cells(zip / "summary_mean.csv").size(), 3u);
}

// A sweep over `cleave measure brazilian`: the column named with its unit holds the splitting
// tensile strength 2 P / (pi D t) of the row's peak load and the disc's diameter and thickness
// (6 mm and 5 mm in the file), and summary_mean.csv the mean of the two seeds' strengths.
TEST(SweepCommand, OverMeasureTheColumnIsTheBrazilianStrengthOfThePeakLoad) {
  const Scratch s("measure");
  const fs::path out = s.dir / "out";
  const Outcome o = run_cleave("sweep -q " + std::string(CLEAVE_SOURCE_DIR) +
                               "/tests/data/sweep_brazilian.toml --command measure --test brazilian"
                               " --seeds 2 --jobs 2 -o " +
                               out.string());
  ASSERT_EQ(o.code, 0) << o.output;
  const auto rows = cleave::testing::read_csv_cells(out / "summary.csv");
  ASSERT_EQ(rows.size(), 3u);
  const auto& h = rows[0];
  const std::size_t sigma = column(h, "tensile_strength_Pa"), peak = column(h, "peak_load_N");
  ASSERT_LT(sigma, h.size());
  ASSERT_LT(peak, h.size());
  const double pi = std::acos(-1.0);
  double mean = 0.0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_EQ(rows[r][column(h, "status")], "finished");
    const double expected = 2.0 * std::stod(rows[r][peak]) / (pi * 6e-3 * 5e-3);
    EXPECT_NEAR(std::stod(rows[r][sigma]), expected, 1e-6 * expected);
    mean += std::stod(rows[r][sigma]) / 2.0;
  }
  const auto means = cleave::testing::read_csv_cells(out / "summary_mean.csv");
  ASSERT_EQ(means.size(), 2u);  // no other key: one combination
  EXPECT_NEAR(std::stod(means[1][column(means[0], "tensile_strength_Pa_mean")]), mean, 1e-6 * mean);
  EXPECT_EQ(means[1][column(means[0], "tensile_strength_Pa_n")], "2");
  EXPECT_TRUE(fs::exists(out / "run_001" / "measure.toml"));  // each child a measurement
}

TEST(SweepCommand, OptionsThatDoNotFitTheCommandAreUsageErrors) {
  const Scratch s("usage");
  const std::string base = "sweep -q " + std::string(CLEAVE_SOURCE_DIR) +
                           "/tests/data/sweep_brazilian.toml -o " + (s.dir / "out").string() +
                           " --set bond.tbn=1000,2000 ";
  const std::pair<std::string, std::string> cases[] = {
      {"--command bogus", "--command"},
      {"--command measure", "--test"},
      {"--command measure --test nonsense", "--test nonsense"},
      {"--test brazilian", "--test brazilian is for --command measure"},
      {"--command measure --test brazilian --max-steps 5", "--max-steps"},
      {"--cohesive-beam-only", "--cohesive-beam-only"},
      {"--seed-key specimen.seed", "--seed-key"},
      {"--seeds 0", "--seeds"},
      {"--seeds 2 --set orientation.seed=1,2", "orientation.seed is given twice"},
  };
  for (const auto& [args, says] : cases) {
    const Outcome o = run_cleave(base + args);
    EXPECT_EQ(o.code, 2) << args << ": " << o.output;
    EXPECT_NE(o.output.find(says), std::string::npos) << args << ": " << o.output;
  }
  EXPECT_FALSE(fs::exists(s.dir / "out"));
}
