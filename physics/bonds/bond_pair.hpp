#pragma once
/// \file
/// The bonded-particle law (eqs 2.12-2.16 of the dissertation) with its kinematics for two
/// bonds at once, one in each half of an SSE2 register, or four in an AVX register:
/// World::bond_forces' common case.
///
/// Why: one bond's step is a chain of seven square roots and five divisions, each waiting
/// on the one before (the normal's length, the two springs carried into the new plane, the
/// two limits), and perf put most of the law's time just after them. Two independent bonds
/// in one register run both chains in the time of one; four in an AVX register (bond_quad,
/// where the processor has AVX: World::bond_forces asks has_avx()) run four.
///
/// The bits: SSE2's and AVX's packed add, multiply, divide and square root round each lane
/// exactly as the scalar instructions do (no fused multiply-add: the target is AVX, not
/// FMA), and every operation below is the scalar code's (vec3.hpp, tangent.hpp,
/// bond_law.cpp's bond_force, World::bond_forces), in its order; the scalar code's branches
/// (a zero length) become selects of the value that branch returns.
/// `BondPair.GivesTheScalarLawsBitsInEachLane` and `BondQuad.GivesTheScalarLawsBitsInEachLane`
/// hold the two widths to that.

#include <Eigen/Geometry>
#include <cmath>

#include "physics/bonds/bond_law.hpp"
#include "physics/bonds/lanes.hpp"
#include "physics/bonds/vec3.hpp"

namespace cleave::physics {

/// One bond's inputs to bond_pair: its two bodies' poses and motions, its geometry in their
/// frames, its state (updated in place) and its constants (eqs 2.10, 2.11, 2.15).
struct BondLane {
  const Eigen::Vector3d *xa, *va, *wa;
  const Eigen::Quaterniond* qa;
  const Eigen::Vector3d *xb, *vb, *wb;
  const Eigen::Quaterniond* qb;
  const Eigen::Vector3d* shift;  ///< B's image shift in a periodic cell (zero without)
  const Eigen::Vector3d *arm_a, *arm_b, *normal_a, *normal_b;
  BondState* state;
  const BondConstants* constants;
};

/// What one bond's evaluation gives: the bond point and normal, the force and moment on B,
/// and a failure with the loads that broke it (then the state is reset to broken, and force
/// and moment are zero).
struct BondLaneResult {
  V3 point, normal, force, moment;
  BondFailure failure = BondFailure::none;
  BondState at_failure;
};

namespace pair_detail {

using namespace wide;

// (__m128d's and __m256d's attributes are not part of a template argument: no matter here.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"

/// The vectors *(in[i].*field) in lanes i.
template <class D, class Lane, class Field>
CLEAVE_LANES Wide<D> gather(const Lane* in, Field field) {
  return {lanes<D>([&](int i) { return (*(in[i].*field)).x(); }),
          lanes<D>([&](int i) { return (*(in[i].*field)).y(); }),
          lanes<D>([&](int i) { return (*(in[i].*field)).z(); })};
}
/// vec3.hpp's rotated (Eigen's _transformVector), lane i by the quaternion *(in[i].*field).
template <class D, class Lane, class Field>
CLEAVE_LANES Wide<D> rotated(const Lane* in, Field field, const Wide<D>& v) {
  return rotated(lanes<D>([&](int i) { return (in[i].*field)->x(); }),
                 lanes<D>([&](int i) { return (in[i].*field)->y(); }),
                 lanes<D>([&](int i) { return (in[i].*field)->z(); }),
                 lanes<D>([&](int i) { return (in[i].*field)->w(); }), v);
}
/// A bond state's or constants' field, lane i that of bond in[i].
template <class D>
CLEAVE_LANES D of_state(const BondLane* in, double BondState::*field) {
  return lanes<D>([&](int i) { return (*in[i].state).*field; });
}
template <class D>
CLEAVE_LANES Wide<D> of_state3(const BondLane* in, Eigen::Vector3d BondState::*field) {
  return {lanes<D>([&](int i) { return ((*in[i].state).*field).x(); }),
          lanes<D>([&](int i) { return ((*in[i].state).*field).y(); }),
          lanes<D>([&](int i) { return ((*in[i].state).*field).z(); })};
}
template <class D>
CLEAVE_LANES D constant(const BondLane* in, double BondConstants::*field) {
  return lanes<D>([&](int i) { return (*in[i].constants).*field; });
}

/// bond_pair and bond_quad: the N = sizeof(D) / 8 bonds in[0..N) in the lanes of D.
template <class D>
CLEAVE_LANES void bond_lanes(const BondLane* in, BondLaneResult* out, double dt) {
  constexpr int N = sizeof(D) / 8;
  // World::bond_forces: the bond point, the normal, B's material point's velocity relative
  // to A's there, the relative spin.
  const Wide<D> xa = gather<D>(in, &BondLane::xa), xb = gather<D>(in, &BondLane::xb);
  const Wide<D> xb3 = add(xb, gather<D>(in, &BondLane::shift));
  const Wide<D> pa = add(xa, rotated(in, &BondLane::qa, gather<D>(in, &BondLane::arm_a)));
  const Wide<D> pb = add(xb3, rotated(in, &BondLane::qb, gather<D>(in, &BondLane::arm_b)));
  const Wide<D> point = scale(splat<D>(0.5), add(pa, pb));
  const Wide<D> n = normalized(add(rotated(in, &BondLane::qa, gather<D>(in, &BondLane::normal_a)),
                                   rotated(in, &BondLane::qb, gather<D>(in, &BondLane::normal_b))));
  const Wide<D> wa = gather<D>(in, &BondLane::wa), wb = gather<D>(in, &BondLane::wb);
  const Wide<D> velocity = sub(add(gather<D>(in, &BondLane::vb), cross(wb, sub(point, xb3))),
                               add(gather<D>(in, &BondLane::va), cross(wa, sub(point, xa))));
  const Wide<D> spin = sub(wb, wa);
  // bond_force: the increments (eqs 2.12, 2.13).
  const D step = splat<D>(dt);
  const D vn = dot(velocity, n);
  const Wide<D> vs = sub(velocity, scale(vn, n));
  const D wt = dot(spin, n);
  const Wide<D> wr = sub(spin, scale(wt, n));
  const D normal = add(of_state<D>(in, &BondState::normal),
                       mul(mul(constant<D>(in, &BondConstants::kbn), vn), step));
  const Wide<D> shear = sub(into_plane(of_state3<D>(in, &BondState::shear), n),
                            scale(mul(constant<D>(in, &BondConstants::kbs), step), vs));
  const Wide<D> bending = sub(into_plane(of_state3<D>(in, &BondState::bending), n),
                              scale(mul(constant<D>(in, &BondConstants::kbr), step), wr));
  const D torsion = sub(of_state<D>(in, &BondState::torsion),
                        mul(mul(constant<D>(in, &BondConstants::kbt), step), wt));
  const D shear_size = root(dot(shear, shear));
  const D bending_size = root(dot(bending, bending));
  // The loads on B (tension pulls B back towards A).
  const Wide<D> force = add(scale(flip(normal), n), shear);
  const Wide<D> moment = add(bending, scale(torsion, n));
  for (int i = 0; i < N; ++i) {
    const BondLane& l = in[i];
    BondLaneResult& r = out[i];
    BondState& b = *l.state;
    b.normal = lane(normal, i);
    b.shear = eigen(lane(shear, i));
    b.bending = eigen(lane(bending, i));
    b.torsion = lane(torsion, i);
    r.point = lane(point, i);
    r.normal = lane(n, i);
    // Limits (eq. 2.15) and failure (eq. 2.16), as bond_force.
    r.failure = limit_failure(*l.constants, b.normal, lane(shear_size, i), lane(bending_size, i), b.torsion);
    if (r.failure != BondFailure::none) {
      r.at_failure = break_bond(b);
      r.force = r.moment = V3{0.0, 0.0, 0.0};
      continue;
    }
    r.force = lane(force, i);
    r.moment = lane(moment, i);
  }
}

#pragma GCC diagnostic pop

}  // namespace pair_detail

/// Two bonds of the bonded-particle law (in[0..2), out[0..2); BondLaw::bonded_particle, not
/// held, no thermal strain, no moving cell): their kinematics as World::bond_forces makes them and
/// bond_force; each lane to the bit of the scalar code. The states are updated (and reset
/// on a break) as bond_force does. Needs has_avx().
[[gnu::target("avx")]] inline void bond_pair(const BondLane* in, BondLaneResult* out, double dt) {
  pair_detail::bond_lanes<pair_detail::D2>(in, out, dt);
}

/// bond_pair for four bonds (in[0..4), out[0..4)), in AVX's four lanes. Needs has_avx().
[[gnu::target("avx")]] inline void bond_quad(const BondLane* in, BondLaneResult* out, double dt) {
  pair_detail::bond_lanes<pair_detail::D4>(in, out, dt);
}

}  // namespace cleave::physics
