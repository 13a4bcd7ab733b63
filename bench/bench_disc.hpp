#pragma once
/// \file
/// The bonded Brazilian disc the fracture and checkpoint benchmarks load: the lattice of
/// scenarios/brazilian.toml (r = 0.6 mm, r_bar = 0.5 mm, 5 mm thick) widened to hold about
/// `grains` prisms, bonded across its 0.073 mm gaps, between two platens closing at 5 mm/s;
/// with `fracture`, every grain registered for transgranular splitting.

#include <chrono>
#include <cmath>
#include <memory>

#include "geometry/specimen.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "physics/dem/world.hpp"

namespace cleave::bench {

using namespace cleave::physics;

using Clock = std::chrono::steady_clock;
/// Seconds since t0.
inline double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline constexpr double kDilation = 0.05e-3, kRho = 3100.0;

struct Disc {
  geometry::Specimen specimen;
  World world;
  std::unique_ptr<FractureBook> book;
};

/// `manifold`: WorldSettings::manifold_tolerance (0: the exact search).
inline Disc make_disc(int grains, bool fracture, double manifold = 0.0) {
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
  ws.manifold_tolerance = manifold;
  Disc d{geometry::build_specimen(def), World(ws), nullptr};
  const RigidShape shape = make_rigid_shape(d.specimen.prism, kDilation);
  const auto sh = d.world.add_shape(shape);
  double lo = 1e9, hi = -1e9;
  for (const auto& g : d.specimen.grains) {
    d.world.add_body(sh, kRho, g.site.centre + shape.centroid, shape.orientation_for(), Eigen::Vector3d::Zero(),
                     Eigen::Vector3d::Zero(), g.id);
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

}  // namespace cleave::bench
