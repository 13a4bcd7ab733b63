#pragma once
// The bonded-prism fixtures shared by the bond and thermal tests: the prism of table 2.1's
// size (0.5 mm side, 1 mm thick, 0.05 mm dilation, 3100 kg/m^3) and a row of them along x,
// side face to side face.

#include <cmath>
#include <vector>

#include "geometry/exact_polyhedron.hpp"
#include "physics/dem/world.hpp"

namespace cleave::test {

constexpr double kSide = 0.5e-3;       // prism side, m
constexpr double kThick = 1.0e-3;      // prism thickness, m
constexpr double kDilation = 0.05e-3;  // m
constexpr double kRho = 3100.0;
inline const double kFlat = std::sqrt(3.0) * kSide;  // distance between opposite side faces
inline const double kPitch = kFlat + 2.0 * kDilation;  // centroid spacing of touching neighbours
inline const double kBondArea = M_PI * kDilation * kDilation;  // bond section (eq. 2.10)
constexpr double kSpringN = 5000.0, kSpringS = 2000.0;  // bond springs K_bn, K_bs, N/m (table 2.5's size)

/// Springs of table 2.5's size, strengths far above anything the tests load them to.
inline physics::BondParams strong_bonds() { return {kSpringN / kBondArea, kSpringS / kBondArea, 1e12, 1e12}; }

inline physics::RigidShape prism() {
  return physics::make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(kSide, kThick), kDilation);
}

/// A world for these prisms: no gravity, table 2.3's particle springs (5000 and 2000 N/m,
/// friction 0.3) for both sets, one thread, time step `dt`.
inline physics::WorldSettings prism_settings(double dt) {
  physics::WorldSettings ws;
  ws.gravity.setZero();
  ws.dt = dt;
  ws.particle_particle.kn = 5000.0;
  ws.particle_particle.ks = 2000.0;
  ws.particle_particle.mu_s = 0.3;
  ws.particle_wall = ws.particle_particle;
  ws.threads = 1;
  return ws;
}

/// n prisms in a row along x, side face to side face; neighbouring dilated surfaces
/// overlap by `overlap` (negative: a gap; 0: they just touch).
inline std::vector<physics::BodyId> row(physics::World& world, int n, double overlap = 0.0) {
  const physics::RigidShape shape = prism();
  const auto sh = world.add_shape(shape);
  const double pitch = kFlat + 2.0 * kDilation - overlap;
  std::vector<physics::BodyId> ids;
  for (int i = 0; i < n; ++i) ids.push_back(world.add_body(sh, kRho, {i * pitch, 0, 0}, shape.orientation_for()));
  return ids;
}

}  // namespace cleave::test
