#pragma once
/// \file
/// The benchmarks' table of where a step's time goes (World::set_timing).

#include <cstdio>

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

}  // namespace cleave::bench
