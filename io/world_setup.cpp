#include "io/world_setup.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

namespace cleave::io {

namespace {
physics::RigidShape grain_shape(const Scenario& scenario, const geometry::Specimen& specimen) {
  return physics::make_rigid_shape(specimen.prism, scenario.contact.dilation_radius);
}

struct StableStep {
  double dt = 0.0, mass = 0.0, inertia = 0.0, stiffness = 0.0;
};

StableStep stable_step(const Scenario& scenario, const physics::RigidShape& shape) {
  StableStep s;
  s.mass = scenario.material.density * shape.volume;
  s.inertia = scenario.material.density * shape.principal_moments.minCoeff();
  // A bond (eq. 2.10: K = k A_b with the dilation radius) acts in parallel with the
  // particle-particle spring.
  const physics::BondSection section{scenario.contact.dilation_radius};
  const double bond_normal = scenario.bond.enabled ? scenario.bond.params.kbn * section.area() : 0.0;
  const double bond_rolling = scenario.bond.enabled ? scenario.bond.params.kbn * section.inertia() : 0.0;
  s.stiffness = std::max(scenario.contact.particle_particle.c_res * scenario.contact.particle_particle.kn + bond_normal,
                         scenario.contact.particle_wall.c_res * scenario.contact.particle_wall.kn);
  const double arm = shape.bounding_radius();
  const double translation = physics::critical_time_step(s.mass, s.stiffness);
  const double rotation =
      physics::critical_time_step(s.inertia, std::max(s.stiffness * arm * arm, bond_rolling));
  s.dt = scenario.dynamics.dt_safety * std::min(translation, rotation);
  return s;
}
}  // namespace

double stable_time_step(const Scenario& scenario, const geometry::Specimen& specimen) {
  return stable_step(scenario, grain_shape(scenario, specimen)).dt;
}

namespace {
void check_time_step(const Scenario& scenario, const physics::RigidShape& shape) {
  const DynamicsDef& dyn = scenario.dynamics;
  const StableStep s = stable_step(scenario, shape);
  if (dyn.dt > s.dt) {
    throw ScenarioError(
        scenario.source, dyn.dt_position.line, dyn.dt_position.column, "dynamics.dt",
        fmt::format("time step {:.3g} s is above the stable limit; use dt <= {:.3g} s "
                    "(= dt_safety {:g} x 2 sqrt(m/k): lightest body {:.3g} kg, I {:.3g} kg m^2, "
                    "stiffest spring C_res K_n (+ K_bn) = {:.3g} N/m)",
                    dyn.dt, s.dt, dyn.dt_safety, s.mass, s.inertia, s.stiffness));
  }
}
}  // namespace

void check_time_step(const Scenario& scenario, const geometry::Specimen& specimen) {
  check_time_step(scenario, grain_shape(scenario, specimen));
}

physics::World make_world(const Scenario& scenario, const geometry::Specimen& specimen) {
  const physics::RigidShape shape = grain_shape(scenario, specimen);
  check_time_step(scenario, shape);
  const DynamicsDef& dyn = scenario.dynamics;
  physics::WorldSettings ws;
  ws.gravity = dyn.gravity;
  ws.dt = dyn.dt;
  ws.particle_particle = scenario.contact.particle_particle;
  ws.particle_wall = scenario.contact.particle_wall;
  ws.search = dyn.search;
  ws.threads = dyn.threads;
  ws.local_damping = dyn.local_damping;
  physics::World world(ws);
  const std::uint32_t sh = world.add_shape(shape);
  double min_z = std::numeric_limits<double>::infinity();
  for (const auto& g : specimen.grains) min_z = std::min(min_z, g.site.centre.z());
  const Eigen::Vector3d lift(0, 0, dyn.lift - (min_z - specimen.def.t_bar / 2.0));
  for (const auto& g : specimen.grains) {
    world.add_body(sh, scenario.material.density, g.site.centre + shape.centroid + lift,
                   shape.orientation_for(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), g.id);
  }
  for (const auto& w : scenario.walls) world.add_wall(w);
  return world;
}

}  // namespace cleave::io
