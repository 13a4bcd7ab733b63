// The coarse fracture validations of scenarios/validation/ as CI runs them (issue: DCB, ENF and
// MMB of Chen et al. 2020, sec. 7), through `cleave validate` as a user runs them. The test
// reads the written curves and checks them against the corrected beam theory it computes
// itself (eqs 57-58, 59 and 63), not against the numbers the command printed.
#include <gtest/gtest.h>

#include "cli_helpers.hpp"
#include "io/toml_reader.hpp"
#include "io/validation_scenario.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using Outcome = cleave::testing::CliOutcome;
using cleave::testing::run_cleave;

/// Rows of a CSV file with a header line, as numbers (non-numbers read as NaN).
std::vector<std::vector<double>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) {
      try {
        row.push_back(std::stod(cell));
      } catch (...) {
        row.push_back(std::nan(""));
      }
    }
    rows.push_back(row);
  }
  return rows;
}

constexpr double kE = 120e9, kNu = 0.2;

/// Eqs 57-58: the mode-I crack length correction chi_I.
double chi_I() {
  const double G = kE / (2 * (1 + kNu));
  const double gamma = 1.18 * kE / G;
  const double g = gamma / (1 + gamma);
  return std::sqrt(kE / (11 * G) * (3 - 2 * g * g));
}

struct ValidationRun {
  fs::path dir;
  Outcome outcome;
  std::vector<std::vector<double>> measured;  // step, time, delta_mm, load_N, ...
};

ValidationRun validate(const std::string& name) {
  ValidationRun r;
  r.dir = fs::temp_directory_path() / ("cleave_validation_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(r.dir);
  r.outcome = run_cleave("validate " + std::string(CLEAVE_SOURCE_DIR) + "/scenarios/validation/" +
                         name + ".toml -q -o " + r.dir.string());
  r.measured = read_csv(r.dir / "measured.csv");
  return r;
}

/// Mean relative error of the measured load against `expected(delta)` over [from, to] (mm).
template <class F>
double mean_error(const ValidationRun& r, double from, double to, F expected) {
  double sum = 0;
  int n = 0;
  for (const auto& row : r.measured) {
    if (row.size() < 4 || row[2] < from || row[2] > to) continue;
    const double p = expected(row[2]);
    sum += std::abs(row[3] - p) / p;
    ++n;
  }
  EXPECT_GT(n, 20) << "too few points in [" << from << ", " << to << "] mm";
  return n > 0 ? sum / n : 1.0;
}

/// The largest measured load up to `until` (mm of Delta).
double peak_load(const ValidationRun& r, double until) {
  double peak = 0;
  for (const auto& row : r.measured)
    if (row.size() >= 4 && row[2] <= until) peak = std::max(peak, row[3]);
  return peak;
}

/// Checks the cohesive_beam.csv of a validation run: it starts on the closed form's stage-I
/// line (slope in N/mm, within 2e-3) and, softening before LEFM's peak deflection d_peak (mm),
/// stays below it. Returns the rows of its errors_cohesive_beam.csv.
std::vector<std::vector<double>> expect_cohesive_beam_below_stage_i(const fs::path& dir,
                                                                    double slope, double d_peak) {
  const auto czm = read_csv(dir / "cohesive_beam.csv");  // delta_mm, load_N, crack, zone
  EXPECT_GT(czm.size(), 100u);
  if (czm.size() > 5) {
    EXPECT_NEAR(czm[5][1] / (slope * czm[5][0]), 1.0, 2e-3);
  }
  for (const auto& row : czm) {
    if (row[0] > 0.0 && row[0] < d_peak) {
      EXPECT_LE(row[1], slope * row[0] * (1 + 1e-9)) << "Delta = " << row[0] << " mm";
    }
  }
  return read_csv(dir / "errors_cohesive_beam.csv");
}

/// The largest load of the cohesive_beam.csv of a validation run up to `until` (mm of Delta).
double cohesive_peak(const fs::path& dir, double until) {
  double peak = 0;
  for (const auto& row : read_csv(dir / "cohesive_beam.csv"))
    if (row.size() >= 2 && row[0] <= until) peak = std::max(peak, row[1]);
  return peak;
}

/// A coarse strip's peak over its cohesive beam's (the crack front's width law). Beam theory
/// puts the front at B - 2r (text after eq. 49); the lattice's tiled links across the plane
/// (area1 : area2 = 9 : 8, one first and four second neighbours per body) lose only a side
/// body's outward second neighbour, 8/41 of its 2r, at each side. The load at which a crack
/// grows goes as the square root of the front's width (eq. 60: P a = sqrt(B' E I G_c)).
double front_width_ratio(double B, double r) {
  return std::sqrt((B - 2.0 * (8.0 / 41.0) * 2.0 * r) / (B - 2.0 * r));
}

/// Eqs 59-60 for the coarse DCB strip (B = 0.5 mm, h = 1 mm, r = 0.125 mm, a0 = 9 mm,
/// G_Ic = 0.26 N/mm): stage I's slope (N per mm of Delta), the peak P a_eff = sqrt(B' E I G_Ic)
/// with B' = B - 2r, and the peak's deflection (mm).
struct CoarseDcbLefm {
  double slope, p_peak, d_peak;
};
CoarseDcbLefm coarse_dcb_lefm() {
  const double B = 0.5e-3, h = 1e-3, r = 0.125e-3, a = 9e-3 + chi_I() * h;
  const double EI = kE * B * h * h * h / 12;
  const double slope = 3 * EI / (2 * a * a * a) * 1e-3;
  const double p_peak = std::sqrt((B - 2 * r) * EI * 260.0) / a;
  return {slope, p_peak, p_peak / slope};
}

/// The text of the shipped coarse DCB scenario (a missing file is an error, not "").
std::string shipped_dcb_coarse() {
  return cleave::io::toml_reader::read_scenario_text(std::string(CLEAVE_SOURCE_DIR) +
                                                     "/scenarios/validation/dcb_coarse.toml");
}

}  // namespace

// Coarse DCB: a 0.5 mm strip of the paper's beam (2h = 2 mm, a0 = 9 mm, r = 0.125 mm).
TEST(CoarseValidation, DcbStageIFollowsCorrectedBeamTheoryAndPeaksAtTheLefmLoad) {
  const ValidationRun r = validate("dcb_coarse");
  ASSERT_EQ(r.outcome.code, 0) << r.outcome.output;
  const auto [slope, p_peak, d_peak] = coarse_dcb_lefm();
  // Stated bounds: stage I mean within 8%, peak within 22% (measured: 4.3%, +19.7%; the peak
  // is high because B - 2r halves this 2-cube strip: see dcb_coarse.toml).
  EXPECT_LT(mean_error(r, 0.1 * d_peak, 0.9 * d_peak, [s = slope](double d) { return s * d; }), 0.08);
  EXPECT_NEAR(peak_load(r, 2 * d_peak) / p_peak, 1.0, 0.22);
  // What a user opens: the curves, the errors, the plot and the provenance.
  for (const char* f : {"analytic.csv", "errors.csv", "load_deflection.svg", "run.toml",
                        "scenario_as_run.toml", "cohesive_beam.csv", "errors_cohesive_beam.csv"})
    EXPECT_TRUE(fs::exists(r.dir / f)) << f;
  // Beam theory with the cohesive zone starts on eq. 59 (up to Winkler's 3/2 (chi_I h)^3 term,
  // 1e-4 here) and, softening before LEFM's peak, stays below it.
  const auto zerr = expect_cohesive_beam_below_stage_i(r.dir, slope, d_peak);
  ASSERT_EQ(zerr.size(), 2u);  // stage 1 and the peak
  EXPECT_GT(zerr[0][3], 10);   // points compared
  // The strip cracks at its own front's width: 1.27 times the cohesive beam's peak (measured
  // 1.29; the full beams, 8 cubes across, 1.03).
  EXPECT_NEAR(peak_load(r, 2 * d_peak) / cohesive_peak(r.dir, 2 * d_peak) / front_width_ratio(0.5e-3, 0.125e-3),
              1.0, 0.04);
  fs::remove_all(r.dir);
}

// The coarse DCB with sigma_c doubled (Hillerborg's length 1.6 mm instead of 6.4): the LEFM
// regime, where stage I follows eq. 59 closer (mean within 4 %; the paper's material: 4.3 %,
// within 8 %), judged by the command against LEFM.
TEST(CoarseValidation, DcbLefmRegimeStageIFollowsEq59Closer) {
  const ValidationRun r = validate("dcb_lefm_coarse");
  ASSERT_EQ(r.outcome.code, 0) << r.outcome.output;
  const auto [slope, p_peak, d_peak] = coarse_dcb_lefm();
  (void)p_peak;
  EXPECT_LT(mean_error(r, 0.1 * d_peak, 0.9 * d_peak, [s = slope](double d) { return s * d; }), 0.04);
  const auto errors = read_csv(r.dir / "errors.csv");
  ASSERT_GE(errors.size(), 1u);
  EXPECT_LT(errors[0][4], 0.04);  // the command's own stage-I mean, against LEFM
  fs::remove_all(r.dir);
}

// Coarse ENF: three-point bending of the cracked strip, 2L = 30.25 mm.
TEST(CoarseValidation, EnfStageIFollowsCorrectedBeamTheory) {
  const ValidationRun r = validate("enf_coarse");
  ASSERT_EQ(r.outcome.code, 0) << r.outcome.output;
  const double B = 0.5e-3, h = 1e-3, r_ = 0.125e-3, L = 15.0e-3;  // support to mid-span line
  const double a = 9e-3 + 0.42 * chi_I() * h;                      // chi_II = 0.42 chi_I
  const double EI = kE * B * h * h * h / 12;
  const double slope = 96 * EI / (2 * L * L * L + 3 * a * a * a) * 1e-3;  // eq. 63
  const double p_peak = std::sqrt(64 * (B - 2 * r_) * EI * 1002.0 / 3) / a;
  const double d_peak = p_peak / slope;
  // Stated bounds: stage I mean within 8%, peak within 10% (measured: 4.4%, 2.3%).
  EXPECT_LT(mean_error(r, 0.1 * d_peak, 0.9 * d_peak, [s = slope](double d) { return s * d; }), 0.08);
  EXPECT_NEAR(peak_load(r, 2 * d_peak) / p_peak, 1.0, 0.10);
  fs::remove_all(r.dir);
}

// Coarse MMB at beta = 50 %: the command's verdict and its error table (stage I mean within
// 15%, peak within 10%; measured 9.7% and 6.1%: the mixed-mode cohesive zone grows early), and
// the cohesive beam it writes.
TEST(CoarseValidation, Mmb50PassesItsStatedBounds) {
  const ValidationRun r = validate("mmb_50_coarse");
  EXPECT_EQ(r.outcome.code, 0) << r.outcome.output;
  const auto errors = read_csv(r.dir / "errors.csv");
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_LT(errors[0][4], 0.15);  // stage I mean error
  EXPECT_LT(errors[1][4], 0.10);  // peak
  // Beam theory with the mixed-mode cohesive zone starts on eq. 68's line (stage I of
  // analytic.csv: through the origin) and, softening before LEFM's peak, stays below it; the
  // lattice's stage I is closer to it than to LEFM (measured: 2.5 % against 9.7 % mean).
  const auto analytic = read_csv(r.dir / "analytic.csv");  // stage, delta_mm, load_N, crack_mm
  double slope = 0.0, d_peak = 0.0;
  for (const auto& row : analytic)
    if (row[0] == 1 && row[1] > d_peak) d_peak = row[1], slope = row[2] / row[1];
  ASSERT_GT(slope, 0.0);
  const auto zerr = expect_cohesive_beam_below_stage_i(r.dir, slope, d_peak);
  ASSERT_EQ(zerr.size(), 2u);  // stage 1 and the peak
  EXPECT_LT(zerr[0][4], 0.5 * errors[0][4]);
  // The strip cracks at its own front's width (see the coarse DCB; measured 1.269).
  EXPECT_NEAR(peak_load(r, 2 * d_peak) / cohesive_peak(r.dir, 2 * d_peak) /
                  front_width_ratio(0.5e-3, 0.125e-3),
              1.0, 0.04);
  fs::remove_all(r.dir);
}

TEST(CoarseValidation, BadScenarioNamesFileLineAndKeyAndWritesNoResult) {
  const fs::path dir = fs::temp_directory_path() / ("cleave_validation_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string s = shipped_dcb_coarse();
  const auto pos = s.find("velocity = 0.3");
  ASSERT_NE(pos, std::string::npos);
  s.replace(pos, 14, "velocity = -0.3");
  const int line = 1 + static_cast<int>(std::count(s.begin(), s.begin() + pos, '\n'));
  const fs::path file = dir / "bad.toml";
  std::ofstream(file) << s;
  const Outcome o = run_cleave("validate " + file.string() + " -o " + (dir / "out").string());
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("bad.toml:" + std::to_string(line)), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("velocity"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "measured.csv"));
  fs::remove_all(dir);
}

TEST(ValidationScenarioAsRun, EveryShippedScenarioReadsBackEqual) {
  int checked = 0;
  for (const auto& entry :
       fs::directory_iterator(std::string(CLEAVE_SOURCE_DIR) + "/scenarios/validation")) {
    if (entry.path().extension() != ".toml") continue;
    const cleave::io::ValidationScenario a = cleave::io::load_validation_scenario(entry.path());
    const std::string text = cleave::io::validation_scenario_as_run(a);
    const cleave::io::ValidationScenario b =
        cleave::io::parse_validation_scenario(text, "as_run.toml");
    SCOPED_TRACE(entry.path().string());
    const auto& ra = a.rig;
    const auto& rb = b.rig;
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.description, b.description);
    EXPECT_EQ(ra.kind, rb.kind);
    // Bit for bit: lengths were converted to metres once, and are written that way.
    for (auto [x, y] : {std::pair{ra.length, rb.length}, {ra.breadth, rb.breadth},
                        {ra.height, rb.height}, {ra.initial_crack, rb.initial_crack},
                        {ra.radius, rb.radius}, {ra.mode_mix, rb.mode_mix},
                        {ra.link_bending, rb.link_bending}, {ra.intact_length, rb.intact_length},
                        {ra.material.young, rb.material.young},
                        {ra.material.poisson, rb.material.poisson},
                        {ra.material.density, rb.material.density},
                        {ra.material.sigma_c, rb.material.sigma_c}, {ra.material.g_c, rb.material.g_c},
                        {ra.material.kappa, rb.material.kappa},
                        {ra.material.friction, rb.material.friction}, {ra.g_Ic, rb.g_Ic},
                        {ra.g_IIc, rb.g_IIc}, {ra.velocity, rb.velocity},
                        {ra.ramp_time, rb.ramp_time}, {ra.global_damping, rb.global_damping},
                        {ra.dt_safety, rb.dt_safety}, {a.deflection, b.deflection},
                        {a.peak_tolerance, b.peak_tolerance},
                        {a.margin, b.margin}})
      EXPECT_EQ(x, y);
    EXPECT_EQ(a.threads, b.threads);
    EXPECT_EQ(a.records, b.records);
    EXPECT_EQ(a.checks, b.checks);
    EXPECT_FALSE(a.checks.empty());
    EXPECT_EQ(a.reference, b.reference);
    EXPECT_EQ(ra.tiled_areas, rb.tiled_areas);
    EXPECT_EQ(ra.material.initiation, rb.material.initiation);
    EXPECT_EQ(ra.material.compression, rb.material.compression);
    ++checked;
  }
  EXPECT_GE(checked, 9);
}

TEST(ValidationScenario, EffectiveAreasAreTiledUnlessThePapersAreAskedFor) {
  const std::string dcb = shipped_dcb_coarse();
  EXPECT_TRUE(cleave::io::parse_validation_scenario(dcb, "dcb.toml").rig.tiled_areas);
  const auto with_key = [&](const std::string& value) {
    std::string s = dcb;
    const auto pos = s.find("[material]");
    s.insert(pos, "effective_areas = " + value + "\n\n");
    return s;
  };
  const auto paper = cleave::io::parse_validation_scenario(with_key("\"paper\""), "dcb.toml");
  EXPECT_FALSE(paper.rig.tiled_areas);
  // The as-run copy keeps the choice.
  EXPECT_FALSE(cleave::io::parse_validation_scenario(cleave::io::validation_scenario_as_run(paper), "as_run.toml")
                   .rig.tiled_areas);
  try {
    (void)cleave::io::parse_validation_scenario(with_key("\"square\""), "dcb.toml");
    FAIL() << "an unknown effective_areas was accepted";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("dcb.toml:"), std::string::npos) << what;
    EXPECT_NE(what.find("effective_areas"), std::string::npos) << what;
    EXPECT_NE(what.find("tiled"), std::string::npos) << what;
  }
}

TEST(ValidationScenario, CompressionIsThePlanesClosingUnlessThePapersLinkReadingIsAskedFor) {
  const std::string dcb = shipped_dcb_coarse();
  EXPECT_EQ(cleave::io::parse_validation_scenario(dcb, "dcb.toml").rig.material.compression,
            cleave::physics::Compression::plane);
  const auto with_key = [&](const std::string& value) {
    std::string s = dcb;
    const auto pos = s.find("young =");
    s.insert(pos, "compression = " + value + "\n");
    return s;
  };
  const auto link = cleave::io::parse_validation_scenario(with_key("\"link\""), "dcb.toml");
  EXPECT_EQ(link.rig.material.compression, cleave::physics::Compression::link);
  EXPECT_EQ(cleave::io::parse_validation_scenario(cleave::io::validation_scenario_as_run(link),
                                                  "as_run.toml")
                .rig.material.compression,
            cleave::physics::Compression::link);
  try {
    (void)cleave::io::parse_validation_scenario(with_key("\"both\""), "dcb.toml");
    FAIL() << "an unknown compression was accepted";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("dcb.toml:"), std::string::npos) << what;
    EXPECT_NE(what.find("compression"), std::string::npos) << what;
  }
}

TEST(ValidationScenario, IntactLengthIsForTheDcbInWholeCellsAndRunsAsWritten) {
  // The shipped coarse DCB with its intact_length (and the comment under it) taken out.
  std::string dcb = shipped_dcb_coarse();
  const auto from = dcb.find("intact_length"), to = dcb.find("bending_springs");
  ASSERT_NE(from, std::string::npos);
  ASSERT_LT(from, to);
  dcb.erase(from, to - from);
  const auto with_key = [&](const std::string& text, const std::string& line) {
    std::string s = text;
    s.insert(s.find("[material]"), line + "\n\n");
    return s;
  };
  EXPECT_EQ(cleave::io::parse_validation_scenario(dcb, "dcb.toml").rig.intact_length, 0.0);
  const auto v = cleave::io::parse_validation_scenario(with_key(dcb, "intact_length = 3.0"), "dcb.toml");
  EXPECT_DOUBLE_EQ(v.rig.intact_length, 3e-3);
  EXPECT_EQ(cleave::io::parse_validation_scenario(cleave::io::validation_scenario_as_run(v), "as_run.toml")
                .rig.intact_length,
            v.rig.intact_length);
  const auto rejects = [&](const std::string& text, const std::string& file, const std::string& words) {
    try {
      (void)cleave::io::parse_validation_scenario(text, file);
      ADD_FAILURE() << "accepted: " << words;
    } catch (const std::exception& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file + ":"), std::string::npos) << what;
      EXPECT_NE(what.find("intact_length"), std::string::npos) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
    }
  };
  rejects(with_key(dcb, "intact_length = 3.1"), "dcb.toml", "whole number");
  rejects(with_key(dcb, "intact_length = -1.0"), "dcb.toml", "intact_length");
  const std::string enf = cleave::io::toml_reader::read_scenario_text(
      std::string(CLEAVE_SOURCE_DIR) + "/scenarios/validation/enf_coarse.toml");
  rejects(with_key(enf, "intact_length = 3.0"), "enf.toml", "only a DCB");
}

namespace {

/// The shipped coarse DCB with its [validation] table replaced by `table` (which starts with
/// the header), and the line the table's first key is on.
std::pair<std::string, int> dcb_with_validation(const std::string& table) {
  std::string s = shipped_dcb_coarse();
  const auto at = s.find("[validation]");
  s = s.substr(0, at) + table;
  return {s, 2 + static_cast<int>(std::count(s.begin(), s.begin() + at, '\n'))};
}

}  // namespace

TEST(ValidationScenario, StageTablesGiveEachStageItsOwnBoundsAndTheReference) {
  const auto [text, line] = dcb_with_validation(
      "[validation]\nreference = \"cohesive_beam\"\nstage1 = { max = 0.05 }\n"
      "stage2 = { mean = 0.05, max = 0.08 }\nstage3 = { slope = 0.04 }\npeak_tolerance = 0.05\n");
  const auto v = cleave::io::parse_validation_scenario(text, "dcb.toml");
  EXPECT_EQ(v.reference, cleave::io::Reference::cohesive_beam);
  ASSERT_EQ(v.checks.size(), 3u);
  EXPECT_EQ(v.checks[0], (cleave::io::StageCheck{1, 0.0, 0.05, 0.0}));
  EXPECT_EQ(v.checks[1], (cleave::io::StageCheck{2, 0.05, 0.08, 0.0}));
  EXPECT_EQ(v.checks[2], (cleave::io::StageCheck{3, 0.0, 0.0, 0.04}));
  // The short form: one tolerance, on the loads' largest (or mean) error and on the split
  // beam's slope; the reference defaults to LEFM.
  const auto [short_form, l2] = dcb_with_validation(
      "[validation]\nstages = [1, 3]\ntolerance = 0.07\nmeasure = \"mean\"\n");
  const auto w = cleave::io::parse_validation_scenario(short_form, "dcb.toml");
  EXPECT_EQ(w.reference, cleave::io::Reference::lefm);
  ASSERT_EQ(w.checks.size(), 2u);
  EXPECT_EQ(w.checks[0], (cleave::io::StageCheck{1, 0.07, 0.0, 0.0}));
  EXPECT_EQ(w.checks[1], (cleave::io::StageCheck{3, 0.0, 0.0, 0.07}));
}

TEST(ValidationScenario, BadStageBoundsNameFileLineAndKey) {
  const auto rejects = [](const std::string& table, const std::string& key, const std::string& words,
                          int line_offset) {
    const auto [text, line] = dcb_with_validation(table);
    try {
      (void)cleave::io::parse_validation_scenario(text, "dcb.toml");
      ADD_FAILURE() << "accepted:\n" << table;
    } catch (const std::exception& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("dcb.toml:" + std::to_string(line + line_offset)), std::string::npos)
          << what;
      EXPECT_NE(what.find(key), std::string::npos) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
    }
  };
  rejects("[validation]\nstage1 = { max = 0.05, median = 0.1 }\n", "validation.stage1.median",
          "median", 0);
  rejects("[validation]\nstage1 = { slope = 0.05 }\n", "validation.stage1.slope", "split beam",
          0);
  rejects("[validation]\nstage4 = { max = 0.05 }\n", "validation.stage4", "stages 1-3", 0);
  rejects("[validation]\nstage1 = { max = -0.05 }\n", "validation.stage1.max", "max", 0);
  rejects("[validation]\nstage1 = {}\n", "validation.stage1", "bounds nothing", 0);
  rejects("[validation]\nstage1 = 0.05\n", "validation.stage1", "table of bounds", 0);
  rejects("[validation]\nstages = [1]\ntolerance = 0.05\nstage2 = { max = 0.05 }\n",
          "validation.stage2", "not both", 2);
  rejects("[validation]\nstage1 = { max = 0.05 }\ntolerance = 0.05\n", "validation.tolerance",
          "short form", 1);
  rejects("[validation]\nreference = \"fem\"\nstage1 = { max = 0.05 }\n", "validation.reference",
          "cohesive_beam", 0);
  rejects("[validation]\npeak_tolerance = 0.05\n", "validation.stage1", "stages to check", -1);
}

// Beam theory with the cohesive zone tends to LEFM as sigma_c grows (Hillerborg's length
// E G_c / sigma_c^2 against the arm), and --cohesive-beam-only says so without a lattice run:
// with the paper's 70 MPa (length 6.4 mm, six arm thicknesses) stage I of the coarse DCB
// falls more than 5 % below eq. 59 before the peak; at 280 MPa (0.40 mm) it is within 2 %.
TEST(CohesiveBeamOnly, StageITendsToLefmAsTheCohesiveStrengthGrows) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleave_validation_czm_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<double> stage1_max;
  for (const char* strength : {"70e6", "280e6"}) {
    std::string s = shipped_dcb_coarse();
    const auto pos = s.find("cohesive_strength = 70e6");
    ASSERT_NE(pos, std::string::npos);
    s.replace(pos, 24, std::string("cohesive_strength = ") + strength);
    const auto at = s.find("[validation]");
    s = s.substr(0, at) + "[validation]\nstage1 = { max = 0.05 }\n";
    const fs::path file = dir / (std::string("dcb_") + strength + ".toml");
    std::ofstream(file) << s;
    const fs::path out = dir / strength;
    const Outcome o = run_cleave("validate " + file.string() + " --cohesive-beam-only -q -o " + out.string());
    EXPECT_EQ(o.code, std::string(strength) == "70e6" ? 1 : 0) << o.output;
    EXPECT_FALSE(fs::exists(out / "measured.csv")) << "the lattice ran";
    const auto errors = read_csv(out / "errors.csv");
    ASSERT_EQ(errors.size(), 2u);  // stage 1 and the peak
    stage1_max.push_back(errors[0][5]);
  }
  ASSERT_EQ(stage1_max.size(), 2u);
  EXPECT_GT(stage1_max[0], 0.05);
  EXPECT_LT(stage1_max[1], 0.02);
  fs::remove_all(dir);
}

// Validation files take values with units as scenario files do: the coarse DCB written with
// a unit on each dimensional key reads as the shipped one (bare lengths in mm, the rest SI);
// a unit of another dimension is an error at its key.
TEST(ValidationScenarioUnits, ValuesWithUnitsReadAsTheBareOnes) {
  const std::string bare = shipped_dcb_coarse();
  std::string with = bare;
  const auto set = [&](const std::string& from, const std::string& to) {
    ASSERT_NE(with.find(from), std::string::npos) << from;
    with.replace(with.find(from), from.size(), to);
  };
  set("length = 30.0", "length = \"30 mm\"");
  set("particle_radius = 0.125", "particle_radius = \"125 um\"");
  set("young = 120e9", "young = \"120 GPa\"");
  set("density = 2500.0", "density = \"2.5 g/cm^3\"");
  set("cohesive_strength = 70e6", "cohesive_strength = \"70 MPa\"");
  set("g_Ic = 260.0", "g_Ic = \"260 J/m^2\"");
  set("velocity = 0.3", "velocity = \"300 mm/s\"");
  set("ramp_time = 0.5e-3", "ramp_time = \"0.5 ms\"");
  const auto a = cleave::io::parse_validation_scenario(bare, "bare.toml");
  const auto b = cleave::io::parse_validation_scenario(with, "units.toml");
  EXPECT_EQ(a.rig.length, b.rig.length);
  EXPECT_DOUBLE_EQ(a.rig.radius,
                   b.rig.radius);  // 125 x 1e-6 and 0.125 x 1e-3: an ulp apart at most
  EXPECT_EQ(a.rig.material.young, b.rig.material.young);
  EXPECT_EQ(a.rig.material.density, b.rig.material.density);
  EXPECT_EQ(a.rig.material.sigma_c, b.rig.material.sigma_c);
  EXPECT_EQ(a.rig.g_Ic, b.rig.g_Ic);
  EXPECT_DOUBLE_EQ(a.rig.velocity, b.rig.velocity);
  EXPECT_EQ(a.rig.ramp_time, b.rig.ramp_time);
  std::string bad = bare;
  bad.replace(bad.find("young = 120e9"), 13, "young = \"120 mm\"");
  try {
    (void)cleave::io::parse_validation_scenario(bad, "bad.toml");
    ADD_FAILURE() << "a length was taken for Young's modulus";
  } catch (const cleave::io::ScenarioError& e) {
    EXPECT_EQ(e.key(), "material.young");
    EXPECT_GT(e.line(), 0);
    EXPECT_NE(std::string(e.what()).find("but this key is a stress (Pa)"), std::string::npos)
        << e.what();
  }
}
