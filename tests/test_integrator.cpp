// Rigid-body integration: free fall against 1/2 g t^2, and the torque-free asymmetric body
// (energy and angular momentum bounded over 1e5 steps, the intermediate-axis flip).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "eigen_reference.hpp"
#include "geometry/exact_polyhedron.hpp"
#include "physics/dem/integrator.hpp"
#include "physics/dem/world.hpp"

using namespace cleave;
using namespace cleave::physics;
using cleave::test::same_bits;

namespace {

geometry::ExactPolyhedron cuboid(double a, double b, double c) {
  geometry::PolygonMesh m;
  m.vertices = {{0, 0, 0}, {a, 0, 0}, {a, b, 0}, {0, b, 0},
                {0, 0, c}, {a, 0, c}, {a, b, c}, {0, b, c}};
  m.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  return geometry::ExactPolyhedron::from_mesh(m);
}

const double kRho = 3100.0;  // SiC, specific gravity 3.10 (table 2.3)

WorldSettings settings(const Eigen::Vector3d& gravity, double dt) {
  WorldSettings s;
  s.gravity = gravity;
  s.dt = dt;
  return s;
}

class FreeFall : public ::testing::TestWithParam<double> {};

}  // namespace

TEST_P(FreeFall, MatchesHalfGTSquared) {
  const double dt = GetParam();
  World world(settings(Eigen::Vector3d(0, 0, -9.81), dt));
  const auto shape = world.add_shape(
      make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(0.5e-3, 1e-3), 0.05e-3));
  const Eigen::Vector3d x0(0.01, -0.02, 0.05);
  const Eigen::Vector3d v0(0.3, 0.0, 1.0);
  const BodyId id = world.add_body(shape, kRho, x0, Eigen::Quaterniond::Identity(), v0,
                                   Eigen::Vector3d(0, 20, 5));
  const int n = static_cast<int>(std::lround(0.1 / dt));
  for (int i = 0; i < n; ++i) world.step();
  const double t = n * dt;
  const BodyState& s = world.state(id);
  // Velocity Verlet integrates a constant acceleration exactly: only round-off remains.
  const Eigen::Vector3d x_exact = x0 + v0 * t + 0.5 * Eigen::Vector3d(0, 0, -9.81) * t * t;
  EXPECT_NEAR((s.x - x_exact).norm(), 0.0, 1e-12 + 1e-13 * n);
  EXPECT_NEAR(s.v.z(), v0.z() - 9.81 * t, 1e-12 + 1e-14 * n);
  EXPECT_NEAR(world.time(), t, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(TimeSteps, FreeFall, ::testing::Values(1e-3, 1e-4, 2.5e-5));

namespace {

struct Spin {
  World world{settings(Eigen::Vector3d::Zero(), 1.0)};
  BodyId id;
  Eigen::Vector3d moments;
};

/// A 1 x 2 x 3 mm SiC brick (three distinct principal moments) spun with body-frame angular
/// velocity w_body; dt chosen so the body turns `turn_per_step` radians per step.
void make_spin(Spin& s, const Eigen::Vector3d& w_body, double turn_per_step) {
  const RigidShape shape = make_rigid_shape(cuboid(1e-3, 2e-3, 3e-3), 0.0);
  s.world = World(settings(Eigen::Vector3d::Zero(), turn_per_step / w_body.norm()));
  const auto sh = s.world.add_shape(shape);
  const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  s.id = s.world.add_body(sh, kRho, Eigen::Vector3d::Zero(), q, Eigen::Vector3d::Zero(), q * w_body);
  s.moments = s.world.info(s.id).inertia;
}

}  // namespace

TEST(TorqueFreeBody, PrincipalMomentsOfTheBrickMatchTheClosedForm) {
  const RigidShape shape = make_rigid_shape(cuboid(1e-3, 2e-3, 3e-3), 0.0);
  const double V = 6e-9;
  // I = m/12 (b^2 + c^2) etc., ascending: (1+4), (1+9), (4+9) mm^2.
  EXPECT_NEAR(shape.principal_moments[0], V / 12 * 5e-6, 1e-12 * V * 1e-6);
  EXPECT_NEAR(shape.principal_moments[1], V / 12 * 10e-6, 1e-12 * V * 1e-6);
  EXPECT_NEAR(shape.principal_moments[2], V / 12 * 13e-6, 1e-12 * V * 1e-6);
}

TEST(TorqueFreeBody, EnergyAndAngularMomentumStayBoundedOver1e5Steps) {
  Spin s;
  make_spin(s, Eigen::Vector3d(40.0, 25.0, -30.0), 0.01);
  const double e0 = s.world.kinetic_energy();
  const Eigen::Vector3d l0 = s.world.angular_momentum();
  const int steps = 100000;
  double first_window = 0.0, last_window = 0.0, worst_l = 0.0;
  for (int i = 0; i < steps; ++i) {
    s.world.step();
    const double de = std::abs(s.world.kinetic_energy() - e0) / e0;
    if (i < steps / 10) first_window = std::max(first_window, de);
    if (i >= steps - steps / 10) last_window = std::max(last_window, de);
    worst_l = std::max(worst_l, (s.world.angular_momentum() - l0).norm() / l0.norm());
  }
  RecordProperty("energy_error_first", std::to_string(first_window));
  RecordProperty("energy_error_last", std::to_string(last_window));
  EXPECT_LT(std::max(first_window, last_window), 1e-5);
  // No secular drift: the error at the end is no larger than at the start.
  EXPECT_LT(last_window, 2.0 * first_window + 1e-12);
  EXPECT_LT(worst_l, 1e-12);
}

namespace {
/// Counts how often the body's axis `axis` reverses relative to the angular momentum.
int flips_of_axis(Spin& s, int axis, int steps) {
  const Eigen::Vector3d L = s.world.angular_momentum();
  auto sign = [&] {
    const Eigen::Vector3d e = s.world.state(s.id).q * Eigen::Vector3d::Unit(axis);
    return e.dot(L) > 0.0;
  };
  bool last = sign();
  int flips = 0;
  for (int i = 0; i < steps; ++i) {
    s.world.step();
    const bool now = sign();
    flips += now != last;
    last = now;
  }
  return flips;
}
}  // namespace

TEST(TorqueFreeBody, SpinAboutTheIntermediateAxisFlips) {
  // Dzhanibekov effect: rotation about the middle principal axis is unstable; a tiny
  // perturbation grows and the body turns over again and again.
  Spin middle;
  make_spin(middle, Eigen::Vector3d(1e-3, 50.0, 1e-3), 0.01);
  const int flips = flips_of_axis(middle, 1, 100000);
  RecordProperty("middle_axis_flips", flips);
  EXPECT_GE(flips, 2);
  // About the smallest and largest axes the same perturbation stays small: no flip.
  Spin low, high;
  make_spin(low, Eigen::Vector3d(50.0, 1e-3, 1e-3), 0.01);
  make_spin(high, Eigen::Vector3d(1e-3, 1e-3, 50.0), 0.01);
  EXPECT_EQ(flips_of_axis(low, 0, 100000), 0);
  EXPECT_EQ(flips_of_axis(high, 2, 100000), 0);
}

TEST(World, StaleIdsAreDetected) {
  World world;
  const auto sh = world.add_shape(make_rigid_shape(cuboid(1e-3, 1e-3, 1e-3), 0.0));
  const BodyId a = world.add_body(sh, kRho, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  world.remove_body(a);
  const BodyId b = world.add_body(sh, kRho, Eigen::Vector3d::Ones(), Eigen::Quaterniond::Identity());
  EXPECT_EQ(a.index, b.index);  // the slot is reused ...
  EXPECT_FALSE(world.contains(a));  // ... but the old handle is stale
  EXPECT_TRUE(world.contains(b));
  EXPECT_THROW((void)world.state(a), std::out_of_range);
  EXPECT_EQ(world.body_count(), 1u);
}

TEST(World, ABodyInARemovedBodysSlotStartsWithoutItsContactHistory) {
  // A grain rests on a friction floor, its shear springs loaded by a sideways push; it is
  // removed and a new grain placed in the same slot, at rest: the new grain must feel no
  // leftover shear force.
  WorldSettings ws = settings(Eigen::Vector3d(0, 0, -9.81), 1e-6);
  ws.particle_wall.kn = 1e4;
  ws.particle_wall.ks = 1e4;
  ws.particle_wall.mu_s = 0.5;
  World world(ws);
  const RigidShape cube = make_rigid_shape(cuboid(1e-3, 1e-3, 1e-3), 0.05e-3);
  const auto sh = world.add_shape(cube);
  world.add_wall(Wall::plane("floor", {0, 0, 0}, {0, 0, 1}));
  // Pressed into the floor by about its weight's share: 4 corners x kn x 0.77 nm.
  const Eigen::Vector3d at(0, 0, 0.5e-3 + 0.05e-3 - 0.77e-9);
  const BodyId first =
      world.add_body(sh, kRho, at, cube.orientation_for(), Eigen::Vector3d(0.01, 0, 0));
  for (int i = 0; i < 50; ++i) world.step();  // sliding loads the shear springs
  double shear = 0.0;
  for (const auto& c : world.contacts()) shear += std::abs(c.force.x());
  ASSERT_GT(shear, 0.0);
  world.remove_body(first);
  const BodyId second = world.add_body(sh, kRho, at, cube.orientation_for());
  ASSERT_EQ(second.index, first.index);
  world.step();
  // One step of a body at rest: the shear springs hold only that step's tiny increment.
  double fresh = 0.0;
  for (const auto& c : world.contacts()) fresh += std::abs(c.force.x());
  EXPECT_LT(fresh, 1e-3 * shear);
}

namespace {

/// The splitting X(h/2) Y(h/2) Z(h) Y(h/2) X(h/2) written out plainly, with the library's
/// sine and cosine at every sub-flow: the reference the integrator's shortcuts must equal.
Eigen::Quaterniond reference_rotate_free(Eigen::Quaterniond q, const Eigen::Vector3d& L,
                                         const Eigen::Vector3d& inv_inertia, double h) {
  Eigen::Vector3d pi = rotated(q.conjugate(), L);
  const int axes[5] = {0, 1, 2, 1, 0};
  const double steps[5] = {0.5 * h, 0.5 * h, h, 0.5 * h, 0.5 * h};
  for (int s = 0; s < 5; ++s) {
    const int k = axes[s], i = (k + 1) % 3, j = (k + 2) % 3;
    const double theta = steps[s] * pi[k] * inv_inertia[k];
    const double ch = std::cos(0.5 * theta), sh = std::sin(0.5 * theta);
    const double c = 1.0 - 2.0 * sh * sh, sn = 2.0 * sh * ch;
    const double pi_i = pi[i], pi_j = pi[j];
    pi[i] = c * pi_i + sn * pi_j;
    pi[j] = -sn * pi_i + c * pi_j;
    Eigen::Quaterniond r(ch, 0.0, 0.0, 0.0);
    r.vec()[k] = sh;
    q = q * r;
  }
  q.normalize();
  return q;
}

bool same_bits(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return std::memcmp(a.coeffs().data(), b.coeffs().data(), 4 * sizeof(double)) == 0;
}

/// A body of random pose and angular momentum whose sub-flows turn it by about 10^e rad.
void random_body(std::mt19937_64& rng, BodyState& s, BodyInfo& b, double h, double e) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  s.x = {u(rng), u(rng), u(rng)};
  s.v = {u(rng), u(rng), u(rng)};
  s.q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
  b.inv_inertia = Eigen::Vector3d(1.0 + 0.5 * u(rng), 2.0 + u(rng), 3.0 + u(rng)) * 1e9;
  s.L = Eigen::Vector3d(u(rng), u(rng), u(rng)) * (std::pow(10.0, e) / (h * 3e9));
}

}  // namespace

TEST(Integrator, TinyHalfAnglesSkipTheSineAndCosineWithTheSameBits) {
  // Below 2^-27 the library's sine is the angle and its cosine 1, to the bit: the shortcut
  // the integrator takes there.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> exponent(-320.0, std::log10(0x1p-27));
  std::vector<double> xs = {0.0, -0.0, std::nextafter(0x1p-27, 0.0), -std::nextafter(0x1p-27, 0.0), 1e-310};
  for (int k = 0; k < 20000; ++k) xs.push_back((k % 2 ? -1.0 : 1.0) * std::pow(10.0, exponent(rng)));
  for (double x : xs) {
    ASSERT_EQ(std::sin(x), x) << x;
    ASSERT_EQ(std::cos(x), 1.0) << x;
  }
  // And a free rotation at any angle, tiny ones included, is the plain splitting's to the bit.
  const double h = 1e-6;
  int tiny = 0;
  for (int k = 0; k < 6000; ++k) {
    BodyState s;
    BodyInfo b;
    random_body(rng, s, b, h, -14.0 + 13.0 * (k % 14) / 13.0);
    tiny += std::abs(0.5 * h * s.L.norm() * 3e9) < 0x1p-27;
    const Eigen::Quaterniond want = reference_rotate_free(s.q, s.L, b.inv_inertia, h);
    rotate_free(s.q, s.L, b.inv_inertia, h);
    ASSERT_TRUE(same_bits(s.q, want)) << "body " << k;
  }
  EXPECT_GT(tiny, 1000);  // the shortcut was taken
}

/// n random bodies twice over (`one`, stepped one at a time, and `many`, as a batch), with
/// pointers to the batch.
struct BodyBatch {
  int n = 0;
  BodyState one[kDriftBatch], many[kDriftBatch];
  BodyInfo info[kDriftBatch];
  BodyState* ptr[kDriftBatch];
  const BodyInfo* info_ptr[kDriftBatch];
  /// Makes body m with `make(state, info, m)`, then copies it into the batch.
  template <class Make>
  BodyBatch(int count, Make&& make) : n(count) {
    for (int m = 0; m < n; ++m) {
      make(one[m], info[m], m);
      many[m] = one[m];
      ptr[m] = &many[m];
      info_ptr[m] = &info[m];
    }
  }
};

// The batch drift (four bodies side by side, three as two and one, ...) gives each body the
// bits of its own drift (width 1): orientations, momenta from 1e-12 to 1 (tiny half angles
// and large ones), bodies that do not turn among those that do.
TEST(Integrator, TheDriftGivesTheSameBitsAtWidthsOneTwoAndFour) {
  std::mt19937_64 rng(11);
  const double h = 1e-6;
  for (int trial = 0; trial < 8000; ++trial) {
    BodyBatch b(1 + trial % kDriftBatch, [&](BodyState& s, BodyInfo& info, int m) {
      random_body(rng, s, info, h, -12.0 + 12.0 * ((trial + m) % 7) / 6.0);
      if ((trial + m) % 5 == 0) s.L.setZero();  // a body that does not turn
    });
    for (int m = 0; m < b.n; ++m) drift(b.one[m], b.info[m], h);
    drift(b.ptr, b.info_ptr, b.n, h);
    for (int m = 0; m < b.n; ++m) {
      ASSERT_TRUE(same_bits(b.many[m].q, b.one[m].q)) << "trial " << trial << " body " << m;
      ASSERT_TRUE(same_bits(b.many[m].x, b.one[m].x));
      ASSERT_TRUE(same_bits(b.many[m].w, b.one[m].w));
    }
  }
}

// The closing kick four bodies at a time (their angular velocities side by side) gives each
// body the bits of its own kick (width 1): random orientations, momenta, forces and torques,
// bodies at rest among them.
TEST(Integrator, TheKickGivesTheSameBitsAtWidthsOneTwoAndFour) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double h = 1e-6;
  for (int trial = 0; trial < 8000; ++trial) {
    BodyBatch b(1 + trial % kDriftBatch, [&](BodyState& s, BodyInfo& info, int m) {
      random_body(rng, s, info, h, -12.0 + 12.0 * ((trial + m) % 7) / 6.0);
      info.inv_mass = 1e6 * (1.0 + 0.5 * u(rng));
      s.f = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1e-3;
      s.tau = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1e-9;
      if ((trial + m) % 5 == 0) s.L.setZero(), s.tau.setZero();  // a body at rest
    });
    for (int m = 0; m < b.n; ++m) kick(b.one[m], b.info[m], 0.5 * h);
    kick(b.ptr, b.info_ptr, b.n, 0.5 * h);
    for (int m = 0; m < b.n; ++m) {
      ASSERT_TRUE(same_bits(b.many[m].w, b.one[m].w)) << "trial " << trial << " body " << m;
      ASSERT_TRUE(same_bits(b.many[m].v, b.one[m].v));
      ASSERT_TRUE(same_bits(b.many[m].L, b.one[m].L));
    }
  }
}

// angular_velocity in scalars against its Eigen form, w = R I^-1 R^T L, to the bit.
TEST(Integrator, AngularVelocityInScalarsGivesTheBitsOfItsEigenForm) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-12.0, 2.0);
  for (int t = 0; t < 200000; ++t) {
    Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
    q.normalize();
    if (t % 9 == 0) q = Eigen::Quaterniond::Identity();
    const Eigen::Vector3d L = Eigen::Vector3d(u(rng), u(rng), t % 5 == 0 ? -0.0 : u(rng)) * std::pow(10.0, e(rng));
    const Eigen::Vector3d inv(std::pow(10.0, e(rng) + 8.0), std::pow(10.0, e(rng) + 8.0), std::pow(10.0, e(rng) + 8.0));
    const Eigen::Vector3d want = rotated(q, inv.cwiseProduct(rotated(q.conjugate(), L)));
    const Eigen::Vector3d got = angular_velocity(q, L, inv);
    ASSERT_TRUE(cleave::test::same_bits(got, want)) << t;
  }
}

// Local damping (Cundall's, table 2.3's alpha): each force component loses alpha of its size
// against the sign of that velocity component: F_c - alpha |F_c| sgn(v_c).
TEST(LocalDamping, EachForceComponentLosesAlphaOfItsSizeAgainstItsVelocity) {
  const Eigen::Vector3d g(3.0, -4.0, 5.0);
  WorldSettings ws = settings(g, 1e-7);
  ws.local_damping = 0.7;
  World world(ws);
  const auto sh = world.add_shape(make_rigid_shape(cuboid(1e-3, 1e-3, 1e-3), 0.0));
  const BodyId id = world.add_body(sh, kRho, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  // The kicks of one step (1e-6 m/s) keep the velocities' signs.
  world.state(id).v = Eigen::Vector3d(1.0, 2.0, -1.0);
  world.step();
  const double m = world.info(id).mass;
  const Eigen::Vector3d f = world.state(id).f;
  EXPECT_DOUBLE_EQ(f.x(), m * 3.0 * (1.0 - 0.7));   // v_x > 0: 3m - 0.7 (3m)
  EXPECT_DOUBLE_EQ(f.y(), m * -4.0 * (1.0 + 0.7));  // v_y > 0: -4m - 0.7 (4m)
  EXPECT_DOUBLE_EQ(f.z(), m * 5.0 * (1.0 + 0.7));   // v_z < 0: 5m + 0.7 (5m)
}
