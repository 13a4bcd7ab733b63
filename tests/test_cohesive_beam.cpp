// The DCB as corrected beam theory with a cohesive zone (physics/cohesive_beam.hpp). Checked
// against closed forms at both ends: before the zone opens the arm is a cantilever on
// Winkler's elastic foundation (Hetenyi's semi-infinite beam); while the crack grows the
// J-integral of the arm equals the fracture energy (Paris & Paris: J B' = 2 P theta at the
// load line) and the load is eq. 60's; a stronger plane brings stage I to eq. 59.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "physics/beam_theory.hpp"
#include "physics/cohesive_beam.hpp"

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
