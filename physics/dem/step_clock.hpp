#pragma once
/// \file
/// The step's stages by name, and the clock that times them (World::set_timing).

#include <cstddef>
#include <cstdint>

namespace cleave::physics {

/// The stages of World::step, in the order a step runs them; their names label the timings.
enum class StepPhase : unsigned char {
  kick_drift,    ///< first half kick and drift (and a periodic cell's deformation)
  poses,         ///< bodies posed, walls in reach, the search's staleness test
  pair_search,   ///< the neighbour search, when the skin is used up
  plan,          ///< manifolds: which pairs carry their contacts, which bodies need vertices
  narrow,        ///< the narrow phase (or carried contacts), pair by pair
  walls,         ///< wall contacts, the contact lists joined
  contact_law,   ///< eqs 2.3-2.8 on every contact
  contact_sums,  ///< contact forces and torques summed onto the bodies
  bond_law,      ///< eqs 2.9-2.16 on every bond (and the breaks logged)
  bond_sums,     ///< bond forces and torques summed onto the bodies
  damping,       ///< stress-criterion breaks, in-plane hold, local damping, domain exchange
  closing_kick,  ///< second half kick, heat conduction
};
inline constexpr std::size_t kStepPhases = 12;
/// Lower-case name of a phase ("narrow", "bond_law", ...).
const char* to_string(StepPhase phase);

/// Wall-clock seconds spent in each part of World::step while timing was on (Yade's
/// timing.stats(), for one world): `seconds[phase]`, and the steps they cover.
struct StepTimings {
  double seconds[kStepPhases] = {};
  std::uint64_t steps = 0;
  [[nodiscard]] double total() const {
    double t = 0.0;
    for (double s : seconds) t += s;
    return t;
  }
};

/// Times the stages of the steps while on: each lap adds the time since the last to a stage.
/// Laps count only inside a step (between start_step and end_step).
class StepClock {
 public:
  /// On: the sums start from zero. Off by default (a clock read per stage and step when on).
  void set_on(bool on) {
    on_ = on;
    if (on) timings_ = StepTimings{};
  }
  [[nodiscard]] bool on() const { return on_; }
  /// A step (or its part after an untimed first force evaluation) starts now.
  void start_step();
  /// What follows is not a step's (the first force evaluation).
  void pause() { in_step_ = false; }
  /// Adds the time since the last lap to `phase`.
  void lap(StepPhase phase) {
    if (on_ && in_step_) lap_to(phase);
  }
  /// The step is over: it counts when it was timed.
  void end_step() {
    if (in_step_) ++timings_.steps;
    in_step_ = false;
  }
  [[nodiscard]] const StepTimings& timings() const { return timings_; }

 private:
  void lap_to(StepPhase phase);
  StepTimings timings_;
  bool on_ = false, in_step_ = false;
  std::int64_t lap_ns_ = 0;
};

}  // namespace cleave::physics
