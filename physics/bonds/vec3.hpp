#pragma once
/// \file
/// Three doubles for the per-contact and per-bond loops (the laws, their kinematics, the
/// sums onto the bodies), with each operation's arithmetic in the order Eigen gives it, so that the
/// results are Eigen's bits (`ContactLaw.ScalarFormGivesEigensBits`,
/// `BondLaw.ScalarFormGivesEigensBits`).
///
/// Why not Eigen::Vector3d there: at -O2 Eigen adds two Vector3d as one SSE pair plus one
/// scalar, and a cross product's result goes through the stack as three scalars; the pair's
/// load then waits for two scalar stores it cannot forward from. perf put 40 % of the
/// contact kinematics' time on two such loads. Plain doubles stay in registers.

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>

namespace cleave::physics {

struct V3 {
  double x, y, z;
};

[[gnu::always_inline]] inline V3 v3(const Eigen::Vector3d& e) { return {e.x(), e.y(), e.z()}; }
[[gnu::always_inline]] inline Eigen::Vector3d eigen(const V3& a) { return {a.x, a.y, a.z}; }
[[gnu::always_inline]] inline V3 operator+(const V3& a, const V3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
[[gnu::always_inline]] inline V3 operator-(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
[[gnu::always_inline]] inline V3 operator*(double s, const V3& a) { return {s * a.x, s * a.y, s * a.z}; }
[[gnu::always_inline]] inline V3 operator*(const V3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
/// Eigen's a.dot(b) and squaredNorm(): (a0 b0 + a1 b1) + a2 b2.
[[gnu::always_inline]] inline double dot(const V3& a, const V3& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
[[gnu::always_inline]] inline double norm(const V3& a) { return std::sqrt(dot(a, a)); }
/// True only when norm(a) < limit, strictly and to the bit, decided without the square root
/// (its latency held up the laws' caps): |a|^2 < fl(limit^2) (1 - 2^-20). With fl(limit^2)
/// and that product each at most one rounding (2^-53) high, |a| < limit (1 - 2^-22), and the
/// correctly rounded root stays below limit. Limits far from 1 (where limit^2 leaves the
/// normal range) and NaN answer false: the caller then takes the root.
[[gnu::always_inline]] inline bool surely_shorter(const V3& a, double limit) {
  return limit > 1e-150 && limit < 1e150 && dot(a, a) < (limit * limit) * (1.0 - 0x1p-20);
}
/// Eigen's a.cross(b).
[[gnu::always_inline]] inline V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Eigen's normalized(): each component divided by the length (unchanged when it is zero).
[[gnu::always_inline]] inline V3 normalized(const V3& a) {
  const double z = dot(a, a);
  if (!(z > 0.0)) return a;
  const double s = std::sqrt(z);
  return {a.x / s, a.y / s, a.z / s};
}
/// q * v with the arithmetic of Eigen's QuaternionBase::_transformVector (the same bits);
/// physics/dem/body.hpp's rotated() is this on Eigen vectors.
[[gnu::always_inline]] inline V3 rotated(const Eigen::Quaterniond& q, const V3& v) {
  const double qx = q.x(), qy = q.y(), qz = q.z(), qw = q.w();
  double ux = qy * v.z - qz * v.y, uy = qz * v.x - qx * v.z, uz = qx * v.y - qy * v.x;
  ux += ux;
  uy += uy;
  uz += uz;
  const double cx = qy * uz - qz * uy, cy = qz * ux - qx * uz, cz = qx * uy - qy * ux;
  return {(v.x + qw * ux) + cx, (v.y + qw * uy) + cy, (v.z + qw * uz) + cz};
}

}  // namespace cleave::physics
