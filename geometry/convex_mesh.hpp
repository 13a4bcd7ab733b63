#pragma once
/// \file
/// Grains from imported meshes: a double polygon mesh (as read from OBJ/STL/PLY) checked
/// and turned into an exact convex polyhedron, or into the exact convex hull of its
/// vertices when asked to. CGAL-free header; the work is done in convex_mesh.cpp.
///
/// The checks, in order, each a GeometryError whose message says what is wrong and where:
///  - no faces, a face with fewer than 3 corners, a repeated corner, a non-finite vertex;
///  - not manifold: an edge shared by more than two faces (which edge, how many such);
///  - not closed: edges used by one face only (how many, and one of them);
///  - faces not consistently oriented (two faces run an edge the same way);
///  - not one closed surface (Euler characteristic other than 2: several pieces, handles);
///  - degenerate: all vertices in one plane (zero volume);
///  - not convex (unless `convex_hull`): the vertex farthest outside a face's plane, by
///    how much (in the mesh's units), and how many vertex/face pairs violate convexity.
///    Vertices less than 1e-6 of the bounding-box diagonal outside a face's plane do not
///    count (planar faces stored in float are seldom exactly planar); the grain is then
///    the exact hull of the vertices, whose volume differs from the mesh's by rounding only.
/// Consistently inward-oriented meshes are accepted (the shape is the same). The result's
/// faces are the hull's planar facets merged into convex polygons, so a cube given as 12
/// triangles becomes 6 squares, and vertices inside a facet or on an edge are dropped.

#include <string>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/polygon_mesh.hpp"

namespace cleave::geometry {

/// An imported grain shape.
struct ConvexMeshResult {
  ExactPolyhedron shape;         ///< exact, closed, convex; in the mesh's coordinates
  bool was_convex = true;        ///< false: the mesh was not convex and `shape` is its hull
                                 ///< (true: `shape` is the mesh's own solid, exactly when
                                 ///< its faces are exactly planar and convex)
  double mesh_volume = 0.0;      ///< the mesh's own enclosed volume (rounded)
  double shape_volume = 0.0;     ///< the result's volume (rounded; > mesh_volume for a hull)
};

/// Checks `mesh` (vertices taken exactly as given) and builds its exact convex shape.
/// With `convex_hull` false a non-convex mesh is an error; with it true the grain is the
/// exact convex hull of the mesh's vertices (the mesh must still be one closed surface).
/// Throws GeometryError; messages start with "mesh '<name>': ".
ConvexMeshResult convex_shape_from_mesh(const PolygonMesh& mesh, bool convex_hull);

}  // namespace cleave::geometry
