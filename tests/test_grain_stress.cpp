// Averaged grain stress (eq. 2.17), its invariants (eq. 2.18) and principal values, against
// closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

#include "physics/bonds/grain_stress.hpp"
#include "physics/dem/world.hpp"
#include "prism_row.hpp"

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

// ---------------------------------------------------------------------------------------
// World::body_stresses on bonded prisms whose neighbours are moved by a prescribed
// displacement gradient: eq. 2.17 against the closed form of the bond law (eqs 2.10-2.12).

namespace {

using cleave::test::kPitch;

/// A prism at the origin and its six honeycomb neighbours (face normals at 0, 60, ..., 300
/// degrees) a small gap away, all bonded and all held. The neighbours are then moved by the
/// displacement field u = G x (G applied to their centroids, no rotation) and the centre's
/// stress is read.
struct Rosette {
  static constexpr double kGap = 2e-6;  // m: no contact force, only the bonds act
  static constexpr double kDt = 1e-7;
  World world{cleave::test::prism_settings(kDt)};
  BodyId centre;
  std::vector<BodyId> ring;
  double volume = cleave::test::prism().volume;
  double pitch = kPitch + kGap;  // centroid distance l

  Rosette() {
    const RigidShape shape = cleave::test::prism();
    const auto sh = world.add_shape(shape);
    centre = world.add_body(sh, cleave::test::kRho, Eigen::Vector3d::Zero(), shape.orientation_for());
    for (int k = 0; k < 6; ++k) {
      const double a = k * M_PI / 3.0;
      ring.push_back(world.add_body(sh, cleave::test::kRho, pitch * Eigen::Vector3d(std::cos(a), std::sin(a), 0),
                                    shape.orientation_for()));
    }
    EXPECT_GE(world.initialise_bonds(cleave::test::strong_bonds(), 2.0 * kGap), 6u);
    world.set_fixed(centre, true);
    for (const BodyId id : ring) world.set_fixed(id, true);
  }

  /// Moves the neighbours by u = G x over `steps` steps, holds them, and returns the centre's
  /// stress after one more step (its forces at the final places).
  Eigen::Matrix3d strained(const Eigen::Matrix3d& G, int steps = 400) {
    for (const BodyId id : ring) world.state(id).v = G * world.state(id).x / (steps * kDt);
    for (int i = 0; i < steps; ++i) world.step();
    for (const BodyId id : ring) world.state(id).v.setZero();
    world.step();
    return world.body_stresses()[centre.index];
  }
};

}  // namespace

TEST(GrainStress, SimpleShearOfTheNeighboursGivesTheSymmetricShearStressOfTheBondSprings) {
  // Simple shear u_x = g y: strain eps_xy = g/2 plus a rigid turn, which loads the centre
  // with a net moment (an asymmetric sum of d (x) f). With d_j = (l/2) n_j and
  // f_j = K_n l (n.eps n) n + K_s l (eps n - (n.eps n) n) (the turn's part of f_j, K_s l w n,
  // cancels when symmetrised), the six directions' sums (sum n_x^2 n_y^2 = 3/4,
  // sum n_x^2 = 3) give sigma_xy = 3/4 (g/2) l^2 (K_n + K_s) / V and nothing else.
  Rosette r;
  const double g = 1e-4;
  Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
  G(0, 1) = g;
  const Eigen::Matrix3d s = r.strained(G);
  const double tau = 0.75 * (g / 2) * r.pitch * r.pitch * (cleave::test::kSpringN + cleave::test::kSpringS) / r.volume;
  EXPECT_NEAR(s(0, 1), tau, 2e-3 * tau);
  EXPECT_NEAR(s(1, 0), tau, 2e-3 * tau);
  EXPECT_EQ(s(0, 1), s(1, 0));  // symmetric to the bit
  for (const auto [i, j] : {std::pair{0, 0}, {1, 1}, {2, 2}, {0, 2}, {2, 0}, {1, 2}, {2, 1}}) {
    EXPECT_NEAR(s(i, j), 0.0, 2e-3 * tau) << i << "," << j;
  }
  // Pure shear: principal stresses -tau, 0, tau; von Mises sqrt(3) tau; q_xy = tau at 45 deg.
  const Eigen::Vector3d p = principal_stresses(s);
  EXPECT_NEAR(p[0], -tau, 2e-3 * tau);
  EXPECT_NEAR(p[2], tau, 2e-3 * tau);
  EXPECT_NEAR(von_mises(s), std::sqrt(3.0) * tau, 2e-3 * tau);
  EXPECT_NEAR(plane_invariants(s).q, tau, 2e-3 * tau);
  EXPECT_NEAR(plane_invariants(s).theta, M_PI / 4, 2e-3);
}

TEST(GrainStress, EqualBiaxialStretchOfTheNeighboursGivesAnInPlaneHydrostaticStress) {
  // u = e (x, y, 0): f_j = K_n l e n_j, so sigma = (l/2) K_n l e (sum n (x) n) / V
  // = 3/2 l^2 K_n e / V on xx and yy, no shear, nothing along the prisms' axis.
  Rosette r;
  const double e = 1e-4;
  const Eigen::Matrix3d G = Eigen::Vector3d(e, e, 0).asDiagonal();
  const Eigen::Matrix3d s = r.strained(G);
  const double sigma = 1.5 * r.pitch * r.pitch * cleave::test::kSpringN * e / r.volume;
  EXPECT_NEAR(s(0, 0), sigma, 2e-3 * sigma);
  EXPECT_NEAR(s(1, 1), sigma, 2e-3 * sigma);
  EXPECT_NEAR(s(0, 1), 0.0, 2e-3 * sigma);
  EXPECT_NEAR(s(2, 2), 0.0, 2e-3 * sigma);
  EXPECT_NEAR(mean_stress(s), 2.0 * sigma / 3.0, 2e-3 * sigma);
  EXPECT_NEAR(plane_invariants(s).p, sigma, 2e-3 * sigma);
  EXPECT_NEAR(plane_invariants(s).q, 0.0, 2e-3 * sigma);
  EXPECT_NEAR(von_mises(s), sigma, 2e-3 * sigma);  // biaxial equal: |sigma|
}

TEST(GrainStress, AnAxiallyLoadedBondedBarCarriesForceOverAreaAlongItsAxis) {
  // Five prisms in a row, the ends pulled apart by delta and held: every bond carries
  // F = K_n delta / 4 (springs in series), and an inner prism, pulled by F at arms of l/2 on
  // both sides, carries sigma = F l / V = F / A (A = V / l, the bar's section per prism):
  // uniaxial, von Mises = |sigma|, its principal direction along the bar.
  World world{cleave::test::prism_settings(1e-7)};
  const auto ids = cleave::test::row(world, 5, -2e-6);
  ASSERT_EQ(world.initialise_bonds(cleave::test::strong_bonds(), 4e-6), 4u);
  world.set_fixed(ids.front(), true);
  world.set_fixed(ids.back(), true);
  for (std::size_t i = 1; i + 1 < ids.size(); ++i) world.set_fixed(ids[i], true);
  const double delta = 4e-8;
  const int steps = 400;
  // The inner prisms follow the uniform stretch, so every bond carries the series force.
  for (std::size_t i = 0; i < ids.size(); ++i) {
    world.state(ids[i]).v = {delta * static_cast<double>(i) / 4.0 / (steps * 1e-7), 0, 0};
  }
  for (int i = 0; i < steps; ++i) world.step();
  for (const BodyId id : ids) world.state(id).v.setZero();
  world.step();
  const double F = cleave::test::kSpringN * delta / 4.0;
  const double pitch = world.state(ids[2]).x.x() - world.state(ids[1]).x.x();
  const double V = cleave::test::prism().volume;
  for (std::size_t i = 1; i + 1 < ids.size(); ++i) {
    const Eigen::Matrix3d s = world.body_stresses()[ids[i].index];
    const double expected = F * pitch / V;
    EXPECT_NEAR(s(0, 0), expected, 1e-3 * expected) << "prism " << i;
    EXPECT_NEAR(von_mises(s), expected, 1e-3 * expected);
    EXPECT_NEAR(principal_stresses(s)[2], expected, 1e-3 * expected);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(s);
    EXPECT_NEAR(std::abs(eig.eigenvectors().col(2).x()), 1.0, 1e-6) << "principal direction along the bar";
    EXPECT_NEAR((s - s.transpose()).norm(), 0.0, 1e-12 * expected);
  }
}
