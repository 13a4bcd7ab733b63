// Averaged grain stress (eq. 2.17), its invariants (eq. 2.18) and principal values, against
// closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "physics/bonds/grain_stress.hpp"

using namespace cleave::physics;

namespace {
const double kSqrt3 = std::sqrt(3.0);
}

TEST(GrainStress, UniaxialLoadOnAPrismGivesForceOverArea) {
  // A hexagonal prism (side a, thickness t) pressed by F at the centres of its basal
  // faces: sigma_zz = -F / A with A the hexagon's area, every other component zero.
  const double a = 0.5e-3, t = 1e-3, F = 2.0;
  const double area = 1.5 * kSqrt3 * a * a, volume = area * t;
  const std::vector<ArmForce> forces{{{0, 0, t / 2}, {0, 0, -F}}, {{0, 0, -t / 2}, {0, 0, F}}};
  const Eigen::Matrix3d s = average_stress(forces, volume);
  EXPECT_NEAR(s(2, 2), -F / area, 1e-9 * F / area);
  EXPECT_NEAR(s.norm() - std::abs(s(2, 2)), 0.0, 1e-9 * F / area);
  EXPECT_NEAR(mean_stress(s), -F / area / 3, 1e-9 * F / area);
  EXPECT_NEAR(von_mises(s), F / area, 1e-9 * F / area);  // uniaxial: von Mises = |sigma|
  const Eigen::Vector3d p = principal_stresses(s);
  EXPECT_NEAR(p[0], -F / area, 1e-9 * F / area);
  EXPECT_NEAR(p[2], 0.0, 1e-9 * F / area);
}

TEST(GrainStress, ShearCoupleGivesASymmetricShearStress) {
  // A unit cube loaded by tau on its four side faces (a pure shear in x-y, in equilibrium):
  // sigma_xy = sigma_yx = tau, p = 0, q = tau, principal stresses -tau, 0, tau at 45 deg.
  const double tau = 3.0, h = 0.5;
  const std::vector<ArmForce> forces{{{h, 0, 0}, {0, tau, 0}},
                                     {{-h, 0, 0}, {0, -tau, 0}},
                                     {{0, h, 0}, {tau, 0, 0}},
                                     {{0, -h, 0}, {-tau, 0, 0}}};
  const Eigen::Matrix3d s = average_stress(forces, 1.0);
  EXPECT_NEAR(s(0, 1), tau, 1e-12);
  EXPECT_NEAR(s(1, 0), tau, 1e-12);
  EXPECT_NEAR(s(0, 0), 0.0, 1e-12);
  const PlaneInvariants inv = plane_invariants(s);
  EXPECT_NEAR(inv.p, 0.0, 1e-12);
  EXPECT_NEAR(inv.q, tau, 1e-12);
  EXPECT_NEAR(inv.theta, M_PI / 4, 1e-12);
  const Eigen::Vector3d p = principal_stresses(s);
  EXPECT_NEAR(p[0], -tau, 1e-12);
  EXPECT_NEAR(p[1], 0.0, 1e-12);
  EXPECT_NEAR(p[2], tau, 1e-12);
}

TEST(GrainStress, RotatingTheLoadRotatesTheStress) {
  const std::vector<ArmForce> forces{{{0.1, 0.2, 0.3}, {1.0, -2.0, 0.5}},
                                     {{-0.1, -0.2, -0.3}, {-1.0, 2.0, -0.5}}};
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<ArmForce> turned;
  for (const auto& f : forces) turned.push_back({R * f.arm, R * f.force});
  const Eigen::Matrix3d s = average_stress(forces, 2.0);
  const Eigen::Matrix3d st = average_stress(turned, 2.0);
  EXPECT_NEAR((st - R * s * R.transpose()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((principal_stresses(st) - principal_stresses(s)).norm(), 0.0, 1e-12);
}
