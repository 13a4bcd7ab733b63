#pragma once
/// \file
/// Catching a run that blows up: after a step, every body's state (pose, velocities, forces),
/// every wall's (place, velocity, reaction) and the periodic cell must be finite, and no
/// body may have moved more than a fraction of its size. An explicit scheme past its
/// stable step (or driven by an absurd load) shows this first; the run should stop there
/// with the step, the body and a time step that would have kept the motion in bounds,
/// rather than write frames of garbage.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "physics/dem/step_listener.hpp"
#include "physics/dem/world.hpp"

namespace cleave::physics {

/// What went wrong in one step, for one wall, the cell or one body (the first found: walls
/// in order, then the cell, then bodies in slot order).
struct BlowUp {
  std::uint64_t step = 0;   ///< the step that produced it (World::steps() after it)
  double time = 0.0;        ///< simulated time after it, s
  BodyId body;
  int grain_id = -1;
  /// A wall's state is not finite (its index in World::walls(); `body` is unset).
  std::optional<std::size_t> wall;
  std::string wall_name;
  bool cell = false;  ///< the periodic cell's vectors are not finite (`body` is unset)
  /// "position", "orientation", "velocity", "angular momentum", "angular velocity", "force"
  /// or "torque" (a wall: "position", "velocity" or "reaction"; the cell: "vectors") when
  /// a value is not finite; empty when the body moved too far.
  std::string non_finite;
  double displacement = 0.0;  ///< largest movement of any point of the body in the step, m
  double fraction = 0.0;      ///< the guard's fraction of the bounding radius
  double limit = 0.0;         ///< fraction x the body's bounding radius, m
  double dt = 0.0;            ///< the time step, s
  /// dt scaled by limit / displacement (movement grows at least linearly with dt, so this
  /// step would have kept it within the limit); dt / 10 for non-finite values.
  double suggested_dt = 0.0;
};

/// Watches a World step by step. Call before_step() before World::step() (or register it
/// with World::add_listener, which calls it) and check() after it. A body's movement in a
/// step is bounded by |dx| + angle(dq) x its bounding radius (no point of a rigid body moves
/// more); it must stay below `fraction` x the bounding radius (default 0.1: a tenth of the body's
/// size per step, far above any sane run: a 1 mm grain at dt = 1e-7 s would need 1000 m/s).
class StepGuard : public StepListener {
 public:
  static constexpr double kDefaultFraction = 0.1;
  explicit StepGuard(double fraction = kDefaultFraction) : fraction_(fraction) {}

  /// Remembers every live body's pose.
  void before_step(const World& world);
  /// As a listener: before each step.
  void before_step(World& world) override { before_step(std::as_const(world)); }
  /// The first body (in slot order) with a non-finite state or a too large movement since
  /// before_step(); none when all is well. Bodies created since (split pieces) are checked
  /// for finite values only. `step_completed` = false: World::step threw part-way (a
  /// non-finite position stops the neighbour search), so the step reported is the one
  /// that was under way, World::steps() + 1.
  [[nodiscard]] std::optional<BlowUp> check(const World& world, bool step_completed = true) const;

  [[nodiscard]] double fraction() const { return fraction_; }

 private:
  struct Pose {
    BodyId id;
    Eigen::Vector3d x;
    Eigen::Quaterniond q;
  };
  double fraction_;
  std::vector<Pose> poses_;
};

/// One line for the user: the step, the time, the body and grain, what went wrong, and the
/// suggested time step (compared with `stable_dt`, the scenario's stable limit, when > 0).
std::string describe(const BlowUp& b, double stable_dt = 0.0);

}  // namespace cleave::physics
