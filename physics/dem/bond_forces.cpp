// The bond law's stage (eqs 2.9-2.16 on every bond, in parallel) and the bonds' sums onto
// the bodies (Bonds::apply_law, Bonds::sum).

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "physics/bonds/bond_batch.hpp"
#include "physics/dem/bodies.hpp"
#include "physics/dem/bonds.hpp"
#include "physics/dem/cell_control.hpp"
#include "physics/dem/step_threads.hpp"
#include "physics/dem/stress_sums.hpp"
#include "physics/dem/thermal_field.hpp"

namespace cleave::physics {

using threads::kParallelMin;

/// One thread's pass of the bond law over its block of bonds: each bond reads the two
/// bodies and writes only itself (and its Push); the bonds that break are listed in
/// `failed`, in bond order.
struct Bonds::LawPass {
  LawPass(Bonds& bonds, const std::vector<BodyState>& states, const std::vector<Role>& roles,
          const ThermalField& thermal, const CellControl& cell, const BondParams& base, double dt,
          std::vector<FailureAt>& failed)
      : bonds(bonds),
        states(states),
        roles(roles),
        thermal(thermal),
        cell(cell),
        base(base),
        dt(dt),
        failed(failed) {}
  Bonds& bonds;
  const std::vector<BodyState>& states;
  const std::vector<Role>& roles;
  const ThermalField& thermal;
  const CellControl& cell;
  const BondParams& base;  // the run's parameters (limits off under a stress criterion or held)
  double dt;
  std::vector<FailureAt>& failed;
  const bool thermal_on = thermal.on(), cell_on = cell.on(), beams = base.law == BondLaw::beam;
  BondConstants constants;
  double constants_radius = std::numeric_limits<double>::quiet_NaN();
  // (Made once a step: made in each call they were zeroed there, a sixth of this loop.)
  BondConstants lane_c[4];
  BondLane lane_in[4];
  BondLaneResult lane_out[4];

  /// Each grain expands about its centroid (seed 003's l0(T), per crystal axis): the bond
  /// point as a point of B moves by alpha_B arm_B dT_B, as a point of A by alpha_A arm_A
  /// dT_A; the bond deforms by their difference on top of the rigid motions. Its normal
  /// part is the gap the grains' thermal strain opens at the bond (negative: they grow into
  /// each other), kept for the pair's contacts (a broken bond's too).
  [[nodiscard]] Eigen::Vector3d thermal_free(const Bond& bd, const BodyState& sa,
                                             const BodyState& sb) const {
    const BodyThermal& ta = thermal[bd.a];
    const BodyThermal& tb = thermal[bd.b];
    const double dta = ta.temperature - ta.bonded_at, dtb = tb.temperature - tb.bonded_at;
    if (dta == 0.0 && dtb == 0.0) return Eigen::Vector3d::Zero();
    return rotated(sb.q, tb.alpha * (bd.arm_b - tb.centre)) * dtb -
           rotated(sa.q, ta.alpha * (bd.arm_a - ta.centre)) * dta;
  }
  /// What the bond adds to each body, for the sum (the same arithmetic the sum did from the
  /// bond itself): a small record read by body, instead of the large bond.
  static void fill(Push& out, const V3& point, const V3& force, const V3& moment) {
    out.force = force;
    out.moment = moment;
    out.point = point;
  }
  void push(std::size_t k) {
    const Bond& bd = bonds.bonds_[k];
    Push& out = bonds.push_[k];
    out.live = bd.intact();
    if (out.live) fill(out, v3(bd.point), v3(bd.force), v3(bd.moment));
  }
  /// Whether a bond has constants of its own (Bond::strength or Bond::stiffness != 1).
  [[nodiscard]] static bool has_own(const Bond& bd) {
    return bd.strength != 1.0 || bd.stiffness != 1.0;
  }
  /// A bond's own strengths and stiffnesses: the run's parameters with them (one law for
  /// every bond; only its constants differ).
  [[nodiscard]] BondParams own_params(const Bond& bd) const {
    BondParams p = base;
    p.tbn *= bd.strength;
    p.tbs *= bd.strength;
    p.sigma_c *= bd.strength;
    p.kbn *= bd.stiffness;
    p.kbs *= bd.stiffness;
    p.beam_young *= bd.stiffness;
    return p;
  }
  /// Eqs 2.10, 2.11 and 2.15's constants of a bond: the run's, made again only when the
  /// section changes from the bond before, or its own.
  BondConstants constants_of(const Bond& bd) {
    if (has_own(bd)) return bond_constants(own_params(bd), bd.section);
    if (!(bd.section.radius == constants_radius)) {
      constants = bond_constants(base, bd.section);
      constants_radius = bd.section.radius;
    }
    return constants;
  }

  /// Four (or two) intact bonds side by side of the plain bonded-particle law go through
  /// bond_batch (bond_batch.hpp), with the bits of one().
  template <std::size_t kN>
  [[gnu::always_inline]] void batch(std::size_t k) {
    static const Eigen::Vector3d kNoShift = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < kN; ++i) {
      Bond& bd = bonds.bonds_[k + i];
      lane_c[i] = constants_of(bd);
      if (cell_on) bd.shift = cell.cell().shift(bd.image);
      const BodyState& sa = states[bd.a];
      const BodyState& sb = states[bd.b];
      lane_in[i] = {&sa.x,        &sa.v,     &sa.w,
                    &sa.q,        &sb.x,     &sb.v,
                    &sb.w,        &sb.q,     cell_on ? &bd.shift : &kNoShift,
                    &bd.arm_a,    &bd.arm_b, &bd.normal_a,
                    &bd.normal_b, &bd.state, &lane_c[i]};
    }
    bond_batch<kN>(lane_in, lane_out, dt);
    for (std::size_t i = 0; i < kN; ++i) {
      Bond& bd = bonds.bonds_[k + i];
      bd.point = eigen(lane_out[i].point);
      bd.normal = eigen(lane_out[i].normal);
      bd.force = eigen(lane_out[i].force);
      bd.moment = eigen(lane_out[i].moment);
      Push& out = bonds.push_[k + i];
      if (lane_out[i].failure != BondFailure::none) {
        failed.push_back({k + i, lane_out[i].failure, lane_out[i].at_failure});
        out.live = false;
        continue;
      }
      out.live = true;
      fill(out, lane_out[i].point, lane_out[i].force, lane_out[i].moment);
    }
  }

  /// The records and bodies a few bonds ahead asked for now: the bonds stream past the
  /// caches, 576 bytes a bond of which the law reads the first five lines, a pattern the
  /// hardware's prefetchers miss in part. Four bonds ahead a turn (the quads' step).
  [[gnu::always_inline]] void prefetch(std::size_t k, std::size_t end) const {
    constexpr std::size_t kBondsAhead = 8;
    if (k + kBondsAhead + 3 >= end) return;
    for (std::size_t j = 0; j < 4; ++j) {
      const char* line = reinterpret_cast<const char*>(&bonds.bonds_[k + kBondsAhead + j]);
      for (int c = 0; c < 5; ++c) __builtin_prefetch(line + 64 * c, 1);
    }
    for (std::size_t j = 0; j < 4; j += 2) {
      const Bond& soon = bonds.bonds_[k + kBondsAhead / 2 + j];  // its line asked for before
      for (const std::uint32_t slot : {soon.a, soon.b}) {
        const char* body = reinterpret_cast<const char*>(&states[slot]);
        __builtin_prefetch(body, 0);
        __builtin_prefetch(body + 64, 0);
      }
    }
  }

  /// BondLaw::beam: bond k's beam (bond_law.hpp, beam_force) from its bodies' poses.
  void beam(Bond& bd, const BodyState& sa, const BodyState& sb, const BondParams& params,
            std::size_t k);
  /// Bond k alone: the general law (thermal, moving cell, beams, a decomposition's roles).
  void one(std::size_t k);
  /// The block [begin, end).
  void run(std::size_t begin, std::size_t end, bool plain);
};

void Bonds::LawPass::run(std::size_t begin, std::size_t end, bool plain) {
  const std::vector<Bond>& list = bonds.bonds_;
  for (std::size_t k = begin; k < end; ++k) {
    prefetch(k, end);
    if (plain && k + 3 < end && list[k].intact() && list[k + 1].intact() && list[k + 2].intact() &&
        list[k + 3].intact()) {
      batch<4>(k);
      k += 3;
      continue;
    }
    if (plain && k + 1 < end && list[k].intact() && list[k + 1].intact()) {
      batch<2>(k);
      ++k;
      continue;
    }
    one(k);
  }
}

void Bonds::LawPass::one(std::size_t k) {
  Bond& bd = bonds.bonds_[k];
  if (!roles.empty()) {
    // One process of a decomposition evaluates the bonds of the bodies it owns (those
    // across its boundary as their other owner does, bit for bit).
    const Role ra = roles[bd.a], rb = roles[bd.b];
    if (ra != Role::owned && rb != Role::owned) {
      push(k);  // its loads as last evaluated (the sum adds them to the ghosts, as before)
      return;
    }
    if (bd.intact() && (ra == Role::dormant || rb == Role::dormant))
      throw std::logic_error("a bond reaches past this process's ghosts (the halo is too thin)");
  }
  const BodyState& sa = states[bd.a];
  const BodyState& sb = states[bd.b];
  if (!bd.intact()) {
    if (thermal_on) {
      const Eigen::Vector3d n =
          (rotated(sa.q, bd.normal_a) + rotated(sb.q, bd.normal_b)).normalized();
      bd.thermal_gap += n.dot(thermal_free(bd, sa, sb));
    }
    bonds.push_[k].live = false;
    return;
  }
  // B's centroid, or its image's in a periodic cell (shift zero without one).
  if (cell_on) bd.shift = cell.cell().shift(bd.image);
  static const Eigen::Vector3d kNoShift = Eigen::Vector3d::Zero();
  const BondLane lane{&sa.x,      &sa.v,      &sa.w,        &sa.q,        &sb.x,
                      &sb.v,      &sb.w,      &sb.q,        cell_on ? &bd.shift : &kNoShift,
                      &bd.arm_a,  &bd.arm_b,  &bd.normal_a, &bd.normal_b, &bd.state,
                      nullptr};
  const BondMotion<double> motion = bond_motion<1>(&lane);
  const V3 point = motion.point;
  bd.point = eigen(point);
  bd.normal = eigen(motion.normal);
  Eigen::Vector3d velocity = eigen(motion.velocity);
  const Eigen::Vector3d xb = eigen(motion.xb);
  if (cell_on && cell.moving()) velocity += cell.gradient() * (xb - sa.x);
  if (thermal_on) {
    const Eigen::Vector3d free = thermal_free(bd, sa, sb);
    velocity += free / dt;
    bd.thermal_gap += bd.normal.dot(free);
    if (beams) {
      // The beam's chord grows as the grains it crosses do: from its end in A to the
      // bond point by A's expansion, from there to its end in B by B's.
      const BodyThermal& ta = thermal[bd.a];
      const BodyThermal& tb = thermal[bd.b];
      const Eigen::Vector3d growth =
          rotated(sa.q, ta.alpha * (bd.arm_a - bd.beam.end_a)) * (ta.temperature - ta.bonded_at) +
          rotated(sb.q, tb.alpha * (bd.beam.end_b - bd.arm_b)) * (tb.temperature - tb.bonded_at);
      const Eigen::Vector3d chord =
          xb + rotated(sb.q, bd.beam.end_b) - sa.x - rotated(sa.q, bd.beam.end_a);
      bd.beam.rest_length += chord.normalized().dot(growth);
    }
  }
  const BondParams* params = &base;
  BondParams own;
  if (has_own(bd)) {
    own = own_params(bd);
    params = &own;
  }
  if (beams) {
    beam(bd, sa, sb, *params, k);
    push(k);
    return;
  }
  const BondResult r = bond_force(*params, constants_of(bd), bd.section, bd.normal, velocity,
                                  sb.w - sa.w, bd.state, dt);
  bd.force = r.force;
  bd.moment = r.moment;
  if (r.failure != BondFailure::none) failed.push_back({k, r.failure, r.at_failure});
  // push(k) from the values at hand (the same operands, so the same bits).
  Push& out = bonds.push_[k];
  out.live = bd.intact();
  if (out.live) fill(out, point, v3(r.force), v3(r.moment));
}

void Bonds::LawPass::beam(Bond& bd, const BodyState& sa, const BodyState& sb,
                          const BondParams& params, std::size_t k) {
  BeamPose pose;
  pose.end_a = sa.x + rotated(sa.q, bd.beam.end_a);
  pose.end_b = sb.x + bd.shift + rotated(sb.q, bd.beam.end_b);
  pose.axis_a = rotated(sa.q, bd.beam.axis_a);
  pose.axis_b = rotated(sb.q, bd.beam.axis_b);
  pose.across_a = rotated(sa.q, bd.beam.across_a);
  pose.across_b = rotated(sb.q, bd.beam.across_b);
  pose.rest_length = bd.beam.rest_length;
  const BeamResult r = beam_force(params, pose);
  // What the bond table and the break log show: the section's loads on B.
  const Eigen::Vector3d e = (pose.end_b - pose.end_a).normalized();
  bd.state.normal = r.axial;
  bd.state.shear = r.force_b + r.axial * e;
  bd.state.torsion = r.moment_b.dot(e);
  bd.state.bending = r.moment_b - bd.state.torsion * e;
  // The beam's own strength (criterion "limits"): its outer fibre's stress.
  if (r.peak_stress > params.sigma_f * bd.strength) {
    // Named by the larger part of that stress: the pull or the bending.
    const double pull = r.axial / BondSection{params.beam_radius}.area();
    const BondFailure mode =
        pull >= r.peak_stress - pull ? BondFailure::tension : BondFailure::bending;
    BondState at = bd.state;
    bd.state = BondState{};
    bd.state.broken = true;
    failed.push_back({k, mode, at});
    return;
  }
  // Force at B's end and B's moment, moved to the bond point (the convention of the sums).
  bd.force = r.force_b;
  bd.moment = r.moment_b + (pose.end_b - bd.point).cross(r.force_b);
}

void Bonds::apply_law(const Bodies& bodies, const ThermalField& thermal, const CellControl& cell,
                      double dt, int nt, double time, std::uint64_t step) {
  const std::size_t n = bonds_.size();
  if (n == 0) return;
  if (static_cast<std::ptrdiff_t>(n) < kParallelMin) nt = 1;
  // The few bonds that break this step are listed by the thread that met them (blocks of
  // bonds in thread order, so the lists joined in thread order are in bond order).
  failures_.resize(static_cast<std::size_t>(std::max(nt, 1)));
  for (auto& list : failures_) list.clear();
  // A stress criterion replaces eq. 2.15's limits (break_by_stress applies it); held bonds
  // have none.
  BondParams base = params_;
  if (base.criterion != BondCriterion::limits || held_) {
    base.tbn = base.tbs = std::numeric_limits<double>::infinity();
    if (base.law == BondLaw::beam) base.sigma_f = std::numeric_limits<double>::infinity();
  }
  push_.resize(n);
  const bool plain = base.law == BondLaw::bonded_particle && !thermal.on() &&
                     !(cell.on() && cell.moving()) && bodies.roles().empty();
#pragma omp parallel num_threads(nt) if (nt > 1)
  {
    const threads::Block block = threads::thread_block(n);
    LawPass pass(*this, bodies.states(), bodies.roles(), thermal, cell, base, dt,
                 failures_[block.thread]);
    pass.run(block.begin, block.end, plain);
  }
  log_breaks(bodies.infos(), time, step);
}

void Bonds::log_breaks(const std::vector<BodyInfo>& infos, double time, std::uint64_t step) {
  // In bond order.
  for (const auto& list : failures_) {
    for (const FailureAt& f : list) {
      Bond& bd = bonds_[f.bond];
      bd.failure = f.failure;
      push_[f.bond].live = false;
      bd.broken_at = time;
      bd.force.setZero();
      bd.moment.setZero();
      breaks_.push_back({time, step, f.bond, bd.a, bd.b, infos[bd.a].grain_id, infos[bd.b].grain_id,
                         bd.point, bd.normal, f.failure, f.at, bd.transmission});
    }
  }
}

void Bonds::sum(Bodies& bodies, bool cell_on, std::vector<Eigen::Vector3d>* diagonals, int nt) {
  if (bonds_.empty()) return;
  if (static_cast<std::ptrdiff_t>(bonds_.size()) < kParallelMin) nt = 1;
  // Onto the bodies in bond order, whatever the number of threads: each thread takes a
  // block of bodies and walks each body's bonds (body_bonds_), summing in registers.
  std::vector<BodyState>& states = bodies.states();
  if (body_bonds_stale_ || body_bond_start_.size() != states.size() + 1)
    list_body_bonds(states.size());
  const std::size_t slots = states.size();
#pragma omp parallel num_threads(nt) if (nt > 1)
  {
    const threads::Block block = threads::thread_block(slots);
    auto body = [&](std::size_t i, auto stress) {
      constexpr bool kStress = decltype(stress)::value;
      const std::uint32_t first = body_bond_start_[i], last = body_bond_start_[i + 1];
      if (first == last) return;
      BodyState& s = states[i];
      V3 f = v3(s.f), tau = v3(s.tau);
      StressDiagonal m;
      const V3 x = v3(s.x);
      if constexpr (kStress) m.load((*diagonals)[i]);
      for (std::uint32_t e = first; e < last; ++e) {
        const std::uint32_t k = body_bonds_[e] >> 1;
        const Push& bp = push_[k];
        if (!bp.live) continue;
        // The torque about the body's centroid: the force's about it plus the moment (B's
        // lever from its image in a periodic cell).
        if ((body_bonds_[e] & 1u) != 0) {  // the bond's B
          const V3 lever = (cell_on ? bp.point - v3(bonds_[k].shift) : bp.point) - x;
          f = f + bp.force;
          tau = tau + (cross(lever, bp.force) + bp.moment);
          if constexpr (kStress) m.add(lever, bp.force);
        } else {
          const V3 lever = bp.point - x;
          f = f - bp.force;
          tau = tau - (cross(lever, bp.force) + bp.moment);
          if constexpr (kStress) m.add(lever, -1.0 * bp.force);
        }
      }
      s.f = eigen(f);
      s.tau = eigen(tau);
      if constexpr (kStress) m.store((*diagonals)[i]);
    };
    if (diagonals != nullptr) {
      for (std::size_t i = block.begin; i < block.end; ++i) body(i, std::true_type{});
    } else {
      for (std::size_t i = block.begin; i < block.end; ++i) body(i, std::false_type{});
    }
  }
}

}  // namespace cleave::physics
