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

/// The kick of n <= kDriftBatch bodies, each with kick()'s bits (their angular velocities
/// side by side, physics/simd.hpp).
void kick(BodyState* const s[], const BodyInfo* const b[], int n, double h);

/// The same kick leaving w as it was, for a kick that a drift (which sets w) follows.
void kick_momenta(BodyState& s, const BodyInfo& b, double h);

/// The drift: x += h v, and the free rotation of (q, L) over h.
void drift(BodyState& s, const BodyInfo& b, double h);

/// Bodies drifted together (see the batch drift below).
constexpr int kDriftBatch = 4;

/// The drift of n <= kDriftBatch bodies at once, each with the bits drift() gives it: their
/// rotations side by side (physics/simd.hpp), so that one body's sub-rotations, which wait on
/// each other, overlap another's.
void drift(BodyState* const s[], const BodyInfo* const b[], int n, double h);

/// Free rigid-body rotation over h of orientation q (principal -> world) with constant
/// world angular momentum L, by the symmetric splitting X(h/2) Y(h/2) Z(h) Y(h/2) X(h/2).
void rotate_free(Eigen::Quaterniond& q, const Eigen::Vector3d& L, const Eigen::Vector3d& inv_inertia,
                 double h);

}  // namespace cleave::physics
