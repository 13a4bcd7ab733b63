// DEM step cost: a settled pile and falling grains of N hexagonal prisms.
//   ./build/bench/cleave_bench_dynamics [N ...]       (default: 168 1000 10000 100000)
// For each case, in its own child process (so peak memory is its own): build the world,
// take a few warm-up steps, time a fixed number of steps and print microseconds per step,
// nanoseconds per primitive contact, touching body pairs and contacts per body, the cost
// per touching pair, and the peak resident memory. Finally the exponent of a log-log fit
// of step time against N.
//
// Settled pile: a box of prisms on the honeycomb lattice (r = t = 1 mm) resting on a floor,
// every grain pressed 5 um into its neighbours' dilated surfaces, under gravity: every
// grain touches its in-plane and stacked neighbours, as in a pile at rest.
// Falling grains: the same lattice with 0.2 mm gaps, high above the floor: bounding spheres
// overlap, so the broad phase and the narrow phase's early outs are what is measured.

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "geometry/specimen.hpp"
#include "physics/world.hpp"

using namespace cleave;

namespace {

constexpr double kR = 1e-3, kT = 1e-3, kDilation = 0.05e-3;

struct Result {
  double us_per_step = 0, contacts = 0, touching_pairs = 0, bodies = 0, peak_mib = 0;
};

physics::World make_case(int n, bool settled, int& bodies) {
  // A box of about n cells: 4 layers, square footprint.
  const double cell_area = 1.5 * std::sqrt(3.0) * kR * kR;
  const double side = std::sqrt(n / 4.0 * cell_area) + kR;
  geometry::SpecimenDef def;
  def.outline = geometry::Outline::box(side, side, 4 * kT);
  def.r = kR;
  def.t = kT;
  const double press = settled ? 5e-6 : -0.2e-3;  // overlap of the dilated surfaces
  def.r_bar = kR - (2 * kDilation - press) / std::sqrt(3.0);
  def.t_bar = kT - (2 * kDilation - press);
  const geometry::Specimen s = geometry::build_specimen(def);
  physics::WorldSettings ws;
  ws.gravity = {0, 0, -9.81};
  // A tiny step keeps the configuration (and so the contact count) what it was built as
  // over the timed steps: the cost of a step does not depend on dt.
  ws.dt = 1e-8;
  ws.particle_particle.kn = 5000;
  ws.particle_particle.ks = 2000;
  ws.particle_particle.c_res = 2;
  ws.particle_particle.mu_s = 0.3;
  ws.particle_wall = ws.particle_particle;
  physics::World world(ws);
  const physics::RigidShape shape = physics::make_rigid_shape(s.prism, kDilation);
  const auto sh = world.add_shape(shape);
  const double lift = settled ? (kDilation - press / 2) : 0.05;
  for (const auto& g : s.grains) {
    world.add_body(sh, 3100.0, g.site.centre + Eigen::Vector3d(0, 0, lift - kT / 2 + def.t_bar / 2),
                   shape.orientation_for());
  }
  world.add_wall(physics::Wall::plane("floor", {0, 0, 0}, {0, 0, 1}));
  bodies = static_cast<int>(s.grains.size());
  return world;
}

Result run_case(int n, bool settled) {
  Result r;
  int bodies = 0;
  physics::World world = make_case(n, settled, bodies);
  r.bodies = bodies;
  for (int i = 0; i < 3; ++i) world.step();  // warm-up: buffers, contact history
  const int steps = std::clamp(static_cast<int>(2e5 / std::max(1, bodies)), 3, 200);
  const auto t0 = std::chrono::steady_clock::now();
  double contacts = 0, pairs = 0;
  for (int i = 0; i < steps; ++i) {
    world.step();
    contacts += static_cast<double>(world.contacts().size());
    std::set<std::pair<std::uint32_t, std::uint32_t>> touching;
    if (i == steps - 1) {
      for (const auto& c : world.contacts()) {
        if (!c.wall) touching.emplace(c.a, c.b);
      }
      pairs = static_cast<double>(touching.size());
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.us_per_step = 1e6 * seconds / steps;
  r.contacts = contacts / steps;
  r.touching_pairs = pairs;
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  r.peak_mib = u.ru_maxrss / 1024.0;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes;
  for (int i = 1; i < argc; ++i) sizes.push_back(std::atoi(argv[i]));
  if (sizes.empty()) sizes = {168, 1000, 10000, 100000};
  std::printf("%-8s %8s %12s %14s %14s %12s %16s %10s\n", "case", "bodies", "us/step",
              "ns/contact", "touching pairs", "contacts/body", "us/pair/step", "peak MiB");
  for (const bool settled : {true, false}) {
    std::vector<std::pair<double, double>> fit;  // (log N, log us/step)
    for (int n : sizes) {
      int fd[2];
      if (pipe(fd) != 0) return 1;
      const pid_t pid = fork();
      if (pid == 0) {
        close(fd[0]);
        const Result r = run_case(n, settled);
        if (write(fd[1], &r, sizeof r) != static_cast<ssize_t>(sizeof r)) std::_Exit(1);
        std::_Exit(0);
      }
      close(fd[1]);
      Result r;
      const bool ok = read(fd[0], &r, sizeof r) == static_cast<ssize_t>(sizeof r);
      close(fd[0]);
      int status = 0;
      waitpid(pid, &status, 0);
      if (!ok) return 1;
      std::printf("%-8s %8.0f %12.1f %14.1f %14.0f %12.2f %16.3f %10.1f\n",
                  settled ? "settled" : "falling", r.bodies, r.us_per_step,
                  r.contacts > 0 ? 1e3 * r.us_per_step / r.contacts : 0.0, r.touching_pairs,
                  r.contacts / r.bodies, r.touching_pairs > 0 ? r.us_per_step / r.touching_pairs : 0.0,
                  r.peak_mib);
      std::fflush(stdout);
      fit.emplace_back(std::log(r.bodies), std::log(r.us_per_step));
    }
    if (fit.size() >= 2) {
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (const auto& [x, y] : fit) {
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
      }
      const double k = static_cast<double>(fit.size());
      std::printf("%-8s cost per step ~ N^%.3f (least squares on log-log)\n",
                  settled ? "settled" : "falling", (k * sxy - sx * sy) / (k * sxx - sx * sx));
    }
  }
  return 0;
}
