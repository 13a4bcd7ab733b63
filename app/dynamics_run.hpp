#pragma once
/// \file
/// A dynamic run of a specimen: the grains become bodies of a physics::World, fall under
/// gravity onto the walls, and the run writes ParaView frames and an energy history.

#include <filesystem>
#include <string>

#include "geometry/specimen.hpp"
#include "io/scenario.hpp"

namespace cleave::app {

struct DynamicsSummary {
  std::uint64_t steps = 0;
  double time = 0.0;
  double kinetic_energy = 0.0;
  double released_energy = 0.0;    ///< potential energy released since the start
  double max_overlap = 0.0;        ///< largest contact overlap seen, m
  double lowest_point = 0.0;       ///< lowest body vertex at the end (world z), m
  bool settled = false;            ///< KE fell below settle_ratio x released energy
  int frames = 0;
  double wall_seconds = 0.0;
};

/// Runs [dynamics] of `scenario` on `specimen`, writing frames/ (bodies_*.vtp,
/// contacts_*.vtp), bodies.pvd, contacts.pvd, energy.csv and walls.csv into `out`. Throws
/// io::ScenarioError when the time step is above the stable limit (io::check_time_step).
DynamicsSummary run_dynamics(const io::Scenario& scenario, const geometry::Specimen& specimen,
                             const std::filesystem::path& out, bool quiet,
                             std::uint64_t max_steps = 0);

}  // namespace cleave::app
