// The cohesive beam bond (seed 003: Andre et al. 2012's Euler-Bernoulli beam between two
// grains) against beam theory: the element's forces are the textbook two-node beam
// stiffness matrix for small end motions, nothing for a rigid motion, G J psi / L in
// torsion; a cantilever of beam-bonded grains under its own weight deflects, node by node,
// as Euler-Bernoulli's point-load solution says, and stretches under an axial pull as
// N L / (E A) adds up; a clamped, heated beam carries -E A alpha dT. Beams survive a split
// of the grain they hold and a checkpoint, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "geometry/exact_polyhedron.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"
#include "prism_row.hpp"

using namespace cleave;
using namespace cleave::physics;
using namespace cleave::test;

namespace {

constexpr double kYoung = 2e10, kPoisson = 0.25, kRadius = 1e-4;  // the beam: Pa, -, m
const double kI = M_PI * std::pow(kRadius, 4) / 4.0;
const double kA = M_PI * kRadius * kRadius;
const double kG = kYoung / (2.0 * (1.0 + kPoisson));

BondParams beam_params() {
  BondParams p;
  p.law = BondLaw::beam;
  p.beam_young = kYoung;
  p.beam_poisson = kPoisson;
  p.beam_radius = kRadius;
  p.sigma_f = std::numeric_limits<double>::infinity();
  return p;
}

/// A beam of length `l` along x at rest: ends at 0 and l x.
BeamPose rest_pose(double l) {
  BeamPose pose;
  pose.end_b = {l, 0, 0};
  pose.rest_length = l;
  return pose;
}

Eigen::Vector3d turn_about(const Eigen::Vector3d& v, const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()) * v;
}

}  // namespace

TEST(BeamForce, SmallEndMotionsFollowTheHermiteBeamElement) {
  // End B moved across by v and the ends turned by phi_a, phi_b in the x-y plane: the beam
  // acts on B with -(K u) of the textbook element (dofs v1, phi1, v2, phi2):
  //   F2 = EI/L^3 (-12 v1 - 6 L phi1 + 12 v2 - 6 L phi2),
  //   M2 = EI/L^3 (6 L v1 + 2 L^2 phi1 - 6 L v2 + 4 L^2 phi2).
  // The same in a turned frame, so that every axis is exercised.
  const double l = 1e-3, v = 2e-9, phi_a = 3e-6, phi_b = -5e-6;
  const double ei = kYoung * kI;
  const double f2 = ei / (l * l * l) * (12.0 * v - 6.0 * l * phi_a - 6.0 * l * phi_b);
  const double m2 = ei / (l * l * l) * (2.0 * l * l * phi_a - 6.0 * l * v + 4.0 * l * l * phi_b);
  const double m1 = ei / (l * l * l) * (4.0 * l * l * phi_a - 6.0 * l * v + 2.0 * l * l * phi_b);
  for (const Eigen::Quaterniond& frame :
       {Eigen::Quaterniond::Identity(), Eigen::Quaterniond(Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()))}) {
    BeamPose pose = rest_pose(l);
    pose.end_b.y() = v;
    pose.axis_a = turn_about(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), phi_a);
    pose.axis_b = turn_about(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), phi_b);
    pose.across_a = turn_about(Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), phi_a);
    pose.across_b = turn_about(Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), phi_b);
    for (Eigen::Vector3d* p : {&pose.end_a, &pose.end_b, &pose.axis_a, &pose.axis_b, &pose.across_a, &pose.across_b})
      *p = frame * *p;
    const BeamResult r = beam_force(beam_params(), pose);
    const Eigen::Vector3d force = frame.conjugate() * r.force_b;
    const Eigen::Vector3d mb = frame.conjugate() * r.moment_b, ma = frame.conjugate() * r.moment_a;
    EXPECT_NEAR(force.y(), -f2, 1e-4 * std::abs(f2));
    EXPECT_NEAR(mb.z(), -m2, 1e-4 * std::abs(m2));
    EXPECT_NEAR(ma.z(), -m1, 1e-4 * std::abs(m1));
    // Nothing out of the plane; the axial force is second order.
    EXPECT_LT(std::abs(force.z()), 1e-9 * std::abs(f2));
    EXPECT_LT(std::abs(force.x()), 1e-3 * std::abs(f2));
    EXPECT_LT(mb.head<2>().norm(), 1e-6 * std::abs(m2));
  }
}

TEST(BeamForce, AxialAndTorsionalSpringsAreEAOverLAndGJOverL) {
  const double l = 1e-3;
  BeamPose pose = rest_pose(l);
  pose.end_b.x() += 1e-7;  // stretched
  BeamResult r = beam_force(beam_params(), pose);
  EXPECT_NEAR(r.axial, kYoung * kA * 1e-7 / l, 1e-9 * r.axial);
  EXPECT_NEAR(r.force_b.x(), -kYoung * kA * 1e-7 / l, 1e-9 * r.axial);
  EXPECT_NEAR(r.peak_stress, kYoung * 1e-7 / l, 1e-9 * r.peak_stress);  // N / A, nothing bent
  // B turned about the axis by psi: restoring torque G J psi / L on B, the opposite on A.
  pose = rest_pose(l);
  const double psi = 0.01;
  pose.across_b = turn_about(Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), psi);
  r = beam_force(beam_params(), pose);
  const double torque = kG * 2.0 * kI * psi / l;
  EXPECT_NEAR(r.moment_b.x(), -torque, 1e-9 * torque);
  EXPECT_NEAR(r.moment_a.x(), torque, 1e-9 * torque);
  EXPECT_NEAR(r.torsion, torque, 1e-9 * torque);
  EXPECT_LT(r.force_b.norm(), 1e-12);
}

TEST(BeamForce, ARigidMotionLoadsNothing) {
  // Any rotation and translation of the whole beam, its ends' frames with it: no force, no
  // moment (co-rotational: large rigid motions are exact).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double l = 1e-3;
  const double scale = kYoung * kA * 1e-3;  // the axial force of a 0.1 % strain
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    const Eigen::Vector3d t(u(rng), u(rng), u(rng));
    BeamPose pose = rest_pose(l);
    pose.end_a = q * pose.end_a + t;
    pose.end_b = q * pose.end_b + t;
    for (Eigen::Vector3d* p : {&pose.axis_a, &pose.axis_b, &pose.across_a, &pose.across_b}) *p = q * *p;
    const BeamResult r = beam_force(beam_params(), pose);
    EXPECT_LT(r.force_b.norm(), 1e-9 * scale) << trial;
    EXPECT_LT(r.moment_a.norm() + r.moment_b.norm(), 1e-9 * scale * l) << trial;
  }
}

namespace {

World beam_world(const Eigen::Vector3d& gravity, double damping = 0.7) {
  WorldSettings ws;
  ws.gravity = gravity;
  ws.dt = 5e-7;
  ws.particle_particle.kn = 5000.0;
  ws.particle_particle.ks = 2000.0;
  ws.particle_wall = ws.particle_particle;
  ws.local_damping = damping;  // 0.7: quasi-static, the answers are equilibria
  ws.threads = 1;
  return World(ws);
}

constexpr double kGap = 2e-5;  // between neighbouring dilated surfaces: the grains never touch

/// n grains in a row along x, a gap apart, beam-bonded, the first one clamped.
std::vector<BodyId> cantilever(World& world, int n) {
  const std::vector<BodyId> ids = row(world, n, -kGap);
  world.set_fixed(ids.front(), true);
  EXPECT_EQ(world.initialise_bonds(beam_params(), 2.0 * kGap), static_cast<std::size_t>(n - 1));
  return ids;
}

}  // namespace

TEST(BeamCantilever, DeflectsUnderItsOwnWeightAsEulerBernoulliSays) {
  // Each grain's weight P = m g is a point load at its centroid, a distance x_i from the
  // clamped one's; Euler-Bernoulli's deflection at x_j is the sum over the loads of
  //   P x^2 (3 a - x) / (6 E I) for x <= a,  P a^2 (3 x - a) / (6 E I) for x >= a,
  // and the tip's slope the sum of P a^2 / (2 E I). Hermite beams between the grains are
  // exact at the nodes: the chain agrees within 0.1 % (0.01 % measured).
  const double g = 9.80665;
  World world = beam_world({0, 0, -g});
  const std::vector<BodyId> ids = cantilever(world, 6);
  std::vector<double> x0;
  for (BodyId id : ids) x0.push_back(world.state(id).x.x());
  for (int s = 0; s < 80000; ++s) world.step();
  const double ei = kYoung * kI;
  double tip_slope = 0.0;
  for (std::size_t j = 1; j < ids.size(); ++j) {
    const double x = x0[j] - x0[0];
    double expected = 0.0;
    for (std::size_t i = 1; i < ids.size(); ++i) {
      const double a = x0[i] - x0[0], p = world.info(ids[i]).mass * g;
      expected -= x <= a ? p * x * x * (3.0 * a - x) / (6.0 * ei) : p * a * a * (3.0 * x - a) / (6.0 * ei);
      if (j == 1) tip_slope -= p * a * a / (2.0 * ei);
    }
    const double w = world.state(ids[j]).x.z();
    EXPECT_NEAR(w, expected, 0.001 * std::abs(expected)) << "grain " << j;
  }
  // The tip grain's turn about y: its x axis dips by the slope (rotation -slope about y).
  const Eigen::Quaterniond q0 = prism().orientation_for();
  const Eigen::Vector3d dir = (world.state(ids.back()).q * q0.conjugate()) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(dir.z(), tip_slope, 0.001 * std::abs(tip_slope));
  // Settled, and no contact carried any of it.
  EXPECT_LT(world.state(ids.back()).v.norm(), 1e-6);
  EXPECT_TRUE(world.contacts().empty());
}

TEST(BeamCantilever, StretchesUnderAnAxialPullByTheSumOfNLOverEA) {
  // Gravity along the bar: segment k carries the weight of the grains beyond it, so the
  // tip moves by the sum over segments of N_k L_k / (E A).
  const double g = 5000.0;
  World world = beam_world({g, 0, 0});
  const std::vector<BodyId> ids = cantilever(world, 6);
  std::vector<double> x0;
  for (BodyId id : ids) x0.push_back(world.state(id).x.x());
  for (int s = 0; s < 60000; ++s) world.step();
  double expected = 0.0;
  for (std::size_t k = 1; k < ids.size(); ++k) {
    double load = 0.0;
    for (std::size_t i = k; i < ids.size(); ++i) load += world.info(ids[i]).mass * g;
    expected += load * (x0[k] - x0[k - 1]) / (kYoung * kA);
  }
  const double moved = world.state(ids.back()).x.x() - x0.back();
  EXPECT_NEAR(moved, expected, 0.001 * expected);
  // The first beam's axial force is the whole weight beyond it.
  double weight = 0.0;
  for (std::size_t i = 1; i < ids.size(); ++i) weight += world.info(ids[i]).mass * g;
  EXPECT_NEAR(world.bonds().front().state.normal, weight, 0.01 * weight);
}

TEST(BeamCantilever, AClampedHeatedBeamCarriesMinusEAAlphaDeltaT) {
  // Both grains held: the beam's rest length grows by alpha L dT, so it pushes with
  // E A alpha dT (compression: the axial force is negative).
  World world = beam_world(Eigen::Vector3d::Zero());
  const std::vector<BodyId> ids = cantilever(world, 2);
  world.set_fixed(ids.back(), true);
  const double alpha = 8e-6, dT = 50.0;
  for (BodyId id : ids) world.set_expansion(id, alpha * Eigen::Matrix3d::Identity());
  world.set_temperature(world.temperature(ids.front()) + dT);  // from the temperature bonded at
  world.step();
  const double expected = -kYoung * kA * alpha * dT;
  EXPECT_NEAR(world.bonds().front().state.normal, expected, 1e-3 * std::abs(expected));
}

TEST(BeamTorsion, ATwistedEndIsHeldByGJPsiOverL) {
  // Both grains held; B spins about the beam's axis for a while: the torque on B is
  // -G J psi / L with psi the angle it turned.
  World world = beam_world(Eigen::Vector3d::Zero());
  const std::vector<BodyId> ids = cantilever(world, 2);
  world.set_fixed(ids.back(), true);
  const double spin = 2.0, steps = 4000;  // rad/s
  world.set_angular_velocity(ids.back(), {spin, 0, 0});
  for (int s = 0; s < steps; ++s) world.step();
  const double psi = spin * steps * 5e-7;
  const double l = world.bonds().front().beam.rest_length;
  const double expected = -kG * 2.0 * kI * psi / l;
  EXPECT_NEAR(world.bonds().front().moment.x(), expected, 2e-3 * std::abs(expected));
  EXPECT_NEAR(world.bonds().front().state.torsion, expected, 2e-3 * std::abs(expected));
}

TEST(BeamBreak, ABeamBreaksWhenItsOuterFibreReachesSigmaF) {
  // sigma_f between the stress the pull makes and twice it: breaks on the way, in tension.
  const double g = 5000.0;
  World world = beam_world({g, 0, 0}, 0.0);  // undamped: the load overshoots
  const std::vector<BodyId> ids = row(world, 2, -kGap);
  world.set_fixed(ids.front(), true);
  BondParams p = beam_params();
  const double stress = world.info(ids.back()).mass * g / kA;  // the static pull's N / A
  p.sigma_f = 1.5 * stress;  // the dynamic overshoot of a suddenly applied load is 2x
  world.initialise_bonds(p, 2.0 * kGap);
  for (int s = 0; s < 20000 && world.bond_breaks().empty(); ++s) world.step();
  ASSERT_EQ(world.bond_breaks().size(), 1u);
  EXPECT_EQ(world.bond_breaks().front().mode, BondFailure::tension);
  EXPECT_GT(world.bond_breaks().front().loads.normal / kA, p.sigma_f);
}

TEST(BeamState, ABeamKeepsItsLoadWhenItsGrainSplits) {
  // The beam's end is a material point: after the grain holding it splits, the piece that
  // takes the bond holds the same end, so the beam's force is the same before and after.
  const geometry::ExactPolyhedron shape = geometry::ExactPolyhedron::hexagonal_prism(kSide, kThick);
  World world = beam_world(Eigen::Vector3d::Zero());
  const std::vector<BodyId> ids = cantilever(world, 2);
  world.set_fixed(ids.back(), true);
  // Load it: B pushed across and turned.
  world.state(ids.back()).x += Eigen::Vector3d(2e-7, 3e-7, -1e-7);
  world.state(ids.back()).q = Eigen::Quaterniond(Eigen::AngleAxisd(2e-4, Eigen::Vector3d(1, 2, 3).normalized())) *
                              world.state(ids.back()).q;
  // The beam's force on grain B (the bond's A and B trade places when B's slot is lower).
  const std::uint32_t grain_b = ids.back().index;
  auto on_b = [&] {
    const Bond& bd = world.bonds().front();
    return Eigen::Vector3d(bd.b == grain_b ? bd.force : -bd.force);
  };
  world.step();
  const Eigen::Vector3d before = on_b();
  ASSERT_GT(before.norm(), 0.0);
  const RigidShape parent_shape = world.shape(world.info(ids.front()).shape);
  std::vector<Fragment> pieces;
  for (const auto& slab : shape.cleavage_slabs({geometry::CleavageFamily::m_10_10, 60})) {
    const RigidShape piece = make_rigid_shape(slab, kDilation);
    pieces.push_back(fragment_placement(parent_shape, piece, world.add_shape(piece)));
  }
  // The fixed grain A splits; its pieces stay held.
  world.split_body(ids.front(), pieces);
  ASSERT_EQ(world.bonds().size(), 1u);
  world.step();
  const Eigen::Vector3d after = on_b();
  EXPECT_LT((after - before).norm(), 1e-6 * before.norm()) << before.transpose() << " / " << after.transpose();
}

TEST(BeamState, ACheckpointCarriesTheBeamsOnBitForBit) {
  auto run = [](World& world, int steps) {
    for (int s = 0; s < steps; ++s) world.step();
  };
  World a = beam_world({0, 0, -9.80665});
  const std::vector<BodyId> ids = cantilever(a, 4);
  a.set_expansion(ids[2], 1e-5 * Eigen::Matrix3d::Identity());
  a.set_temperature(ids[2], 350.0);  // its beams' rest lengths grow
  run(a, 700);
  StateWriter w;
  a.save_state(w);
  World b = beam_world({0, 0, -9.80665});
  StateReader r(w.bytes());
  b.load_state(r);
  EXPECT_EQ(a.state_hash(), b.state_hash());
  run(a, 700);
  run(b, 700);
  EXPECT_EQ(a.state_hash(), b.state_hash());
  EXPECT_EQ(a.bonds()[1].beam.rest_length, b.bonds()[1].beam.rest_length);
  EXPECT_EQ(a.bonds().back().force, b.bonds().back().force);
  EXPECT_TRUE(b.bonds().back().force.norm() > 0.0);
}
