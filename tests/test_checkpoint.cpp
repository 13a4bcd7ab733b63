// Checkpoint and restart: a run stopped part-way and continued from its checkpoint ends in
// exactly the state (World::state_hash) and with exactly the histories of the same run done
// without a stop; a checkpoint that is truncated, corrupted or of another version is refused
// with an error naming the file and what is wrong.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "sim/dynamics.hpp"
#include "geometry/exact_polyhedron.hpp"
#include "geometry/specimen.hpp"
#include "io/checkpoint.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "physics/dem/rigid_shape.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"

extern char** environ;

namespace fs = std::filesystem;
using namespace cleave;

namespace {

const fs::path kScenario = fs::path(CLEAVE_SOURCE_DIR) / "tests" / "data" / "checkpoint_brazilian.toml";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The meta data the checkpoints of a run of `source` carry.
io::CheckpointMeta meta_of(const fs::path& source) {
  io::CheckpointMeta meta;
  meta.cleave_version = "test";
  meta.scenario_source = source.string();
  meta.scenario_text = slurp(source);
  return meta;
}

class Checkpoint : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("cleave_checkpoint_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  /// A small world (two prisms resting on a floor, moving), stepped a little: enough state
  /// for the file-format tests.
  static physics::World small_world() {
    physics::WorldSettings ws;
    ws.dt = 1e-6;
    ws.particle_particle.kn = ws.particle_wall.kn = 1e3;
    ws.particle_particle.ks = ws.particle_wall.ks = 400;
    physics::World world(ws);
    const auto prism = geometry::ExactPolyhedron::hexagonal_prism(1e-3, 1e-3);
    const std::uint32_t shape = world.add_shape(physics::make_rigid_shape(prism, 1e-4));
    world.add_wall(physics::Wall::plane("floor", Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()));
    world.add_body(shape, 3100, {0, 0, 0.6e-3}, Eigen::Quaterniond::Identity(), {0.01, 0, -0.02});
    world.add_body(shape, 3100, {1.6e-3, 0, 0.62e-3}, Eigen::Quaterniond::Identity(), {-0.01, 0, 0},
                   {0, 0, 3});
    for (int i = 0; i < 50; ++i) world.step();
    return world;
  }

  static std::string small_checkpoint() {
    const physics::World world = small_world();
    io::CheckpointMeta meta;
    meta.cleave_version = "test";
    meta.scenario_source = "small.toml";
    meta.scenario_text = "# none\n";
    return io::encode_checkpoint(meta, world, nullptr, "run state");
  }

  /// The message of the CheckpointError reading `file` throws ("" when none).
  static std::string read_error(const fs::path& file) {
    try {
      io::read_checkpoint(file);
    } catch (const io::CheckpointError& e) {
      return e.what();
    }
    return "";
  }

  fs::path write(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return dir_ / name;
  }

  // ---- the CLI ------------------------------------------------------------------------
  pid_t spawn(const std::vector<std::string>& args) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    const std::string log = (dir_ / "log.txt").string();
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    std::vector<std::string> all = {CLEAVE_BINARY};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = -1;
    EXPECT_EQ(posix_spawn(&pid, CLEAVE_BINARY, &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
    return pid;
  }
  static int wait_for(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }
  std::string log() const { return slurp(dir_ / "log.txt"); }

  fs::path dir_;
};

/// The first step at which bonds have broken and a grain has split, the world's state
/// hash there, and the run's final summary.
struct StoppedRun {
  std::uint64_t step = 0;
  std::size_t breaks = 0, pieces = 0;
  sim::DynamicsSummary summary;
};

}  // namespace

TEST_F(Checkpoint, WorldStateRoundTripsBitForBitAndStepsOnIdentically) {
  physics::World a = small_world();
  physics::StateWriter w;
  a.save_state(w);
  physics::World b;
  physics::StateReader r(w.bytes());
  b.load_state(r);
  EXPECT_TRUE(r.done());
  EXPECT_EQ(a.state_hash(), b.state_hash());
  for (int i = 0; i < 200; ++i) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.state_hash(), b.state_hash());
  EXPECT_EQ(a.steps(), b.steps());
  // The hash sees the state: one more step of one world changes it.
  a.step();
  EXPECT_NE(a.state_hash(), b.state_hash());
}

TEST_F(Checkpoint, ABondsOwnStrengthAndStiffnessSurviveTheRoundTrip) {
  physics::World a = small_world();
  physics::BondParams bp;
  bp.kbn = 1e12;
  bp.kbs = 4e11;
  bp.tbn = bp.tbs = 1e6;
  ASSERT_GT(a.initialise_bonds(bp, 1e-3), 0u);
  a.set_bond_strength(0, 0.37);
  a.set_bond_stiffness(0, 2.75);
  EXPECT_THROW(a.set_bond_strength(0, 0.0), std::invalid_argument);
  EXPECT_THROW(a.set_bond_stiffness(0, -1.0), std::invalid_argument);
  physics::StateWriter w;
  a.save_state(w);
  physics::World b;
  physics::StateReader r(w.bytes());
  b.load_state(r);
  ASSERT_EQ(b.bonds().size(), a.bonds().size());
  EXPECT_EQ(b.bonds()[0].strength, 0.37);
  EXPECT_EQ(b.bonds()[0].stiffness, 2.75);
  for (std::size_t k = 1; k < b.bonds().size(); ++k) EXPECT_EQ(b.bonds()[k].stiffness, 1.0);
}

TEST_F(Checkpoint, BrazilianDiscRestartedAfterBondsBrokeAndAGrainSplitEndsWithTheSameHash) {
  const io::Scenario scenario = io::load_scenario(kScenario);
  const geometry::Specimen specimen = geometry::build_specimen(scenario.specimen);

  // 1. The run without interruption.
  const fs::path whole = dir_ / "whole";
  const sim::DynamicsSummary reference = sim::run_dynamics(scenario, specimen, whole, true);
  ASSERT_EQ(reference.ending, sim::RunEnding::completed);
  ASSERT_GT(reference.bond_counts.broken(), 0u);
  ASSERT_GT(reference.splits, 0u);

  // 2. The same run, stopped (with a checkpoint) at the first step after which bonds have
  //    broken and a grain has split, mid-loading.
  const fs::path part = dir_ / "part";
  const fs::path file = part / io::kCheckpointName;
  const io::CheckpointMeta meta = meta_of(kScenario);
  StoppedRun stopped;
  bool stop = false;
  sim::RunHooks hooks;
  hooks.checkpoint_every = 1;
  hooks.on_checkpoint = [&](const sim::RunPoint& p) {
    if (stop || p.stage != "loading" || p.world.bond_breaks().empty() || !p.book) return;
    std::size_t pieces = 0;
    for (const auto& e : p.book->entries(p.world)) pieces += e.lineage.path.empty() ? 0 : 1;
    if (pieces == 0) return;
    stopped.step = p.world.steps();
    stopped.breaks = p.world.bond_breaks().size();
    stopped.pieces = pieces;
    io::write_checkpoint_file(file, io::encode_checkpoint(meta, p.world, p.book, p.run_state()));
    stop = true;
  };
  hooks.stop_requested = [&] { return stop; };
  stopped.summary = sim::run_dynamics(scenario, specimen, part, true, 0, hooks);
  ASSERT_EQ(stopped.summary.ending, sim::RunEnding::interrupted);
  ASSERT_GT(stopped.step, 0u) << "no step had both a broken bond and a split grain";
  EXPECT_GT(stopped.breaks, 0u);
  EXPECT_GT(stopped.pieces, 0u);
  EXPECT_LT(stopped.step + 100, reference.steps) << "the checkpoint should sit well before the end";
  EXPECT_NE(stopped.summary.state_hash, reference.state_hash);

  // 3. Restarted from the checkpoint into the same folder: the same end, bit for bit.
  io::Checkpoint ck = io::read_checkpoint(part);
  EXPECT_EQ(ck.world.steps(), stopped.step);
  EXPECT_EQ(ck.meta.scenario_text, meta.scenario_text);
  ASSERT_TRUE(ck.book.has_value());
  sim::RunResume resume{std::move(ck.world), std::move(ck.book), std::move(ck.run_state)};
  const sim::DynamicsSummary restarted =
      sim::run_dynamics(scenario, specimen, part, true, 0, {}, &resume);
  EXPECT_EQ(restarted.ending, sim::RunEnding::completed);
  EXPECT_EQ(restarted.state_hash, reference.state_hash);
  EXPECT_EQ(restarted.steps, reference.steps);
  EXPECT_EQ(restarted.time, reference.time);
  EXPECT_EQ(restarted.splits, reference.splits);
  EXPECT_EQ(restarted.bond_counts.broken(), reference.bond_counts.broken());
  EXPECT_EQ(restarted.peak_load, reference.peak_load);
  EXPECT_EQ(restarted.frames, reference.frames);
  EXPECT_EQ(restarted.final_pieces.size(), reference.final_pieces.size());
  // The histories continue as if never stopped: the same files, byte for byte.
  for (const char* f : {"load_displacement.csv", "energy.csv", "walls.csv", "bonds.csv", "bond_breaks.csv",
                        "splits.csv", "cracks.csv", "bodies.pvd", "cracks.pvd"}) {
    EXPECT_TRUE(slurp(part / f) == slurp(whole / f)) << f << " differs after the restart";
  }
  // The crack areas are made again from the world and the fracture book: the same bits, and
  // the crack surfaces drawn after the restart (their areas and opening times) the same.
  EXPECT_EQ(restarted.cracks.intergranular_area, reference.cracks.intergranular_area);
  EXPECT_EQ(restarted.cracks.transgranular_area, reference.cracks.transgranular_area);
  EXPECT_GT(reference.cracks.transgranular_area, 0.0);
  ASSERT_EQ(restarted.stages.size(), reference.stages.size());
  for (std::size_t k = 0; k < reference.stages.size(); ++k) {
    EXPECT_EQ(restarted.stages[k].cracks_at_peak.transgranular_area,
              reference.stages[k].cracks_at_peak.transgranular_area);
    EXPECT_EQ(restarted.stages[k].cracks_start.intergranular, reference.stages[k].cracks_start.intergranular);
  }
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(whole / "frames")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("cracks_", 0) != 0) continue;
    ++frames;
    EXPECT_TRUE(slurp(part / "frames" / name) == slurp(entry.path())) << name << " differs after the restart";
  }
  EXPECT_GT(frames, 0);
}

TEST_F(Checkpoint, SigtermLeavesACheckpointThatRestartsToTheUninterruptedHash) {
  // The uninterrupted run, through the CLI.
  const fs::path whole = dir_ / "whole";
  ASSERT_EQ(wait_for(spawn({"run", kScenario.string(), "--out", whole.string(), "--quiet"})), 0) << log();
  const io::Manifest reference = io::read_manifest(whole);
  ASSERT_EQ(reference.status, "finished");
  const std::string hash = reference.facts.at("final_state_hash");
  const auto total = std::stoull(reference.facts.at("dynamics_steps"));

  // The same run, with periodic checkpoints, killed by SIGTERM once one is there.
  const fs::path out = dir_ / "out";
  const pid_t pid = spawn({"run", kScenario.string(), "--out", out.string(), "--quiet", "--checkpoint-every", "200"});
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(out / io::kCheckpointName) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(fs::exists(out / io::kCheckpointName)) << log();
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  ASSERT_EQ(wait_for(pid), 128 + SIGTERM) << "the run ended before the signal came: " << log();
  const io::Manifest stopped = io::read_manifest(out);
  EXPECT_EQ(stopped.status, "interrupted");
  EXPECT_EQ(stopped.facts.at("dynamics_ending"), "interrupted");
  const auto at = std::stoull(stopped.facts.at("dynamics_steps"));
  EXPECT_LT(at, total);
  // The checkpoint is the state at the stop (written on the signal), not the last periodic one.
  const io::Checkpoint ck = io::read_checkpoint(out / io::kCheckpointName);
  EXPECT_EQ(ck.world.steps(), at);
  EXPECT_FALSE(fs::exists(out / "checkpoint.tmp"));
  // The message names the command that continues it, even with --quiet.
  EXPECT_NE(log().find("continue it with: cleave restart " + out.string()), std::string::npos) << log();

  // `cleave restart DIR` continues it to the end: the same final state and histories.
  ASSERT_EQ(wait_for(spawn({"restart", out.string(), "--quiet"})), 0) << log();
  const io::Manifest finished = io::read_manifest(out);
  EXPECT_EQ(finished.status, "finished");
  EXPECT_EQ(finished.facts.at("final_state_hash"), hash);
  EXPECT_EQ(finished.facts.at("dynamics_steps"), reference.facts.at("dynamics_steps"));
  EXPECT_EQ(finished.facts.at("transgranular_splits"), reference.facts.at("transgranular_splits"));
  EXPECT_EQ(finished.provenance.at("restarted_at_step"), std::to_string(at));
  for (const char* f : {"load_displacement.csv", "bond_breaks.csv", "splits.csv", "geometry.exact"}) {
    EXPECT_TRUE(slurp(out / f) == slurp(whole / f)) << f << " differs after the restart";
  }
}

TEST_F(Checkpoint, ATruncatedCheckpointSaysWhereItEnds) {
  const std::string bytes = small_checkpoint();
  const fs::path good = write("good", bytes);
  EXPECT_EQ(read_error(good), "");
  for (const std::size_t keep : {bytes.size() - 1, bytes.size() / 2, std::size_t{30}, std::size_t{10}}) {
    const fs::path cut = write("cut", bytes.substr(0, keep));
    const std::string e = read_error(cut);
    EXPECT_NE(e.find(cut.string()), std::string::npos) << e;
    EXPECT_NE(e.find("truncated at byte " + std::to_string(keep)), std::string::npos) << e;
  }
  const fs::path empty = write("empty", "");
  EXPECT_NE(read_error(empty).find("truncated at byte 0"), std::string::npos);
}

TEST_F(Checkpoint, ABitFlippedCheckpointFailsItsChecksum) {
  const std::string bytes = small_checkpoint();
  // A bit in the payload (a body's position), one in the middle, one in the checksum itself.
  for (const std::size_t at : {std::size_t{100}, bytes.size() / 2, bytes.size() - 3}) {
    std::string bad = bytes;
    bad[at] = static_cast<char>(bad[at] ^ 0x10);
    const fs::path file = write("flipped", bad);
    const std::string e = read_error(file);
    EXPECT_NE(e.find(file.string()), std::string::npos) << e;
    EXPECT_NE(e.find("checksum mismatch"), std::string::npos) << at << ": " << e;
  }
}

TEST_F(Checkpoint, OtherVersionsAndOtherFilesAreRefusedByName) {
  std::string bytes = small_checkpoint();
  const auto next = static_cast<char>(io::kCheckpointVersion + 1);  // a version not yet made
  bytes[8] = next;  // the version field
  EXPECT_NE(read_error(write("next", bytes)).find("version " + std::to_string(next) + " not supported"),
            std::string::npos);
  // Version 3, before each bond had its stiffness factor, is refused, naming this one.
  bytes[8] = 3;
  EXPECT_NE(read_error(write("v3", bytes)).find("version 3 not supported (this cleave reads version 4)"),
            std::string::npos);
  const std::string e = read_error(write("text", "this is not a checkpoint at all, just some text"));
  EXPECT_NE(e.find("not a cleave checkpoint"), std::string::npos) << e;
  EXPECT_NE(read_error(dir_ / "missing").find("cannot be read"), std::string::npos);
}

TEST_F(Checkpoint, TheCliRefusesABadCheckpointWithItsErrorAndNoCrash) {
  std::string bytes = small_checkpoint();
  const fs::path file = write("checkpoint", bytes.substr(0, bytes.size() - 10));
  EXPECT_EQ(wait_for(spawn({"restart", file.string(), "--quiet"})), 2);
  const std::string text = log();
  EXPECT_NE(text.find("cannot restart"), std::string::npos) << text;
  EXPECT_NE(text.find("truncated at byte " + std::to_string(bytes.size() - 10)), std::string::npos) << text;
}

TEST_F(Checkpoint, AWriteKeepsTheLastGoodCheckpointUntilTheNewOneIsComplete) {
  const std::string first = small_checkpoint();
  const fs::path file = dir_ / "checkpoint";
  io::write_checkpoint_file(file, first);
  // A write that cannot complete (its temporary name is taken by a folder) leaves the last
  // good checkpoint in place and readable.
  fs::create_directories(dir_ / "checkpoint.tmp");
  EXPECT_THROW(io::write_checkpoint_file(file, first + "more"), io::CheckpointError);
  EXPECT_EQ(slurp(file), first);
  EXPECT_EQ(read_error(file), "");
}

TEST_F(Checkpoint, ACoolingPolycrystalRestartedMidCoolingEndsWithTheSameHashAndThermalHistory) {
  // scenarios/thermal_microcracking.toml stopped once bonds have cracked on cooling and
  // continued from its checkpoint: temperatures, expansion tensors, thermal gaps and the
  // thermal.csv history carry over bit for bit.
  const fs::path source = fs::path(CLEAVE_SOURCE_DIR) / "scenarios" / "thermal_microcracking.toml";
  const io::Scenario scenario = io::load_scenario(source);
  const geometry::Specimen specimen = geometry::build_specimen(scenario.specimen);
  const fs::path whole = dir_ / "whole";
  const sim::DynamicsSummary reference = sim::run_dynamics(scenario, specimen, whole, true);
  ASSERT_EQ(reference.ending, sim::RunEnding::completed);
  ASSERT_GT(reference.bond_counts.broken(), 0u);

  const fs::path part = dir_ / "part";
  const io::CheckpointMeta meta = meta_of(source);
  bool stop = false;
  std::uint64_t stopped_at = 0;
  sim::RunHooks hooks;
  hooks.checkpoint_every = 1;
  hooks.on_checkpoint = [&](const sim::RunPoint& p) {
    if (stop || p.stage != "cool" || p.world.bond_breaks().empty()) return;
    stopped_at = p.world.steps();
    io::write_checkpoint_file(part / io::kCheckpointName, io::encode_checkpoint(meta, p.world, p.book, p.run_state()));
    stop = true;
  };
  hooks.stop_requested = [&] { return stop; };
  ASSERT_EQ(sim::run_dynamics(scenario, specimen, part, true, 0, hooks).ending, sim::RunEnding::interrupted);
  ASSERT_GT(stopped_at, 0u);
  EXPECT_LT(stopped_at + 100, reference.steps);

  io::Checkpoint ck = io::read_checkpoint(part);
  EXPECT_TRUE(ck.world.thermal());
  sim::RunResume resume{std::move(ck.world), std::move(ck.book), std::move(ck.run_state)};
  const sim::DynamicsSummary restarted = sim::run_dynamics(scenario, specimen, part, true, 0, {}, &resume);
  EXPECT_EQ(restarted.ending, sim::RunEnding::completed);
  EXPECT_EQ(restarted.state_hash, reference.state_hash);
  EXPECT_EQ(restarted.bond_counts.broken(), reference.bond_counts.broken());
  for (const char* f : {"thermal.csv", "bonds.csv", "bond_breaks.csv", "energy.csv"}) {
    EXPECT_TRUE(slurp(part / f) == slurp(whole / f)) << f << " differs after the restart";
  }
}
