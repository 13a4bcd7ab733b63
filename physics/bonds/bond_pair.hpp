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
/// exactly as the scalar instructions do (no fused multiply-add: the target is AVX, not FMA), and every operation below is the scalar code's
/// (vec3.hpp, tangent.hpp, bond_law.cpp's bond_force, World::bond_forces), in its order; the
/// scalar code's branches (a zero length) become selects of the value that branch returns.
/// `BondPair.GivesTheScalarLawsBitsInEachLane` holds both widths to that.

#include <immintrin.h>

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

// (__m128d's and __m256d's attributes are not part of a template argument: no matter here.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"

/// The AVX lanes' functions are compiled for AVX (the caller checks has_avx()); the SSE2
/// ones too, so that one generic body (bond_lanes) serves both.
#define CLEAVE_LANES [[gnu::always_inline, gnu::target("avx")]] inline

using D2 = __m128d;
using D4 = __m256d;
template <class D>
struct Wide {
  D x, y, z;
};
using W3 = Wide<D2>;

CLEAVE_LANES D2 add(D2 a, D2 b) { return _mm_add_pd(a, b); }
CLEAVE_LANES D2 sub(D2 a, D2 b) { return _mm_sub_pd(a, b); }
CLEAVE_LANES D2 mul(D2 a, D2 b) { return _mm_mul_pd(a, b); }
CLEAVE_LANES D2 div(D2 a, D2 b) { return _mm_div_pd(a, b); }
CLEAVE_LANES D2 root(D2 a) { return _mm_sqrt_pd(a); }
CLEAVE_LANES D2 equal(D2 a, D2 b) { return _mm_cmpeq_pd(a, b); }
CLEAVE_LANES D2 greater(D2 a, D2 b) { return _mm_cmpgt_pd(a, b); }
CLEAVE_LANES D2 flip(D2 a) { return _mm_xor_pd(a, _mm_set1_pd(-0.0)); }  // the sign bit
/// `mask ? a : b`, lane by lane.
CLEAVE_LANES D2 pick(D2 mask, D2 a, D2 b) { return _mm_or_pd(_mm_and_pd(mask, a), _mm_andnot_pd(mask, b)); }
CLEAVE_LANES D4 add(D4 a, D4 b) { return _mm256_add_pd(a, b); }
CLEAVE_LANES D4 sub(D4 a, D4 b) { return _mm256_sub_pd(a, b); }
CLEAVE_LANES D4 mul(D4 a, D4 b) { return _mm256_mul_pd(a, b); }
CLEAVE_LANES D4 div(D4 a, D4 b) { return _mm256_div_pd(a, b); }
CLEAVE_LANES D4 root(D4 a) { return _mm256_sqrt_pd(a); }
CLEAVE_LANES D4 equal(D4 a, D4 b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
CLEAVE_LANES D4 greater(D4 a, D4 b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
CLEAVE_LANES D4 flip(D4 a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
CLEAVE_LANES D4 pick(D4 mask, D4 a, D4 b) { return _mm256_or_pd(_mm256_and_pd(mask, a), _mm256_andnot_pd(mask, b)); }

/// The register of get(0), get(1), ... in lanes 0, 1, ...
template <class D, class Get>
CLEAVE_LANES D lanes(Get&& get) {
  if constexpr (sizeof(D) == 16) {
    return _mm_set_pd(get(1), get(0));
  } else {
    return _mm256_set_pd(get(3), get(2), get(1), get(0));
  }
}
template <class D>
CLEAVE_LANES D splat(double a) {
  return lanes<D>([a](int) { return a; });
}
/// Lane i of v.
template <class D>
CLEAVE_LANES double lane(D v, int i) {
  alignas(32) double out[sizeof(D) / 8];
  if constexpr (sizeof(D) == 16) {
    _mm_store_pd(out, v);
  } else {
    _mm256_store_pd(out, v);
  }
  return out[i];
}
template <class D>
CLEAVE_LANES V3 lane(const Wide<D>& v, int i) {
  return {lane(v.x, i), lane(v.y, i), lane(v.z, i)};
}

template <class D>
CLEAVE_LANES Wide<D> pick(D mask, const Wide<D>& a, const Wide<D>& b) {
  return {pick(mask, a.x, b.x), pick(mask, a.y, b.y), pick(mask, a.z, b.z)};
}
template <class D>
CLEAVE_LANES Wide<D> add(const Wide<D>& a, const Wide<D>& b) {
  return {add(a.x, b.x), add(a.y, b.y), add(a.z, b.z)};
}
template <class D>
CLEAVE_LANES Wide<D> sub(const Wide<D>& a, const Wide<D>& b) {
  return {sub(a.x, b.x), sub(a.y, b.y), sub(a.z, b.z)};
}
template <class D>
CLEAVE_LANES Wide<D> scale(D s, const Wide<D>& a) {
  return {mul(s, a.x), mul(s, a.y), mul(s, a.z)};
}
/// vec3.hpp's dot: (a0 b0 + a1 b1) + a2 b2.
template <class D>
CLEAVE_LANES D dot(const Wide<D>& a, const Wide<D>& b) {
  return add(add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z));
}
template <class D>
CLEAVE_LANES Wide<D> cross(const Wide<D>& a, const Wide<D>& b) {
  return {sub(mul(a.y, b.z), mul(a.z, b.y)), sub(mul(a.z, b.x), mul(a.x, b.z)), sub(mul(a.x, b.y), mul(a.y, b.x))};
}
/// vec3.hpp's normalized: unchanged where the squared length is not positive.
template <class D>
CLEAVE_LANES Wide<D> normalized(const Wide<D>& a) {
  const D z = dot(a, a);
  const D s = root(z);
  const Wide<D> n{div(a.x, s), div(a.y, s), div(a.z, s)};
  return pick(greater(z, splat<D>(0.0)), n, a);
}
/// The vectors *(in[i].*field) in lanes i.
template <class D, class Lane, class Field>
CLEAVE_LANES Wide<D> gather(const Lane* in, Field field) {
  return {lanes<D>([&](int i) { return (*(in[i].*field)).x(); }), lanes<D>([&](int i) { return (*(in[i].*field)).y(); }),
          lanes<D>([&](int i) { return (*(in[i].*field)).z(); })};
}
/// vec3.hpp's rotated (Eigen's _transformVector), lane i by the quaternion *(in[i].*field).
template <class D, class Lane, class Field>
CLEAVE_LANES Wide<D> rotated(const Lane* in, Field field, const Wide<D>& v) {
  const D qx = lanes<D>([&](int i) { return (in[i].*field)->x(); });
  const D qy = lanes<D>([&](int i) { return (in[i].*field)->y(); });
  const D qz = lanes<D>([&](int i) { return (in[i].*field)->z(); });
  const D qw = lanes<D>([&](int i) { return (in[i].*field)->w(); });
  D ux = sub(mul(qy, v.z), mul(qz, v.y)), uy = sub(mul(qz, v.x), mul(qx, v.z)), uz = sub(mul(qx, v.y), mul(qy, v.x));
  ux = add(ux, ux);
  uy = add(uy, uy);
  uz = add(uz, uz);
  const D cx = sub(mul(qy, uz), mul(qz, uy)), cy = sub(mul(qz, ux), mul(qx, uz)), cz = sub(mul(qx, uy), mul(qy, ux));
  return {add(add(v.x, mul(qw, ux)), cx), add(add(v.y, mul(qw, uy)), cy), add(add(v.z, mul(qw, uz)), cz)};
}
/// tangent.hpp's into_plane: v where its length is zero, zero where its part across n is.
template <class D>
CLEAVE_LANES Wide<D> into_plane(const Wide<D>& v, const Wide<D>& n) {
  const D zero = splat<D>(0.0);
  const D len = root(dot(v, v));
  const Wide<D> t = sub(v, scale(dot(v, n), n));
  const D tl = root(dot(t, t));
  const Wide<D> scaled = scale(div(len, tl), t);
  // (t * (len / tl) is vec3.hpp's t * s: each component times s, the same product.)
  const Wide<D> across = pick(equal(tl, zero), Wide<D>{zero, zero, zero}, scaled);
  return pick(equal(len, zero), v, across);
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
  const D normal = add(of_state<D>(in, &BondState::normal), mul(mul(constant<D>(in, &BondConstants::kbn), vn), step));
  const Wide<D> shear = sub(into_plane(of_state3<D>(in, &BondState::shear), n),
                            scale(mul(constant<D>(in, &BondConstants::kbs), step), vs));
  const Wide<D> bending = sub(into_plane(of_state3<D>(in, &BondState::bending), n),
                              scale(mul(constant<D>(in, &BondConstants::kbr), step), wr));
  const D torsion = sub(of_state<D>(in, &BondState::torsion), mul(mul(constant<D>(in, &BondConstants::kbt), step), wt));
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

#undef CLEAVE_LANES
#pragma GCC diagnostic pop

}  // namespace pair_detail

/// Whether this processor runs AVX (bond_pair and bond_quad need it; without, World evaluates
/// each bond alone, with the same bits).
[[nodiscard]] inline bool has_avx() {
  static const bool avx = __builtin_cpu_supports("avx");
  return avx;
}

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
