// Provenance of a result folder: SHA-256 of the files written (known test vectors), the
// file list of io::ResultRecord, and the scenario as run (scenario_to_toml) read back equal.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"

namespace fs = std::filesystem;
using namespace cleave::io;

namespace {

// FIPS 180-2 / NIST test vectors.
constexpr const char* kShaEmpty = "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855";
constexpr const char* kShaAbc = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
constexpr const char* kSha448Bits = "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1";
constexpr const char* kShaMillionA = "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0";

class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("cleave_prov_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  void write(const fs::path& rel, const std::string& text) {
    fs::create_directories((dir_ / rel).parent_path());
    std::ofstream(dir_ / rel, std::ios::binary) << text;
  }
  fs::path dir_;
};

}  // namespace

TEST(Sha256, KnownTestVectors) {
  EXPECT_EQ(sha256_hex(""), kShaEmpty);
  EXPECT_EQ(sha256_hex("abc"), kShaAbc);
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"), kSha448Bits);
}

using Sha256File = TempDir;

TEST_F(Sha256File, ReadsTheWholeFileAcrossBufferBoundaries) {
  write("a.bin", std::string(1000000, 'a'));  // > the reader's 64 KiB buffer, not a multiple
  EXPECT_EQ(sha256_file(dir_ / "a.bin"), kShaMillionA);
  write("abc.txt", "abc");
  EXPECT_EQ(sha256_file(dir_ / "abc.txt"), kShaAbc);
  EXPECT_THROW(sha256_file(dir_ / "missing"), std::runtime_error);
}

using ResultRecordTest = TempDir;

TEST_F(ResultRecordTest, ListsAndHashesExactlyTheFilesWrittenSinceTheStart) {
  // Left by an earlier run: older than this run's start, so not this run's.
  write("old.csv", "stale");
  write("frames/old_000099.vtp", "stale");
  const auto long_ago = fs::file_time_type::clock::now() - std::chrono::hours(1);
  fs::last_write_time(dir_ / "old.csv", long_ago);
  fs::last_write_time(dir_ / "frames/old_000099.vtp", long_ago);

  ResultRecord record(dir_);
  record.manifest.provenance["seed"] = "42";
  record.start();
  {
    const Manifest running = read_manifest(dir_);
    EXPECT_EQ(running.status, "running");
    EXPECT_EQ(running.provenance.at("seed"), "42");
    EXPECT_TRUE(running.files.empty());
  }
  write("abc.txt", "abc");
  write("frames/empty.vtp", "");
  write("frames/big.bin", std::string(1000000, 'a'));
  write("half_written.csv.tmp", "partial");
  record.manifest.facts["steps"] = "10";
  record.close(run_status::finished);

  const Manifest m = read_manifest(dir_);
  EXPECT_EQ(m.status, "finished");
  EXPECT_EQ(m.facts.at("steps"), "10");
  ASSERT_EQ(m.files.size(), 3u);
  EXPECT_EQ(m.files[0].path, "abc.txt");
  EXPECT_EQ(m.files[0].bytes, 3u);
  EXPECT_EQ(m.files[0].sha256, kShaAbc);
  EXPECT_EQ(m.files[1].path, "frames/big.bin");
  EXPECT_EQ(m.files[1].bytes, 1000000u);
  EXPECT_EQ(m.files[1].sha256, kShaMillionA);
  EXPECT_EQ(m.files[2].path, "frames/empty.vtp");
  EXPECT_EQ(m.files[2].sha256, kShaEmpty);
  // SHA256SUMS in `sha256sum -c` form.
  EXPECT_EQ(read_file(dir_ / kChecksumsName),
            std::string(kShaAbc) + "  abc.txt\n" + kShaMillionA + "  frames/big.bin\n" + kShaEmpty +
                "  frames/empty.vtp\n");
}

TEST_F(ResultRecordTest, AFailedRunKeepsItsReason) {
  ResultRecord record(dir_);
  record.start();
  write("energy.csv", "time_s\n");
  EXPECT_TRUE(record.close_quietly(run_status::failed, "the run blew up at step 3"));
  const Manifest m = read_manifest(dir_);
  EXPECT_EQ(m.status, "failed");
  EXPECT_EQ(m.reason, "the run blew up at step 3");
  ASSERT_EQ(m.files.size(), 1u);
  EXPECT_EQ(m.files[0].path, "energy.csv");
}

// ---- the scenario as run ----------------------------------------------------------------------

namespace {

/// Non-default values in every table the writer knows, in millimetres, with awkward strings.
const char* kEverything = R"(
[scenario]
name = "every \"key\" set"
description = """two
lines \\ and a backslash\tand a tab"""
length_unit = "mm"
[specimen]
shape = "beam"
length = 20.3
height = 5.1
thickness = 3.3
notch_width = 1.1
notch_depth = 1.7
keep = "centre_inside"
[grain]
r = 1.1
r_bar = 0.93
t = 1.3
t_bar = 1.01
[orientation]
seed = 123456789
family_mix = 0.3
angles = [120, 0]
[split]
min_fragment_fraction = 0.037
[output]
mesh_format = "stl_ascii"
mesh_layout = "per_fragment"
frame_meshes = true
[material]
density = 3217.5
[contact]
dilation_radius = 0.047
[contact.particle_particle]
kn = 5123.0
ks = 2011.5
kr = 1e-7
kt = 2e-7
c_res = 2.5
mu_s = 0.31
mu_r = 0.47
damping = 0.13
[contact.particle_wall]
kn = 10000
c_res = 10
[dynamics]
dt = 1.23e-7
gravity = [0.1, -0.2, -9.81]
lift = 0.7
frames = 7
settle_ratio = 1e-6
dt_safety = 0.35
search = "basic"
threads = 3
local_damping = 0.7
[bond]
law = "cohesive"
kbn = 1.7e13
kbs = 0.7e13
sigma_c = 3.3e6
g_c = 21.5
[fracture]
sigma_f_hyd = -1.5e6
k_ic = 3.1e6
c = 0.9
crack_length = 0.33
check_every = 5
[[wall]]
name = "floor"
kind = "plane"
point = [0, 0, -0.1]
normal = [0, 0.1, 1]
[[wall]]
name = "top plate"
kind = "platen"
point = [10.15, 5.3, 1.65]
normal = [0, -1, 0]
u = [1, 0.2, 0]
size = [30.1, 7.7]
velocity = [0, -0.013, 0]
load_axis = [0, -1, 0.001]
[[wall]]
name = "roller"
kind = "cylinder"
point = [3.1, -0.71, -1]
normal = [0, 0, 1]
length = 5.3
radius = 0.7
load_axis = [0, 1, 0]
[[stage]]
name = "compact"
wall_velocity = { "top plate" = [0, -0.07, 0], floor = [0, 0, 0.001] }
time = 0.0123
until = "all_in_contact"
frames = 3
[[stage]]
name = "bond"
kind = "bond"
distance = 0.0123
[[stage]]
name = "load"
wall_velocity = { "top plate" = [0, -0.001, 0] }
steps = 98765
until = "load_drop"
load_drop = 0.35
load_walls = ["top plate", "roller"]
frames = 0
)";

Scenario round_trip(const Scenario& s) { return parse_scenario(scenario_to_toml(s), "as_run.toml"); }

std::string listed(const std::vector<std::string>& keys) {
  std::string out;
  for (const auto& k : keys) out += k + " ";
  return out;
}

}  // namespace

TEST(ScenarioAsRun, EveryKeyReadsBackEqual) {
  const Scenario s = parse_scenario(kEverything, "everything.toml");
  const std::string text = scenario_to_toml(s);
  const Scenario back = parse_scenario(text, "as_run.toml");
  EXPECT_TRUE(scenario_differences(s, back).empty()) << listed(scenario_differences(s, back)) << "\n" << text;
  // Written in metres: 1.1 mm is 0.0011 m, exactly as the reader converted it.
  EXPECT_NE(text.find("length_unit = \"m\""), std::string::npos) << text;
  EXPECT_EQ(back.specimen.r, 1.1 * 1e-3);
  EXPECT_EQ(back.specimen.seed, 123456789u);
  EXPECT_EQ(back.name, "every \"key\" set");
  EXPECT_EQ(back.description, "two\nlines \\ and a backslash\tand a tab");
  ASSERT_EQ(back.stages.size(), 3u);
  EXPECT_EQ(back.stages[2].load_walls, (std::vector<std::string>{"top plate", "roller"}));
  // Written once more, the text is the same (nothing drifts from one round to the next).
  EXPECT_EQ(scenario_to_toml(back), text);
}

TEST(ScenarioAsRun, DefaultsAreWrittenOut) {
  const Scenario s = parse_scenario(R"(
[specimen]
shape = "disc"
diameter = 15
thickness = 5
[grain]
r = 1
t = 1
)", "minimal.toml");
  const std::string text = scenario_to_toml(s);
  // The defaults of scenario.hpp as keys of the file, so the folder says what ran.
  for (const char* line : {"name = \"minimal\"", "description = \"\"", "r_bar = 0.001", "seed = 1", "family_mix = 0.5",
                           "angles = [0, 60, 120]", "min_fragment_fraction = 0.01",
                           "mesh_format = \"obj\"", "density = 3100.0", "keep = \"cell_inside\""}) {
    EXPECT_NE(text.find(line), std::string::npos) << line << "\n" << text;
  }
  EXPECT_TRUE(scenario_differences(s, round_trip(s)).empty()) << listed(scenario_differences(s, round_trip(s)));
}

TEST(ScenarioAsRun, EveryShippedScenarioReadsBackEqual) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(CLEAVE_SOURCE_DIR) / "scenarios")) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    const Scenario s = load_scenario(entry.path());
    const Scenario back = round_trip(s);
    EXPECT_TRUE(scenario_differences(s, back).empty()) << listed(scenario_differences(s, back));
    ++count;
  }
  EXPECT_GE(count, 5);
}

TEST(ScenarioAsRun, TheComparisonSeesAChangeInAnyTable) {
  // The round-trip tests above are only as good as scenario_differences: it must notice.
  const Scenario s = parse_scenario(kEverything, "everything.toml");
  auto changed = [&](auto&& edit) {
    Scenario t = s;
    edit(t);
    return scenario_differences(s, t);
  };
  using V = std::vector<std::string>;
  EXPECT_EQ(changed([](Scenario& t) { t.specimen.outline.notch_depth *= 1 + 1e-16 * 4; }), V{"specimen.notch_depth"});
  EXPECT_EQ(changed([](Scenario& t) { t.specimen.seed += 1; }), V{"orientation.seed"});
  EXPECT_EQ(changed([](Scenario& t) { t.output.frame_meshes = false; }), V{"output.frame_meshes"});
  EXPECT_EQ(changed([](Scenario& t) { t.contact.particle_wall.mu_r = 0.1; }), V{"contact.particle_wall.mu_r"});
  EXPECT_EQ(changed([](Scenario& t) { t.dynamics.dt = 1.24e-7; }), V{"dynamics.dt"});
  EXPECT_EQ(changed([](Scenario& t) { t.bond.params.g_c = 1; }), V{"bond.g_c"});
  EXPECT_EQ(changed([](Scenario& t) { t.fracture.check_every = 1; }), V{"fracture.check_every"});
  EXPECT_EQ(changed([](Scenario& t) { t.fracture.params.inertia = false; }), V{"fracture.inertia"});
  EXPECT_EQ(changed([](Scenario& t) { t.walls[2].load_axis = {0, 0, 1}; }), V{"wall[3].load_axis"});
  EXPECT_EQ(changed([](Scenario& t) { t.walls[1].velocity.y() = 0; }), V{"wall[2].velocity"});
  EXPECT_EQ(changed([](Scenario& t) { t.stages[0].wall_velocity[1].second.y() = 0; }),
            V{"stage[1].wall_velocity.top plate"});
  EXPECT_EQ(changed([](Scenario& t) { t.stages[2].load_drop = 0.5; }), V{"stage[3].load_drop"});
  EXPECT_EQ(changed([](Scenario& t) { t.stages[1].temperature_field = "300 + x"; }), V{"stage[2].temperature_field"});
  EXPECT_EQ(changed([](Scenario& t) { t.stages[1].hold_cracks = true; }), V{"stage[2].hold_cracks"});
  EXPECT_EQ(changed([](Scenario& t) { t.stages.pop_back(); }), V{"stage (count)"});
  EXPECT_TRUE(changed([](Scenario& t) { t.source = "elsewhere.toml"; }).empty());
}
