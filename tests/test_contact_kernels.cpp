// Contact kernels between the primitives of dilated polyhedra (physics/dem/contact_kernels.hpp).
//
// Hand-computed cases: every expected point, normal and penetration below is worked out in
// the comments from the definitions (penetration = sum of radii - distance between the
// cores, point = midpoint of the two surface points along the normal).
//
// Brute-force references: the distance from a point to a segment or a convex polygon, and
// between two segments, found by minimising over dense parameter grids. A grid minimum is
// never below the true minimum and, for a grid of step h over a feature of size L, at most
// L h / 2 above it (1-D) or L h above it (triangle grid), so the reported penetration must
// lie in [R - grid_min, R - grid_min + tolerance]. When a kernel declines a pair that is
// surely within reach, the grid minimum over the feature's boundary (ends, polygon edges)
// must equal the overall grid minimum within the boundary's sampling tolerance: the closest
// point is on the boundary, which belongs to another primitive.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/rng.hpp"
#include "physics/dem/contact_kernels.hpp"

using cleave::geometry::SplitMix64;
using Eigen::Vector3d;
using namespace cleave::physics;

namespace {

constexpr double kTight = 1e-12;

void expect_near(const Vector3d& actual, const Vector3d& expected, double tol) {
  EXPECT_LT((actual - expected).norm(), tol)
      << "actual " << actual.transpose() << ", expected " << expected.transpose();
}

/// A contact's skeleton points: point - (ra - pen/2) n on A's core (centre, axis, polygon),
/// point + (rb - pen/2) n on B's core.
Vector3d core_a(const PrimitiveContact& c, double ra) {
  return c.point - (ra - 0.5 * c.penetration) * c.normal;
}
Vector3d core_b(const PrimitiveContact& c, double rb) {
  return c.point + (rb - 0.5 * c.penetration) * c.normal;
}

double uniform(SplitMix64& rng, double lo, double hi) {
  return lo + (hi - lo) * rng.uniform();
}

Vector3d random_in_box(SplitMix64& rng, double half) {
  return Vector3d(uniform(rng, -half, half), uniform(rng, -half, half), uniform(rng, -half, half));
}

Vector3d random_unit(SplitMix64& rng) {
  for (;;) {
    const Vector3d v = random_in_box(rng, 1.0);
    const double n2 = v.squaredNorm();
    if (n2 > 1e-4 && n2 <= 1.0) return v / std::sqrt(n2);
  }
}

Vector3d random_in_ball(SplitMix64& rng, double radius) {
  for (;;) {
    const Vector3d v = random_in_box(rng, 1.0);
    if (v.squaredNorm() <= 1.0) return radius * v;
  }
}

/// Textbook distance from x to the segment a-b (a != b): clamped orthogonal projection.
double distance_to_segment(const Vector3d& x, const Vector3d& a, const Vector3d& b) {
  const Vector3d ab = b - a;
  const double t = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - x).norm();
}

/// min over i = 0..n of |a + (i/n)(b - a) - x|.
double sampled_point_segment(const Vector3d& x, const Vector3d& a, const Vector3d& b, int n) {
  double best = INFINITY;
  for (int i = 0; i <= n; ++i) {
    best = std::min(best, (a + (static_cast<double>(i) / n) * (b - a) - x).norm());
  }
  return best;
}

// ------------------------------------------------------------------------------------------
// Sphere - sphere
// ------------------------------------------------------------------------------------------

TEST(SphereSphereKernel, HandComputedOverlaps) {
  {
    // Centres 1.5 apart on x, radii 1 and 1: surfaces at x = 1 (A) and x = 0.5 (B).
    const auto c = sphere_sphere(Vector3d(0, 0, 0), 1.0, Vector3d(1.5, 0, 0), 1.0);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->penetration, 0.5, kTight);
    expect_near(c->normal, Vector3d(1, 0, 0), kTight);
    expect_near(c->point, Vector3d(0.75, 0, 0), kTight);
  }
  {
    // Centres 2 apart on z, radii 2 and 0.5: surfaces at z = 2 (A) and z = 1.5 (B).
    const auto c = sphere_sphere(Vector3d(0, 0, 0), 2.0, Vector3d(0, 0, 2), 0.5);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->penetration, 0.5, kTight);
    expect_near(c->normal, Vector3d(0, 0, 1), kTight);
    expect_near(c->point, Vector3d(0, 0, 1.75), kTight);
  }
  {
    // Offset (1,2,2): distance 3, n = (1,2,2)/3; radii 1.5 and 2: penetration 0.5.
    // A's surface 1.5 n = (0.5,1,1) + c_a; B's surface c_b - 2 n = (1,2,2) - (2,4,4)/3.
    const Vector3d ca(1, -1, 0.5);
    const auto c = sphere_sphere(ca, 1.5, ca + Vector3d(1, 2, 2), 2.0);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->penetration, 0.5, kTight);
    expect_near(c->normal, Vector3d(1, 2, 2) / 3.0, kTight);
    expect_near(c->point, ca + 0.5 * (Vector3d(0.5, 1, 1) + Vector3d(1.0 / 3, 2.0 / 3, 2.0 / 3)),
                kTight);
  }
}

TEST(SphereSphereKernel, SeparatedAndTouchingSpheresGiveNothing) {
  EXPECT_FALSE(sphere_sphere(Vector3d(0, 0, 0), 1.0, Vector3d(2.5, 0, 0), 1.0));
  // Exactly touching: penetration 0 is not > -0.
  EXPECT_FALSE(sphere_sphere(Vector3d(0, 0, 0), 1.0, Vector3d(0, 2, 0), 1.0));
  EXPECT_FALSE(sphere_sphere(Vector3d(0, 0, 0), 0.0, Vector3d(0, 0, 0), 0.0));
}

TEST(SphereSphereKernel, MarginReportsNearbyGaps) {
  // Radii 1 and 1, centres 2.1 apart: a gap of 0.1 between x = 1 (A) and x = 1.1 (B).
  const auto c = sphere_sphere(Vector3d(0, 0, 0), 1.0, Vector3d(2.1, 0, 0), 1.0, 0.2);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, -0.1, kTight);
  expect_near(c->normal, Vector3d(1, 0, 0), kTight);
  expect_near(c->point, Vector3d(1.05, 0, 0), kTight);
  EXPECT_FALSE(sphere_sphere(Vector3d(0, 0, 0), 1.0, Vector3d(2.1, 0, 0), 1.0, 0.05));
}

TEST(SphereSphereKernel, CoincidentCentresUsePlusZ) {
  // Normal +z; A's surface at c + 0.7 z, B's at c - 0.3 z: point c + 0.2 z.
  const Vector3d centre(0.3, -0.2, 1.0);
  const auto c = sphere_sphere(centre, 0.7, centre, 0.3);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 1.0, kTight);
  expect_near(c->normal, Vector3d(0, 0, 1), kTight);
  expect_near(c->point, centre + Vector3d(0, 0, 0.2), kTight);
}

TEST(SphereSphereKernel, RandomPairsAgainstDefinitionAndSwap) {
  SplitMix64 rng(0x5e5e);
  int contacts = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vector3d ca = random_in_box(rng, 1.0), cb = random_in_box(rng, 1.0);
    const double ra = uniform(rng, 0.05, 1.0), rb = uniform(rng, 0.05, 1.0);
    const double margin = rng.below(2) ? 0.1 : 0.0;
    const double pen = ra + rb - (cb - ca).norm();
    const auto ab = sphere_sphere(ca, ra, cb, rb, margin);
    const auto ba = sphere_sphere(cb, rb, ca, ra, margin);
    if (std::abs(pen + margin) < 1e-9) continue;  // undecidable in floating point
    ASSERT_EQ(ab.has_value(), pen > -margin) << k;
    ASSERT_EQ(ba.has_value(), pen > -margin) << k;
    if (!ab) continue;
    ++contacts;
    EXPECT_NEAR(ab->penetration, pen, kTight);
    EXPECT_NEAR(ab->normal.norm(), 1.0, kTight);
    expect_near(core_a(*ab, ra), ca, 1e-12);
    expect_near(core_b(*ab, rb), cb, 1e-12);
    EXPECT_NEAR(ba->penetration, ab->penetration, kTight);
    expect_near(ba->normal, -ab->normal, kTight);
    expect_near(ba->point, ab->point, 1e-12);
  }
  EXPECT_GT(contacts, 1000);
}

// ------------------------------------------------------------------------------------------
// Sphere - facet
// ------------------------------------------------------------------------------------------

const std::array<Vector3d, 4> kUnitSquare = {Vector3d(0, 0, 0), Vector3d(1, 0, 0),
                                             Vector3d(1, 1, 0), Vector3d(0, 1, 0)};

TEST(SphereFacetKernel, SphereAboveUnitSquare) {
  // Centre 0.8 above the plane z = 0; rs = 0.5, rf = 0.4: penetration 0.5 + 0.4 - 0.8.
  // Normal -z; A's surface at z = 0.3, B's at z = 0.4: point z = 0.35.
  const auto c = sphere_facet(Vector3d(0.3, 0.6, 0.8), 0.5, kUnitSquare, Vector3d(0, 0, 1), 0.4);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.1, kTight);
  expect_near(c->normal, Vector3d(0, 0, -1), kTight);
  expect_near(c->point, Vector3d(0.3, 0.6, 0.35), kTight);
}

TEST(SphereFacetKernel, ProjectionOutsideOrOnTheBoundaryGivesNothing) {
  const Vector3d up(0, 0, 1);
  EXPECT_FALSE(sphere_facet(Vector3d(1.2, 0.5, 0.5), 0.5, kUnitSquare, up, 0.4));
  EXPECT_FALSE(sphere_facet(Vector3d(-0.01, 0.5, 0.5), 0.5, kUnitSquare, up, 0.4));
  EXPECT_FALSE(sphere_facet(Vector3d(0.5, 1.3, 0.1), 0.5, kUnitSquare, up, 0.4));
  // On an edge and on a corner: the cylinder and the vertex sphere own those.
  EXPECT_FALSE(sphere_facet(Vector3d(1.0, 0.5, 0.5), 0.5, kUnitSquare, up, 0.4));
  EXPECT_FALSE(sphere_facet(Vector3d(0.5, 0.0, 0.5), 0.5, kUnitSquare, up, 0.4));
  EXPECT_FALSE(sphere_facet(Vector3d(0.0, 0.0, 0.5), 0.5, kUnitSquare, up, 0.4));
  EXPECT_FALSE(sphere_facet(Vector3d(1.0, 1.0, 0.5), 0.5, kUnitSquare, up, 0.4));
  // Just inside still counts.
  EXPECT_TRUE(sphere_facet(Vector3d(1.0 - 1e-9, 0.5, 0.5), 0.5, kUnitSquare, up, 0.4));
}

TEST(SphereFacetKernel, OneSided) {
  const Vector3d up(0, 0, 1);
  // Centre below the plane, well within reach of the thickened facet: nothing.
  EXPECT_FALSE(sphere_facet(Vector3d(0.5, 0.5, -0.2), 0.5, kUnitSquare, up, 0.4));
  EXPECT_FALSE(sphere_facet(Vector3d(0.5, 0.5, -1e-12), 0.5, kUnitSquare, up, 0.4));
  // The same square seen from below (reversed order, outward -z) does answer: d = 0.2,
  // penetration 0.7; A's surface at z = -0.2 + 0.5, B's at z = -0.4; point z = -0.05.
  const std::array<Vector3d, 4> flipped = {kUnitSquare[3], kUnitSquare[2], kUnitSquare[1],
                                           kUnitSquare[0]};
  const auto c = sphere_facet(Vector3d(0.5, 0.5, -0.2), 0.5, flipped, -up, 0.4);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.7, kTight);
  expect_near(c->normal, up, kTight);
  expect_near(c->point, Vector3d(0.5, 0.5, -0.05), kTight);
  // Centre in the plane (d = 0) counts: penetration rs + rf.
  const auto in_plane = sphere_facet(Vector3d(0.5, 0.5, 0.0), 0.5, kUnitSquare, up, 0.4);
  ASSERT_TRUE(in_plane);
  EXPECT_NEAR(in_plane->penetration, 0.9, kTight);
  // Clockwise seen from `outward` breaks the convention: nothing is ever inside.
  EXPECT_FALSE(sphere_facet(Vector3d(0.5, 0.5, 0.2), 0.5, flipped, up, 0.4));
}

TEST(SphereFacetKernel, FarAndMargin) {
  const Vector3d up(0, 0, 1);
  EXPECT_FALSE(sphere_facet(Vector3d(0.5, 0.5, 2.0), 0.5, kUnitSquare, up, 0.4));
  // d = 1.0, rs + rf = 0.9: gap 0.1 between A's surface z = 0.5 and B's z = 0.4.
  const auto c = sphere_facet(Vector3d(0.5, 0.5, 1.0), 0.5, kUnitSquare, up, 0.4, 0.2);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, -0.1, kTight);
  expect_near(c->point, Vector3d(0.5, 0.5, 0.45), kTight);
  EXPECT_FALSE(sphere_facet(Vector3d(0.5, 0.5, 1.0), 0.5, kUnitSquare, up, 0.4, 0.05));
}

TEST(SphereFacetKernel, DegeneratePolygonsGiveNothing) {
  const Vector3d up(0, 0, 1);
  const std::array<Vector3d, 2> two = {Vector3d(0, 0, 0), Vector3d(1, 0, 0)};
  EXPECT_FALSE(sphere_facet(Vector3d(0.5, 0, 0.1), 0.5, two, up, 0.4));
  EXPECT_FALSE(sphere_facet(Vector3d(0.5, 0, 0.1), 0.5, std::span<const Vector3d>(), up, 0.4));
}

/// Regular hexagon of circumradius 2 in the plane z = h, CCW seen from +z: vertices
/// (+-2, 0), (+-1, +-sqrt3). Its bottom edge y = -sqrt3 is exactly representable.
std::array<Vector3d, 6> hexagon(double h) {
  const double s3 = std::sqrt(3.0);
  return {Vector3d(2, 0, h),  Vector3d(1, s3, h),   Vector3d(-1, s3, h),
          Vector3d(-2, 0, h), Vector3d(-1, -s3, h), Vector3d(1, -s3, h)};
}

TEST(SphereFacetKernel, AxisAlignedHexagon) {
  const auto hex = hexagon(0.5);
  const Vector3d up(0, 0, 1);
  // (1.2, 1.1): the edge from (2,0) to (1,sqrt3) has outward normal (sqrt3, 1)/2 and
  // apothem sqrt3; (1.2 sqrt3 + 1.1)/2 = 1.589 < 1.732, inside. d = 0.3; rs = 0.25, rf = 0.1:
  // penetration 0.05; A's surface at z = 0.55, B's at z = 0.6, point z = 0.575.
  const auto c = sphere_facet(Vector3d(1.2, 1.1, 0.8), 0.25, hex, up, 0.1);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.05, kTight);
  expect_near(c->normal, -up, kTight);
  expect_near(c->point, Vector3d(1.2, 1.1, 0.575), kTight);
  // (1.4, 1.1): (1.4 sqrt3 + 1.1)/2 = 1.762 > 1.732, outside, though |x| < 2 and |y| < sqrt3.
  EXPECT_FALSE(sphere_facet(Vector3d(1.4, 1.1, 0.8), 0.25, hex, up, 0.1));
  // On the bottom edge and on vertices.
  EXPECT_FALSE(sphere_facet(Vector3d(0.3, -std::sqrt(3.0), 0.8), 0.25, hex, up, 0.1));
  EXPECT_FALSE(sphere_facet(Vector3d(2, 0, 0.8), 0.25, hex, up, 0.1));
  EXPECT_FALSE(sphere_facet(Vector3d(-1, std::sqrt(3.0), 0.8), 0.25, hex, up, 0.1));
}

TEST(SphereFacetKernel, RotatedHexagon) {
  // The hexagon of AxisAlignedHexagon (h = 0) moved rigidly: every distance is unchanged.
  const Eigen::Matrix3d rot =
      Eigen::AngleAxisd(0.7, Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  const Vector3d shift(0.4, -1.3, 2.2);
  std::array<Vector3d, 6> hex = hexagon(0.0);
  for (auto& v : hex) v = rot * v + shift;
  const Vector3d outward = rot * Vector3d(0, 0, 1);
  const auto place = [&](double x, double y, double z) -> Vector3d {
    return rot * Vector3d(x, y, z) + shift;
  };
  // Local centre (-0.5, -1.2, 0.3): inside (|y| < sqrt3, and the lower-left edge test
  // (0.5 sqrt3 + 1.2)/2 = 1.033 < sqrt3). rs = 0.3, rf = 0.2: penetration 0.2; A's surface
  // at local z = 0, B's at z = 0.2, point z = 0.1.
  const auto c = sphere_facet(place(-0.5, -1.2, 0.3), 0.3, hex, outward, 0.2);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.2, 1e-12);
  expect_near(c->normal, -outward, 1e-12);
  expect_near(c->point, place(-0.5, -1.2, 0.1), 1e-12);
  EXPECT_FALSE(sphere_facet(place(-1.4, -1.2, 0.3), 0.3, hex, outward, 0.2));   // outside
  EXPECT_FALSE(sphere_facet(place(-0.5, -1.2, -0.1), 0.3, hex, outward, 0.2));  // below
  EXPECT_FALSE(sphere_facet(place(-0.5, -1.2, 0.6), 0.3, hex, outward, 0.2));   // far
}

/// A random convex polygon: 3..8 points in angular order on an ellipse, in a random plane.
struct RandomFacet {
  std::vector<Vector3d> polygon;
  Vector3d outward;
  Vector3d centre, e1, e2;  ///< the ellipse's centre and in-plane axes
  double ax = 0, ay = 0;    ///< its semi-axes
};

RandomFacet random_facet(SplitMix64& rng) {
  const Vector3d e3 = random_unit(rng);
  const Vector3d e1 = e3.unitOrthogonal();
  const Vector3d e2 = e3.cross(e1);
  const Vector3d origin = random_in_box(rng, 0.5);
  const double ax = uniform(rng, 0.3, 1.0), ay = uniform(rng, 0.3, 1.0);
  const int count = 3 + static_cast<int>(rng.below(6));
  std::vector<double> angles;
  for (int i = 0; i < count; ++i) angles.push_back(uniform(rng, 0.0, 2 * std::numbers::pi));
  std::sort(angles.begin(), angles.end());
  RandomFacet f{{}, e3, origin, e1, e2, ax, ay};
  for (double a : angles) {
    f.polygon.push_back(origin + ax * std::cos(a) * e1 + ay * std::sin(a) * e2);
  }
  return f;
}

TEST(SphereFacetKernel, RandomFacetsAgainstSampledDistance) {
  SplitMix64 rng(0xface7);
  constexpr int kGrid = 250;       // triangle grid: step = edge / kGrid
  constexpr int kEdgeGrid = 4000;  // boundary: step = edge / kEdgeGrid
  int contacts = 0, boundary = 0, below = 0;
  for (int k = 0; k < 1200; ++k) {
    const RandomFacet f = random_facet(rng);
    const auto& poly = f.polygon;
    const Vector3d c = f.centre + uniform(rng, -1.0, 1.0) * f.ax * f.e1 +
                       uniform(rng, -1.0, 1.0) * f.ay * f.e2 + uniform(rng, -0.2, 0.6) * f.outward;
    const double rs = uniform(rng, 0.1, 0.5), rf = uniform(rng, 0.0, 0.3);
    const double margin = rng.below(2) ? 0.1 : 0.0;
    const double R = rs + rf;

    // Interior: fan triangles with barycentric grids; boundary: each edge finely.
    double grid_min = INFINITY, tol = 0.0, boundary_min = INFINITY, boundary_tol = 0.0;
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      const Vector3d u = poly[i] - poly[0], v = poly[i + 1] - poly[0];
      tol = std::max(tol, std::max({u.norm(), v.norm(), (v - u).norm()}) / kGrid);
      for (int a = 0; a <= kGrid; ++a) {
        for (int b = 0; a + b <= kGrid; ++b) {
          const Vector3d x =
              poly[0] + (static_cast<double>(a) / kGrid) * u + (static_cast<double>(b) / kGrid) * v;
          grid_min = std::min(grid_min, (x - c).norm());
        }
      }
    }
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vector3d& a = poly[i];
      const Vector3d& b = poly[(i + 1) % poly.size()];
      boundary_min = std::min(boundary_min, sampled_point_segment(c, a, b, kEdgeGrid));
      boundary_tol = std::max(boundary_tol, (b - a).norm() / (2 * kEdgeGrid));
    }
    grid_min = std::min(grid_min, boundary_min);

    const double d = f.outward.dot(c - poly[0]);
    const auto hit = sphere_facet(c, rs, poly, f.outward, rf, margin);
    if (hit) {
      ++contacts;
      EXPECT_GE(d, 0.0) << k;
      EXPECT_GT(hit->penetration, -margin) << k;
      EXPECT_GE(hit->penetration, R - grid_min - 1e-12) << k;
      EXPECT_LE(hit->penetration, R - grid_min + tol + 1e-12) << k;
      EXPECT_NEAR(hit->normal.norm(), 1.0, kTight);
      expect_near(hit->normal, -f.outward, kTight);
      expect_near(core_a(*hit, rs), c, 1e-12);
      // B's core point is in the polygon: in its plane and left of every edge.
      const Vector3d foot = core_b(*hit, rf);
      EXPECT_NEAR(f.outward.dot(foot - poly[0]), 0.0, 1e-12) << k;
      for (std::size_t i = 0; i < poly.size(); ++i) {
        const Vector3d& a = poly[i];
        const Vector3d& b = poly[(i + 1) % poly.size()];
        EXPECT_GE((b - a).cross(foot - a).dot(f.outward), -1e-12) << k;
      }
    } else if (d < 0.0) {
      ++below;
    } else if (R - d > -margin + 1e-12) {
      // Within reach of the plane but declined: the closest point must be on the boundary.
      ++boundary;
      EXPECT_LE(boundary_min - grid_min, boundary_tol + 1e-12) << k;
    }
  }
  EXPECT_GT(contacts, 150) << boundary << " " << below;
  EXPECT_GT(boundary, 150) << contacts << " " << below;
  EXPECT_GT(below, 50) << contacts << " " << boundary;
}

// ------------------------------------------------------------------------------------------
// Sphere - cylinder
// ------------------------------------------------------------------------------------------

TEST(SphereCylinderKernel, HandComputed) {
  const Vector3d p(0, 0, 0), q(2, 0, 0);
  {
    // Centre 0.8 from the x axis at x = 0.5; rs = 0.6, rc = 0.3: penetration 0.1. Normal
    // -y; A's surface at y = 0.2, B's at y = 0.3: point y = 0.25.
    const auto c = sphere_cylinder(Vector3d(0.5, 0.8, 0), 0.6, p, q, 0.3);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->penetration, 0.1, kTight);
    expect_near(c->normal, Vector3d(0, -1, 0), kTight);
    expect_near(c->point, Vector3d(0.5, 0.25, 0), kTight);
  }
  {
    // Centre at (1.5, 0.3, 0.4): distance 0.5 along -(0, 0.6, 0.8); rs = 0.4, rc = 0.2:
    // penetration 0.1. Measured from the foot (1.5, 0, 0) along (0, 0.6, 0.8), A's surface
    // is at 0.5 - 0.4 = 0.1 and B's at 0.2: point at 0.15, i.e. (1.5, 0.09, 0.12).
    const auto c = sphere_cylinder(Vector3d(1.5, 0.3, 0.4), 0.4, p, q, 0.2);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->penetration, 0.1, kTight);
    expect_near(c->normal, Vector3d(0, -0.6, -0.8), kTight);
    expect_near(c->point, Vector3d(1.5, 0.09, 0.12), kTight);
  }
  {
    // A slanted axis: p = (1,1,1), q = (1,1,1) + 2 (1,2,2)/3. The centre sits at foot
    // (1,1,1) + (1,2,2)/3 plus 0.7 along (2,-2,1)/3, which is perpendicular to the axis.
    const Vector3d ps(1, 1, 1), dir = Vector3d(1, 2, 2) / 3.0, side = Vector3d(2, -2, 1) / 3.0;
    const Vector3d foot = ps + dir;
    const auto c = sphere_cylinder(foot + 0.7 * side, 0.5, ps, ps + 2 * dir, 0.3);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->penetration, 0.1, kTight);
    expect_near(c->normal, -side, kTight);
    // B's surface at foot + 0.3 side, A's at foot + 0.2 side.
    expect_near(c->point, foot + 0.25 * side, kTight);
  }
}

TEST(SphereCylinderKernel, BeyondTheEndsGivesNothing) {
  const Vector3d p(0, 0, 0), q(2, 0, 0);
  EXPECT_FALSE(sphere_cylinder(Vector3d(2.3, 0.1, 0), 0.6, p, q, 0.3));
  EXPECT_FALSE(sphere_cylinder(Vector3d(-0.1, 0.2, 0), 0.6, p, q, 0.3));
  // Foot exactly on an end: the vertex sphere owns it.
  EXPECT_FALSE(sphere_cylinder(Vector3d(2.0, 0.2, 0), 0.6, p, q, 0.3));
  EXPECT_FALSE(sphere_cylinder(Vector3d(0.0, 0.0, 0.2), 0.6, p, q, 0.3));
  EXPECT_TRUE(sphere_cylinder(Vector3d(2.0 - 1e-9, 0.2, 0), 0.6, p, q, 0.3));
  // Within reach of the axis line but off the segment, in both directions of the segment.
  EXPECT_FALSE(sphere_cylinder(Vector3d(2.3, 0.1, 0), 0.6, q, p, 0.3));
  // Zero-length segment.
  EXPECT_FALSE(sphere_cylinder(Vector3d(0, 0.1, 0), 0.6, p, p, 0.3));
}

TEST(SphereCylinderKernel, FarAndMargin) {
  const Vector3d p(0, 0, 0), q(2, 0, 0);
  EXPECT_FALSE(sphere_cylinder(Vector3d(1, 0, 1.5), 0.6, p, q, 0.3));
  // Distance 1.0, radii 0.6 + 0.3: gap 0.1 between A's surface z = 0.4 and B's z = 0.3.
  const auto c = sphere_cylinder(Vector3d(1, 0, 1.0), 0.6, p, q, 0.3, 0.2);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, -0.1, kTight);
  expect_near(c->point, Vector3d(1, 0, 0.35), kTight);
  EXPECT_FALSE(sphere_cylinder(Vector3d(1, 0, 1.0), 0.6, p, q, 0.3, 0.05));
}

TEST(SphereCylinderKernel, CentreOnTheAxis) {
  const Vector3d p(0, 0, 0), q(0, 3, 4);
  const auto c = sphere_cylinder(Vector3d(0, 1.5, 2), 0.5, p, q, 0.25);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.75, kTight);
  EXPECT_NEAR(c->normal.norm(), 1.0, kTight);
  EXPECT_NEAR(c->normal.dot(q - p), 0.0, kTight);
  // Both cores are the centre: point = centre + (0.5 - 0.25)/2 n.
  expect_near(c->point, Vector3d(0, 1.5, 2) + 0.125 * c->normal, kTight);
}

TEST(SphereCylinderKernel, RandomAgainstSampledDistance) {
  SplitMix64 rng(0xc411);
  constexpr int kGrid = 20000;
  int contacts = 0, ends = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vector3d p = random_in_box(rng, 0.5);
    const Vector3d q = p + uniform(rng, 0.2, 1.5) * random_unit(rng);
    const Vector3d c = p + uniform(rng, -0.4, 1.4) * (q - p) + random_in_ball(rng, 0.8);
    const double rs = uniform(rng, 0.05, 0.5), rc = uniform(rng, 0.05, 0.3);
    const double margin = rng.below(2) ? 0.1 : 0.0;
    const double R = rs + rc;
    const double grid_min = sampled_point_segment(c, p, q, kGrid);
    const double tol = (q - p).norm() / (2 * kGrid);
    const double end_min = std::min((c - p).norm(), (c - q).norm());

    const auto hit = sphere_cylinder(c, rs, p, q, rc, margin);
    const auto reversed = sphere_cylinder(c, rs, q, p, rc, margin);
    ASSERT_EQ(hit.has_value(), reversed.has_value()) << k;
    if (hit) {
      ++contacts;
      EXPECT_GT(hit->penetration, -margin) << k;
      EXPECT_GE(hit->penetration, R - grid_min - 1e-12) << k;
      EXPECT_LE(hit->penetration, R - grid_min + tol + 1e-12) << k;
      EXPECT_NEAR(hit->normal.norm(), 1.0, kTight);
      EXPECT_NEAR(hit->normal.dot((q - p).normalized()), 0.0, 1e-12) << k;
      expect_near(core_a(*hit, rs), c, 1e-12);
      EXPECT_LT(distance_to_segment(core_b(*hit, rc), p, q), 1e-12) << k;
      EXPECT_NEAR(reversed->penetration, hit->penetration, 1e-12) << k;
      expect_near(reversed->normal, hit->normal, 1e-12);
      expect_near(reversed->point, hit->point, 1e-12);
    } else if (R - grid_min > -margin) {
      // Surely within reach but declined: the closest point of the segment is an end.
      ++ends;
      EXPECT_LE(end_min - grid_min, 1e-12) << k;
    }
  }
  EXPECT_GT(contacts, 400) << ends;
  EXPECT_GT(ends, 300) << contacts;
}

// ------------------------------------------------------------------------------------------
// Cylinder - cylinder
// ------------------------------------------------------------------------------------------

TEST(CylinderCylinderKernel, CrossingPerpendicular) {
  // x axis from -1 to 1 and a y-parallel segment at x = 0.2, z = 0.5: closest points
  // (0.2, 0, 0) and (0.2, 0, 0.5). Radii 0.3 + 0.3 - 0.5 = 0.1; A's surface at z = 0.3,
  // B's at z = 0.2: point z = 0.25.
  const auto c = cylinder_cylinder(Vector3d(-1, 0, 0), Vector3d(1, 0, 0), 0.3,
                                   Vector3d(0.2, -1, 0.5), Vector3d(0.2, 1, 0.5), 0.3);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.1, kTight);
  expect_near(c->normal, Vector3d(0, 0, 1), kTight);
  expect_near(c->point, Vector3d(0.2, 0, 0.25), kTight);
}

TEST(CylinderCylinderKernel, SkewAtSixtyDegrees) {
  // Segment 2 lies in the plane z = -0.7 through (0.3, 0, -0.7) along (cos60, sin60, 0),
  // so the common perpendicular is the z direction at x = 0.3. Distance 0.7; radii 0.5 and
  // 0.4: penetration 0.2. Normal -z; A's surface at z = -0.5, B's at z = -0.3: point -0.4.
  const Vector3d dir(0.5, std::sqrt(3.0) / 2, 0), foot(0.3, 0, -0.7);
  const auto c = cylinder_cylinder(Vector3d(-1, 0, 0), Vector3d(1, 0, 0), 0.5, foot - 0.5 * dir,
                                   foot + 1.5 * dir, 0.4);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.2, kTight);
  expect_near(c->normal, Vector3d(0, 0, -1), kTight);
  expect_near(c->point, Vector3d(0.3, 0, -0.4), kTight);
}

TEST(CylinderCylinderKernel, ClosestPointAtAnEndGivesNothing) {
  // The y-parallel segment at x = 1.2 passes beyond the end of the x segment.
  EXPECT_FALSE(cylinder_cylinder(Vector3d(-1, 0, 0), Vector3d(1, 0, 0), 0.3, Vector3d(1.2, -1, 0.1),
                                 Vector3d(1.2, 1, 0.1), 0.3));
  // It ends before reaching the x axis (closest point is its end (0.2, -0.2, 0.1)).
  EXPECT_FALSE(cylinder_cylinder(Vector3d(-1, 0, 0), Vector3d(1, 0, 0), 0.3, Vector3d(0.2, -1, 0.1),
                                 Vector3d(0.2, -0.2, 0.1), 0.3));
  // Exactly through the end x = 1.
  EXPECT_FALSE(cylinder_cylinder(Vector3d(-1, 0, 0), Vector3d(1, 0, 0), 0.3, Vector3d(1, -1, 0.1),
                                 Vector3d(1, 1, 0.1), 0.3));
  // Zero-length segments.
  EXPECT_FALSE(cylinder_cylinder(Vector3d(0, 0, 0), Vector3d(0, 0, 0), 0.3, Vector3d(0, -1, 0.1),
                                 Vector3d(0, 1, 0.1), 0.3));
  EXPECT_FALSE(cylinder_cylinder(Vector3d(-1, 0, 0), Vector3d(1, 0, 0), 0.3, Vector3d(0, 0, 0.1),
                                 Vector3d(0, 0, 0.1), 0.3));
}

TEST(CylinderCylinderKernel, FarAndMargin) {
  const Vector3d p1(-1, 0, 0), q1(1, 0, 0), p2(0, -1, 0.7), q2(0, 1, 0.7);
  EXPECT_FALSE(cylinder_cylinder(p1, q1, 0.3, p2, q2, 0.3));
  // Distance 0.7, radii 0.3 + 0.3: gap 0.1 between z = 0.3 and z = 0.4.
  const auto c = cylinder_cylinder(p1, q1, 0.3, p2, q2, 0.3, 0.2);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, -0.1, kTight);
  expect_near(c->point, Vector3d(0, 0, 0.35), kTight);
  EXPECT_FALSE(cylinder_cylinder(p1, q1, 0.3, p2, q2, 0.3, 0.05));
}

TEST(CylinderCylinderKernel, CrossingAxes) {
  // Axes intersecting at (0.5, 0, 0): distance 0, penetration r1 + r2; normal along the
  // common perpendicular (here +-z).
  const auto c = cylinder_cylinder(Vector3d(0, 0, 0), Vector3d(1, 0, 0), 0.2, Vector3d(0.5, -1, 0),
                                   Vector3d(0.5, 1, 0), 0.1);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.3, kTight);
  EXPECT_NEAR(std::abs(c->normal.z()), 1.0, kTight);
  expect_near(c->point, Vector3d(0.5, 0, 0) + 0.05 * c->normal, kTight);
}

TEST(CylinderCylinderKernel, ParallelOverlapContactsAtTheMiddle) {
  const Vector3d p1(0, 0, 0), q1(2, 0, 0);
  {
    // Segment 2 along y = 0.5 from x = 1 to 3: overlap x in [1, 2], middle x = 1.5.
    // Distance 0.5, radii 0.3 + 0.3; A's surface y = 0.3, B's y = 0.2: point y = 0.25.
    for (const bool flip : {false, true}) {
      const Vector3d a(1, 0.5, 0), b(3, 0.5, 0);
      const auto c = flip ? cylinder_cylinder(p1, q1, 0.3, b, a, 0.3)
                          : cylinder_cylinder(p1, q1, 0.3, a, b, 0.3);
      ASSERT_TRUE(c) << flip;
      EXPECT_NEAR(c->penetration, 0.1, kTight);
      expect_near(c->normal, Vector3d(0, 1, 0), kTight);
      expect_near(c->point, Vector3d(1.5, 0.25, 0), kTight);
    }
  }
  {
    // Segment 2 inside the span of segment 1, at z = 0.4 from x = 0.5 to 1: middle 0.75.
    // Radii 0.25 + 0.25: penetration 0.1; A's surface z = 0.25, B's z = 0.15: point z = 0.2.
    const auto c =
        cylinder_cylinder(p1, q1, 0.25, Vector3d(0.5, 0, 0.4), Vector3d(1, 0, 0.4), 0.25);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->penetration, 0.1, kTight);
    expect_near(c->normal, Vector3d(0, 0, 1), kTight);
    expect_near(c->point, Vector3d(0.75, 0, 0.2), kTight);
  }
  {
    // A slanted pair: segment 1 along (2,1,2)/3 from the origin, length 3; segment 2 the
    // same direction offset by 0.6 along the perpendicular (1,0,-1)/sqrt2, parameters
    // [2, 5] along the axis. Overlap [2, 3], middle 2.5; radii 0.4 + 0.3: penetration 0.1.
    const Vector3d u = Vector3d(2, 1, 2) / 3.0, side = Vector3d(1, 0, -1) / std::sqrt(2.0);
    const auto c = cylinder_cylinder(Vector3d::Zero(), 3 * u, 0.4, 2 * u + 0.6 * side,
                                     5 * u + 0.6 * side, 0.3);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->penetration, 0.1, 1e-12);
    expect_near(c->normal, side, 1e-12);
    // A's surface at 0.4 side, B's at 0.3 side: point 2.5 u + 0.35 side.
    expect_near(c->point, 2.5 * u + 0.35 * side, 1e-12);
  }
}

TEST(CylinderCylinderKernel, ParallelWithoutOverlapGivesNothing) {
  const Vector3d p1(0, 0, 0), q1(2, 0, 0);
  // Collinear, end to end.
  EXPECT_FALSE(cylinder_cylinder(p1, q1, 0.3, Vector3d(2, 0, 0), Vector3d(3, 0, 0), 0.3));
  // Offset, end abutting end in projection: overlap of length zero.
  EXPECT_FALSE(cylinder_cylinder(p1, q1, 0.3, Vector3d(2, 0.4, 0), Vector3d(3, 0.4, 0), 0.3));
  EXPECT_FALSE(cylinder_cylinder(p1, q1, 0.3, Vector3d(-1, 0.4, 0), Vector3d(0, 0.4, 0), 0.3));
  // Offset with a gap along the axis.
  EXPECT_FALSE(cylinder_cylinder(p1, q1, 0.3, Vector3d(2.1, 0.2, 0), Vector3d(3, 0.2, 0), 0.3));
}

TEST(CylinderCylinderKernel, CollinearOverlap) {
  // Same line, overlap x in [1, 2]: distance 0, penetration 0.5; point on the axis at 1.5
  // shifted by (r1 - r2)/2 along some normal across the axis.
  const auto c = cylinder_cylinder(Vector3d(0, 0, 0), Vector3d(2, 0, 0), 0.3, Vector3d(1, 0, 0),
                                   Vector3d(3, 0, 0), 0.2);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.5, kTight);
  EXPECT_NEAR(c->normal.norm(), 1.0, kTight);
  EXPECT_NEAR(c->normal.x(), 0.0, kTight);
  expect_near(c->point, Vector3d(1.5, 0, 0) + 0.05 * c->normal, kTight);
}

TEST(CylinderCylinderKernel, NearlyParallel) {
  const Vector3d p1(0, 0, 0), q1(2, 0, 0);
  // Tilted by 1e-9 rad: as parallel, contact at the middle of the overlap [1, 2].
  for (const double tilt : {1e-15, 1e-12, 1e-9, 1e-7}) {
    const auto c =
        cylinder_cylinder(p1, q1, 0.3, Vector3d(1, 0.5, 0), Vector3d(3, 0.5 + 2 * tilt, tilt), 0.3);
    ASSERT_TRUE(c) << tilt;
    EXPECT_NEAR(c->penetration, 0.1, 1e-6) << tilt;
    expect_near(c->normal, Vector3d(0, 1, 0), 1e-6);
    expect_near(c->point, Vector3d(1.5, 0.25, 0), 1e-6);
  }
  // Tilted by 1e-3 in the plane z = 0, converging towards x < 0 where the segments have
  // ended: the closest points are ends, so nothing.
  EXPECT_FALSE(cylinder_cylinder(p1, q1, 0.3, Vector3d(1, 0.5, 0), Vector3d(3, 0.502, 0), 0.3));
  // Tilted by 2e-3 out of the plane, twisting about x = 1: the common perpendicular is the
  // y direction at x = 1, distance 0.5.
  const auto c =
      cylinder_cylinder(p1, q1, 0.3, Vector3d(0, 0.5, -0.002), Vector3d(2, 0.5, 0.002), 0.3);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->penetration, 0.1, 1e-12);
  expect_near(c->normal, Vector3d(0, 1, 0), 1e-12);
  expect_near(c->point, Vector3d(1, 0.25, 0), 1e-12);
}

/// Two random segments: generic, or (nearly) parallel with tilts from 0 to 1e-3.
struct SegmentPair {
  Vector3d p1, q1, p2, q2;
  bool parallel = false;
};

SegmentPair random_segments(SplitMix64& rng) {
  SegmentPair s;
  s.p1 = random_in_box(rng, 0.5);
  const Vector3d d1 = uniform(rng, 0.2, 1.5) * random_unit(rng);
  s.q1 = s.p1 + d1;
  if (rng.below(3) != 0) {
    s.p2 = s.p1 + uniform(rng, -0.3, 1.3) * d1 + random_in_ball(rng, 0.8);
    s.q2 = s.p2 + uniform(rng, 0.2, 1.5) * random_unit(rng);
    return s;
  }
  s.parallel = true;
  const Vector3d u = d1.normalized();
  Vector3d across = random_unit(rng);
  across = (across - across.dot(u) * u).normalized();
  const double tilt = rng.below(4) == 0 ? 0.0 : std::pow(10.0, uniform(rng, -13.0, -3.0));
  const double len2 = uniform(rng, 0.2, 1.5);
  const Vector3d d2 = (rng.below(2) ? 1.0 : -1.0) * len2 * (u + tilt * random_unit(rng));
  s.p2 = s.p1 + uniform(rng, -1.5, 1.5) * u + uniform(rng, 0.0, 0.6) * across;
  s.q2 = s.p2 + d2;
  return s;
}

TEST(CylinderCylinderKernel, RandomAgainstSampledDistance) {
  SplitMix64 rng(0xc7c7);
  constexpr int kGrid = 20000;  // over segment 1; the inner minimum over segment 2 is exact
  int contacts = 0, parallel_contacts = 0, ends = 0;
  for (int k = 0; k < 3000; ++k) {
    const SegmentPair s = random_segments(rng);
    const double r1 = uniform(rng, 0.05, 0.3), r2 = uniform(rng, 0.05, 0.3);
    const double margin = rng.below(2) ? 0.1 : 0.0;
    const double R = r1 + r2;
    const double L1 = (s.q1 - s.p1).norm(), L2 = (s.q2 - s.p2).norm();
    const double tol = L1 / (2 * kGrid);
    // Minimum over the square (s, t) and over its boundary s or t in {0, 1}.
    double grid_min = INFINITY, boundary_min = INFINITY;
    for (int i = 0; i <= kGrid; ++i) {
      const Vector3d x = s.p1 + (static_cast<double>(i) / kGrid) * (s.q1 - s.p1);
      grid_min = std::min(grid_min, distance_to_segment(x, s.p2, s.q2));
      boundary_min = std::min({boundary_min, (x - s.p2).norm(), (x - s.q2).norm()});
    }
    boundary_min = std::min({boundary_min, distance_to_segment(s.p1, s.p2, s.q2),
                             distance_to_segment(s.q1, s.p2, s.q2)});

    const auto hit = cylinder_cylinder(s.p1, s.q1, r1, s.p2, s.q2, r2, margin);
    if (hit) {
      ++contacts;
      parallel_contacts += s.parallel;
      // Parallel pairs may pick the middle of the overlap: off by up to 1e-6 of its length.
      const double slack = 1e-6 * std::min(L1, L2) + 1e-12;
      EXPECT_GT(hit->penetration, -margin) << k;
      EXPECT_GE(hit->penetration, R - grid_min - slack) << k;
      EXPECT_LE(hit->penetration, R - grid_min + tol + 1e-12) << k;
      EXPECT_NEAR(hit->normal.norm(), 1.0, kTight);
      EXPECT_NEAR(hit->normal.dot((s.q1 - s.p1) / L1), 0.0, 1e-6) << k;
      EXPECT_NEAR(hit->normal.dot((s.q2 - s.p2) / L2), 0.0, 1e-6) << k;
      EXPECT_LT(distance_to_segment(core_a(*hit, r1), s.p1, s.q1), 1e-12) << k;
      EXPECT_LT(distance_to_segment(core_b(*hit, r2), s.p2, s.q2), 1e-12) << k;
    } else if (R - grid_min > -margin) {
      // Surely within reach but declined: some closest pair involves a segment end.
      ++ends;
      EXPECT_LE(boundary_min - grid_min, tol + 1e-12) << k;
    }
  }
  EXPECT_GT(contacts, 300) << parallel_contacts << " " << ends;
  EXPECT_GT(parallel_contacts, 100) << contacts << " " << ends;
  EXPECT_GT(ends, 400) << contacts << " " << parallel_contacts;
}

TEST(CylinderCylinderKernel, SwapAndReversalSymmetry) {
  SplitMix64 rng(0x5a5a);
  int contacts = 0;
  for (int k = 0; k < 4000; ++k) {
    const SegmentPair s = random_segments(rng);
    const double r1 = uniform(rng, 0.05, 0.3), r2 = uniform(rng, 0.05, 0.3);
    const double margin = rng.below(2) ? 0.1 : 0.0;
    const auto ab = cylinder_cylinder(s.p1, s.q1, r1, s.p2, s.q2, r2, margin);
    const auto ba = cylinder_cylinder(s.p2, s.q2, r2, s.p1, s.q1, r1, margin);
    const auto rev = cylinder_cylinder(s.q1, s.p1, r1, s.q2, s.p2, r2, margin);
    ASSERT_EQ(ab.has_value(), ba.has_value()) << k;
    ASSERT_EQ(ab.has_value(), rev.has_value()) << k;
    if (!ab) continue;
    ++contacts;
    EXPECT_NEAR(ba->penetration, ab->penetration, 1e-12) << k;
    expect_near(ba->normal, -ab->normal, 1e-9);
    expect_near(ba->point, ab->point, 1e-12);
    EXPECT_NEAR(rev->penetration, ab->penetration, 1e-12) << k;
    expect_near(rev->normal, ab->normal, 1e-9);
    expect_near(rev->point, ab->point, 1e-9);
  }
  EXPECT_GT(contacts, 400);
}

}  // namespace
