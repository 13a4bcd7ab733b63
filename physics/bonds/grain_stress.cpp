#include "physics/bonds/grain_stress.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace cleave::physics {

Eigen::Matrix3d average_stress(std::span<const ArmForce> forces, double volume) {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  for (const ArmForce& af : forces) s += af.arm * af.force.transpose();
  return stress_from_sum(s, volume);
}

Eigen::Matrix3d stress_from_sum(const Eigen::Matrix3d& sum, double volume) {
  const Eigen::Matrix3d transposed = sum.transpose();
  return (sum + transposed) / (2.0 * volume);
}

PlaneInvariants plane_invariants(const Eigen::Matrix3d& sigma) {
  const double sxx = sigma(0, 0), syy = sigma(1, 1), sxy = sigma(0, 1);
  PlaneInvariants out;
  out.p = 0.5 * (sxx + syy);
  out.q = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  out.theta = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  return out;
}

Eigen::Vector3d principal_stresses(const Eigen::Matrix3d& sigma) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(sigma, Eigen::EigenvaluesOnly).eigenvalues();
}

double mean_stress(const Eigen::Matrix3d& sigma) { return sigma.trace() / 3.0; }

double von_mises(const Eigen::Matrix3d& sigma) {
  const Eigen::Matrix3d dev = sigma - mean_stress(sigma) * Eigen::Matrix3d::Identity();
  return std::sqrt(1.5 * dev.cwiseProduct(dev).sum());
}

}  // namespace cleave::physics
