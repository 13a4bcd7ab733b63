#pragma once
/// \file
/// The world: shapes, bodies in contiguous arrays addressed by stable ids, and the step
/// orchestrator. `step()` runs named stages in order (see docs/ARCHITECTURE.md):
///   kick + drift -> forces (gravity, then contacts) -> kick.

#include <Eigen/Dense>
#include <cstdint>
#include <vector>


#include "physics/body.hpp"
#include "physics/contact_law.hpp"
#include "physics/narrow_phase.hpp"
#include "physics/neighbour_search.hpp"
#include "physics/rigid_shape.hpp"
#include "physics/wall.hpp"

namespace cleave::physics {

struct WorldSettings {
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.80665);  ///< m/s^2
  double dt = 1e-6;                                               ///< time step, s
  ContactParams particle_particle;  ///< table 2.3, particle-particle set
  ContactParams particle_wall;      ///< table 2.3, particle-wall set
  SearchMethod search = SearchMethod::bounding_box;
  /// Threads for the per-body and per-contact loops (0: OpenMP's default, i.e. all cores).
  /// Results are bit-identical for any count: work is split into ordered blocks and the
  /// forces are summed in contact order.
  int threads = 0;
  /// Verlet skin of the neighbour search, as a fraction of the smallest bounding radius:
  /// pairs are searched with this margin and reused until some body has moved more than
  /// half of it (0: search every step).
  double search_skin = 0.1;
};

/// One contact of the last step, for output and tests.
struct ContactRecord {
  std::uint32_t a = 0;          ///< body slot of A, or wall index when `wall` is set
  std::uint32_t b = 0;          ///< body slot of B
  bool wall = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< from A towards B
  double overlap = 0.0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< on B
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

  /// Adds a wall; returns its index.
  std::size_t add_wall(Wall wall);
  [[nodiscard]] const std::vector<Wall>& walls() const { return walls_; }
  [[nodiscard]] Wall& wall(std::size_t i) { return walls_.at(i); }

  /// Advances the world by one time step.
  void step();
  /// Contacts of the last force evaluation.
  [[nodiscard]] const std::vector<ContactRecord>& contacts() const { return records_; }
  /// Slots of live bodies in ascending order, with their ids.
  [[nodiscard]] std::vector<BodyId> body_ids() const;
  /// The averaged stress (eq. 2.17, grain_stress.hpp) of every body from the contacts of
  /// the last force evaluation, indexed by slot (zero for slots without a live body).
  [[nodiscard]] std::vector<Eigen::Matrix3d> body_stresses() const;
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
  void body_contacts(int threads);
  void wall_contacts();
  void evaluate_and_apply(int threads);
  void evaluate_contact(std::size_t k, std::size_t& history_cursor);
  void sum_forces();

  /// A contact's identity across steps: the two bodies (or wall and body) and the two
  /// features touching. Contacts are produced in ascending key order every step, so the
  /// history of the previous step is found by a forward merge, without hashing.
  struct ContactKey {
    std::uint32_t a, b, fa, fb;
    auto operator<=>(const ContactKey&) const = default;
  };
  struct HistoryEntry {
    ContactKey key;
    ContactHistory history;
  };
  /// A contact found this step, before the law is applied.
  struct Pending {
    ContactKey key;  // a carries kWallFlag for wall contacts
    PrimitiveContact contact;
  };
  const ContactHistory* previous_history(const ContactKey& key) const;
  static constexpr std::uint32_t kWallFlag = 0x80000000u;

  WorldSettings settings_;
  std::vector<RigidShape> shapes_;
  std::vector<BodyState> states_;  // hot, indexed by slot
  std::vector<BodyInfo> infos_;    // cold, indexed by slot
  std::vector<std::uint32_t> free_slots_;
  std::size_t live_ = 0;
  std::vector<Wall> walls_;
  std::vector<PosedShape> posed_;         // by slot, refreshed each force evaluation
  std::vector<std::uint32_t> live_slots_;
  std::vector<BoundingSphere> spheres_;
  std::vector<BodyPair> pairs_;
  std::vector<Eigen::Vector3d> searched_at_;  // centres at the last search, by live index
  double skin_ = 0.0;                         // margin of the last search
  bool pairs_current_ = false;
  NeighbourSearch search_;
  std::vector<HistoryEntry> history_, next_history_;  // sorted by key
  std::vector<Pending> pending_;
  std::vector<std::vector<Pending>> thread_pending_;
  std::vector<ContactForce> forces_;
  std::vector<ContactRecord> records_;
  double time_ = 0.0;
  std::uint64_t steps_ = 0;
  bool forces_current_ = false;
};

}  // namespace cleave::physics
