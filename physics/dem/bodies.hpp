#pragma once
/// \file
/// The bodies' owner: shapes, and the bodies in slots (hot state, cold record, role), with
/// stable ids; the integrator's half steps over them.

#include <Eigen/Dense>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "physics/dem/body.hpp"
#include "physics/dem/domain.hpp"
#include "physics/dem/exact_sum.hpp"
#include "physics/dem/rigid_shape.hpp"

namespace cleave::physics {

/// One piece a body breaks into (chapter 3): a registered shape placed in the parent's
/// principal frame. `fragment_placement` computes the placement from the two shapes.
struct Fragment {
  std::uint32_t shape = 0;                                   ///< World shape index
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();          ///< its centroid, parent's frame
  Eigen::Quaterniond turn = Eigen::Quaterniond::Identity();  ///< its frame -> parent's frame
};

/// Where piece `piece` (cut from `parent`'s exact shape, in the same shape coordinates)
/// sits in the parent's principal frame.
Fragment fragment_placement(const RigidShape& parent, const RigidShape& piece, std::uint32_t shape);

/// Shapes and bodies. A body lives in a slot: its state (hot, read and written every step)
/// and its record (cold) at the same index; a removed body's slot is reused by the next body
/// added, with a new generation. The step's loops read the vectors directly.
class Bodies {
 public:
  std::uint32_t add_shape(RigidShape shape);
  [[nodiscard]] const RigidShape& shape(std::uint32_t index) const { return shapes_[index]; }
  [[nodiscard]] std::size_t shape_count() const { return shapes_.size(); }
  [[nodiscard]] const std::vector<RigidShape>& shapes() const { return shapes_; }
  /// The shape of the body in `slot`.
  [[nodiscard]] const RigidShape& shape_of(std::uint32_t slot) const {
    return shapes_[infos_[slot].shape];
  }

  /// A new body in a free slot (or a new one); see World::add_body.
  BodyId add(std::uint32_t shape, double rho, const Eigen::Vector3d& x, const Eigen::Quaterniond& q,
             const Eigen::Vector3d& v, const Eigen::Vector3d& w, int grain_id);
  /// Frees the body's slot (its id must be valid).
  void remove(BodyId id);
  [[nodiscard]] bool contains(BodyId id) const {
    return id.index < infos_.size() && infos_[id.index].alive &&
           infos_[id.index].generation == id.generation;
  }
  /// The slot of `id`; throws std::out_of_range naming `what` when stale or invalid.
  std::uint32_t slot_of(BodyId id, const char* what) const {
    if (!contains(id)) throw std::out_of_range(std::string(what) + "stale or invalid body id");
    return id.index;
  }
  [[nodiscard]] BodyId id_at(std::uint32_t slot) const;
  [[nodiscard]] std::vector<BodyId> ids() const;
  [[nodiscard]] std::size_t count() const { return live_; }
  /// Slots, free ones included.
  [[nodiscard]] std::size_t slots() const { return states_.size(); }
  void set_angular_velocity(std::uint32_t slot, const Eigen::Vector3d& w);

  [[nodiscard]] std::vector<BodyState>& states() { return states_; }
  [[nodiscard]] const std::vector<BodyState>& states() const { return states_; }
  [[nodiscard]] std::vector<BodyInfo>& infos() { return infos_; }
  [[nodiscard]] const std::vector<BodyInfo>& infos() const { return infos_; }
  [[nodiscard]] const std::vector<std::uint32_t>& free_slots() const { return free_slots_; }

  /// One process of a domain: the role of each slot (empty: all owned).
  [[nodiscard]] Role role(std::uint32_t slot) const {
    return roles_.empty() ? Role::owned : roles_[slot];
  }
  [[nodiscard]] bool owns(std::uint32_t slot) const { return role(slot) == Role::owned; }
  [[nodiscard]] const std::vector<Role>& roles() const { return roles_; }
  void set_roles(std::vector<Role> roles);
  /// Takes the roles away (a whole-world interlude of a domain's process), for set_roles after.
  std::vector<Role> take_roles() { return std::exchange(roles_, {}); }
  void set_role(std::uint32_t slot, Role role) {
    if (!roles_.empty()) roles_[slot] = role;
  }
  /// Whether a body came or went since the domain last partitioned, and clears it.
  bool take_changed() { return std::exchange(changed_, false); }

  /// The first half step of the velocity Verlet scheme over the owned bodies: half kick
  /// of the momenta (free ones), then the drift of every owned body.
  void kick_drift(double h, int threads);
  /// The closing half kick of the free owned bodies.
  void closing_kick(double h, int threads);
  /// WorldSettings::in_plane: drops each free body's force and momentum along z and its
  /// torque and angular momentum about x and y (`live`: the slots this evaluation posed).
  void hold_in_plane(const std::vector<std::uint32_t>& live);
  /// WorldSettings::local_damping `alpha` on the forces and torques of the free bodies.
  void apply_local_damping(double alpha, const std::vector<std::uint32_t>& live, int threads);

  [[nodiscard]] double kinetic_energy() const;
  [[nodiscard]] double potential_energy(const Eigen::Vector3d& gravity) const;
  [[nodiscard]] ExactSum owned_kinetic_energy() const;
  [[nodiscard]] ExactSum owned_potential_energy(const Eigen::Vector3d& gravity) const;
  [[nodiscard]] Eigen::Vector3d linear_momentum() const;
  [[nodiscard]] Eigen::Vector3d angular_momentum() const;

  /// A checkpoint's bodies (world_state.cpp checks them before).
  void restore(std::vector<RigidShape> shapes, std::vector<BodyState> states,
               std::vector<BodyInfo> infos, std::vector<std::uint32_t> free_slots,
               std::size_t live);

 private:
  std::vector<RigidShape> shapes_;
  std::vector<BodyState> states_;  // hot, indexed by slot
  std::vector<BodyInfo> infos_;    // cold, indexed by slot
  std::vector<std::uint32_t> free_slots_;
  std::size_t live_ = 0;
  std::vector<Role> roles_;  // by slot; empty: every body owned
  bool changed_ = false;     // a body came or went since the domain last partitioned
};

}  // namespace cleave::physics
