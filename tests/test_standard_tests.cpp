// The standard tests' formulas (validation/standard_tests.hpp) against closed forms derived
// apart from them: beam statics for four-point flexure, the edge-crack and deep-crack limits
// of the notched beam, a brute-force sum over the honeycomb's springs, and random affine
// displacement fields.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "validation/standard_tests.hpp"

using namespace cleave::physics;

TEST(FourPointFlexure, TheStrengthIsTheMidSpanMomentOverTheSectionModulus) {
  // Statics of the rig: supports at 0 and L carry P/2 each; the loading rollers at
  // (L - L_i)/2 and (L + L_i)/2 push P/2 each. The moment at mid-span, summed from the left:
  // M = (P/2)(L/2) - (P/2)(L/2 - (L - L_i)/2); the outer fibre's stress 6M / (b d^2).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.1, 1.0);
  for (int k = 0; k < 20; ++k) {
    const double P = 1e3 * u(rng), L = 0.04 * u(rng) + 0.01, Li = L * u(rng) * 0.9;
    const double b = 0.004 * u(rng), d = 0.003 * u(rng);
    const double M = 0.5 * P * 0.5 * L - 0.5 * P * (0.5 * L - 0.5 * (L - Li));
    EXPECT_NEAR(four_point_flexural_strength(P, L, Li, b, d), 6.0 * M / (b * d * d),
                1e-12 * 6.0 * M / (b * d * d));
  }
  // ASTM C1161's quarter-point form: 3 P L / (4 b d^2).
  EXPECT_DOUBLE_EQ(four_point_flexural_strength(1000.0, 0.04, 0.02, 0.004, 0.003),
                   3.0 * 1000.0 * 0.04 / (4.0 * 0.004 * 0.003 * 0.003));
}

TEST(SingleEdgeNotchedBeam, AShallowNotchIsTheEdgeCrackInTheBendingStress) {
  // a << W: K = 1.1215 sigma sqrt(pi a), sigma = 3 P S / (2 B W^2) at the notch root.
  const double P = 100.0, S = 0.016, B = 0.003, W = 0.004;
  for (double alpha : {1e-5, 1e-4}) {
    const double a = alpha * W;
    const double edge = 1.1215 * 3.0 * P * S / (2.0 * B * W * W) * std::sqrt(M_PI * a);
    EXPECT_NEAR(senb_stress_intensity(P, S, B, W, a) / edge, 1.0, 2e-3) << alpha;
  }
}

TEST(SingleEdgeNotchedBeam, ADeepNotchIsTheLigamentInPureBending) {
  // W - a = b << W: K = 3.975 M / (B b^1.5) (Tada, Paris and Irwin), M = P S / 4.
  const double P = 100.0, S = 0.016, B = 0.003, W = 0.004;
  for (double ligament : {1e-4, 1e-5}) {
    const double b = ligament * W;
    const double deep = 3.975 * (P * S / 4.0) / (B * std::pow(b, 1.5));
    EXPECT_NEAR(senb_stress_intensity(P, S, B, W, W - b) / deep, 1.0, 3e-3) << ligament;
  }
  EXPECT_THROW((void)senb_geometry_factor(1.0), std::invalid_argument);
  EXPECT_THROW((void)senb_geometry_factor(0.0), std::invalid_argument);
}

TEST(EdgeNotchedStripInTension, AShallowNotchIsTheEdgeCrackInTheRemoteStress) {
  // a << W: K = 1.1215 sigma sqrt(pi a), sigma = N / (B W).
  const double N = 100.0, B = 0.003, W = 0.004;
  for (double alpha : {1e-5, 1e-4}) {
    const double a = alpha * W;
    const double edge = 1.1215 * N / (B * W) * std::sqrt(M_PI * a);
    EXPECT_NEAR(edge_notch_tension_stress_intensity(N, B, W, a) / edge, 1.0, 2e-3) << alpha;
  }
}

TEST(EdgeNotchedStripInTension, ADeepNotchIsItsLigamentUnderTheForceAndItsMomentAboutIt) {
  // W - a = b << W: the ligament carries N and the moment N (W - b) / 2 of the force on the
  // strip's centre line about the ligament's; the moment dominates, K -> 3.975 M / (B b^1.5)
  // (Tada, Paris and Irwin's deep crack in bending, as the notched beam's test above).
  const double N = 100.0, B = 0.003, W = 0.004;
  for (double ligament : {1e-4, 1e-5}) {
    const double b = ligament * W;
    const double deep = 3.975 * (N * 0.5 * (W - b)) / (B * std::pow(b, 1.5));
    EXPECT_NEAR(edge_notch_tension_stress_intensity(N, B, W, W - b) / deep, 1.0, 5e-3) << ligament;
  }
  // Linear in the force, compression closing the crack as tension opens it.
  EXPECT_DOUBLE_EQ(edge_notch_tension_stress_intensity(-N, B, W, 0.5 * W),
                   -edge_notch_tension_stress_intensity(N, B, W, 0.5 * W));
  EXPECT_THROW((void)edge_notch_tension_stress_intensity(N, B, W, W), std::invalid_argument);
  EXPECT_THROW((void)edge_notch_tension_stress_intensity(N, B, W, 0.0), std::invalid_argument);
}

TEST(HoneycombElasticity, MatchesABruteForceSumOverTheSixSprings) {
  // Energy per unit area of a uniform in-plane strain, summed spring by spring over the six
  // neighbours (each spring shared by two grains), against (lambda/2) tr^2 + mu eps:eps of
  // plane stress with the closed form's E and nu.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double spacing = 0.37e-3, thickness = 2e-3;
  const double area = std::sqrt(3.0) / 2.0 * spacing * spacing;
  for (int k = 0; k < 20; ++k) {
    const double kn = 1e8 * (1.5 + u(rng)), ks = kn * 0.5 * (1.0 + u(rng));
    Eigen::Matrix2d eps;
    eps << u(rng), u(rng), 0.0, u(rng);
    eps(1, 0) = eps(0, 1);
    eps *= 1e-4;
    double energy = 0.0;
    for (int i = 0; i < 6; ++i) {
      const double th = M_PI / 3.0 * i + 0.1;  // any rotation of the lattice: isotropic
      const Eigen::Vector2d n(std::cos(th), std::sin(th));
      const Eigen::Vector2d du = eps * (spacing * n);
      const double dn = n.dot(du);
      const Eigen::Vector2d dt = du - dn * n;
      energy += 0.25 * (kn * dn * dn + ks * dt.squaredNorm());
    }
    const HoneycombElasticity e = honeycomb_elasticity(kn, ks, thickness);
    const double E2 = e.young * thickness, nu = e.poisson;
    const double lambda = E2 * nu / (1.0 - nu * nu), mu = E2 / (2.0 * (1.0 + nu));
    const double tr = eps.trace();
    const double continuum = 0.5 * lambda * tr * tr + mu * (eps.array() * eps.array()).sum();
    EXPECT_NEAR(energy / area / continuum, 1.0, 1e-12);
    const BondSprings back = honeycomb_springs(e.young, e.poisson, thickness);
    EXPECT_NEAR(back.kn / kn, 1.0, 1e-12);
    EXPECT_NEAR(back.ks / ks, 1.0, 1e-12);
  }
  EXPECT_NEAR(honeycomb_elasticity(1.0, 0.0, 1.0).poisson, 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(honeycomb_elasticity(1.0, 1.0, 1.0).poisson, 0.0, 1e-15);
  EXPECT_THROW((void)honeycomb_springs(4e11, 0.4, 1e-3), std::invalid_argument);
}

TEST(AffineFit, RecoversARandomAffineFieldAndItsStrain) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix2d G;
  G << 1e-4, 3e-5, -2e-5, -4e-5;
  const Eigen::Vector2d c(1e-6, -2e-6);
  std::vector<Eigen::Vector2d> x, d;
  for (int i = 0; i < 50; ++i) {
    x.emplace_back(0.01 * u(rng), 0.02 * u(rng));
    d.push_back(c + G * x.back());
  }
  const AffineFit fit = fit_affine(x, d);
  EXPECT_NEAR((fit.gradient - G).norm(), 0.0, 1e-15);
  EXPECT_NEAR((fit.translation - c).norm(), 0.0, 1e-18);
  EXPECT_NEAR(fit.strain()(0, 1), 0.5e-5, 1e-16);
  EXPECT_LT(fit.rms_residual, 1e-18);
  // Noise that averages out leaves the field within its standard error.
  std::normal_distribution<double> noise(0.0, 1e-8);
  for (auto& v : d) v += Eigen::Vector2d(noise(rng), noise(rng));
  EXPECT_NEAR((fit_affine(x, d).gradient - G).norm(), 0.0, 1e-5 * 1e-1);
  const std::vector<Eigen::Vector2d> line = {{0, 0}, {1, 1}, {2, 2}};
  EXPECT_THROW((void)fit_affine(line, line), std::invalid_argument);
}
