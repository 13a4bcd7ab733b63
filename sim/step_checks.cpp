#include "sim/step_checks.hpp"

#include <algorithm>
#include <array>

namespace cleave::sim {

double max_overlap(const physics::World& world) {
  double overlap = 0.0;
  for (const auto& c : world.contacts()) overlap = std::max(overlap, c.overlap);
  return overlap;
}

StepChecks::StepChecks(double max_move_fraction, double stable_dt,
                       std::function<bool()> stop_requested)
    : guard_(max_move_fraction),
      stable_dt_(stable_dt),
      stop_requested_(std::move(stop_requested)) {}

physics::StepNeeds StepChecks::needs(const physics::World& world) const {
  return check_ ? check_->needs(world) : physics::StepNeeds{};
}

void StepChecks::before_step(physics::World& world) {
  verdict_ = {};
  guard_.before_step(world);
}

void StepChecks::after_step(physics::World& world) {
  judge(world, true);
  if (!verdict_.failure && check_) check_->after_step(world);
}

bool StepChecks::after_throw(physics::World& world) {
  if (!guard_.check(world, false)) return false;
  judge(world, false);
  return true;
}

void StepChecks::judge(physics::World& world, bool completed) {
  if (const auto blow_up = guard_.check(world, completed))
    verdict_.failure = physics::describe(*blow_up, stable_dt_);
  if (physics::Domain* domain = world.domain()) {
    // One reduction a step for what every process must agree on: the largest overlap,
    // a stop request, and whether (and where first) the step blew up.
    const bool stop = stop_requested_ && stop_requested_();
    std::array<double, 3> v{
        max_overlap(world), stop ? 1.0 : 0.0,
        verdict_.failure ? static_cast<double>(domain->size() - domain->rank()) : 0.0};
    domain->max(v);
    verdict_.overlap = v[0];
    verdict_.stop = v[1] > 0.0;
    if (v[2] > 0.0)
      verdict_.failure = domain->first(verdict_.failure);  // the lowest process that saw one
  }
}

}  // namespace cleave::sim
