// Parameter sweeps: --set parsing, the Cartesian product, keys written into the scenario, the
// Weibull fit against closed-form quantiles and against samples of a known distribution, and
// `cleave sweep` of a 4-seed Brazilian ensemble as a user runs it.
#include <gtest/gtest.h>

#include "cli_helpers.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

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
  for (const char* bad : {"bond.tbn", "=1", "bond.tbn=", "tbn=1", "bond.tbn=1,,2",
                          "orientation.seed=5..2", "orientation.seed=a..3", "stage[0].time=1",
                          "stage[x].time=1", "bond..tbn=1"}) {
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
  const std::vector<SweepAxis> axes = {parse_sweep_axis("bond.tbn=1,2"),
                                       parse_sweep_axis("orientation.seed=7,8"),
                                       parse_sweep_axis("stage[2].time=0.25,0.5"),
                                       parse_sweep_axis("output.mesh_format=obj,stl")};
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
      runs.emplace_back(d, s0 * std::pow(d / 4.0, -2.0 / m) * std::pow(-std::log(1.0 - u(rng)), 1.0 / m));
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
  EXPECT_NEAR(e.prefactor * std::pow(4.0, -e.exponent), e.groups.front().mean, 0.02 * e.groups.front().mean);
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
  const Outcome o = run_cleave("sweep " + scenario + " --set orientation.seed=1..4 --jobs 2 -o " +
                               dir.string());
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
  const fs::path dir = fs::temp_directory_path() / ("cleave_sweep_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string scenario = std::string(CLEAVE_SOURCE_DIR) + "/tests/data/sweep_brazilian.toml";
  const Outcome o =
      run_cleave("sweep " + scenario + " --set bond.nonsense=1,2 -o " + dir.string());
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
