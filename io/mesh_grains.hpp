#pragma once
/// \file
/// Grains from mesh files (a scenario's [[mesh_grain]] tables): each mesh of an OBJ, STL or
/// PLY file (read through assimp, io::read_meshes) scaled, moved, checked and made an exact
/// convex shape (geometry::convex_shape_from_mesh).

#include <Eigen/Dense>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/specimen.hpp"

namespace cleave::io {

/// One [[mesh_grain]] table, in SI.
struct MeshGrainSpec {
  std::filesystem::path file;  ///< as resolved (relative to the scenario file's folder)
  double scale = 1.0;          ///< file coordinates x scale = metres
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< metres, added after scaling
  bool convex_hull = false;    ///< a non-convex mesh becomes its convex hull
};

/// A mesh grain that cannot be made: the message names the file, the mesh and the problem.
class MeshGrainError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One grain per mesh of the file, in file order, named "<file name>" (or
/// "<file name>:<mesh name>" when the file holds several). Throws MeshGrainError: missing or
/// unreadable file, then (per mesh) not closed, not manifold, inconsistent faces, degenerate,
/// or not convex without `convex_hull`.
std::vector<geometry::CustomGrainDef> load_mesh_grains(const MeshGrainSpec& spec);

/// How deep two convex meshes (outward faces, world coordinates) reach into each other: the
/// least overlap of their projections over the separating axes of two convex polyhedra (each
/// face normal, each cross product of an edge of one with an edge of the other), which is
/// the distance that separates them. 0 or less: they are apart or only touch.
double convex_overlap(const geometry::PolygonMesh& a, const geometry::PolygonMesh& b);

}  // namespace cleave::io
