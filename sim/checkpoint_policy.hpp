#pragma once
/// \file
/// When a run hands its state to RunHooks for a checkpoint (every N steps, and once when a
/// stop is requested; on several processes the whole world is gathered first), and the run
/// loop's own state in a checkpoint (RunPoint::run_state): the stage under way, the summary
/// so far, the histories and the frame series.

#include <cstdint>
#include <string>

#include "io/scenario.hpp"
#include "physics/dem/world.hpp"
#include "sim/dynamics.hpp"
#include "sim/frames.hpp"
#include "sim/run_history.hpp"
#include "sim/stage_plan.hpp"

namespace cleave::sim {

class CheckpointPolicy {
 public:
  explicit CheckpointPolicy(const RunHooks& hooks) : hooks_(hooks) {}
  /// After a step, its fracture check, its history row and frame: every checkpoint_every
  /// steps (counted in World::steps).
  void after_step(physics::World& world, const RunPoint& point) const;
  /// A stop was requested: the checkpoint a restart continues from, before the outputs.
  void on_interrupt(physics::World& world, const RunPoint& point) const;

 private:
  const RunHooks& hooks_;
};

/// The run loop's state besides the world: what encode_run_state saves and
/// decode_run_state restores.
struct RunState {
  std::size_t& stage_index;  ///< in the scenario's stages (0 for a plain run)
  std::string& stage;        ///< its name
  DynamicsSummary& summary;
  RunHistory& history;
  FrameWriter& frames;
};

/// The loop's state inside stage `progress`, for RunPoint::run_state.
std::string encode_run_state(const RunState& s, const StageProgress& progress);
/// Takes back what encode_run_state saved into `s`; returns the progress of the stage it was
/// in. Throws std::runtime_error when it does not fit the scenario or the world.
StageProgress decode_run_state(const std::string& bytes, const RunState& s,
                               const io::Scenario& scenario, const physics::World& world);

}  // namespace cleave::sim
