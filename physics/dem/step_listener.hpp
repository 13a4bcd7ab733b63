#pragma once
/// \file
/// What runs around a step without being physics of its own: boundary ramps, the step guard,
/// the transgranular check. Each registers with World::add_listener and says what the coming
/// step must compute for it, instead of the World growing a switch per user (Jolt's
/// PhysicsStepListener; Box2D's callbacks between collide and solve).

namespace cleave::physics {

class World;

/// What one step computes beyond the forces, because a listener will read it.
struct StepNeeds {
  /// Eq. 2.17's sums (their diagonals) along with the forces: World::stress_sum_diagonals
  /// reads them after the step without walking the contacts again.
  bool stress_sums = false;
  StepNeeds& operator|=(const StepNeeds& other) {
    stress_sums = stress_sums || other.stress_sums;
    return *this;
  }
};

/// Called by World::step, listeners in the order they were added.
class StepListener {
 public:
  virtual ~StepListener() = default;
  /// Before the step: what it must compute for this listener (asked once a step, after
  /// before_step).
  [[nodiscard]] virtual StepNeeds needs(const World& /*world*/) const { return {}; }
  /// Before the step's first half-kick: set what the step reads (wall velocities,
  /// temperatures).
  virtual void before_step(World& /*world*/) {}
  /// After the closing kick, time and step count advanced. Not called when the step threw.
  virtual void after_step(World& /*world*/) {}
};

}  // namespace cleave::physics
