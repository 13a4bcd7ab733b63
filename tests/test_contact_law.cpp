// The contact law of sec. 2.3.2 (eqs 2.3-2.8) as a pure function, and head-on collisions of
// two prisms in a world: momentum, restitution from C_res, energy without damping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include "geometry/exact_polyhedron.hpp"
#include "eigen_reference.hpp"
#include "physics/dem/contact_law.hpp"
#include "physics/dem/world.hpp"

using namespace cleave;
using namespace cleave::physics;
using cleave::test::eigen_into_plane;
using cleave::test::same_bits;

namespace {
ContactKinematics pressing(double overlap, double vn) {
  ContactKinematics k;
  k.normal = Eigen::Vector3d::UnitZ();
  k.overlap = overlap;
  k.velocity = Eigen::Vector3d(0, 0, vn);
  k.spin = Eigen::Vector3d::Zero();
  k.m_crit = 1e-6;
  k.i_crit = 1e-12;
  k.lever = 1e-4;
  return k;
}
}  // namespace

TEST(ContactLaw, HookeOnLoadingStifferByCresOnUnloading) {
  ContactParams p;
  p.kn = 5e6;
  p.c_res = 2.0;
  p.damping_ratio = 0.0;
  ContactHistory h;
  const double dt = 1e-7;
  // Loading to 2 um: F = Kn delta.
  for (double d : {0.5e-6, 1e-6, 2e-6}) {
    EXPECT_NEAR(contact_force(p, pressing(d, -1.0), h, dt).force.z(), p.kn * d, 1e-9);
  }
  // Unloading: slope C_res Kn from (2 um, 10 N); zero at delta_0 = 2 um (1 - 1/2) = 1 um.
  EXPECT_NEAR(contact_force(p, pressing(1.5e-6, 1.0), h, dt).force.z(), 2 * p.kn * 0.5e-6, 1e-9);
  EXPECT_NEAR(contact_force(p, pressing(1.0e-6, 1.0), h, dt).force.z(), 0.0, 1e-9);
  EXPECT_EQ(contact_force(p, pressing(0.5e-6, 1.0), h, dt).force.z(), 0.0);  // never pulls
  // Reloading follows the unloading line back up to the loading curve.
  EXPECT_NEAR(contact_force(p, pressing(1.8e-6, -1.0), h, dt).force.z(), 2 * p.kn * 0.8e-6, 1e-9);
  EXPECT_NEAR(contact_force(p, pressing(2.5e-6, -1.0), h, dt).force.z(), p.kn * 2.5e-6, 1e-9);
}

TEST(ContactLaw, NormalDampingOpposesTheRelativeNormalVelocity) {
  ContactParams p;
  p.kn = 5e6;
  p.c_res = 2.0;
  ContactHistory h1, h2;
  const auto k_in = pressing(1e-6, -0.5), k_out = pressing(1e-6, 0.0);
  const double with = contact_force(p, k_in, h1, 1e-7).force.z();
  const double without = contact_force(p, k_out, h2, 1e-7).force.z();
  // eq 2.6: 0.1 sqrt(C_res Kn m_crit) times the normal speed.
  EXPECT_NEAR(with - without, 0.1 * std::sqrt(2.0 * 5e6 * 1e-6) * 0.5, 1e-12);
}

TEST(ContactLaw, ShearSpringIsCappedByCoulomb) {
  ContactParams p;
  p.kn = 5e6;
  p.ks = 2e6;
  p.mu_s = 0.3;
  p.damping_ratio = 0.0;
  ContactHistory h;
  auto k = pressing(1e-6, 0.0);
  k.velocity = Eigen::Vector3d(0.1, 0, 0);  // B slides along +x relative to A
  const double dt = 1e-6;
  // Elastic while |Fs| < mu Fn: Fs = -Ks * (0.1 dt) per step.
  ContactForce f = contact_force(p, k, h, dt);
  EXPECT_NEAR(f.force.x(), -p.ks * 0.1 * dt, 1e-12);
  EXPECT_FALSE(f.sliding);
  for (int i = 0; i < 100; ++i) f = contact_force(p, k, h, dt);
  EXPECT_TRUE(f.sliding);
  EXPECT_NEAR(f.force.x(), -0.3 * p.kn * 1e-6, 1e-12);  // mu Fn, opposing the slip
}

TEST(ContactLaw, RollingMomentOpposesRelativeRollingAndIsCapped) {
  ContactParams p;
  p.kn = 5e6;
  p.kr = 1e-3;
  p.kt = 1e-3;
  p.mu_r = 0.5;
  p.damping_ratio = 0.0;
  ContactHistory h;
  auto k = pressing(1e-6, 0.0);
  k.spin = Eigen::Vector3d(2.0, 0, 3.0);  // rolling about x, twisting about z
  const ContactForce f = contact_force(p, k, h, 1e-6);
  EXPECT_NEAR(f.moment.x(), -p.kr * 2.0 * 1e-6, 1e-15);
  EXPECT_NEAR(f.moment.z(), -p.kt * 3.0 * 1e-6, 1e-15);
  ContactHistory h2;
  k.spin = Eigen::Vector3d(1e6, 0, 0);
  const ContactForce capped = contact_force(p, k, h2, 1e-6);
  EXPECT_NEAR(std::abs(capped.moment.x()), 0.5 * p.kn * 1e-6 * k.lever, 1e-15);
}

namespace {

struct Collision {
  Eigen::Vector3d p_before, p_after;
  double v_rel_before = 0, v_rel_after = 0, ke_before = 0, ke_after = 0;
};

/// Two equal hexagonal prisms (r = 0.5 mm, t = 1 mm, SiC) fly at each other along z, basal
/// faces first (B turned 10 degrees about z), with no gravity, damping or friction.
Collision head_on(double c_res) {
  WorldSettings ws;
  ws.gravity.setZero();
  ws.particle_particle.kn = 5e6;  // table 2.3's 5000 read as N/mm
  ws.particle_particle.ks = 2e6;
  ws.particle_particle.c_res = c_res;
  ws.particle_particle.damping_ratio = 0.0;
  const auto prism = geometry::ExactPolyhedron::hexagonal_prism(0.5e-3, 1e-3);
  const RigidShape shape = make_rigid_shape(prism, 0.05e-3);
  const double mass = 3100.0 * shape.volume;
  // Contact lasts about pi sqrt(m_red / (n Kn)); resolve it with ~400 steps.
  ws.dt = 3.14159 * std::sqrt(0.5 * mass / (6 * c_res * ws.particle_particle.kn)) / 400;
  World world(ws);
  const auto sh = world.add_shape(shape);
  const Eigen::Quaterniond qa = shape.orientation_for();
  const Eigen::Quaterniond qb =
      shape.orientation_for(Eigen::Quaterniond(Eigen::AngleAxisd(0.1745, Eigen::Vector3d::UnitZ())));
  const double gap = 1e-3 + 2 * 0.05e-3 + 2e-6;  // thickness + two dilations + 2 um apart
  const BodyId a = world.add_body(sh, 3100.0, Eigen::Vector3d(0.02e-3, 0.01e-3, 0.0), qa,
                                  Eigen::Vector3d(0, 0, 0.05));
  const BodyId b = world.add_body(sh, 3100.0, Eigen::Vector3d(0.0, 0.0, gap), qb,
                                  Eigen::Vector3d(0, 0, -0.05));
  Collision c;
  c.p_before = world.linear_momentum();
  c.v_rel_before = world.state(b).v.z() - world.state(a).v.z();
  c.ke_before = world.kinetic_energy();
  bool touched = false;
  for (int i = 0; i < 100000; ++i) {
    world.step();
    if (!world.contacts().empty()) touched = true;
    if (touched && world.contacts().empty()) break;
  }
  EXPECT_TRUE(touched);
  c.p_after = world.linear_momentum();
  c.v_rel_after = world.state(b).v.z() - world.state(a).v.z();
  c.ke_after = world.kinetic_energy();
  return c;
}

class HeadOnCollision : public ::testing::TestWithParam<double> {};

}  // namespace

TEST_P(HeadOnCollision, RestitutionIsOneOverSqrtCres) {
  const double c_res = GetParam();
  const Collision c = head_on(c_res);
  // Linear momentum: internal forces cancel exactly pair by pair.
  EXPECT_NEAR((c.p_after - c.p_before).norm(), 0.0, 1e-15);
  const double e = -c.v_rel_after / c.v_rel_before;
  EXPECT_NEAR(e, 1.0 / std::sqrt(c_res), 0.01);
  if (c_res == 1.0) {
    EXPECT_NEAR(c.ke_after / c.ke_before, 1.0, 1e-3);  // energy comes back
  }
}

INSTANTIATE_TEST_SUITE_P(Cres, HeadOnCollision, ::testing::Values(1.0, 2.0, 4.0));

TEST(CriticalTimeStep, IsTwiceSqrtMassOverStiffness) {
  EXPECT_DOUBLE_EQ(critical_time_step(4.0, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(critical_time_step(1e-6, 1e8), 2e-7);
}

namespace {

/// Random draws for the law's bit tests: u uniform in [-1, 1), e in [-8, 0) (decades),
/// vectors of a scale, and parameters near table 2.3's (rolling and torsion on when asked).
struct LawDraws {
  std::mt19937_64 rng;
  std::uniform_real_distribution<double> u{-1.0, 1.0}, e{-8.0, 0.0};
  explicit LawDraws(std::uint64_t seed) : rng(seed) {}
  Eigen::Vector3d vec(double scale) {
    const double x = u(rng), y = u(rng), z = u(rng);
    return Eigen::Vector3d(x * scale, y * scale, z * scale);
  }
  ContactParams params(bool rolling) {
    ContactParams p;
    p.kn = 5e6 * (1.0 + u(rng));
    p.ks = 2e6 * (1.0 + u(rng));
    p.c_res = 1.0 + std::abs(u(rng));
    p.mu_s = 0.3 + 0.2 * u(rng);
    if (rolling) {
      p.kr = 1e-3 * (1.0 + u(rng));
      p.kt = 1e-3 * (1.0 + u(rng));
      p.mu_r = 0.1;
    }
    return p;
  }
};

}  // namespace

TEST(SurelyShorter, NeverClaimsALengthAtOrAboveTheLimitAndSeesTheClearlyShorter) {
  // The caps' test without the square root (vec3.hpp): whenever it says |a| < limit, the
  // correctly rounded root must be below limit. Random vectors over 60 decades, against
  // limits a few ulps from their length and within 4e-6 of it either side (its margin is
  // 2^-20, about 1e-6), and against clearly longer limits, which it must see.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-30.0, 30.0), r(-4e-6, 4e-6);
  std::uniform_int_distribution<int> ulps(-8, 8);
  int claimed = 0, left = 0;
  for (int trial = 0; trial < 400000; ++trial) {
    const double scale = std::pow(10.0, e(rng));
    const V3 a{u(rng) * scale, u(rng) * scale, u(rng) * scale};
    const double len = norm(a);
    double limit = len * (1.0 + r(rng));
    if (trial % 2) {
      limit = len;
      const int k = ulps(rng);
      for (int i = 0; i < std::abs(k); ++i) limit = std::nextafter(limit, k > 0 ? HUGE_VAL : 0.0);
    }
    if (surely_shorter(a, limit)) {
      ++claimed;
      ASSERT_LT(norm(a), limit) << trial;
    } else {
      ++left;
    }
    ASSERT_TRUE(surely_shorter(a, len * (1.0 + 1e-5))) << trial;
    ASSERT_FALSE(surely_shorter(a, len)) << trial;
  }
  EXPECT_GT(claimed, 40000);  // both answers were given near the margin
  EXPECT_GT(left, 200000);
  const V3 nan{std::nan(""), 0.0, 0.0};
  EXPECT_FALSE(surely_shorter(nan, 1.0));
  EXPECT_FALSE(surely_shorter(V3{1e-200, 0.0, 0.0}, 1e-160));  // limit^2 not normal: the root decides
}


TEST(ContactLaw, GivesTheSameBitsAtWidthsOneAndFour) {
  // contact_forces<4> against contact_force (the law at width 1), lane by lane, to the bit:
  // random quads over every branch (loading and unloading, sliding and sticking, rolling
  // capped or not, torsion clamped either side, springs along the normal, no overlap, fresh
  // histories), each lane its own coefficients. A lane's result that depended on its
  // neighbours', or a select that differed from the branch, fails it.
  LawDraws draw(17);
  auto& rng = draw.rng;
  auto& u = draw.u;
  auto& e = draw.e;
  auto vec = [&](double scale) { return draw.vec(scale); };
  int sliding = 0, sticking = 0, rolled_capped = 0, clamped_low = 0, clamped_high = 0,
      unloading = 0, apart = 0;
  for (int trial = 0; trial < 10000; ++trial) {
    ContactParams p = draw.params(trial % 2 != 0);  // rolling and torsion every other quad
    p.damping_ratio = trial % 5 == 0 ? 0.0 : 0.1;
    ContactKinematics k[4];
    ContactDamping d[4];
    ContactHistory h[4], h_ref[4];
    ContactForce got[4];
    for (int i = 0; i < 4; ++i) {
      k[i].normal = vec(1.0).normalized();
      k[i].overlap = 1e-6 * u(rng);
      k[i].velocity = vec(std::pow(10.0, e(rng)));
      k[i].spin = vec(std::pow(10.0, e(rng)));
      k[i].lever = 1e-4 * (1.0 + u(rng));
      d[i] = contact_damping(p, 1e-6 * (1.0 + u(rng)), 1e-12 * (1.0 + u(rng)));
      const int kind = static_cast<int>(rng() % 6);
      if (kind != 0) {  // fresh otherwise (zero springs: into_plane's early out)
        h[i].shear = vec(10.0 * std::pow(10.0, e(rng) / 4.0));
        h[i].rolling = vec(1e-6 * std::pow(10.0, e(rng)));
        h[i].torsion = 1e-6 * u(rng);
        h[i].max_overlap = 1e-6 * std::abs(u(rng));
      }
      if (kind == 1) {  // springs along the normal (nothing left across it)
        h[i].shear = 3.0 * k[i].normal;
        h[i].rolling = -1e-7 * k[i].normal;
      }
      if (kind == 2) h[i].torsion = (rng() % 2 ? 1.0 : -1.0) * 1e-3;  // far past the cap
      h_ref[i] = h[i];
    }
    const ContactKinematics* in[4] = {&k[0], &k[1], &k[2], &k[3]};
    const ContactDamping* dp[4] = {&d[0], &d[1], &d[2], &d[3]};
    ContactHistory* hp[4] = {&h[0], &h[1], &h[2], &h[3]};
    ContactForce* out[4] = {&got[0], &got[1], &got[2], &got[3]};
    got[trial % 4].moment = Eigen::Vector3d::Constant(7.0);  // must come back zero (or set)
    contact_forces<4>(p, in, dp, hp, out, 1e-6);
    for (int i = 0; i < 4; ++i) {
      const double torsion_before = h_ref[i].torsion;
      const ContactForce want = contact_force(p, k[i], d[i], h_ref[i], 1e-6);
      ASSERT_TRUE(same_bits(got[i].force, want.force)) << trial << " lane " << i;
      ASSERT_TRUE(same_bits(got[i].moment, want.moment)) << trial << " lane " << i;
      ASSERT_EQ(got[i].sliding, want.sliding) << trial << " lane " << i;
      ASSERT_TRUE(same_bits(h[i].shear, h_ref[i].shear)) << trial << " lane " << i;
      ASSERT_TRUE(same_bits(h[i].rolling, h_ref[i].rolling)) << trial << " lane " << i;
      ASSERT_EQ(std::memcmp(&h[i].torsion, &h_ref[i].torsion, sizeof(double)), 0) << trial;
      ASSERT_EQ(std::memcmp(&h[i].max_overlap, &h_ref[i].max_overlap, sizeof(double)), 0) << trial;
      (want.sliding ? sliding : sticking) += 1;
      if (k[i].overlap <= 0.0) ++apart;
      if (k[i].overlap > 0.0 && h_ref[i].max_overlap > k[i].overlap) ++unloading;
      if (p.kr > 0.0) {
        const double wt = k[i].spin.dot(k[i].normal);
        const double free_torsion = torsion_before - p.kt * 1e-6 * wt;
        if (h_ref[i].torsion != free_torsion) (h_ref[i].torsion > free_torsion ? clamped_low : clamped_high) += 1;
        const double fn = want.force.dot(k[i].normal);
        if (h_ref[i].rolling.norm() > 0.0 && h_ref[i].rolling.norm() >= 0.999 * p.mu_r * std::abs(fn) * k[i].lever)
          ++rolled_capped;
      }
    }
  }
  // Every branch was taken many times.
  EXPECT_GT(sliding, 2000);
  EXPECT_GT(sticking, 2000);
  EXPECT_GT(rolled_capped, 500);
  EXPECT_GT(clamped_low, 500);
  EXPECT_GT(clamped_high, 500);
  EXPECT_GT(unloading, 2000);
  EXPECT_GT(apart, 2000);
}
