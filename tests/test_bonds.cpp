// Bonds in the world (sec. 2.3.3 of seed 000): bond initialisation with stored overlaps,
// the bond stiffness of a bonded chain against the series-spring formula, a bonded
// specimen at rest, and each failure mode of eq. 2.16 alone, exactly at its limit, under a
// prescribed motion; the gallop that finds a contact's bond.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "geometry/exact_polyhedron.hpp"
#include "physics/dem/gallop.hpp"
#include "physics/dem/world.hpp"
#include "prism_row.hpp"
#include "stress_sum_reference.hpp"

using namespace cleave;
using namespace cleave::physics;
using namespace cleave::test;

namespace {

/// Table 2.5 read as in scenarios/: bond springs of 5000 N/m and 2000 N/m on the section of
/// the dilation radius (eq. 2.10), strengths 1000 Pa.
BondParams table_2_5() {
  const double area = M_PI * kDilation * kDilation;
  return {5000.0 / area, 2000.0 / area, 1000.0, 1000.0};
}

ContactParams contact_law() {
  ContactParams p;
  p.kn = 5000.0;
  p.ks = 2000.0;
  p.c_res = 2.0;
  p.mu_s = 0.3;
  return p;
}

World make_world(double dt, double local_damping = 0.0) {
  WorldSettings ws;
  ws.gravity.setZero();
  ws.dt = dt;
  ws.particle_particle = contact_law();
  ws.particle_wall = contact_law();
  ws.local_damping = local_damping;
  ws.threads = 1;
  return World(ws);
}

}  // namespace

TEST(BondInitialisation, BondsEveryPairWithinTheBondingDistanceAndStoresOverlaps) {
  World world = make_world(1e-7);
  // Three prisms 4 um apart (gap between dilated surfaces), then a fourth 30 um away.
  auto ids = row(world, 3, -4e-6);
  const RigidShape shape = prism();
  ids.push_back(world.add_body(0, kRho, {2 * (kFlat + 2 * kDilation + 4e-6) + kFlat + 2 * kDilation + 30e-6, 0, 0},
                               shape.orientation_for()));
  EXPECT_EQ(world.initialise_bonds(table_2_5(), 5e-6), 2u);
  for (const Bond& b : world.bonds()) {
    EXPECT_TRUE(b.initial.empty());  // not touching: nothing to store
    EXPECT_NEAR(std::abs(b.normal.x()), 1.0, 1e-12);
    EXPECT_DOUBLE_EQ(b.section.radius, kDilation);
    // The bond point lies midway between the two side faces.
    const double mid = 0.5 * (world.state(ids[b.a]).x.x() + world.state(ids[b.b]).x.x());
    EXPECT_NEAR(b.point.x(), mid, 1e-12);
  }
  EXPECT_THROW(world.initialise_bonds(table_2_5(), 5e-6), std::logic_error);

  // Overlapping neighbours: the overlaps are stored, so nothing pushes them apart.
  World pressed = make_world(1e-7);
  row(pressed, 2, 6e-6);
  ASSERT_EQ(pressed.initialise_bonds(table_2_5(), 0.0), 1u);
  const Bond& b = pressed.bonds().front();
  ASSERT_FALSE(b.initial.empty());
  for (const auto& o : b.initial) EXPECT_NEAR(o.overlap, 6e-6, 1e-12);
}

TEST(BondedSpecimen, AFreshlyBondedPressedBlockStaysAtRestFor10000Steps) {
  // A 4 x 3 block of prisms pressed 6 um into each other (dilated surfaces overlap), as
  // after compaction. Bonded with stored overlaps it carries no force and does not move;
  // the same block unbonded springs apart (the control that shows the test can fail).
  auto block = [](World& world) {
    const RigidShape shape = prism();
    const auto sh = world.add_shape(shape);
    const double pitch = kFlat + 2.0 * kDilation - 6e-6;
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 4; ++i) {
        // Honeycomb rows: every other row shifted by half a pitch, rows pitch * sqrt(3)/2 apart.
        const Eigen::Vector3d x((i + 0.5 * (j % 2)) * pitch, j * pitch * std::sqrt(3.0) / 2.0, 0);
        world.add_body(sh, kRho, x, shape.orientation_for());
      }
    }
  };
  World bonded = make_world(2e-7);
  block(bonded);
  const std::size_t bonds = bonded.initialise_bonds(table_2_5(), 0.0);
  EXPECT_EQ(bonds, 3u * 3u + 2u * 7u);  // 3 per row, 7 between neighbouring rows (honeycomb)
  for (int i = 0; i < 10000; ++i) bonded.step();
  EXPECT_EQ(bonded.bond_counts().intact, bonds);
  EXPECT_TRUE(bonded.bond_breaks().empty());
  EXPECT_EQ(bonded.kinetic_energy(), 0.0);

  World loose = make_world(2e-7);
  block(loose);
  for (int i = 0; i < 1000; ++i) loose.step();
  // 6 um of overlap on 5000 N/m springs stores ~1e-7 J per contact point: it comes out.
  EXPECT_GT(loose.kinetic_energy(), 1e-9);
}

TEST(BondedChain, TensionForceMatchesTheSeriesStiffnessOfItsBonds) {
  // n prisms bonded in a row; the first held, the last pulled by delta and held. In
  // equilibrium every bond carries the same force, K_bn delta / (n - 1), with
  // K_bn = k_bn A_b (eqs 2.10, 2.12); contacts do not act in tension.
  for (const int n : {2, 3, 6}) {
    World world = make_world(2e-7, 0.7);
    const auto ids = row(world, n, 3e-6);
    ASSERT_EQ(world.initialise_bonds(table_2_5(), 0.0), static_cast<std::size_t>(n - 1));
    world.set_fixed(ids.front(), true);
    world.set_fixed(ids.back(), true);
    const double delta = 1e-9;  // m, below the 1.57e-9 m tension limit of one bond
    const int pull_steps = 2000;
    world.state(ids.back()).v = {delta / (pull_steps * 2e-7), 0, 0};
    for (int i = 0; i < pull_steps; ++i) world.step();
    world.state(ids.back()).v.setZero();
    for (int i = 0; i < 100000; ++i) world.step();
    const double k_bn = table_2_5().kbn * M_PI * kDilation * kDilation;
    const double expected = k_bn * delta / (n - 1);
    // The held end feels the chain pull it back (-x), the other end forward.
    EXPECT_NEAR(world.state(ids.back()).f.x(), -expected, 1e-6 * expected) << n << " prisms";
    EXPECT_NEAR(world.state(ids.front()).f.x(), expected, 1e-6 * expected) << n << " prisms";
    for (const Bond& b : world.bonds()) EXPECT_NEAR(b.state.normal, expected, 1e-6 * expected);
    // Eq. 2.17 counts bond forces: an inner prism pulled by F on both sides at arms of half
    // the pitch carries sigma_xx = 2 (pitch / 2) F / V, and nothing else.
    if (n >= 3) {
      const BodyId mid = ids[1];
      const Eigen::Matrix3d sigma = world.body_stresses()[mid.index];
      const double pitch = kFlat + 2.0 * kDilation - 3e-6;
      const double V = prism().volume;
      EXPECT_NEAR(sigma(0, 0), pitch * expected / V, 1e-5 * pitch * expected / V);
      EXPECT_NEAR(sigma(1, 1), 0.0, 1e-9 * pitch * expected / V);
      EXPECT_NEAR(sigma(0, 1), 0.0, 1e-9 * pitch * expected / V);
    }
  }
}

namespace {

/// Two bonded prisms side by side along x; A held still, B moved by a prescribed rigid
/// motion for `steps` steps. Returns the world after the motion.
struct Pair {
  World world = make_world(1e-7);
  BodyId a, b;
  Pair() {
    const auto ids = row(world, 2, 2e-6);
    a = ids[0];
    b = ids[1];
    world.initialise_bonds(table_2_5(), 0.0);
    world.set_fixed(a, true);
    world.set_fixed(b, true);
  }
  /// Moves B's material point at the bond by `move` and turns B about it by `turn`, over
  /// `steps` steps.
  void drive(const Eigen::Vector3d& move, const Eigen::Vector3d& turn, int steps) {
    const double T = steps * 1e-7;
    const Eigen::Vector3d w = turn / T;
    const Eigen::Vector3d p = world.bonds().front().point;
    world.set_angular_velocity(b, w);
    // The centroid moves so that the bond point has velocity move / T.
    world.state(b).v = move / T + w.cross(world.state(b).x - p);
    for (int i = 0; i < steps; ++i) world.step();
  }
};

struct ModeCase {
  BondFailure mode;
  const char* name;
};
/// The four loads a bond carries, for the tests run once per load.
const std::array<ModeCase, 4> kEachMode{{{BondFailure::tension, "tension"},
                                        {BondFailure::shear, "shear"},
                                        {BondFailure::bending, "bending"},
                                        {BondFailure::torsion, "torsion"}}};
std::string mode_name(const ::testing::TestParamInfo<ModeCase>& info) { return info.param.name; }
class BondFailureAtItsLimit : public ::testing::TestWithParam<ModeCase> {};

/// The relative motion that loads `mode` alone to `fraction` of its limit (eq. 2.15).
void load_to(Pair& pair, BondFailure mode, double fraction) {
  const BondParams p = table_2_5();
  const BondSection s{kDilation};
  const Eigen::Vector3d n = Eigen::Vector3d::UnitX(), t = Eigen::Vector3d::UnitY();
  const double r = s.radius;
  switch (mode) {
    case BondFailure::tension:  // opening: F_bn = K_bn delta = t_bn A
      pair.drive(fraction * p.tbn / p.kbn * n, Eigen::Vector3d::Zero(), 400);
      break;
    case BondFailure::shear:  // sliding: F_bs = K_bs delta = t_bs A
      pair.drive(fraction * p.tbs / p.kbs * t, Eigen::Vector3d::Zero(), 400);
      break;
    case BondFailure::bending:  // K_br theta = t_bn I / r, K_br = k_bn I
      pair.drive(Eigen::Vector3d::Zero(), fraction * p.tbn / (r * p.kbn) * t, 400);
      break;
    case BondFailure::torsion:  // K_bt theta = t_bs J / r, K_bt = k_bs J
      pair.drive(Eigen::Vector3d::Zero(), fraction * p.tbs / (r * p.kbs) * n, 400);
      break;
    case BondFailure::none:
      break;
  }
}

}  // namespace

TEST_P(BondFailureAtItsLimit, IntactJustBelowBrokenInThatModeJustAbove) {
  const ModeCase c = GetParam();
  {
    Pair below;
    load_to(below, c.mode, 0.999);
    EXPECT_EQ(below.world.bond_counts().intact, 1u) << c.name;
    EXPECT_TRUE(below.world.bond_breaks().empty()) << c.name;
  }
  Pair above;
  load_to(above, c.mode, 1.001);
  const BondCounts counts = above.world.bond_counts();
  EXPECT_EQ(counts.intact, 0u) << c.name;
  ASSERT_EQ(above.world.bond_breaks().size(), 1u) << c.name;
  const BondBreak& br = above.world.bond_breaks().front();
  EXPECT_EQ(br.mode, c.mode) << c.name;
  EXPECT_EQ(above.world.bonds().front().failure, c.mode);
  EXPECT_GT(br.time, 0.0);
  // The logged load is the one that passed its limit (eq. 2.15), by at most one step's
  // increment (the motion is spread over 400 steps).
  const BondParams p = table_2_5();
  const BondSection s{kDilation};
  double load = 0.0, limit = 0.0;
  switch (c.mode) {
    case BondFailure::tension: load = br.loads.normal, limit = p.tbn * s.area(); break;
    case BondFailure::shear: load = br.loads.shear.norm(), limit = p.tbs * s.area(); break;
    case BondFailure::bending:
      load = br.loads.bending.norm(), limit = p.tbn * s.inertia() / s.radius;
      break;
    case BondFailure::torsion:
      load = std::abs(br.loads.torsion), limit = p.tbs * s.polar() / s.radius;
      break;
    case BondFailure::none: break;
  }
  EXPECT_GT(load, limit) << c.name;
  EXPECT_LT(load, limit * (1.0 + 1.001 / 400 + 1e-9)) << c.name;
  // A broken bond never heals: moving back leaves it broken and carrying nothing.
  above.drive(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 10);
  EXPECT_EQ(above.world.bond_counts().broken(), 1u);
  EXPECT_EQ(above.world.bonds().front().force.norm(), 0.0);
}

TEST_P(BondFailureAtItsLimit, HeldPastItsLimitItStaysIntactAndBreaksOnTheFirstStepReleased) {
  // hold_bonds (a stage's hold_cracks): 1 % past its limit the bond carries on; released,
  // it breaks at the next step, in the mode that passed.
  const ModeCase c = GetParam();
  Pair held;
  held.world.hold_bonds(true);
  load_to(held, c.mode, 1.01);
  EXPECT_EQ(held.world.bond_counts().intact, 1u) << c.name;
  EXPECT_TRUE(held.world.bond_breaks().empty()) << c.name;
  held.world.hold_bonds(false);
  held.world.step();
  ASSERT_EQ(held.world.bond_breaks().size(), 1u) << c.name;
  EXPECT_EQ(held.world.bond_breaks().front().mode, c.mode) << c.name;
}

INSTANTIATE_TEST_SUITE_P(Modes, BondFailureAtItsLimit, ::testing::ValuesIn(kEachMode),
                         mode_name);

TEST(BondedPair, CompressionAddsTheContactSpringsToTheBond) {
  // Quasi-parallel model: pushed together, the bond (K_bn) and the contact (K_n per contact
  // point, counted from the stored overlap) both resist, and their forces add.
  Pair pair;
  const double delta = 0.5e-9;
  pair.drive(-delta * Eigen::Vector3d::UnitX(), Eigen::Vector3d::Zero(), 200);
  World& w = pair.world;
  // One more step at rest, so the contact damping of eq. 2.6 has no speed to act on.
  w.state(pair.b).v.setZero();
  w.set_angular_velocity(pair.b, Eigen::Vector3d::Zero());
  w.step();
  const double k_bn = table_2_5().kbn * M_PI * kDilation * kDilation;
  double contact = 0.0;
  std::size_t points = 0;
  for (const auto& c : w.contacts()) {
    if (c.wall) continue;
    contact += c.force.x();
    if (c.force.norm() > 0.0) ++points;
  }
  ASSERT_GT(points, 0u);
  EXPECT_NEAR(contact, points * 5000.0 * delta, 1e-3 * points * 5000.0 * delta);
  EXPECT_NEAR(w.bonds().front().force.x(), k_bn * delta, 1e-6 * k_bn * delta);
  EXPECT_NEAR(w.state(pair.b).f.x(), contact + k_bn * delta, 1e-3 * k_bn * delta);
}

namespace {

/// A 30 x 20 bonded honeycomb block (600 prisms, over 1700 bonds: the parallel paths run)
/// on `threads` threads, its left column held and its right column pulled along x at
/// 0.05 m/s (10 nm a step: bonds break within 300 steps). `top`: the highest centroid's y.
/// `turn` turns the whole block, positions, orientations and pull (x, y above are before it).
World pulled_block(int threads, double& top,
                   const Eigen::Quaterniond& turn = Eigen::Quaterniond::Identity()) {
  WorldSettings ws;
  ws.gravity.setZero();
  ws.dt = 2e-7;
  ws.particle_particle = contact_law();
  ws.particle_wall = contact_law();
  ws.local_damping = 0.3;
  ws.threads = threads;
  World world(ws);
  const RigidShape shape = prism();
  const auto sh = world.add_shape(shape);
  const double pitch = kFlat + 2.0 * kDilation - 2e-6;
  std::vector<BodyId> left, right;
  top = -1e9;
  for (int j = 0; j < 20; ++j) {
    for (int i = 0; i < 30; ++i) {
      const Eigen::Vector3d x((i + 0.5 * (j % 2)) * pitch, j * pitch * std::sqrt(3.0) / 2.0, 0);
      const BodyId id = world.add_body(sh, kRho, turn * x, turn * shape.orientation_for());
      if (i == 0) left.push_back(id);
      if (i == 29) right.push_back(id);
      top = std::max(top, x.y());
    }
  }
  world.initialise_bonds(table_2_5(), 0.0);
  for (BodyId id : left) world.set_fixed(id, true);
  for (BodyId id : right) {
    world.set_fixed(id, true);
    world.state(id).v = turn * Eigen::Vector3d(0.05, 0.0, 0.0);
  }
  return world;
}

}  // namespace

TEST(BondedSpecimen, BitIdenticalForOneAndTwoThreadsUntilAndAfterBondsBreak) {
  // A 30 x 20 honeycomb block (600 prisms, over 1700 bonds: the parallel paths run), its
  // left column held and its right column pulled apart until bonds break; positions,
  // velocities and the break log must agree bit for bit between 1 and 2 threads.
  auto simulate = [](int threads) {
    double top = 0.0;
    World world = pulled_block(threads, top);
    for (int i = 0; i < 300; ++i) world.step();
    return world;
  };
  const World one = simulate(1);
  const World two = simulate(2);
  ASSERT_GT(one.bonds().size(), 1700u);
  ASSERT_FALSE(one.bond_breaks().empty());
  ASSERT_EQ(one.bond_breaks().size(), two.bond_breaks().size());
  for (std::size_t k = 0; k < one.bond_breaks().size(); ++k) {
    EXPECT_EQ(one.bond_breaks()[k].bond, two.bond_breaks()[k].bond);
    EXPECT_EQ(one.bond_breaks()[k].step, two.bond_breaks()[k].step);
  }
  const auto ids = one.body_ids();
  for (const BodyId id : ids) {
    EXPECT_EQ(std::memcmp(one.state(id).x.data(), two.state(id).x.data(), sizeof(double) * 3), 0);
    EXPECT_EQ(std::memcmp(one.state(id).v.data(), two.state(id).v.data(), sizeof(double) * 3), 0);
    EXPECT_EQ(std::memcmp(one.state(id).L.data(), two.state(id).L.data(), sizeof(double) * 3), 0);
  }
}

namespace {

/// Table 2.5's springs with the cohesive law of seed 002: sigma_c = 1000 Pa, and G_c such
/// that the softening branch is 10 times as long as the elastic one (dc = 11 dn0).
BondParams cohesive_params() {
  BondParams p = table_2_5();
  p.law = BondLaw::cohesive;
  p.sigma_c = 1000.0;
  p.g_c = 5.0 * p.sigma_c * (p.sigma_c / p.kbn);
  return p;
}

/// Two prisms bonded with the cohesive law; B driven along `dir` by `total` in `steps`
/// steps. Returns the work the drive did against the bond, and whether it broke.
struct CohesiveDrive {
  double work = 0.0;
  std::size_t broken_at_step = 0;
};
CohesiveDrive drive_apart(const Eigen::Vector3d& dir, double total, int steps) {
  World world = make_world(1e-7);
  const auto ids = row(world, 2, 2e-6);
  world.initialise_bonds(cohesive_params(), 0.0);
  world.set_fixed(ids[0], true);
  world.set_fixed(ids[1], true);
  const double T = steps * 1e-7;
  world.state(ids[1]).v = dir * (total / T);
  CohesiveDrive out;
  Eigen::Vector3d before = world.bonds().front().force;
  for (int i = 0; i < steps; ++i) {
    world.step();
    const Eigen::Vector3d after = world.bonds().front().force;
    // The drive holds B against the bond force: trapezoid rule over the step's travel.
    out.work -= 0.5 * (before + after).dot(dir * (total / steps));
    before = after;
    if (out.broken_at_step == 0 && !world.bonds().front().intact()) out.broken_at_step = i + 1;
  }
  return out;
}

}  // namespace

TEST(CohesiveGrainBond, OpeningToDecohesionDissipatesGcPerBondAreaPlusTheElasticPart) {
  const BondParams p = cohesive_params();
  const double A = BondSection{kDilation}.area();
  const double d0 = p.sigma_c / p.kbn, dc = d0 + 2.0 * p.g_c / p.sigma_c;
  // Eq. 18 (softening: G_c) plus the elastic loading up to initiation (sigma_c d0 / 2).
  const double expected = A * (p.g_c + 0.5 * p.sigma_c * d0);
  const CohesiveDrive d = drive_apart(Eigen::Vector3d::UnitX(), 1.2 * dc, 4800);
  ASSERT_GT(d.broken_at_step, 0u);
  // It lets go where lambda = 1 (eq. 16): at an opening of dc, within one step.
  EXPECT_NEAR(d.broken_at_step * 1.2 * dc / 4800, dc, 1.2 * dc / 4800 + 1e-15);
  EXPECT_NEAR(d.work, expected, 2e-3 * expected);
}

TEST(CohesiveGrainBond, SlidingToDecohesionDissipatesTheSameGc) {
  const BondParams p = cohesive_params();
  const double A = BondSection{kDilation}.area();
  const double d0 = std::min(p.sigma_c / p.kbn, p.sigma_c / p.kbs);  // eq. 32
  const double dc = d0 + 2.0 * p.g_c / p.sigma_c;
  // Elastic shear up to the circular criterion, then a softening branch worth G_c.
  const double expected = A * (p.g_c + 0.5 * p.kbs * d0 * d0);
  const CohesiveDrive d = drive_apart(Eigen::Vector3d::UnitY(), 1.2 * dc, 4800);
  ASSERT_GT(d.broken_at_step, 0u);
  EXPECT_NEAR(d.broken_at_step * 1.2 * dc / 4800, dc, 1.2 * dc / 4800 + 1e-15);
  EXPECT_NEAR(d.work, expected, 2e-3 * expected);
}

TEST(CohesiveGrainBond, StopsShortOfDecohesionIntactAndSoftened) {
  const BondParams p = cohesive_params();
  const double d0 = p.sigma_c / p.kbn, dc = d0 + 2.0 * p.g_c / p.sigma_c;
  World world = make_world(1e-7);
  const auto ids = row(world, 2, 2e-6);
  world.initialise_bonds(p, 0.0);
  world.set_fixed(ids[0], true);
  world.set_fixed(ids[1], true);
  world.state(ids[1]).v = Eigen::Vector3d::UnitX() * (0.5 * (d0 + dc) / (1000 * 1e-7));
  for (int i = 0; i < 1000; ++i) world.step();
  const Bond& b = world.bonds().front();
  ASSERT_TRUE(b.intact());
  EXPECT_EQ(b.state.cohesive.phase, LinkPhase::cohesive);
  // Halfway down the softening line the traction is sigma_c / 2 (eq. 15).
  const double A = BondSection{kDilation}.area();
  EXPECT_NEAR(-b.force.x(), 0.5 * p.sigma_c * A, 1e-3 * p.sigma_c * A);
}

class StressCriterion : public ::testing::TestWithParam<BondCriterion> {
 protected:
  /// Four prisms in a row bonded with the criterion (sigma_f = 1e4 Pa), the first held,
  /// the last pulled slowly along x; `breaking`: the middle bond's tension when its grains'
  /// stress reaches the criterion (the closed form of the first test).
  void SetUp() override {
    ids = row(world, 4, 0.0);
    params = table_2_5();
    params.criterion = GetParam();
    params.sigma_f = 1e4;
    ASSERT_EQ(world.initialise_bonds(params, 1e-6), 3u);
    world.set_fixed(ids[0], true);
    world.set_fixed(ids[3], true);
    world.state(ids[3]).v = Eigen::Vector3d(1e-3, 0, 0);
    const double pitch = kFlat + 2.0 * kDilation;
    const double volume = world.shape(world.info(ids[1]).shape).volume;
    const double factor = GetParam() == BondCriterion::rankine ? 1.0 : 3.0;
    breaking = factor * params.sigma_f * volume / pitch;
  }
  World world = make_world(5e-7, 0.7);
  std::vector<BodyId> ids;
  BondParams params;
  double breaking = 0.0;
};

TEST_P(StressCriterion, AChainPulledApartBreaksWhereItsGrainsStressReachesSigmaF) {
  // Four prisms in a row, the first held, the last pulled slowly along x. Each inner grain
  // carries the chain's force F on both sides, so its Love-Weber stress (eq. 2.17) is
  // sigma_xx = 2 (pitch / 2) F / V and nothing else; the end grains carry half of it. The
  // bond between the two inner grains breaks first, when sigma_xx reaches sigma_f
  // (Rankine: the largest principal stress) or 3 sigma_f (hydrostatic: sigma_xx / 3).
  double force = 0.0;  // the middle bond's tension on the step before the first break
  int steps = 0;
  while (world.bond_breaks().empty() && steps < 40000) {
    force = world.bonds()[1].state.normal;
    world.step();
    ++steps;
  }
  ASSERT_EQ(world.bond_breaks().size(), 1u) << "after " << steps << " steps";
  EXPECT_EQ(world.bond_breaks().front().bond, 1u);  // the inner one
  EXPECT_EQ(world.bond_breaks().front().mode, BondFailure::tension);
  EXPECT_NEAR(force, breaking, 0.01 * breaking);
  // With the stress criterion, eq. 2.15's limits (1000 Pa on the bond's tiny section, far
  // below this force) do not break anything.
  EXPECT_GT(force, params.tbn * M_PI * kDilation * kDilation);
  EXPECT_FALSE(world.bonds()[1].intact());
  EXPECT_TRUE(world.bonds()[0].intact());
}

TEST_P(StressCriterion, HeldBondsOutlastSigmaFAndBreakOnTheFirstStepReleased) {
  // The chain above, its bonds held until the inner grains' stress is 50 % past the
  // criterion's: none breaks; released, the overloaded ones break at the next step.
  world.hold_bonds(true);
  int steps = 0;
  while (world.bonds()[1].state.normal < 1.5 * breaking && steps < 80000) {
    world.step();
    ++steps;
  }
  ASSERT_GE(world.bonds()[1].state.normal, 1.5 * breaking) << "after " << steps << " steps";
  EXPECT_TRUE(world.bond_breaks().empty());
  world.hold_bonds(false);
  world.step();
  EXPECT_FALSE(world.bond_breaks().empty());
  EXPECT_FALSE(world.bonds()[1].intact());
}

INSTANTIATE_TEST_SUITE_P(RankineAndHydrostatic, StressCriterion,
                         ::testing::Values(BondCriterion::rankine, BondCriterion::hydrostatic));

TEST(GrainStressSums, ByBodyGiveTheBitsOfAWalkOverTheContactRecordsAndBonds) {
  // A 30 x 20 bonded honeycomb block (600 prisms: the parallel paths run) pressed by a
  // platen from above and pulled on its right column until bonds break: contacts between
  // grains, with the platen, intact and broken bonds. World::stress_sums and forces_on,
  // made from the step's lists by body or summed with the forces (a listener's StepNeeds), must
  // give every slot the bits of a walk over contacts() and bonds(), on 1 and 2 threads,
  // and after a wall is added (lists stale: the records themselves).
  for (const int threads : {1, 2}) {
    double top = 0.0;
    World world = pulled_block(threads, top);
    const double pitch = kFlat + 2.0 * kDilation - 2e-6;
    // A platen touching the top row's dilated corners, closing on them.
    world.add_wall(Wall::platen("top", {15 * pitch, top + kSide + kDilation - 2e-6, 0}, {0, -1, 0}, {1, 0, 0},
                                20 * pitch, kThick));
    world.wall(0).velocity = {0, -0.02, 0};
    for (int i = 0; i < 300; ++i) world.step();
    ASSERT_FALSE(world.bond_breaks().empty());
    std::size_t on_wall = 0;
    for (const ContactRecord& c : world.contacts()) on_wall += c.wall;
    ASSERT_GT(on_wall, 0u);
    expect_sums_match_the_records(world, threads == 1 ? "1 thread, by body" : "2 threads, by body");
    SumsWithTheForces sums;  // the next step sums them with the forces
    world.add_listener(&sums);
    world.step();
    world.remove_listener(&sums);
    expect_sums_match_the_records(world, threads == 1 ? "1 thread, with the forces" : "2 threads, with the forces");
    world.add_wall(Wall::plane("far", {0, -1.0, 0}, {0, 1, 0}));  // lists stale until the next step
    expect_sums_match_the_records(world, "after add_wall");
    world.step();
    expect_sums_match_the_records(world, "the step after");
  }
}

TEST(Gallop, StopsWhereAForwardWalkStops) {
  // gallop.hpp against the walk it replaces (World::initial_overlap's cursor through the
  // bonds), on random sorted arrays with runs of equal keys, from random starts, for targets
  // near and far: the same index every time.
  std::mt19937_64 rng(31);
  int far = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<int> v(rng() % 300);
    for (int& x : v) x = static_cast<int>(rng() % 200);
    std::sort(v.begin(), v.end());
    const std::size_t from = v.empty() ? 0 : rng() % (v.size() + 1);
    const int key = static_cast<int>(rng() % 210) - 5;
    auto before = [&](int x) { return x < key; };
    std::size_t walk = from;
    while (walk < v.size() && before(v[walk])) ++walk;
    ASSERT_EQ(physics::gallop(v, from, before), walk) << trial;
    far += walk > from + 16 ? 1 : 0;
  }
  EXPECT_GT(far, 2000);  // long strides were taken, not only the first steps
}

namespace {
/// The load a pair's bond carries along `mode` after load_to (its normal force, shear force,
/// bending or torsion moment).
double bond_load(const World& w, BondFailure mode) {
  const BondState& s = w.bonds().front().state;
  switch (mode) {
    case BondFailure::tension:
      return s.normal;
    case BondFailure::shear:
      return s.shear.norm();
    case BondFailure::bending:
      return s.bending.norm();
    case BondFailure::torsion:
      return std::abs(s.torsion);
    case BondFailure::none:
      break;
  }
  return 0.0;
}
}  // namespace

class BondStiffnessFactor : public ::testing::TestWithParam<ModeCase> {};

TEST_P(BondStiffnessFactor, ABondOfFactorSCarriesSTimesTheClosedFormLoad) {
  // Eqs 2.10-2.13: the same relative motion loads a bond of stiffness factor s by s K delta
  // (K_bn, K_bs) or s K theta (K_br = k_bn I, K_bt = k_bs J); its limits (eq. 2.15) stay.
  const ModeCase c = GetParam();
  const BondParams p = table_2_5();
  const BondSection s{kDilation};
  const double r = s.radius;
  for (const double factor : {1.0, 0.25, 2.5}) {
    Pair pair;
    pair.world.set_bond_stiffness(0, factor);
    // A third of the limit of factor 1: factor 2.5 loads the bond to 83 % of it.
    load_to(pair, c.mode, 1.0 / 3.0);
    ASSERT_EQ(pair.world.bond_counts().intact, 1u) << c.name << " s = " << factor;
    double expected = 0.0;
    switch (c.mode) {
      case BondFailure::tension:
        expected = p.kbn * s.area() * (p.tbn / p.kbn / 3.0);
        break;
      case BondFailure::shear:
        expected = p.kbs * s.area() * (p.tbs / p.kbs / 3.0);
        break;
      case BondFailure::bending:
        expected = p.kbn * s.inertia() * (p.tbn / (r * p.kbn) / 3.0);
        break;
      case BondFailure::torsion:
        expected = p.kbs * s.polar() * (p.tbs / (r * p.kbs) / 3.0);
        break;
      case BondFailure::none:
        break;
    }
    expected *= factor;
    EXPECT_NEAR(bond_load(pair.world, c.mode), expected, 1e-6 * expected)
        << c.name << " s = " << factor;
  }
}

INSTANTIATE_TEST_SUITE_P(EachLoad, BondStiffnessFactor, ::testing::ValuesIn(kEachMode),
                         mode_name);

TEST(BondStiffnessFactor, AChainOfBondsOfOwnFactorsPullsWithTheirSeriesStiffness) {
  // Six prisms, five bonds of factors s_i (four side by side in the law's lanes, one alone):
  // pulled by delta and held, each carries F = delta / sum(1 / (s_i K_bn)).
  const std::vector<double> factors{1.0, 2.0, 0.5, 4.0, 3.0};
  World world = make_world(2e-7, 0.7);
  const auto ids = row(world, 6, 3e-6);
  ASSERT_EQ(world.initialise_bonds(table_2_5(), 0.0), factors.size());
  for (std::size_t k = 0; k < factors.size(); ++k) world.set_bond_stiffness(k, factors[k]);
  EXPECT_THROW(world.set_bond_stiffness(0, 0.0), std::invalid_argument);
  world.set_fixed(ids.front(), true);
  world.set_fixed(ids.back(), true);
  const double delta = 1e-9;
  const int pull_steps = 2000;
  world.state(ids.back()).v = {delta / (pull_steps * 2e-7), 0, 0};
  for (int i = 0; i < pull_steps; ++i) world.step();
  world.state(ids.back()).v.setZero();
  for (int i = 0; i < 100000; ++i) world.step();
  const double k_bn = table_2_5().kbn * M_PI * kDilation * kDilation;
  double compliance = 0.0;
  for (const double s : factors) compliance += 1.0 / (s * k_bn);
  const double expected = delta / compliance;
  EXPECT_NEAR(world.state(ids.back()).f.x(), -expected, 1e-6 * expected);
  for (const Bond& b : world.bonds()) EXPECT_NEAR(b.state.normal, expected, 1e-6 * expected);
}
