// The particle-based cohesive crack model of secs 2-3 (eqs 7-33) and the Hertz-Mindlin contact
// law of sec. 4 (eqs 34-45) of Chen et al. (seed 002). Expected values are worked out by hand
// from the formulas (the arithmetic is in the comments), never read off the code.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "physics/bonds/cohesive_law.hpp"
#include "physics/lattice/hertz_mindlin.hpp"

using namespace cleave::physics;

namespace {

// The paper's DCB material (sec. 7): E = 120 GPa, nu = 0.2, r = 0.125 mm, sigma_c = 70 MPa,
// G_c = 0.26 N/mm. Eq. 3: k_n = 2 E r / (5 (1 - 2 nu)) = 3e7 / 3 = 1e7 N/m,
// k_s = 2 E r (1 - 4 nu) / (5 (1 - 2 nu)(1 + nu)) = 3e7 * 0.2 / 3.6 = 1.6667e6 N/m;
// first-neighbour area A = pi r^2 / 4 (text after eq. 9).
const double kR = 0.125e-3;
const CohesiveParams kParams{1e7, 6e6 / 3.6, M_PI* kR* kR / 4, 70e6, 260.0};
const CohesiveLimits kLim = cohesive_limits(kParams);

/// Traction along the radial direction u = (cos t, sin t) of the (<dn>, ds) plane.
double radial(const CohesiveTraction& t, double theta) {
  return t.tn * std::cos(theta) + t.ts * std::sin(theta);
}

struct PathWork {
  double total = 0;      ///< work over the whole path
  double softening = 0;  ///< work over the steps that start in the cohesive phase
};

/// Monotonic loading along direction theta from rho = 0 to rho_end in n steps; trapezoidal
/// work of the traction on the separation.
PathWork radial_work(double theta, double rho_end, int n) {
  CohesiveState s;
  PathWork w;
  const double c = std::cos(theta), sn = std::sin(theta);
  CohesiveTraction prev = cohesive_traction(kParams, kLim, 0.0, 0.0, s);
  for (int i = 1; i <= n; ++i) {
    const LinkPhase before = s.phase;
    const double rho = rho_end * i / n, h = rho_end / n;
    const CohesiveTraction t = cohesive_traction(kParams, kLim, rho * c, rho * sn, s);
    const double dw = 0.5 * (radial(prev, theta) + radial(t, theta)) * h;
    w.total += dw;
    if (before != LinkPhase::connective) w.softening += dw;
    prev = t;
  }
  return w;
}

}  // namespace

TEST(CohesiveLimits, SeparationsOfThePapersDcbMaterial) {
  // Eq. 12: dn0 = A sigma_c / k_n = 1.2271846e-8 * 7e7 / 1e7 = 8.5902924e-8 m.
  EXPECT_NEAR(kLim.dn0, 8.5902924e-8, 1e-6 * 8.59e-8);
  // Eq. 13: ds0 = A sigma_c / k_s = 0.85902924 / 1.6666667e6 = 5.1541754e-7 m.
  EXPECT_NEAR(kLim.ds0, 5.1541754e-7, 1e-6 * 5.15e-7);
  // Eq. 32: d0 = min = dn0 (k_s < k_n).
  EXPECT_DOUBLE_EQ(kLim.d0, kLim.dn0);
  // dc = d0 + 2 G_c / sigma_c = 8.5902924e-8 + 520 / 7e7 = 7.5144743e-6 m.
  EXPECT_NEAR(kLim.dc, 7.5144743e-6, 1e-6 * 7.51e-6);
  // lambda_cr = d0 / dc = 8.5902924e-8 / 7.5144743e-6 = 0.011431661.
  EXPECT_NEAR(kLim.lambda_cr, 0.011431661, 1e-8);
}

TEST(CohesiveLaw, ConnectiveStageIsLinearAndReversible) {
  CohesiveState s;
  const double A = kParams.area, d0 = kLim.d0;
  // A loop inside the initiation circle, out and back: eqs 7-11 at every point.
  const std::array<std::array<double, 2>, 6> path{{{0.3 * d0, 0.0},
                                                   {0.5 * d0, 0.6 * d0},
                                                   {-2.0 * d0, 0.9 * d0},
                                                   {0.0, 0.99 * d0},
                                                   {0.5 * d0, 0.6 * d0},
                                                   {0.0, 0.0}}};
  for (const auto& [dn, ds] : path) {
    const CohesiveTraction t = cohesive_traction(kParams, kLim, dn, ds, s);
    EXPECT_DOUBLE_EQ(t.tn, kParams.kn * dn / A);
    EXPECT_DOUBLE_EQ(t.ts, kParams.ks * ds / A);
    EXPECT_EQ(s.phase, LinkPhase::connective);
  }
  // psi_max (eq. 33) is the largest psi = |(<dn>, ds)| / d0 seen: 0.99 (the compressed point
  // has psi = 0.9: compression does not count).
  EXPECT_NEAR(s.psi_max, 0.99, 1e-12);
  EXPECT_EQ(damage(kLim, s), 0.0);
}

TEST(CohesiveLaw, InitiationHappensExactlyAtPsiOne) {
  const double theta = M_PI / 5, d0 = kLim.d0;
  {
    CohesiveState s;  // just inside the circle: still connective
    const double rho = (1.0 - 1e-9) * d0;
    const CohesiveTraction t =
        cohesive_traction(kParams, kLim, rho * std::cos(theta), rho * std::sin(theta), s);
    EXPECT_EQ(s.phase, LinkPhase::connective);
    EXPECT_DOUBLE_EQ(t.tn, kParams.kn * rho * std::cos(theta) / kParams.area);
  }
  {
    CohesiveState s;  // just outside: cohesive in the same call, with the cohesive traction
    const double rho = (1.0 + 1e-9) * d0;
    const CohesiveTraction t =
        cohesive_traction(kParams, kLim, rho * std::cos(theta), rho * std::sin(theta), s);
    EXPECT_EQ(s.phase, LinkPhase::cohesive);
    // lambda = rho / dc = (1 + 1e-9) lambda_cr, so d ~ 1e-11 and r = 1: the effective traction
    // is sigma_c, pointing along the separation (eqs 24-26).
    EXPECT_NEAR(t.tn, kParams.sigma_c * std::cos(theta), 1e-6 * kParams.sigma_c);
    EXPECT_NEAR(t.ts, kParams.sigma_c * std::sin(theta), 1e-6 * kParams.sigma_c);
    EXPECT_NEAR(s.lambda_max, (1.0 + 1e-9) * kLim.lambda_cr, 1e-15);
    EXPECT_GT(s.psi_max, 1.0);
    EXPECT_NEAR(damage(kLim, s), 0.0, 1e-9);
  }
}

TEST(CohesiveLaw, SofteningBranchDissipatesGcForEveryModeMix) {
  // Pure mode I, pure mode II, and two mixtures (dn = ds tan 30 deg, and 70 deg from mode I).
  for (double theta : {0.0, M_PI / 2, M_PI / 2 - M_PI / 6, 70.0 * M_PI / 180}) {
    const int n = 4000000;
    const PathWork w = radial_work(theta, 1.0001 * kLim.dc, n);
    EXPECT_NEAR(w.softening, kParams.g_c, 1e-3 * kParams.g_c) << "theta " << theta;
    // Up to initiation the springs store (k_n cos^2 + k_s sin^2) d0^2 / (2A); for mode I that
    // is 1e7 * (8.5902924e-8)^2 / (2 * 1.2271846e-8) = 3.0066 N/m, for mode II a sixth of it.
    const double c = std::cos(theta), sn = std::sin(theta);
    const double elastic =
        (kParams.kn * c * c + kParams.ks * sn * sn) * kLim.d0 * kLim.d0 / (2 * kParams.area);
    EXPECT_NEAR(w.total, kParams.g_c + elastic, 1e-3 * elastic) << "theta " << theta;
  }
  EXPECT_NEAR(1e7 * 8.5902924e-8 * 8.5902924e-8 / (2 * 1.2271846e-8), 3.0066, 1e-4);
}

TEST(CohesiveLaw, UnloadingAndReloadingFollowTheSecantWithoutDissipation) {
  const double theta = M_PI / 6;
  const double c = std::cos(theta), sn = std::sin(theta);
  const double lambda_half = 0.5 * (kLim.lambda_cr + 1.0);
  const double rho_peak = lambda_half * kLim.dc;
  CohesiveState s;
  CohesiveTraction t;
  for (int i = 1; i <= 1000; ++i) {
    const double rho = rho_peak * i / 1000;
    t = cohesive_traction(kParams, kLim, rho * c, rho * sn, s);
  }
  const CohesiveTraction peak = t;
  // Eq. 15 at lambda_half: T = sigma_c (1 - lambda) / (1 - lambda_cr) = sigma_c / 2.
  EXPECT_NEAR(std::hypot(peak.tn, peak.ts), 0.5 * kParams.sigma_c, 1e-9 * kParams.sigma_c);
  const double d_peak = damage(kLim, s);
  EXPECT_NEAR(d_peak, 0.5, 1e-12);
  // Unload to the origin and reload, both in m steps; trapezoidal work over the closed cycle.
  const int m = 500;
  double work = 0.0, prev_t = radial(peak, theta);
  const double slope = prev_t / lambda_half;  // secant to the origin (eqs 23-24)
  for (int i = 1; i <= 2 * m; ++i) {
    const double frac = i <= m ? 1.0 - static_cast<double>(i) / m : static_cast<double>(i - m) / m;
    const double rho = frac * rho_peak;
    t = cohesive_traction(kParams, kLim, rho * c, rho * sn, s);
    const double tr = radial(t, theta);
    work += 0.5 * (prev_t + tr) * (i <= m ? -rho_peak / m : rho_peak / m);
    prev_t = tr;
    // T proportional to lambda on the way (T = sigma_c (1 - d) lambda / lambda_max).
    EXPECT_NEAR(tr, slope * frac * lambda_half, 1e-9 * kParams.sigma_c);
    EXPECT_NEAR(t.tn * sn - t.ts * c, 0.0, 1e-9 * kParams.sigma_c);  // stays radial
    EXPECT_EQ(damage(kLim, s), d_peak);
  }
  EXPECT_LT(std::abs(work), 1e-9 * (0.5 * kParams.sigma_c * rho_peak));
  EXPECT_NEAR(t.tn, peak.tn, 1e-12 * kParams.sigma_c);
  EXPECT_NEAR(t.ts, peak.ts, 1e-12 * kParams.sigma_c);
  EXPECT_EQ(s.phase, LinkPhase::cohesive);
}

TEST(CohesiveLaw, DamageNeverDecreasesAndPhasesOnlyMoveForward) {
  std::mt19937 rng(20200813);
  std::normal_distribution<double> step(0.0, kLim.dc / 40);
  CohesiveState s;
  double dn = 0.0, s1 = 0.0, s2 = 0.0;  // two shear components: ds is their length (eq. 10)
  double last_damage = 0.0, last_lambda = 0.0;
  int last_phase = 0;
  bool reached_contact = false, saw_compression = false;
  for (int i = 0; i < 10000; ++i) {
    dn += step(rng);
    s1 += step(rng);
    s2 += step(rng);
    saw_compression |= dn < 0;
    const CohesiveTraction t = cohesive_traction(kParams, kLim, dn, std::hypot(s1, s2), s);
    const double d = damage(kLim, s);
    EXPECT_GE(d, last_damage) << "step " << i;
    EXPECT_GE(s.lambda_max, last_lambda) << "step " << i;
    EXPECT_GE(static_cast<int>(s.phase), last_phase) << "step " << i;
    EXPECT_GE(d, 0.0);
    EXPECT_LE(d, 1.0);
    if (s.phase == LinkPhase::contact) {
      reached_contact = true;
      EXPECT_EQ(t.tn, 0.0);
      EXPECT_EQ(t.ts, 0.0);
    }
    last_damage = d;
    last_lambda = s.lambda_max;
    last_phase = static_cast<int>(s.phase);
  }
  EXPECT_TRUE(reached_contact);
  EXPECT_TRUE(saw_compression);
}

TEST(CohesiveLaw, CompleteDecohesionLeavesNoTractionForEver) {
  CohesiveState s;
  // Just before lambda = 1 in pure mode I: T = sigma_c (1 - lambda) / (1 - lambda_cr), tiny.
  CohesiveTraction t = cohesive_traction(kParams, kLim, (1.0 - 1e-6) * kLim.dc, 0.0, s);
  EXPECT_EQ(s.phase, LinkPhase::cohesive);
  EXPECT_NEAR(t.tn, kParams.sigma_c * 1e-6 / (1.0 - kLim.lambda_cr), 1e-3);
  // At lambda = 1 (eq. 16): zero, and the link is in contact (Table 1).
  t = cohesive_traction(kParams, kLim, kLim.dc, 0.0, s);
  EXPECT_EQ(s.phase, LinkPhase::contact);
  EXPECT_EQ(t.tn, 0.0);
  EXPECT_EQ(t.ts, 0.0);
  EXPECT_EQ(damage(kLim, s), 1.0);
  // Closing again, shearing, compressing: still nothing (the contact law takes over).
  for (const auto& [dn, ds] : std::array<std::array<double, 2>, 4>{
           {{0.5 * kLim.dc, 0.0}, {0.0, 0.1 * kLim.dc}, {-kLim.d0, 0.0}, {0.0, 0.0}}}) {
    t = cohesive_traction(kParams, kLim, dn, ds, s);
    EXPECT_EQ(t.tn, 0.0);
    EXPECT_EQ(t.ts, 0.0);
    EXPECT_EQ(s.phase, LinkPhase::contact);
  }
}

TEST(CohesiveLaw, CompressionMeetsThePenaltyAndCountsInNeitherPsiNorLambda) {
  const double A = kParams.area;
  {
    CohesiveState s;  // connective, pressed far beyond d0: eq. 7, psi stays 0
    const CohesiveTraction t = cohesive_traction(kParams, kLim, -5.0 * kLim.d0, 0.0, s);
    EXPECT_DOUBLE_EQ(t.tn, -5.0 * kParams.kn * kLim.d0 / A);
    EXPECT_EQ(t.ts, 0.0);
    EXPECT_EQ(s.phase, LinkPhase::connective);
    EXPECT_EQ(s.psi_max, 0.0);
  }
  {
    CohesiveState s;  // cohesive at lambda = 0.3 (pure opening), then pressed and sheared
    cohesive_traction(kParams, kLim, 0.3 * kLim.dc, 0.0, s);
    ASSERT_EQ(s.phase, LinkPhase::cohesive);
    const double dn = -2.0 * kLim.d0, ds = 0.2 * kLim.dc;
    const CohesiveTraction t = cohesive_traction(kParams, kLim, dn, ds, s);
    EXPECT_DOUBLE_EQ(t.tn, kParams.kn * dn / A);  // penalty (sec. 3.2)
    // lambda = ds / dc = 0.2 < lambda_max = 0.3: unloading, d = (0.3 - lambda_cr) /
    // (1 - lambda_cr), Ts = sigma_c (1 - d) (0.2 / 0.3) (eqs 22-26).
    const double d = (0.3 - 0.011431661) / (1.0 - 0.011431661);
    EXPECT_NEAR(t.ts, kParams.sigma_c * (1.0 - d) * 0.2 / 0.3, 1e-6 * kParams.sigma_c);
    EXPECT_NEAR(s.lambda_max, 0.3, 1e-12);
  }
}

TEST(CohesiveLaw, AShorteningThatIsNotThePlaneClosingSeparatesAsAnOpeningDoes) {
  // The lattice's "plane" reading (physics/lattice/cubic_lattice.hpp, Compression::plane) tells the
  // law how much of a link's shortening is the plane closing; the rest separates. Shortened
  // with nothing of it closing, the link is the mirror image of an opened one: the same
  // tractions, opposite in sign, and the same work to decohesion, A (G_c + sigma_c dn0 / 2).
  CohesiveState opened, shortened;
  const int n = 20000;
  const double end = 1.05 * kLim.dc, h = end / n;
  double work = 0.0, prev = 0.0;
  for (int i = 1; i <= n; ++i) {
    const double dn = end * i / n;
    const CohesiveTraction a = cohesive_traction(kParams, kLim, dn, 0.0, opened);
    const CohesiveTraction b = cohesive_traction(kParams, kLim, -dn, 0.0, shortened, 0.0);
    EXPECT_DOUBLE_EQ(b.tn, -a.tn) << "dn = " << dn;
    EXPECT_EQ(shortened.phase, opened.phase);
    work += 0.5 * (prev - b.tn) * h;  // the work done on the link as it is shortened
    prev = -b.tn;
  }
  EXPECT_EQ(shortened.phase, LinkPhase::contact);
  // Per unit area: 260 + 7e7 * 8.5902924e-8 / 2 = 263.00660 N/m.
  EXPECT_NEAR(work, 263.00660, 1e-3 * 263.0);
  // Where part of it is the plane closing, that part meets the penalty and the rest counts:
  // connective, the spring is linear in the whole shortening whatever the split.
  CohesiveState s;
  const CohesiveTraction t = cohesive_traction(kParams, kLim, -0.5 * kLim.d0, 0.0, s, -0.2 * kLim.d0);
  EXPECT_EQ(s.phase, LinkPhase::connective);
  EXPECT_NEAR(s.psi_max, 0.3, 1e-12);  // |(-0.5 + 0.2) d0| / d0
  EXPECT_DOUBLE_EQ(t.tn, -0.5 * kParams.kn * kLim.d0 / kParams.area);
}

// Initiation::traction (cleave's rule, physics/bonds/cohesive_law.hpp): a link turns cohesive where
// its spring's traction reaches sigma_c, and softens from there with its own dc.
namespace {

CohesiveParams traction_params() {
  CohesiveParams p = kParams;
  p.initiation = Initiation::traction;
  return p;
}

/// Where the spring's traction reaches sigma_c along direction theta of the (<dn>, ds)
/// plane: |(k_n c, k_s s)| rho / A = sigma_c, i.e. rho = 1 / |(c / dn0, s / ds0)| (eq. 31).
double traction_onset(double theta) {
  return 1.0 / std::hypot(std::cos(theta) / kLim.dn0, std::sin(theta) / kLim.ds0);
}

}  // namespace

TEST(TractionInitiation, ShearTractionIsContinuousWhereThePapersLawJumpsSixfold) {
  // Pure mode II. The paper's eq. 32 initiates at ds = d0 = dn0, where the spring carries
  // k_s dn0 / A = sigma_c k_s / k_n = sigma_c / 6 (k_s / k_n = 0.2 / 1.2), and the cohesive
  // branch starts at sigma_c: a jump of six.
  {
    CohesiveState below, above;
    const double ts_below =
        cohesive_traction(kParams, kLim, 0.0, (1.0 - 1e-9) * kLim.d0, below).ts;
    const double ts_above =
        cohesive_traction(kParams, kLim, 0.0, (1.0 + 1e-9) * kLim.d0, above).ts;
    EXPECT_EQ(below.phase, LinkPhase::connective);
    EXPECT_EQ(above.phase, LinkPhase::cohesive);
    EXPECT_NEAR(ts_below, kParams.sigma_c / 6.0, 1e-6 * kParams.sigma_c);
    EXPECT_NEAR(ts_above, kParams.sigma_c, 1e-6 * kParams.sigma_c);
  }
  // The traction rule initiates at ds0 = A sigma_c / k_s, with sigma_c on both sides.
  const CohesiveParams p = traction_params();
  CohesiveState below, above;
  const double ts_below = cohesive_traction(p, kLim, 0.0, (1.0 - 1e-9) * kLim.ds0, below).ts;
  const double ts_above = cohesive_traction(p, kLim, 0.0, (1.0 + 1e-9) * kLim.ds0, above).ts;
  EXPECT_EQ(below.phase, LinkPhase::connective);
  EXPECT_EQ(above.phase, LinkPhase::cohesive);
  EXPECT_NEAR(ts_below, kParams.sigma_c, 1e-6 * kParams.sigma_c);
  EXPECT_NEAR(ts_above, kParams.sigma_c, 1e-6 * kParams.sigma_c);
  // Its own dc: ds0 + 2 G_c / sigma_c = 5.1541754e-7 + 7.4285714e-6 = 7.9439889e-6 m.
  EXPECT_NEAR(above.dc, 7.9439889e-6, 1e-6 * 7.94e-6);
  EXPECT_NEAR(damage(kLim, above), 0.0, 1e-9);
}

TEST(TractionInitiation, InitiatesWhereTheTractionReachesSigmaCInEveryDirection) {
  const CohesiveParams p = traction_params();
  for (double theta : {0.0, 0.3, M_PI / 4, 1.2, M_PI / 2}) {
    const double rho = traction_onset(theta), c = std::cos(theta), sn = std::sin(theta);
    CohesiveState in, out;
    const CohesiveTraction ti =
        cohesive_traction(p, kLim, (1.0 - 1e-9) * rho * c, (1.0 - 1e-9) * rho * sn, in);
    const CohesiveTraction to =
        cohesive_traction(p, kLim, (1.0 + 1e-9) * rho * c, (1.0 + 1e-9) * rho * sn, out);
    EXPECT_EQ(in.phase, LinkPhase::connective) << "theta " << theta;
    EXPECT_EQ(out.phase, LinkPhase::cohesive) << "theta " << theta;
    EXPECT_NEAR(std::hypot(ti.tn, ti.ts), kParams.sigma_c, 1e-6 * kParams.sigma_c);
    EXPECT_NEAR(std::hypot(to.tn, to.ts), kParams.sigma_c, 1e-6 * kParams.sigma_c);
  }
  // Pure mode I is the paper's law: the same onset dn0 and the same dc.
  EXPECT_NEAR(traction_onset(0.0), kLim.dn0, 1e-15);
}

TEST(TractionInitiation, SofteningDissipatesGcForEveryModeMixAndUnloadingNothing) {
  const CohesiveParams p = traction_params();
  for (double theta : {0.0, M_PI / 2, M_PI / 3, 70.0 * M_PI / 180}) {
    const double c = std::cos(theta), sn = std::sin(theta);
    const double onset = traction_onset(theta), end = onset + 2.0 * p.g_c / p.sigma_c;
    CohesiveState s;
    CohesiveTraction prev = cohesive_traction(p, kLim, 0.0, 0.0, s);
    double soft = 0.0, total = 0.0, last_damage = 0.0;
    const int n = 2000000;
    for (int i = 1; i <= n; ++i) {
      const LinkPhase before = s.phase;
      const double rho = 1.0001 * end * i / n;
      const CohesiveTraction t = cohesive_traction(p, kLim, rho * c, rho * sn, s);
      const double dw = 0.5 * (radial(prev, theta) + radial(t, theta)) * (1.0001 * end / n);
      total += dw;
      if (before != LinkPhase::connective) soft += dw;
      const double d = damage(kLim, s);
      ASSERT_GE(d, last_damage);
      last_damage = d;
      prev = t;
    }
    EXPECT_EQ(s.phase, LinkPhase::contact) << "theta " << theta;
    EXPECT_NEAR(soft, p.g_c, 1e-3 * p.g_c) << "theta " << theta;
    // Stored up to the onset: (k_n c^2 + k_s s^2) onset^2 / (2A), the springs' work along
    // the path (sigma_c onset / 2 in the pure modes).
    const double stored = (p.kn * c * c + p.ks * sn * sn) * onset * onset / (2.0 * p.area);
    EXPECT_NEAR(total - soft, stored, 2e-3 * stored) << "theta " << theta;
  }
  // Unloading half way down the softening branch and reloading: along the secant, no work.
  const double theta = M_PI / 2, onset = traction_onset(theta);
  const double peak = onset + 0.5 * 2.0 * p.g_c / p.sigma_c;
  CohesiveState s;
  for (int i = 1; i <= 1000; ++i) cohesive_traction(p, kLim, 0.0, peak * i / 1000, s);
  const double t_peak = cohesive_traction(p, kLim, 0.0, peak, s).ts;
  // Half way (to within the loading step by which initiation was passed, which sets dc):
  // eq. 15 with this link's dc gives sigma_c (dc - peak) / (2 G_c / sigma_c), about sigma_c / 2.
  const double gap = 2.0 * p.g_c / p.sigma_c;
  EXPECT_NEAR(s.dc, onset + gap, peak / 1000);
  EXPECT_NEAR(t_peak, p.sigma_c * (s.dc - peak) / gap, 1e-9 * p.sigma_c);
  const double d_peak = damage(kLim, s);
  EXPECT_NEAR(d_peak, (peak - (s.dc - gap)) / gap, 1e-9);
  EXPECT_NEAR(d_peak, 0.5, 1e-3);
  double work = 0.0, prev = t_peak;
  const int m = 500;
  for (int i = 1; i <= 2 * m; ++i) {
    const double frac = i <= m ? 1.0 - static_cast<double>(i) / m : static_cast<double>(i - m) / m;
    const double ts = cohesive_traction(p, kLim, 0.0, frac * peak, s).ts;
    EXPECT_NEAR(ts, t_peak * frac, 1e-9 * p.sigma_c);
    work += 0.5 * (prev + ts) * (i <= m ? -peak / m : peak / m);
    prev = ts;
    EXPECT_EQ(damage(kLim, s), d_peak);
  }
  EXPECT_LT(std::abs(work), 1e-9 * t_peak * peak);
}

TEST(LinkPhase, Names) {
  EXPECT_STREQ(to_string(LinkPhase::connective), "connective");
  EXPECT_STREQ(to_string(LinkPhase::cohesive), "cohesive");
  EXPECT_STREQ(to_string(LinkPhase::contact), "contact");
}

// ---- Hertz-Mindlin contact (sec. 4) ----

TEST(HertzMindlin, EquivalentPropertiesOfTwoUnequalBodies) {
  // Aluminium-like i (E 70 GPa, nu 0.3, r 1 mm) against steel-like j (200 GPa, 0.25, 2 mm).
  const HertzMindlinParams p = hertz_mindlin_params(70e9, 0.3, 1e-3, 200e9, 0.25, 2e-3, 0.5, 0.2);
  // Eq. 35: E* = (0.91 / 70e9 + 0.9375 / 200e9)^-1 = (1.3e-11 + 4.6875e-12)^-1 = 5.65371e10.
  EXPECT_NEAR(p.e_star, 1.0 / 1.76875e-11, 1e-9 * p.e_star);
  // Eq. 36: r* = (1000 + 500)^-1 = 6.6667e-4 m.
  EXPECT_NEAR(p.r_star, 1.0 / 1500.0, 1e-18);
  // Eq. 41: G_i = 70e9 / 2.6 = 2.6923077e10, G_j = 200e9 / 2.5 = 8e10,
  // G* = (1.7 / 2.6923077e10 + 1.75 / 8e10)^-1 = (6.3142857e-11 + 2.1875e-11)^-1 = 1.1762235e10.
  EXPECT_NEAR(p.g_star, 1.1762235e10, 1e-7 * 1.1762235e10);
  EXPECT_EQ(p.kappa, 0.5);
  EXPECT_EQ(p.friction, 0.2);
}

namespace {
const HertzMindlinParams kSteel =
    hertz_mindlin_params(200e9, 0.3, 1e-3, 200e9, 0.3, 1e-3, 1.0, 0.5);
}

TEST(HertzMindlin, NormalForceIsHertzsLaw) {
  // Equal steel spheres: E* = E / (2 (1 - nu^2)) = 200e9 / 1.82, r* = 0.5 mm.
  const double e_star = 200e9 / 1.82, r_star = 0.5e-3;
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, 2) / 3.0;
  double f_prev = 0.0;
  for (double overlap : {1e-7, 2e-7, 1e-6, 5e-6}) {
    HertzMindlinState s;
    const HertzMindlinForce f =
        hertz_mindlin_force(kSteel, overlap, n, Eigen::Vector3d::Zero(), s, 1e-7);
    const double expected = 4.0 / 3.0 * e_star * std::sqrt(r_star) * std::pow(overlap, 1.5);
    EXPECT_NEAR(f.force.dot(n), expected, 1e-12 * expected);  // pushes B away from A
    EXPECT_NEAR((f.force - f.force.dot(n) * n).norm(), 0.0, 1e-12 * expected);
    if (overlap == 2e-7) {  // doubling the overlap: 2^1.5 times the force
      EXPECT_NEAR(f.force.norm() / f_prev, std::pow(2.0, 1.5), 1e-12);
    }
    f_prev = f.force.norm();
  }
}

TEST(HertzMindlin, HeadOnCollisionOfEqualSpheresConservesEnergy) {
  // Two equal steel spheres (radius 1 mm, density 7800) approach at 0.1 m/s each and bounce
  // off without damping: the Hertz force derives from the potential 8/15 E* sqrt(r*) d^2.5, so
  // velocity Verlet brings them back apart at the approach speed.
  const double R = 1e-3, m = 7800.0 * 4.0 / 3.0 * M_PI * R * R * R, v0 = 0.1, dt = 1e-9;
  const Eigen::Vector3d n = Eigen::Vector3d::UnitX();
  double xa = 0.0, xb = 2.0 * R, va = v0, vb = -v0;  // just touching
  HertzMindlinState s;
  auto force_on_b = [&](double xa_, double xb_, double va_, double vb_) {
    const double overlap = 2.0 * R - (xb_ - xa_);
    return hertz_mindlin_force(kSteel, overlap, n, Eigen::Vector3d(vb_ - va_, 0, 0), s, dt)
        .force.x();
  };
  double f = force_on_b(xa, xb, va, vb);
  int steps = 0;
  do {
    xa += va * dt - 0.5 * f / m * dt * dt;
    xb += vb * dt + 0.5 * f / m * dt * dt;
    const double f_new = force_on_b(xa, xb, va, vb);
    va -= 0.5 * (f + f_new) / m * dt;
    vb += 0.5 * (f + f_new) / m * dt;
    f = f_new;
    ++steps;
  } while (xb - xa < 2.0 * R + 1e-12 && steps < 10000000);
  EXPECT_GT(steps, 1000);  // the contact was resolved in many steps
  EXPECT_NEAR(vb - va, 2.0 * v0, 1e-4 * 2.0 * v0);
  EXPECT_NEAR(va + vb, 0.0, 1e-12);
}

TEST(HertzMindlin, ShearSpringAndCoulombCap) {
  const double overlap = 1e-6, dt = 1e-7;
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  // Equal steel spheres: G = 200e9 / 2.6, G* = G / (2 (2 - nu)) = 200e9 / (2.6 * 3.4).
  const double g_star = 200e9 / (2.6 * 3.4), r_star = 0.5e-3;
  const double kt = 16.0 / 3.0 * g_star * std::sqrt(r_star * overlap);  // eq. 40
  const double fn = 4.0 / 3.0 * 200e9 / 1.82 * std::sqrt(r_star) * std::pow(overlap, 1.5);
  HertzMindlinParams stuck = kSteel;
  stuck.friction = 1e6;  // no sliding
  {
    HertzMindlinState s;  // slide B by d = 2e-9 m along x in one step
    const double d = 2e-9;
    const HertzMindlinForce f =
        hertz_mindlin_force(stuck, overlap, n, Eigen::Vector3d(d / dt, 0, 0), s, dt);
    EXPECT_NEAR(f.force.x(), -kt * d, 1e-12 * kt * d);
    EXPECT_NEAR(f.force.z(), fn, 1e-12 * fn);
    EXPECT_NEAR(s.shear.x(), d, 1e-24);
    // The normal velocity does not enter the shear displacement (eq. 43).
    hertz_mindlin_force(stuck, overlap, n, Eigen::Vector3d(0, 0, 1.0), s, dt);
    EXPECT_NEAR(s.shear.x(), d, 1e-24);
    EXPECT_NEAR(s.shear.z(), 0.0, 1e-30);
    // The normal turns: the stored displacement is carried into the new tangent plane.
    const Eigen::Vector3d n2 = Eigen::Vector3d(0.1, 0, 1).normalized();
    hertz_mindlin_force(stuck, overlap, n2, Eigen::Vector3d::Zero(), s, dt);
    EXPECT_NEAR(s.shear.dot(n2), 0.0, 1e-24);
    EXPECT_NEAR(s.shear.norm(), d, 1e-22);
  }
  {
    HertzMindlinState s;  // friction 0.5: a large slide is capped at 0.5 F_n
    const double d = 1e-6;
    ASSERT_GT(kt * d, 0.5 * fn);
    HertzMindlinForce f =
        hertz_mindlin_force(kSteel, overlap, n, Eigen::Vector3d(0, d / dt, 0), s, dt);
    EXPECT_NEAR(f.force.y(), -0.5 * fn, 1e-12 * fn);
    EXPECT_NEAR(s.shear.y(), 0.5 * fn / kt, 1e-12 * fn / kt);  // shrunk to the sliding force
    // Reversing by a small amount unloads elastically from the sliding force.
    const double back = 0.1 * fn / kt;
    f = hertz_mindlin_force(kSteel, overlap, n, Eigen::Vector3d(0, -back / dt, 0), s, dt);
    EXPECT_NEAR(f.force.y(), -0.4 * fn, 1e-9 * fn);
  }
  {
    HertzMindlinParams slippery = kSteel;  // friction 0: frictionless sliding
    slippery.friction = 0.0;
    HertzMindlinState s;
    const HertzMindlinForce f =
        hertz_mindlin_force(slippery, overlap, n, Eigen::Vector3d(1.0, 0, 0), s, dt);
    EXPECT_EQ(f.force.x(), 0.0);
    EXPECT_EQ(s.shear.norm(), 0.0);
  }
}

TEST(HertzMindlin, StateResetsWhenTheParticlesSeparate) {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  HertzMindlinParams stuck = kSteel;
  stuck.friction = 1e6;
  HertzMindlinState s;
  hertz_mindlin_force(stuck, 1e-6, n, Eigen::Vector3d(0.01, 0, 0), s, 1e-7);
  ASSERT_TRUE(s.touching);
  ASSERT_GT(s.shear.norm(), 0.0);
  for (double gap : {0.0, -1e-9}) {
    const HertzMindlinForce f =
        hertz_mindlin_force(stuck, gap, n, Eigen::Vector3d(1, 0, 0), s, 1e-7);
    EXPECT_EQ(f.force.norm(), 0.0);
    EXPECT_FALSE(s.touching);
    EXPECT_EQ(s.shear.norm(), 0.0);
  }
  // A new contact starts with no shear load.
  const HertzMindlinForce f = hertz_mindlin_force(stuck, 1e-6, n, Eigen::Vector3d::Zero(), s, 1e-7);
  EXPECT_EQ(f.force.x(), 0.0);
  EXPECT_GT(f.force.z(), 0.0);
}
