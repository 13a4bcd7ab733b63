// Dilated-polyhedron contacts between two prisms: face-to-face patches, edge-on-face,
// independence from how faces are listed, and no touching point counted twice.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/rng.hpp"
#include "physics/narrow_phase.hpp"

using namespace cleave;
using namespace cleave::physics;

namespace {

const double kR = 0.5e-3, kT = 1e-3, kRho = 0.05e-3;  // side, thickness, dilation radius

RigidShape prism() { return make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(kR, kT), kRho); }

PosedShape pose(const RigidShape& shape, const Eigen::Vector3d& x, const Eigen::Quaterniond& turn) {
  BodyState s;
  s.x = x;
  s.q = shape.orientation_for(turn);
  PosedShape p;
  p.update(shape, s);
  return p;
}

Eigen::Quaterniond about_z(double deg) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitZ()));
}

std::vector<FeatureContact> contacts(const PosedShape& a, const PosedShape& b) {
  std::vector<FeatureContact> out;
  polyhedron_contacts(a, b, 0.0, out);
  return out;
}

}  // namespace

TEST(FaceToFace, CoaxialPrismsTouchAtTheCornersOfTheirOverlap) {
  const RigidShape s = prism();
  const double delta = 1e-6;
  const double z = kT + 2 * kRho - delta;  // B's basal face pressed delta into A's top face
  // Aligned: the overlap is the hexagon itself, six corners (each counted once).
  auto c = contacts(pose(s, {0, 0, 0}, about_z(0)), pose(s, {0, 0, z}, about_z(0)));
  EXPECT_EQ(c.size(), 6u);
  // Turned 30 degrees: the overlap of two hexagons is a 12-gon whose corners are the rim
  // crossings (no corner of either hexagon lies inside the other).
  c = contacts(pose(s, {0, 0, 0}, about_z(0)), pose(s, {0, 0, z}, about_z(30)));
  EXPECT_EQ(c.size(), 12u);
  for (const auto& fc : c) {
    EXPECT_NEAR(fc.contact.penetration, delta, 1e-12);
    EXPECT_NEAR(fc.contact.normal.z(), 1.0, 1e-12);  // from A (below) towards B
    EXPECT_NEAR(fc.contact.point.z(), kT / 2 + kRho - delta / 2, 1e-12);
  }
  // The 12 points are symmetric about the axis: they sum to the centre (no net torque).
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& fc : c) sum += fc.contact.point;
  EXPECT_NEAR(sum.head<2>().norm(), 0.0, 1e-15);
}

TEST(FaceToFace, NoContactWhileTheDilatedFacesAreApart) {
  const RigidShape s = prism();
  EXPECT_TRUE(contacts(pose(s, {0, 0, 0}, about_z(0)), pose(s, {0, 0, kT + 2 * kRho + 1e-7}, about_z(17))).empty());
}

TEST(EdgeOnFace, APrismOnItsSideEdgeTouchesAtTheEdgesEnds) {
  const RigidShape s = prism();
  // A lies on its side (axis along x) with a side edge down: turned about x so that edge
  // is lowest. B is a large flat prism below (its top face at z = 0).
  const RigidShape big = make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(3e-3, kT), kRho);
  const PosedShape b = pose(big, {0, 0, -kT / 2}, about_z(0));
  // Turned -30 degrees about its axis a corner of the hexagon points along +x; laid on its
  // side (+90 degrees about y, which takes +x to -z) that corner's long edge is lowest, r
  // below the axis.
  const Eigen::Quaterniond side =
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY())) * about_z(-30);
  const double delta = 2e-7;
  const PosedShape a = pose(s, {0, 0, kR + 2 * kRho - delta}, side);
  const auto c = contacts(b, a);  // B first: the flat face, then the edge
  ASSERT_EQ(c.size(), 2u);  // the edge's two end corners over the face; nothing counted twice
  for (const auto& fc : c) {
    EXPECT_NEAR(fc.contact.penetration, delta, 1e-12);
    EXPECT_NEAR(fc.contact.normal.z(), 1.0, 1e-12);
  }
  EXPECT_NEAR(std::abs(c[0].contact.point.x() - c[1].contact.point.x()), kT, 1e-12);
}

TEST(FaceListing, ContactsDoNotDependOnWhereAFaceLoopStarts) {
  // The same prism with every face loop rotated: the contact set is the same.
  geometry::PolygonMesh m = geometry::ExactPolyhedron::hexagonal_prism(kR, kT).to_mesh();
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    std::rotate(m.faces[f].begin(), m.faces[f].begin() + (f % m.faces[f].size()), m.faces[f].end());
  }
  const RigidShape plain = prism();
  const RigidShape rotated = make_rigid_shape(geometry::ExactPolyhedron::from_mesh(m), kRho);
  geometry::SplitMix64 rng(7);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d x(0.6e-3 * (rng.uniform() - 0.5), 0.6e-3 * (rng.uniform() - 0.5),
                            kT + 2 * kRho - 2e-6 * rng.uniform());
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.2 * (rng.uniform() - 0.5),
                                                 Eigen::Vector3d(rng.uniform(), rng.uniform(), 1).normalized()) *
                               about_z(360 * rng.uniform()));
    auto p1 = contacts(pose(plain, {0, 0, 0}, about_z(0)), pose(plain, x, q));
    auto p2 = contacts(pose(rotated, {0, 0, 0}, about_z(0)), pose(rotated, x, q));
    ASSERT_EQ(p1.size(), p2.size());
    auto key = [](const FeatureContact& a, const FeatureContact& b) {
      return std::tie(a.contact.point.x(), a.contact.point.y()) < std::tie(b.contact.point.x(), b.contact.point.y());
    };
    std::sort(p1.begin(), p1.end(), key);
    std::sort(p2.begin(), p2.end(), key);
    for (std::size_t i = 0; i < p1.size(); ++i) {
      EXPECT_NEAR((p1[i].contact.point - p2[i].contact.point).norm(), 0.0, 1e-15);
      EXPECT_NEAR(p1[i].contact.penetration, p2[i].contact.penetration, 1e-18);
    }
    compared += static_cast<int>(p1.size());
  }
  EXPECT_GT(compared, 200);
}

TEST(NoDoubleCounting, RandomTouchingPosesNeverReportOnePointTwice) {
  const RigidShape s = prism();
  geometry::SplitMix64 rng(11);
  int total = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // B somewhere around A, turned at random, moved in along the line of centres until
    // the first contacts appear.
    Eigen::Vector3d dir(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
    dir.normalize();
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(Eigen::AngleAxisd(2 * M_PI * rng.uniform(),
                                             Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5,
                                                             rng.uniform() - 0.5).normalized()));
    const PosedShape a = pose(s, {0, 0, 0}, about_z(0));
    double d = 3e-3;
    std::vector<FeatureContact> c;
    while (d > 0 && (c = contacts(a, pose(s, d * dir, q))).empty()) d -= 2e-6;
    ASSERT_FALSE(c.empty());
    total += static_cast<int>(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
      EXPECT_NEAR(c[i].contact.normal.norm(), 1.0, 1e-12);
      EXPECT_GT(c[i].contact.penetration, 0.0);
      EXPECT_LT(c[i].contact.penetration, 2.5e-6);  // caught within one approach step
      for (std::size_t j = i + 1; j < c.size(); ++j) {
        EXPECT_GT((c[i].contact.point - c[j].contact.point).norm(), 1e-9)
            << "features " << std::hex << c[i].feature_a << "/" << c[i].feature_b << " and "
            << c[j].feature_a << "/" << c[j].feature_b;
      }
    }
    if (HasFailure()) break;
  }
  EXPECT_GT(total, 3000);
}
