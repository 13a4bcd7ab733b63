// Exact cleavage splitting: slabs of every family x angle, and random / degenerate planes
// through random fragments, recursively. Volume sums are compared in exact arithmetic.
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/rng.hpp"

using namespace cleave::geometry;

namespace {

struct SlabCase {
  CleavageFamily family;
  int angle;
};
std::string slab_case_name(const ::testing::TestParamInfo<SlabCase>& info) {
  return std::string(info.param.family == CleavageFamily::a_11_20 ? "a11_20" : "m10_10") + "_" +
         std::to_string(info.param.angle);
}
class CleavageSlabs : public ::testing::TestWithParam<SlabCase> {};

}  // namespace

TEST_P(CleavageSlabs, ExactVolumeSumConvexClosedAndInsideTheGrain) {
  const auto [family, angle] = GetParam();
  // App. C sizes: r_bar = 0.5 mm, t_bar = 1 mm.
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(0.5e-3, 1.0e-3);
  const auto slabs = prism.cleavage_slabs({family, angle});
  ASSERT_EQ(static_cast<int>(slabs.size()), slab_count(family));
  EXPECT_TRUE(total_volume(slabs) == prism.volume());
  for (const auto& s : slabs) {
    EXPECT_TRUE(s.is_valid_convex());
    EXPECT_TRUE(validate_with_cgal(s).ok());
    EXPECT_TRUE(s.is_inside(prism));
    EXPECT_TRUE(s.to_mesh().is_closed_and_consistently_oriented());
  }
  const ExactScalar V = prism.volume();
  if (family == CleavageFamily::a_11_20) {
    // Fig. 2.8: isosceles triangular prism, rectangular prism, triangular prism. A triangle
    // of three consecutive corners holds exactly 1/6 of the hexagon.
    EXPECT_EQ(slabs[0].num_vertices(), 6);
    EXPECT_EQ(slabs[0].num_faces(), 5);
    EXPECT_EQ(slabs[1].num_vertices(), 8);
    EXPECT_EQ(slabs[1].num_faces(), 6);
    EXPECT_EQ(slabs[2].num_vertices(), 6);
    EXPECT_TRUE(slabs[0].volume() * ExactScalar(6.0) == V);
    EXPECT_TRUE(slabs[2].volume() * ExactScalar(6.0) == V);
    EXPECT_TRUE(slabs[1].volume() * ExactScalar(1.5) == V);
  } else {
    // Fig. 2.9: two equal trapezoidal prisms (the cut joins opposite corners).
    EXPECT_EQ(slabs[0].num_vertices(), 8);
    EXPECT_EQ(slabs[1].num_vertices(), 8);
    EXPECT_TRUE(slabs[0].volume() == slabs[1].volume());
  }
  // Slabs are ordered along the cleavage normal: their centroids' projections increase.
  const auto n = cleavage_normal({family, angle});
  const Eigen::Vector3d normal(n[0], n[1], n[2]);
  for (std::size_t i = 1; i < slabs.size(); ++i) {
    EXPECT_LT(slabs[i - 1].mass_properties().centroid.dot(normal),
              slabs[i].mass_properties().centroid.dot(normal));
  }
}

INSTANTIATE_TEST_SUITE_P(FamiliesAndAngles, CleavageSlabs,
                         ::testing::Values(SlabCase{CleavageFamily::a_11_20, 0},
                                           SlabCase{CleavageFamily::a_11_20, 60},
                                           SlabCase{CleavageFamily::a_11_20, 120},
                                           SlabCase{CleavageFamily::m_10_10, 0},
                                           SlabCase{CleavageFamily::m_10_10, 60},
                                           SlabCase{CleavageFamily::m_10_10, 120}),
                         slab_case_name);

TEST(CleavageSlabs, CutsRunThroughCornersAtTheNamedAngles) {
  // <10-10> at 0 degrees: the plane x = 0 through corners 0 and 3.
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(1.0, 1.0);
  const auto planes = prism.cleavage_planes({CleavageFamily::m_10_10, 0});
  ASSERT_EQ(planes.size(), 1u);
  EXPECT_NEAR(planes[0].normal_approx().x(), 1.0, 1e-15);
  EXPECT_NEAR(planes[0].offset_approx(), 0.0, 1e-15);
  // <11-20> at 0 degrees: normal at 30 degrees, offsets -r/2 and +r/2 (short diagonals).
  const auto three = prism.cleavage_planes({CleavageFamily::a_11_20, 0});
  ASSERT_EQ(three.size(), 2u);
  for (const auto& p : three) {
    EXPECT_NEAR(p.normal_approx().x(), std::sqrt(3.0) / 2.0, 1e-15);
    EXPECT_NEAR(p.normal_approx().y(), 0.5, 1e-15);
  }
  EXPECT_NEAR(three[0].offset_approx(), -0.5, 1e-15);
  EXPECT_NEAR(three[1].offset_approx(), 0.5, 1e-15);
}

// ---------------------------------------------------------------------------------------

namespace {

/// Random planes of several kinds through a body; some are degenerate on purpose.
ExactPlane random_plane(const ExactPolyhedron& body, SplitMix64& rng, int& kind) {
  auto unit = [&] {
    Eigen::Vector3d v;
    do {
      v = {2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1};
    } while (v.squaredNorm() < 1e-4 || v.squaredNorm() > 1.0);
    return v;
  };
  const int nv = body.num_vertices();
  kind = static_cast<int>(rng.below(4));
  switch (kind) {
    case 0: {  // through a random interior point with a random normal
      const auto v = body.vertices_approx();
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      double wsum = 0.0;
      for (const auto& q : v) {
        const double w = rng.uniform() + 1e-3;
        p += w * q;
        wsum += w;
      }
      const Eigen::Vector3d n = unit();
      return ExactPlane::from_normal_offset(n, n.dot(p / wsum));
    }
    case 1:  // through one vertex exactly
      return ExactPlane::through_vertex(body, static_cast<int>(rng.below(nv)), unit());
    case 2: {  // along an edge of the body, turned by a random direction about it
      const auto& f = body.faces()[rng.below(body.num_faces())];
      const int e = static_cast<int>(rng.below(static_cast<std::uint32_t>(f.size())));
      return ExactPlane::through_segment(body, f[e], f[(e + 1) % f.size()], unit());
    }
    default: {  // through three vertices (often a diagonal cut, sometimes a face)
      int i = static_cast<int>(rng.below(nv)), j, k;
      do j = static_cast<int>(rng.below(nv)); while (j == i);
      do k = static_cast<int>(rng.below(nv)); while (k == i || k == j);
      try {
        return ExactPlane::through_vertices(body, i, j, k);
      } catch (const GeometryError&) {  // collinear corners: fall back to a vertex plane
        return ExactPlane::through_vertex(body, i, unit());
      }
    }
  }
}

}  // namespace

TEST(RandomSplits, ExactVolumeSumAtEveryLevelOfFiveDeepTrees) {
  SplitMix64 rng(20261122);
  int splits = 0, refusals = 0;
  int kinds_split[4] = {0, 0, 0, 0};
  int deepest = 0;
  std::function<void(const ExactPolyhedron&, int)> grow = [&](const ExactPolyhedron& body,
                                                              int level) {
    deepest = std::max(deepest, level);
    if (level == 5) return;
    for (int attempt = 0; attempt < 50; ++attempt) {
      int kind = 0;
      const ExactPlane plane = random_plane(body, rng, kind);
      const SplitResult r = body.split(plane, 1e-3);
      if (!r.ok()) {
        ++refusals;
        EXPECT_FALSE(r.reason.empty());
        EXPECT_FALSE(r.below.has_value());
        continue;
      }
      ++splits;
      ++kinds_split[kind];
      // The invariant, exactly.
      EXPECT_TRUE(r.below->volume() + r.above->volume() == body.volume());
      EXPECT_TRUE(r.below->is_valid_convex());
      EXPECT_TRUE(r.above->is_valid_convex());
      EXPECT_TRUE(r.below->is_inside(body));
      EXPECT_TRUE(r.above->is_inside(body));
      if (::testing::Test::HasFailure()) return;
      grow(*r.below, level + 1);
      grow(*r.above, level + 1);
      return;
    }
    ADD_FAILURE() << "no plane split a body at level " << level;
  };
  const CrystalOrientation orientations[] = {{CleavageFamily::a_11_20, 0},
                                             {CleavageFamily::m_10_10, 60}};
  for (int tree = 0; tree < 60 && !::testing::Test::HasFailure(); ++tree) {
    const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(0.5e-3, 1.0e-3);
    if (tree % 3 == 0) {
      grow(prism, 0);
    } else {  // start from a cleavage slab: fragments of fragments
      const auto slabs = prism.cleavage_slabs(orientations[tree % 2]);
      grow(slabs[tree % slabs.size()], 1);
    }
  }
  EXPECT_GE(splits, 1000);
  EXPECT_EQ(deepest, 5);
  for (int k = 0; k < 4; ++k) EXPECT_GT(kinds_split[k], 0) << "plane kind " << k;
  EXPECT_GT(refusals, 0);  // degenerate planes (faces, supporting edges) were met and refused
}

TEST(SplitRefusals, PlanesThatMissTheBodyAreRefusedWithAReason) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(1.0, 1.0);
  // Entirely outside.
  SplitResult r = prism.split(ExactPlane::from_normal_offset({0, 0, 1}, 2.0));
  EXPECT_EQ(r.status, SplitStatus::misses_body);
  EXPECT_NE(r.reason.find("does not cut"), std::string::npos);
  // Coplanar with the top face.
  r = prism.split(ExactPlane::from_normal_offset({0, 0, 1}, 0.5));
  EXPECT_EQ(r.status, SplitStatus::misses_body);
  // Coplanar with a side face, through its own vertices.
  r = prism.split(ExactPlane::through_vertices(prism, 0, 6, 1));
  EXPECT_EQ(r.status, SplitStatus::misses_body);
  // Touching only a corner: a plane through vertex 0 with the corner's own direction.
  r = prism.split(ExactPlane::through_vertex(prism, 0, {0, 1, -0.1}));
  EXPECT_EQ(r.status, SplitStatus::misses_body);
  // Supporting along an edge (vertical edge at corner 0), not entering the body.
  r = prism.split(ExactPlane::through_segment(prism, 0, 6, {1, 0, 0}));
  EXPECT_EQ(r.status, SplitStatus::misses_body);
}

TEST(SplitRefusals, SliversBelowTheMinimumFractionAreRefused) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(1.0, 1.0);
  // A thin cap under the top face: 1% of the thickness.
  const ExactPlane near_top = ExactPlane::from_normal_offset({0, 0, 1}, 0.49);
  SplitResult r = prism.split(near_top, 0.05);
  EXPECT_EQ(r.status, SplitStatus::sliver);
  EXPECT_NE(r.reason.find("minimum fraction"), std::string::npos);
  EXPECT_NEAR(r.above_fraction, 0.01, 1e-12);
  // The same plane is accepted with a smaller threshold, and is exact.
  r = prism.split(near_top, 0.005);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.below->volume() + r.above->volume() == prism.volume());
}

TEST(DegeneratePlanes, ThroughVerticesAndAlongEdgesSplitExactly) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(1.0, 1.0);
  // Through two opposite vertical edges (corners 1 and 4): no new vertices at all.
  SplitResult r = prism.split(ExactPlane::through_vertices(prism, 1, 4, 7));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.below->num_vertices() + r.above->num_vertices(), 16);
  EXPECT_TRUE(r.below->volume() == r.above->volume());
  // A diagonal plane through a bottom corner and the opposite top corner, and one more corner.
  r = prism.split(ExactPlane::through_vertices(prism, 0, 9, 2));
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.below->volume() + r.above->volume() == prism.volume());
  EXPECT_TRUE(r.below->is_valid_convex() && r.above->is_valid_convex());
  // Along a top edge, tilted into the body.
  r = prism.split(ExactPlane::through_segment(prism, 6, 7, {0.1, -0.3, -1.0}));
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.below->volume() + r.above->volume() == prism.volume());
  EXPECT_TRUE(validate_with_cgal(*r.below).ok());
  EXPECT_TRUE(validate_with_cgal(*r.above).ok());
}

TEST(CleavageSlabs, CutsBelowTheMinimumFragmentFractionAreSkipped) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(1.0, 1.0);
  const CrystalOrientation three{CleavageFamily::a_11_20, 60};
  // Each <11-20> cut alone takes 1/6 of the prism: a threshold above 1/6 skips both cuts
  // and the grain stays whole; below it, all three slabs are made.
  const auto whole = prism.cleavage_slabs(three, 0.18);
  ASSERT_EQ(whole.size(), 1u);
  EXPECT_TRUE(whole[0].volume() == prism.volume());
  EXPECT_EQ(prism.cleavage_slabs(three, 0.16).size(), 3u);
  // <10-10> halves survive any threshold the scenario accepts (below 0.5).
  EXPECT_EQ(prism.cleavage_slabs({CleavageFamily::m_10_10, 0}, 0.49).size(), 2u);
}

TEST(DegeneratePlanes, ACornerCutBelowDoubleResolutionStillSplitsExactly) {
  // The plane x + y + z = 24 - d cuts the unit cube's corner (8, 8, 8) off as a tetrahedron
  // of legs d: exactly d^3 / 6, however small. Its volume in doubles (coordinates near 1)
  // rounds to nothing or below (the cube sits at [7, 8]^3, where the double sum of the
  // faces' volume terms cancels); with no minimum fraction the cut must still be made.
  PolygonMesh m;
  m.vertices = {{7, 7, 7}, {8, 7, 7}, {8, 8, 7}, {7, 8, 7}, {7, 7, 8}, {8, 7, 8}, {8, 8, 8}, {7, 8, 8}};
  m.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  const ExactPolyhedron cube = ExactPolyhedron::from_mesh(m);
  for (double d : {0x1p-20, 0x1p-30, 0x1p-36, 0x1p-40, 0x1p-44, 0x1p-46}) {
    const ExactPlane plane = ExactPlane::from_normal_offset({-1.0, -1.0, -1.0}, -(24.0 - d));
    const SplitResult r = cube.split(plane);
    ASSERT_TRUE(r.ok()) << d << ": " << r.reason;
    EXPECT_EQ(r.above->volume() + r.below->volume(), cube.volume()) << d;
    const ExactScalar corner = r.below->volume();  // the negative side: x + y + z > 24 - d
    EXPECT_EQ(corner + corner + corner + corner + corner + corner,
              ExactScalar(d) * ExactScalar(d) * ExactScalar(d))
        << d;
    const std::optional<ExactPolyhedron> kept = cube.clipped(plane);
    ASSERT_TRUE(kept.has_value()) << d;
    EXPECT_EQ(kept->volume(), r.above->volume()) << d;
  }
}
