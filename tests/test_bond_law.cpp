// The bond law of sec. 2.3.3 (eqs 2.9-2.16): stiffnesses from the bond section, and each
// failure mode alone, exactly at its limit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "io/sweep.hpp"
#include "physics/bonds/bond_law.hpp"
#include "physics/bonds/bond_batch.hpp"
#include "eigen_reference.hpp"

using namespace cleave::physics;
using cleave::test::same_bits;

namespace {

// Table 2.5's bond parameters (bending and Brazilian tests), read as SI: stiffness per
// area N/m^3, strengths Pa; the bond radius is the 0.05 mm dilation radius.
const BondParams kParams{5000.0, 2000.0, 1000.0, 1000.0};
const BondSection kSection{0.05e-3};
const Eigen::Vector3d kN = Eigen::Vector3d::UnitZ();
const double kDt = 1e-6;

/// Applies one step of relative motion that moves B by `move` and turns it by `turn`.
BondResult push(BondState& s, const Eigen::Vector3d& move, const Eigen::Vector3d& turn) {
  return bond_force(kParams, kSection, kN, move / kDt, turn / kDt, s, kDt);
}

}  // namespace

TEST(BondSection, AreaAndMomentsOfTheCircularSection) {
  const double r = 0.05e-3;
  EXPECT_DOUBLE_EQ(kSection.area(), M_PI * r * r);
  EXPECT_DOUBLE_EQ(kSection.inertia(), M_PI * r * r * r * r / 4);
  EXPECT_DOUBLE_EQ(kSection.polar(), M_PI * r * r * r * r / 2);
}

TEST(BondLaw, ForcesAndMomentsFollowTheBondStiffnesses) {
  const double A = kSection.area(), I = kSection.inertia(), J = kSection.polar();
  BondState s;
  // Open by 1e-9 m: tension K_bn delta pulls B back (eq. 2.12).
  BondResult r = push(s, 1e-9 * kN, Eigen::Vector3d::Zero());
  EXPECT_NEAR(r.force.z(), -kParams.kbn * A * 1e-9, 1e-24);
  // Slide by 2e-9 m along x: shear K_bs delta opposes it.
  r = push(s, Eigen::Vector3d(2e-9, 0, 0), Eigen::Vector3d::Zero());
  EXPECT_NEAR(r.force.x(), -kParams.kbs * A * 2e-9, 1e-24);
  EXPECT_NEAR(r.force.z(), -kParams.kbn * A * 1e-9, 1e-24);  // the opening is still there
  // Bend by 1e-6 rad about x and twist by 2e-6 rad about the normal (eq. 2.13).
  r = push(s, Eigen::Vector3d::Zero(), Eigen::Vector3d(1e-6, 0, 2e-6));
  EXPECT_NEAR(r.moment.x(), -kParams.kbn * I * 1e-6, 1e-30);
  EXPECT_NEAR(r.moment.z(), -kParams.kbs * J * 2e-6, 1e-30);
  EXPECT_EQ(r.failure, BondFailure::none);
  EXPECT_FALSE(s.broken);
}

namespace {

struct Mode {
  BondFailure failure;
  const char* name;
};
class FailureMode : public ::testing::TestWithParam<Mode> {};

/// The motion that brings mode m to `fraction` of its limit (eq. 2.15), alone.
void load(BondFailure m, double fraction, Eigen::Vector3d& move, Eigen::Vector3d& turn) {
  const double r = kSection.radius;
  move.setZero();
  turn.setZero();
  switch (m) {
    case BondFailure::tension:  // K_bn d = t_bn A  ->  d = t_bn / k_bn
      move.z() = fraction * kParams.tbn / kParams.kbn;
      break;
    case BondFailure::shear:  // K_bs d = t_bs A  ->  d = t_bs / k_bs
      move.y() = fraction * kParams.tbs / kParams.kbs;
      break;
    case BondFailure::bending:  // k_bn I theta = t_bn I / r  ->  theta = t_bn / (k_bn r)
      turn.y() = fraction * kParams.tbn / (kParams.kbn * r);
      break;
    case BondFailure::torsion:  // k_bs J theta = t_bs J / r  ->  theta = t_bs / (k_bs r)
      turn.z() = fraction * kParams.tbs / (kParams.kbs * r);
      break;
    case BondFailure::none:
      break;
  }
}

}  // namespace

TEST_P(FailureMode, IntactJustBelowItsLimitBrokenJustAbove) {
  const BondFailure m = GetParam().failure;
  Eigen::Vector3d move, turn;
  BondState below;
  load(m, 1.0 - 1e-9, move, turn);
  BondResult r = push(below, move, turn);
  EXPECT_EQ(r.failure, BondFailure::none);
  EXPECT_FALSE(below.broken);
  EXPECT_GT(r.force.norm() + r.moment.norm(), 0.0);

  BondState above;
  load(m, 1.0 + 1e-9, move, turn);
  r = push(above, move, turn);
  EXPECT_EQ(r.failure, m);
  EXPECT_TRUE(above.broken);
  EXPECT_EQ(r.force.norm() + r.moment.norm(), 0.0);
  // Broken for good: no force however it is loaded afterwards.
  r = push(above, -move, -turn);
  EXPECT_EQ(r.failure, BondFailure::none);
  EXPECT_EQ(r.force.norm() + r.moment.norm(), 0.0);
}

INSTANTIATE_TEST_SUITE_P(Modes, FailureMode,
                         ::testing::Values(Mode{BondFailure::tension, "tension"},
                                           Mode{BondFailure::shear, "shear"},
                                           Mode{BondFailure::bending, "bending"},
                                           Mode{BondFailure::torsion, "torsion"}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(BondLaw, CompressionDoesNotBreakInTension) {
  BondState s;
  // Pressed together far beyond the tensile limit's opening: compression is not tension.
  const BondResult r = push(s, -10.0 * kParams.tbn / kParams.kbn * kN, Eigen::Vector3d::Zero());
  EXPECT_EQ(r.failure, BondFailure::none);
  EXPECT_GT(r.force.z(), 0.0);  // pushes B away
}

namespace cleave::physics {

TEST(BondStrengthFactor, DrawsAWeibullOfUnitMeanAndTheModulusAskedFor) {
  // 20,000 bonds of a 200 x 100 grid of grain pairs: the factors' mean is 1 and their
  // Weibull plot has slope m (the fit of io::fit_weibull, a separate estimator).
  for (const double m : {4.0, 12.0}) {
    std::vector<double> f;
    double sum = 0.0;
    for (int a = 0; a < 200; ++a)
      for (int b = 200; b < 300; ++b) {
        f.push_back(bond_strength_factor(7, a, b, m));
        sum += f.back();
      }
    EXPECT_NEAR(sum / static_cast<double>(f.size()), 1.0, 0.01) << m;
    const io::WeibullFit fit = io::fit_weibull(f);
    EXPECT_NEAR(fit.modulus, m, 0.05 * m);
    EXPECT_NEAR(fit.scale, 1.0 / std::tgamma(1.0 + 1.0 / m), 0.01);
  }
}

TEST(BondStrengthFactor, IsTheSameForEitherOrderOfTheGrainsAndChangesWithTheSeed) {
  int differ = 0;
  for (int a = 0; a < 50; ++a) {
    EXPECT_EQ(bond_strength_factor(3, a, a + 7, 6.0), bond_strength_factor(3, a + 7, a, 6.0));
    if (bond_strength_factor(3, a, a + 7, 6.0) != bond_strength_factor(4, a, a + 7, 6.0)) ++differ;
  }
  EXPECT_EQ(differ, 50);
}

}  // namespace cleave::physics


namespace {

/// One bond as World::bond_forces evaluates it one at a time: bond_motion at width 1 and
/// bond_force.
struct OneBond {
  Eigen::Vector3d point, normal, force, moment;
  BondResult result;
};
OneBond one_bond(const BondLane& l, const BondParams& p, const BondSection& s, double dt) {
  OneBond o;
  const BondMotion<double> m = bond_motion<1>(&l);
  o.point = eigen(m.point);
  o.normal = eigen(m.normal);
  o.result = bond_force(p, *l.constants, s, o.normal, eigen(m.velocity), *l.wb - *l.wa, *l.state, dt);
  o.force = o.result.force;
  o.moment = o.result.moment;
  return o;
}

}  // namespace

// bond_batch at width N (World::bond_forces' common case: four) against the bonds evaluated
// one at a time as World::bond_forces does (width 1): random poses, motions, loads and
// strengths, unloaded springs (into_plane's early out) and every failure mode; each lane to
// the bit.
template <int N>
void lanes_give_the_scalar_bits() {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-9.0, -3.0), f(0.5, 1.5);
  auto vec = [&](double scale) {
    const double x = u(rng), y = u(rng), z = u(rng);
    return Eigen::Vector3d(x * scale, y * scale, z * scale);
  };
  auto turn = [&] {
    const double w = u(rng), x = u(rng), y = u(rng), z = u(rng);
    return Eigen::Quaterniond(w, x, y, z).normalized();
  };
  int failures[5] = {0, 0, 0, 0, 0};
  for (int trial = 0; trial < 10000; ++trial) {
    struct Side {
      Eigen::Vector3d xa, va, wa, xb, vb, wb, shift, arm_a, arm_b, normal_a, normal_b;
      Eigen::Quaterniond qa, qb;
      BondState state;
      BondConstants constants;
      BondLane lane() {
        return {&xa, &va, &wa, &qa, &xb, &vb, &wb, &qb, &shift, &arm_a, &arm_b, &normal_a, &normal_b, &state, &constants};
      }
    } side[N];
    for (Side& b : side) {
      b.xa = vec(5e-3);
      b.xb = b.xa + vec(1e-3);
      b.shift = trial % 4 == 1 ? vec(1e-2) : Eigen::Vector3d::Zero();
      b.qa = turn();
      b.qb = turn();
      const double speed = std::pow(10.0, e(rng)) / kDt, spin = std::pow(10.0, e(rng) + 3.0) / kDt;
      b.va = vec(speed);
      b.vb = vec(speed);
      b.wa = vec(spin);
      b.wb = vec(spin);
      b.arm_a = vec(0.5e-3);
      b.arm_b = vec(0.5e-3);
      b.normal_a = vec(1.0).normalized();
      b.normal_b = b.qb.conjugate() * (b.qa * b.normal_a + vec(0.1)).normalized();
      if (trial % 3 != 0) {  // a third start unloaded (zero springs)
        b.state.normal = 1e-5 * u(rng);
        b.state.shear = vec(2e-5 * std::abs(u(rng)));
        b.state.bending = vec(2e-10 * std::abs(u(rng)));
        b.state.torsion = 4e-10 * u(rng);
      }
      // Each bond its own strengths (World's BondParams times Bond::strength) half the time.
      BondParams p = kParams;
      if (trial % 2 == 0) {
        const double factor = f(rng);
        p.tbn *= factor;
        p.tbs *= factor;
      }
      b.constants = bond_constants(p, kSection);
    }
    Side ref[N];
    OneBond want[N];
    BondLane in[N];
    for (int i = 0; i < N; ++i) {
      ref[i] = side[i];
      want[i] = one_bond(ref[i].lane(), kParams, kSection, kDt);
      in[i] = side[i].lane();
    }
    BondLaneResult got[N];
    bond_batch<N>(in, got, kDt);
    for (int i = 0; i < N; ++i) {
      const OneBond& w = want[i];
      const BondLaneResult& g = got[i];
      ASSERT_EQ(g.failure, w.result.failure) << trial << " lane " << i;
      ASSERT_TRUE(same_bits(eigen(g.point), w.point)) << trial << " lane " << i;
      ASSERT_TRUE(same_bits(eigen(g.normal), w.normal)) << trial << " lane " << i;
      ASSERT_TRUE(same_bits(eigen(g.force), w.force)) << trial << " lane " << i;
      ASSERT_TRUE(same_bits(eigen(g.moment), w.moment)) << trial << " lane " << i;
      // The state after the step (reset when it broke) and the loads that broke it.
      const BondState &gs = side[i].state, &ws = ref[i].state;
      ASSERT_EQ(gs.broken, ws.broken) << trial;
      ASSERT_TRUE(same_bits(gs.shear, ws.shear) && same_bits(gs.bending, ws.bending)) << trial << " lane " << i;
      ASSERT_EQ(std::memcmp(&gs.normal, &ws.normal, sizeof(double)), 0) << trial;
      ASSERT_EQ(std::memcmp(&gs.torsion, &ws.torsion, sizeof(double)), 0) << trial;
      if (w.result.failure != BondFailure::none) {
        const BondState &ga = g.at_failure, &wa = w.result.at_failure;
        ASSERT_TRUE(same_bits(ga.shear, wa.shear) && same_bits(ga.bending, wa.bending)) << trial;
        ASSERT_EQ(std::memcmp(&ga.normal, &wa.normal, sizeof(double)), 0) << trial;
        ASSERT_EQ(std::memcmp(&ga.torsion, &wa.torsion, sizeof(double)), 0) << trial;
      }
      ++failures[static_cast<int>(w.result.failure)];
    }
  }
  // Intact bonds and every failure mode were met, in all lanes together.
  for (int mode = 0; mode < 5; ++mode) EXPECT_GT(failures[mode], 100) << "mode " << mode;
}

TEST(BondLaw, GivesTheSameBitsAtWidthsOneAndTwo) { ASSERT_NO_FATAL_FAILURE(lanes_give_the_scalar_bits<2>()); }

TEST(BondLaw, GivesTheSameBitsAtWidthsOneAndFour) { ASSERT_NO_FATAL_FAILURE(lanes_give_the_scalar_bits<4>()); }
