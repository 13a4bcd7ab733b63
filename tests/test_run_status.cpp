// A result folder tells the truth about its run: `running` while it goes, then `finished`,
// `interrupted` (SIGTERM) or `failed` (a blow-up, with the step, the body and a time step),
// and its provenance: versions, seed, the scenario as run and the SHA-256 of every file.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <openssl/evp.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "cli_helpers.hpp"
#include "folder_test.hpp"
#include "io/checkpoint.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"
#include "sim/simulation.hpp"

extern char** environ;

namespace fs = std::filesystem;
using cleave::io::Manifest;
using cleave::io::read_manifest;
using cleave::testing::drop_scenario;

namespace {

/// SHA-256 of a file straight from OpenSSL's EVP interface, not through io::sha256_file.
std::string openssl_sha256(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string bytes = ss.str();
  std::array<unsigned char, EVP_MAX_MD_SIZE> md{};
  unsigned int n = 0;
  EVP_Digest(bytes.data(), bytes.size(), md.data(), &n, EVP_sha256(), nullptr);
  std::string hex;
  char buf[3];
  for (unsigned int i = 0; i < n; ++i) {
    std::snprintf(buf, sizeof buf, "%02x", md[i]);
    hex += buf;
  }
  return hex;
}

class RunStatus : public cleave::testing::FolderTest {
 protected:
  /// Starts `cleave run SCENARIO --out OUT --quiet` with its output in dir_/log.txt.
  pid_t spawn_run(const fs::path& scenario, const fs::path& out) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    const std::string log = (dir_ / "log.txt").string();
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    std::vector<std::string> args = {CLEAVE_BINARY, "run", scenario.string(), "--out", out.string(), "--quiet"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, CLEAVE_BINARY, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    EXPECT_EQ(rc, 0);
    return pid;
  }
  /// Waits for the process; its exit code, or -signal when a signal ended it.
  static int wait_for(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }
  std::string log() const {
    std::ifstream in(dir_ / "log.txt");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  int run(const fs::path& scenario, const fs::path& out) { return wait_for(spawn_run(scenario, out)); }

  /// Every file of the folder (but the manifest and SHA256SUMS) is listed with the hash
  /// OpenSSL computes for it now, and nothing else is listed.
  void expect_files_hashed(const fs::path& out, const Manifest& m) {
    std::set<std::string> on_disk;
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      const std::string rel = e.path().lexically_relative(out).generic_string();
      if (e.is_regular_file() && rel != "run.toml" && rel != "SHA256SUMS") on_disk.insert(rel);
    }
    std::set<std::string> listed;
    for (const auto& f : m.files) {
      listed.insert(f.path);
      ASSERT_TRUE(fs::exists(out / f.path)) << f.path;
      EXPECT_EQ(f.sha256, openssl_sha256(out / f.path)) << f.path;
      EXPECT_EQ(f.bytes, fs::file_size(out / f.path)) << f.path;
    }
    EXPECT_EQ(listed, on_disk);
  }

};

}  // namespace

TEST_F(RunStatus, AFinishedRunRecordsItsProvenanceAndHashesEveryFile) {
  const fs::path scenario = write("drop.toml", drop_scenario("drop", "duration = 6e-5\nframes = 2\n"));
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run(scenario, out), 0) << log();
  const Manifest m = read_manifest(out);
  EXPECT_EQ(m.status, "finished");
  EXPECT_TRUE(m.reason.empty());
  for (const char* key : {"cleave_version", "cgal_version", "assimp_version", "openvdb_version",
                          "eigen_version", "seed", "scenario", "scenario_sha256", "scenario_as_run",
                          "started_utc", "ended_utc"}) {
    EXPECT_TRUE(m.provenance.count(key)) << key;
  }
  const std::regex version(R"(\d+\.\d+(\.\d+)?)");
  for (const char* key : {"cgal_version", "assimp_version", "openvdb_version", "eigen_version"}) {
    EXPECT_TRUE(std::regex_match(m.provenance.at(key), version)) << key << " = " << m.provenance.at(key);
  }
  EXPECT_EQ(m.provenance.at("cgal_version").substr(0, 2), "5.");   // Debian 12: 5.5
  EXPECT_EQ(m.provenance.at("eigen_version").substr(0, 4), "3.4.");
  EXPECT_EQ(m.provenance.at("seed"), "7");
  EXPECT_EQ(m.provenance.at("scenario_sha256"), openssl_sha256(scenario));
  EXPECT_EQ(m.facts.at("dynamics_ending"), "completed");

  // The scenario as run reads back as the scenario that was run.
  ASSERT_TRUE(fs::exists(out / "scenario_as_run.toml"));
  const auto original = cleave::io::load_scenario(scenario);
  const auto as_run = cleave::io::load_scenario(out / "scenario_as_run.toml");
  EXPECT_TRUE(cleave::io::scenario_differences(original, as_run).empty());
  EXPECT_EQ(as_run.specimen.seed, 7u);

  // Every file the run wrote, hashed.
  expect_files_hashed(out, m);
}

TEST_F(RunStatus, AFileTheEarlierRunDidNotWriteStopsTheRerunAndThenTheListIsTheFolder) {
  const fs::path scenario = write("drop.toml", drop_scenario("drop", "duration = 6e-5\nframes = 2\n"));
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run(scenario, out), 0) << log();  // the earlier run
  std::ofstream(out / "frames" / "bodies_000099.vtp") << "stale";
  fs::last_write_time(out / "frames" / "bodies_000099.vtp",
                      fs::file_time_type::clock::now() - std::chrono::hours(2));
  // Not the earlier run's (not in its manifest): the rerun neither removes it nor mixes it in.
  EXPECT_EQ(run(scenario, out), 2) << log();
  EXPECT_NE(log().find("frames/bodies_000099.vtp"), std::string::npos) << log();
  EXPECT_TRUE(fs::exists(out / "frames" / "bodies_000099.vtp"));
  fs::remove(out / "frames" / "bodies_000099.vtp");
  ASSERT_EQ(run(scenario, out), 0) << log();
  const Manifest m = read_manifest(out);
  EXPECT_TRUE(std::any_of(m.files.begin(), m.files.end(),
                          [](const auto& f) { return f.path == "frames/bodies_000000.vtp"; }));
  expect_files_hashed(out, m);
}

TEST_F(RunStatus, SigtermStopsTheRunCleanlyWithStatusInterrupted) {
  // Long enough (millions of steps) that only the signal can end it within the test.
  const fs::path scenario = write("long.toml", drop_scenario("drop", "duration = 10.0\nframes = 1000000\n"));
  const fs::path out = dir_ / "out";
  const pid_t pid = spawn_run(scenario, out);
  ASSERT_GT(pid, 0);
  // Wait until the manifest says running and the step loop has begun (its first frame).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  bool stepping = false;
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(out / "run.toml") && read_manifest(out).status == "running" &&
        fs::exists(out / "frames" / "bodies_000001.vtp")) {
      stepping = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!stepping) {
    kill(pid, SIGKILL);
    wait_for(pid);
    FAIL() << "the run never reached its step loop: " << log();
  }
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  const int code = wait_for(pid);
  EXPECT_EQ(code, 128 + SIGTERM) << log();
  const Manifest m = read_manifest(out);
  EXPECT_EQ(m.status, "interrupted");
  EXPECT_NE(m.reason.find("SIGTERM"), std::string::npos) << m.reason;
  EXPECT_EQ(m.facts.at("dynamics_ending"), "interrupted");
  const auto steps = std::stoull(m.facts.at("dynamics_steps"));
  EXPECT_GT(steps, 0u);
  EXPECT_LT(steps, 8000000u);  // 10 s at 1.2 us: it stopped long before the end
  // What it had is written and hashed: the histories up to the stop and the frames.
  for (const char* f : {"energy.csv", "walls.csv", "bodies.pvd", "scenario_as_run.toml"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  expect_files_hashed(out, m);
  EXPECT_EQ(m.provenance.at("seed"), "7");
}

TEST_F(RunStatus, ABlowUpFailsWithStepBodyAndSuggestedTimeStep) {
  // Gravity a hundred million times too strong: in its first step, from rest, every grain
  // falls g dt^2 / 2 (velocity Verlet), 0.72 mm, most of its own size.
  const double g = 1e9, dt = 1.2e-6;
  const fs::path scenario =
      write("boom.toml", drop_scenario("drop", "duration = 1e-3\ngravity = [0.0, 0.0, -1e9]\n"));
  const fs::path out = dir_ / "out";
  EXPECT_EQ(run(scenario, out), 1) << log();
  const Manifest m = read_manifest(out);
  EXPECT_EQ(m.status, "failed");
  EXPECT_EQ(m.facts.at("dynamics_ending"), "blew_up");
  EXPECT_NE(m.reason.find("step 1 "), std::string::npos) << m.reason;
  EXPECT_NE(m.reason.find("body 0 "), std::string::npos) << m.reason;  // the first, in slot order
  // The suggested step shrinks dt by limit / displacement; the limit is a tenth of the
  // bounding radius of the dilated prism: corner at sqrt(r_bar^2 + (t_bar/2)^2), plus dilation.
  const double radius = std::hypot(0.9e-3, 0.425e-3) + 0.05e-3;
  const double expected = dt * (0.1 * radius) / (0.5 * g * dt * dt);
  std::smatch match;
  ASSERT_TRUE(std::regex_search(m.reason, match, std::regex(R"(suggested dt <= ([0-9.e+-]+) s)"))) << m.reason;
  EXPECT_NEAR(std::stod(match[1]), expected, 0.01 * expected) << m.reason;
  EXPECT_NE(log().find("blew up"), std::string::npos) << log();
  // The failed folder is still a truthful record of what was written.
  expect_files_hashed(out, m);
}

TEST_F(RunStatus, ABlowUpKeepsTheLastGoodCheckpointWhichReproducesIt) {
  // Gravity 7.2e5 m/s^2 from rest: the per-step fall g (n - 1/2) dt^2 passes a tenth of the
  // grain's bounding radius (0.104 mm) at step 101, still 15 mm above the floor. Checkpoints
  // every 20 steps: the one of step 100 is the last good state, and the blow-up must not
  // overwrite it.
  const fs::path scenario =
      write("late_boom.toml", drop_scenario("drop", "duration = 1e-2\ngravity = [0.0, 0.0, -7.2e5]\n"));
  const fs::path out = dir_ / "out";
  const std::string run_cmd = std::string(CLEAVE_BINARY) + " run --quiet " + scenario.string() +
                              " --out " + out.string() + " --checkpoint-every 20 > " +
                              (dir_ / "first.log").string() + " 2>&1";
  const int first = std::system(run_cmd.c_str());
  ASSERT_TRUE(WIFEXITED(first));
  EXPECT_EQ(WEXITSTATUS(first), 1);
  const Manifest m = read_manifest(out);
  EXPECT_EQ(m.status, "failed");
  std::smatch step;
  ASSERT_TRUE(std::regex_search(m.reason, step, std::regex(R"(step (\d+) )"))) << m.reason;
  const std::uint64_t blew_at = std::stoull(step[1]);
  EXPECT_NEAR(static_cast<double>(blew_at), 101.0, 2.0) << m.reason;
  const cleave::io::Checkpoint last = cleave::io::read_checkpoint(out / "checkpoint");
  EXPECT_LT(last.world.steps(), blew_at);
  EXPECT_GE(last.world.steps() + 20, blew_at);
  EXPECT_EQ(last.world.steps() % 20, 0u);
  // Restarted from it, the run blows up again at the same step: the checkpoint is the good
  // state just before, and the failure is reproducible from it.
  const std::string restart = std::string(CLEAVE_BINARY) + " restart --quiet " + out.string() +
                              " > " + (dir_ / "restart.log").string() + " 2>&1";
  const int second = std::system(restart.c_str());
  ASSERT_TRUE(WIFEXITED(second));
  EXPECT_EQ(WEXITSTATUS(second), 1);
  const Manifest again = read_manifest(out);
  EXPECT_EQ(again.status, "failed");
  EXPECT_NE(again.reason.find("step " + std::to_string(blew_at) + " "), std::string::npos)
      << again.reason;
}

namespace {

/// `command` through the shell with its output in `log`; its exit code (-1: not exited).
int shell(const std::string& command, const fs::path& log) {
  const int rc = std::system((command + " > " + log.string() + " 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Every cell of every CSV table in `dir` that reads as NaN or an infinity, as "file: cell".
std::vector<std::string> non_finite_cells(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".csv") continue;
    std::stringstream text(slurp(e.path()));
    std::string line;
    while (std::getline(text, line)) {
      std::stringstream cells(line);
      std::string cell;
      while (std::getline(cells, cell, ',')) {
        std::string c;
        for (char ch : cell) c += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        if (!c.empty() && (c[0] == '-' || c[0] == '+')) c.erase(0, 1);
        if (c == "nan" || c == "inf" || c == "infinity")
          found.push_back(e.path().filename().string() + ": " + line);
      }
    }
  }
  return found;
}

}  // namespace

TEST_F(RunStatus, AStepLimitThatCutsTheStagesShortIsStoppedWithItsStepAndStage) {
  // Four-point bending: its approach stage ends on walls_touch after a few hundred steps,
  // so a limit of 1000 steps in all falls in the loading stage, long before its load drop.
  const fs::path out = dir_ / "out";
  const std::string scenario =
      std::string(CLEAVE_SOURCE_DIR) + "/scenarios/four_point_bending.toml";
  const int code = shell(
      std::string(CLEAVE_BINARY) + " run " + scenario + " --max-steps 1000 --out " + out.string(),
      dir_ / "log.txt");
  EXPECT_EQ(code, 0) << log();  // the user asked for the limit: not an error
  const Manifest m = read_manifest(out);
  EXPECT_EQ(m.status, cleave::io::run_status::stopped);
  EXPECT_NE(m.reason.find("step 1000 "), std::string::npos) << m.reason;
  EXPECT_NE(m.reason.find("'loading'"), std::string::npos) << m.reason;
  EXPECT_EQ(m.facts.at("stopped_at_step"), "1000");
  EXPECT_EQ(m.facts.at("stopped_in_stage"), "loading");
  EXPECT_EQ(m.facts.at("stage_loading_ended_by"), "max_steps");
  EXPECT_EQ(m.facts.at("dynamics_ending"), "stopped");
  EXPECT_NE(log().find("stopped at step 1000"), std::string::npos) << log();
  expect_files_hashed(out, m);
  // Its files are whole up to the step it stopped at: the exact volume check takes it.
  EXPECT_EQ(shell(std::string(CLEAVE_BINARY) + " check volume --summary " + out.string(),
                  dir_ / "check.txt"),
            0)
      << slurp(dir_ / "check.txt");
}

TEST_F(RunStatus, AStepLimitAtTheRunsOwnLengthIsFinishedAndOneLessIsStopped) {
  const fs::path scenario = write("drop.toml", drop_scenario("drop", "duration = 6e-5\nframes = 2\n"));
  const std::string run_cmd = std::string(CLEAVE_BINARY) + " run --quiet " + scenario.string();
  ASSERT_EQ(shell(run_cmd + " --out " + (dir_ / "whole").string(), dir_ / "log.txt"), 0) << log();
  const Manifest whole = read_manifest(dir_ / "whole");
  ASSERT_EQ(whole.status, "finished");
  const std::uint64_t n = std::stoull(whole.facts.at("dynamics_steps"));
  ASSERT_GT(n, 2u);
  // A limit the run does not reach before its end changes nothing.
  ASSERT_EQ(
      shell(run_cmd + " --max-steps " + std::to_string(n) + " --out " + (dir_ / "at").string(),
            dir_ / "log.txt"),
      0)
      << log();
  const Manifest at = read_manifest(dir_ / "at");
  EXPECT_EQ(at.status, "finished");
  EXPECT_EQ(at.facts.at("final_state_hash"), whole.facts.at("final_state_hash"));
  // One step less: the run (a plain one, its stage "run") did not get to its end.
  ASSERT_EQ(shell(run_cmd + " --max-steps " + std::to_string(n - 1) + " --out " +
                      (dir_ / "short").string(),
                  dir_ / "log.txt"),
            0)
      << log();
  const Manifest cut = read_manifest(dir_ / "short");
  EXPECT_EQ(cut.status, "stopped");
  EXPECT_EQ(cut.facts.at("stopped_at_step"), std::to_string(n - 1));
  EXPECT_EQ(cut.facts.at("stopped_in_stage"), "run");
  EXPECT_EQ(cut.facts.at("dynamics_steps"), std::to_string(n - 1));
}

TEST_F(RunStatus, ABlowUpToInfinityFailsAtItsStepAndWritesNoNonFiniteValue) {
  // Gravity 1e300 m/s^2: after one step a grain's speed is 1.2e294 m/s and its kinetic
  // energy overflows a double. The run fails at step 1 naming the body, and no table holds
  // the infinite row.
  const fs::path scenario =
      write("inf.toml", drop_scenario("drop", "duration = 1e-3\ngravity = [0.0, 0.0, -1e300]\n"));
  const fs::path out = dir_ / "out";
  EXPECT_EQ(run(scenario, out), 1) << log();
  const Manifest m = read_manifest(out);
  EXPECT_EQ(m.status, "failed");
  EXPECT_NE(m.reason.find("step 1 "), std::string::npos) << m.reason;
  EXPECT_NE(m.reason.find("body 0 "), std::string::npos) << m.reason;
  EXPECT_EQ(non_finite_cells(out), std::vector<std::string>{});
  expect_files_hashed(out, m);
}

TEST_F(RunStatus, ANonFiniteWallVelocitySetBetweenStepsFailsThereNamingTheWall) {
  // The library's own door (Python's sim.wall(...).velocity): a NaN velocity given to a
  // wall after step 5. The wall's place is NaN after step 6; nothing it touches need turn
  // NaN (no body is near it), so only the wall can tell.
  const std::string text = drop_scenario("drop", "duration = 1e-4\nframes = 2\n") + R"(
[[wall]]
name = "lid"
kind = "plane"
point = [0.0, 0.0, 60.0]
normal = [0.0, 0.0, -1.0]
)";
  cleave::sim::SimulationOptions options;
  options.out = dir_ / "out";
  options.quiet = true;
  auto sim = cleave::sim::Simulation::from_text(text, "lid.toml", options);
  sim->start();
  ASSERT_EQ(sim->advance(5), 5u);
  cleave::physics::World& world = sim->dynamics()->world();
  ASSERT_EQ(world.walls().size(), 2u);
  ASSERT_EQ(world.walls()[1].name, "lid");
  world.wall(1).velocity = Eigen::Vector3d(0.0, 0.0, std::nan(""));
  const cleave::sim::RunReport report = sim->finish();
  EXPECT_EQ(report.status, cleave::sim::RunReport::Status::failed);
  EXPECT_NE(report.message.find("step 6 "), std::string::npos) << report.message;
  EXPECT_NE(report.message.find("wall 1 ('lid')"), std::string::npos) << report.message;
  EXPECT_NE(report.message.find("velocity"), std::string::npos) << report.message;
  const Manifest m = read_manifest(dir_ / "out");
  EXPECT_EQ(m.status, "failed");
  EXPECT_EQ(m.reason, report.message);
  EXPECT_EQ(non_finite_cells(dir_ / "out"), std::vector<std::string>{});
  EXPECT_TRUE(fs::exists(dir_ / "out" / "load_displacement.csv"));
}
