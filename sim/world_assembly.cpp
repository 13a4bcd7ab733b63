#include "sim/world_assembly.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>

#include "geometry/rng.hpp"
#include "sim/phases.hpp"

namespace cleave::sim {

using io::DynamicsDef;
using io::length_unit_metres;
using io::Scenario;
using io::ScenarioError;
using io::SourcePosition;
using io::StageDef;
using io::ThermalDef;

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

/// The lightest density a body carries: the material's (the lightest phase's), times
/// [dynamics] density_scale.
double lightest_grain_density(const Scenario& scenario) {
  return lightest_density(scenario) * scenario.dynamics.density_scale;
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
  // The stiffest phase's bonds (stiffest_bond_factor: 1 without phases).
  const double stiffest = stiffest_bond_factor(scenario);
  const double kbn = scenario.bond.params.kbn * stiffest;
  double bond_normal = scenario.bond.enabled ? kbn * section.area() : 0.0;
  double bond_rolling = scenario.bond.enabled ? kbn * section.inertia() : 0.0;
  if (scenario.bond.enabled && scenario.bond.params.law == physics::BondLaw::beam) {
    // A beam of length L: E A / L along it, 12 E I / L^3 across it, 6 E I / L against an end
    // turned with the other (beam_force's element).
    physics::BondParams b = scenario.bond.params;
    b.beam_young *= stiffest;
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
  const double rho = lightest_grain_density(scenario);
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

std::string advised_time_step(double limit) {
  // The largest 3-digit decimal not above the limit, found by reading the text back as the
  // scenario reader would: rounding to nearest could advise a step just above it.
  const double scale = std::pow(10.0, 2.0 - std::floor(std::log10(limit)));
  for (double m = std::floor(limit * scale) + 1.0; m > 0.0; m -= 1.0) {
    std::string text = fmt::format("{:.3g}", m / scale);
    if (std::strtod(text.c_str(), nullptr) <= limit) return text;
  }
  return fmt::format("{:.17g}", limit);
}

namespace {
double check_time_step(const Scenario& scenario, const std::vector<physics::RigidShape>& shapes) {
  const DynamicsDef& dyn = scenario.dynamics;
  const StableStep s = stable_step(scenario, shapes);
  if (dyn.dt > s.dt) {
    throw ScenarioError(
        scenario.source, dyn.dt_position.line, dyn.dt_position.column, "dynamics.dt",
        fmt::format("time step {:.3g} s is above the stable limit; use dt <= {} s "
                    "(= dt_safety {:g} x 2 sqrt(m/k): lightest body {:.3g} kg, I {:.3g} kg m^2, "
                    "stiffest spring C_res K_n (+ K_bn) = {:.3g} N/m)",
                    dyn.dt, advised_time_step(s.dt), dyn.dt_safety, s.mass, s.inertia,
                    s.stiffness));
  }
  return s.dt;
}
}  // namespace

double check_time_step(const Scenario& scenario, const geometry::Specimen& specimen) {
  return check_time_step(scenario, grain_shapes(scenario, specimen));
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

void apply_thermal(const Scenario& scenario, const geometry::Specimen& specimen, physics::World& world) {
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
  const bool phase_alpha = std::any_of(scenario.phases.begin(), scenario.phases.end(),
                                       [](const io::PhaseDef& p) { return !std::isnan(p.alpha); });
  if (thermal.alpha_a != 0.0 || thermal.alpha_b != 0.0 || thermal.alpha_c != 0.0 || phase_alpha) {
    for (const physics::BodyId id : world.body_ids()) {
      const int grain = world.info(id).grain_id;
      const geometry::Grain& g = specimen.grains.at(static_cast<std::size_t>(grain));
      if (!scenario.phases.empty()) {
        // A phase with its own (isotropic) alpha.
        const double alpha = scenario.phases.at(static_cast<std::size_t>(g.phase)).alpha;
        if (!std::isnan(alpha)) {
          world.set_expansion(
              id, physics::World::crystal_expansion(Eigen::Vector3d::UnitZ(), alpha, alpha));
          continue;
        }
      }
      if (thermal.c_axis == ThermalDef::Axis::crystal) {
        const Eigen::Vector3d abc(thermal.alpha_a, thermal.alpha_b, thermal.alpha_c);
        world.set_expansion(id, physics::World::crystal_expansion(
                                    specimen.grains.at(static_cast<std::size_t>(grain)).crystal, abc));
        continue;
      }
      const Eigen::Vector3d c = grain_c_axis(thermal, grain);
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

namespace {
/// The bodies of a world as the narrow phase sees them, for the start checks.
std::vector<physics::PosedShape> posed_bodies(const physics::World& world,
                                              const std::vector<physics::BodyId>& ids) {
  std::vector<physics::PosedShape> posed(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    posed[i].update(world.shape(world.info(ids[i]).shape), world.state(ids[i]));
  }
  return posed;
}

/// A length in the file's unit, for messages.
struct InUnit {
  const Scenario& s;
  std::string operator()(double metres) const {
    return fmt::format("{:.4g} {}", metres / length_unit_metres(s.length_unit), s.length_unit);
  }
};

/// What to change when neighbouring grains overlap or stand apart: the specimen's own keys.
std::string spacing_keys(const Scenario& s, const InUnit& in_unit) {
  const geometry::SpecimenDef& d = s.specimen;
  switch (d.kind) {
    case geometry::SpecimenKind::lattice:
      return fmt::format(
          "[grain] r - r_bar (neighbouring side faces are sqrt(3) (r - r_bar) = {} apart) and "
          "[contact] dilation_radius ({})",
          in_unit(std::sqrt(3.0) * (d.r - d.r_bar)), in_unit(s.contact.dilation_radius));
    case geometry::SpecimenKind::voronoi:
      return fmt::format("[specimen] gap ({}) and [contact] dilation_radius ({})",
                         in_unit(d.voronoi.gap), in_unit(s.contact.dilation_radius));
    default:
      return fmt::format(
          "the [[mesh_grain]] positions and scales and [contact] dilation_radius ({})",
          in_unit(s.contact.dilation_radius));
  }
}

/// The first stage bonds (before anything moves): the overlaps at the start are stored.
const StageDef* bond_stage_first(const Scenario& s) {
  return !s.stages.empty() && s.stages.front().kind == StageDef::Kind::bond ? &s.stages.front()
                                                                            : nullptr;
}

/// Neighbouring grains: overlaps where no bond stage stores them, shapes that intersect, and
/// a first bond stage that leaves a grain without a bond. One broad phase on the bounding
/// spheres (within the reach the checks need) and the narrow phase on its pairs.
void check_grain_spacing(const Scenario& s, const physics::World& world,
                         const std::vector<physics::BodyId>& ids,
                         const std::vector<physics::PosedShape>& posed) {
  if (ids.size() < 2) return;
  const InUnit in_unit{s};
  const double dilation = s.contact.dilation_radius;
  const double tolerance = 1e-6 * dilation;
  const StageDef* bond = bond_stage_first(s);
  std::vector<physics::BoundingSphere> spheres;
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const double r = world.shape(world.info(ids[i]).shape).bounding_radius();
    spheres.push_back({world.state(ids[i]).x, r});
    smallest = std::min(smallest, r);
  }
  std::vector<physics::BodyPair> pairs;
  physics::NeighbourSearch search(s.dynamics.search);
  // The pairs the first step meets, or that the first bond stage bonds (its distance as the
  // margin, as World::initialise_bonds searches).
  search.find_pairs(spheres, bond ? bond->bond_distance : 0.0, pairs);
  std::vector<char> bonded(ids.size(), 0);
  std::vector<physics::FeatureContact> features;
  double deepest = 0.0;
  physics::BodyPair deepest_pair{0, 0};
  for (const auto& [i, j] : pairs) {
    features.clear();
    physics::polyhedron_contacts(posed[i], posed[j], 0.0, features);
    for (const auto& f : features) {
      if (f.contact.penetration > deepest) {
        deepest = f.contact.penetration;
        deepest_pair = {i, j};
      }
    }
    if (bond && !(bonded[i] && bonded[j])) {
      if (bond->bond_distance > 0.0)
        physics::polyhedron_contacts(posed[i], posed[j], bond->bond_distance, features);
      if (!features.empty()) bonded[i] = bonded[j] = 1;
    }
  }
  const SourcePosition& at = s.contact.dilation_position;
  const int grain_a = world.info(ids[deepest_pair.first]).grain_id;
  const int grain_b = world.info(ids[deepest_pair.second]).grain_id;
  if (deepest > 2.0 * dilation + tolerance) {
    throw ScenarioError(
        s.source, at.line, at.column, "contact.dilation_radius",
        fmt::format(
            "grains {} and {} overlap by {} at the start, more than their two dilation radii ({}): "
            "their shapes themselves intersect, which no contact can resolve; change {}",
            grain_a, grain_b, in_unit(deepest), in_unit(2.0 * dilation), spacing_keys(s, in_unit)));
  }
  // Deeper than a dilation radius is no packing at rest (its overlaps are a small fraction of
  // the dilation) but grains placed into each other.
  if (deepest > dilation + tolerance && bond == nullptr) {
    throw ScenarioError(s.source, at.line, at.column, "contact.dilation_radius",
                        fmt::format("grains {} and {} overlap by {} at the start, more than the "
                                    "dilation radius ({}), and no "
                                    "bond stage comes first to store the overlap: their contact "
                                    "pushes them apart from step 1. "
                                    "Leave neighbours' dilated surfaces apart: change {}",
                                    grain_a, grain_b, in_unit(deepest), in_unit(dilation),
                                    spacing_keys(s, in_unit)));
  }
  // A periodic cell's pairs across its faces are not searched here: its bonding is left to the run.
  if (bond == nullptr || world.cell() != nullptr) return;
  // Every grain bonds to a neighbour within the distance (World::initialise_bonds).
  const std::size_t loose = static_cast<std::size_t>(std::count(bonded.begin(), bonded.end(), 0));
  if (loose == 0) return;
  // What distance would do: each loose grain's nearest neighbour, looked for up to half the
  // smallest grain's reach; only features whose normal points from one grain to the other
  // count (at margins near a grain's size the search also pairs a vertex with a face behind it).
  const double reach = std::max(2.0 * bond->bond_distance, 0.5 * smallest);
  search.find_pairs(spheres, reach, pairs);
  std::vector<double> nearest(ids.size(), std::numeric_limits<double>::infinity());
  for (const auto& [i, j] : pairs) {
    if (bonded[i] && bonded[j]) continue;
    features.clear();
    physics::polyhedron_contacts(posed[i], posed[j], reach, features);
    const Eigen::Vector3d across = posed[j].centre - posed[i].centre;
    for (const auto& f : features) {
      if (f.contact.normal.dot(across) <= 0.0) continue;
      nearest[i] = std::min(nearest[i], -f.contact.penetration);
      nearest[j] = std::min(nearest[j], -f.contact.penetration);
    }
  }
  double widest = 0.0;
  int loose_grain = -1;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (bonded[i] || (loose_grain >= 0 && !(nearest[i] > widest))) continue;
    widest = nearest[i];
    loose_grain = world.info(ids[i]).grain_id;
  }
  const std::size_t index = static_cast<std::size_t>(bond - s.stages.data());
  const std::string nearest_text =
      std::isfinite(widest)
          ? fmt::format("its nearest neighbour's dilated surface is {} away", in_unit(widest))
          : fmt::format("no other grain is within {} of it", in_unit(reach));
  throw ScenarioError(
      s.source, bond->distance_position.line, bond->distance_position.column,
      fmt::format("stage[{}].distance", index + 1),
      fmt::format("bond stage '{}' bonds grains within {} of each other, but {} of the {} grains "
                  "would get no "
                  "bond (grain {}: {}). Give a distance above the gap between neighbours' dilated "
                  "surfaces{}; when the grains change size, scale distance together with {}",
                  bond->name, in_unit(bond->bond_distance), loose, ids.size(), loose_grain,
                  nearest_text, std::isfinite(widest) ? " (" + in_unit(widest) + ")" : "",
                  spacing_keys(s, in_unit)));
}

/// How far wall `w` (a plane or platen) is in front of the specimen: the least distance from
/// its surface to a dilated vertex of a body in its footprint along its normal (negative: the
/// wall cuts into a body); infinity when no body is in the footprint.
struct WallReach {
  double gap = std::numeric_limits<double>::infinity();
  std::size_t body = 0;
};
WallReach wall_reach(const physics::Wall& w, const std::vector<physics::PosedShape>& posed) {
  WallReach r;
  for (std::size_t i = 0; i < posed.size(); ++i) {
    for (const Eigen::Vector3d& v : posed[i].vertices) {
      const auto c = w.sphere_contact(v, posed[i].radius, std::numeric_limits<double>::infinity());
      if (c && -c->penetration < r.gap) {
        r.gap = -c->penetration;
        r.body = i;
      }
    }
  }
  return r;
}

/// The deepest a cylinder wall reaches into a body's dilated vertices and edges (0: none).
WallReach cylinder_reach(const physics::Wall& w, const std::vector<physics::PosedShape>& posed) {
  WallReach r;
  r.gap = 0.0;
  for (std::size_t i = 0; i < posed.size(); ++i) {
    const physics::PosedShape& p = posed[i];
    auto take = [&](const std::optional<physics::PrimitiveContact>& c) {
      if (c && -c->penetration < r.gap) {
        r.gap = -c->penetration;
        r.body = i;
      }
    };
    for (const Eigen::Vector3d& v : p.vertices) take(w.sphere_contact(v, p.radius));
    for (const auto& e : p.primitives->edges) {
      take(w.edge_contact(p.vertices[static_cast<std::size_t>(e.a)],
                          p.vertices[static_cast<std::size_t>(e.b)], p.radius));
    }
  }
  return r;
}

/// Walls that cut into the specimen at the start, and walls_touch stages that cannot close
/// their walls' gaps.
void check_walls(const Scenario& s, const physics::World& world,
                 const std::vector<physics::BodyId>& ids,
                 const std::vector<physics::PosedShape>& posed) {
  const InUnit in_unit{s};
  const double dilation = s.contact.dilation_radius;
  const double tolerance = 1e-6 * dilation;
  const std::vector<physics::Wall>& walls = world.walls();
  auto wall_index = [&](const std::string& name) {
    return static_cast<std::size_t>(
        std::find_if(walls.begin(), walls.end(), [&](const auto& w) { return w.name == name; }) -
        walls.begin());
  };
  // A wall `depth` into grain body `b`'s dilated surface.
  auto cut = [&](std::size_t k, double depth, std::size_t body, const std::string& why) {
    const physics::Wall& w = walls[k];
    const SourcePosition at = k < s.wall_points.size() ? s.wall_points[k] : SourcePosition{};
    const std::string fix = w.kind == physics::Wall::Kind::cylinder
                                ? "move its point clear of the specimen"
                                : fmt::format(
                                      "move its point at least that far out along its normal, or "
                                      "give gap (its distance from "
                                      "the specimen's dilated surface, in {}), which places it "
                                      "whatever the grains' size",
                                      s.length_unit);
    return ScenarioError(
        s.source, at.line, at.column, fmt::format("wall[{}].point", k + 1),
        fmt::format(
            "wall '{}' reaches {} into grain {} at the start (its surface dilated by {}): {}; "
            "{}",
            w.name, in_unit(depth), world.info(ids[body]).grain_id, in_unit(dilation), why, fix));
  };
  std::vector<WallReach> reach(walls.size());
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const physics::Wall& w = walls[k];
    reach[k] =
        w.kind == physics::Wall::Kind::cylinder ? cylinder_reach(w, posed) : wall_reach(w, posed);
    // Past the dilated skin into the grain itself: no contact at rest is that deep (a packing
    // pressed onto a floor overlaps it by a small fraction of the dilation).
    if (reach[k].gap < -dilation - tolerance) {
      throw cut(k, -reach[k].gap, reach[k].body,
                "it cuts the grain itself and pushes the specimen from step 1");
    }
  }
  // The walls' travel through the stages, while it is known (a stage that ends on an event
  // leaves it unknown): a walls_touch stage must start with its load walls clear of the
  // specimen, and bring each one it moves to it.
  std::vector<double> closed(walls.size(), 0.0);
  for (std::size_t si = 0; si < s.stages.size(); ++si) {
    const StageDef& st = s.stages[si];
    if (st.kind != StageDef::Kind::motion) continue;
    const std::string stage = fmt::format("stage[{}]", si + 1);
    auto gap_of = [&](std::size_t k) { return reach[k].gap - closed[k]; };
    if (st.until == StageDef::Until::walls_touch) {
      for (const std::string& name : st.load_walls) {
        const std::size_t k = wall_index(name);
        if (k == walls.size() || walls[k].kind == physics::Wall::Kind::cylinder ||
            !(gap_of(k) < -tolerance))
          continue;
        throw cut(
            k, -gap_of(k), reach[k].body,
            fmt::format(
                "stage '{}' waits for it to touch the specimen, but it starts inside it and the "
                "stage ends at once on a specimen pressed by it",
                st.name));
      }
    }
    const double length = st.steps > 0 ? static_cast<double>(st.steps) * s.dynamics.dt : st.time;
    // A velocity ramped up over ramp_time: the time at full speed that covers the same distance.
    const double full_speed_time = st.ramp_time >= length ? length * length / (2.0 * st.ramp_time)
                                                          : length - 0.5 * st.ramp_time;
    for (std::size_t j = 0; j < st.wall_velocity.size(); ++j) {
      const auto& [name, v] = st.wall_velocity[j];
      const std::size_t k = wall_index(name);
      if (k == walls.size() || walls[k].kind == physics::Wall::Kind::cylinder) continue;
      const double gap = gap_of(k);
      const double speed = v.dot(walls[k].normal);  // towards the bodies' side
      if (st.until == StageDef::Until::walls_touch &&
          std::find(st.load_walls.begin(), st.load_walls.end(), name) != st.load_walls.end() &&
          gap > tolerance) {
        if (!std::isfinite(gap)) {
          const SourcePosition at = k < s.wall_points.size() ? s.wall_points[k] : SourcePosition{};
          throw ScenarioError(
              s.source, at.line, at.column, fmt::format("wall[{}].point", k + 1),
              fmt::format(
                  "stage '{}' waits for wall '{}' to touch the specimen, but no grain lies in "
                  "front of it (its platen's footprint misses the specimen)",
                  st.name, name));
        }
        const SourcePosition vat =
            j < st.wall_velocity_positions.size() ? st.wall_velocity_positions[j] : st.position;
        if (!(speed > 0.0)) {
          throw ScenarioError(
              s.source, vat.line, vat.column, fmt::format("{}.wall_velocity.{}", stage, name),
              fmt::format("stage '{}' (until = \"walls_touch\") moves wall '{}' {} the specimen "
                          "(its velocity along "
                          "the wall's normal, towards the grains, is {} per s), but the specimen's "
                          "surface is {} in "
                          "front of it: the wall never touches; reverse the velocity",
                          st.name, name, speed < 0.0 ? "away from" : "parallel to", in_unit(speed),
                          in_unit(gap)));
        }
        const double travel = speed * full_speed_time;
        if (travel < gap) {
          const double at_speed = gap / speed;  // the time needed without a ramp
          const double needed = at_speed >= 0.5 * st.ramp_time
                                    ? at_speed + 0.5 * st.ramp_time
                                    : std::sqrt(2.0 * st.ramp_time * at_speed);
          throw ScenarioError(
              s.source, st.length_position.line, st.length_position.column,
              fmt::format("{}.{}", stage, st.steps > 0 ? "steps" : "time"),
              fmt::format("stage '{}' (until = \"walls_touch\") moves wall '{}' {} towards the "
                          "specimen in its {:.4g} "
                          "s, but the specimen's surface is {} in front of it: the stage would end "
                          "before the wall "
                          "touches; give it at least {:.4g} s ({} steps), a faster wall_velocity, "
                          "or place the wall "
                          "with gap",
                          st.name, name, in_unit(travel), length, in_unit(gap), needed,
                          static_cast<std::uint64_t>(std::ceil(needed / s.dynamics.dt))));
        }
      }
      closed[k] += speed * full_speed_time;
    }
    if (st.until != StageDef::Until::limit) break;  // where the walls stop is not known
  }
}
}  // namespace

std::vector<ScenarioError> start_warnings(const Scenario& scenario,
                                          const geometry::Specimen& specimen) {
  std::vector<ScenarioError> warnings;
  const geometry::SpecimenDef& d = scenario.specimen;
  const StageDef* bond = bond_stage_first(scenario);
  if (!scenario.dynamics.enabled || bond == nullptr || d.kind != geometry::SpecimenKind::lattice)
    return warnings;
  const InUnit in_unit{scenario};
  const double dilation = scenario.contact.dilation_radius;
  // Neighbouring prisms' side faces are sqrt(3) (r - r_bar) apart; stacked layers' end faces
  // t - t_bar (App. C).
  const double side = std::sqrt(3.0) * (d.r - d.r_bar);
  bool layers = false;
  for (const auto& g : specimen.grains)
    layers = layers || g.site.centre.z() != specimen.grains.front().site.centre.z();
  std::string what;
  if (side < 2.0 * dilation) {
    what = fmt::format("neighbouring grains' side faces are sqrt(3) (r - r_bar) = {} apart",
                       in_unit(side));
  } else if (layers && d.t - d.t_bar < 2.0 * dilation) {
    what =
        fmt::format("stacked grains' end faces are t - t_bar = {} apart", in_unit(d.t - d.t_bar));
  } else {
    return warnings;
  }
  const SourcePosition& at = scenario.contact.dilation_position;
  warnings.emplace_back(
      scenario.source, at.line, at.column, "contact.dilation_radius",
      fmt::format(
          "{}, less than two dilation radii ({}): their dilated surfaces overlap at the start. "
          "Bond stage "
          "'{}' stores the overlap, but every bonded pair then also touches from step 1, stiffer "
          "in "
          "compression than in tension. For the same model with other grains, scale [contact] "
          "dilation_radius and the stage's distance ({}) with r - r_bar",
          what, in_unit(2.0 * dilation), bond->name, in_unit(bond->bond_distance)));
  return warnings;
}

void check_start(const Scenario& scenario, const physics::World& world) {
  const std::vector<physics::BodyId> ids = world.body_ids();
  const std::vector<physics::PosedShape> posed = posed_bodies(world, ids);
  check_grain_spacing(scenario, world, ids, posed);
  check_walls(scenario, world, ids, posed);
}

physics::World make_world(const Scenario& scenario, const geometry::Specimen& specimen) {
  return assemble_world(scenario, specimen).world;
}

AssembledWorld assemble_world(const Scenario& scenario, const geometry::Specimen& specimen) {
  const std::vector<physics::RigidShape> shapes = grain_shapes(scenario, specimen);
  const double stable_dt = check_time_step(scenario, shapes);
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
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    try {
      ids.push_back(world.add_shape(shapes[k]));
    } catch (const std::invalid_argument& e) {
      // Name the grain: shape k is the first grain of that shape.
      int grain = -1;
      for (const auto& g : specimen.grains) {
        if (g.shape == static_cast<int>(k)) {
          grain = g.id;
          break;
        }
      }
      throw std::invalid_argument(fmt::format("{}: grain {}: {}", scenario.source, grain, e.what()));
    }
  }
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
    world.add_body(ids.at(k), grain_density(scenario, g), g.site.centre + shapes[k].centroid + lift,
                   shapes[k].orientation_for(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                   g.id);
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
  if (scenario.thermal.enabled) apply_thermal(scenario, specimen, world);
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
      // A point the file already puts at the gap, to rounding, is kept as written: giving gap
      // to a wall placed by hand does not move it by the bits of this sum.
      const double move = nearest - scenario.contact.dilation_radius - scenario.wall_gaps[i];
      if (std::isfinite(nearest) && std::abs(move) > 1e-9 * scenario.contact.dilation_radius)
        w.origin += move * n;
    }
    world.add_wall(w);
  }
  check_start(scenario, world);
  return {std::move(world), stable_dt};
}

}  // namespace cleave::sim
