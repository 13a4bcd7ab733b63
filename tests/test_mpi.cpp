// The MPI domain decomposition (parallel/): run under mpirun with 1, 2 and 4 processes
// (CTest does); every process also steps the whole world alone, and the two must agree bit
// for bit at every step.

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "parallel/mpi_domain.hpp"
#include "physics/dem/wall.hpp"
#include "prism_row.hpp"

namespace cleave {
namespace {

using parallel::Bisection;
using parallel::MpiDomain;
using physics::World;

/// Two layers of eight prisms lying on a floor, a gap between neighbours, all sliding +x:
/// friction on the floor and between the layers keeps shear histories while the bodies cross
/// the cuts between processes.
World sliding_world() {
  physics::WorldSettings ws = test::prism_settings(2e-6);
  ws.gravity = Eigen::Vector3d(0, 0, -9.81);
  World world(ws);
  const physics::RigidShape shape = test::prism();
  const auto sh = world.add_shape(shape);
  const double z0 = 0.5 * test::kThick + test::kDilation;
  const double pitch = test::kPitch + 0.4e-3;
  for (int layer = 0; layer < 2; ++layer) {
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d x(i * pitch + 0.1e-3 * layer, 0.0, z0 + layer * (test::kThick + 2.0 * test::kDilation));
      world.add_body(sh, test::kRho, x, shape.orientation_for(), Eigen::Vector3d(0.2 - 0.05 * layer, 0.0, 0.0));
    }
  }
  world.add_wall(physics::Wall::plane("floor", Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()));
  return world;
}

bool same(const physics::BodyState& a, const physics::BodyState& b) {
  auto eq = [](const auto& u, const auto& v) { return std::memcmp(&u, &v, sizeof u) == 0; };
  return eq(a.x, b.x) && eq(a.q.coeffs(), b.q.coeffs()) && eq(a.v, b.v) && eq(a.L, b.L) && eq(a.w, b.w) &&
         eq(a.f, b.f) && eq(a.tau, b.tau);
}

/// The owned bodies of `split` against the whole world `serial`; the walls' reactions too.
bool agrees(const World& split, const World& serial) {
  for (const physics::BodyId id : serial.body_ids()) {
    if (split.owns(id.index) && !same(split.state(id), serial.state(id))) return false;
  }
  for (std::size_t w = 0; w < serial.walls().size(); ++w) {
    if (std::memcmp(&split.walls()[w].reaction, &serial.walls()[w].reaction, sizeof(Eigen::Vector3d)) != 0) return false;
  }
  return true;
}

TEST(MpiDomain, SlidingBodiesCrossTheCutsWithTheirContactHistoriesAsOneProcessWouldStepThem) {
  World serial = sliding_world(), split = sliding_world();
  MpiDomain domain(1.05);  // re-cut as soon as one process owns a body more than its share
  domain.attach(split);
  bool apart = false;
  std::uint64_t first_apart = 0;
  for (int k = 0; k < 4000; ++k) {
    serial.step();
    split.step();
    if (!apart && !agrees(split, serial)) {
      apart = true;
      first_apart = split.steps();
    }
  }
  EXPECT_FALSE(domain.any(apart)) << "first difference at step " << first_apart;
  // The bodies slid about 0.7 mm: across the cuts when there are several processes.
  if (domain.size() > 1) {
    EXPECT_GT(domain.count(domain.stats().migrated), 0u);
    // The load drifted past the threshold and space was cut anew (beyond the first cuts).
    EXPECT_GT(domain.count(domain.stats().rebalances), static_cast<std::uint64_t>(domain.size()));
  }
  EXPECT_GT(domain.count(domain.stats().repartitions), 1u);
  // The friction springs were loaded (a history to carry), and the gathered world is the
  // whole world's state, histories included.
  domain.gather_all(split);
  EXPECT_EQ(split.state_hash(), serial.state_hash());
  EXPECT_GT(serial.state(serial.body_ids().front()).x.x(), 0.5e-3);
}

TEST(MpiDomain, ABondedRowPulledApartBreaksTheSameBondsAtTheSameSteps) {
  physics::BondParams params = test::strong_bonds();
  params.tbn = params.tbs = 1e6;  // Pa: broken after about a micrometre of opening
  auto make = [&] {
    World world(test::prism_settings(2e-6));
    const auto ids = test::row(world, 12);
    world.set_fixed(ids.front(), true);
    world.set_fixed(ids.back(), true);
    return world;
  };
  World serial = make(), split = make();
  MpiDomain domain;
  domain.attach(split);
  serial.initialise_bonds(params, 1e-6);
  split.initialise_bonds(params, 1e-6);
  ASSERT_EQ(split.bonds().size(), 11u);
  for (World* w : {&serial, &split}) {
    const physics::BodyId last = w->body_ids().back();
    w->state(last).v = Eigen::Vector3d(0.05, 0.0, 0.0);
  }
  bool apart = false;
  for (int k = 0; k < 3000; ++k) {
    serial.step();
    split.step();
    apart = apart || !agrees(split, serial);
  }
  EXPECT_FALSE(domain.any(apart));
  ASSERT_GT(serial.bond_breaks().size(), 0u);
  // Every process has the whole break log, as one process logs it.
  ASSERT_EQ(split.bond_breaks().size(), serial.bond_breaks().size());
  for (std::size_t b = 0; b < serial.bond_breaks().size(); ++b) {
    EXPECT_EQ(split.bond_breaks()[b].bond, serial.bond_breaks()[b].bond);
    EXPECT_EQ(split.bond_breaks()[b].step, serial.bond_breaks()[b].step);
    EXPECT_EQ(split.bond_breaks()[b].mode, serial.bond_breaks()[b].mode);
  }
  EXPECT_EQ(split.bond_counts().broken(), serial.bond_counts().broken());
  domain.gather_all(split);
  EXPECT_EQ(split.state_hash(), serial.state_hash());
}

TEST(Bisection, EveryPointLiesInItsOwnersBoxAndThePartsShareThePointsEvenly) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int parts : {1, 2, 3, 4, 7, 8}) {
    std::vector<Bisection::Point> points;
    for (std::uint32_t i = 0; i < 1000; ++i) points.push_back({Eigen::Vector3d(3.0 * u(rng), u(rng), 0.5 * u(rng)), i});
    const Bisection cuts(points, parts);
    std::vector<int> count(static_cast<std::size_t>(parts), 0);
    for (const auto& p : points) {
      const int owner = cuts.owner(p.x);
      ASSERT_GE(owner, 0);
      ASSERT_LT(owner, parts);
      ++count[static_cast<std::size_t>(owner)];
      EXPECT_EQ(cuts.distance(owner, p.x), 0.0);
      // Brute force: the point is outside (or on the rim of) every other part's box.
      for (int q = 0; q < parts; ++q) {
        if (q == owner) continue;
        const bool inside = (p.x.array() > cuts.lo(q).array()).all() && (p.x.array() < cuts.hi(q).array()).all();
        EXPECT_FALSE(inside);
      }
    }
    // Each part's share of 1000 points for its share of the parts, within one per cut level.
    for (int q = 0; q < parts; ++q) EXPECT_NEAR(count[static_cast<std::size_t>(q)], 1000.0 / parts, 3.0) << parts;
  }
}

}  // namespace
}  // namespace cleave

int main(int argc, char** argv) {
  cleave::parallel::MpiSession mpi(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  if (mpi.rank() != 0) {
    // One report: the other processes' results reach it through the collective checks.
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
