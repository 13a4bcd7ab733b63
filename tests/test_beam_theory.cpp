// Closed-form load-deflection curves of the DCB, ENF and MMB tests (sec. 7, eqs 56-70 of
// Chen et al., seed 002). The curves are checked against fracture mechanics rather than
// against their own formulas: along every crack-growth branch the energy release rate
// G = P^2 / (2 B') dC/da, with dC/da by finite differences, must equal the toughness.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>

#include "validation/beam_theory.hpp"

using namespace cleave::physics;

namespace {

// The paper's beams (sec. 7): E = 120 GPa, nu = 0.2, B = 2 mm, 2h = 2 mm, r = 0.125 mm,
// G_Ic = 0.26 N/mm, G_IIc = 1.002 N/mm.
// By hand: I = B h^3 / 12 = 1.6667e-13 m^4, EI = 0.02 N m^2, B' = B - 2r = 1.75 mm.
// chi_I (eqs 57-58): E/G = 2.4, Gamma = 1.18 * 2.4 = 2.832, Gamma/(1+Gamma) = 0.73903967,
// 3 - 2 * 0.73903967^2 = 1.90764074, chi_I = sqrt(2.4 / 11 * 1.90764074) = 0.64514535263;
// chi_II = 0.42 chi_I = 0.27096104810 (both to 11 digits).
constexpr double kEI = 0.02, kBp = 1.75e-3, kChiI = 0.64514535263, kChiII = 0.27096104810;
constexpr double kH = 1e-3, kGIc = 260.0, kGIIc = 1002.0;
constexpr double kHalfSpan = 15.125e-3;

BeamTest dcb() {
  return {BeamTestKind::dcb, 120e9, 0.2, 2e-3, kH, 30e-3, 9e-3, 0.125e-3, kGIc, kGIIc};
}
BeamTest enf(double a0 = 9e-3) {
  return {BeamTestKind::enf, 120e9, 0.2, 2e-3, kH, kHalfSpan, a0, 0.125e-3, kGIc, kGIIc};
}
BeamTest mmb(double beta) {
  BeamTest t{BeamTestKind::mmb, 120e9, 0.2, 2e-3, kH, kHalfSpan, 9e-3, 0.125e-3, kGIc, kGIIc};
  t.C = mmb_lever_arm(beta, kHalfSpan);
  return t;
}

std::vector<CurvePoint> stage_points(const std::vector<CurvePoint>& c, int stage) {
  std::vector<CurvePoint> out;
  for (const CurvePoint& p : c)
    if (p.stage == stage) out.push_back(p);
  return out;
}

/// G = P^2 / (2B') dC/da at the interior points of a growth branch, with C = Delta / P read
/// off the neighbouring points of the branch (central differences).
std::vector<double> release_rates(const std::vector<CurvePoint>& branch) {
  std::vector<double> g;
  for (size_t i = 1; i + 1 < branch.size(); ++i) {
    const CurvePoint &a = branch[i - 1], &b = branch[i], &c = branch[i + 1];
    const double dC = c.delta / c.load - a.delta / a.load;
    g.push_back(b.load * b.load / (2 * kBp) * dC / (c.crack - a.crack));
  }
  return g;
}

/// analytic_load, with NaN for "no load" so that a missing value fails the comparison.
double load_at(const BeamTest& t, int stage, double delta) {
  return analytic_load(t, stage, delta).value_or(std::numeric_limits<double>::quiet_NaN());
}

/// Root of a monotone f on [lo, hi] by bisection.
double bisect(const std::function<double(double)>& f, double lo, double hi) {
  const bool rising = f(hi) > f(lo);
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    ((f(mid) > 0) == rising ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST(BeamTheory, CorrectionFactors) {
  EXPECT_NEAR(chi_I(120e9, 0.2), kChiI, 1e-8);
  EXPECT_NEAR(chi_II(120e9, 0.2), kChiII, 1e-8);
  // nu = 0 (E/G = 2, Gamma = 2.36): sqrt(2/11 (3 - 2 (2.36/3.36)^2)) = 0.62939
  EXPECT_NEAR(chi_I(1e9, 0.0), std::sqrt(2.0 / 11 * (3 - 2 * std::pow(2.36 / 3.36, 2))), 1e-12);
}

TEST(BeamTheory, MmbLeverArmsOfThePaper) {
  // Sec. 7.3 prints C = 32.590, 13.226 and 8.443 mm for beta = 20, 50 and 80 %.
  EXPECT_NEAR(mmb_lever_arm(0.2, kHalfSpan), 32.590e-3, 1e-6);
  EXPECT_NEAR(mmb_lever_arm(0.5, kHalfSpan), 13.226e-3, 1e-6);
  EXPECT_NEAR(mmb_lever_arm(0.8, kHalfSpan), 8.443e-3, 1e-6);
  EXPECT_THROW(mmb_lever_arm(0.05, kHalfSpan), std::domain_error);  // below 1/13
  EXPECT_THROW(mmb_lever_arm(1.0, kHalfSpan), std::domain_error);
  // The lever arm reproduces beta through G_II / G_I = 3 (C + L)^2 / (4 (3C - L)^2) (eq. 66
  // into the DCB and ENF release rates without corrections).
  for (double beta : {0.2, 0.5, 0.8}) {
    const double C = mmb_lever_arm(beta, kHalfSpan);
    const MmbLoads l = mmb_loads(1.0, C, kHalfSpan);
    const double gI = l.p_I * l.p_I, gII = 3.0 * l.p_II * l.p_II / 64.0;  // times a^2/(B'EI)
    EXPECT_NEAR(gII / (gI + gII), beta, 1e-12);
  }
  // Eq. 66 by hand for C = L: P_I = 2L/(4L) P = P/2, P_II = 2P.
  const MmbLoads l = mmb_loads(10.0, 0.1, 0.1);
  EXPECT_DOUBLE_EQ(l.p_I, 5.0);
  EXPECT_DOUBLE_EQ(l.p_II, 20.0);
}

TEST(BeamTheory, DcbPeakLoadOfThePaper) {
  // P_max = sqrt(B' E I G_Ic) / (a0 + chi_I h) = sqrt(1.75e-3 * 0.02 * 260) / 9.64514535e-3
  //       = 0.09539392 / 9.64514535e-3 = 9.890356 N.
  const double p_max = std::sqrt(kBp * kEI * kGIc) / (9e-3 + kChiI * kH);
  EXPECT_NEAR(p_max, 9.890356, 1e-5);
  const auto [lo, hi] = stage_range(dcb(), 1);
  EXPECT_EQ(lo, 0.0);
  // Delta at the peak: 2 P (a0 + chi h)^3 / (3EI) (eq. 59).
  EXPECT_NEAR(hi, 2 * p_max * std::pow(9e-3 + kChiI * kH, 3) / (3 * kEI), 1e-6 * hi);
  EXPECT_NEAR(load_at(dcb(), 1, hi), p_max, 1e-6 * p_max);
  // The highest load before the arms are split (stage III, a linear load line, climbs on).
  double top = 0;
  for (const CurvePoint& p : analytic_curve(dcb(), 10e-3, 200))
    if (p.stage < 3) top = std::max(top, p.load);
  EXPECT_NEAR(top, p_max, 1e-6 * p_max);
}

TEST(BeamTheory, DcbStagesFollowBeamTheoryAndGrowthKeepsGAtGIc) {
  const std::vector<CurvePoint> c = analytic_curve(dcb(), 20e-3, 2001);
  const auto s1 = stage_points(c, 1), s2 = stage_points(c, 2), s3 = stage_points(c, 3);
  ASSERT_EQ(s1.size(), 2001u);
  ASSERT_EQ(s2.size(), 2001u);
  ASSERT_EQ(s3.size(), 2001u);
  // Stage I and III slopes: the compliances 2 (a + chi h)^3 / (3EI) at a0 and at L (eqs 59, 61).
  const double c1 = 2 * std::pow(9e-3 + kChiI * kH, 3) / (3 * kEI);
  const double c3 = 2 * std::pow(30e-3 + kChiI * kH, 3) / (3 * kEI);
  for (const CurvePoint& p : s1) EXPECT_NEAR(p.delta, c1 * p.load, 1e-12 + 1e-9 * p.delta);
  for (const CurvePoint& p : s3) EXPECT_NEAR(p.delta, c3 * p.load, 1e-9 * p.delta);
  EXPECT_NEAR(s3.back().delta, 20e-3, 1e-12);  // the curve stops at delta_max
  // Stage II runs from a0 to L, along eq. 60: Delta = 2 (B'EIG)^(3/2) / (3 E I P^2) ...
  EXPECT_NEAR(s2.front().crack, 9e-3, 1e-15);
  EXPECT_NEAR(s2.back().crack, 30e-3, 1e-15);
  const double s = std::sqrt(kBp * kEI * kGIc);
  for (const CurvePoint& p : s2)
    EXPECT_NEAR(p.delta, 2 * s * s * s / (3 * kEI * p.load * p.load), 1e-9 * p.delta);
  // ... on which the compliance-derived energy release rate is G_Ic throughout.
  for (double g : release_rates(s2)) EXPECT_NEAR(g, kGIc, 1e-5 * kGIc);
  // Continuity: the stages meet at the same (Delta, P).
  EXPECT_NEAR(s1.back().delta, s2.front().delta, 1e-12 * s1.back().delta);
  EXPECT_NEAR(s1.back().load, s2.front().load, 1e-12 * s1.back().load);
  EXPECT_NEAR(s2.back().delta, s3.front().delta, 1e-12 * s2.back().delta);
  EXPECT_NEAR(s2.back().load, s3.front().load, 1e-12 * s2.back().load);
  const auto r1 = stage_range(dcb(), 1), r2 = stage_range(dcb(), 2), r3 = stage_range(dcb(), 3);
  EXPECT_NEAR(r1.second, r2.first, 1e-12 * r1.second);
  EXPECT_NEAR(r2.second, r3.first, 1e-9 * r2.second);
  EXPECT_TRUE(std::isinf(r3.second));
  EXPECT_NEAR(load_at(dcb(), 2, r2.second), load_at(dcb(), 3, r2.second), 1e-6);
  // analytic_load on stage II: P = sqrt(2 S^3 / (3 EI Delta)), and nothing outside the stage.
  const double mid = 0.5 * (r2.first + r2.second);
  EXPECT_NEAR(load_at(dcb(), 2, mid), std::sqrt(2 * s * s * s / (3 * kEI * mid)), 1e-9);
  EXPECT_FALSE(analytic_load(dcb(), 2, 0.5 * r2.first));
  EXPECT_FALSE(analytic_load(dcb(), 2, 1.5 * r2.second));
  EXPECT_FALSE(analytic_load(dcb(), 1, 1.01 * r1.second));
  EXPECT_NEAR(load_at(dcb(), 3, 0.1), 0.1 / c3, 1e-9);
  EXPECT_TRUE(std::isnan(stage_range(dcb(), 4).first));
}

TEST(BeamTheory, EnfStagesFollowBeamTheoryAndGrowthKeepsGAtGIIc) {
  const double L = kHalfSpan, a2_0 = 9e-3 + kChiII * kH;
  const double K = std::sqrt(64 * kBp * kEI * kGIIc / 3);  // P (a + chi_II h) while growing
  const std::vector<CurvePoint> c = analytic_curve(enf(), 3e-3, 2001);
  const auto s1 = stage_points(c, 1), s2 = stage_points(c, 2), s3 = stage_points(c, 3),
             s4 = stage_points(c, 4);
  ASSERT_EQ(s1.size(), 2001u);
  ASSERT_EQ(s2.size(), 2001u);
  ASSERT_EQ(s3.size(), 2001u);
  ASSERT_EQ(s4.size(), 2001u);
  // Stage I: C = (2L^3 + 3 (a0 + chi h)^3) / (96 EI) (eq. 63); stage IV: L^3 / (12 EI) (eq. 65).
  const double c1 = (2 * L * L * L + 3 * a2_0 * a2_0 * a2_0) / (96 * kEI);
  for (const CurvePoint& p : s1) EXPECT_NEAR(p.delta, c1 * p.load, 1e-12 + 1e-9 * p.delta);
  for (const CurvePoint& p : s4)
    EXPECT_NEAR(p.delta, L * L * L / (12 * kEI) * p.load, 1e-12 + 1e-9 * p.delta);
  // Growth: G_II = G_IIc on stages II and III alike.
  for (double g : release_rates(s2)) EXPECT_NEAR(g, kGIIc, 1e-5 * kGIIc);
  for (double g : release_rates(s3)) EXPECT_NEAR(g, kGIIc, 1e-5 * kGIIc);
  // Stages II and III meet at a + chi h = L, at P = K / L and Delta = 5 P L^3 / (96 EI).
  const double p_mid = K / L;
  EXPECT_NEAR(s2.back().crack + kChiII * kH, L, 1e-12);
  EXPECT_NEAR(s2.back().load, p_mid, 1e-9 * p_mid);
  EXPECT_NEAR(s2.back().delta, 5 * p_mid * L * L * L / (96 * kEI), 1e-9 * s2.back().delta);
  EXPECT_NEAR(s3.front().delta, s2.back().delta, 1e-12);
  EXPECT_NEAR(s3.front().load, s2.back().load, 1e-9);
  EXPECT_NEAR(s1.back().delta, s2.front().delta, 1e-15);
  // Stage III: P = K / b, Delta = K (8L^3 / b - 3 b^2) / (96 EI) with b = 2L - (a + chi h),
  // rising towards the split-beam line of stage IV, which it reaches only as b -> 0.
  for (const CurvePoint& p : s3) {
    const double b = 2 * L - p.crack - kChiII * kH;
    EXPECT_NEAR(p.load, K / b, 1e-9 * p.load);
    EXPECT_NEAR(p.delta, K * (8 * L * L * L / b - 3 * b * b) / (96 * kEI), 1e-9 * p.delta);
    EXPECT_LT(p.delta, L * L * L / (12 * kEI) * p.load);
  }
  EXPECT_NEAR(s3.back().delta, 3e-3, 1e-12);
  const auto r3 = stage_range(enf(), 3);
  EXPECT_NEAR(r3.first, s3.front().delta, 1e-12);
  EXPECT_TRUE(std::isinf(r3.second));
  const double d3 = 2e-3;  // b from Delta by bisection, then P = K / b
  const double b3 = bisect(
      [&](double b) { return K * (8 * L * L * L / b - 3 * b * b) / (96 * kEI) - d3; }, 1e-9, L);
  EXPECT_NEAR(load_at(enf(), 3, d3), K / b3, 1e-7 * K / b3);
  const double far = 1.0;  // at a deflection of 1 m, stage III is within 1e-6 of stage IV
  EXPECT_NEAR(load_at(enf(), 3, far), 12 * kEI * far / (L * L * L), 1e-6 * 12 * kEI / (L * L * L));
  // Stage IV is the split beam's reference line, never reached on the LEFM path.
  EXPECT_TRUE(std::isnan(stage_range(enf(), 4).first));
  EXPECT_FALSE(analytic_load(enf(), 4, 2e-3));
}

TEST(BeamTheory, EnfSnapBackIsNotReachableUnderDisplacementControl) {
  const double L = kHalfSpan, a2_0 = 9e-3 + kChiII * kH;
  const double K = std::sqrt(64 * kBp * kEI * kGIIc / 3);
  // Stage II in terms of the effective crack: Delta(a) = K (2L^3 / a + 3 a^2) / (96 EI), which
  // falls until a = L / 3^(1/3) = 10.487 mm and rises after; a0 + chi h = 9.271 mm is below.
  auto delta2 = [&](double a) { return K * (2 * L * L * L / a + 3 * a * a) / (96 * kEI); };
  const double a_min = L / std::cbrt(3.0);
  ASSERT_LT(a2_0, a_min);
  const double d_peak = delta2(a2_0), d_min = delta2(a_min);
  // The path itself goes through the snap-back: Delta decreases along stage II for a while.
  const auto s2 = stage_points(analytic_curve(enf(), 3e-3, 501), 2);
  EXPECT_LT(s2[10].delta, s2[0].delta);
  // Under displacement control stage I holds up to the peak, then the crack jumps at constant
  // Delta to the later point of stage II with the same Delta.
  const auto r1 = stage_range(enf(), 1), r2 = stage_range(enf(), 2);
  EXPECT_NEAR(r1.second, d_peak, 1e-9 * d_peak);
  EXPECT_NEAR(r2.first, d_peak, 1e-9 * d_peak);
  const double a_land = bisect([&](double a) { return delta2(a) - d_peak; }, a_min, L);
  EXPECT_GT(a_land, a_min);
  EXPECT_LT(a_land, L);
  const std::optional<double> p_land = analytic_load(enf(), 2, d_peak * (1 + 1e-9));
  ASSERT_TRUE(p_land);
  EXPECT_NEAR(*p_land, K / a_land, 1e-6 * K / a_land);
  // Inside the snap-back's deflection range only stage I answers.
  for (double f : {0.1, 0.5, 0.9}) {
    const double d = d_min + f * (d_peak - d_min);
    EXPECT_FALSE(analytic_load(enf(), 2, d)) << f;
    EXPECT_NEAR(load_at(enf(), 1, d), d * 96 * kEI / (2 * L * L * L + 3 * a2_0 * a2_0 * a2_0),
                1e-9);
  }
  // Reachable stage II points: P = K / a with delta2(a) = Delta on the rising side.
  const double d = 0.5 * (r2.first + r2.second);
  const double a = bisect([&](double x) { return delta2(x) - d; }, a_min, L);
  EXPECT_NEAR(load_at(enf(), 2, d), K / a, 1e-7 * K / a);
  // A longer initial crack (12 mm, effective 12.27 mm > 10.487 mm): no snap-back, stage II
  // starts at the peak with the peak load.
  const auto q1 = stage_range(enf(12e-3), 1), q2 = stage_range(enf(12e-3), 2);
  EXPECT_NEAR(q1.second, q2.first, 1e-12 * q1.second);
  EXPECT_NEAR(load_at(enf(12e-3), 2, q2.first), K / (12e-3 + kChiII * kH), 1e-6);
  // A short one (6 mm): the jump lands beyond mid-span, stage II is never reached.
  EXPECT_GT(delta2(6e-3 + kChiII * kH), delta2(L));
  EXPECT_TRUE(std::isnan(stage_range(enf(6e-3), 2).first));
  EXPECT_FALSE(analytic_load(enf(6e-3), 2, delta2(L)));
  EXPECT_NEAR(stage_range(enf(6e-3), 3).first, delta2(6e-3 + kChiII * kH), 1e-12);
}

namespace {

/// DCB and ENF compliances by hand (eqs 59, 63, 64) as functions of the physical crack.
double dcb_compliance(double a) {
  return 2 * std::pow(a + kChiI * kH, 3) / (3 * kEI);
}
double enf_compliance(double a) {
  const double L = kHalfSpan, a2 = a + kChiII * kH;
  if (a2 <= L) return (2 * L * L * L + 3 * a2 * a2 * a2) / (96 * kEI);
  return (8 * L * L * L - 3 * std::pow(2 * L - a2, 3)) / (96 * kEI);
}
double derivative(const std::function<double(double)>& f, double x, double h) {
  return (f(x + h) - f(x - h)) / (2 * h);
}

/// Complementary energy of the mode-I part of the MMB (both arms): cantilevers from the
/// effective root a + chi_I h, opened by p_I at the end and closed by f at mid-span, by
/// Simpson's rule on each side of the mid-span load.
double mode1_energy(double a, double p_I, double f) {
  const double L = kHalfSpan, root = a + kChiI * kH;
  auto m = [&](double x) { return p_I * x - f * std::max(x - L, 0.0); };
  auto simpson = [&](double lo, double hi) {
    if (hi <= lo) return 0.0;
    const int n = 64;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
      const double x = lo + (hi - lo) * i / n, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      sum += w * m(x) * m(x);
    }
    return sum * (hi - lo) / (3 * n);
  };
  return 2 * (simpson(0, std::min(root, L)) + simpson(L, root)) / (2 * kEI);
}

}  // namespace

TEST(BeamTheory, MmbGrowthMeetsTheLinearCriterionBeforeAndAfterMidSpan) {
  const double L = kHalfSpan;
  for (double beta : {0.2, 0.5, 0.8}) {
    const BeamTest t = mmb(beta);
    const MmbLoads unit = mmb_loads(1.0, t.C, L);
    const std::vector<CurvePoint> c = analytic_curve(t, 1.0, 401);
    const auto s1 = stage_points(c, 1), s2 = stage_points(c, 2), s3 = stage_points(c, 3);
    ASSERT_EQ(s2.size(), 401u) << beta;
    ASSERT_EQ(s3.size(), 401u) << beta;
    EXPECT_TRUE(stage_points(c, 4).empty());
    // Stage I: Delta = 2 P_I (a0 + chi_I h)^3 / (3EI) (eq. 68).
    for (const CurvePoint& p : s1)
      EXPECT_NEAR(p.delta, unit.p_I * p.load * dcb_compliance(9e-3), 1e-12 + 1e-9 * p.delta);
    // Stage II: G_I from the DCB compliance with P_I, G_II from the ENF compliance with P_II,
    // G_I / G_Ic + G_II / G_IIc = 1 (eq. 69); Delta from eq. 68.
    for (const CurvePoint& p : s2) {
      const double pI = unit.p_I * p.load, pII = unit.p_II * p.load;
      const double gI = pI * pI / (2 * kBp) * derivative(dcb_compliance, p.crack, 1e-8);
      const double gII = pII * pII / (2 * kBp) * derivative(enf_compliance, p.crack, 1e-8);
      EXPECT_NEAR(gI / kGIc + gII / kGIIc, 1.0, 1e-6) << beta << " a " << p.crack;
      EXPECT_NEAR(p.delta, pI * dcb_compliance(p.crack), 1e-9 * p.delta);
    }
    EXPECT_NEAR(s2.back().crack + kChiI * kH, L, 1e-12);
    // Stage III: the mid-span load rides on the upper arm; G_I from the mode-I part's energy,
    // Delta from Castigliano on it, G_II from the ENF compliance.
    for (const CurvePoint& p : s3) {
      const double pI = unit.p_I * p.load, pII = unit.p_II * p.load;
      if (std::abs(p.crack + kChiII * kH - L) < 1e-7) continue;  // the ENF kink
      const double gI =
          derivative([&](double a) { return mode1_energy(a, pI, pII / 2); }, p.crack, 1e-8) / kBp;
      const double gII = pII * pII / (2 * kBp) * derivative(enf_compliance, p.crack, 1e-8);
      EXPECT_NEAR(gI / kGIc + gII / kGIIc, 1.0, 1e-5) << beta << " a " << p.crack;
      const double opening =
          derivative([&](double q) { return mode1_energy(p.crack, q, pII / 2); }, pI, 1e-6 * pI);
      EXPECT_NEAR(p.delta, opening, 1e-7 * p.delta) << beta << " a " << p.crack;
    }
    // Continuity where the stages meet.
    EXPECT_NEAR(s1.back().delta, s2.front().delta, 1e-12 * s1.back().delta);
    EXPECT_NEAR(s1.back().load, s2.front().load, 1e-12 * s1.back().load);
    EXPECT_NEAR(s2.back().delta, s3.front().delta, 1e-12 * s2.back().delta);
    EXPECT_NEAR(s2.back().load, s3.front().load, 1e-12 * s2.back().load);
    const auto r2 = stage_range(t, 2), r3 = stage_range(t, 3);
    EXPECT_NEAR(r2.second, r3.first, 1e-9 * r2.second);
    EXPECT_NEAR(load_at(t, 2, r2.second), load_at(t, 3, r3.first), 1e-6);
    // The path ends where the mode-I root moment vanishes (beta 0.5, 0.8) or the mode-I root
    // reaches the far support (beta 0.2).
    const CurvePoint& end = s3.back();
    const double root = end.crack + kChiI * kH;
    const double moment = unit.p_I * root - unit.p_II / 2 * (root - L);
    if (beta == 0.2)
      EXPECT_NEAR(root, 2 * L, 1e-12);
    else
      EXPECT_NEAR(moment, 0.0, 1e-9);
    EXPECT_NEAR(r3.second, end.delta, 1e-9 * end.delta);  // Delta rises all along here
    EXPECT_FALSE(analytic_load(t, 3, 1.01 * r3.second));
  }
}

TEST(BeamTheory, InconsistentTestsAreRejected) {
  BeamTest t = dcb();
  t.a0 = 31e-3;  // past the end of the beam
  EXPECT_THROW(stage_range(t, 1), std::invalid_argument);
  t = mmb(0.5);
  t.C = 0.3 * kHalfSpan;  // P_I < 0: the lever closes the crack
  EXPECT_THROW(analytic_curve(t, 1e-3, 10), std::invalid_argument);
}

TEST(BeamTheory, SplitBeamsAreTheDcbArmsClampedAtLAndTheEnfsTwoStackedBeams) {
  // DCB stage III (eq. 61): two cantilevers L + chi_I h long, C = 2 (L + chi_I h)^3 / (3EI).
  // By hand: L + chi_I h = 30.64514535 mm, cubed 2.8779620e-5 m^3 -> C = 9.5932067e-4 m/N.
  EXPECT_EQ(split_stage(BeamTestKind::dcb), 3);
  EXPECT_NEAR(split_compliance(dcb()), 9.5932067e-4, 1e-11);
  EXPECT_DOUBLE_EQ(split_crack(dcb()), 30e-3);
  // ENF stage IV (eq. 65): two beams of EI each on a span 2L, C = (2L)^3 / (48 * 2EI).
  // By hand: 15.125 mm cubed = 3.4600801e-6 m^3 / (12 * 0.02) = 1.4417000e-5 m/N.
  EXPECT_EQ(split_stage(BeamTestKind::enf), 4);
  EXPECT_NEAR(split_compliance(enf()), 1.4417000e-5, 1e-12);
  EXPECT_DOUBLE_EQ(split_crack(enf()), 2 * kHalfSpan);
  // The MMB's path ends before its beam splits.
  EXPECT_EQ(split_stage(BeamTestKind::mmb), 0);
  EXPECT_TRUE(std::isnan(split_compliance(mmb(0.5))));
  // The ENF's stage III lies above the split line (stiffer) and meets it only in the limit.
  const auto c = analytic_curve(enf(), 3e-3, 50);
  for (const CurvePoint& p : c) {
    if (p.stage != 3) continue;
    EXPECT_GT(p.load, p.delta / split_compliance(enf()));
  }
}
