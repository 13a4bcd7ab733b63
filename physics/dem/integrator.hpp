#pragma once
/// \file
/// Time integration of rigid bodies: velocity Verlet (kick-drift-kick) for translation and,
/// for rotation, the same kicks of the angular momentum around a free-rigid-body drift
/// computed by the symmetric splitting of Dullweber, Leimkuhler & McLachlan (J. Chem.
/// Phys. 107, 1997): the kinetic energy is split along the three principal axes and each
/// part is an exact rotation about that axis. The scheme is symplectic and time-reversible,
/// conserves the angular momentum exactly (up to round-off) and keeps the energy of a
/// torque-free body bounded with no secular drift, with the full inertia tensor of a
/// non-spherical body (seed 003: velocity Verlet with quaternions).

#include <cmath>

#include "physics/dem/body.hpp"

namespace cleave::physics {

/// Angular velocity (world) from angular momentum (world): w = R I^-1 R^T L.
Eigen::Vector3d angular_velocity(const Eigen::Quaterniond& q, const Eigen::Vector3d& L,
                                 const Eigen::Vector3d& inv_inertia);

/// Half of velocity Verlet's kick: v += h f / m, L += h tau, and w follows.
void kick(BodyState& s, const BodyInfo& b, double h);

/// The kick of n <= kDriftBatch bodies, each with kick()'s bits; with `lanes`, four bodies'
/// angular velocities in AVX's lanes where the processor has them.
void kick(BodyState* const s[], const BodyInfo* const b[], int n, double h, bool lanes = true);

/// The same kick leaving w as it was, for a kick that a drift (which sets w) follows.
void kick_momenta(BodyState& s, const BodyInfo& b, double h);

/// The drift: x += h v, and the free rotation of (q, L) over h.
void drift(BodyState& s, const BodyInfo& b, double h);

/// Bodies drifted together (see the batch drift below).
constexpr int kDriftBatch = 4;

/// The drift of n <= kDriftBatch bodies at once, each with the bits drift() gives it: their
/// rotations are computed side by side, so that the sines and cosines of different bodies
/// overlap (one body's five sub-rotations depend on each other); four in AVX's lanes with
/// `lanes` where the processor has them.
void drift(BodyState* const s[], const BodyInfo* const b[], int n, double h, bool lanes = true);

/// a * b with the arithmetic of Eigen's SSE quaternion product (the same bits), in scalars:
/// the drift's sub-rotations build b a component at a time, and Eigen's product then reads
/// it as two 16-byte loads that wait for those 8-byte stores (perf put a quarter of the
/// drift on four such loads).
[[gnu::always_inline]] inline Eigen::Quaterniond quaternion_product(const Eigen::Quaterniond& a,
                                                                    const Eigen::Quaterniond& b) {
  const double x = a.x(), y = a.y(), z = a.z(), w = a.w();
  const double bx = b.x(), by = b.y(), bz = b.z(), bw = b.w();
  Eigen::Quaterniond r;
  r.x() = (w * bx + y * bz) - (z * by - x * bw);
  r.y() = (w * by + y * bw) + (z * bx - x * bz);
  r.z() = (w * bz - y * bx) + (z * bw + x * by);
  r.w() = (w * bw - y * by) - (z * bz + x * bx);
  return r;
}

/// q.normalize() with the arithmetic of Eigen's SSE code (the same bits), in scalars.
[[gnu::always_inline]] inline void normalize_quaternion(Eigen::Quaterniond& q) {
  const double x = q.x(), y = q.y(), z = q.z(), w = q.w();
  const double n2 = (x * x + z * z) + (y * y + w * w);  // Eigen's two-lane sum of squares
  if (!(n2 > 0.0)) return;
  const double n = std::sqrt(n2);
  q.x() = x / n;
  q.y() = y / n;
  q.z() = z / n;
  q.w() = w / n;
}

/// Free rigid-body rotation over h of orientation q (principal -> world) with constant
/// world angular momentum L, by the symmetric splitting X(h/2) Y(h/2) Z(h) Y(h/2) X(h/2).
void rotate_free(Eigen::Quaterniond& q, const Eigen::Vector3d& L, const Eigen::Vector3d& inv_inertia,
                 double h);

}  // namespace cleave::physics
