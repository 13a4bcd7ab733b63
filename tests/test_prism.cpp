// The hexagonal prism grain against closed forms derived by hand:
//   volume           V   = (3 sqrt3 / 2) a^2 t
//   polar moment     Izz = V (5/12) a^2          (hexagon = 6 equilateral triangles:
//                                                  each A(a^2/12 + a^2/3) about the centre)
//   in-plane moments Ixx = Iyy = V (5 a^2 / 24 + t^2 / 12),  products of inertia zero.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/contact_primitives.hpp"

using namespace cleave::geometry;

namespace {
const double kSqrt3 = std::sqrt(3.0);

struct PrismCase {
  double side;
  double thickness;
};
class HexagonalPrismClosedForm : public ::testing::TestWithParam<PrismCase> {};
}  // namespace

TEST_P(HexagonalPrismClosedForm, VolumeCentroidAndInertia) {
  const auto [a, t] = GetParam();
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(a, t);
  const double V = 1.5 * kSqrt3 * a * a * t;
  const MassProperties mp = prism.mass_properties();
  EXPECT_NEAR(mp.volume, V, 1e-14 * V);
  EXPECT_NEAR(prism.volume().to_double(), V, 1e-14 * V);
  // Symmetric corners: the centroid is exactly the origin.
  EXPECT_EQ(mp.centroid.x(), 0.0);
  EXPECT_EQ(mp.centroid.y(), 0.0);
  EXPECT_EQ(mp.centroid.z(), 0.0);
  const double Izz = V * 5.0 / 12.0 * a * a;
  const double Ixx = V * (5.0 * a * a / 24.0 + t * t / 12.0);
  const double scale = std::max(Izz, Ixx);
  EXPECT_NEAR(mp.inertia(0, 0), Ixx, 1e-13 * scale);
  EXPECT_NEAR(mp.inertia(1, 1), Ixx, 1e-13 * scale);
  EXPECT_NEAR(mp.inertia(2, 2), Izz, 1e-13 * scale);
  EXPECT_NEAR(mp.inertia(0, 1), 0.0, 1e-13 * scale);
  EXPECT_NEAR(mp.inertia(0, 2), 0.0, 1e-13 * scale);
  EXPECT_NEAR(mp.inertia(1, 2), 0.0, 1e-13 * scale);
  // Principal moments ascending and right-handed axes.
  EXPECT_LE(mp.principal_moments[0], mp.principal_moments[1]);
  EXPECT_LE(mp.principal_moments[1], mp.principal_moments[2]);
  EXPECT_NEAR(mp.principal_axes.determinant(), 1.0, 1e-12);
  // Density scales mass and inertia.
  const double rho = 3100.0;  // SiC, specific gravity 3.10 (table 2.3)
  EXPECT_NEAR(mp.mass(rho), rho * V, 1e-14 * rho * V);
  EXPECT_NEAR(mp.inertia_tensor(rho)(2, 2), rho * Izz, 1e-13 * rho * scale);
}

INSTANTIATE_TEST_SUITE_P(Sizes, HexagonalPrismClosedForm,
                         ::testing::Values(PrismCase{1.0, 1.0}, PrismCase{0.5e-3, 1.0e-3},
                                           PrismCase{2.0, 0.25}, PrismCase{0.75, 3.0}));

TEST(HexagonalPrism, IsAClosedOutwardConvexPolyhedron) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(0.6e-3, 1.3e-3);
  EXPECT_EQ(prism.num_vertices(), 12);
  EXPECT_EQ(prism.num_edges(), 18);
  EXPECT_EQ(prism.num_faces(), 8);
  EXPECT_TRUE(prism.is_valid_convex());
  const CgalValidation cgal = validate_with_cgal(prism);
  EXPECT_TRUE(cgal.valid_mesh);
  EXPECT_TRUE(cgal.closed);
  EXPECT_TRUE(cgal.outward_oriented);
  EXPECT_TRUE(cgal.volume_matches);
  EXPECT_TRUE(prism.to_mesh().is_closed_and_consistently_oriented());
  EXPECT_GT(prism.to_mesh().signed_volume(), 0.0);
}

TEST(HexagonalPrism, CornersFollowAppendixA) {
  // App. A (GrainVertices.m): corner n at (r sin(60 n), r cos(60 n)), z = -+ t/2.
  const double r = 0.5, t = 1.0;
  const auto v = ExactPolyhedron::hexagonal_prism(r, t).vertices_approx();
  for (int n = 0; n < 6; ++n) {
    const double th = n * M_PI / 3.0;
    EXPECT_NEAR(v[n].x(), r * std::sin(th), 1e-15);
    EXPECT_NEAR(v[n].y(), r * std::cos(th), 1e-15);
    EXPECT_EQ(v[n].z(), -t / 2);
    EXPECT_NEAR(v[6 + n].x(), r * std::sin(th), 1e-15);
    EXPECT_EQ(v[6 + n].z(), t / 2);
  }
}

TEST(HexagonalPrism, RejectsNonPositiveSizes) {
  EXPECT_THROW(ExactPolyhedron::hexagonal_prism(0.0, 1.0), GeometryError);
  EXPECT_THROW(ExactPolyhedron::hexagonal_prism(1.0, -1.0), GeometryError);
}

TEST(ExactText, RoundTripsExactly) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(0.6e-3, 1.3e-3);
  const auto slabs = prism.cleavage_slabs({CleavageFamily::a_11_20, 60});
  for (const auto& s : slabs) {
    const std::string text = s.to_exact_text();
    const ExactPolyhedron back = ExactPolyhedron::from_exact_text(text);
    EXPECT_TRUE(back.volume() == s.volume());
    EXPECT_EQ(back.to_exact_text(), text);
  }
}

TEST(ExactText, RejectsMalformedText) {
  const std::string good = ExactPolyhedron::hexagonal_prism(1.0, 1.0).to_exact_text();
  EXPECT_THROW(ExactPolyhedron::from_exact_text(""), GeometryError);
  EXPECT_THROW(ExactPolyhedron::from_exact_text(good.substr(0, good.size() / 2)), GeometryError);
  std::string bad_number = good;
  bad_number.replace(bad_number.find('\n') + 1, 1, "x");
  EXPECT_THROW(ExactPolyhedron::from_exact_text(bad_number), GeometryError);
  EXPECT_THROW(ExactPolyhedron::from_exact_text("vertices 1\n1/0 0 0\nfaces 0\n"), GeometryError);
  // A face reversed: the surface is no longer consistently oriented.
  std::string flipped = good;
  flipped.replace(flipped.find("6 0 1 2 3 4 5"), 13, "6 5 4 3 2 1 0");
  EXPECT_THROW(ExactPolyhedron::from_exact_text(flipped), GeometryError);
}

TEST(FromMesh, RejectsOpenInwardAndNonConvexMeshes) {
  PolygonMesh cube;
  cube.name = "cube";
  cube.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  cube.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  const ExactPolyhedron ok = ExactPolyhedron::from_mesh(cube);
  EXPECT_TRUE(ok.volume() == ExactScalar(1.0));

  PolygonMesh open = cube;
  open.faces.pop_back();
  EXPECT_THROW(ExactPolyhedron::from_mesh(open), GeometryError);

  PolygonMesh inward = cube;
  for (auto& f : inward.faces) std::reverse(f.begin(), f.end());
  EXPECT_THROW(ExactPolyhedron::from_mesh(inward), GeometryError);

  PolygonMesh dented = cube;
  dented.vertices[6] = {0.5, 0.5, 0.5};  // pushes a corner in: faces no longer planar/convex
  EXPECT_THROW(ExactPolyhedron::from_mesh(dented), GeometryError);
}

TEST(ContactPrimitives, PrismHasTwelveSpheresEighteenCylindersEightFaces) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(0.5, 1.0);
  const MassProperties mp = prism.mass_properties();
  const ContactPrimitives cp = make_contact_primitives(prism.to_mesh(), mp.centroid, 0.05);
  EXPECT_EQ(cp.vertices.size(), 12u);
  EXPECT_EQ(cp.edges.size(), 18u);
  EXPECT_EQ(cp.faces.size(), 8u);
  // 2 hexagons -> 4 triangles each, 6 quads -> 2 each.
  EXPECT_EQ(cp.triangles.size(), 20u);
  // Diagonals of the triangulation are not contact edges: every contact edge is an edge of
  // exactly two faces, and the triangles' own edges include 20*3/2 - 18 = 12 diagonals.
  for (const auto& e : cp.edges) {
    EXPECT_GE(e.left_face, 0);
    EXPECT_GE(e.right_face, 0);
    EXPECT_NE(e.left_face, e.right_face);
  }
  // Bounding radius: corner distance sqrt(r^2 + (t/2)^2) plus the dilation.
  EXPECT_NEAR(cp.bounding_radius, std::sqrt(0.25 + 0.25) + 0.05, 1e-15);
  // Face areas and normals: the hexagon and the side rectangles.
  double area = 0.0;
  for (const auto& f : cp.faces) {
    area += f.area;
    EXPECT_NEAR(f.normal.norm(), 1.0, 1e-15);
    EXPECT_GT(f.normal.dot(f.centroid), 0.0);  // outward from the centroid
  }
  EXPECT_NEAR(area, 2 * 1.5 * kSqrt3 * 0.25 + 6 * 0.5 * 1.0, 1e-14);
}

TEST(ContactPrimitives, RejectsNegativeDilationAndOpenMeshes) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(0.5, 1.0);
  EXPECT_THROW(make_contact_primitives(prism.to_mesh(), {0, 0, 0}, -1.0), std::invalid_argument);
  PolygonMesh open = prism.to_mesh();
  open.faces.pop_back();
  EXPECT_THROW(make_contact_primitives(open, {0, 0, 0}, 0.0), std::invalid_argument);
}
