// The cubic lattice of the validation tests (seed 002, sec. 7):
//   ./build/bench/cleave_bench_lattice [SCENARIO] [STEPS]
// (default scenarios/validation/dcb.toml, 2000 steps). Builds the test rig of the scenario,
// runs STEPS steps with 1 and with all threads (from rest, so the weak plane is intact: the
// cost of a step does not depend on it), one link at a time and four at a time in AVX's lanes
// alternated over CLEAVE_BENCH_ROUNDS rounds (3; CLEAVE_BENCH_LANES=0 or 1 runs one way
// alone, for a profile), and prints bodies, links, microseconds per step,
// nanoseconds per link and steps per second, and the wall time a whole validation run of
// that scenario takes at this rate.

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
  // Rounds alternate the links one at a time and four at a time (CubicLatticeDef::lanes), so
  // that this machine's swings fall on both alike; the figure of each is its best round.
  const int rounds = std::getenv("CLEAVE_BENCH_ROUNDS") ? std::atoi(std::getenv("CLEAVE_BENCH_ROUNDS")) : 3;
  const char* only = std::getenv("CLEAVE_BENCH_LANES");  // 0 or 1: that way alone (profiles)
  for (int threads : {1, max_threads}) {
    omp_set_num_threads(threads);
    double best[2] = {1e300, 1e300};
    std::uint64_t hash[2] = {0, 0};
    int bodies = 0;
    std::size_t links = 0;
    double dt = 0.0;
    for (int round = 0; round < rounds; ++round)
      for (int lanes : {0, 1}) {
        if (only != nullptr && std::atoi(only) != lanes) continue;
        physics::BeamRigDef def = v.rig;
        def.lanes = lanes == 1;
        physics::BeamTestRig rig(def);
        rig.step();  // first force evaluation
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < steps; ++i) rig.step();
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        best[lanes] = std::min(best[lanes], s / steps);
        hash[lanes] = rig.lattice().state_hash();
        bodies = rig.lattice().size();
        links = rig.lattice().links().size();
        dt = rig.time_step();
      }
    const double rate = v.rig.kind == physics::BeamTestKind::dcb ? 2 * v.rig.velocity : v.rig.velocity;
    const double run_steps = (v.deflection / rate + 0.5 * v.rig.ramp_time) / dt;
    for (int lanes : {0, 1}) {
      if (best[lanes] == 1e300) continue;  // not run
      const double per_step = best[lanes];
      std::printf(
          "threads %d, %s: %d bodies, %zu links, dt %.3g s: %.1f us/step, %.1f ns/link, %.0f "
          "steps/s; a whole run (%.3g steps) would take %.0f s\n",
          threads, lanes ? "four links at a time" : "one link at a time ", bodies, links, dt,
          per_step * 1e6, per_step * 1e9 / static_cast<double>(links), 1.0 / per_step, run_steps,
          run_steps * per_step);
    }
    if (only == nullptr)
      std::printf("threads %d: four at a time / one at a time %.3f, the same state: %s\n", threads,
                best[1] / best[0], hash[0] == hash[1] ? "yes" : "NO");
    if (threads == max_threads) break;
  }
  return 0;
}
