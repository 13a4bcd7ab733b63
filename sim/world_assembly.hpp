#pragma once
/// \file
/// From a scenario and its specimen to a physics::World: one body per grain (world shape k
/// is the rigid form of Specimen::shapes[k]; lattice grains share one prism), the walls,
/// the contact parameters, and the stable time step check (the most restrictive shape).

#include <string>
#include <vector>

#include "geometry/specimen.hpp"
#include "io/scenario.hpp"
#include "physics/dem/world.hpp"

namespace cleave::sim {

/// The largest stable time step: dt_safety x 2 sqrt(m/k) for the lightest body against the
/// stiffest spring (C_res K_n on unloading), for translation and for rotation about the
/// weakest axis with the spring at the body's bounding radius.
double stable_time_step(const io::Scenario& scenario, const geometry::Specimen& specimen);

/// Throws io::ScenarioError at [dynamics] dt (file, line, key) when dt is above
/// stable_time_step, saying which value is needed (advised_time_step). Returns the limit.
double check_time_step(const io::Scenario& scenario, const geometry::Specimen& specimen);

/// The time step the refusal advises for a stable `limit`: the largest decimal of three
/// significant digits whose text, read back, is not above it (so that setting it passes).
std::string advised_time_step(double limit);

/// The start of a run, before step 1 (make_world calls it on the world it made): throws
/// io::ScenarioError naming the file, line and keys when
/// - neighbouring grains' dilated surfaces overlap by more than the dilation radius and no
///   bond stage comes first to store the overlap, or their shapes themselves intersect
///   (contact.dilation_radius, naming [grain] r and r_bar or the specimen's own keys);
/// - a first bond stage's distance leaves some grain without a bond (stage[N].distance);
/// - a wall reaches past a grain's dilated surface into the grain itself, or a load wall of
///   an until = "walls_touch" stage starts inside the specimen (wall[N].point);
/// - such a stage moves a load wall away from the specimen, or not as far as the gap in
///   front of it in its length (stage[N].wall_velocity.NAME, stage[N].time or .steps).
/// Pairs across a periodic cell's faces are not searched.
/// One broad phase on bounding spheres, the narrow phase on its pairs and one pass over the
/// vertices per wall: the cost of about one step.
void check_start(const io::Scenario& scenario, const physics::World& world);

/// What a run may start with but seldom means, as ScenarioErrors to print as warnings: a
/// lattice bonded by a first bond stage whose neighbours' dilated faces overlap (side faces
/// sqrt(3) (r - r_bar) or stacked end faces t - t_bar apart, under two dilation radii), so
/// that every bonded pair also touches from the start (a grain size changed without
/// scaling [contact] dilation_radius and the bond distance with it).
std::vector<io::ScenarioError> start_warnings(const io::Scenario& scenario,
                                          const geometry::Specimen& specimen);

/// The same stable step for one body of the given mass, smallest principal moment of
/// inertia and bounding radius (e.g. a piece a transgranular split has just made), with
/// the scenario's springs and dt_safety.
double stable_time_step(const io::Scenario& scenario, double mass, double inertia, double bounding_radius);

/// The world of a [dynamics] run: grains become bodies at their lattice centres lifted so
/// the specimen's lowest point is `dynamics.lift` above z = 0, at rest; walls are added in
/// file order (a `gap` wall placed against the specimen). Checks the time step first and
/// the start (check_start) last.
physics::World make_world(const io::Scenario& scenario, const geometry::Specimen& specimen);

/// make_world's world and the stable step its check found: the World owns dt
/// (WorldSettings::dt); the limit is kept for what a run says when it blows up.
struct AssembledWorld {
  physics::World world;
  double stable_dt = 0.0;  ///< stable_time_step, s
};
AssembledWorld assemble_world(const io::Scenario& scenario, const geometry::Specimen& specimen);

/// A grain's c-axis under [thermal] c_axis: z (a honeycomb grain's prism axis) or a
/// direction uniform on the sphere drawn from the seed and the grain's id.
Eigen::Vector3d grain_c_axis(const io::ThermalDef& thermal, int grain_id);

/// [thermal] on a world of grains (make_world calls it): every grain at the temperature (and
/// the gradient's linear field; a field below 0 K is a io::ScenarioError at thermal.gradient), its
/// expansion tensor alpha_a I + (alpha_c - alpha_a) c c^T about its c-axis (c_axis =
/// crystal: R diag(alpha_a, alpha_b, alpha_c) R^T with R its grain's crystal), the conduction.
void apply_thermal(const io::Scenario& scenario, const geometry::Specimen& specimen, physics::World& world);

}  // namespace cleave::sim
