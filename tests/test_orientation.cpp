// Crystal orientations: the Bunge convention against matrices written out by hand, the symmetry
// groups, misorientation angles, and the sampled textures against their stated laws by
// chi-square goodness-of-fit tests (Mackenzie's cubic law, Morawiec's hexagonal and trigonal
// ones, themselves checked against a quadrature over rotation axes done here).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "geometry/orientation.hpp"
#include "geometry/rng.hpp"

using namespace cleave::geometry;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double deg = pi / 180.0;

// The matrices of the Bunge definition, as the convention states them.
Matrix3d Rz(double a) {
  Matrix3d m;
  m << std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a), 0, 0, 0, 1;
  return m;
}
Matrix3d Rx(double a) {
  Matrix3d m;
  m << 1, 0, 0, 0, std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a);
  return m;
}

bool same_rotation(const Quaterniond& a, const Quaterniond& b, double tol = 1e-12) {
  return std::abs(std::abs(a.normalized().dot(b.normalized())) - 1.0) < tol;
}

/// Pearson's statistic of `samples` against the density `f` on [lo, hi] (any normalisation) in
/// `bins` bins of equal expected count, from f's cumulative integral by Simpson's rule.
double chi_square(const std::vector<double>& samples, const std::function<double(double)>& f,
                  double lo, double hi, int bins) {
  const int steps = 20000;  // even
  const double h = (hi - lo) / steps;
  std::vector<double> cdf(steps / 2 + 1, 0.0);
  for (int i = 0; i < steps / 2; ++i) {
    const double a = lo + 2 * i * h;
    cdf[i + 1] = cdf[i] + h / 3.0 * (f(a) + 4.0 * f(a + h) + f(a + 2 * h));
  }
  const double total = cdf.back();
  // Bin index of x: its cumulative probability times bins.
  const auto prob = [&](double x) {
    const double t = std::clamp((x - lo) / (2 * h), 0.0, steps / 2.0 - 1e-9);
    const auto i = static_cast<std::size_t>(t);
    return (cdf[i] + (t - i) * (cdf[i + 1] - cdf[i])) / total;
  };
  std::vector<double> count(bins, 0.0);
  for (double x : samples) count[std::min(bins - 1, static_cast<int>(prob(x) * bins))] += 1.0;
  const double expected = static_cast<double>(samples.size()) / bins;
  double chi2 = 0.0;
  for (double c : count) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

/// The 99.9 % quantile of chi-square with k degrees of freedom, Wilson & Hilferty (1931):
/// k (1 - 2/(9k) + z sqrt(2/(9k)))^3 with z = 3.0902, the standard normal's 99.9 % quantile.
double chi2_quantile_999(int k) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + 3.0902 * std::sqrt(a), 3);
}

constexpr int kBins = 36;

std::vector<double> uniform_pair_angles(PointGroup group, int pairs, std::uint64_t seed) {
  std::vector<double> out;
  for (int i = 0; i < pairs; ++i)
    out.push_back(misorientation_angle(uniform_orientation(seed, 2 * i),
                                       uniform_orientation(seed, 2 * i + 1), group));
  return out;
}

}  // namespace

TEST(BungeEuler, OrientationIsTheTransposeOfThePassiveMatrix) {
  for (const auto& e : {std::array{10.0, 20.0, 30.0}, std::array{200.0, 95.0, 330.0},
                        std::array{359.0, 179.0, 1.0}, std::array{45.0, 54.7356, 0.0}}) {
    const double p1 = e[0] * deg, P = e[1] * deg, p2 = e[2] * deg;
    const Matrix3d g = Rz(p2) * Rx(P) * Rz(p1);
    EXPECT_LT((from_bunge(p1, P, p2).toRotationMatrix() - g.transpose()).norm(), 1e-14);
  }
}

TEST(BungeEuler, SingleAnglesTurnTheCrystalAxesAsDerivedByHand) {
  // phi1 = 90 deg: g = Rz(90) has rows (0 1 0), (-1 0 0), (0 0 1): crystal x is specimen y,
  // crystal y is specimen -x.
  const Quaterniond a = from_bunge(90 * deg, 0, 0);
  EXPECT_LT((a * Vector3d::UnitX() - Vector3d::UnitY()).norm(), 1e-15);
  EXPECT_LT((a * Vector3d::UnitY() + Vector3d::UnitX()).norm(), 1e-15);
  // Phi = 90 deg: g = Rx(90) has rows (1 0 0), (0 0 1), (0 -1 0): crystal y is specimen z,
  // crystal z is specimen -y.
  const Quaterniond b = from_bunge(0, 90 * deg, 0);
  EXPECT_LT((b * Vector3d::UnitY() - Vector3d::UnitZ()).norm(), 1e-15);
  EXPECT_LT((b * Vector3d::UnitZ() + Vector3d::UnitY()).norm(), 1e-15);
  // (90, 90, 0): crystal z is g's third row, Rx(90)'s (0 -1 0) turned by Rz(90):
  // (sin phi1 sin Phi, -cos phi1 sin Phi, cos Phi) = (1, 0, 0).
  EXPECT_LT((from_bunge(90 * deg, 90 * deg, 0) * Vector3d::UnitZ() - Vector3d::UnitX()).norm(),
            1e-15);
  // Canonical form.
  EXPECT_GE(from_bunge(350 * deg, 170 * deg, 350 * deg).w(), 0.0);
}

TEST(BungeEuler, AnglesRoundTripInTheirRanges) {
  SplitMix64 rng(7);
  for (int i = 0; i < 2000; ++i) {
    const double p1 = 2 * pi * rng.uniform(), P = pi * rng.uniform(), p2 = 2 * pi * rng.uniform();
    const auto e = to_bunge(from_bunge(p1, P, p2));
    EXPECT_NEAR(e[0], p1, 1e-9);
    EXPECT_NEAR(e[1], P, 1e-9);
    EXPECT_NEAR(e[2], p2, 1e-9);
  }
  for (int i = 0; i < 2000; ++i) {
    const Quaterniond q = uniform_orientation(11, i);
    const auto e = to_bunge(q);
    ASSERT_GE(e[0], 0.0);
    ASSERT_LT(e[0], 2 * pi);
    ASSERT_GE(e[1], 0.0);
    ASSERT_LE(e[1], pi);
    ASSERT_GE(e[2], 0.0);
    ASSERT_LT(e[2], 2 * pi);
    EXPECT_TRUE(same_rotation(from_bunge(e[0], e[1], e[2]), q, 1e-13));
  }
}

TEST(BungeEuler, GimbalLockKeepsTheDefinedCombination) {
  // Phi = 0: g = Rz(phi2 + phi1), only the sum is defined; Phi = pi: g = Rz(phi2) Rx(pi) Rz(phi1)
  // = Rx(pi) Rz(phi1 - phi2), only the difference is.
  const double p1 = 250 * deg, p2 = 170 * deg;
  auto e = to_bunge(from_bunge(p1, 0.0, p2));
  EXPECT_NEAR(e[0], p1 + p2 - 2 * pi, 1e-12);
  EXPECT_EQ(e[1], 0.0);
  EXPECT_EQ(e[2], 0.0);
  e = to_bunge(from_bunge(p1, pi, p2));
  EXPECT_NEAR(e[0], p1 - p2, 1e-12);
  EXPECT_EQ(e[1], pi);
  EXPECT_EQ(e[2], 0.0);
  const Matrix3d g = Rx(pi) * Rz(p1 - p2);
  EXPECT_LT((from_bunge(e[0], e[1], e[2]).toRotationMatrix() - g.transpose()).norm(), 1e-14);
  // The identity.
  e = to_bunge(Quaterniond::Identity());
  EXPECT_EQ(e[0], 0.0);
  EXPECT_EQ(e[1], 0.0);
  EXPECT_EQ(e[2], 0.0);
}

TEST(SymmetryOperators, FormAGroupOfTheCrystalsOrder) {
  for (const auto& entry : {std::pair{PointGroup::cubic, 24},
                             {PointGroup::hexagonal, 12},
                             {PointGroup::trigonal, 6},
                             {PointGroup::orthorhombic, 4},
                             {PointGroup::none, 1}}) {
    // Named copies, not a structured binding: clang 14 refuses a binding in a lambda.
    const PointGroup group = entry.first;
    const int order = entry.second;
    const auto ops = symmetry_operators(group);
    ASSERT_EQ(static_cast<int>(ops.size()), order) << to_string(group);
    const auto index_of = [&](const Quaterniond& q) {
      int found = -1;
      for (int k = 0; k < order; ++k)
        if (same_rotation(ops[k], q, 1e-12)) found = k;
      return found;
    };
    for (int i = 0; i < order; ++i) {
      EXPECT_EQ(index_of(ops[i]), i) << "duplicate in " << to_string(group);
      EXPECT_GE(index_of(ops[i].conjugate()), 0);
      for (int j = 0; j < order; ++j) EXPECT_GE(index_of(ops[i] * ops[j]), 0);
    }
  }
}

TEST(SymmetryOperators, LeaveTheDefiningDirectionsInvariant) {
  const auto maps_set_onto_itself = [](PointGroup group, const std::vector<Vector3d>& set) {
    for (const auto& s : symmetry_operators(group))
      for (const auto& v : set) {
        bool hit = false;
        for (const auto& w : set) hit = hit || (s * v - w).norm() < 1e-12;
        if (!hit) return false;
      }
    return true;
  };
  std::vector<Vector3d> cube;
  for (int a = 0; a < 3; ++a) {
    cube.push_back(Vector3d::Unit(a));
    cube.push_back(-Vector3d::Unit(a));
  }
  EXPECT_TRUE(maps_set_onto_itself(PointGroup::cubic, cube));
  const std::vector<Vector3d> c_axis{Vector3d::UnitZ(), -Vector3d::UnitZ()};
  std::vector<Vector3d> six_a, three_a;
  for (int k = 0; k < 6; ++k) six_a.emplace_back(std::cos(k * pi / 3), std::sin(k * pi / 3), 0);
  for (int k = 0; k < 3; ++k)
    three_a.emplace_back(std::cos(k * 2 * pi / 3), std::sin(k * 2 * pi / 3), 0);
  EXPECT_TRUE(maps_set_onto_itself(PointGroup::hexagonal, c_axis));
  EXPECT_TRUE(maps_set_onto_itself(PointGroup::hexagonal, six_a));
  EXPECT_TRUE(maps_set_onto_itself(PointGroup::trigonal, c_axis));
  EXPECT_TRUE(maps_set_onto_itself(PointGroup::trigonal, three_a));
  // Trigonal is not hexagonal: the 60 deg turn about c takes a1 off the three a axes.
  EXPECT_FALSE(maps_set_onto_itself(PointGroup::hexagonal, three_a));
}

TEST(MisorientationAngle, IsTheSmallestAngleOverBothGrainsSymmetry) {
  for (auto group : {PointGroup::cubic, PointGroup::hexagonal, PointGroup::trigonal,
                     PointGroup::orthorhombic}) {
    const auto ops = symmetry_operators(group);
    for (int i = 0; i < 200; ++i) {
      const Quaterniond q1 = uniform_orientation(3, 2 * i), q2 = uniform_orientation(3, 2 * i + 1);
      // Brute force: every pair of equivalent orientations q1 S_a, q2 S_b.
      double best = pi;
      for (const auto& a : ops)
        for (const auto& b : ops)
          best = std::min(
              best, 2 * std::acos(std::min(1.0, std::abs(((q1 * a).conjugate() * (q2 * b)).w()))));
      const double w = misorientation_angle(q1, q2, group);
      EXPECT_NEAR(w, best, 1e-7);
      EXPECT_NEAR(misorientation_angle(q2, q1, group), w, 1e-12);
      const Quaterniond r = uniform_orientation(5, i);  // a common specimen rotation
      EXPECT_NEAR(misorientation_angle(r * q1, r * q2, group), w, 1e-12);
      EXPECT_LE(w, max_misorientation_angle(group) + 1e-12);
      EXPECT_NEAR(misorientation_angle(q1, q1 * ops[i % ops.size()], group), 0.0, 1e-7);
    }
  }
}

TEST(MisorientationDensity, LargestAnglesAreThePublishedOnes) {
  // Mackenzie (1958): 62.80 deg for cubic; Grimmer (1979) / Morawiec (1995): 93.84 deg for 622,
  // 104.48 deg for 32.
  EXPECT_NEAR(max_misorientation_angle(PointGroup::cubic) / deg, 62.80, 0.005);
  EXPECT_NEAR(max_misorientation_angle(PointGroup::hexagonal) / deg, 93.84, 0.005);
  EXPECT_NEAR(max_misorientation_angle(PointGroup::trigonal) / deg, 104.48, 0.005);
  // 222: the fundamental zone is the cube |r_i| <= 1, its corner tan(w/2) = sqrt(3): 120 deg.
  EXPECT_NEAR(max_misorientation_angle(PointGroup::orthorhombic) / deg, 120.0, 1e-9);
}

TEST(MisorientationDensity, CubicMeanIsMackenziesPublishedValue) {
  // Mackenzie (1958): the mean misorientation angle of random cubes is 40.74 deg.
  const double top = max_misorientation_angle(PointGroup::cubic);
  const int n = 20000;
  double mean = 0.0;
  for (int i = 0; i < n; ++i) {
    const double w = (i + 0.5) * top / n;
    mean += w * misorientation_angle_density_cubic(w) * top / n;
  }
  EXPECT_NEAR(mean / deg, 40.74, 0.005);
}

TEST(MisorientationDensity, MackenziesCubicFormIsMorawiecsCubicCase) {
  for (double w = 0.0; w < 64 * deg; w += 0.05 * deg)
    EXPECT_NEAR(misorientation_angle_density_cubic(w),
                misorientation_angle_density(w, PointGroup::cubic), 1e-12)
        << w / deg;
}

TEST(MisorientationDensity, IntegratesToOneAndVanishesAtTheLargestAngle) {
  for (auto group :
       {PointGroup::cubic, PointGroup::hexagonal, PointGroup::trigonal, PointGroup::orthorhombic,
        PointGroup::none}) {
    const double top = max_misorientation_angle(group);
    const int n = 20000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
      const double a = top * i / n, h = top / n;
      sum += h / 6 *
             (misorientation_angle_density(a, group) +
              4 * misorientation_angle_density(a + h / 2, group) +
              misorientation_angle_density(a + h, group));
    }
    EXPECT_NEAR(sum, 1.0, 1e-6) << to_string(group);
    if (group != PointGroup::none) {
      EXPECT_LT(misorientation_angle_density(top * (1 - 1e-9), group), 1e-3) << to_string(group);
    }
  }
}

TEST(MisorientationDensity, ClosedFormsMatchAQuadratureOverRotationAxes) {
  // For a rotation angle omega, the density is (N / pi)(1 - cos omega) times the fraction of axes
  // n for which the rotation (n, omega) is already the smallest of its equivalents. The axes are
  // a Fibonacci lattice on the sphere (its error here is about 0.1 % of the peak).
  const int axes = 24000;
  std::vector<Vector3d> n(axes);
  for (int i = 0; i < axes; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / axes, r = std::sqrt(1 - z * z);
    const double phi = i * pi * (3.0 - std::sqrt(5.0));
    n[i] = Vector3d(r * std::cos(phi), r * std::sin(phi), z);
  }
  for (auto group : {PointGroup::cubic, PointGroup::hexagonal, PointGroup::trigonal,
                     PointGroup::orthorhombic}) {
    const auto ops = symmetry_operators(group);
    const double top = max_misorientation_angle(group);
    double worst = 0.0, peak = 0.0;
    for (int s = 1; s < 60; ++s) {
      const double w = top * s / 60.0;
      int inside = 0;
      for (const auto& axis : n) {
        const Quaterniond q(Eigen::AngleAxisd(w, axis));
        bool smallest = true;
        for (const auto& op : ops) smallest = smallest && std::abs((q * op).w()) <= q.w() + 1e-12;
        inside += smallest;
      }
      const double quadrature = ops.size() / pi * (1 - std::cos(w)) * inside / axes;
      const double closed = misorientation_angle_density(w, group);
      worst = std::max(worst, std::abs(quadrature - closed));
      peak = std::max(peak, closed);
    }
    EXPECT_LT(worst, 0.003 * peak) << to_string(group);
  }
}

TEST(UniformOrientation, PairMisorientationsFollowMackenziesCubicLaw) {
  const auto angles = uniform_pair_angles(PointGroup::cubic, 20000, 2026);
  const double chi2 = chi_square(angles, misorientation_angle_density_cubic, 0.0,
                                 max_misorientation_angle(PointGroup::cubic), kBins);
  EXPECT_LT(chi2, chi2_quantile_999(kBins - 1));
}

TEST(UniformOrientation, PairMisorientationsFollowTheHexagonalAndTrigonalLaws) {
  for (auto group : {PointGroup::hexagonal, PointGroup::trigonal, PointGroup::orthorhombic,
                     PointGroup::none}) {
    const auto angles = uniform_pair_angles(group, 20000, 2027);
    const double chi2 = chi_square(
        angles, [group](double w) { return misorientation_angle_density(w, group); }, 0.0,
        max_misorientation_angle(group), kBins);
    EXPECT_LT(chi2, chi2_quantile_999(kBins - 1)) << to_string(group);
  }
}

TEST(UniformOrientation, AnglesToAFixedOrientationFollowTheSameLaws) {
  // q1^-1 q2 is uniform when q2 is, whatever q1: the angles of single orientations to the
  // identity follow the same laws as those of pairs.
  for (auto group : {PointGroup::cubic, PointGroup::hexagonal}) {
    std::vector<double> angles;
    for (int i = 0; i < 20000; ++i)
      angles.push_back(
          misorientation_angle(Quaterniond::Identity(), uniform_orientation(31, i), group));
    const double chi2 = chi_square(
        angles, [group](double w) { return misorientation_angle_density(w, group); }, 0.0,
        max_misorientation_angle(group), kBins);
    EXPECT_LT(chi2, chi2_quantile_999(kBins - 1)) << to_string(group);
  }
}

TEST(UniformOrientation, UniformlyDrawnEulerAnglesFailTheSameTest) {
  // Euler angles drawn uniformly over their box are not uniform over SO(3) (the Haar measure has
  // sin(Phi) dPhi). Their angles to the identity must fail the test above. (Angles between two
  // such orientations are not a sharp probe: the product of two draws is already close to
  // uniform after the cubic reduction, chi-square about 50 for 20,000 pairs.)
  SplitMix64 rng(2026);
  const auto draw = [&] {
    return from_bunge(2 * pi * rng.uniform(), pi * rng.uniform(), 2 * pi * rng.uniform());
  };
  for (auto group : {PointGroup::cubic, PointGroup::hexagonal}) {
    std::vector<double> angles;
    for (int i = 0; i < 20000; ++i)
      angles.push_back(misorientation_angle(Quaterniond::Identity(), draw(), group));
    const double chi2 = chi_square(
        angles, [group](double w) { return misorientation_angle_density(w, group); }, 0.0,
        max_misorientation_angle(group), kBins);
    EXPECT_GT(chi2, chi2_quantile_999(kBins - 1)) << to_string(group);
  }
}

TEST(UniformOrientation, EachGrainHasItsOwnStream) {
  EXPECT_TRUE(uniform_orientation(9, 17).coeffs() == uniform_orientation(9, 17).coeffs());
  EXPECT_FALSE(uniform_orientation(9, 17).coeffs() == uniform_orientation(9, 18).coeffs());
  EXPECT_FALSE(uniform_orientation(9, 17).coeffs() == uniform_orientation(10, 17).coeffs());
}

TEST(PreferredOrientation, ZeroSpreadGivesExactlyTheTarget) {
  const Quaterniond q0 = from_bunge(30 * deg, 40 * deg, 50 * deg);
  for (int g = 0; g < 10; ++g)
    EXPECT_TRUE(preferred_orientation(1, g, q0, 0.0).coeffs() == q0.coeffs());
  EXPECT_THROW(preferred_orientation(1, 0, q0, -0.1), std::invalid_argument);
}

TEST(PreferredOrientation, AnglesToTheTargetFollowTheGaussianLaw) {
  // Stated law: density of omega ~ (1 - cos omega) exp(-omega^2 / (2 spread^2)) on [0, pi],
  // axes uniform. 0.2 and 0.9 rad exercise one sampler, 1.5 the other.
  const Quaterniond q0 = from_bunge(100 * deg, 30 * deg, 200 * deg);
  for (double spread : {0.2, 0.9, 1.5}) {
    std::vector<double> angles;
    Vector3d axis_sum = Vector3d::Zero();
    const int n = 20000;
    for (int g = 0; g < n; ++g) {
      const Quaterniond q = preferred_orientation(4, g, q0, spread);
      const Quaterniond r = q * q0.conjugate();
      angles.push_back(rotation_angle(r));
      axis_sum += (r.w() >= 0 ? 1.0 : -1.0) * r.vec().normalized();
    }
    const auto law = [spread](double w) {
      return (1 - std::cos(w)) * std::exp(-w * w / (2 * spread * spread));
    };
    EXPECT_LT(chi_square(angles, law, 0.0, pi, kBins), chi2_quantile_999(kBins - 1)) << spread;
    // Uniform axes: each component of the mean axis has standard deviation 1 / sqrt(3 n).
    EXPECT_LT(axis_sum.norm() / n, 4.0 / std::sqrt(n)) << spread;
  }
}

TEST(PreferredOrientation, ALawOfTheWrongWidthFailsTheSameTest) {
  const Quaterniond q0 = Quaterniond::Identity();
  std::vector<double> angles;
  for (int g = 0; g < 20000; ++g)
    angles.push_back(rotation_angle(preferred_orientation(4, g, q0, 0.2)));
  const auto law = [](double w) {
    return (1 - std::cos(w)) * std::exp(-w * w / (2 * 0.21 * 0.21));
  };
  EXPECT_GT(chi_square(angles, law, 0.0, pi, kBins), chi2_quantile_999(kBins - 1));
}

TEST(FibreOrientation, ZeroSpreadPutsTheCrystalDirectionOnTheAxisWithUniformSpin) {
  const Vector3d d(1, 1, 1), a(1, 2, -0.5);
  const Vector3d an = a.normalized(), e1 = an.unitOrthogonal(), e2 = an.cross(e1);
  // A crystal direction normal to d; its azimuth about the axis is the spin.
  const Vector3d p = Vector3d(1, -1, 0).normalized();
  std::vector<double> azimuth;
  for (int g = 0; g < 20000; ++g) {
    const Quaterniond q = fibre_orientation(8, g, d, a, 0.0);
    ASSERT_LT((q * d.normalized() - an).norm(), 1e-14);
    const Vector3d s = q * p;
    azimuth.push_back(std::atan2(s.dot(e2), s.dot(e1)) + pi);
  }
  EXPECT_LT(chi_square(
                azimuth, [](double) { return 1.0; }, 0.0, 2 * pi, kBins),
            chi2_quantile_999(kBins - 1));
}

TEST(FibreOrientation, TiltFromTheAxisFollowsTheGaussianLawOnTheSphere) {
  // Stated law: density of theta ~ sin(theta) exp(-theta^2 / (2 spread^2)) on [0, pi].
  const Vector3d d(0, 0, 1), a(1, 1, 0);
  for (double spread : {0.15, 0.9, 1.3}) {
    std::vector<double> tilt;
    Vector3d dir_sum = Vector3d::Zero();
    const int n = 20000;
    for (int g = 0; g < n; ++g) {
      const Vector3d v = fibre_orientation(12, g, d, a, spread) * d;
      tilt.push_back(std::acos(std::clamp(v.dot(a.normalized()), -1.0, 1.0)));
      dir_sum += v - v.dot(a.normalized()) * a.normalized();
    }
    const auto law = [spread](double t) {
      return std::sin(t) * std::exp(-t * t / (2 * spread * spread));
    };
    EXPECT_LT(chi_square(tilt, law, 0.0, pi, kBins), chi2_quantile_999(kBins - 1)) << spread;
    // Uniform azimuth of the tilt: the mean of the tilted direction's normal part is ~0.
    EXPECT_LT(dir_sum.norm() / n, 4.0 / std::sqrt(n)) << spread;
  }
}

TEST(FibreOrientation, ACrystalDirectionOppositeToTheAxisIsTurnedOntoIt) {
  const Vector3d a(0.3, -0.2, 0.9);
  for (int g = 0; g < 100; ++g) {
    const Quaterniond q = fibre_orientation(2, g, -a, a, 0.0);
    EXPECT_LT((q * (-a).normalized() - a.normalized()).norm(), 1e-14);
  }
  EXPECT_THROW(fibre_orientation(2, 0, Vector3d::Zero(), a, 0.1), std::invalid_argument);
}

TEST(PointGroupNames, RoundTripAndUnknownNamesListTheChoices) {
  for (auto g : {PointGroup::cubic, PointGroup::hexagonal, PointGroup::trigonal,
                 PointGroup::orthorhombic, PointGroup::none})
    EXPECT_EQ(parse_point_group(to_string(g)), g);
  try {
    parse_point_group("hcp");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cubic, hexagonal, trigonal, orthorhombic or none"), std::string::npos);
  }
}
