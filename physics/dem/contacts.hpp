#pragma once
/// \file
/// The contacts' owner: the bodies posed for the search, the neighbour search's pairs (a
/// Verlet list), the narrow phase (with its feature caches and manifolds), wall contacts,
/// the contact histories, the contact law's application and its sums onto the bodies.

#include <Eigen/Dense>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "physics/bonds/vec3.hpp"
#include "physics/dem/body.hpp"
#include "physics/dem/contact_law.hpp"
#include "physics/dem/narrow_phase.hpp"
#include "physics/dem/neighbour_search.hpp"
#include "physics/dem/wall.hpp"
#include "physics/dem/world_settings.hpp"

namespace cleave::physics {

class Bodies;
class Bonds;
class CellControl;
class ThermalField;

/// One contact of the last step, for output and tests.
struct ContactRecord {
  std::uint32_t a = 0;  ///< body slot of A, or wall index when `wall` is set
  std::uint32_t b = 0;  ///< body slot of B
  bool wall = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< from A towards B
  double overlap = 0.0;  ///< beyond the overlap stored at bonding or a split (raw otherwise)
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  ///< on B
  /// In a periodic cell, where B's image sits: B acts from x_B + shift, so its lever arm is
  /// point - shift - x_B (zero without a cell, and for walls).
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
};

/// A contact's identity across steps: the two bodies (or wall and body) and the two
/// features touching. Contacts are produced in ascending key order every step, so the
/// history of the previous step is found by a forward merge, without hashing.
struct ContactKey {
  std::uint32_t a, b, fa, fb;  ///< a carries Contacts::kWallFlag for wall contacts
  auto operator<=>(const ContactKey&) const = default;
};
/// A contact's history (shear, rolling and twist springs) under its key.
struct HistoryEntry {
  ContactKey key;
  ContactHistory history;
};
/// A wall contact's force and its place in the contact list (summed into the wall's
/// reaction in that order).
struct WallForceAt {
  std::uint32_t wall, slot;
  std::uint64_t order;
  Eigen::Vector3d force;
};

/// The contacts of the bodies with each other and with the walls, step by step.
class Contacts {
 public:
  static constexpr std::uint32_t kWallFlag = 0x80000000u;
  /// Pairs per chunk of the narrow phase; the contact list is the chunks' lists in order,
  /// then the walls'.
  static constexpr std::size_t kPairChunk = 256;
  /// Body slots per piece of the wall contacts.
  static constexpr std::size_t kWallPiece = 512;
  /// A contact found this step, before the law is applied.
  struct Pending {
    ContactKey key;  // a carries kWallFlag for wall contacts
    PrimitiveContact contact;
  };

  explicit Contacts(SearchMethod search) : search_(search) {}

  // The step's stages, in order.
  /// Poses every live body this process holds (its force reset to its weight, its torque to
  /// zero), lists the walls within its reach, and says whether the last search's pairs may
  /// miss some (a body has moved half the skin since, or bodies came or went).
  [[nodiscard]] bool pose(Bodies& bodies, const std::vector<Wall>& walls, const CellControl& cell,
                          const WorldSettings& settings, int threads);
  /// The neighbour search: the pairs within the skin, their images in a periodic cell, the
  /// manifolds carried over to the new list.
  void search(const Bodies& bodies, const CellControl& cell, const WorldSettings& settings);
  /// The contact lists sized for the pairs; with manifolds, which pairs carry their
  /// contacts, which the near features hold apart, and which bodies need their geometry.
  void plan(const CellControl& cell, const WorldSettings& settings, int threads);
  /// The narrow phase (or the carried contacts), pair by pair.
  void narrow(const CellControl& cell, const WorldSettings& settings, int threads);
  /// The wall contacts of the bodies this process owns; the contact lists joined.
  void walls(const Bodies& bodies, const std::vector<Wall>& walls, bool cell, int threads);
  /// Eqs 2.3-2.8 on every contact: each reads the bodies' states and the previous step's
  /// history, and writes its own slot.
  void apply_law(const Bodies& bodies, const std::vector<Wall>& walls, const Bonds& bonds,
                 const ThermalField& thermal, const CellControl& cell,
                 const WorldSettings& settings, int threads);
  /// The contact forces and torques summed onto the bodies in contact order, the walls'
  /// reactions too; with `diagonals`, eq. 2.17's diagonal terms by body. This step's
  /// histories become the ones the next step reads.
  void sum(Bodies& bodies, std::vector<Wall>& walls, std::vector<Eigen::Vector3d>* diagonals,
           int threads);

  /// Contacts of the last force evaluation (made on the first call after it).
  [[nodiscard]] const std::vector<ContactRecord>& records(int threads) const;
  [[nodiscard]] std::vector<WallForceAt> wall_forces() const;
  /// The contacts `bodies`' process counts (World::owned_contact_count).
  [[nodiscard]] std::size_t owned_count(const Bodies& bodies) const;

  // What the step keeps by body (the stress sums read it).
  [[nodiscard]] std::size_t pending_count() const {
    return part_start_.empty() ? 0 : part_start_.back();
  }
  /// Where the walls' contacts start in the contact list (they follow every pair's).
  [[nodiscard]] std::size_t wall_contacts_begin() const;
  /// Calls f(k, contact k) for k in [begin, end), in order.
  template <class F>
  void for_pending(std::size_t begin, std::size_t end, F&& f) const;
  /// Calls f(is_b, contact, k) for each contact of body `slot` with another body, pair by
  /// pair in the pairs' order (k: its index in the contact list; is_b: the body is B).
  template <class F>
  void for_pair_contacts_of(std::size_t slot, F&& f) const;
  [[nodiscard]] const std::vector<ContactForce>& forces() const { return forces_; }
  /// In a periodic cell, by contact: B's shift (empty without a cell).
  [[nodiscard]] const std::vector<Eigen::Vector3d>& shifts() const { return contact_shift_; }
  /// By slot: bit w set when wall w may touch the body (walls from 31 on share bit 31).
  [[nodiscard]] const std::vector<std::uint32_t>& wall_reach() const { return wall_reach_; }
  /// Whether the lists by body describe the pairs of `slots` slots as they are.
  [[nodiscard]] bool by_body_current(std::size_t slots) const {
    return !body_pairs_stale_ && body_pair_start_.size() == slots + 1;
  }

  /// The slots this evaluation posed (live, held by this process), ascending.
  [[nodiscard]] const std::vector<std::uint32_t>& live() const { return live_slots_; }
  [[nodiscard]] const std::vector<PosedShape>& posed() const { return posed_; }
  /// Every live body's vertices and planes (a lazy pose may have skipped some).
  void pose_geometry();

  // Bodies come and go; the run changes its choices.
  /// The pairs are searched afresh at the next evaluation (a body came or went).
  void forget_pairs() { pairs_current_ = false; }
  /// Another set of bodies here (a domain's roles): the pair list and its caches afresh.
  void forget_search() {
    pairs_current_ = false;
    near_.clear();
  }
  /// A removed body's contact histories go: a body that later takes its slot must not
  /// inherit its springs.
  void forget_slot(std::uint32_t slot);
  void clear_near() { near_.clear(); }
  void clear_history() { history_.clear(); }

  // What a domain decomposition exchanges (exchange.hpp).
  /// The contact histories, sorted by key.
  [[nodiscard]] const std::vector<HistoryEntry>& histories() const { return history_; }
  void set_histories(std::vector<HistoryEntry> history) { history_ = std::move(history); }
  /// Adds those of `arrived` (sorted by key) this process lacks (one it has is the same).
  void merge_histories(const std::vector<HistoryEntry>& arrived);
  void set_records(std::vector<ContactRecord> records) {
    records_ = std::move(records);
    records_current_ = true;
  }

  /// The search's state as a checkpoint holds it (world_state.cpp).
  struct SearchState {
    bool current = false;
    double skin = 0.0;
    std::vector<Eigen::Vector3d> at;
    std::vector<Eigen::Quaterniond> q;
    std::vector<BodyPair> pairs;
    std::vector<Eigen::Vector3i> images;
    std::vector<std::uint32_t> manifold_slots;
    std::vector<ContactManifold> manifolds;
  };
  [[nodiscard]] bool pairs_current() const { return pairs_current_; }
  [[nodiscard]] double skin() const { return skin_; }
  [[nodiscard]] const std::vector<Eigen::Vector3d>& searched_at() const { return searched_at_; }
  [[nodiscard]] const std::vector<Eigen::Quaterniond>& searched_q() const { return searched_q_; }
  [[nodiscard]] const std::vector<BodyPair>& pairs() const { return pairs_; }
  [[nodiscard]] const std::vector<Eigen::Vector3i>& pair_images() const { return pair_image_; }
  [[nodiscard]] const std::vector<std::uint32_t>& manifold_slots() const { return manifold_slots_; }
  [[nodiscard]] const std::vector<ContactManifold>& manifolds() const { return manifolds_; }
  /// A checkpoint's contacts; every live body posed afresh.
  void restore(SearchMethod search, SearchState state, std::vector<HistoryEntry> history,
               std::vector<ContactRecord> records, const Bodies& bodies);

 private:
  /// Asks for the first four cache lines of posed_[slot] (its frame, travel and box).
  void prefetch_posed(std::uint32_t slot) const {
    const char* at = reinterpret_cast<const char*>(&posed_[slot]);
    for (int line = 0; line < 4; ++line) __builtin_prefetch(at + 64 * line);
  }
  /// The damping coefficients of the last pair contact_inputs saw (key a, body b), and
  /// what they were made from (a wall or not, A's and B's masses and least moments).
  struct PairDamping {
    std::uint32_t a = 0, b = 0;
    bool valid = false;
    bool wall = false;
    double mass_a = 0.0, mass_b = 0.0, moment_a = 0.0, moment_b = 0.0;
    ContactDamping damping;
  };
  /// What contact_inputs reads besides the contacts.
  struct LawInputs {
    const Bodies& bodies;
    const std::vector<Wall>& walls;
    const Bonds& bonds;
    const ThermalField& thermal;
    const CellControl& cell;
  };
  /// The contact law's inputs for contact k (`p`, under `params`: the walls' or the
  /// pairs'): its kinematics into `kin`, the previous step's history copied into
  /// next_history_[k] (walking `history_cursor` forward through history_), the pair's
  /// coefficients into `pair` (kept from the pair before when the same). Reads the bodies'
  /// states, writes only slot k.
  void contact_inputs(const LawInputs& in, const Pending& p, std::size_t k,
                      const ContactParams& params, std::size_t& history_cursor,
                      std::size_t& bond_cursor, PairDamping& pair, ContactKinematics& kin);
  /// Subtracts from contact p's `overlap` what counts as zero: the overlap stored at bonding
  /// or a split, and the gap the grains' thermal expansion has opened (B's centroid at `xb`).
  void discount_overlap(const LawInputs& in, const Pending& p, const V3& xb,
                        std::size_t& bond_cursor, double& overlap) const;
  /// The previous step's history of `key` into `h` (walking `cursor` forward).
  void carry_history(const ContactKey& key, std::size_t& cursor, ContactHistory& h) const;
  /// The pair's damping coefficients into `pair` (kept when its bodies are as the last's).
  static void pair_damping(const LawInputs& in, const Pending& p, const ContactParams& params,
                           PairDamping& pair);
  const ContactHistory* previous_history(const ContactKey& key) const;
  /// Index of the first entry of history_ whose key is not below `key`.
  std::size_t history_index(const ContactKey& key) const;
  /// Pair p's contacts into `out` (a periodic cell's pair with B's shifts into `shifts`).
  struct NarrowScratch;
  void narrow_pair(std::size_t p, std::size_t end, const WorldSettings& settings,
                   std::vector<Pending>& out, NarrowScratch& scratch);
  void narrow_periodic_pair(std::size_t p, const CellControl& cell, const WorldSettings& settings,
                            std::vector<Pending>& out, std::vector<Eigen::Vector3d>& shifts,
                            NarrowScratch& scratch);
  void join_pending(bool cell);
  void list_body_pairs(std::size_t slots);

  std::vector<PosedShape> posed_;  // by slot, refreshed each force evaluation
  std::vector<std::uint32_t> live_slots_;
  /// By slot, from the poses' loop: bit w set when wall w may touch the body (walls from 31
  /// on share bit 31, and are tested again one by one).
  std::vector<std::uint32_t> wall_reach_;
  std::vector<BoundingSphere> spheres_;
  std::vector<BodyPair> pairs_;
  std::vector<Eigen::Vector3i>
      pair_image_;  // by pair, in a cell: B's nearest image (fixed between searches)
  /// A list on cache lines of its own: lists that threads fill side by side shared the
  /// line holding their ends (false sharing: the wall contacts on two threads took longer
  /// than on one).
  template <class T>
  struct alignas(64) OwnLines {
    std::vector<T> list;
  };
  std::vector<OwnLines<Eigen::Vector3d>>
      chunk_shift_;                             // in a cell: per chunk_pending_ entry, B's shift
  std::vector<Eigen::Vector3d> contact_shift_;  // in a cell: per pending contact (walls: zero)
  std::vector<NearFeatures> near_;          // by pair; cleared with each new pair list and on load
  std::vector<ContactManifold> manifolds_;  // by pair (manifold_tolerance > 0); follow the pairs
  std::vector<std::uint32_t> manifold_slots_;  // live slots when the pairs were listed
  std::vector<unsigned char> held_;            // by pair: its manifold holds contacts
  enum : unsigned char { kCarried, kApart, kSearch };
  std::vector<unsigned char> plan_;           // by pair, with manifolds: what narrow does
  std::vector<unsigned char> need_geometry_;  // by slot: a search reads its vertices and planes
  void plan_pairs(int nt, std::size_t slots, bool cached);
  std::vector<Eigen::Vector3d> searched_at_;    // centres at the last search, by live index
  std::vector<Eigen::Quaterniond> searched_q_;  // orientations at the last search, by live index
  double skin_ = 0.0;                           // margin of the last search
  bool pairs_current_ = false;
  NeighbourSearch search_;
  std::vector<HistoryEntry> history_, next_history_;  // sorted by key
  /// This step's contacts, in the order the law and the sums go through them: the lists of
  /// the chunks of pairs, then those of the walls (wall by wall, piece of body slots by
  /// piece), read in place rather than copied into one list.
  std::vector<OwnLines<Pending>> chunk_pending_, wall_pending_;
  std::vector<const std::vector<Pending>*> parts_;  // the lists in order
  std::vector<std::size_t> part_start_;  // index of each list's first contact; back(): all
  std::vector<ContactForce> forces_;
  /// By pair: the index of its first contact in its chunk's list (narrow), so that a
  /// pair's contacts are [part_start_[chunk] + pair_first_[p], the next pair's or the chunk's end).
  std::vector<std::uint32_t> pair_first_;
  /// By slot, the body's pairs in ascending order, each as (pair index << 1) | (1 if it is the
  /// pair's B): sum walks a body's contacts in list order through them. Made again after
  /// each new pair list (body_pairs_stale_).
  std::vector<std::uint32_t> body_pair_start_, body_pairs_;
  bool body_pairs_stale_ = true;
  std::vector<double> overlaps_;                // per pending contact: the overlap the law saw
  mutable std::vector<ContactRecord> records_;  // records(), made when first asked for
  mutable bool records_current_ = true;
};

template <class F>
void Contacts::for_pending(std::size_t begin, std::size_t end, F&& f) const {
  if (begin >= end) return;
  // The list holding contact `begin`: the last one starting at or before it.
  auto part =
      static_cast<std::size_t>(std::upper_bound(part_start_.begin(), part_start_.end(), begin) -
                               part_start_.begin()) -
      1;
  for (std::size_t k = begin; k < end; ++part) {
    const std::vector<Pending>& list = *parts_[part];
    const std::size_t stop = std::min(end, part_start_[part + 1]);
    for (std::size_t i = k - part_start_[part]; k < stop; ++k, ++i) f(k, list[i]);
  }
}

template <class F>
[[gnu::always_inline]] inline void Contacts::for_pair_contacts_of(std::size_t slot, F&& f) const {
  // A pair's contacts are consecutive in its chunk's list, from pair_first_ to the next
  // pair's first (or the list's end).
  for (std::uint32_t e = body_pair_start_[slot]; e < body_pair_start_[slot + 1]; ++e) {
    const std::uint32_t p = body_pairs_[e] >> 1;
    const bool is_b = (body_pairs_[e] & 1u) != 0;
    const std::size_t chunk = p / kPairChunk;
    const std::vector<Pending>& list = chunk_pending_[chunk].list;
    const std::size_t stop =
        (p + 1) % kPairChunk != 0 && p + 1 < pairs_.size() ? pair_first_[p + 1] : list.size();
    const std::size_t base = part_start_[chunk];
    for (std::size_t j = pair_first_[p]; j < stop; ++j) f(is_b, list[j], base + j);
  }
}

}  // namespace cleave::physics
