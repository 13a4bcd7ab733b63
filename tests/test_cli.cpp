// Whole-scenario tests of the `cleave` executable: what a user runs and looks at.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

#include "cli_helpers.hpp"
#include "folder_test.hpp"
#include "io/exact_store.hpp"
#include "io/mesh_io.hpp"
#include "io/result_dir.hpp"

namespace fs = std::filesystem;

namespace {

using Outcome = cleave::testing::CliOutcome;
using cleave::testing::run_cleave;

class CleaveCli : public cleave::testing::FolderTest {};

const char* kSmallBox = R"(
[scenario]
name = "small"
[specimen]
shape = "box"
size = [6.0, 6.0, 2.0]
[grain]
r = 1.0
r_bar = 0.9
t = 1.0
[orientation]
seed = 3
)";

}  // namespace

TEST_F(CleaveCli, RunThenExactVolumeCheckPasses) {
  const fs::path scenario = write("small.toml", kSmallBox);
  const fs::path out = dir_ / "out";
  const Outcome run = run_cleave("run " + scenario.string() + " --out " + out.string());
  ASSERT_EQ(run.code, 0) << run.output;
  for (const char* f : {"run.toml", "geometry.exact", "specimen.csv", "fragments.csv",
                        "specimen.svg", "scenario.toml"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  EXPECT_EQ(cleave::io::read_manifest(out).status, "finished");
  // Grains in the CSV match the exact store, and every grain has 2 or 3 slabs.
  const auto store = cleave::io::read_exact_store(out / "geometry.exact");
  ASSERT_GT(store.grains.size(), 5u);
  EXPECT_GE(store.fragments.size(), 2 * store.grains.size());
  EXPECT_LE(store.fragments.size(), 3 * store.grains.size());

  const Outcome check = run_cleave("check volume " + out.string());
  EXPECT_EQ(check.code, 0) << check.output;
  EXPECT_NE(check.output.find("every grain's fragments sum exactly to its volume"), std::string::npos);
  EXPECT_EQ(check.output.find("NOT EQUAL"), std::string::npos);

  // The exported scene: one named, closed, outward mesh per fragment, holding its volume.
  const auto meshes = cleave::io::read_meshes(out / "meshes" / "fragments.obj");
  ASSERT_EQ(meshes.size(), store.fragments.size());
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const auto& f = store.fragments[i];
    EXPECT_EQ(meshes[i].name, f.lineage.name());
    EXPECT_TRUE(meshes[i].is_closed_and_consistently_oriented()) << meshes[i].name;
    EXPECT_EQ(meshes[i].vertices.size(), static_cast<std::size_t>(store.shapes[f.shape].num_vertices()));
    EXPECT_EQ(meshes[i].faces.size(), static_cast<std::size_t>(store.shapes[f.shape].num_faces()));
    const double exact = store.shapes[f.shape].volume().to_double();
    EXPECT_NEAR(meshes[i].signed_volume(), exact, 1e-4 * exact) << meshes[i].name;  // float32 files
  }
}

TEST_F(CleaveCli, CheckFailsWhenAFragmentIsSwappedForAnother) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run_cleave("run " + write("s.toml", kSmallBox).string() + " -q --out " + out.string()).code, 0);
  // Point the first fragment at the prism's shape (shape 0): its grain now has too much.
  std::string text = cleave::io::read_file(out / "geometry.exact");
  const auto at = text.find("\nfragment 0.0 shape ");
  ASSERT_NE(at, std::string::npos);
  const auto num = at + std::string("\nfragment 0.0 shape ").size();
  text.replace(num, text.find(' ', num) - num, "0");
  std::ofstream(out / "geometry.exact") << text;
  const Outcome check = run_cleave("check volume " + out.string());
  EXPECT_EQ(check.code, 1) << check.output;
  EXPECT_NE(check.output.find("NOT EQUAL"), std::string::npos);
  EXPECT_NE(check.output.find("1 grain(s) do NOT conserve volume"), std::string::npos);
}

TEST_F(CleaveCli, CheckFailsWhenAFragmentIsMovedOutOfItsGrain) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run_cleave("run " + write("s.toml", kSmallBox).string() + " -q --out " + out.string()).code, 0);
  // Shift fragment 0.0 by 1 mm in z: volumes still sum exactly, but it leaves its grain.
  auto store = cleave::io::read_exact_store(out / "geometry.exact");
  ASSERT_FALSE(store.fragments.empty());
  ASSERT_EQ(store.fragments[0].lineage.path_string(), "0.0");
  store.fragments[0].position.z() += 1e-3;
  cleave::io::write_exact_store(out / "geometry.exact", store);
  const Outcome check = run_cleave("check volume --summary " + out.string());
  EXPECT_EQ(check.code, 1) << check.output;
  EXPECT_NE(check.output.find("every grain's fragments sum exactly"), std::string::npos);
  EXPECT_NE(check.output.find("1 grain(s) have a fragment reaching outside the grain"),
            std::string::npos)
      << check.output;
}

TEST_F(CleaveCli, VoxelCheckMeasuresMeshesAndFlagsALeakyOne) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run_cleave("run " + write("s.toml", kSmallBox).string() +
                   " -q --mesh-format obj --mesh-layout per_fragment --out " + out.string())
                .code,
            0);
  Outcome check = run_cleave("check volume --voxel --summary " + out.string());
  ASSERT_EQ(check.code, 0) << check.output;
  EXPECT_NE(check.output.find("0 missing, 0 beyond tolerance"), std::string::npos) << check.output;

  // Knock one face out of one fragment's mesh: it no longer encloses its volume.
  const fs::path victim = out / "meshes" / "grain_0000.0.obj";
  ASSERT_TRUE(fs::exists(victim));
  std::istringstream in(cleave::io::read_file(victim));
  std::string line, kept;
  bool dropped = false;
  while (std::getline(in, line)) {
    if (!dropped && line.rfind("f ", 0) == 0) {
      dropped = true;
      continue;
    }
    kept += line + "\n";
  }
  ASSERT_TRUE(dropped);
  std::ofstream(victim) << kept;
  check = run_cleave("check volume --voxel --summary " + out.string());
  EXPECT_EQ(check.code, 1) << check.output;
  EXPECT_NE(check.output.find("grain_0000.0"), std::string::npos) << check.output;
}

TEST_F(CleaveCli, BadScenariosAreClearErrorsWithFileLineAndKey) {
  const fs::path missing = dir_ / "nope.toml";
  Outcome o = run_cleave("run " + missing.string() + " --out " + (dir_ / "o1").string());
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.output.find(missing.string()), std::string::npos) << o.output;

  std::string bad = kSmallBox;
  bad.replace(bad.find("r_bar = 0.9"), 11, "r_bar = 1.5");
  o = run_cleave("run " + write("rbar.toml", bad).string() + " --out " + (dir_ / "o2").string());
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.output.find("rbar.toml:9:"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("grain.r_bar"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(dir_ / "o2" / "run.toml"));

  bad = kSmallBox;
  bad.replace(bad.find("seed = 3"), 8, "sead = 3");
  o = run_cleave("run " + write("typo.toml", bad).string() + " --out " + (dir_ / "o3").string());
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.output.find("typo.toml:12:"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("orientation.sead"), std::string::npos) << o.output;

  o = run_cleave("run " + write("ok.toml", kSmallBox).string() + " --mesh-format ply");
  EXPECT_NE(o.code, 0);
  EXPECT_NE(o.output.find("ply"), std::string::npos) << o.output;
}

TEST_F(CleaveCli, AFailedRunIsNotPassedOffAsAResult) {
  // A time step above the stable limit fails the run once its folder is made (a box that
  // holds no grain is now refused before, io/budget.hpp).
  const std::string unstable =
      std::string(kSmallBox) +
      "[contact]\ndilation_radius = 0.05\n[contact.particle_particle]\nkn = 5000.0\n"
      "[contact.particle_wall]\nkn = 5000.0\n[dynamics]\ndt = 1.0\nduration = 2.0\n";
  const fs::path out = dir_ / "out";
  const Outcome run =
      run_cleave("run " + write("unstable.toml", unstable).string() + " --out " + out.string());
  EXPECT_NE(run.code, 0) << run.output;
  EXPECT_EQ(cleave::io::read_manifest(out).status, "failed");
  const Outcome check = run_cleave("check volume " + out.string());
  EXPECT_EQ(check.code, 2);
  EXPECT_NE(check.output.find("unfinished"), std::string::npos) << check.output;
  // A folder that is no result at all.
  EXPECT_EQ(run_cleave("check volume " + dir_.string()).code, 2);
}

TEST_F(CleaveCli, EveryShippedScenarioParsesAndTheDemoRuns) {
  for (const auto& entry : fs::directory_iterator(fs::path(CLEAVE_SOURCE_DIR) / "scenarios")) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    const fs::path out = dir_ / entry.path().stem();
    // Dynamics runs are cut short: this checks that every file runs, not the physics.
    const Outcome run =
        run_cleave("run -q --max-steps 50 " + entry.path().string() + " --out " + out.string());
    EXPECT_EQ(run.code, 0) << run.output;
    EXPECT_EQ(run_cleave("check volume --summary " + out.string()).code, 0);
  }
}

TEST_F(CleaveCli, TimingClocksEveryPartOfTheStepsAndTheirSumIsTheTotal) {
  // `cleave run --timing` on the Brazilian fracture scenario (bonds, walls, the
  // transgranular check every step): timing.csv lists each part of the step and the check,
  // the steps it clocked (the run's), and its parts add up to its total; without the flag
  // there is no timing.csv.
  const std::filesystem::path scenario = std::filesystem::path(CLEAVE_SOURCE_DIR) / "scenarios/brazilian_fracture.toml";
  const std::filesystem::path out = dir_ / "timed", plain = dir_ / "plain";
  const Outcome run = run_cleave("run --timing --max-steps 40 " + scenario.string() + " --out " + out.string());
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("timing"), std::string::npos) << run.output;
  std::ifstream in(out / "timing.csv");
  ASSERT_TRUE(in) << "no timing.csv";
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "part,wall_s,wall_ms_per_step,share,steps");
  std::vector<std::string> parts;
  double sum = 0.0, total = -1.0;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string part, seconds, ms, share, steps;
    std::getline(row, part, ',');
    std::getline(row, seconds, ',');
    std::getline(row, ms, ',');
    std::getline(row, share, ',');
    std::getline(row, steps, ',');
    EXPECT_EQ(steps, "40") << line;
    EXPECT_GE(std::stod(seconds), 0.0) << line;
    EXPECT_LE(std::stod(share), 1.0) << line;
    if (part == "total") {
      total = std::stod(seconds);
    } else {
      parts.push_back(part);
      sum += std::stod(seconds);
    }
  }
  const std::vector<std::string> expected = {"kick_drift", "poses", "pair_search", "plan", "narrow",
                                             "walls", "contact_law", "contact_sums", "bond_law", "bond_sums",
                                             "damping", "closing_kick", "transgranular_check"};
  EXPECT_EQ(parts, expected);
  ASSERT_GT(total, 0.0);
  EXPECT_NEAR(sum, total, 1e-5);  // each part rounded to a microsecond
  ASSERT_EQ(run_cleave("run -q --max-steps 5 " + scenario.string() + " --out " + plain.string()).code, 0);
  EXPECT_FALSE(std::filesystem::exists(plain / "timing.csv"));
}

TEST_F(CleaveCli, StlExportsPerFragmentAndRefusesVoxelCheckOfAnUnnamedScene) {
  const fs::path per = dir_ / "per";
  ASSERT_EQ(run_cleave("run " + write("s.toml", kSmallBox).string() +
                       " -q --mesh-format stl --mesh-layout per_fragment --out " + per.string())
                .code,
            0);
  const auto store = cleave::io::read_exact_store(per / "geometry.exact");
  std::size_t stl_files = 0;
  for (const auto& e : fs::directory_iterator(per / "meshes")) stl_files += e.path().extension() == ".stl";
  EXPECT_EQ(stl_files, store.fragments.size());
  const Outcome ok = run_cleave("check volume --voxel --summary " + per.string());
  EXPECT_EQ(ok.code, 0) << ok.output;

  const fs::path scene = dir_ / "scene";
  ASSERT_EQ(run_cleave("run " + write("s2.toml", kSmallBox).string() +
                       " -q --mesh-format stl --mesh-layout scene --out " + scene.string())
                .code,
            0);
  const Outcome refused = run_cleave("check volume --voxel " + scene.string());
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.output.find("STL keeps no mesh names"), std::string::npos) << refused.output;
}

TEST_F(CleaveCli, TheProgressLineGivesAnEtaOnlyWhereTheStepLimitEndsTheStage) {
  // The approach stage of the Brazilian disc ends when the platens touch (an event), not at
  // its time limit: the progress line names the event instead of a time. A drop test ends
  // at its duration or sooner, when the grains settle: an upper bound.
  const fs::path root(CLEAVE_SOURCE_DIR);
  const Outcome disc = run_cleave("run " + (root / "scenarios/brazilian_fracture.toml").string() +
                                  " --max-steps 300 --out " + (dir_ / "disc").string());
  ASSERT_EQ(disc.code, 0) << disc.output;
  EXPECT_NE(disc.output.find("stage approach"), std::string::npos) << disc.output;
  EXPECT_NE(disc.output.find("until walls_touch"), std::string::npos) << disc.output;
  EXPECT_EQ(disc.output.find("ETA"), std::string::npos) << disc.output;
  const Outcome drop = run_cleave("run " + (root / "scenarios/demo_drop.toml").string() +
                                  " --max-steps 300 --out " + (dir_ / "drop").string());
  ASSERT_EQ(drop.code, 0) << drop.output;
  EXPECT_NE(drop.output.find("ETA <= "), std::string::npos) << drop.output;
}

TEST_F(CleaveCli, MaxStepsCountsEveryStepAndEndsTheStageItFallsIn) {
  // --max-steps N: N steps in all, whatever stages end by their events on the way (the
  // Brazilian disc's approach ends when the platens touch, after a few hundred steps); the
  // stage it falls in says it was cut by it.
  const fs::path out = dir_ / "cut";
  const Outcome run = run_cleave("run " + (fs::path(CLEAVE_SOURCE_DIR) / "scenarios/brazilian_fracture.toml").string() +
                                 " --quiet --max-steps 3000 --out " + out.string());
  ASSERT_EQ(run.code, 0) << run.output;
  const auto m = cleave::io::read_manifest(out);
  EXPECT_EQ(m.facts.at("dynamics_steps"), "3000");
  EXPECT_EQ(m.facts.at("stage_approach_ended_by"), "walls_touch");
  EXPECT_EQ(m.facts.at("stage_loading_ended_by"), "max_steps");
}

namespace {

/// kSmallBox falling under gravity onto nothing: a dynamics run whose every step is dt long.
std::string small_drop() {
  // Its two layers of prisms a little apart (t_bar < t): they would start pressed together.
  std::string box = kSmallBox;
  box.replace(box.find("t = 1.0\n"), 8, "t = 1.0\nt_bar = 0.8\n");
  return box + R"(
[contact]
dilation_radius = 0.05
[contact.particle_particle]
kn = 5.0
[contact.particle_wall]
kn = 5.0
[dynamics]
dt = 1e-6
duration = 1.0
gravity = [0.0, 0.0, -9.81]
frames = 0
)";
}

}  // namespace

TEST_F(CleaveCli, RunSetOverridesAKeyAndRecordsIt) {
  // Ten steps of dt: the simulated time is 10 dt, so --set dynamics.dt=1e-5 gives 1e-4 s
  // where the file's 1e-6 gives 1e-5 s.
  const fs::path scenario = write("drop.toml", small_drop());
  const fs::path plain = dir_ / "plain", set = dir_ / "set";
  ASSERT_EQ(
      run_cleave("run -q --max-steps 10 " + scenario.string() + " --out " + plain.string()).code,
      0);
  const Outcome o = run_cleave("run -q --max-steps 10 " + scenario.string() +
                               " --set dynamics.dt=1e-5 "
                               "--set orientation.seed=4 --out " +
                               set.string());
  ASSERT_EQ(o.code, 0) << o.output;
  const auto before = cleave::io::read_manifest(plain), after = cleave::io::read_manifest(set);
  EXPECT_DOUBLE_EQ(std::stod(before.facts.at("dynamics_time_s")), 10 * 1e-6);
  EXPECT_DOUBLE_EQ(std::stod(after.facts.at("dynamics_time_s")), 10 * 1e-5);
  EXPECT_EQ(after.provenance.at("seed"), "4");
  EXPECT_EQ(after.provenance.at("overrides"), "dynamics.dt=1e-5; orientation.seed=4");
  EXPECT_EQ(before.provenance.count("overrides"), 0u);
  // A value with its unit: 10 us.
  const fs::path with_unit = dir_ / "unit";
  ASSERT_EQ(run_cleave("run -q --max-steps 10 " + scenario.string() +
                       " --set 'dynamics.dt=10 us' --out " + with_unit.string())
                .code,
            0);
  EXPECT_DOUBLE_EQ(std::stod(cleave::io::read_manifest(with_unit).facts.at("dynamics_time_s")),
                   10 * 1e-5);
}

TEST_F(CleaveCli, ABadRunOverrideIsAUsageErrorNamingTheOverride) {
  const fs::path scenario = write("drop.toml", small_drop());
  const std::string run = "run -q " + scenario.string() + " --out " + (dir_ / "o").string() + " ";
  Outcome o = run_cleave(run + "--set dynamics.dt=abc");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("--set dynamics.dt=abc: key 'dynamics.dt': expected a number"),
            std::string::npos)
      << o.output;
  EXPECT_EQ(o.output.find("drop.toml:"), std::string::npos) << o.output;  // no line of the file
  o = run_cleave(run + "--set dynamics.dt=-1");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("--set dynamics.dt=-1: key 'dynamics.dt': must be > 0"),
            std::string::npos)
      << o.output;
  o = run_cleave(run + "--set bond.nonsense=1");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("--set bond.nonsense=1: key 'bond.nonsense': unknown key"),
            std::string::npos)
      << o.output;
  // One value for a run; a key path; a time step above the stable limit, found after reading.
  o = run_cleave(run + "--set dynamics.dt=1e-6,2e-6");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("--set dynamics.dt=1e-6,2e-6: give one value"), std::string::npos)
      << o.output;
  o = run_cleave(run + "--set dt=1");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("--set dt"), std::string::npos) << o.output;
  o = run_cleave(run + "--set dynamics.dt=1");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("--set dynamics.dt=1: key 'dynamics.dt'"), std::string::npos) << o.output;
  o = run_cleave("run --restart " + (dir_ / "o").string() + " --set dynamics.dt=1e-6");
  EXPECT_EQ(o.code, 2) << o.output;
  // An error of the file itself keeps its line.
  std::string bad = small_drop();
  bad.replace(bad.find("r_bar = 0.9"), 11, "r_bar = 1.5");
  o = run_cleave("run -q " + write("rbar.toml", bad).string() + " --set dynamics.dt=1e-6");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("rbar.toml:9:"), std::string::npos) << o.output;
}

namespace {

/// Whether a column or field name says its unit (a suffix) or is a plain number by the list
/// of dimensionless names (counts, ids, labels, ratios, unit vectors).
bool names_its_unit(const std::string& name) {
  static const std::vector<std::string> suffixes = {
      "_s",   "_J",  "_m",         "_m2",      "_m3",        "_N",          "_Pa",
      "_K",   "_deg", "_Nm",       "_Pa_sqrt_m", "_m_per_s", "_rad_per_s", "_ms_per_step", "_kg"};
  static const std::set<std::string> dimensionless = {
      "stage", "step", "steps", "contacts", "intact", "broken_tension", "broken_shear",
      "broken_bending", "broken_torsion", "bonds_intact", "bonds_broken", "grain_splits", "grain",
      "parent", "pieces", "plane", "nx", "ny", "nz", "criterion", "bond", "body_a", "body_b",
      "grain_a", "grain_b", "mode", "grain_id", "row", "i", "j", "k", "family", "slabs", "name",
      "path", "strain_x", "strain_y", "strain_z", "axis", "strain", "poisson", "part", "share",
      "bodies", "passing",
      "intergranular_count", "transgranular_count", "transgranular_area_fraction",
      "transgranular_count_fraction",
      // VTK fields
      "body_index", "link_index", "body_id", "family_11_20", "c_axis", "normal", "with_wall",
      "failure_mode", "periodic", "wall_index", "crack_index", "kind"};
  if (dimensionless.count(name) > 0) return true;
  return std::any_of(suffixes.begin(), suffixes.end(), [&](const std::string& s) {
    return name.size() > s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
  });
}

/// Every CSV header column and VTK field name of a result folder that does not name its unit.
std::vector<std::string> names_without_unit(const fs::path& dir, std::size_t& checked) {
  std::vector<std::string> bad;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const fs::path& p = e.path();
    if (p.extension() == ".csv") {
      const auto rows = cleave::testing::read_csv_cells(p);
      if (rows.empty()) continue;
      for (const auto& column : rows[0]) {
        ++checked;
        if (!names_its_unit(column)) bad.push_back(p.filename().string() + ": " + column);
      }
    } else if (p.extension() == ".vtp") {
      std::ifstream in(p);
      const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      for (std::size_t at = xml.find("<DataArray"); at != std::string::npos;
           at = xml.find("<DataArray", at + 1)) {
        const std::size_t end = xml.find('>', at);
        const std::size_t name = xml.find("Name=\"", at);
        if (name == std::string::npos || name > end) continue;
        const std::string field = xml.substr(name + 6, xml.find('"', name + 6) - name - 6);
        if (field == "connectivity" || field == "offsets" || field == "Points") continue;
        ++checked;
        if (!names_its_unit(field)) bad.push_back(p.filename().string() + ": " + field);
      }
    }
  }
  return bad;
}

}  // namespace

TEST_F(CleaveCli, EveryOutputColumnAndFieldNamesItsUnit) {
  // Real runs: a bonded disc with fracture and --timing (energy, walls, load_displacement,
  // bonds, bond_breaks, splits, timing, specimen, fragments, bodies, contacts, bonds frames)
  // and a thermal one (thermal.csv); each header column and VTK field ends in its unit or is
  // on the list of plain numbers.
  const fs::path src(CLEAVE_SOURCE_DIR);
  const fs::path fracture = dir_ / "fracture", thermal = dir_ / "thermal";
  ASSERT_EQ(run_cleave("run -q --timing --max-steps 300 " +
                       (src / "scenarios/brazilian_fracture.toml").string() +
                       " --set dynamics.frames=2 --out " + fracture.string())
                .code,
            0);
  ASSERT_EQ(run_cleave("run -q --max-steps 100 " +
                       (src / "scenarios/thermal_microcracking.toml").string() + " --out " +
                       thermal.string())
                .code,
            0);
  // Grains resting on a floor: contact frames with their fields.
  const fs::path contacts = dir_ / "contacts";
  const fs::path floor = write("floor.toml", small_drop() +
                                                 "[[wall]]\nkind = \"plane\"\npoint = [0, 0, 0]\n"
                                                 "normal = [0, 0, 1]\n");
  ASSERT_EQ(run_cleave("run -q --max-steps 20 " + floor.string() +
                       " --set dynamics.frames=2 --out " + contacts.string())
                .code,
            0);
  std::ifstream frame(contacts / "frames" / "contacts_000001.vtp");
  const std::string xml((std::istreambuf_iterator<char>(frame)), std::istreambuf_iterator<char>());
  EXPECT_NE(xml.find("Name=\"overlap_m\""), std::string::npos) << "no contact in the last frame";
  for (const char* f :
       {"energy.csv", "walls.csv", "load_displacement.csv", "bonds.csv", "bond_breaks.csv",
        "splits.csv", "cracks.csv", "timing.csv", "specimen.csv", "fragments.csv"})
    EXPECT_TRUE(fs::exists(fracture / f)) << f;
  EXPECT_TRUE(fs::exists(thermal / "thermal.csv"));
  for (const fs::path& dir : {fracture, thermal, contacts}) {
    std::size_t checked = 0;
    const auto bad = names_without_unit(dir, checked);
    EXPECT_GT(checked, 50u) << dir;
    for (const auto& b : bad) ADD_FAILURE() << dir.filename().string() << "/" << b << ": no unit";
  }
}

TEST_F(CleaveCli, AResultFolderOutsideWhatCleaveOwnsIsRefusedBeforeAnythingIsWritten) {
  // A scenario name that would lead out of results/ is an error at its key; --out the root,
  // or a folder holding another program's files, is a usage error, and those files stay.
  std::string escaping = kSmallBox;
  escaping.replace(escaping.find("name = \"small\""), 14, "name = \"../../cleave_escaped\"");
  const fs::path scenario = write("escaping.toml", escaping);
  const Outcome named = run_cleave("run " + scenario.string());
  EXPECT_EQ(named.code, 2) << named.output;
  EXPECT_NE(named.output.find("escaping.toml:3"), std::string::npos) << named.output;
  EXPECT_NE(named.output.find("must be a plain folder name"), std::string::npos) << named.output;
  EXPECT_FALSE(fs::exists(fs::current_path() / "../cleave_escaped"));

  const fs::path small = write("small.toml", kSmallBox);
  const Outcome root = run_cleave("run " + small.string() + " --out /");
  EXPECT_EQ(root.code, 2) << root.output;
  EXPECT_NE(root.output.find("is the file system's root"), std::string::npos) << root.output;
  const fs::path src(CLEAVE_SOURCE_DIR);
  for (const std::string& other :
       {"sweep " + (src / "scenarios/brazilian_fracture.toml").string() + " --set orientation.seed=1..2",
        "validate " + (src / "scenarios/validation/dcb_coarse.toml").string()}) {
    const Outcome refused_root = run_cleave(other + " --out /");
    EXPECT_EQ(refused_root.code, 2) << other << ": " << refused_root.output;
    EXPECT_NE(refused_root.output.find("is the file system's root"), std::string::npos) << refused_root.output;
  }

  const fs::path foreign = dir_ / "foreign";
  fs::create_directories(foreign / "meshes");
  std::ofstream(foreign / "notes.txt") << "mine";
  std::ofstream(foreign / "meshes" / "part.stl") << "mine too";
  const Outcome refused = run_cleave("run " + small.string() + " --out " + foreign.string());
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_NE(refused.output.find("no cleave run.toml"), std::string::npos) << refused.output;
  EXPECT_TRUE(fs::exists(foreign / "notes.txt"));
  EXPECT_TRUE(fs::exists(foreign / "meshes" / "part.stl"));
  EXPECT_FALSE(fs::exists(foreign / "run.toml"));

  // Its own earlier result is a folder it may write again.
  const fs::path mine = dir_ / "mine";
  ASSERT_EQ(run_cleave("run " + small.string() + " --quiet --out " + mine.string()).code, 0);
  const Outcome again = run_cleave("run " + small.string() + " --quiet --out " + mine.string());
  EXPECT_EQ(again.code, 0) << again.output;
}

TEST_F(CleaveCli, UsageErrorsExitTwoAndStepCountsAreWholeNumbers) {
  // Every usage error is exit 2 (the command line parser's own codes were 104-114); a step
  // count is a whole number, so -1 cannot wrap to 2^64 - 1 and 1e23 is no count.
  const fs::path small = write("small.toml", kSmallBox);
  for (const std::string& bad : {"--max-steps -1", "--max-steps 1e23", "--checkpoint-every -5",
                                 "--max-steps 10000000000000000", "--no-such-option"}) {
    const Outcome o = run_cleave("run " + small.string() + " --quiet --out " + (dir_ / "o").string() + " " + bad);
    EXPECT_EQ(o.code, 2) << bad << ": " << o.output;
    EXPECT_FALSE(fs::exists(dir_ / "o" / "run.toml")) << bad;
  }
  EXPECT_EQ(run_cleave("frobnicate").code, 2);
  EXPECT_EQ(run_cleave("--help").code, 0);
  EXPECT_EQ(run_cleave("run " + small.string() + " --quiet --max-steps 10 --out " + (dir_ / "o").string()).code, 0);
}

TEST_F(CleaveCli, NumericOptionsOutsideTheirRangeAreUsageErrorsNamingTheOption) {
  // NaN passed CLI11's ranges (every comparison with NaN is false), a tolerance had no bound,
  // and a sweep range of two far-apart integers overflowed its length check and allocated
  // until bad_alloc. Each is now refused before anything runs, naming the option.
  const fs::path small = write("small.toml", kSmallBox);
  const fs::path result = dir_ / "result";
  ASSERT_EQ(run_cleave("run " + small.string() + " --quiet --out " + result.string()).code, 0);
  const std::string sweep = "sweep " + std::string(CLEAVE_SOURCE_DIR) +
                            "/tests/data/sweep_brazilian.toml -q -o " + (dir_ / "sweep").string() +
                            " ";
  const std::pair<std::string, std::string> cases[] = {
      {"check volume " + result.string() + " --voxel --voxels-per-length nan",
       "--voxels-per-length"},
      {"check volume " + result.string() + " --voxel --voxels-per-length 1e400",
       "--voxels-per-length"},
      {"check volume " + result.string() + " --voxel --voxel-tolerance nan", "--voxel-tolerance"},
      {"check volume " + result.string() + " --voxel --voxel-tolerance -0.1", "--voxel-tolerance"},
      {"measure brazilian " + small.string() + " --converge --tolerance nan -o " +
           (dir_ / "m").string(),
       "--tolerance"},
      {"measure brazilian " + small.string() + " --converge --tolerance inf -o " +
           (dir_ / "m").string(),
       "--tolerance"},
      {"measure brazilian " + small.string() + " --converge --tolerance 0 -o " +
           (dir_ / "m").string(),
       "--tolerance"},
      {"measure brazilian " + small.string() + " --converge --max-runs 2.5 -o " +
           (dir_ / "m").string(),
       "--max-runs"},
      {"calibrate " + small.string() + " --tolerance nan -o " + (dir_ / "c").string(),
       "--tolerance"},
      {"calibrate " + small.string() + " --tolerance -1 -o " + (dir_ / "c").string(),
       "--tolerance"},
      {"calibrate " + small.string() + " --tolerance 7 -o " + (dir_ / "c").string(), "--tolerance"},
      {sweep + "--set orientation.seed=1,2 --jobs 0", "--jobs"},
      {sweep + "--set orientation.seed=1,2 --jobs -3", "--jobs"},
      {sweep + "--set orientation.seed=1,2 --jobs 1.5", "--jobs"},
      {sweep + "--set orientation.seed=1,2 --jobs 100000000", "--jobs"},
      {sweep + "--set orientation.seed=-9000000000000000000..9000000000000000000",
       "orientation.seed"},
      {sweep + "--set orientation.seed=1,2 --max-steps 2.5", "--max-steps"},
  };
  for (const auto& [args, option] : cases) {
    const Outcome o = run_cleave(args);
    EXPECT_EQ(o.code, 2) << args << ": " << o.output;
    EXPECT_NE(o.output.find(option), std::string::npos) << args << ": " << o.output;
  }
  for (const char* never : {"m", "c", "sweep"}) EXPECT_FALSE(fs::exists(dir_ / never)) << never;
}
