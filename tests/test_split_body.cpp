// A body replaced mid-run by the exact pieces it breaks into (chapter 3 of seed 000): mass,
// linear and angular momentum kept through the split, the exact volume kept, the pieces in
// the parent's place, and bonds handed to the piece that holds their point.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/exact_polyhedron.hpp"
#include "physics/dem/world.hpp"

using namespace cleave;
using namespace cleave::physics;

namespace {

constexpr double kSide = 0.5e-3, kThick = 1.0e-3, kDilation = 0.05e-3, kRho = 3100.0;

World quiet_world() {
  WorldSettings ws;
  ws.gravity.setZero();
  ws.dt = 1e-7;
  ws.particle_particle.kn = 5000.0;
  ws.particle_wall.kn = 5000.0;
  ws.threads = 1;
  return World(ws);
}

/// Relative difference, for vectors of any scale.
double rel(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() / std::max(a.norm(), b.norm());
}

}  // namespace

TEST(SplitBody, CleavageSlabsKeepMassMomentumAngularMomentumAndExactVolume) {
  const geometry::ExactPolyhedron prism = geometry::ExactPolyhedron::hexagonal_prism(kSide, kThick);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto family : {geometry::CleavageFamily::a_11_20, geometry::CleavageFamily::m_10_10}) {
    for (const int angle : {0, 60, 120}) {
      const std::vector<geometry::ExactPolyhedron> slabs = prism.cleavage_slabs({family, angle});
      ASSERT_GE(slabs.size(), 2u);
      // Exact: the slabs' volumes sum to the prism's, compared as rationals.
      EXPECT_TRUE(geometry::total_volume(slabs) == prism.volume());

      World world = quiet_world();
      const RigidShape parent_shape = make_rigid_shape(prism, kDilation);
      const auto parent_index = world.add_shape(parent_shape);
      std::vector<Fragment> pieces;
      double piece_volume = 0.0;
      for (const auto& slab : slabs) {
        const RigidShape piece = make_rigid_shape(slab, kDilation);
        piece_volume += piece.volume;
        pieces.push_back(fragment_placement(parent_shape, piece, world.add_shape(piece)));
      }
      // A moving, tumbling grain at a random place and orientation.
      const Eigen::Quaterniond q =
          Eigen::Quaterniond(Eigen::AngleAxisd(3.0 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()));
      const Eigen::Vector3d x(u(rng) * 1e-2, u(rng) * 1e-2, u(rng) * 1e-2);
      const Eigen::Vector3d v(u(rng), u(rng), u(rng)), w(300 * u(rng), 300 * u(rng), 300 * u(rng));
      const BodyId parent = world.add_body(parent_index, kRho, x, parent_shape.orientation_for(q), v, w, 7);
      const double m0 = world.info(parent).mass;
      const Eigen::Vector3d p0 = world.linear_momentum(), L0 = world.angular_momentum();
      const double ke0 = world.kinetic_energy();
      // The parent's corners, in the world.
      std::vector<Eigen::Vector3d> corners;
      for (const auto& c : parent_shape.primitives.vertices) corners.push_back(x + world.state(parent).q * c);

      const std::vector<BodyId> ids = world.split_body(parent, pieces);
      ASSERT_EQ(ids.size(), slabs.size());
      EXPECT_FALSE(world.contains(parent));
      double m = 0.0;
      for (const BodyId id : ids) {
        m += world.info(id).mass;
        EXPECT_EQ(world.info(id).grain_id, 7);
      }
      const std::string what = std::string(to_string(family)) + " " + std::to_string(angle);
      EXPECT_NEAR(m, m0, 1e-12 * m0) << what;
      EXPECT_NEAR(piece_volume, parent_shape.volume, 1e-12 * parent_shape.volume) << what;
      EXPECT_LT(rel(world.linear_momentum(), p0), 1e-12) << what;
      EXPECT_LT(rel(world.angular_momentum(), L0), 1e-12) << what;
      // A rigid split moves nothing relative to anything: kinetic energy is kept too.
      EXPECT_NEAR(world.kinetic_energy(), ke0, 1e-11 * ke0) << what;
      // Every corner of every piece lies on or inside the parent, and every corner of the
      // parent is a corner of some piece.
      std::size_t matched = 0;
      for (const auto& c : corners) {
        bool found = false;
        for (const BodyId id : ids) {
          const auto& s = world.state(id);
          for (const auto& pv : world.shape(world.info(id).shape).primitives.vertices) {
            found = found || (s.x + s.q * pv - c).norm() < 1e-12;
          }
        }
        matched += found;
      }
      EXPECT_EQ(matched, corners.size()) << what;
    }
  }
}

TEST(SplitBody, BondsGoToThePieceThatHoldsTheirPoint) {
  // Prism 0 in the middle, bonded to a neighbour on its +x side and one on its -x side.
  // Split it in two along the plane x = 0: each bond must follow the half on its side,
  // with its point and normal where they were, and the bonded assembly stays at rest.
  const geometry::ExactPolyhedron prism = geometry::ExactPolyhedron::hexagonal_prism(kSide, kThick);
  World world = quiet_world();
  const RigidShape shape = make_rigid_shape(prism, kDilation);
  const auto sh = world.add_shape(shape);
  const double pitch = std::sqrt(3.0) * kSide + 2 * kDilation - 2e-6;
  const BodyId mid = world.add_body(sh, kRho, {0, 0, 0}, shape.orientation_for());
  const BodyId right = world.add_body(sh, kRho, {pitch, 0, 0}, shape.orientation_for());
  const BodyId left = world.add_body(sh, kRho, {-pitch, 0, 0}, shape.orientation_for());
  const BondParams params{5000.0 / (M_PI * kDilation * kDilation), 0.0, 1e6, 1e6};
  ASSERT_EQ(world.initialise_bonds(params, 0.0), 2u);
  std::vector<Eigen::Vector3d> points;
  for (const Bond& b : world.bonds()) points.push_back(b.point);

  const auto halves = prism.split(geometry::ExactPlane::from_normal_offset({1, 0, 0}, 0.0));
  ASSERT_TRUE(halves.ok());
  std::vector<Fragment> pieces;
  for (const auto& half : {*halves.below, *halves.above}) {
    const RigidShape piece = make_rigid_shape(half, kDilation);
    pieces.push_back(fragment_placement(shape, piece, world.add_shape(piece)));
  }
  const std::vector<BodyId> ids = world.split_body(mid, pieces);
  ASSERT_EQ(world.bonds().size(), 2u);
  for (const Bond& b : world.bonds()) {
    const bool to_right = b.a == right.index || b.b == right.index;
    const bool to_left = b.a == left.index || b.b == left.index;
    ASSERT_TRUE(to_right != to_left);
    // The below half (x < 0) holds the left bond, the above half the right one.
    const BodyId expected = to_left ? ids[0] : ids[1];
    EXPECT_TRUE(b.a == expected.index || b.b == expected.index);
    EXPECT_LT(b.a, b.b);
  }
  // Nothing moved: one step later the bond points are where they were and no force acts.
  world.step();
  for (const Bond& b : world.bonds()) {
    double nearest = 1.0;
    for (const auto& p : points) nearest = std::min(nearest, (b.point - p).norm());
    EXPECT_LT(nearest, 1e-15);
    EXPECT_LT(b.force.norm(), 1e-18);
    // The bond normal still points from A to B.
    const Eigen::Vector3d ab = world.state(world.id_at(b.b)).x - world.state(world.id_at(b.a)).x;
    EXPECT_GT(b.normal.dot(ab), 0.0);
  }
  EXPECT_EQ(world.kinetic_energy(), 0.0);
}
