#pragma once
/// \file
/// The bonded-particle law (eqs 2.12-2.16 of the dissertation) with its kinematics for two
/// bonds at once, one in each half of an SSE2 register: World::bond_forces' common case.
///
/// Why: one bond's step is a chain of seven square roots and five divisions, each waiting
/// on the one before (the normal's length, the two springs carried into the new plane, the
/// two limits), and perf put most of the law's time just after them. Two independent bonds
/// in one register run both chains in the time of one.
///
/// The bits: SSE2's packed add, multiply, divide and square root round each lane exactly as
/// the scalar instructions do, and every operation below is the scalar code's
/// (vec3.hpp, tangent.hpp, bond_law.cpp's bond_force, World::bond_forces), in its order; the
/// scalar code's branches (a zero length) become selects of the value that branch returns.
/// `BondPair.GivesTheScalarLawsBits` holds it to that.

#include <emmintrin.h>

#include <Eigen/Geometry>
#include <cmath>

#include "physics/bonds/bond_law.hpp"
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

using D2 = __m128d;
struct W3 {
  D2 x, y, z;
};

[[gnu::always_inline]] inline D2 two(double a, double b) { return _mm_set_pd(b, a); }
[[gnu::always_inline]] inline D2 add(D2 a, D2 b) { return _mm_add_pd(a, b); }
[[gnu::always_inline]] inline D2 sub(D2 a, D2 b) { return _mm_sub_pd(a, b); }
[[gnu::always_inline]] inline D2 mul(D2 a, D2 b) { return _mm_mul_pd(a, b); }
[[gnu::always_inline]] inline D2 div(D2 a, D2 b) { return _mm_div_pd(a, b); }
/// `mask ? a : b`, lane by lane.
[[gnu::always_inline]] inline D2 pick(D2 mask, D2 a, D2 b) {
  return _mm_or_pd(_mm_and_pd(mask, a), _mm_andnot_pd(mask, b));
}
[[gnu::always_inline]] inline W3 pick(D2 mask, const W3& a, const W3& b) {
  return {pick(mask, a.x, b.x), pick(mask, a.y, b.y), pick(mask, a.z, b.z)};
}
[[gnu::always_inline]] inline W3 two(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return {two(a.x(), b.x()), two(a.y(), b.y()), two(a.z(), b.z())};
}
[[gnu::always_inline]] inline W3 add(const W3& a, const W3& b) { return {add(a.x, b.x), add(a.y, b.y), add(a.z, b.z)}; }
[[gnu::always_inline]] inline W3 sub(const W3& a, const W3& b) { return {sub(a.x, b.x), sub(a.y, b.y), sub(a.z, b.z)}; }
[[gnu::always_inline]] inline W3 scale(D2 s, const W3& a) { return {mul(s, a.x), mul(s, a.y), mul(s, a.z)}; }
/// vec3.hpp's dot: (a0 b0 + a1 b1) + a2 b2.
[[gnu::always_inline]] inline D2 dot(const W3& a, const W3& b) {
  return add(add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z));
}
[[gnu::always_inline]] inline W3 cross(const W3& a, const W3& b) {
  return {sub(mul(a.y, b.z), mul(a.z, b.y)), sub(mul(a.z, b.x), mul(a.x, b.z)), sub(mul(a.x, b.y), mul(a.y, b.x))};
}
/// vec3.hpp's normalized: unchanged where the squared length is not positive.
[[gnu::always_inline]] inline W3 normalized(const W3& a) {
  const D2 z = dot(a, a);
  const D2 s = _mm_sqrt_pd(z);
  const W3 n{div(a.x, s), div(a.y, s), div(a.z, s)};
  return pick(_mm_cmpgt_pd(z, _mm_setzero_pd()), n, a);
}
/// vec3.hpp's rotated (Eigen's _transformVector), the two quaternions' in the two lanes.
[[gnu::always_inline]] inline W3 rotated(const Eigen::Quaterniond& q0, const Eigen::Quaterniond& q1, const W3& v) {
  const D2 qx = two(q0.x(), q1.x()), qy = two(q0.y(), q1.y()), qz = two(q0.z(), q1.z()), qw = two(q0.w(), q1.w());
  D2 ux = sub(mul(qy, v.z), mul(qz, v.y)), uy = sub(mul(qz, v.x), mul(qx, v.z)), uz = sub(mul(qx, v.y), mul(qy, v.x));
  ux = add(ux, ux);
  uy = add(uy, uy);
  uz = add(uz, uz);
  const D2 cx = sub(mul(qy, uz), mul(qz, uy)), cy = sub(mul(qz, ux), mul(qx, uz)), cz = sub(mul(qx, uy), mul(qy, ux));
  return {add(add(v.x, mul(qw, ux)), cx), add(add(v.y, mul(qw, uy)), cy), add(add(v.z, mul(qw, uz)), cz)};
}
/// tangent.hpp's into_plane: v where its length is zero, zero where its part across n is.
[[gnu::always_inline]] inline W3 into_plane(const W3& v, const W3& n) {
  const D2 zero = _mm_setzero_pd();
  const D2 len = _mm_sqrt_pd(dot(v, v));
  const W3 t = sub(v, scale(dot(v, n), n));
  const D2 tl = _mm_sqrt_pd(dot(t, t));
  const W3 scaled = scale(div(len, tl), t);
  // (t * (len / tl) is vec3.hpp's t * s: each component times s, the same product.)
  const W3 across = pick(_mm_cmpeq_pd(tl, zero), W3{zero, zero, zero}, scaled);
  return pick(_mm_cmpeq_pd(len, zero), v, across);
}
[[gnu::always_inline]] inline double lane0(D2 v) { return _mm_cvtsd_f64(v); }
[[gnu::always_inline]] inline double lane1(D2 v) { return _mm_cvtsd_f64(_mm_unpackhi_pd(v, v)); }
[[gnu::always_inline]] inline V3 lane(const W3& v, int i) {
  return i == 0 ? V3{lane0(v.x), lane0(v.y), lane0(v.z)} : V3{lane1(v.x), lane1(v.y), lane1(v.z)};
}
[[gnu::always_inline]] inline double lane(D2 v, int i) { return i == 0 ? lane0(v) : lane1(v); }

}  // namespace pair_detail

/// Two bonds of the bonded-particle law (BondLaw::bonded_particle, not held, no thermal
/// strain, no moving cell): their kinematics as World::bond_forces makes them and
/// bond_force; each lane to the bit of the scalar code. The states
/// are updated (and reset on a break) as bond_force does.
inline void bond_pair(const BondLane (&in)[2], BondLaneResult (&out)[2], double dt) {
  using namespace pair_detail;
  const BondLane &l0 = in[0], &l1 = in[1];
  // World::bond_forces: the bond point, the normal, B's material point's velocity relative
  // to A's there, the relative spin.
  const W3 xa = two(*l0.xa, *l1.xa), xb = two(*l0.xb, *l1.xb), shift = two(*l0.shift, *l1.shift);
  const W3 xb3 = add(xb, shift);
  const W3 pa = add(xa, rotated(*l0.qa, *l1.qa, two(*l0.arm_a, *l1.arm_a)));
  const W3 pb = add(xb3, rotated(*l0.qb, *l1.qb, two(*l0.arm_b, *l1.arm_b)));
  const W3 point = scale(_mm_set1_pd(0.5), add(pa, pb));
  const W3 n = normalized(
      add(rotated(*l0.qa, *l1.qa, two(*l0.normal_a, *l1.normal_a)), rotated(*l0.qb, *l1.qb, two(*l0.normal_b, *l1.normal_b))));
  const W3 wa = two(*l0.wa, *l1.wa), wb = two(*l0.wb, *l1.wb);
  const W3 velocity = sub(add(two(*l0.vb, *l1.vb), cross(wb, sub(point, xb3))),
                          add(two(*l0.va, *l1.va), cross(wa, sub(point, xa))));
  const W3 spin = sub(wb, wa);
  // bond_force: the increments (eqs 2.12, 2.13).
  const BondState &s0 = *l0.state, &s1 = *l1.state;
  const BondConstants &k0 = *l0.constants, &k1 = *l1.constants;
  const D2 step = _mm_set1_pd(dt);
  const D2 vn = dot(velocity, n);
  const W3 vs = sub(velocity, scale(vn, n));
  const D2 wt = dot(spin, n);
  const W3 wr = sub(spin, scale(wt, n));
  const D2 normal = add(two(s0.normal, s1.normal), mul(mul(two(k0.kbn, k1.kbn), vn), step));
  const W3 shear = sub(into_plane(two(s0.shear, s1.shear), n), scale(mul(two(k0.kbs, k1.kbs), step), vs));
  const W3 bending = sub(into_plane(two(s0.bending, s1.bending), n), scale(mul(two(k0.kbr, k1.kbr), step), wr));
  const D2 torsion = sub(two(s0.torsion, s1.torsion), mul(mul(two(k0.kbt, k1.kbt), step), wt));
  const D2 shear_size = _mm_sqrt_pd(dot(shear, shear));
  const D2 bending_size = _mm_sqrt_pd(dot(bending, bending));
  // The loads on B (tension pulls B back towards A).
  const D2 minus = _mm_set1_pd(-0.0);
  const W3 force = add(scale(_mm_xor_pd(normal, minus), n), shear);
  const W3 moment = add(bending, scale(torsion, n));
  for (int i = 0; i < 2; ++i) {
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

}  // namespace cleave::physics
