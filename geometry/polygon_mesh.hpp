#pragma once
/// \file
/// A plain double-precision polygon mesh: what leaves the exact world for export,
/// rendering and contact primitives. No CGAL here.

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace cleave::geometry {

/// A closed polygon mesh in double precision. Faces list vertex indices counter-clockwise
/// seen from outside (outward orientation). Faces may be polygons (the exact shapes have
/// hexagons and quads); `triangulated()` fans them into triangles.
struct PolygonMesh {
  std::string name;                        ///< lineage name, e.g. "grain_0017.1.0"
  std::vector<Eigen::Vector3d> vertices;   ///< positions (SI metres in world or body frame)
  std::vector<std::vector<int>> faces;     ///< CCW-from-outside vertex loops

  /// Number of undirected edges (each shared by exactly two faces in a closed mesh).
  [[nodiscard]] std::size_t edge_count() const;
  /// Fan triangulation of every face; keeps vertex indices, so the vertex count is unchanged.
  [[nodiscard]] PolygonMesh triangulated() const;
  /// Signed volume by the divergence theorem (positive when outward oriented).
  [[nodiscard]] double signed_volume() const;
  /// True when every directed edge appears exactly once and its reverse exactly once:
  /// the mesh is closed (watertight) and consistently oriented.
  [[nodiscard]] bool is_closed_and_consistently_oriented() const;
};

}  // namespace cleave::geometry
