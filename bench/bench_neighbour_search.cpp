// Coarse contact detection (App. B.1 of the dissertation, seed 000), one DEM step's call:
// basic vs bounding-box grid for 10^3..10^5 bodies, margin 0, buffers warm.
//   prisms: bounding spheres of prisms, r = 0.6 mm +-10 %, uniformly random centres at a
//           sphere volume fraction of 0.6 (about 5 neighbours per body);
//   mixed:  half such grains, half fragments with log-uniform r in 0.03..0.6 mm (1x..20x),
//           same volume fraction;
//   huge:   such grains and one body in 1000 ten times larger (together as much volume as
//           the grains), same volume fraction: where basic cells are far too big;
//   far:    the prisms, with one body in 1000 thrown 100 m away (the grid's dense window
//           then covers the bulk only; the far cells are hashed).
// Bodies are in random index order (no spatial coherence), the cache's worst case.
// The time_per_body counter is the figure to read.
//   ./bench_neighbour_search --benchmark_counters_tabular=true

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/rng.hpp"
#include "physics/dem/neighbour_search.hpp"

using cleave::geometry::SplitMix64;
using namespace cleave::physics;

namespace {

enum class Scene { prisms, mixed, huge, far };

std::vector<BoundingSphere> make_scene(Scene scene, std::size_t n) {
  SplitMix64 rng(2024 + n);
  std::vector<double> radii(n);
  double volume = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    radii[k] = 0.6e-3 * (0.9 + 0.2 * rng.uniform());
    if (scene == Scene::mixed && k % 2 == 1) radii[k] = 0.03e-3 * std::pow(20.0, rng.uniform());
    if (scene == Scene::huge && k % 1000 == 999) radii[k] *= 10.0;
    volume += 4.0 / 3.0 * std::numbers::pi * std::pow(radii[k], 3);
  }
  const double side = std::cbrt(volume / 0.6);
  std::vector<BoundingSphere> bodies(n);
  for (std::size_t k = 0; k < n; ++k) {
    bodies[k].centre = side * Eigen::Vector3d(rng.uniform(), rng.uniform(), rng.uniform());
    bodies[k].radius = radii[k];
    if (scene == Scene::far && k % 1000 == 0) {
      bodies[k].centre += 100.0 * Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5, 1.0);
    }
  }
  return bodies;
}

void BM_NeighbourSearch(benchmark::State& state, SearchMethod method, Scene scene) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const std::vector<BoundingSphere> bodies = make_scene(scene, n);
  NeighbourSearch search(method);
  std::vector<BodyPair> pairs;
  search.find_pairs(bodies, 0.0, pairs);  // warm the buffers, as in a running simulation
  for (auto _ : state) {
    search.find_pairs(bodies, 0.0, pairs);
    benchmark::DoNotOptimize(pairs.data());
    benchmark::ClobberMemory();
  }
  // Seconds per body, printed with an SI prefix (e.g. "85n" = 85 ns per body).
  state.counters["time_per_body"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
  state.counters["pairs_per_body"] = static_cast<double>(pairs.size()) / static_cast<double>(n);
}

void sizes(benchmark::internal::Benchmark* b) {
  b->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
}

BENCHMARK_CAPTURE(BM_NeighbourSearch, basic_prisms, SearchMethod::basic, Scene::prisms)
    ->Apply(sizes);
BENCHMARK_CAPTURE(BM_NeighbourSearch, bbox_prisms, SearchMethod::bounding_box, Scene::prisms)
    ->Apply(sizes);
BENCHMARK_CAPTURE(BM_NeighbourSearch, basic_mixed, SearchMethod::basic, Scene::mixed)->Apply(sizes);
BENCHMARK_CAPTURE(BM_NeighbourSearch, bbox_mixed, SearchMethod::bounding_box, Scene::mixed)
    ->Apply(sizes);
BENCHMARK_CAPTURE(BM_NeighbourSearch, basic_huge, SearchMethod::basic, Scene::huge)->Apply(sizes);
BENCHMARK_CAPTURE(BM_NeighbourSearch, bbox_huge, SearchMethod::bounding_box, Scene::huge)
    ->Apply(sizes);
BENCHMARK_CAPTURE(BM_NeighbourSearch, basic_far, SearchMethod::basic, Scene::far)->Apply(sizes);
BENCHMARK_CAPTURE(BM_NeighbourSearch, bbox_far, SearchMethod::bounding_box, Scene::far)
    ->Apply(sizes);

}  // namespace

BENCHMARK_MAIN();
