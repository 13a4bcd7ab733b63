#include "physics/dem/step_clock.hpp"

#include <chrono>

namespace cleave::physics {

namespace {
std::int64_t clock_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

const char* to_string(StepPhase phase) {
  static constexpr const char* kNames[kStepPhases] = {
      "kick_drift",  "poses",        "pair_search", "plan",      "narrow",  "walls",
      "contact_law", "contact_sums", "bond_law",    "bond_sums", "damping", "closing_kick"};
  const auto k = static_cast<std::size_t>(phase);
  return k < kStepPhases ? kNames[k] : "unknown";
}

void StepClock::start_step() {
  if (!on_) return;
  in_step_ = true;
  lap_ns_ = clock_ns();
}

void StepClock::lap_to(StepPhase phase) {
  const std::int64_t now = clock_ns();
  timings_.seconds[static_cast<std::size_t>(phase)] += 1e-9 * static_cast<double>(now - lap_ns_);
  lap_ns_ = now;
}

}  // namespace cleave::physics
