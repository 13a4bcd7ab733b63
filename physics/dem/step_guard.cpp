#include "physics/dem/step_guard.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace cleave::physics {

namespace {

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

/// The first non-finite part of a body's state, or nullptr.
const char* non_finite_part(const BodyState& s) {
  if (!finite(s.x)) return "position";
  if (!s.q.coeffs().allFinite()) return "orientation";
  if (!finite(s.v)) return "velocity";
  if (!finite(s.L)) return "angular momentum";
  if (!finite(s.w)) return "angular velocity";
  if (!finite(s.f)) return "force";
  if (!finite(s.tau)) return "torque";
  return nullptr;
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

}  // namespace

void StepGuard::before_step(const World& world) {
  poses_.clear();
  for (const BodyId id : world.body_ids()) {
    if (!world.owns(id.index)) continue;  // one process of several watches its own bodies
    const BodyState& s = world.state(id);
    poses_.push_back({id, s.x, s.q});
  }
}

std::optional<BlowUp> StepGuard::check(const World& world, bool step_completed) const {
  auto blow_up = [&](BodyId id) {
    BlowUp b;
    b.step = world.steps() + (step_completed ? 0 : 1);
    b.time = world.time() + (step_completed ? 0.0 : world.settings().dt);
    b.body = id;
    if (id.valid()) b.grain_id = world.info(id).grain_id;
    b.dt = world.settings().dt;
    b.fraction = fraction_;
    return b;
  };
  // Walls first: a wall gone wrong (a non-finite velocity set between steps) is the cause
  // of what its bodies do next. A handful of walls: no cost worth counting.
  for (std::size_t i = 0; i < world.walls().size(); ++i) {
    const Wall& w = world.walls()[i];
    const char* part = !finite(w.velocity)   ? "velocity"  // the cause before its effect
                       : !finite(w.origin)   ? "position"
                       : !finite(w.reaction) ? "reaction"
                                             : nullptr;
    if (part) {
      BlowUp b = blow_up(BodyId{});
      b.wall = i;
      b.wall_name = w.name;
      b.non_finite = part;
      b.displacement = std::numeric_limits<double>::quiet_NaN();
      return b;
    }
  }
  if (const PeriodicCell* cell = world.cell(); cell && !cell->vectors().allFinite()) {
    BlowUp b = blow_up(BodyId{});
    b.cell = true;
    b.non_finite = "vectors";
    b.displacement = std::numeric_limits<double>::quiet_NaN();
    b.suggested_dt = b.dt / 10.0;
    return b;
  }
  std::size_t k = 0;  // poses_ and body_ids() are both in slot order
  for (const BodyId id : world.body_ids()) {
    if (!world.owns(id.index)) continue;
    const BodyState& s = world.state(id);
    if (const char* part = non_finite_part(s)) {
      BlowUp b = blow_up(id);
      b.non_finite = part;
      b.displacement = std::numeric_limits<double>::quiet_NaN();
      b.limit = fraction_ * world.shape(world.info(id).shape).bounding_radius();
      b.suggested_dt = b.dt / 10.0;
      return b;
    }
    while (k < poses_.size() && poses_[k].id.index < id.index) ++k;
    if (k == poses_.size() || !(poses_[k].id == id)) continue;  // a new body (split piece)
    const Pose& before = poses_[k];
    const double radius = world.shape(world.info(id).shape).bounding_radius();
    const double turn = before.q.angularDistance(s.q);
    Eigen::Vector3d dx = s.x - before.x;
    // In a periodic cell a body that left through a face came back through the other.
    if (const PeriodicCell* cell = world.cell()) dx += cell->shift(cell->nearest_image(before.x, s.x));
    const double moved = dx.norm() + turn * radius;
    const double limit = fraction_ * radius;
    if (moved > limit) {
      BlowUp b = blow_up(id);
      b.displacement = moved;
      b.limit = limit;
      // A movement too large for a double (inf) gives no scale: a tenth of dt, as for NaN.
      b.suggested_dt = std::isfinite(moved) ? b.dt * limit / moved : b.dt / 10.0;
      return b;
    }
  }
  return std::nullopt;
}

std::string describe(const BlowUp& b, double stable_dt) {
  if (b.wall) {
    // A wall moves as it is told: the cause is its prescribed motion, not the time step.
    return "the run blew up at step " + std::to_string(b.step) + " (t = " + number(b.time) +
           " s): wall " + std::to_string(*b.wall) + " ('" + b.wall_name + "'): its " +
           b.non_finite +
           " is not finite (NaN or infinite); a wall moves as prescribed (its stage's "
           "wall_velocity, "
           "or a velocity or place set between steps)";
  }
  std::string what;
  if (!b.non_finite.empty()) {
    what = "its " + b.non_finite + " is not finite (NaN or infinite)";
  } else {
    what = "it moved " + number(b.displacement) + " m in one step, more than " +
           number(b.fraction) + " of its bounding radius (" + number(b.limit) + " m)";
  }
  const std::string who =
      b.cell ? std::string("the periodic cell")
             : "body " + std::to_string(b.body.index) +
                   (b.grain_id >= 0 ? " (grain " + std::to_string(b.grain_id) + ")" : "");
  std::string line = "the run blew up at step " + std::to_string(b.step) +
                     " (t = " + number(b.time) + " s): " + who + ": " + what +
                     "; dt = " + number(b.dt) + " s, suggested dt <= " + number(b.suggested_dt) +
                     " s";
  if (stable_dt > 0.0) {
    line += b.dt > stable_dt
                ? "; the stable step (critical step x dt_safety) is " + number(stable_dt) +
                      " s and dt is above it: use dt <= " +
                      number(std::min(stable_dt, b.suggested_dt)) + " s"
                : "; dt is within the stable step (critical step x dt_safety = " +
                      number(stable_dt) + " s), so look at the loads too (wall speeds, gravity, "
                      "stiffnesses)";
  }
  return line;
}

}  // namespace cleave::physics
