// Time and peak memory to build a specimen of N grains and split every grain into its
// cleavage slabs, exactly.
//   ./build/bench/cleave_bench_specimen [grains=10000]
// Two paths are timed, each in a fresh process state:
//   shared    what `cleave run` does: grains share one exact prism, each distinct
//             orientation is cut once, every piece gets its world mesh;
//   unshared  the worst case: every grain is its own exact prism placed in world
//             coordinates and cut on its own, with an exact volume check per grain.

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "geometry/specimen.hpp"

using namespace cleave::geometry;

namespace {

SpecimenDef specimen_of(int grains) {
  // r = t = 1 mm, 10 layers; a square box with about grains/10 cells per layer.
  const double cell_area = 1.5 * std::sqrt(3.0);  // mm^2 per lattice cell
  const double side = std::sqrt(grains / 10.0 * cell_area) + 1.0;
  SpecimenDef def;
  def.outline = Outline::box(side * 1e-3, side * 1e-3, 10e-3);
  def.r_bar = 0.95e-3;
  def.seed = 2026;
  return def;
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

long peak_rss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

void run(const std::string& mode, int grains) {
  const double t0 = now();
  const Specimen s = build_specimen(specimen_of(grains));
  const double t_build = now() - t0;
  std::size_t pieces = 0;
  std::vector<PolygonMesh> meshes;  // every piece's world mesh, as `cleave run` exports
  std::vector<ExactPolyhedron> kept;
  if (mode == "shared") {
    const auto p = split_into_slabs(s);
    for (const auto& piece : p) meshes.push_back(piece.shape->to_mesh(piece.lineage.name(), piece.position));
    pieces = p.size();
  } else {
    for (const auto& g : s.grains) {
      const ExactPolyhedron prism = s.prism.translated(g.site.centre);
      auto slabs = prism.cleavage_slabs(g.orientation);
      if (!(total_volume(slabs) == prism.volume())) {
        std::fprintf(stderr, "volume not conserved for grain %d\n", g.id);
        std::exit(1);
      }
      for (auto& sl : slabs) {
        meshes.push_back(sl.to_mesh());
        kept.push_back(std::move(sl));
      }
    }
    pieces = kept.size();
  }
  const double t_total = now() - t0;
  std::printf("%-8s  grains %6zu  pieces %6zu  build %.3f s  build+split %.3f s  peak RSS %.1f MiB\n",
              mode.c_str(), s.grains.size(), pieces, t_build, t_total, peak_rss_kib() / 1024.0);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const int grains = argc > 1 ? std::atoi(argv[1]) : 10000;
  // Each mode in a child process so its peak memory is its own.
  for (const std::string mode : {"shared", "unshared"}) {
    const pid_t pid = fork();
    if (pid == 0) {
      run(mode, grains);
      std::_Exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return 1;
  }
  return 0;
}
