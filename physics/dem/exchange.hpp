#pragma once
/// \file
/// What a domain decomposition (parallel::MpiDomain) moves between the processes that step
/// one World, through the World's owners: ghost states in and out, bodies migrating with
/// their contact histories and bonds, the walls' reactions and bond breaks made the whole
/// world's after the forces, and everything gathered on every process. Roles are set with
/// World::set_domain and World::set_roles. All plain data: the types travel as bytes
/// between processes of one binary.

#include <cstdint>
#include <span>
#include <vector>

#include "physics/dem/bodies.hpp"
#include "physics/dem/bonds.hpp"
#include "physics/dem/contacts.hpp"
#include "physics/dem/wall.hpp"

namespace cleave::physics {

/// A view of a World's owners for its Domain (World::exchange); valid while the World is
/// and no body is added.
class Exchange {
 public:
  Exchange(Bodies& bodies, Contacts& contacts, Bonds& bonds, std::vector<Wall>& walls)
      : bodies_(bodies), contacts_(contacts), bonds_(bonds), walls_(walls) {}

  // Bodies, by slot.
  [[nodiscard]] std::size_t slots() const { return bodies_.slots(); }
  /// A live body this process owns.
  [[nodiscard]] bool owned(std::uint32_t slot) const {
    return bodies_.infos()[slot].alive && bodies_.owns(slot);
  }
  [[nodiscard]] const BodyState& state(std::uint32_t slot) const { return bodies_.states()[slot]; }
  /// A ghost's state from its owner, or a migrating body's from its last owner.
  void set_state(std::uint32_t slot, const BodyState& state) { bodies_.states()[slot] = state; }
  /// The bytes of a body's state (kStateBytes of them) into `out`, and back from `in`.
  static constexpr std::size_t kStateBytes = sizeof(BodyState);
  void pack_state(std::uint32_t slot, char* out) const;
  void unpack_state(std::uint32_t slot, const char* in);
  /// Whether a body came or went (a split) since the last partition; clears it.
  bool take_bodies_changed() { return bodies_.take_changed(); }

  // A body migrating to another process takes its contact histories and bonds along.
  /// The contact histories that name the body in `slot`, in key order.
  [[nodiscard]] std::vector<HistoryEntry> histories_of(std::uint32_t slot) const;
  /// Adds the histories that arrived (any order) that this process lacks.
  void merge_histories(std::vector<HistoryEntry> arrived);
  /// By slot, the indices of its bonds (World::bonds), ascending.
  [[nodiscard]] std::vector<std::vector<std::uint32_t>> bonds_by_slot() const;
  [[nodiscard]] BondDynamic bond(std::size_t k) const { return bonds_.dynamic(k); }
  void set_bond(const BondDynamic& d) { bonds_.apply(d); }

  // After the forces.
  /// The wall contacts' forces this process found, with their place in its contact list.
  [[nodiscard]] std::vector<WallForceAt> wall_forces() const { return contacts_.wall_forces(); }
  /// The walls' reactions from the whole world's wall forces, summed in the order given.
  void set_wall_reactions(const std::vector<WallForceAt>& forces);
  /// This force evaluation's bond breaks; replaced by the whole world's (in bond order).
  [[nodiscard]] std::span<const BondBreak> step_breaks() const { return bonds_.step_breaks(); }
  void set_step_breaks(const std::vector<BondBreak>& breaks) { bonds_.set_step_breaks(breaks); }

  // Everything on every process.
  /// The histories this process counts: those whose A (a wall contact's body) it owns.
  [[nodiscard]] std::vector<HistoryEntry> owned_histories() const;
  /// Replaces the histories by the whole world's (any order).
  void set_histories(std::vector<HistoryEntry> history);
  /// Replaces the contact records by the whole world's, in one process's order.
  void set_records(std::vector<ContactRecord> records) {
    contacts_.set_records(std::move(records));
  }

 private:
  Bodies& bodies_;
  Contacts& contacts_;
  Bonds& bonds_;
  std::vector<Wall>& walls_;
};

}  // namespace cleave::physics
