// Exact geometry throughput: cleavage slab splits of a prism, random plane splits of
// random fragments, exact mass properties.
//   ./build/bench/cleave_bench --benchmark_filter=Split

#include <benchmark/benchmark.h>

#include <vector>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/rng.hpp"

using namespace cleave::geometry;

namespace {

Eigen::Vector3d random_unit(SplitMix64& rng) {
  Eigen::Vector3d v;
  do {
    v = {2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1};
  } while (v.squaredNorm() < 1e-4 || v.squaredNorm() > 1.0);
  return v.normalized();
}

/// A plane through a random interior point (random weights of the vertices).
ExactPlane random_plane_through(const ExactPolyhedron& body, SplitMix64& rng) {
  const auto v = body.vertices_approx();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double wsum = 0.0;
  for (const auto& q : v) {
    const double w = rng.uniform() + 0.05;
    p += w * q;
    wsum += w;
  }
  const Eigen::Vector3d n = random_unit(rng);
  return ExactPlane::from_normal_offset(n, n.dot(p / wsum));
}

/// Fragments 0..4 splits deep below a prism, from random planes.
std::vector<ExactPolyhedron> random_fragments(int count, SplitMix64& rng) {
  std::vector<ExactPolyhedron> out;
  while (static_cast<int>(out.size()) < count) {
    ExactPolyhedron body = ExactPolyhedron::hexagonal_prism(0.5e-3, 1.0e-3);
    const int depth = static_cast<int>(rng.below(5));
    for (int d = 0; d < depth; ++d) {
      SplitResult r = body.split(random_plane_through(body, rng), 0.05);
      if (!r.ok()) continue;
      body = rng.below(2) ? *r.above : *r.below;
    }
    out.push_back(body);
  }
  return out;
}

void BM_PrismIntoSlabs(benchmark::State& state) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(0.5e-3, 1.0e-3);
  const CrystalOrientation o{state.range(0) ? CleavageFamily::a_11_20 : CleavageFamily::m_10_10,
                             static_cast<int>(state.range(1))};
  for (auto _ : state) {
    auto slabs = prism.cleavage_slabs(o);
    benchmark::DoNotOptimize(slabs);
  }
  state.counters["grains/s"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                  benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PrismIntoSlabs)->ArgsProduct({{1, 0}, {0, 60, 120}})->ArgNames({"three_slab", "angle"});

/// Arg 0: the split alone; arg 1: the split plus the exact check parent = sum of parts.
void BM_RandomPlaneThroughRandomFragment(benchmark::State& state) {
  const bool check_volume = state.range(0) != 0;
  SplitMix64 rng(42);
  const auto bodies = random_fragments(64, rng);
  std::vector<ExactPlane> planes;
  for (const auto& b : bodies) planes.push_back(random_plane_through(b, rng));
  std::size_t i = 0;
  for (auto _ : state) {
    const ExactPolyhedron& body = bodies[i % bodies.size()];
    SplitResult r = body.split(planes[i % planes.size()], 0.0);
    if (!r.ok() ||
        (check_volume && !(r.below->volume() + r.above->volume() == body.volume()))) {
      state.SkipWithError("split refused or volume not conserved");
      break;
    }
    benchmark::DoNotOptimize(r);
    ++i;
  }
  state.counters["splits/s"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                  benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RandomPlaneThroughRandomFragment)->Arg(0)->Arg(1)->ArgName("exact_volume_check");

void BM_ExactMassProperties(benchmark::State& state) {
  SplitMix64 rng(44);
  const auto bodies = state.range(0) ? random_fragments(64, rng)
                                     : std::vector{ExactPolyhedron::hexagonal_prism(0.5e-3, 1e-3)};
  std::vector<std::string> texts;
  for (const auto& b : bodies) texts.push_back(b.to_exact_text());
  std::size_t i = 0;
  for (auto _ : state) {
    // A shape keeps its mass properties once computed: time the computation on a fresh one.
    state.PauseTiming();
    const ExactPolyhedron fresh = ExactPolyhedron::from_exact_text(texts[i++ % texts.size()]);
    state.ResumeTiming();
    benchmark::DoNotOptimize(fresh.mass_properties());
  }
}
BENCHMARK(BM_ExactMassProperties)->Arg(0)->Arg(1)->ArgName("random_fragment");

}  // namespace

BENCHMARK_MAIN();
