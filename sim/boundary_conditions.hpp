#pragma once
/// \file
/// What a stage of a run drives: its walls' velocities (with their ramp), the thermal quench,
/// the temperature ramp, growing gradient and prescribed field, the periodic cell's strain
/// rate and stress control. What acts in every step is a physics::StepListener registered on
/// the World while the stage runs.

#include <cstdint>
#include <memory>
#include <vector>

#include "io/scenario.hpp"
#include "physics/dem/world.hpp"

namespace cleave::sim {

/// The index of the wall named `name` (the scenario reader checked the names).
std::size_t wall_index(const physics::World& world, const std::string& name);

/// What a stage sets once as it begins: its walls move as it says and the others stand
/// still, its quench, its cell's strain rate (not when `resumed`: the checkpoint's world has
/// them), the cell's stress control (always: it is a setting, not state).
void begin_stage_conditions(physics::World& world, const io::Scenario& scenario,
                            const io::StageDef& stage, bool resumed);

/// A motion stage's conditions that act in every step, registered on `world` (before any
/// step of the stage) and removed when this ends, in the order they act: the wall velocity
/// ramp, the uniform temperature ramp, the growing gradient, the prescribed field. Each
/// counts the stage's steps from `steps_before`, the steps the stage had taken already
/// (a resumed stage), and reads the time step from the World.
class StageConditions {
 public:
  StageConditions(physics::World& world, const io::StageDef& stage, std::uint64_t steps_before);
  ~StageConditions();
  StageConditions(const StageConditions&) = delete;
  StageConditions& operator=(const StageConditions&) = delete;

 private:
  physics::World& world_;
  std::vector<std::unique_ptr<physics::StepListener>> listeners_;
};

}  // namespace cleave::sim
