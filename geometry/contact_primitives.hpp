#pragma once
/// \file
/// The double-precision contact data of a shape, derived once from its exact polyhedron:
/// the primitives of a dilated polyhedron (sec. 2.3.1 of the dissertation). Vertices become
/// spheres, edges cylinders and faces flat facets, all of radius `dilation_radius`.
///
/// Unlike the dissertation's mesh (14 spheres, 36 cylinders, 24 facets per prism, which
/// includes the centre points and fan diagonals of a triangulated mesh), only the true
/// corners and edges of the polyhedron are spheres and cylinders: a prism has 12, 18 and 8.
/// Face triangles exist for kernels that want them, but each knows its face and their
/// diagonals are never contact edges, so contact forces cannot depend on triangulation.

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "geometry/polygon_mesh.hpp"

namespace cleave::geometry {

struct ContactFace {
  std::vector<int> vertices;          ///< CCW seen from outside
  std::vector<int> rim;               ///< edge i: index of the edge vertices[i] -> vertices[i + 1]
  Eigen::Vector3d normal;             ///< outward unit normal
  double offset = 0.0;                ///< normal . x = offset on the face plane
  Eigen::Vector3d centroid;           ///< area centroid of the face
  double area = 0.0;
};

struct ContactEdge {
  int a = 0, b = 0;                   ///< vertex indices, a < b
  int left_face = -1, right_face = -1;///< the two faces sharing the edge
};

struct ContactTriangle {
  std::array<int, 3> v{};             ///< CCW seen from outside
  int face = -1;                      ///< the polygon face it belongs to
};

struct ContactPrimitives {
  /// Shape-frame position of the body-frame origin (the centroid); all coordinates below
  /// are relative to it, in the shape frame's axes.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> vertices;
  std::vector<ContactEdge> edges;
  std::vector<Eigen::Vector3d> edge_units;  ///< unit direction of each edge, a -> b
  std::vector<double> edge_lengths;
  std::vector<ContactFace> faces;
  std::vector<ContactTriangle> triangles;
  double dilation_radius = 0.0;
  /// How far a direction in an edge's normal cone (between its two faces' outward normals)
  /// can point against either face's normal, over all edges: max(0, -n_left . n_right),
  /// plus 1e-6 for the cone test's tolerance and rounding. 0 to 1 for a convex shape.
  double edge_cone_spread = 0.0;
  /// Radius of the sphere about the origin that holds the dilated shape:
  /// max |vertex| + dilation_radius.
  double bounding_radius = 0.0;
};

/// Fills what follows from the vertices, edges and faces: every face's `rim`, every edge's
/// unit direction and length, and the edge cone spread. Returns false when a side of a face
/// is not an edge.
bool finish_primitives(ContactPrimitives& p);

/// Contact primitives of a closed, outward, convex polygon mesh given in its shape frame;
/// `centroid` (shape frame) becomes the origin. Throws std::invalid_argument for a
/// negative dilation radius or a mesh that is not closed and consistently oriented.
ContactPrimitives make_contact_primitives(const PolygonMesh& shape, const Eigen::Vector3d& centroid,
                                          double dilation_radius);

}  // namespace cleave::geometry
