#pragma once
/// \file
/// What is checked after every step of a run, in this order: the step guard (a state that
/// is not finite, or a body that moved too far), the processes' agreement on it and on a
/// stop request, then the transgranular check. The check is a listener of its own kind
/// (physics::TransgranularCheck) but runs through this one, and only after a step the guard
/// passed: a grain never splits from a blown-up state, as when the run loop called it.

#include <functional>
#include <optional>
#include <string>

#include "physics/dem/step_guard.hpp"
#include "physics/dem/world.hpp"
#include "physics/transgranular/transgranular.hpp"

namespace cleave::sim {

/// The largest contact overlap of the last force evaluation (this process's contacts), m.
double max_overlap(const physics::World& world);

/// The verdict on one step.
struct StepVerdict {
  std::optional<std::string> failure;  ///< the blow-up, described (physics::describe)
  /// Several processes: the largest contact overlap of all and whether any was asked to
  /// stop, read in the same reduction as the blow-up.
  std::optional<double> overlap;
  bool stop = false;
};

class StepChecks final : public physics::StepListener {
 public:
  /// `stable_dt`: the stable step, for the blow-up message. `stop_requested` (may be empty)
  /// is asked once a step on several processes, to stop them all after the same step.
  StepChecks(double max_move_fraction, double stable_dt, std::function<bool()> stop_requested);
  /// The transgranular check to run after the steps the guard passes (null: none).
  void set_fracture(physics::TransgranularCheck* check) { check_ = check; }

  [[nodiscard]] physics::StepNeeds needs(const physics::World& world) const override;
  void before_step(physics::World& world) override;
  void after_step(physics::World& world) override;
  /// World::step threw part-way: the guard's verdict on what it left. False when the state
  /// is sound (the exception is then an error of its own, for the caller to rethrow).
  bool after_throw(physics::World& world);

  [[nodiscard]] const StepVerdict& verdict() const { return verdict_; }

 private:
  void judge(physics::World& world, bool completed);

  physics::StepGuard guard_;
  double stable_dt_;
  std::function<bool()> stop_requested_;
  physics::TransgranularCheck* check_ = nullptr;
  StepVerdict verdict_;
};

}  // namespace cleave::sim
