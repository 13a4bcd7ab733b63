#include "sim/checkpoint_policy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace cleave::sim {

namespace {

/// The layout of the run state in a checkpoint.
constexpr std::uint32_t kRunStateLayout = 4;  // 2: thermal.csv; 3: cell.csv, modulus.csv;
                                              // 4: cracks.csv, the stages' crack totals

}  // namespace

void CheckpointPolicy::after_step(physics::World& world, const RunPoint& point) const {
  if (!hooks_.on_checkpoint || hooks_.checkpoint_every == 0 ||
      world.steps() % hooks_.checkpoint_every != 0)
    return;
  if (world.domain()) world.domain()->gather_all(world);  // the whole world into the checkpoint
  hooks_.on_checkpoint(point);
}

void CheckpointPolicy::on_interrupt(physics::World& world, const RunPoint& point) const {
  if (!hooks_.on_interrupt) return;
  if (world.domain()) world.domain()->gather_all(world);
  hooks_.on_interrupt(point);
}

std::string encode_run_state(const RunState& s, const StageProgress& progress) {
  physics::StateWriter w;
  w.put(kRunStateLayout);
  w.put<std::uint64_t>(s.stage_index);
  w.put(s.stage);
  put_progress(w, progress);
  w.put<std::int32_t>(s.frames.frames());
  w.put(s.summary.max_overlap);
  w.put<std::uint64_t>(s.summary.bonds);
  w.put<std::uint64_t>(s.summary.splits);
  w.count(s.summary.stages.size());
  for (const auto& st : s.summary.stages) put_summary(w, st);
  s.history.put_start(w);
  s.history.put_tables(w);
  w.put(s.frames.last_step());
  s.frames.put_series(w);
  return w.take();
}

StageProgress decode_run_state(const std::string& bytes, const RunState& s,
                               const io::Scenario& scenario, const physics::World& world) {
  physics::StateReader r(bytes);
  StageProgress p;
  try {
    if (const auto layout = r.get<std::uint32_t>(); layout != kRunStateLayout) {
      r.fail(fmt::format("run state layout {} is not supported (this build reads {})", layout,
                         kRunStateLayout));
    }
    s.stage_index = r.get<std::uint64_t>();
    const std::size_t stages = std::max<std::size_t>(1, scenario.stages.size());
    if (s.stage_index >= stages) r.fail("the stage index is beyond the scenario's stages");
    s.stage = r.string();
    const std::string expected =
        scenario.stages.empty() ? "run" : scenario.stages[s.stage_index].name;
    if (s.stage != expected) {
      r.fail(fmt::format("the checkpoint is in stage '{}' but the scenario's stage {} is '{}'",
                         s.stage, s.stage_index + 1, expected));
    }
    p = get_progress(r);
    s.frames.set_frames(r.get<std::int32_t>());
    s.summary.max_overlap = r.get<double>();
    s.summary.bonds = r.get<std::uint64_t>();
    s.summary.splits = r.get<std::uint64_t>();
    s.summary.stages.resize(r.count(8));
    for (auto& st : s.summary.stages) st = get_summary(r);
    s.history.get_start(r);
    s.history.get_tables(r);
    s.frames.set_last_step(r.get<std::uint64_t>());
    s.frames.get_series(r, !world.walls().empty(),
                        scenario.bond.enabled || scenario.fracture.enabled);
    if (!r.done()) r.fail("unread bytes after the run state");
    if (s.history.wall_origins().size() != world.walls().size() ||
        p.stage_origin.size() != world.walls().size()) {
      r.fail("the walls of the run state do not match the world's");
    }
  } catch (const physics::StateError& e) {
    throw std::runtime_error(fmt::format("checkpoint run state: {}", e.what()));
  }
  return p;
}

}  // namespace cleave::sim
