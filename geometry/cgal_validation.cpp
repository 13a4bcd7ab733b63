// A second opinion on exact shapes from CGAL's own mesh algorithms (used by tests):
// kept in its own translation unit because Polygon_mesh_processing is slow to compile.

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>

#include "geometry/exact_internal.hpp"

namespace cleave::geometry {

CgalValidation validate_with_cgal(const ExactPolyhedron& shape) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  using Mesh = CGAL::Surface_mesh<Point3>;
  const auto& impl = ExactAccess::impl(shape);

  Mesh mesh;
  std::vector<Mesh::Vertex_index> vi;
  vi.reserve(impl.vertices.size());
  for (const auto& p : impl.vertices) vi.push_back(mesh.add_vertex(p));
  CgalValidation out;
  for (const auto& f : impl.faces) {
    std::vector<Mesh::Vertex_index> loop;
    for (int i : f) loop.push_back(vi[i]);
    if (mesh.add_face(loop) == Mesh::null_face()) return out;  // non-manifold: invalid
  }
  out.valid_mesh = CGAL::is_valid_polygon_mesh(mesh);
  out.closed = CGAL::is_closed(mesh);
  if (!out.valid_mesh || !out.closed) return out;
  if (!PMP::triangulate_faces(mesh)) return out;
  out.outward_oriented = PMP::is_outward_oriented(mesh);
  out.volume_matches = PMP::volume(mesh) == ExactAccess::value(shape.volume());
  return out;
}

}  // namespace cleave::geometry
