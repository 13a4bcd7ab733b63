// Periodic cells (issue 23): the nearest image and the wrap against a brute-force search; a
// body leaving through one face comes in through the other with its momentum; a contact and
// a bond across the boundary give, step by step, what the same pair gives inside a world
// without a cell; a honeycomb pulled through its periodic cell has the Young's modulus and
// Poisson's ratio of the bulk of a large non-periodic block, and of the closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "physics/dem/state_codec.hpp"
#include "physics/dem/step_guard.hpp"
#include "physics/dem/world.hpp"
#include "prism_row.hpp"
#include "stress_sum_reference.hpp"
#include "validation/standard_tests.hpp"

using namespace cleave;
using namespace cleave::physics;
using namespace cleave::test;

namespace {


WorldSettings settings() {
  WorldSettings ws = prism_settings(1e-7);
  ws.particle_particle.damping_ratio = 0.1;
  ws.particle_wall = ws.particle_particle;
  return ws;
}

}  // namespace

TEST(PeriodicCell, TheNearestImageAndTheWrapMatchABruteForceSearch) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d size(1.0 + u(rng) * 0.5, 2.0 + u(rng), 1.5 + u(rng) * 0.5);
    const Eigen::Vector3d lo(u(rng), u(rng), u(rng));
    const std::array<bool, 3> periodic{true, trial % 2 == 0, trial % 3 != 0};
    const PeriodicCell cell = PeriodicCell::box(lo, lo + size, periodic);
    const Eigen::Vector3d a = lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(size) * 3.0;
    const Eigen::Vector3d b = lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(size) * 3.0;
    // Brute force: every image within eight cells, the nearest by distance.
    Eigen::Vector3i best = Eigen::Vector3i::Zero();
    double nearest = (b - a).norm();
    for (int x = -8; x <= 8; ++x) {
      for (int y = -8; y <= 8; ++y) {
        for (int z = -8; z <= 8; ++z) {
          const Eigen::Vector3i n(periodic[0] ? x : 0, periodic[1] ? y : 0, periodic[2] ? z : 0);
          const double d = (b + size.cwiseProduct(n.cast<double>()) - a).norm();
          if (d < nearest) {
            nearest = d;
            best = n;
          }
        }
      }
    }
    EXPECT_EQ(cell.nearest_image(a, b), best) << trial;
    // The wrap puts a point in [lo, lo + size) along the periodic axes, by whole cells.
    const Eigen::Vector3d home = a - cell.shift(cell.outside(a));
    for (int k = 0; k < 3; ++k) {
      if (!periodic[k]) {
        EXPECT_EQ(home[k], a[k]);
        continue;
      }
      EXPECT_GE(home[k], lo[k] - 1e-12);
      EXPECT_LT(home[k], lo[k] + size[k] + 1e-12);
      const double cells = (a[k] - home[k]) / size[k];
      EXPECT_NEAR(cells, std::round(cells), 1e-9);
    }
  }
}

TEST(PeriodicWorld, ABodyLeavingOneFaceEntersTheOtherWithItsMomentum) {
  World world(settings());
  const RigidShape shape = prism();
  const auto sh = world.add_shape(shape);
  const double lx = 6e-3;
  world.set_cell(PeriodicCell::box({0, -5e-3, -5e-3}, {lx, 5e-3, 5e-3}, {true, false, false}));
  const Eigen::Vector3d v(2.0, 0.3, 0.0), w(0.0, 0.0, 40.0);
  const BodyId id = world.add_body(sh, kRho, {lx - 1e-4, 0, 0}, shape.orientation_for(), v, w);
  const Eigen::Vector3d p0 = world.linear_momentum();
  StepGuard guard;
  const int steps = 3000;  // 0.3 ms: 0.6 mm along x, through the face at x = lx
  for (int s = 0; s < steps; ++s) {
    guard.before_step(world);
    world.step();
    ASSERT_FALSE(guard.check(world).has_value()) << "the wrap is not a blow-up, step " << s;
  }
  const BodyState& st = world.state(id);
  EXPECT_NEAR(st.x.x(), lx - 1e-4 + v.x() * steps * 1e-7 - lx, 1e-12);  // came in at x = 0
  EXPECT_GE(st.x.x(), 0.0);
  EXPECT_NEAR(st.x.y(), v.y() * steps * 1e-7, 1e-12);  // not periodic in y: no wrap
  EXPECT_EQ(st.v, v);
  EXPECT_TRUE(st.w.isApprox(w, 1e-12));
  EXPECT_TRUE(world.linear_momentum().isApprox(p0, 1e-14));
}

namespace {

/// Two grains side by side along x, B on A's left, their dilated surfaces `overlap` into
/// each other (negative: apart). In the periodic world (a cell periodic in x from 0 to
/// kCell) A sits just inside the face at x = 0 and B beyond it: the first step wraps B to
/// the far face, and the two meet through B's image.
struct Pair {
  World world;
  BodyId a, b;
};

constexpr double kCell = 5e-3;

Pair pair(bool periodic, double overlap, const Eigen::Vector3d& va, const Eigen::Vector3d& vb,
          const Eigen::Vector3d& wa) {
  Pair p{World(settings()), {}, {}};
  const RigidShape shape = prism();
  const auto sh = p.world.add_shape(shape);
  const double xa = 0.3 * kPitch, xb = xa - kPitch + overlap;
  if (periodic) p.world.set_cell(PeriodicCell::box({0, -4e-3, -4e-3}, {kCell, 4e-3, 4e-3}, {true, false, false}));
  p.a = p.world.add_body(sh, kRho, {xa, 0, 0}, shape.orientation_for(), va, wa);
  p.b = p.world.add_body(sh, kRho, {xb, 0, 0}, shape.orientation_for(), vb);
  return p;
}

}  // namespace

TEST(PeriodicWorld, AContactAcrossTheBoundaryIsTheSameContactAsInside) {
  // B comes at A obliquely with A spinning: normal, tangential (incremental, Coulomb) and
  // rolling terms all act. Step by step, the force on B and the pair's relative position
  // agree with the pair in open space to round-off.
  const Eigen::Vector3d va(0.2, 0.1, 0.0), vb(1.0, -0.4, 0.05), wa(0, 0, 30.0);
  Pair in = pair(false, -1e-6, va, vb, wa);
  Pair across = pair(true, -1e-6, va, vb, wa);
  double largest = 0.0;
  for (int s = 0; s < 4000; ++s) {
    in.world.step();
    across.world.step();
    // B was placed left of the face at x = 0: the first step wrapped it to the far face.
    ASSERT_GT(across.world.state(across.b).x.x(), 0.5 * kCell);
    const Eigen::Vector3d f_in = in.world.state(in.b).f, f_across = across.world.state(across.b).f;
    largest = std::max(largest, f_in.norm());
    ASSERT_LT((f_in - f_across).norm(), 1e-7 * std::max(f_in.norm(), 1e-3)) << "step " << s;
    ASSERT_LT((in.world.state(in.b).tau - across.world.state(across.b).tau).norm(), 1e-6 * std::max(largest, 1e-3) * kPitch)
        << "step " << s;
    Eigen::Vector3d gap_in = in.world.state(in.b).x - in.world.state(in.a).x;
    Eigen::Vector3d gap_across = across.world.state(across.b).x - across.world.state(across.a).x;
    gap_across.x() = std::remainder(gap_across.x(), kCell);
    ASSERT_LT((gap_in - gap_across).norm(), 1e-12) << "step " << s;
    // The records name B's image: its lever arm from B is the one inside.
    const auto& ci = in.world.contacts();
    const auto& ca = across.world.contacts();
    ASSERT_EQ(ci.size(), ca.size()) << "step " << s;
    for (std::size_t k = 0; k < ci.size(); ++k) {
      EXPECT_EQ(ca[k].shift, Eigen::Vector3d(-kCell, 0, 0));
      const Eigen::Vector3d arm_in = ci[k].point - in.world.state(in.b).x;
      const Eigen::Vector3d arm_across = ca[k].point - ca[k].shift - across.world.state(across.b).x;
      ASSERT_LT((arm_in - arm_across).norm(), 1e-12);
    }
  }
  EXPECT_GT(largest, 1e-3);  // they did collide
}

TEST(PeriodicWorld, ABondAcrossTheBoundaryIsTheSameBondAsInside) {
  // Bonded touching, then pulled apart obliquely and twisted: the bond's force and moment
  // follow the same history across the boundary as inside; at the end it breaks the same.
  const Eigen::Vector3d va(0.05, 0.02, 0.0), vb(-0.05, -0.03, 0.01), wa(0, 0, 5.0);
  Pair in = pair(false, 0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  Pair across = pair(true, 0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  BondParams weak = strong_bonds();
  weak.tbn = 3e4;  // breaks in tension within the run
  ASSERT_EQ(in.world.initialise_bonds(weak, 1e-6), 1u);
  ASSERT_EQ(across.world.initialise_bonds(weak, 1e-6), 1u);
  for (World* w : {&in.world, &across.world}) {
    const auto ids = w->body_ids();
    w->state(ids[0]).v = va;
    w->set_angular_velocity(ids[0], wa);
    w->state(ids[1]).v = vb;
  }
  for (int s = 0; s < 6000; ++s) {
    in.world.step();
    across.world.step();
    const Bond& bi = in.world.bonds().front();
    const Bond& ba = across.world.bonds().front();
    ASSERT_EQ(bi.intact(), ba.intact()) << "step " << s;
    ASSERT_LT((bi.force - ba.force).norm(), 1e-7 * std::max(bi.force.norm(), 1e-4)) << "step " << s;
    ASSERT_LT((bi.moment - ba.moment).norm(), 1e-7 * std::max(bi.moment.norm(), 1e-9)) << "step " << s;
    ASSERT_LT((in.world.state(in.b).f - across.world.state(across.b).f).norm(), 1e-7 * std::max(bi.force.norm(), 1e-4));
  }
  // B went home to the far face; the bond joins A to its image on A's left.
  EXPECT_GT(across.world.state(across.b).x.x(), 0.5 * kCell);
  EXPECT_EQ(across.world.bonds().front().image, Eigen::Vector3i(-1, 0, 0));
  ASSERT_EQ(in.world.bond_breaks().size(), 1u);
  ASSERT_EQ(across.world.bond_breaks().size(), 1u);
  EXPECT_EQ(in.world.bond_breaks().front().step, across.world.bond_breaks().front().step);
  EXPECT_EQ(in.world.bond_breaks().front().mode, across.world.bond_breaks().front().mode);
}

namespace {

/// A honeycomb layer of nx x ny prisms (ny even), flats facing +-x, touching; positions of
/// the triangular lattice of spacing kPitch.
std::vector<BodyId> honeycomb(World& world, int nx, int ny) {
  const RigidShape shape = prism();
  const auto sh = world.add_shape(shape);
  std::vector<BodyId> ids;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Eigen::Vector3d x((i + 0.5 * (j % 2) + 0.25) * kPitch, (j + 0.5) * kPitch * std::sqrt(3.0) / 2.0, 0.0);
      ids.push_back(world.add_body(sh, kRho, x, shape.orientation_for()));
    }
  }
  return ids;
}

}  // namespace

TEST(PeriodicWorld, AHoneycombPulledThroughItsCellHasTheBulkYoungsModulus) {
  // Uniaxial strain eps along x (y held): sigma_xx = (lambda + 2 mu) eps, sigma_yy =
  // lambda eps, so nu = sigma_yy / sigma_xx and E = (sigma_xx / eps)(1 - nu^2).
  // - Periodic: an 8 x 8 cell, every grain riding the cell's velocity gradient; the stress
  //   is World::cell_stress.
  // - Bulk: a 24 x 24 block without a cell, every grain moved by the same affine field;
  //   the stress is the mean over the grains at least four rows from any edge of their
  //   Love-Weber stresses times their volume, per honeycomb cell area.
  // Both against each other and the closed form (validation/standard_tests.hpp).
  const double rate = 2.0, eps_steps = 500;  // 1/s; strain 1e-4 at dt 1e-7
  const double eps = rate * eps_steps * 1e-7;
  const double per_body = std::sqrt(3.0) / 2.0 * kPitch * kPitch;  // honeycomb cell area
  // Periodic.
  World cell_world(settings());
  const int n = 8;
  const std::vector<BodyId> ids = honeycomb(cell_world, n, n);
  const double ly = n * kPitch * std::sqrt(3.0) / 2.0;
  cell_world.set_cell(PeriodicCell::box({0, 0, -0.5 * kThick}, {n * kPitch, ly, 0.5 * kThick}, {true, true, false}));
  ASSERT_EQ(cell_world.initialise_bonds(strong_bonds(), 1e-6), static_cast<std::size_t>(3 * n * n));
  for (BodyId id : ids) cell_world.set_fixed(id, true);  // ride the affine field exactly
  Eigen::Matrix3d l = Eigen::Matrix3d::Zero();
  l(0, 0) = rate;
  cell_world.set_velocity_gradient(l);
  for (int s = 0; s < eps_steps; ++s) cell_world.step();
  const double strain = cell_world.cell()->vectors()(0, 0) / (n * kPitch) - 1.0;
  EXPECT_NEAR(strain, eps, 1e-3 * eps);
  const Eigen::Matrix3d sp = cell_world.cell_stress();
  EXPECT_TRUE(cell_world.contacts().empty());  // pulled: only the bonds carry
  // Bulk.
  World block(settings());
  const int m = 24;
  const std::vector<BodyId> all = honeycomb(block, m, m);
  block.initialise_bonds(strong_bonds(), 1e-6);
  for (BodyId id : all) {
    block.set_fixed(id, true);
    block.state(id).v = Eigen::Vector3d(rate * block.state(id).x.x(), 0, 0);
  }
  for (int s = 0; s < eps_steps; ++s) block.step();
  const std::vector<Eigen::Matrix3d> stress = block.body_stresses();
  Eigen::Matrix3d sb = Eigen::Matrix3d::Zero();
  int inner = 0;
  const double volume = cell_world.shape(0).volume;
  for (int j = 4; j < m - 4; ++j) {
    for (int i = 4; i < m - 4; ++i) {
      sb += stress[all[static_cast<std::size_t>(j * m + i)].index] * volume / (per_body * kThick);
      ++inner;
    }
  }
  sb /= inner;
  // Against each other.
  EXPECT_NEAR(sp(0, 0), sb(0, 0), 1e-3 * sb(0, 0));
  EXPECT_NEAR(sp(1, 1), sb(1, 1), 1e-3 * sb(0, 0));
  const double nu_p = sp(1, 1) / sp(0, 0), e_p = sp(0, 0) / strain * (1.0 - nu_p * nu_p);
  const double nu_b = sb(1, 1) / sb(0, 0), e_b = sb(0, 0) / eps * (1.0 - nu_b * nu_b);
  EXPECT_NEAR(e_p / e_b, 1.0, 2e-3) << "periodic " << e_p << " Pa, bulk " << e_b << " Pa";
  // Against the closed form.
  const HoneycombElasticity closed = honeycomb_elasticity(kSpringN, kSpringS, kThick);
  EXPECT_NEAR(e_p / closed.young, 1.0, 2e-3) << e_p << " vs " << closed.young;
  EXPECT_NEAR(nu_p, closed.poisson, 2e-3);
  // No shear, and no stress through the thickness (the layer is free in z).
  EXPECT_LT(std::abs(sp(0, 1)), 1e-6 * sp(0, 0));
  EXPECT_LT(std::abs(sp(2, 2)), 1e-6 * sp(0, 0));
}

TEST(PeriodicWorld, StressSumsByBodyTakeBsLeverFromItsImageAsTheRecordsDo) {
  // An 8 x 8 bonded cell squeezed along x: contacts and bonds across the periodic faces act
  // on B's image. World::stress_sums and forces_on (from the lists by body) give every slot
  // the bits of a walk over contacts() and bonds() with their shifts.
  World world(settings());
  const int n = 8;
  const std::vector<BodyId> ids = honeycomb(world, n, n);
  const double ly = n * kPitch * std::sqrt(3.0) / 2.0;
  world.set_cell(PeriodicCell::box({0, 0, -0.5 * kThick}, {n * kPitch, ly, 0.5 * kThick}, {true, true, false}));
  world.initialise_bonds(strong_bonds(), 1e-6);
  Eigen::Matrix3d l = Eigen::Matrix3d::Zero();
  l(0, 0) = -20.0;
  world.set_velocity_gradient(l);
  for (int s = 0; s < 300; ++s) world.step();
  std::size_t across = 0, bonds_across = 0;
  for (const ContactRecord& c : world.contacts()) across += !c.shift.isZero(0.0);
  for (const Bond& bd : world.bonds()) bonds_across += !bd.shift.isZero(0.0);
  ASSERT_GT(across, 0u);
  ASSERT_GT(bonds_across, 0u);
  expect_sums_match_the_records(world, "a squeezed periodic cell, by body");
  SumsWithTheForces sums;
  world.add_listener(&sums);
  world.step();
  world.remove_listener(&sums);
  expect_sums_match_the_records(world, "a squeezed periodic cell, with the forces");
}

TEST(PeriodicWorld, UnderStressControlAStrainedCellRelaxesToItsStressFreeSize) {
  // The 8 x 8 honeycomb cell squeezed by 1e-4 along x (grains riding the field), then let
  // go with Berendsen's control on: modulus M = sigma_xx / eps of the squeezed cell (its
  // uniaxial-strain stiffness), tau = 1000 steps. After eight tau the mean normal
  // stresses are below 1 % of the squeeze's and the cell is back to its size within 5 %
  // of the squeeze (the honeycomb's bonds are stress-free at their bonding length).
  WorldSettings ws = settings();
  ws.local_damping = 0.7;
  World world(ws);
  const int n = 8;
  const std::vector<BodyId> ids = honeycomb(world, n, n);
  const double lx = n * kPitch, ly = n * kPitch * std::sqrt(3.0) / 2.0;
  world.set_cell(PeriodicCell::box({0, 0, -0.5 * kThick}, {lx, ly, 0.5 * kThick}, {true, true, false}));
  ASSERT_EQ(world.initialise_bonds(strong_bonds(), 1e-6), static_cast<std::size_t>(3 * n * n));
  for (BodyId id : ids) world.set_fixed(id, true);
  Eigen::Matrix3d l = Eigen::Matrix3d::Zero();
  l(0, 0) = -2.0;  // 1/s: 1e-4 over 500 steps of 1e-7 s
  world.set_velocity_gradient(l);
  for (int s = 0; s < 500; ++s) world.step();
  const double squeeze = world.cell()->vectors()(0, 0) / lx - 1.0;
  ASSERT_NEAR(squeeze, -1e-4, 1e-7);
  const Eigen::Matrix3d squeezed = world.cell_stress();
  ASSERT_LT(squeezed(0, 0), 0.0);
  const double modulus = squeezed(0, 0) / squeeze, tau = 1000 * 1e-7;
  for (BodyId id : ids) world.set_fixed(id, false);
  world.set_velocity_gradient(Eigen::Matrix3d::Zero());
  world.set_stress_control(modulus, tau);
  for (int s = 0; s < 8000; ++s) world.step();
  const Eigen::Matrix3d relaxed = world.cell_stress();
  EXPECT_LT(std::abs(relaxed(0, 0)), 0.01 * std::abs(squeezed(0, 0))) << relaxed;
  EXPECT_LT(std::abs(relaxed(1, 1)), 0.01 * std::abs(squeezed(0, 0))) << relaxed;
  EXPECT_LT(std::abs(world.cell()->vectors()(0, 0) / lx - 1.0), 0.05 * 1e-4);
  EXPECT_LT(std::abs(world.cell()->vectors()(1, 1) / ly - 1.0), 0.05 * 1e-4);
  // Without the control the squeezed cell keeps its stress.
  world.set_stress_control(modulus, 0.0);
  for (BodyId id : ids) world.set_fixed(id, true);
  world.set_velocity_gradient(l);
  for (int s = 0; s < 500; ++s) world.step();
  world.set_velocity_gradient(Eigen::Matrix3d::Zero());
  for (BodyId id : ids) world.set_fixed(id, false);
  for (int s = 0; s < 4000; ++s) world.step();
  EXPECT_GT(std::abs(world.cell_stress()(0, 0)), 0.5 * std::abs(squeezed(0, 0)));
}

TEST(PeriodicWorld, ACheckpointOfAStrainingCellCarriesOnBitForBit) {
  auto setup = [](World& world) {
    const std::vector<BodyId> ids = honeycomb(world, 6, 6);
    world.set_cell(PeriodicCell::box({0, 0, -0.5 * kThick}, {6 * kPitch, 3 * std::sqrt(3.0) * kPitch, 0.5 * kThick},
                                     {true, true, false}));
    world.initialise_bonds(strong_bonds(), 1e-6);
    world.state(ids[7]).v = Eigen::Vector3d(0.3, -0.2, 0.1);  // something moves
    Eigen::Matrix3d l = Eigen::Matrix3d::Zero();
    l(0, 0) = 5.0;
    l(0, 1) = 1.0;
    world.set_velocity_gradient(l);
  };
  WorldSettings ws = settings();
  ws.local_damping = 0.3;
  World a(ws);
  setup(a);
  for (int s = 0; s < 300; ++s) a.step();
  StateWriter w;
  a.save_state(w);
  World b(ws);
  StateReader r(w.bytes());
  b.load_state(r);
  EXPECT_EQ(a.state_hash(), b.state_hash());
  ASSERT_NE(b.cell(), nullptr);
  EXPECT_EQ(a.cell()->vectors(), b.cell()->vectors());
  for (int s = 0; s < 300; ++s) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.state_hash(), b.state_hash());
  EXPECT_EQ(a.cell_stress(), b.cell_stress());
}

TEST(PeriodicWorld, BadCellsAreRefused) {
  World world(settings());
  honeycomb(world, 2, 2);
  EXPECT_THROW(world.set_cell(PeriodicCell::box({0, 0, 0}, {1e-3, 1e-3, 1e-3}, {false, false, false})),
               std::invalid_argument);
  EXPECT_THROW(world.set_velocity_gradient(Eigen::Matrix3d::Identity()), std::logic_error);
  EXPECT_THROW((void)world.cell_stress(), std::logic_error);
  // Two grains across: a pair would meet twice.
  world.set_cell(PeriodicCell::box({0, 0, -1e-3}, {2 * kPitch, 2 * kPitch, 1e-3}, {true, true, false}));
  EXPECT_THROW(world.step(), std::runtime_error);
}
