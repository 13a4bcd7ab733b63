// Transgranular fracture costs (chapter 3):
//   ./build/bench/cleave_bench_fracture [GRAINS]        (default 10000)
// 1. One split inside a running world: the first cut of a (shape, plane) pair (exact CGAL
//    split + mass properties of the pieces) and a repeated one (shared pieces), each with
//    World::split_body, in microseconds.
// 2. A bonded Brazilian disc of about GRAINS prisms (the lattice of scenarios/brazilian.toml
//    with the disc widened), squeezed between two platens: milliseconds per step with the
//    transgranular check after every step (gate open, so every grain is assessed on every
//    plane: the worst case) and without it, and how many grains split.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "geometry/specimen.hpp"
#include "physics/fracture_book.hpp"
#include "physics/transgranular.hpp"
#include "physics/world.hpp"

using namespace cleave;
using namespace cleave::physics;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr double kDilation = 0.05e-3, kRho = 3100.0;

struct Disc {
  geometry::Specimen specimen;
  World world;
  std::unique_ptr<FractureBook> book;
};

/// The Brazilian disc of scenarios/brazilian.toml (r = 0.6 mm, r_bar = 0.5 mm, 5 mm thick)
/// widened to hold about `grains` grains, bonded across its 0.073 mm gaps, between two
/// platens closing at 5 mm/s.
Disc make_disc(int grains, bool fracture) {
  geometry::SpecimenDef def;
  const double diameter = 15e-3 * std::sqrt(grains / 187.0);
  def.outline = geometry::Outline::disc(diameter, 5e-3);
  def.keep = geometry::KeepRule::centre_inside;
  def.r = 0.6e-3;
  def.r_bar = 0.5e-3;
  def.t = def.t_bar = 5e-3;
  def.seed = 7;
  WorldSettings ws;
  ws.gravity.setZero();
  ws.dt = 1.5e-5;
  ws.particle_particle.kn = 5.0;
  ws.particle_particle.ks = 2.0;
  ws.particle_particle.c_res = 2.0;
  ws.particle_wall.kn = 10.0;
  ws.particle_wall.ks = 2.0;
  ws.particle_wall.c_res = 10.0;
  ws.local_damping = 0.7;
  Disc d{geometry::build_specimen(def), World(ws), nullptr};
  const RigidShape shape = make_rigid_shape(d.specimen.prism, kDilation);
  const auto sh = d.world.add_shape(shape);
  double lo = 1e9, hi = -1e9;
  for (const auto& g : d.specimen.grains) {
    d.world.add_body(sh, kRho, g.site.centre + shape.centroid, shape.orientation_for(), {}, {}, g.id);
    lo = std::min(lo, g.site.centre.y());
    hi = std::max(hi, g.site.centre.y());
  }
  const double reach = def.r_bar + kDilation;
  const double cx = diameter / 2;
  d.world.add_wall(Wall::platen("bottom", {cx, lo - reach, 2.5e-3}, {0, 1, 0}, {1, 0, 0}, diameter, 5e-3));
  d.world.add_wall(Wall::platen("top", {cx, hi + reach, 2.5e-3}, {0, -1, 0}, {1, 0, 0}, diameter, 5e-3));
  d.world.wall(0).velocity = {0, 5e-3, 0};
  d.world.wall(1).velocity = {0, -5e-3, 0};
  const double area = M_PI * kDilation * kDilation;
  d.world.initialise_bonds({5.0 / area, 2.0 / area, 1e3, 1e3}, 0.08e-3);
  if (fracture) {
    d.book = std::make_unique<FractureBook>(kDilation, 0.01);
    d.book->add_shape(sh, std::make_shared<const geometry::ExactPolyhedron>(d.specimen.prism));
    for (const BodyId id : d.world.body_ids()) {
      const int g = d.world.info(id).grain_id;
      d.book->add_grain(d.world, id, g, d.specimen.grains[static_cast<std::size_t>(g)].orientation);
    }
  }
  return d;
}

}  // namespace

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
  p.sigma_f_hyd = -1e30;  // gate open: every grain assessed on every plane, every step
  p.crack_length = 0.1e-3;
  p.k_ic = 0.5;  // Pa sqrt(m): low enough that the loaded disc fragments during the run
  constexpr int kWarm = 20, kSteps = 100;
  for (const bool fracture : {false, true}) {
    Disc d = make_disc(grains, fracture);
    // Load first, so the disc is stressed when timing starts.
    for (int i = 0; i < 2000; ++i) d.world.step();
    std::size_t splits = 0;
    for (int i = 0; i < kWarm; ++i) {
      d.world.step();
      if (fracture) splits += transgranular_step(d.world, *d.book, p).size();
    }
    const auto t0 = Clock::now();
    for (int i = 0; i < kSteps; ++i) {
      d.world.step();
      if (fracture) splits += transgranular_step(d.world, *d.book, p).size();
    }
    const double ms = 1e3 * since(t0) / kSteps;
    std::printf("Brazilian disc, %zu grains, %zu bonds: transgranular %s: %.2f ms/step (%.1f steps/s), "
                "%zu splits, %zu bodies at the end\n",
                d.specimen.grains.size(), d.world.bonds().size(), fracture ? "on " : "off", ms, 1e3 / ms,
                splits, d.world.body_count());
  }
  return 0;
}
