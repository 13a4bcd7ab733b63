// The cubic lattice of the validation tests (seed 002, sec. 7):
//   ./build/bench/cleave_bench_lattice [SCENARIO] [STEPS]
// (default scenarios/validation/dcb.toml, 2000 steps). Builds the test rig of the scenario,
// runs STEPS steps with 1 and with all threads (from rest, so the weak plane is intact: the
// cost of a step does not depend on it), and prints bodies, links, microseconds per step,
// nanoseconds per link and steps per second, and the wall time a whole validation run of
// that scenario takes at this rate.

#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "io/validation_scenario.hpp"
#include "validation/beam_test_rig.hpp"

using namespace cleave;

int main(int argc, char** argv) {
  const std::string file =
      argc > 1 ? argv[1] : std::string(CLEAVE_SOURCE_DIR) + "/scenarios/validation/dcb.toml";
  const int steps = argc > 2 ? std::atoi(argv[2]) : 2000;
  const io::ValidationScenario v = io::load_validation_scenario(file);
  const int max_threads = omp_get_max_threads();
  std::printf("scenario %s\n", file.c_str());
  for (int threads : {1, max_threads}) {
    omp_set_num_threads(threads);
    physics::BeamTestRig rig(v.rig);
    rig.step();  // first force evaluation
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < steps; ++i) rig.step();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& lat = rig.lattice();
    const double per_step = s / steps;
    const double rate = v.rig.kind == physics::BeamTestKind::dcb ? 2 * v.rig.velocity : v.rig.velocity;
    const double run_steps = (v.deflection / rate + 0.5 * v.rig.ramp_time) / rig.time_step();
    std::printf(
        "threads %d: %d bodies, %zu links, dt %.3g s: %.1f us/step, %.1f ns/link, %.0f steps/s; "
        "a whole run (%.3g steps) would take %.0f s\n",
        threads, lat.size(), lat.links().size(), rig.time_step(), per_step * 1e6,
        per_step * 1e9 / static_cast<double>(lat.links().size()), 1.0 / per_step, run_steps,
        run_steps * per_step);
    if (threads == max_threads) break;
  }
  return 0;
}
