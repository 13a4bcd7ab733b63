// Thermal expansion of bonded grains (seed 003: bonds relax to l0(T) = l0(T0) + alpha
// (T - T0), generalised to a tensor per grain), against closed forms: a free bar lengthens
// by alpha L dT and carries nothing, a clamped one carries -E alpha dT, a bimaterial pair
// and an anisotropic pair move and stress as their expansion tensors say; pieces of a
// split grain keep its temperature and expansion; a checkpoint carries them bit for bit.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/exact_polyhedron.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"
#include "prism_row.hpp"

using namespace cleave;
using namespace cleave::physics;
using namespace cleave::test;

namespace {

const double kArea = kBondArea;

World make_world() {
  WorldSettings ws = prism_settings(2e-7);
  ws.local_damping = 0.7;  // quasi-static: the answers are equilibria
  return World(ws);
}

/// Ramps every body from its temperature by dT over `ramp` steps, then lets it settle.
void heat(World& world, const std::vector<BodyId>& ids, double dT, int ramp = 4000, int settle = 30000) {
  std::vector<double> start;
  for (BodyId id : ids) start.push_back(world.temperature(id));
  for (int s = 1; s <= ramp; ++s) {
    for (std::size_t i = 0; i < ids.size(); ++i) world.set_temperature(ids[i], start[i] + dT * s / ramp);
    world.step();
  }
  for (int s = 0; s < settle; ++s) world.step();
}

/// The largest contact force on any body (bonded pairs touch: their contacts count too).
double largest_contact_force(const World& world) {
  double most = 0.0;
  for (const ContactRecord& c : world.contacts()) most = std::max(most, c.force.norm());
  return most;
}

}  // namespace

class FreeBar : public ::testing::TestWithParam<double> {};

TEST_P(FreeBar, LengthensByAlphaLDeltaTAndCarriesNoForce) {
  // Heated (dT > 0) or cooled (dT < 0): the free bar's length changes by alpha L dT and
  // neither its bonds nor its contacts carry anything. Cooled, the grains' shapes (which
  // keep their size) press into each other by alpha pitch |dT| per pair: the contacts must
  // count from the thermal gap, or they hold the bar open.
  const double alpha = 1e-5, dT = GetParam();
  World world = make_world();
  const std::vector<BodyId> ids = row(world, 5);
  world.set_temperature(1500.0);
  for (BodyId id : ids) world.set_expansion(id, alpha * Eigen::Matrix3d::Identity());
  ASSERT_EQ(world.initialise_bonds(strong_bonds(), 1e-6), 4u);
  const double length = world.state(ids.back()).x.x() - world.state(ids.front()).x.x();
  heat(world, ids, dT);
  const double grown = world.state(ids.back()).x.x() - world.state(ids.front()).x.x() - length;
  EXPECT_NEAR(grown, alpha * length * dT, 0.005 * std::abs(alpha * length * dT));
  // Against the clamped force K_bn alpha pitch |dT|: at most 0.5 % of it is left.
  const double clamped = kSpringN * alpha * kPitch * std::abs(dT);
  for (const Bond& b : world.bonds()) EXPECT_LT(b.force.norm(), 0.005 * clamped);
  EXPECT_LT(largest_contact_force(world), 0.005 * clamped);
  for (BodyId id : ids) EXPECT_EQ(world.temperature(id), 1500.0 + dT);
}

INSTANTIATE_TEST_SUITE_P(HeatedAndCooled, FreeBar, ::testing::Values(100.0, -100.0));

class OrthorhombicBar : public ::testing::TestWithParam<int> {};

TEST_P(OrthorhombicBar, LengthensByAlphaOfTheCrystalAxisAlongItAndByTheTensorObliquely) {
  // Every grain of a free bar shares one orthorhombic crystal (seed 003's aluminium titanate:
  // alpha_a, alpha_b, alpha_c). Turned so that its axis i lies along the bar, the bar
  // lengthens by alpha_i L dT; turned obliquely, by (sum_i alpha_i (e_i . x)^2) L dT. (The
  // tensor's shear part turns a free bar rigidly, so the end's sideways move is no check.)
  const Eigen::Vector3d abc = Eigen::Vector3d(-2.38, 11.97, 20.80) * 0.8e-6;
  const int axis = GetParam();
  Eigen::Quaterniond crystal;
  if (axis < 3) {
    // Crystal axis `axis` onto x, turned about x by a further 0.7 rad (any turn about the bar).
    crystal = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX()) *
              Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::Unit(axis), Eigen::Vector3d::UnitX());
  } else {
    crystal = Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 2, 3).normalized());
  }
  const Eigen::Matrix3d r = crystal.toRotationMatrix();
  double along = 0.0;
  for (int i = 0; i < 3; ++i) along += abc[i] * r(0, i) * r(0, i);
  if (axis < 3) ASSERT_NEAR(along, abc[axis], 1e-20);
  const double dT = -300.0;
  World world = make_world();
  const std::vector<BodyId> ids = row(world, 5);
  world.set_temperature(1500.0);
  for (BodyId id : ids) world.set_expansion(id, World::crystal_expansion(crystal, abc));
  ASSERT_EQ(world.initialise_bonds(strong_bonds(), 1e-6), 4u);
  const Eigen::Vector3d span = world.state(ids.back()).x - world.state(ids.front()).x;
  heat(world, ids, dT);
  const Eigen::Vector3d moved = world.state(ids.back()).x - world.state(ids.front()).x - span;
  const double length = span.x();
  const double scale = abc.cwiseAbs().maxCoeff() * length * std::abs(dT);
  EXPECT_NEAR((span + moved).norm() - span.norm(), along * length * dT, 0.005 * scale);
}

INSTANTIATE_TEST_SUITE_P(AxesAndOblique, OrthorhombicBar, ::testing::Values(0, 1, 2, 3));

TEST(ClampedBar, CarriesMinusEAlphaDeltaTInEveryBond) {
  // Both ends held: each bond's stress is -E_b alpha dT, E_b = k_bn l the bond's modulus
  // (eq. 2.9's k_bn is stress per opening; over its length l = pitch, stress per strain).
  const double alpha = 8e-6, dT = 200.0;
  World world = make_world();
  const std::vector<BodyId> ids = row(world, 4);
  for (BodyId id : ids) world.set_expansion(id, alpha * Eigen::Matrix3d::Identity());
  ASSERT_EQ(world.initialise_bonds(strong_bonds(), 1e-6), 3u);
  world.set_fixed(ids.front(), true);
  world.set_fixed(ids.back(), true);
  heat(world, ids, dT);
  const double modulus = strong_bonds().kbn * kPitch;
  for (const Bond& b : world.bonds()) {
    const double stress = b.state.normal / kArea;  // positive in tension
    EXPECT_NEAR(stress, -modulus * alpha * dT, 1e-3 * modulus * alpha * dT);
  }
  // The inner grains stay where they were: the bar cannot grow.
  EXPECT_NEAR(world.state(ids[1]).x.x(), kPitch, 1e-9 * kPitch);
}

TEST(BimaterialPair, SeparatesAndStressesAsItsTwoExpansionsAdd) {
  // A of alpha_1, B of alpha_2, the bond point midway: free, the centroids part by
  // (alpha_1 + alpha_2) (pitch / 2) dT; held, the bond carries K_bn times that.
  const double a1 = 4e-6, a2 = 12e-6, dT = 150.0;
  const double opening = (a1 + a2) * 0.5 * kPitch * dT;
  for (const bool held : {false, true}) {
    World world = make_world();
    const std::vector<BodyId> ids = row(world, 2);
    world.set_expansion(ids[0], a1 * Eigen::Matrix3d::Identity());
    world.set_expansion(ids[1], a2 * Eigen::Matrix3d::Identity());
    ASSERT_EQ(world.initialise_bonds(strong_bonds(), 1e-6), 1u);
    if (held) {
      world.set_fixed(ids[0], true);
      world.set_fixed(ids[1], true);
    }
    heat(world, ids, dT);
    const double gap = world.state(ids[1]).x.x() - world.state(ids[0]).x.x() - kPitch;
    const Bond& b = world.bonds().front();
    if (held) {
      EXPECT_NEAR(gap, 0.0, 1e-15);
      EXPECT_NEAR(b.state.normal, -kSpringN * opening, 1e-3 * kSpringN * opening);
    } else {
      EXPECT_NEAR(gap, opening, 0.005 * opening);
      EXPECT_LT(std::abs(b.state.normal), 0.005 * kSpringN * opening);
    }
    // Its contact and bond both count from the gap the grains' growth closed.
    EXPECT_NEAR(b.thermal_gap, -opening, 1e-3 * opening);
  }
}

TEST(AnisotropicPair, BondStrainFollowsAlphaAlongTheBondAndTheBondEndsRelaxed) {
  // Both grains with alpha_a across and alpha_c along a c-axis 35 degrees off the bond in
  // the xy plane. Free, the pair's separation strain is n^T alpha n dT, and the bond ends
  // unloaded: the part of alpha d dT across the bond is taken up by the centroids' motion
  // and by both grains turning alike (a turn the bending spring does not resist), in a
  // share the dynamics picks; the bond point's two material points must meet again.
  const double aa = -2e-6, ac = 20e-6, dT = 120.0;
  const double angle = 35.0 * M_PI / 180.0;
  const Eigen::Vector3d c(std::cos(angle), std::sin(angle), 0.0);
  const Eigen::Matrix3d alpha = World::crystal_expansion(c, aa, ac);
  World world = make_world();
  const std::vector<BodyId> ids = row(world, 2);
  for (BodyId id : ids) world.set_expansion(id, alpha);
  ASSERT_EQ(world.initialise_bonds(strong_bonds(), 1e-6), 1u);
  const Eigen::Vector3d d = world.state(ids[1]).x - world.state(ids[0]).x;
  const Eigen::Quaterniond q0 = world.state(ids[0]).q;
  heat(world, ids, dT, 4000, 60000);
  const Eigen::Vector3d moved = world.state(ids[1]).x - world.state(ids[0]).x - d;
  const Eigen::Vector3d n = d.normalized();
  const double strain = n.dot(alpha * n) * dT;
  EXPECT_NEAR(moved.dot(n) / d.norm(), strain, 0.005 * std::abs(strain));
  // Unloaded: against the force of the whole misfit held, K_bs |alpha d dT|.
  const Bond& b = world.bonds().front();
  EXPECT_LT(b.force.norm(), 0.005 * kSpringS * (alpha * d * dT).norm());
  // Misfit across the bond: without the thermal term the shear spring would hold it.
  EXPECT_GT(std::abs(moved.y()), 0.1 * std::abs((alpha * d * dT).y()));
  // The tensor turns with the grain: kept in its frame, read back in world axes.
  const Eigen::Matrix3d turn = (world.state(ids[0]).q * q0.conjugate()).toRotationMatrix();
  EXPECT_TRUE(world.expansion(ids[0]).isApprox(turn * alpha * turn.transpose(), 1e-9));
  EXPECT_FALSE(turn.isIdentity(1e-6));  // it did turn
}

TEST(ThermalState, ASplitGrainsPiecesKeepItsTemperatureAndExpansion) {
  const geometry::ExactPolyhedron prism = geometry::ExactPolyhedron::hexagonal_prism(kSide, kThick);
  World world = make_world();
  const RigidShape parent_shape = make_rigid_shape(prism, kDilation);
  const auto sh = world.add_shape(parent_shape);
  std::vector<Fragment> pieces;
  for (const auto& slab : prism.cleavage_slabs({geometry::CleavageFamily::m_10_10, 60})) {
    const RigidShape piece = make_rigid_shape(slab, kDilation);
    pieces.push_back(fragment_placement(parent_shape, piece, world.add_shape(piece)));
  }
  ASSERT_GE(pieces.size(), 2u);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const BodyId parent = world.add_body(sh, kRho, {0, 0, 0}, q);
  const Eigen::Matrix3d alpha = World::crystal_expansion(Eigen::Vector3d(0.2, -0.5, 1.0), 3e-6, 9e-6);
  world.set_expansion(parent, alpha);
  world.set_temperature(parent, 900.0);
  for (BodyId id : world.split_body(parent, pieces)) {
    EXPECT_EQ(world.temperature(id), 900.0);
    EXPECT_TRUE(world.expansion(id).isApprox(alpha, 1e-12)) << world.expansion(id);
  }
}

TEST(ThermalState, ASplitGrainsPiecesPressOnItsNeighboursAsItDidTheStepBefore) {
  // Three prisms in a row, held, heated by 300 K with alpha = 1e-5 (no bonds: their
  // contacts count the gap the expansion closed). The middle one is split across the row,
  // on the {10-10} plane parallel to the faces its neighbours touch. Its pieces go on
  // expanding about the parent's centroid, so each neighbour feels the same force after the
  // split as before it. (About their own centroids, the near piece's face would stand
  // alpha dT times the distance between the two centroids further back at once, and the
  // force would drop by a fifth here.)
  const geometry::ExactPolyhedron exact = geometry::ExactPolyhedron::hexagonal_prism(kSide, kThick);
  const double alpha = 1e-5, dT = 300.0;
  int across = 0;
  for (const int angle : {0, 60, 120}) {
    World world = make_world();
    const std::vector<BodyId> ids = row(world, 3, 1e-9);  // touching: the contacts are found
    for (BodyId id : ids) {
      world.set_temperature(id, 300.0);
      world.set_expansion(id, alpha * Eigen::Matrix3d::Identity());
      world.set_fixed(id, true);
      world.set_temperature(id, 300.0 + dT);
    }
    auto on = [&](std::uint32_t slot) {  // the contact force on one body
      Eigen::Vector3d f = Eigen::Vector3d::Zero();
      for (const ContactRecord& c : world.contacts()) {
        if (c.b == slot) f += c.force;
        if (!c.wall && c.a == slot) f -= c.force;
      }
      return f;
    };
    world.step();
    const Eigen::Vector3d before_a = on(ids[0].index), before_c = on(ids[2].index);
    ASSERT_GT(before_a.norm(), 0.0);
    const RigidShape parent_shape = prism();
    std::vector<Fragment> pieces;
    for (const auto& slab : exact.cleavage_slabs({geometry::CleavageFamily::m_10_10, angle})) {
      const RigidShape piece = make_rigid_shape(slab, kDilation);
      pieces.push_back(fragment_placement(parent_shape, piece, world.add_shape(piece)));
    }
    const Eigen::Vector3d centre = world.state(ids[1]).x;
    const std::vector<BodyId> split = world.split_body(ids[1], pieces);
    ASSERT_EQ(split.size(), 2u);
    const double apart = std::abs(world.state(split[0]).x.x() - world.state(split[1]).x.x());
    if (apart < 0.3 * kFlat) continue;  // this plane does not cut across the row
    ++across;
    EXPECT_NEAR((world.state(split[0]).x - centre).norm() + (world.state(split[1]).x - centre).norm(), apart,
                1e-9 * kFlat);
    world.step();
    const Eigen::Vector3d after_a = on(ids[0].index), after_c = on(ids[2].index);
    // About the pieces' own centroids the overlap alpha dT (x_B - x_A) would lose
    // alpha dT (apart / 2): the force (linear in it) that share.
    EXPECT_GT(0.5 * apart / kPitch, 0.15) << "the test would not see the difference";
    EXPECT_LT((after_a - before_a).norm(), 1e-6 * before_a.norm()) << angle << ": " << before_a.transpose() << " -> "
                                                                   << after_a.transpose();
    EXPECT_LT((after_c - before_c).norm(), 1e-6 * before_c.norm()) << angle;
  }
  EXPECT_EQ(across, 1);
}

TEST(ThermalState, ACheckpointMidRampCarriesOnBitForBit) {
  auto setup = [](World& world) {
    const std::vector<BodyId> ids = row(world, 3);
    for (BodyId id : ids) world.set_expansion(id, World::crystal_expansion(Eigen::Vector3d(1, 1, 0), 1e-6, 2e-5));
    world.initialise_bonds(strong_bonds(), 1e-6);
    world.set_conduction(100.0, 1.0);
    world.set_temperature(300.0);
    world.set_temperature_held(ids.front(), true);
    return ids;
  };
  auto ramp = [](World& world, int from, int to) {
    const BodyId end = world.body_ids().front();
    for (int s = from; s < to; ++s) {
      world.set_temperature(end, 300.0 + 0.05 * s);  // the rest follow by conduction
      world.step();
    }
  };
  World a = make_world();
  setup(a);
  ramp(a, 0, 500);
  StateWriter w;
  a.save_state(w);
  World b = make_world();
  StateReader r(w.bytes());
  b.load_state(r);
  EXPECT_EQ(a.state_hash(), b.state_hash());
  ramp(a, 500, 1000);
  ramp(b, 500, 1000);
  EXPECT_EQ(a.state_hash(), b.state_hash());
  EXPECT_TRUE(b.thermal());
  EXPECT_EQ(b.conductivity(), 100.0);
  EXPECT_EQ(a.temperature(a.body_ids().back()), b.temperature(b.body_ids().back()));
  EXPECT_GT(b.temperature(b.body_ids().back()), 300.0);
  EXPECT_EQ(a.bonds().front().thermal_gap, b.bonds().front().thermal_gap);
  EXPECT_NE(a.bonds().front().thermal_gap, 0.0);
  // The temperature is part of the hash when bodies expand.
  const std::uint64_t before = b.state_hash();
  b.set_temperature(b.temperature(b.body_ids().front()) + 1.0);
  EXPECT_NE(b.state_hash(), before);
}

TEST(ThermalState, BadInputIsRefused) {
  World world = make_world();
  const BodyId id = row(world, 1).front();
  EXPECT_THROW(world.set_temperature(id, std::nan("")), std::invalid_argument);
  Eigen::Matrix3d skew = Eigen::Matrix3d::Zero();
  skew(0, 1) = 1e-6;
  EXPECT_THROW(world.set_expansion(id, skew), std::invalid_argument);
  EXPECT_THROW(World::crystal_expansion(Eigen::Vector3d::Zero(), 1e-6, 1e-6), std::invalid_argument);
  EXPECT_FALSE(world.thermal());
  world.set_expansion(id, 1e-6 * Eigen::Matrix3d::Identity());
  EXPECT_TRUE(world.thermal());
}

TEST(Conduction, TwoBondedGrainsRelaxAsTheLumpedExponential) {
  // Two grains of heat capacities C = m c_p joined by one bond of conductance
  // G = lambda S_t / d: their difference decays as exp(-G (1/C_a + 1/C_b) t), and the
  // heat they hold together stays what it was. S_t is the touching side faces' area.
  const double lambda = 1.0, cp = 1.0;
  World world = make_world();
  const std::vector<BodyId> ids = row(world, 2);
  ASSERT_EQ(world.initialise_bonds(strong_bonds(), 1e-6), 1u);
  world.set_conduction(lambda, cp);
  EXPECT_NEAR(world.bonds().front().transmission, kSide * kThick, 1e-9 * kSide * kThick);
  world.set_temperature(ids[0], 400.0);
  world.set_temperature(ids[1], 300.0);
  const double m = world.info(ids[0]).mass;
  const double rate = lambda * kSide * kThick / kPitch * 2.0 / (m * cp);
  const int steps = 20000;
  for (int s = 0; s < steps; ++s) world.step();
  const double t = steps * world.settings().dt;
  const double diff = world.temperature(ids[0]) - world.temperature(ids[1]);
  EXPECT_NEAR(diff, 100.0 * std::exp(-rate * t), 1e-3 * 100.0 * std::exp(-rate * t));
  EXPECT_GT(rate * t, 0.5);  // it has decayed far enough to tell
  EXPECT_NEAR(world.temperature(ids[0]) + world.temperature(ids[1]), 700.0, 1e-9);
}

TEST(Conduction, ABondedRodsFirstModeDecaysAsTheHeatEquationSays) {
  // A rod of 16 grains face to face, insulated ends, starting in the first mode
  // T = T0 + dT cos(pi x / L): the heat equation gives a decay rate kappa pi^2 / L^2 with
  // the chain's diffusivity kappa = lambda S_t d / (rho c_p V) (its conductance per length
  // over its heat capacity per length), L = N d. Within 2 % (the chain's discreteness).
  const int n = 16;
  const double lambda = 100.0, cp = 1.0;
  World world = make_world();
  const std::vector<BodyId> ids = row(world, n);
  ASSERT_EQ(world.initialise_bonds(strong_bonds(), 1e-6), static_cast<std::size_t>(n - 1));
  world.set_conduction(lambda, cp);
  auto mode = [&](int i) { return std::cos(M_PI * (i + 0.5) / n); };
  for (int i = 0; i < n; ++i) world.set_temperature(ids[i], 500.0 + 50.0 * mode(i));
  auto amplitude = [&] {
    double num = 0.0, den = 0.0;
    for (int i = 0; i < n; ++i) {
      num += (world.temperature(ids[i]) - 500.0) * mode(i);
      den += mode(i) * mode(i);
    }
    return num / den;
  };
  const double volume = world.shape(world.info(ids[0]).shape).volume;
  const double kappa = lambda * kSide * kThick * kPitch / (kRho * cp * volume);
  const double length = n * kPitch;
  const double rate = kappa * M_PI * M_PI / (length * length);
  const int steps = 20000;
  for (int s = 0; s < steps; ++s) world.step();
  const double t = steps * world.settings().dt;
  const double measured = -std::log(amplitude() / 50.0) / t;
  EXPECT_NEAR(measured, rate, 0.02 * rate);
  EXPECT_GT(rate * t, 0.3);
  // Insulated: the mean temperature stays.
  double mean = 0.0;
  for (BodyId id : ids) mean += world.temperature(id) / n;
  EXPECT_NEAR(mean, 500.0, 1e-9);
}

TEST(Conduction, AHeldFaceQuenchesItsNeighboursAndABrokenBondStopsTheHeat) {
  // Three grains: the first held at 300 K, the others at 800 K; the middle cools and the
  // third follows. Then the third is pulled off (its bond, 1e-6 of the other's strength,
  // breaks in tension): from then on its temperature stays, while the middle's falls on.
  World world = make_world();
  const std::vector<BodyId> ids = row(world, 3);
  BondParams weak = strong_bonds();
  weak.tbn = weak.tbs = 1e3;
  ASSERT_EQ(world.initialise_bonds(weak, 1e-6), 2u);
  world.set_bond_strength(0, 1e6);  // bonds sorted by pair: 0 joins grains 0 and 1
  world.set_conduction(100.0, 1.0);
  world.set_temperature(800.0);
  world.set_temperature(ids[0], 300.0);
  world.set_temperature_held(ids[0], true);
  world.set_fixed(ids[0], true);
  for (int s = 0; s < 1000; ++s) world.step();
  EXPECT_EQ(world.temperature(ids[0]), 300.0);
  EXPECT_LT(world.temperature(ids[1]), 700.0);
  EXPECT_LT(world.temperature(ids[2]), 800.0);
  EXPECT_GT(world.temperature(ids[2]), world.temperature(ids[1]));
  world.set_fixed(ids[2], true);
  world.state(ids[2]).v = Eigen::Vector3d(1e-3, 0, 0);
  int steps = 0;
  while (world.bonds()[1].intact() && steps < 1000) {
    world.step();
    ++steps;
  }
  ASSERT_FALSE(world.bonds()[1].intact());
  ASSERT_TRUE(world.bonds()[0].intact());
  const double third = world.temperature(ids[2]), middle = world.temperature(ids[1]);
  for (int s = 0; s < 1000; ++s) world.step();
  EXPECT_EQ(world.temperature(ids[2]), third);
  EXPECT_LT(world.temperature(ids[1]), middle - 1.0);
  EXPECT_THROW(world.set_conduction(-1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(world.set_conduction(1.0, 0.0), std::invalid_argument);
}

TEST(ThermalField, ALinearFieldLeavesAFreeBlockUnstressedAndAQuadraticOneDoesNot) {
  // A free honeycomb block of 5 x 4 bonded prisms, alpha isotropic: a temperature linear in
  // x and y is a compatible thermal strain (a free body takes it without stress), a
  // quadratic one is not. Against the force a clamped bond would carry at the largest
  // temperature change, K_bn alpha pitch dT: the linear field leaves under 0.2 % of it in
  // any bond, the quadratic one (its Laplacian is not zero: incompatible in the plane) over
  // 2 % in some (the control that shows the test can fail).
  const double alpha = 1e-5, swing = 200.0;
  auto largest_bond_force = [&](bool quadratic) {
    World world = make_world();
    const RigidShape shape = prism();
    const auto sh = world.add_shape(shape);
    std::vector<BodyId> ids;
    std::vector<Eigen::Vector2d> at;
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 5; ++i) {
        const Eigen::Vector3d x((i + 0.5 * (j % 2)) * kPitch, j * kPitch * std::sqrt(3.0) / 2.0, 0);
        ids.push_back(world.add_body(sh, kRho, x, shape.orientation_for()));
        at.emplace_back(x.x() / (5 * kPitch), x.y() / (4 * kPitch));  // about 0..1 across the block
      }
    }
    for (BodyId id : ids) world.set_expansion(id, alpha * Eigen::Matrix3d::Identity());
    world.set_temperature(1000.0);
    EXPECT_GT(world.initialise_bonds(strong_bonds(), 1e-6), 30u);
    const int ramp = 4000;
    for (int s = 1; s <= ramp + 40000; ++s) {
      const double f = std::min(1.0, static_cast<double>(s) / ramp);
      for (std::size_t k = 0; k < ids.size(); ++k) {
        const Eigen::Vector2d p = at[k];
        const double shape_of_field = quadratic ? p.x() * p.x() + p.y() * p.y() : 0.6 * p.x() + 0.4 * p.y();
        world.set_temperature(ids[k], 1000.0 + f * swing * shape_of_field);
      }
      world.step();
    }
    double most = 0.0;
    for (const Bond& b : world.bonds()) most = std::max(most, b.force.norm());
    return most;
  };
  const double clamped = kSpringN * alpha * kPitch * swing;
  const double linear = largest_bond_force(false), quadratic = largest_bond_force(true);
  EXPECT_LT(linear, 0.002 * clamped);  // measured: 0.03 %
  EXPECT_GT(quadratic, 0.02 * clamped);  // measured: 6.7 %
}
