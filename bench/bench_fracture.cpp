// Transgranular fracture costs (chapter 3):
//   ./build/bench/cleave_bench_fracture [GRAINS] [K_IC] [GATE] [MANIFOLD]
//   (defaults 10000, 0.5 Pa m^0.5, gate open; GATE: eq. 3.22's sigma_f_hyd in Pa; MANIFOLD:
//   WorldSettings::manifold_tolerance, default 0, the exact search; CLEAVE_BENCH_STEPS:
//   timed steps, default 100; CLEAVE_BENCH_PHASES=1: where the step and the check go)
// 1. One split inside a running world: the first cut of a (shape, plane) pair (exact CGAL
//    split + mass properties of the pieces) and a repeated one (shared pieces), each with
//    World::split_body, in microseconds.
// 2. A bonded Brazilian disc of about GRAINS prisms (the lattice of scenarios/brazilian.toml
//    with the disc widened), squeezed between two platens: milliseconds per step with the
//    transgranular check after every step (gate open, so every grain is assessed on every
//    plane: the worst case; GATE sets a real one) and without it, and how many grains
//    split. A K_IC high enough that nothing splits times the assessment alone (no pieces,
//    so the neighbour search's pair list and near-feature caches are never rebuilt for new
//    bodies).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>

#include "geometry/specimen.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "physics/transgranular/transgranular.hpp"
#include "physics/dem/world.hpp"
#include "bench_disc.hpp"
#include "step_phases.hpp"

using namespace cleave;
using namespace cleave::physics;
using cleave::bench::Disc;
using cleave::bench::make_disc;

using cleave::bench::Clock;
using cleave::bench::since;

int main(int argc, char** argv) {
  const int grains = argc > 1 ? std::atoi(argv[1]) : 10000;

  // 1. Split cost.
  {
    Disc d = make_disc(1000, true);
    std::vector<BodyId> ids = d.world.body_ids();
    d.world.step();
    const auto t_first = Clock::now();
    const SplitEvent first = d.book->split(d.world, ids[0], 0);
    const double first_us = 1e6 * since(t_first);
    // The same orientation's plane 0 on grains of the same orientation: shared pieces.
    const auto orientation = d.specimen.grains[0].orientation;
    int repeats = 0;
    const auto t_repeat = Clock::now();
    for (std::size_t k = 1; k < ids.size() && repeats < 100; ++k) {
      if (!(d.specimen.grains[k].orientation == orientation)) continue;
      d.book->split(d.world, ids[k], 0);
      ++repeats;
    }
    const double repeat_us = 1e6 * since(t_repeat) / std::max(repeats, 1);
    std::printf("split inside a running world (1,000 bonded grains): first cut of a shape and plane "
                "%.0f us (exact split + mass properties), repeated %.1f us (mean of %d); %zu pieces\n",
                first_us, repeat_us, repeats, first.ids.size());
  }

  // 2. A fragmenting disc, with and without the check.
  FractureParams p;
  // Default: gate open, every grain assessed on every plane, every step (the worst case).
  p.sigma_f_hyd = argc > 3 ? std::atof(argv[3]) : -1e30;
  p.crack_length = 0.1e-3;
  p.k_ic = argc > 2 ? std::atof(argv[2]) : 0.5;  // Pa sqrt(m): 0.5 fragments the loaded disc
  const double manifold = argc > 4 ? std::atof(argv[4]) : 0.0;
  if (manifold > 0.0) std::printf("persistent contact manifolds: tolerance %g (an approximation)\n", manifold);
  // CLEAVE_BENCH_STEPS: timed steps per case (default 100; more for a profile of the check).
  const char* steps_env = std::getenv("CLEAVE_BENCH_STEPS");
  // CLEAVE_BENCH_PHASES=1: where each case's step goes (World::set_timing), and the check's.
  const char* phases_env = std::getenv("CLEAVE_BENCH_PHASES");
  const bool phases = phases_env != nullptr && std::string(phases_env) != "0";
  constexpr int kWarm = 20;
  const int kSteps = steps_env ? std::max(1, std::atoi(steps_env)) : 100;
  for (const bool fracture : {false, true}) {
    Disc d = make_disc(grains, fracture, manifold);
    // Load first, so the disc is stressed when timing starts.
    for (int i = 0; i < 2000; ++i) d.world.step();
    // The check every step, as a run registers it: a listener, so the steps it reads sum
    // eq. 2.17's diagonals with their forces.
    TransgranularCheck check(*d.book, p, 1);
    if (fracture) d.world.add_listener(&check);
    std::size_t splits = 0;
    for (int i = 0; i < kWarm; ++i) {
      d.world.step();
      splits += check.take_events().size();
    }
    // Timed in blocks of 10 steps: the mean, and the fastest block (this machine's speed
    // swings by tens of percent within a minute; the fastest block is the least disturbed).
    constexpr int kBlock = 10;
    double total = 0.0, best = std::numeric_limits<double>::infinity();
    const double check0 = check.seconds();
    d.world.set_timing(phases);
    for (int done = 0; done < kSteps; done += kBlock) {
      const auto t0 = Clock::now();
      for (int i = 0; i < kBlock; ++i) {
        d.world.step();
        splits += check.take_events().size();
      }
      const double block = since(t0);
      total += block;
      best = std::min(best, block / kBlock);
    }
    const double ms = 1e3 * total / ((kSteps + kBlock - 1) / kBlock * kBlock);
    std::printf("Brazilian disc, %zu grains, %zu bonds: transgranular %s: %.2f ms/step (%.1f steps/s), "
                "fastest 10-step block %.2f ms/step (%.1f steps/s), %zu splits, %zu bodies at the end\n",
                d.specimen.grains.size(), d.world.bonds().size(), fracture ? "on " : "off", ms, 1e3 / ms,
                1e3 * best, 1.0 / best, splits, d.world.body_count());
    if (phases) {
      cleave::bench::print_phases("where the step goes", d.world.timings());
      if (fracture)
        std::printf("  and the transgranular check (TransgranularCheck, in the step): %.3f ms/step\n",
                    1e3 * (check.seconds() - check0) / static_cast<double>(d.world.timings().steps));
    }
  }
  return 0;
}
