// The DCB as corrected beam theory with a cohesive zone (validation/cohesive_beam.hpp). Checked
// against closed forms at both ends: before the zone opens the arm is a cantilever on
// Winkler's elastic foundation (Hetenyi's semi-infinite beam); while the crack grows the
// J-integral of the arm equals the fracture energy (Paris & Paris: J B' = 2 P theta at the
// load line) and the load is eq. 60's; a stronger plane brings stage I to eq. 59. The ENF and
// the MMB likewise: eq. 63 and eq. 68 before the zone opens, eqs 64 and 69 while the crack runs.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include "validation/beam_theory.hpp"
#include "validation/cohesive_beam.hpp"

using namespace cleave::physics;

namespace {

// The paper's DCB (sec. 7.1): E = 120 GPa, nu = 0.2, B = 2 mm, h = 1 mm, L = 30 mm, a0 = 9 mm,
// r = 0.125 mm, G_Ic = 0.26 N/mm. By hand: EI = 0.02 N m^2, B' = 1.75 mm,
// chi_I h = 0.64514535263 mm (test_beam_theory.cpp).
constexpr double kEI = 0.02, kBp = 1.75e-3, kLambda = 0.64514535263e-3, kGIc = 260.0;

BeamTest dcb() {
  return {BeamTestKind::dcb, 120e9, 0.2, 2e-3, 1e-3, 30e-3, 9e-3, 0.125e-3, kGIc, 1002.0};
}

}  // namespace

TEST(CohesiveBeam, TheFoundationsDecayLengthIsChiIH) {
  // k = 4 EI / (chi_I h)^4, so (4 EI / k)^(1/4) = chi_I h.
  const double k = cohesive_beam_spring(dcb());
  EXPECT_NEAR(std::pow(4.0 * kEI / k, 0.25), kLambda, 1e-10 * kLambda);  // kLambda: 11 digits
}

TEST(CohesiveBeam, BeforeTheZoneOpensTheArmIsACantileverOnWinklersFoundation) {
  // Hetenyi: a semi-infinite beam on springs k, loaded at its end by V = P and M = P a (the
  // cracked arm's lever), with lambda = 1/beta = chi_I h, deflects y = P (1 + a/lambda)
  // lambda^3 / (2EI) and turns theta = P (lambda^2 + 2 a lambda) / (2EI); the free arm adds
  // its own bending. The load-line deflection of one arm is then
  //   w0 = P / (3EI) (a^3 + 3 a^2 lambda + 3 a lambda^2 + 3 lambda^3 / 2)
  // and its slope theta0 = P (a + lambda)^2 / (2EI). Delta = 2 w0.
  const double a = 9e-3, l = kLambda;
  const double compliance = 2.0 / (3.0 * kEI) * (a * a * a + 3 * a * a * l + 3 * a * l * l + 1.5 * l * l * l);
  // 0.05 mm of opening: about half the load at which the first point of the plane reaches
  // sigma_c = 70 MPa (the zone opens near Delta = 0.1 mm).
  const auto curve = cohesive_dcb_curve(dcb(), 70e6, 3e-3, 0.05e-3, {0, 10});
  ASSERT_EQ(curve.size(), 11u);
  for (size_t i = 1; i < curve.size(); ++i) {
    const CohesiveBeamPoint& p = curve[i];
    EXPECT_EQ(p.process_zone, 9e-3) << "the zone opened at Delta = " << p.delta;
    EXPECT_NEAR(p.delta / p.load, compliance, 1e-6 * compliance) << "Delta = " << p.delta;
    EXPECT_NEAR(p.rotation, p.load * (a + l) * (a + l) / (2.0 * kEI),
                1e-6 * p.rotation);
  }
  // Eq. 59 is the same to within the 3/2 lambda^3 term: 1.5e-4 here.
  const double eq59 = 2.0 * std::pow(a + l, 3) / (3.0 * kEI);
  EXPECT_NEAR(curve.back().delta / curve.back().load, eq59, 2e-4 * eq59);
}

TEST(CohesiveBeam, WhileTheCrackGrowsTheJIntegralIsTheFractureEnergyAndTheLoadIsEq60s) {
  // For an Euler arm on any foundation loaded monotonically, EI w''' w' - EI w''^2 / 2 + Phi(w)
  // is constant along the foundation, and Phi at a fully decohered point is half the
  // plane's G_Ic B' (the spring's energy comes back). So 2 P theta0 = G_Ic B' whenever the
  // crack runs, whatever sigma_c (Paris & Paris' J of the DCB). Eq. 60 says the same through
  // the LEFM compliance: both are checked on the points where the tip is well inside the
  // plane.
  const BeamTest t = dcb();
  for (double sigma_c : {35e6, 70e6, 140e6}) {
    const auto curve = cohesive_dcb_curve(t, sigma_c, 3e-3, 2.6e-3, {0, 520});
    int growing = 0;
    for (const CohesiveBeamPoint& p : curve) {
      if (p.crack < t.a0 + 2e-3 || p.process_zone > t.L - 1e-3) continue;
      ++growing;
      EXPECT_NEAR(2.0 * p.load * p.rotation / (kGIc * kBp), 1.0, 2e-3)
          << "sigma_c = " << sigma_c << ", Delta = " << p.delta;
      const auto lefm = analytic_load(t, 2, p.delta);
      ASSERT_TRUE(lefm.has_value());
      EXPECT_NEAR(p.load / *lefm, 1.0, 5e-3) << "sigma_c = " << sigma_c << ", Delta = " << p.delta;
    }
    EXPECT_GT(growing, 100) << "sigma_c = " << sigma_c;
  }
}

TEST(CohesiveBeam, AStrongerPlaneBringsStageIToEq59) {
  // Before the peak the cohesive zone softens the beam: the shortfall against eq. 59 at 0.9 of
  // LEFM's peak deflection shrinks as sigma_c grows (Hillerborg's length E G_Ic / sigma_c^2
  // against the arm), and is gone once that length is a small part of h.
  const BeamTest t = dcb();
  const double peak_delta = stage_range(t, 1).second;
  const double at = 0.9 * peak_delta;
  double previous = 1.0;
  for (double sigma_c : {35e6, 70e6, 140e6, 220e6}) {
    const auto curve = cohesive_dcb_curve(t, sigma_c, 3e-3, at, {0, 300});
    const double shortfall = 1.0 - curve.back().load / *analytic_load(t, 1, curve.back().delta);
    EXPECT_GT(shortfall, 0.0) << "sigma_c = " << sigma_c;
    EXPECT_LT(shortfall, previous) << "sigma_c = " << sigma_c;
    previous = shortfall;
  }
  // E G_Ic / sigma_c^2 = 0.64 mm at 220 MPa.
  EXPECT_LT(previous, 0.01);
}

TEST(CohesiveBeam, DissipatesGTimesTheCrackedArea) {
  // Energy balance over the whole path: the work of the load less what unloading would give
  // back is the fracture energy dissipated: at least G_Ic B' for every unit of decohered
  // length, at most that of the whole weak plane (L - a0) B'.
  const BeamTest t = dcb();
  const auto curve = cohesive_dcb_curve(t, 70e6, 3e-3, 4e-3, {0, 800});
  double work = 0.0;
  for (size_t i = 1; i < curve.size(); ++i)
    work += 0.5 * (curve[i].load + curve[i - 1].load) * (curve[i].delta - curve[i - 1].delta);
  const CohesiveBeamPoint& end = curve.back();
  // Unloaded from there, every part goes back along its secant to the origin (the beam and
  // springs are linear, a damaged point unloads to the origin, eqs 23-24), so the load would
  // return P Delta / 2 of the work: the rest was dissipated.
  const double dissipated = work - 0.5 * end.load * end.delta;
  const double cracked = (end.crack - t.a0) * kBp * kGIc;
  const double whole = (t.L - t.a0) * kBp * kGIc;
  EXPECT_GT(dissipated, cracked * 0.995);
  EXPECT_LT(dissipated, whole * 1.005);
}

TEST(CohesiveBeam, RefusesWhatItCannotSolve) {
  BeamTest enf = dcb();
  enf.kind = BeamTestKind::enf;
  enf.L = 15.125e-3;
  EXPECT_THROW(cohesive_dcb_curve(enf, 70e6, 0, 1e-3), std::invalid_argument);
  EXPECT_THROW(cohesive_dcb_curve(dcb(), -1.0, 0, 1e-3), std::invalid_argument);
  // sigma_c^2 > G_Ic k / B' (about 260 MPa here): the softening would snap back at a point.
  EXPECT_THROW(cohesive_dcb_curve(dcb(), 400e6, 0, 1e-3), std::invalid_argument);
}

TEST(CohesiveBeam, LoadBetweenPointsIsLinearAndNaNOutside) {
  const std::vector<CohesiveBeamPoint> c = {{0.0, 0.0, 0, 0, 0}, {1.0, 2.0, 0, 0, 0},
                                            {3.0, 1.0, 0, 0, 0}};
  EXPECT_DOUBLE_EQ(cohesive_load(c, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(cohesive_load(c, 2.0), 1.5);
  EXPECT_DOUBLE_EQ(cohesive_load(c, 3.0), 1.0);
  EXPECT_TRUE(std::isnan(cohesive_load(c, 3.5)));
  EXPECT_TRUE(std::isnan(cohesive_load(c, -0.1)));
}

namespace {

BeamTest enf() {
  return {BeamTestKind::enf, 120e9, 0.2, 2e-3, 1e-3, 15.125e-3, 9e-3, 0.125e-3, kGIc, 1002.0};
}

}  // namespace

TEST(CohesiveEnf, BeforeTheZoneOpensItIsEq63sBeam) {
  // Bonded, the two arms are one beam of 8 EI; cracked, two of EI each; the slip's spring
  // carries eq. 63's shear correction chi_II h (the effective crack length of a shear lag
  // with that decay length is a + chi_II h only to first order: 0.2 % here).
  const BeamTest t = enf();
  const double c63 = (2 * std::pow(t.L, 3) + 3 * std::pow(t.a0 + 0.27096104810e-3, 3)) /
                     (96.0 * kEI);
  const auto curve = cohesive_enf_curve(t, 70e6, 0.02e-3, {0, 4});
  ASSERT_EQ(curve.size(), 5u);
  for (size_t i = 1; i < curve.size(); ++i) {
    EXPECT_EQ(curve[i].process_zone, t.a0) << "the zone opened at Delta = " << curve[i].delta;
    EXPECT_NEAR(curve[i].delta / curve[i].load, c63, 5e-3 * c63);
  }
  // A beam with the plane cut all along (8 EI -> 2 EI) or bonded to the support (a0 -> 0)
  // would be far off: the check can tell them apart.
  EXPECT_GT(std::abs(c63 / (std::pow(2 * t.L, 3) / (48 * 8 * kEI)) - 1.0), 0.1);
}

TEST(CohesiveEnf, PastMidSpanTheCrackGrowsAlongEq64AndTheBeamsNeverSplit) {
  // Once the zone has run past the load line, J = G_IIc holds at the tip as in the DCB, and the
  // load is eq. 64's at every deflection, whatever sigma_c; the load rises with Delta and the
  // crack stays short of the far support (stage IV is a limit of LEFM's path, and of this one).
  const BeamTest t = enf();
  for (double sigma_c : {70e6, 140e6}) {
    const auto curve = cohesive_enf_curve(t, sigma_c, 3e-3, {0, 300});
    int compared = 0;
    double last_load = 0.0;
    for (const CohesiveBeamPoint& p : curve) {
      if (p.delta < 0.8e-3) continue;
      const auto lefm = analytic_load(t, 3, p.delta);
      ASSERT_TRUE(lefm.has_value()) << "Delta = " << p.delta;
      EXPECT_NEAR(p.load / *lefm, 1.0, 5e-3) << "sigma_c = " << sigma_c << ", Delta = " << p.delta;
      EXPECT_GT(p.load, last_load);
      last_load = p.load;
      ++compared;
    }
    EXPECT_GT(compared, 200);
    EXPECT_LT(curve.back().crack, 2.0 * t.L - 5e-3) << "sigma_c = " << sigma_c;
  }
}

TEST(CohesiveEnf, AStrongPlaneSnapsBackAtThePeakAWeakOneDoesNot) {
  // a0 / L = 0.595 < 3^(-1/3): eq. 63's stage II turns back in Delta, so under displacement
  // control a brittle plane's load drops at the peak and lands on the reachable part of the
  // path. sigma_c = 300 MPa (E G_IIc / sigma_c^2 = 1.3 mm) behaves so; at 70 MPa the zone
  // (24 mm by that measure) takes the load down gradually instead.
  const BeamTest t = enf();
  auto largest_drop = [&](double sigma_c) {
    const auto curve = cohesive_enf_curve(t, sigma_c, 0.6e-3, {0, 600});
    double drop = 0.0;
    for (size_t i = 1; i < curve.size(); ++i)
      drop = std::max(drop, 1.0 - curve[i].load / curve[i - 1].load);
    // After the peak the crack grows stably and the load is LEFM's again.
    const CohesiveBeamPoint& end = curve.back();
    std::optional<double> lefm = analytic_load(t, 3, end.delta);
    if (!lefm) lefm = analytic_load(t, 2, end.delta);
    EXPECT_TRUE(lefm.has_value());
    if (lefm) {
      EXPECT_NEAR(end.load / *lefm, 1.0, 0.02) << "sigma_c = " << sigma_c;
    }
    return drop;
  };
  EXPECT_GT(largest_drop(300e6), 0.15);  // in one step of 1 micrometre
  EXPECT_LT(largest_drop(70e6), 0.03);
}

namespace {

// The paper's MMB at beta = 50 % (sec. 7.3) on the lattice's as-built half span L = 15 mm,
// with one G_c = G_IIc in both modes, as the scenario.
BeamTest mmb() {
  BeamTest t{BeamTestKind::mmb, 120e9, 0.2, 2e-3, 1e-3, 15e-3, 9e-3, 0.125e-3, 1002.0, 1002.0};
  t.C = mmb_lever_arm(0.5, t.L);
  return t;
}

}  // namespace

TEST(CohesiveMmb, BeforeTheZoneOpensTheEndOpensAsTheDcbPartAlone) {
  // Linear beams: the lever's loads split into an opening pair P_I = (3C - L) P / (4L) on the
  // arms' ends and a symmetric ENF load (eq. 66). The symmetric part bends both arms alike
  // and leaves the end's opening alone; so Delta / P is P_I / P times the DCB arm pair's
  // compliance, Hetenyi's cantilever on Winkler's foundation (as in the DCB test above), up
  // to the mid-span push's own dent in the foundation 6 mm (9 decay lengths) from the tip.
  const BeamTest t = mmb();
  const double a = t.a0, l = kLambda;
  const double dcb = 2.0 / (3.0 * kEI) * (a * a * a + 3 * a * a * l + 3 * a * l * l + 1.5 * l * l * l);
  const double p_I = (3.0 * t.C - t.L) / (4.0 * t.L);
  const auto curve = cohesive_mmb_curve(t, 70e6, 0.02e-3, {0, 4});
  ASSERT_EQ(curve.size(), 5u);
  for (size_t i = 1; i < curve.size(); ++i) {
    EXPECT_EQ(curve[i].process_zone, t.a0) << "the zone opened at Delta = " << curve[i].delta;
    EXPECT_NEAR(curve[i].delta / curve[i].load, p_I * dcb, 1e-4 * p_I * dcb);
  }
  // Eq. 68 (the DCB's a + chi_I h in place of Hetenyi's terms) is the same to 2e-4.
  const double eq68 = *analytic_load(t, 1, curve.back().delta);
  EXPECT_NEAR(curve.back().load / eq68, 1.0, 2e-4);
}

TEST(CohesiveMmb, OnceTheCrackRunsTheLoadTendsToEq69sAsThePlaneStrengthens) {
  // While the crack grows the energy released goes into the plane's G_c whatever the mode
  // mix (the law is isotropic in the jump, so any radial path dissipates G_c), and the load
  // is LEFM's with G_I + G_II = G_c (eq. 69, and its continuation past mid-span). The zone's
  // own mode mix drifts along its length, so the match is only as good as the zone is short:
  // the load's excess over LEFM past Delta = 1.3 mm (crack past mid-span) shrinks as
  // sigma_c grows.
  const BeamTest t = mmb();
  double previous = 1.0;
  for (double sigma_c : {70e6, 140e6}) {
    const auto curve = cohesive_mmb_curve(t, sigma_c, 2e-3, {0, 400});
    double worst = 0.0;
    int compared = 0;
    for (const CohesiveBeamPoint& p : curve) {
      if (p.delta < 1.3e-3) continue;
      const auto lefm = analytic_load(t, 3, p.delta);
      ASSERT_TRUE(lefm.has_value()) << "Delta = " << p.delta;
      worst = std::max(worst, std::abs(p.load / *lefm - 1.0));
      ++compared;
    }
    EXPECT_GT(compared, 100);
    EXPECT_LT(worst, previous) << "sigma_c = " << sigma_c;
    EXPECT_LT(worst, sigma_c < 100e6 ? 0.015 : 0.005) << "sigma_c = " << sigma_c;
    previous = worst;
    // The crack has run past mid-span, and stays well short of the far support.
    EXPECT_GT(curve.back().crack, t.L);
    EXPECT_LT(curve.back().crack, 2.0 * t.L - 5e-3);
  }
}

TEST(CohesiveMmb, TheLeversLoadPointTravelsAsFarAsInTheLatticeRuns) {
  // The lever is rigid: its load point moves down by the mid-span's deflection plus (that
  // deflection + the end's rise) C / L. The full lattice runs (docs/validation/mmb_*,
  // archived; their rig drives the load point at 0.075 m/s after a 0.5 ms ramp, and turns
  // the lever under its own equations) took it this far to Delta = 1.4 mm: the travel that
  // `cleave validate` now estimates its step count from. A lever that forgot the end's
  // rise, or took the load point at the end, would be 25-50 % off.
  struct Run {
    double beta, time_s, delta_mm, tolerance;
  };
  // Last rows of docs/validation/mmb_{20,50,80}/measured.csv (time, Delta).
  for (const Run& run : {Run{0.2, 0.0358386967, 1.40131431, 0.02}, Run{0.5, 0.0192432052, 1.40346294, 0.02},
                         Run{0.8, 0.0252478418, 1.40072113, 0.10}}) {
    BeamTest t = mmb();
    t.C = mmb_lever_arm(run.beta, t.L);
    const double travel = 0.075 * (run.time_s - 0.25e-3);
    const auto curve = cohesive_mmb_curve(t, 70e6, run.delta_mm * 1e-3, {0, 400});
    ASSERT_FALSE(curve.empty());
    EXPECT_NEAR(curve.back().delta, run.delta_mm * 1e-3, 1e-9);
    EXPECT_NEAR(curve.back().load_point / travel, 1.0, run.tolerance) << "beta = " << run.beta;
    EXPECT_GT(curve.back().load_point, curve.back().delta);  // the load point outruns the end
  }
}

TEST(CohesiveMmb, RefusesWhatItCannotSolve) {
  BeamTest t = mmb();
  EXPECT_THROW(cohesive_mmb_curve(enf(), 70e6, 1e-3), std::invalid_argument);
  EXPECT_THROW(cohesive_mmb_curve(t, 0.0, 1e-3), std::invalid_argument);
  t.g_Ic = 260.0;  // the law has one G_c
  EXPECT_THROW(cohesive_mmb_curve(t, 70e6, 1e-3), std::invalid_argument);
}
