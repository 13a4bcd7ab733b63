#pragma once
/// \file
/// The bonded-particle law (eqs 2.12-2.16 of the dissertation) with its kinematics, written
/// once over physics/simd.hpp's lanes: bond_force is it for one bond, bond_batch for W = 1,
/// 2 or 4 bonds side by side (World::bond_forces' common case, four at a time).
///
/// Why lanes: one bond's step is a chain of seven square roots and five divisions, each
/// waiting on the one before (the normal's length, the two springs carried into the new
/// plane, the two limits). Independent bonds in the lanes of one register run their chains
/// in the time of one. Each lane rounds as the scalar code does (simd.hpp), so a bond's bits
/// do not depend on the lanes it shares.

#include <Eigen/Geometry>

#include "physics/bonds/bond_law.hpp"
#include "physics/bonds/tangent.hpp"
#include "physics/bonds/vec3.hpp"
#include "physics/simd.hpp"

namespace cleave::physics {

/// One bond's inputs to bond_batch: its two bodies' poses and motions, its geometry in their
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

/// Where a bond is and how its ends move, lane by lane: the bond point (the mean of its two
/// material points), the normal (the mean of its two material normals, unit), the velocity
/// of B's material point there relative to A's, the relative spin, and B's centroid (its
/// image's in a periodic cell).
template <class T>
struct BondMotion {
  Vec3<T> point, normal, velocity, spin, xb;
};
template <int W>
[[gnu::always_inline]] inline BondMotion<simd::Real<W>> bond_motion(const BondLane* in) {
  using T = simd::Real<W>;
  auto vec = [&](const Eigen::Vector3d* BondLane::*f) __attribute__((always_inline)) {
    return load3<W>([&](int i) -> const Eigen::Vector3d& { return *(in[i].*f); });
  };
  auto quat = [&](const Eigen::Quaterniond* BondLane::*f) __attribute__((always_inline)) {
    return load_quat<W>([&](int i) -> const Eigen::Quaterniond& { return *(in[i].*f); });
  };
  const Quat<T> qa = quat(&BondLane::qa), qb = quat(&BondLane::qb);
  BondMotion<T> m;
  const Vec3<T> xa = vec(&BondLane::xa);
  m.xb = vec(&BondLane::xb) + vec(&BondLane::shift);
  const Vec3<T> pa = xa + rotated(qa, vec(&BondLane::arm_a)),
                pb = m.xb + rotated(qb, vec(&BondLane::arm_b));
  m.point = 0.5 * (pa + pb);
  m.normal =
      normalized(rotated(qa, vec(&BondLane::normal_a)) + rotated(qb, vec(&BondLane::normal_b)));
  const Vec3<T> wa = vec(&BondLane::wa), wb = vec(&BondLane::wb);
  m.velocity = (vec(&BondLane::vb) + cross(wb, m.point - m.xb)) -
               (vec(&BondLane::va) + cross(wa, m.point - xa));
  m.spin = wb - wa;
  return m;
}

/// A bond's four loads (BondState's), lane by lane.
template <class T>
struct BondLoads {
  T normal;
  Vec3<T> shear, bending;
  T torsion;
};

/// Eqs 2.12-2.13, lane by lane: the springs carried into the plane across the unit normal n
/// and incremented by one step dt of relative velocity and spin, with the spring
/// stiffnesses K_bn, K_bs, K_br, K_bt (eqs 2.10, 2.11). Opening along n is tension.
template <class T>
[[gnu::always_inline]] inline BondLoads<T> bond_increment(const BondLoads<T>& b, const T& kbn,
                                                          const T& kbs, const T& kbr, const T& kbt,
                                                          const Vec3<T>& n, const Vec3<T>& velocity,
                                                          const Vec3<T>& spin, double dt) {
  const T vn = dot(velocity, n);
  const Vec3<T> vs = velocity - vn * n;
  const T wt = dot(spin, n);
  const Vec3<T> wr = spin - wt * n;
  return {b.normal + kbn * vn * dt, into_plane(b.shear, n) - kbs * dt * vs,
          into_plane(b.bending, n) - kbr * dt * wr, b.torsion - kbt * dt * wt};
}

/// The bonded-particle law for the W bonds in[0..W) (BondLaw::bonded_particle, not held, no
/// thermal strain, no moving cell): their kinematics as World::bond_forces makes them
/// (bond_motion), the increments (bond_increment), the limits (eq. 2.15) and failure (eq.
/// 2.16) as bond_force; the states are updated (and reset on a break) as bond_force does.
template <int W>
inline void bond_batch(const BondLane* in, BondLaneResult* out, double dt) {
  using T = simd::Real<W>;
  const BondMotion<T> m = bond_motion<W>(in);
  auto state = [&](double BondState::*f) __attribute__((always_inline)) {
    return simd::load<W>([&](int i) { return (*in[i].state).*f; });
  };
  auto state3 = [&](Eigen::Vector3d BondState::*f) __attribute__((always_inline)) {
    return load3<W>([&](int i) -> const Eigen::Vector3d& { return (*in[i].state).*f; });
  };
  auto constant = [&](double BondConstants::*f) __attribute__((always_inline)) {
    return simd::load<W>([&](int i) { return (*in[i].constants).*f; });
  };
  const BondLoads<T> b = bond_increment<T>(
      {state(&BondState::normal), state3(&BondState::shear), state3(&BondState::bending),
       state(&BondState::torsion)},
      constant(&BondConstants::kbn), constant(&BondConstants::kbs), constant(&BondConstants::kbr),
      constant(&BondConstants::kbt), m.normal, m.velocity, m.spin, dt);
  const T shear_size = norm(b.shear), bending_size = norm(b.bending);
  // The loads on B (tension pulls B back towards A).
  const Vec3<T> force = -b.normal * m.normal + b.shear;
  const Vec3<T> moment = b.bending + b.torsion * m.normal;
  for (int i = 0; i < W; ++i) {
    const BondLane& l = in[i];
    BondLaneResult& r = out[i];
    BondState& s = *l.state;
    s.normal = simd::lane(b.normal, i);
    s.shear = eigen(lane(b.shear, i));
    s.bending = eigen(lane(b.bending, i));
    s.torsion = simd::lane(b.torsion, i);
    r.point = lane(m.point, i);
    r.normal = lane(m.normal, i);
    r.failure = limit_failure(*l.constants, s.normal, simd::lane(shear_size, i),
                              simd::lane(bending_size, i), s.torsion);
    if (r.failure != BondFailure::none) {
      r.at_failure = break_bond(s);
      r.force = r.moment = V3{0.0, 0.0, 0.0};
      continue;
    }
    r.force = lane(force, i);
    r.moment = lane(moment, i);
  }
}

}  // namespace cleave::physics
