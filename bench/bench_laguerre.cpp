// Timed driver: a log-normal Laguerre specimen (fit in doubles, then the exact cells), and
// the exact check that the cells' volumes sum to the box's.
// Usage: cleave_bench_laguerre [cells=1000] [spread=0.35]
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "geometry/laguerre.hpp"
#include "geometry/voronoi.hpp"

int main(int argc, char** argv) {
  namespace g = cleave::geometry;
  const int cells = argc > 1 ? std::atoi(argv[1]) : 1000;
  const double spread = argc > 2 ? std::atof(argv[2]) : 0.35;
  const Eigen::Vector3d size(1e-3, 1e-3, 1e-3);
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const auto t = g::lognormal_laguerre(size, cells, spread, 1);
  const auto t1 = clock::now();
  const bool exact =
      g::total_volume(t.cells) == g::exact_box(Eigen::Vector3d::Zero(), size).volume();
  double worst = 0.0;
  for (std::size_t i = 0; i < t.cells.size(); ++i)
    worst = std::max(worst, std::abs(t.cells[i].volume().to_double() / t.targets[i] - 1.0));
  std::printf(
      "%d cells, spread %.2f: built in %.2f s (%d Newton steps, fit error %.2e); exact "
      "cells off their targets by at most %.2e; volumes sum exactly to the box: %s\n",
      cells, spread, std::chrono::duration<double>(t1 - t0).count(), t.fit.iterations,
      t.fit.max_relative_error, worst, exact ? "yes" : "NO");
  // The .tess reader rebuilds cells from given seeds and weights, with no fit to guide it.
  const auto t2 = clock::now();
  const auto again =
      g::laguerre_cells(g::exact_box(Eigen::Vector3d::Zero(), size), t.points, t.fit.weights);
  const auto t3 = clock::now();
  const bool same = g::total_volume(again) == g::total_volume(t.cells);
  std::printf(
      "rebuilt from the seeds and weights alone (as a .tess is read) in %.2f s; exact "
      "sum %s\n",
      std::chrono::duration<double>(t3 - t2).count(), same ? "the same" : "DIFFERENT");
  return exact && same ? 0 : 1;
}
