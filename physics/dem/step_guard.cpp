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
    b.grain_id = world.info(id).grain_id;
    b.dt = world.settings().dt;
    b.fraction = fraction_;
    return b;
  };
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
      b.suggested_dt = b.dt * limit / moved;
      return b;
    }
  }
  return std::nullopt;
}

std::string describe(const BlowUp& b, double stable_dt) {
  std::string what;
  if (!b.non_finite.empty()) {
    what = "its " + b.non_finite + " is not finite (NaN or infinite)";
  } else {
    what = "it moved " + number(b.displacement) + " m in one step, more than " +
           number(b.fraction) + " of its bounding radius (" + number(b.limit) + " m)";
  }
  std::string line = "the run blew up at step " + std::to_string(b.step) + " (t = " +
                     number(b.time) + " s): body " + std::to_string(b.body.index) +
                     (b.grain_id >= 0 ? " (grain " + std::to_string(b.grain_id) + ")" : "") + ": " +
                     what + "; dt = " + number(b.dt) + " s, suggested dt <= " +
                     number(b.suggested_dt) + " s";
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
