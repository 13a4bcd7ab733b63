#pragma once
/// \file
/// The world: shapes, bodies in contiguous arrays addressed by stable ids, and the step
/// orchestrator. `step()` runs named stages in order (see docs/ARCHITECTURE.md):
///   kick + drift -> forces (gravity, then contacts) -> kick.

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "physics/body.hpp"
#include "physics/rigid_shape.hpp"

namespace cleave::physics {

struct WorldSettings {
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.80665);  ///< m/s^2
  double dt = 1e-6;                                               ///< time step, s
};

class World {
 public:
  explicit World(WorldSettings settings = {});

  /// Registers a shape; bodies refer to it by the returned index.
  std::uint32_t add_shape(RigidShape shape);
  [[nodiscard]] const RigidShape& shape(std::uint32_t index) const { return shapes_[index]; }

  /// Adds a body of `shape` with density `rho` (kg/m^3), centroid at `x`, principal frame
  /// turned to world by `q`, velocity `v` and angular velocity `w` (world).
  BodyId add_body(std::uint32_t shape, double rho, const Eigen::Vector3d& x,
                  const Eigen::Quaterniond& q, const Eigen::Vector3d& v = Eigen::Vector3d::Zero(),
                  const Eigen::Vector3d& w = Eigen::Vector3d::Zero(), int grain_id = -1);
  /// Removes a body; its id (and any copy of it) becomes invalid.
  void remove_body(BodyId id);
  [[nodiscard]] bool contains(BodyId id) const;
  [[nodiscard]] std::size_t body_count() const { return live_; }

  /// Access by id; throws std::out_of_range for a stale or invalid id.
  [[nodiscard]] const BodyState& state(BodyId id) const;
  [[nodiscard]] BodyState& state(BodyId id);
  [[nodiscard]] const BodyInfo& info(BodyId id) const;
  /// Sets a body's angular velocity (world), i.e. its angular momentum L = R I R^T w.
  void set_angular_velocity(BodyId id, const Eigen::Vector3d& w);

  /// Advances the world by one time step.
  void step();
  [[nodiscard]] double time() const { return time_; }
  [[nodiscard]] std::uint64_t steps() const { return steps_; }
  [[nodiscard]] const WorldSettings& settings() const { return settings_; }

  /// Totals over live bodies (for tests and reports).
  [[nodiscard]] double kinetic_energy() const;
  [[nodiscard]] double potential_energy() const;  ///< -m g . x
  [[nodiscard]] Eigen::Vector3d linear_momentum() const;
  [[nodiscard]] Eigen::Vector3d angular_momentum() const;  ///< about the world origin

 private:
  void compute_forces();

  WorldSettings settings_;
  std::vector<RigidShape> shapes_;
  std::vector<BodyState> states_;  // hot, indexed by slot
  std::vector<BodyInfo> infos_;    // cold, indexed by slot
  std::vector<std::uint32_t> free_slots_;
  std::size_t live_ = 0;
  double time_ = 0.0;
  std::uint64_t steps_ = 0;
  bool forces_current_ = false;
};

}  // namespace cleave::physics
