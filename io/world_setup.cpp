#include "io/world_setup.hpp"

#include "geometry/rng.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace cleave::io {

namespace {
/// One rigid shape per distinct grain shape, in Specimen::shapes order.
std::vector<physics::RigidShape> grain_shapes(const Scenario& scenario,
                                              const geometry::Specimen& specimen) {
  std::vector<physics::RigidShape> shapes;
  for (const auto& s : specimen.shapes) {
    shapes.push_back(physics::make_rigid_shape(s, scenario.contact.dilation_radius));
  }
  return shapes;
}

/// The density the bodies carry: the material's, times [dynamics] density_scale.
double grain_density(const Scenario& scenario) {
  return scenario.material.density * scenario.dynamics.density_scale;
}

struct StableStep {
  double dt = 0.0, mass = 0.0, inertia = 0.0, stiffness = 0.0;
};

/// `spacing`: the shortest centroid distance of two bonded grains (a beam's length).
StableStep stable_step(const Scenario& scenario, double mass, double inertia, double arm, double spacing) {
  StableStep s;
  s.mass = mass;
  s.inertia = inertia;
  // A bond (eq. 2.10: K = k A_b with the dilation radius) acts in parallel with the
  // particle-particle spring.
  const physics::BondSection section{scenario.contact.dilation_radius};
  double bond_normal = scenario.bond.enabled ? scenario.bond.params.kbn * section.area() : 0.0;
  double bond_rolling = scenario.bond.enabled ? scenario.bond.params.kbn * section.inertia() : 0.0;
  if (scenario.bond.enabled && scenario.bond.params.law == physics::BondLaw::beam) {
    // A beam of length L: E A / L along it, 12 E I / L^3 across it, 6 E I / L against an end
    // turned with the other (beam_force's element).
    const physics::BondParams& b = scenario.bond.params;
    const physics::BondSection beam{b.beam_radius};
    const double l = spacing;
    bond_normal = std::max(b.beam_young * beam.area() / l, 12.0 * b.beam_young * beam.inertia() / (l * l * l));
    bond_rolling = 6.0 * b.beam_young * beam.inertia() / l;
  }
  s.stiffness = std::max(scenario.contact.particle_particle.c_res * scenario.contact.particle_particle.kn + bond_normal,
                         scenario.contact.particle_wall.c_res * scenario.contact.particle_wall.kn);
  const double translation = physics::critical_time_step(s.mass, s.stiffness);
  const double rotation =
      physics::critical_time_step(s.inertia, std::max(s.stiffness * arm * arm, bond_rolling));
  s.dt = scenario.dynamics.dt_safety * std::min(translation, rotation);
  return s;
}

StableStep stable_step(const Scenario& scenario, const physics::RigidShape& shape) {
  const double rho = grain_density(scenario);
  // Two grains face to face: their centroids at least twice the nearest face apart.
  double inner = std::numeric_limits<double>::infinity();
  for (const auto& face : shape.primitives.faces) inner = std::min(inner, face.offset);
  const double spacing = 2.0 * (inner + shape.primitives.dilation_radius);
  return stable_step(scenario, rho * shape.volume, rho * shape.principal_moments.minCoeff(),
                     shape.bounding_radius(), spacing);
}
}  // namespace

double stable_time_step(const Scenario& scenario, double mass, double inertia, double bounding_radius) {
  return stable_step(scenario, mass, inertia, bounding_radius, bounding_radius).dt;
}

namespace {
/// The most restrictive of the shapes' stable steps.
StableStep stable_step(const Scenario& scenario, const std::vector<physics::RigidShape>& shapes) {
  StableStep worst;
  for (const auto& shape : shapes) {
    const StableStep s = stable_step(scenario, shape);
    if (worst.mass == 0.0 || s.dt < worst.dt) worst = s;
  }
  return worst;
}
}  // namespace

double stable_time_step(const Scenario& scenario, const geometry::Specimen& specimen) {
  return stable_step(scenario, grain_shapes(scenario, specimen)).dt;
}

namespace {
void check_time_step(const Scenario& scenario, const std::vector<physics::RigidShape>& shapes) {
  const DynamicsDef& dyn = scenario.dynamics;
  const StableStep s = stable_step(scenario, shapes);
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
  check_time_step(scenario, grain_shapes(scenario, specimen));
}

Eigen::Vector3d grain_c_axis(const ThermalDef& thermal, int grain_id) {
  if (thermal.c_axis == ThermalDef::Axis::prism) return Eigen::Vector3d::UnitZ();
  // Uniform on the sphere (Archimedes): z uniform in [-1, 1], azimuth uniform; the grain's
  // own stream, as its orientation and Voronoi site have.
  geometry::SplitMix64 rng = geometry::stream_for(thermal.seed, static_cast<std::uint64_t>(grain_id));
  const double z = 2.0 * rng.uniform() - 1.0;
  const double phi = 2.0 * M_PI * rng.uniform();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

void apply_thermal(const Scenario& scenario, physics::World& world) {
  const ThermalDef& thermal = scenario.thermal;
  world.set_temperature(thermal.temperature);
  if (!thermal.gradient.isZero(0.0)) {
    // A linear field about the grains' mean centroid.
    const std::vector<physics::BodyId> ids = world.body_ids();
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const physics::BodyId id : ids) mean += world.state(id).x / static_cast<double>(ids.size());
    for (const physics::BodyId id : ids) {
      const double t = thermal.temperature + thermal.gradient.dot(world.state(id).x - mean);
      if (!(t > 0.0)) {
        throw ScenarioError(scenario.source, thermal.gradient_at.line, thermal.gradient_at.column, "thermal.gradient",
                            "the field falls to " + std::to_string(t) +
                                " K at a grain; every grain's temperature must stay above 0 K");
      }
      world.set_temperature(id, t);
    }
  }
  if (thermal.alpha_a != 0.0 || thermal.alpha_c != 0.0) {
    for (const physics::BodyId id : world.body_ids()) {
      const Eigen::Vector3d c = grain_c_axis(thermal, world.info(id).grain_id);
      world.set_expansion(id, physics::World::crystal_expansion(c, thermal.alpha_a, thermal.alpha_c));
    }
  }
  world.set_conduction(thermal.conductivity, thermal.heat_capacity);
}

namespace {
Eigen::Vector3d specimen_def_size(const Scenario& scenario) { return scenario.specimen.voronoi.size; }
/// [dynamics] in_plane holds each body to turning about z, which is its own motion only
/// when z is one of its principal axes (a prism standing along z, and its slabs cut by
/// planes through z): otherwise an angular momentum along z would still turn it about x or
/// y. Refuses any other body (a Voronoi grain, a prism lying down).
void check_in_plane(const Scenario& scenario, const physics::World& world) {
  for (const physics::BodyId id : world.body_ids()) {
    // z is a principal axis when the inertia tensor in world axes has no xz, yz products
    // (whatever the principal frame an equal pair of moments left the shape with).
    const Eigen::Matrix3d r = world.state(id).q.toRotationMatrix();  // principal -> world
    const Eigen::Matrix3d inertia = r * world.info(id).inertia.asDiagonal() * r.transpose();
    const double off = std::hypot(inertia(0, 2), inertia(1, 2)) / inertia.trace();
    if (off > 1e-9) {
      throw ScenarioError(scenario.source, scenario.dynamics.in_plane_position.line,
                          scenario.dynamics.in_plane_position.column, "dynamics.in_plane",
                          fmt::format("motion in the xy plane needs every grain to have a principal axis "
                                      "along z (a prism standing along z); grain {} has not (products "
                                      "of inertia with z {:.3g} of its trace): remove in_plane or use a "
                                      "honeycomb specimen",
                                      world.info(id).grain_id, off));
    }
  }
}
}  // namespace

physics::World make_world(const Scenario& scenario, const geometry::Specimen& specimen) {
  const std::vector<physics::RigidShape> shapes = grain_shapes(scenario, specimen);
  check_time_step(scenario, shapes);
  const DynamicsDef& dyn = scenario.dynamics;
  physics::WorldSettings ws;
  ws.gravity = dyn.gravity;
  ws.dt = dyn.dt;
  ws.particle_particle = scenario.contact.particle_particle;
  ws.particle_wall = scenario.contact.particle_wall;
  ws.search = dyn.search;
  ws.threads = dyn.threads;
  ws.local_damping = dyn.local_damping;
  ws.manifold_tolerance = dyn.manifold_tolerance;
  ws.in_plane = dyn.in_plane;
  physics::World world(ws);
  // World shape k is specimen shape k (sim/dynamics.cpp registers them so with the fracture book).
  std::vector<std::uint32_t> ids;
  for (const auto& shape : shapes) ids.push_back(world.add_shape(shape));
  std::vector<double> shape_low;
  for (const auto& s : specimen.shapes) {
    double low = std::numeric_limits<double>::infinity();
    for (const auto& v : s.vertices_approx()) low = std::min(low, v.z());
    shape_low.push_back(low);
  }
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& g : specimen.grains) {
    lowest = std::min(lowest, g.site.centre.z() + shape_low.at(static_cast<std::size_t>(g.shape)));
  }
  const Eigen::Vector3d lift(0, 0, dyn.lift - lowest);
  for (const auto& g : specimen.grains) {
    const auto k = static_cast<std::size_t>(g.shape);
    world.add_body(ids.at(k), grain_density(scenario), g.site.centre + shapes[k].centroid + lift,
                   shapes[k].orientation_for(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), g.id);
  }
  if (dyn.in_plane) check_in_plane(scenario, world);
  if (scenario.periodic.enabled) {
    // The Voronoi box, lifted with its grains, is the periodic cell (the cells tile it).
    const Eigen::Vector3d lo = lift;
    const physics::PeriodicCell cell = physics::PeriodicCell::box(lo, lo + specimen_def_size(scenario), scenario.periodic.axes);
    // A pair must meet through one image only: the cell over twice a pair's reach across.
    double largest = 0.0, smallest = std::numeric_limits<double>::infinity();
    for (const auto& shape : shapes) {
      largest = std::max(largest, shape.bounding_radius());
      smallest = std::min(smallest, shape.bounding_radius());
    }
    const double reach = 2.0 * largest + ws.search_skin * smallest;
    for (int k = 0; k < 3; ++k) {
      if (cell.periodic(k) && !(cell.width(k) > 2.0 * reach)) {
        throw ScenarioError(scenario.source, scenario.periodic.position.line, scenario.periodic.position.column,
                            "periodic.axes",
                            fmt::format("the cell is {:.4g} mm across {}, but a pair of these grains reaches {:.4g} mm "
                                        "(2 x the largest bounding radius, {:.4g} mm, plus the search skin): a periodic "
                                        "cell must be over twice that across, so that no pair meets twice; use a "
                                        "larger box or more, smaller grains",
                                        cell.width(k) * 1e3, "xyz"[k], reach * 1e3, largest * 1e3));
      }
    }
    world.set_cell(cell);
  }
  if (scenario.thermal.enabled) apply_thermal(scenario, world);
  for (std::size_t i = 0; i < scenario.walls.size(); ++i) {
    physics::Wall w = scenario.walls[i];
    if (i < scenario.wall_gaps.size() && !std::isnan(scenario.wall_gaps[i])) {
      // Against the specimen: the nearest grain's surface (its vertices dilated by the contact
      // radius, where contact begins) lies `gap` in front of the wall.
      const Eigen::Vector3d n = w.normal.normalized();
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& g : specimen.grains) {
        for (const auto& v : specimen.shapes.at(static_cast<std::size_t>(g.shape)).vertices_approx())
          nearest = std::min(nearest, (g.site.centre + v + lift - w.origin).dot(n));
      }
      if (std::isfinite(nearest))
        w.origin += (nearest - scenario.contact.dilation_radius - scenario.wall_gaps[i]) * n;
    }
    world.add_wall(w);
  }
  return world;
}

}  // namespace cleave::io
