#pragma once
/// \file
/// The averaged Cauchy stress of a discrete element from its contact forces (sec. 2.4 of
/// the dissertation, eq. 2.17; Love-Weber), its 2D invariants (eq. 2.18) and principal
/// stresses.
///
/// Eq. 2.17 as printed carries an extra 1/2 inside the bracket; the symmetric Love-Weber
/// average it cites is sigma = 1/(2V) sum_j (d_j (x) f_j + f_j (x) d_j), which is what makes
/// the average of a uniformly loaded body equal the applied traction (see the tests), so
/// that is what cleave computes.

#include <Eigen/Dense>
#include <span>

namespace cleave::physics {

/// One force on the body and its arm from the body's centroid to where it acts.
struct ArmForce {
  Eigen::Vector3d arm;
  Eigen::Vector3d force;
};

/// Eq. 2.17: the symmetric average stress of a body of volume `volume` (Pa; tension > 0).
Eigen::Matrix3d average_stress(std::span<const ArmForce> forces, double volume);

/// Eq. 2.17 from a body's sum of arm (x) force: (S + S^T) / 2V. The one place that
/// symmetrises, so that no caller writes S into itself while reading S^T (Eigen aliasing).
Eigen::Matrix3d stress_from_sum(const Eigen::Matrix3d& sum, double volume);

/// Eq. 2.18: p = (sxx + syy) / 2, q = sqrt((sxx - syy)^2 / 4 + sxy^2),
/// theta = atan2(2 sxy, sxx - syy) / 2.
struct PlaneInvariants {
  double p = 0.0, q = 0.0, theta = 0.0;
};
PlaneInvariants plane_invariants(const Eigen::Matrix3d& sigma);

/// Principal stresses, ascending (most compressive first).
Eigen::Vector3d principal_stresses(const Eigen::Matrix3d& sigma);

/// Mean stress tr(sigma) / 3 (the hydrostatic stress of eq. 3.22).
double mean_stress(const Eigen::Matrix3d& sigma);

/// Von Mises equivalent stress.
double von_mises(const Eigen::Matrix3d& sigma);

}  // namespace cleave::physics
