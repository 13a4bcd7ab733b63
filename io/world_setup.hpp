#pragma once
/// \file
/// From a scenario and its specimen to a physics::World: one body per grain (world shape k
/// is the rigid form of Specimen::shapes[k]; lattice grains share one prism), the walls,
/// the contact parameters, and the stable time step check (the most restrictive shape).

#include "geometry/specimen.hpp"
#include "io/scenario.hpp"
#include "physics/dem/world.hpp"

namespace cleave::io {

/// The largest stable time step: dt_safety x 2 sqrt(m/k) for the lightest body against the
/// stiffest spring (C_res K_n on unloading), for translation and for rotation about the
/// weakest axis with the spring at the body's bounding radius.
double stable_time_step(const Scenario& scenario, const geometry::Specimen& specimen);

/// Throws ScenarioError at [dynamics] dt (file, line, key) when dt is above
/// stable_time_step, saying which value is needed.
void check_time_step(const Scenario& scenario, const geometry::Specimen& specimen);

/// The same stable step for one body of the given mass, smallest principal moment of
/// inertia and bounding radius (e.g. a piece a transgranular split has just made), with
/// the scenario's springs and dt_safety.
double stable_time_step(const Scenario& scenario, double mass, double inertia, double bounding_radius);

/// The world of a [dynamics] run: grains become bodies at their lattice centres lifted so
/// the specimen's lowest point is `dynamics.lift` above z = 0, at rest; walls are added in
/// file order. Checks the time step first.
physics::World make_world(const Scenario& scenario, const geometry::Specimen& specimen);

/// A grain's c-axis under [thermal] c_axis: z (a honeycomb grain's prism axis) or a
/// direction uniform on the sphere drawn from the seed and the grain's id.
Eigen::Vector3d grain_c_axis(const ThermalDef& thermal, int grain_id);

/// [thermal] on a world of grains (make_world calls it): every grain at the temperature (and
/// the gradient's linear field; a field below 0 K is a ScenarioError at thermal.gradient), its
/// expansion tensor alpha_a I + (alpha_c - alpha_a) c c^T about its c-axis, the conduction.
void apply_thermal(const Scenario& scenario, physics::World& world);

}  // namespace cleave::io
