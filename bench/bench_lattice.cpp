// The cubic lattice of the validation tests (seed 002, sec. 7):
//   ./build/bench/cleave_bench_lattice [SCENARIO] [STEPS]
// (default scenarios/validation/dcb.toml, 2000 steps). Builds the test rig of the scenario,
// runs STEPS steps with 1 and with all threads (from rest, so the weak plane is intact: the
// cost of a step does not depend on it), best of CLEAVE_BENCH_ROUNDS rounds (3), and prints
// bodies, links, microseconds per step, nanoseconds per link and steps per second, the wall
// time a whole validation run of that scenario takes at this rate, and the state hash.

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
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
  const int rounds = std::getenv("CLEAVE_BENCH_ROUNDS") ? std::atoi(std::getenv("CLEAVE_BENCH_ROUNDS")) : 3;
  for (int threads : {1, max_threads}) {
    omp_set_num_threads(threads);
    double best = 1e300;
    std::uint64_t hash = 0;
    int bodies = 0;
    std::size_t links = 0;
    double dt = 0.0;
    for (int round = 0; round < rounds; ++round) {
      physics::BeamTestRig rig(v.rig);
      rig.step();  // first force evaluation
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < steps; ++i) rig.step();
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      best = std::min(best, s / steps);
      hash = rig.lattice().state_hash();
      bodies = rig.lattice().size();
      links = rig.lattice().links().size();
      dt = rig.time_step();
    }
    const double rate = v.rig.kind == physics::BeamTestKind::dcb ? 2 * v.rig.velocity : v.rig.velocity;
    const double run_steps = (v.deflection / rate + 0.5 * v.rig.ramp_time) / dt;
    std::printf(
        "threads %d: %d bodies, %zu links, dt %.3g s: %.1f us/step, %.1f ns/link, %.0f steps/s; a "
        "whole run (%.3g steps) would take %.0f s; state hash %016llx\n",
        threads, bodies, links, dt, best * 1e6, best * 1e9 / static_cast<double>(links), 1.0 / best, run_steps,
        run_steps * best, static_cast<unsigned long long>(hash));
    if (threads == max_threads) break;
  }
  return 0;
}
