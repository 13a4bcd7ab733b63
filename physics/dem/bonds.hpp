#pragma once
/// \file
/// The bonds' owner (sec. 2.3.3): the bond list, bonding, the bond law's application and
/// sums, breaks (by eq. 2.15's limits or a stress criterion), and the overlaps that count as
/// zero between a split's pieces.

#include <Eigen/Dense>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "physics/bonds/bond_law.hpp"
#include "physics/bonds/vec3.hpp"
#include "physics/dem/body.hpp"
#include "physics/dem/gallop.hpp"
#include "physics/dem/narrow_phase.hpp"
#include "physics/dem/neighbour_search.hpp"
#include "physics/dem/periodic_cell.hpp"

namespace cleave::physics {

class Bodies;
class CellControl;
class ThermalField;

/// A bond between two bodies (sec. 2.3.3): eqs 2.9-2.16 act at the bond point in parallel
/// with the contact law (quasi-parallel model). The bond point and normal are material:
/// each is stored in both bodies' principal frames at bonding and followed as they move.
struct alignas(64) Bond {
  // What the bond law reads every step fills the first two cache lines, what it writes the
  // next three (the bond law walks 30,000 of them a step in a 10,000-grain disc, at
  // the machine's memory bandwidth: its bytes set its pace); the rest after.
  std::uint32_t a = 0, b = 0;  ///< body slots, a < b
  BondSection section;         ///< eq. 2.10: radius = dilation radius of the smaller body
  Eigen::Vector3d arm_a = Eigen::Vector3d::Zero();      ///< bond point from A's centroid, A's frame
  Eigen::Vector3d arm_b = Eigen::Vector3d::Zero();      ///< bond point from B's centroid, B's frame
  Eigen::Vector3d normal_a = Eigen::Vector3d::UnitZ();  ///< normal (A towards B), A's frame
  Eigen::Vector3d normal_b = Eigen::Vector3d::UnitZ();  ///< the same in B's frame
  /// This bond's strengths over the [bond] table's (t_bn, t_bs; sigma_c of the cohesive law):
  /// 1 unless the scenario scatters them (bond_strength_factor).
  double strength = 1.0;
  /// This bond's stiffnesses over the [bond] table's (k_bn and k_bs; E_m of the beam law):
  /// 1 unless its grains' phases make it stiffer or softer ([[phase]], [[boundary]]).
  double stiffness = 1.0;
  // Last force evaluation (world): the bond point, normal, and the force and moment on B;
  // from the third line (then the bonded-particle state: three lines written a step).
  alignas(64) Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  BondState state;  ///< its bonded-particle fields first (the cohesive history last)
  /// In a periodic cell, the image of B the bond joins A to: B acts from x_B + H image
  /// (World::cell), `shift` = H image as of the last evaluation. Zero without a cell (the
  /// bond law then reads a zero of its own, not this line).
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  // Read on a break, a split, a periodic image's change, or by the other laws.
  Eigen::Vector3i image = Eigen::Vector3i::Zero();  ///< B's image (see `shift`)
  BondFailure failure = BondFailure::none;          ///< the mode it broke in
  double broken_at = -1.0;                          ///< simulated time of the break, s
  /// The physical overlap of each touching feature pair at bonding (end of 2.3.3): later
  /// overlaps of the same features count from it, so the bonded assembly starts stress-free.
  /// Kept after the bond breaks, so a broken bond does not spring apart.
  struct Overlap {
    std::uint32_t fa, fb;  ///< kAnyFeature for both: any feature pair (after a split)
    double overlap;
  };
  static constexpr std::uint32_t kAnyFeature = 0xFFFFFFFFu;
  std::vector<Overlap> initial;
  /// The gap the two grains' thermal strain has opened at the bond along its normal since
  /// bonding (m; negative when they have grown into each other). The pair's contacts count
  /// their overlap from it as well, since the grains' shapes keep their reference size.
  double thermal_gap = 0.0;
  /// Heat conduction's transmission surface S_t (m^2): the area of the two grains' touching
  /// faces at bonding (the polygon of the contact points), the section's where they touch
  /// at an edge or a corner.
  double transmission = 0.0;
  /// The beam law's beam (BondLaw::beam): its ends (the centroids at bonding, moved to a
  /// piece's frame when a grain splits), its axis (A towards B) and a direction across it,
  /// each in A's and in B's principal frame, and its rest length L_m (which follows the
  /// grains' thermal expansion). Unused by the other laws.
  struct Beam {
    Eigen::Vector3d end_a = Eigen::Vector3d::Zero(), end_b = Eigen::Vector3d::Zero();
    Eigen::Vector3d axis_a = Eigen::Vector3d::UnitX(), axis_b = Eigen::Vector3d::UnitX();
    Eigen::Vector3d across_a = Eigen::Vector3d::UnitY(), across_b = Eigen::Vector3d::UnitY();
    double rest_length = 0.0;
  };
  Beam beam;
  [[nodiscard]] bool intact() const { return !state.broken; }
};

/// One bond failure (eq. 2.16), as logged.
struct BondBreak {
  double time = 0.0;
  std::uint64_t step = 0;
  std::size_t bond = 0;  ///< index into World::bonds()
  std::uint32_t a = 0, b = 0;
  int grain_a = -1, grain_b = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  BondFailure mode = BondFailure::none;
  BondState loads;  ///< the bond's forces and moments when it broke
  /// The grain-boundary face the bond stood for, its intergranular crack's area (m^2):
  /// Bond::transmission, the touching faces' polygon at bonding (the bond section's area
  /// where the grains touched at an edge or a corner). Taken at the break, since `bond`
  /// indexes the list as it was then (a split re-sorts it).
  double face_area = 0.0;
};

/// Intact bonds and broken ones by mode.
struct BondCounts {
  std::size_t intact = 0, tension = 0, shear = 0, bending = 0, torsion = 0;
  [[nodiscard]] std::size_t broken() const { return tension + shear + bending + torsion; }
};

/// What a bond carries from step to step (its geometry at bonding is on every process
/// already): what a domain decomposition sends of it (exchange.hpp).
struct BondDynamic {
  std::uint64_t index;
  BondState state;
  BondFailure failure;
  double broken_at, thermal_gap, rest_length;
  Eigen::Vector3d point, normal, force, moment, shift;
};

/// The bonds, sorted by (a, b), and what the step keeps of them.
class Bonds {
 public:
  [[nodiscard]] const std::vector<Bond>& list() const { return bonds_; }
  [[nodiscard]] bool empty() const { return bonds_.empty(); }
  [[nodiscard]] const BondParams& params() const { return params_; }
  /// Sets bond k's strength factor (Bond::strength, > 0).
  void set_strength(std::size_t k, double factor);
  /// Sets bond k's stiffness factor (Bond::stiffness, > 0).
  void set_stiffness(std::size_t k, double factor);
  [[nodiscard]] BondCounts counts() const;
  /// While held, no intact bond breaks (World::hold_bonds).
  void hold(bool held) { held_ = held; }
  /// Every bond failure so far, in the order they happened.
  [[nodiscard]] const std::vector<BondBreak>& breaks() const { return breaks_; }

  /// Bonds every pair of `live` bodies (posed as `posed`) whose dilated surfaces are within
  /// `distance` (World::initialise_bonds, which poses them and resets the motion after).
  void make(const BondParams& params, double distance, const Bodies& bodies,
            const std::vector<PosedShape>& posed, const std::vector<std::uint32_t>& live,
            const CellControl& cell, SearchMethod search);

  // The step's stages.
  /// A force evaluation starts: the breaks from here on are this step's.
  void begin_evaluation() { breaks_at_step_ = breaks_.size(); }
  /// Eqs 2.9-2.16 on every bond whose bodies this process owns; the breaks logged at `time`,
  /// `step` (World::step's bond_law).
  void apply_law(const Bodies& bodies, const ThermalField& thermal, const CellControl& cell,
                 double dt, int threads, double time, std::uint64_t step);
  /// The intact bonds' forces and torques summed onto the bodies in bond order (bond_sums);
  /// with `diagonals`, eq. 2.17's diagonal terms onto them too.
  void sum(Bodies& bodies, bool cell, std::vector<Eigen::Vector3d>* diagonals, int threads);
  /// Whether a stress criterion breaks bonds after the sums (BondCriterion::rankine or
  /// hydrostatic; not while held).
  [[nodiscard]] bool stress_criterion() const {
    return params_.criterion != BondCriterion::limits && !bonds_.empty() && !held_;
  }
  /// Breaks the intact bonds whose grains' mean stress (`stress` by slot, eq. 2.17) passes
  /// sigma_f (times the bond's strength factor); returns how many broke.
  std::size_t break_by_stress(const std::vector<Eigen::Matrix3d>& stress,
                              const std::vector<BodyInfo>& infos, double time, std::uint64_t step);

  /// The overlap stored at bonding for features (fa, fb) of bonded pair (a, b), or 0;
  /// `cursor` walks forward through the bonds (sorted by pair) as keys ascend.
  double initial_overlap(std::uint32_t a, std::uint32_t b, std::uint32_t fa, std::uint32_t fb,
                         std::size_t& cursor) const;
  /// The overlap that counts as zero between a and b (a < b) after a split, or 0.
  [[nodiscard]] double pair_offset(std::uint32_t a, std::uint32_t b) const;
  [[nodiscard]] bool has_offsets() const { return !offsets_.empty(); }

  /// By bond, this step: what it adds to its bodies (force and moment on B, A's their
  /// opposites, at the bond point: the sum makes each torque about the body's centroid),
  /// written by the bond law, read by the sums.
  struct Push {
    V3 force, moment;   ///< on B (A's: their opposites)
    V3 point;           ///< the bond point: the lever of the torques, and stress_sums'
    bool live = false;  ///< intact: the sum adds it
  };
  [[nodiscard]] const std::vector<Push>& pushes() const { return push_; }
  /// By slot, the body's bonds: body_bonds()[body_start()[i] .. body_start()[i + 1]), each
  /// (bond index << 1) | (1 if the body is the bond's B).
  [[nodiscard]] const std::vector<std::uint32_t>& body_start() const { return body_bond_start_; }
  [[nodiscard]] const std::vector<std::uint32_t>& body_bonds() const { return body_bonds_; }
  /// Whether the lists by body describe the bonds of `slots` slots as they are.
  [[nodiscard]] bool by_body_current(std::size_t slots) const {
    return bonds_.empty() || (!body_bonds_stale_ && body_bond_start_.size() == slots + 1);
  }

  // Bodies come, go, split and wrap.
  /// Drops the bonds and offsets of a removed body.
  void forget_slot(std::uint32_t slot);
  /// What a splitting body takes to its pieces: its bonds, and the overlaps its neighbours
  /// counted from (each piece gets them with those neighbours).
  struct Parted {
    std::vector<Bond> moved;
    std::vector<std::pair<std::uint32_t, double>> stored;
  };
  [[nodiscard]] Parted part(std::uint32_t slot) const;
  /// After the split of the body in `slot` (state `ps`) into `pieces`: each bond follows its
  /// material point to the piece that holds it; the pieces' overlaps with each other and with
  /// the parent's neighbours count as zero.
  void follow_split(Parted parted, std::uint32_t slot, const BodyState& ps,
                    const std::vector<BodyId>& pieces, const Bodies& bodies);
  /// Periodic cell: after the bodies wrapped by `moved` cells, each bond re-joins the same images.
  void follow_wrap(const std::vector<Eigen::Vector3i>& moved, const PeriodicCell& cell);

  // What a domain decomposition exchanges (exchange.hpp).
  [[nodiscard]] BondDynamic dynamic(std::size_t k) const;
  void apply(const BondDynamic& d);
  /// This force evaluation's breaks.
  [[nodiscard]] std::span<const BondBreak> step_breaks() const {
    return std::span<const BondBreak>(breaks_).subspan(breaks_at_step_);
  }
  /// Replaces this evaluation's breaks (the whole world's, in bond order).
  void set_step_breaks(const std::vector<BondBreak>& breaks) {
    breaks_.resize(breaks_at_step_);
    breaks_.insert(breaks_.end(), breaks.begin(), breaks.end());
  }

  /// Overlaps that count as zero between pairs that are not bonded (or no longer have the
  /// bond that stored them): pieces of one split, whose dilated surfaces overlap across
  /// the new crack by the sum of their dilation radii, and pieces of a split body with the
  /// parent's neighbours. Sorted by (a, b), a < b.
  struct PairOffset {
    std::uint32_t a, b;
    double overlap;
  };
  [[nodiscard]] const std::vector<PairOffset>& offsets() const { return offsets_; }
  /// A checkpoint's bonds.
  void restore(std::vector<Bond> bonds, std::vector<PairOffset> offsets, const BondParams& params,
               std::vector<BondBreak> breaks);

 private:
  /// A bond that broke in this evaluation's law, as the thread that met it listed it.
  struct FailureAt {
    std::size_t bond;
    BondFailure failure;
    BondState at;
  };
  struct LawPass;  // bond_forces.cpp: one thread's pass of the law over its block of bonds
  void list_body_bonds(std::size_t slots);
  void log_breaks(const std::vector<BodyInfo>& infos, double time, std::uint64_t step);

  std::vector<Bond> bonds_;  // sorted by (a, b)
  std::vector<PairOffset> offsets_;
  BondParams params_;
  bool held_ = false;  // hold
  /// The bonds that broke in this step's bond law, one list per thread.
  std::vector<std::vector<FailureAt>> failures_;
  std::vector<BondBreak> breaks_;
  std::size_t breaks_at_step_ = 0;  // breaks_.size() when this force evaluation began
  std::vector<Push> push_;
  std::vector<std::uint32_t> body_bond_start_, body_bonds_;
  bool body_bonds_stale_ = true;
};

inline double Bonds::initial_overlap(std::uint32_t a, std::uint32_t b, std::uint32_t fa,
                                     std::uint32_t fb, std::size_t& cursor) const {
  auto before = [&](const Bond& bd) { return bd.a < a || (bd.a == a && bd.b < b); };
  if (cursor > 0 && cursor <= bonds_.size() && !before(bonds_[cursor - 1])) {
    // Out of order (a new thread block starts mid-pair): search again.
    cursor = static_cast<std::size_t>(
        std::lower_bound(bonds_.begin(), bonds_.end(), std::pair{a, b},
                         [](const Bond& bd, std::pair<std::uint32_t, std::uint32_t> k) {
                           return std::pair{bd.a, bd.b} < k;
                         }) -
        bonds_.begin());
  }
  // Forward by gallop (gallop.hpp), to the bond a walk would stop at: a loaded disc's few
  // hundred contacts lie far apart among its many bonds, and a walk read a cache line of
  // every bond between them.
  cursor = gallop(bonds_, cursor, before);
  if (cursor == bonds_.size() || bonds_[cursor].a != a || bonds_[cursor].b != b) return 0.0;
  // The features' own stored overlap; a feature pair that did not touch at bonding (the
  // search may name another vertex or edge for a contact of the same faces once they move,
  // as it does between coplanar faces) counts from the largest the pair stored.
  double most = 0.0;
  for (const Bond::Overlap& o : bonds_[cursor].initial) {
    if (o.fa == fa && o.fb == fb) return o.overlap;
    most = std::max(most, o.overlap);
  }
  return most;
}

inline double Bonds::pair_offset(std::uint32_t a, std::uint32_t b) const {
  const auto it =
      std::lower_bound(offsets_.begin(), offsets_.end(), std::pair{a, b},
                       [](const PairOffset& o, std::pair<std::uint32_t, std::uint32_t> k) {
                         return std::pair{o.a, o.b} < k;
                       });
  return it != offsets_.end() && it->a == a && it->b == b ? it->overlap : 0.0;
}

}  // namespace cleave::physics
