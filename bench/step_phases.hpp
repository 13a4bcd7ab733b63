#pragma once
/// \file
/// The benchmarks' table of where a step's time goes (World::set_timing).

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "physics/dem/world.hpp"

namespace cleave::bench {

/// Prints each part's milliseconds a step and share of the step, under `title`.
inline void print_phases(const char* title, const physics::StepTimings& t) {
  if (t.steps == 0) return;
  const double total = t.total();
  std::printf("  %s: %.3f ms/step over %llu steps\n", title, 1e3 * total / static_cast<double>(t.steps),
              static_cast<unsigned long long>(t.steps));
  for (std::size_t k = 0; k < physics::kStepPhases; ++k) {
    if (t.seconds[k] == 0.0) continue;
    std::printf("    %-13s %8.3f ms/step %5.1f %%\n", physics::to_string(static_cast<physics::StepPhase>(k)),
                1e3 * t.seconds[k] / static_cast<double>(t.steps), total > 0.0 ? 100.0 * t.seconds[k] / total : 0.0);
  }
}

/// CLEAVE_BENCH_ALTERNATE=1: the timed steps alternate between the lanes on (even steps) and
/// off (odd steps, WorldSettings::lanes), each phase's time summed by parity. The machine's
/// speed swings by tens of percent within a minute; alternating step by step puts its swings
/// on both sides alike, so the two columns compare the code and not the moment.
class LaneAlternation {
 public:
  LaneAlternation() {
    const char* env = std::getenv("CLEAVE_BENCH_ALTERNATE");
    on_ = env != nullptr && std::string(env) != "0";
  }
  [[nodiscard]] bool on() const { return on_; }
  /// One step of `world` (timing on), its phases added to the side it ran on.
  void step(physics::World& world) {
    if (!on_) {
      world.step();
      return;
    }
    const bool lanes = steps_ % 2 == 0;
    world.set_lanes(lanes);
    const physics::StepTimings before = world.timings();
    world.step();
    const physics::StepTimings& after = world.timings();
    physics::StepTimings& side = lanes ? with_ : without_;
    for (std::size_t k = 0; k < physics::kStepPhases; ++k)
      side.seconds[k] += after.seconds[k] - before.seconds[k];
    side.steps += after.steps - before.steps;
    ++steps_;
    world.set_lanes(true);
  }
  /// The two sides' phases, in ms summed over each side's steps, and how much less the lanes take.
  void print() const {
    if (!on_ || with_.steps == 0 || without_.steps == 0) return;
    std::printf(
        "  alternated step by step (CLEAVE_BENCH_ALTERNATE), ms summed over %llu steps each:\n",
        static_cast<unsigned long long>(std::min(with_.steps, without_.steps)));
    std::printf("    %-13s %10s %10s %7s\n", "phase", "lanes on", "lanes off", "less");
    for (std::size_t k = 0; k < physics::kStepPhases; ++k) {
      if (with_.seconds[k] == 0.0 && without_.seconds[k] == 0.0) continue;
      print_row(physics::to_string(static_cast<physics::StepPhase>(k)), with_.seconds[k],
                without_.seconds[k]);
    }
    print_row("step", with_.total(), without_.total());
    std::fflush(stdout);  // (a benchmark's child process leaves without flushing)
  }

 private:
  static void print_row(const char* name, double on, double off) {
    std::printf("    %-13s %10.2f %10.2f %6.1f%%\n", name, 1e3 * on, 1e3 * off,
                off > 0.0 ? 100.0 * (1.0 - on / off) : 0.0);
  }
  bool on_ = false;
  std::uint64_t steps_ = 0;
  physics::StepTimings with_, without_;
};

}  // namespace cleave::bench
