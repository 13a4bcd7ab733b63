#include "io/mesh_grains.hpp"

#include <algorithm>
#include <limits>

#include "geometry/convex_mesh.hpp"
#include "io/mesh_io.hpp"

namespace cleave::io {

std::vector<geometry::CustomGrainDef> load_mesh_grains(const MeshGrainSpec& spec) {
  std::vector<geometry::PolygonMesh> meshes;
  try {
    meshes = read_meshes(spec.file);
  } catch (const MeshIoError& e) {
    throw MeshGrainError(e.what());
  }
  const std::string file_name = spec.file.filename().string();
  std::vector<geometry::CustomGrainDef> grains;
  for (auto& mesh : meshes) {
    try {
      // Checked first as the file has it, so that messages quote the file's coordinates;
      // then made in place (scaled and moved in doubles, then taken exactly).
      geometry::ConvexMeshResult r = geometry::convex_shape_from_mesh(mesh, spec.convex_hull);
      if (spec.scale != 1.0 || spec.offset != Eigen::Vector3d::Zero()) {
        for (auto& v : mesh.vertices) v = v * spec.scale + spec.offset;
        r = geometry::convex_shape_from_mesh(mesh, spec.convex_hull);
      }
      grains.push_back({meshes.size() == 1 ? file_name : file_name + ":" + mesh.name,
                        std::move(r.shape)});
    } catch (const geometry::GeometryError& e) {
      throw MeshGrainError("mesh file '" + spec.file.string() + "': " + e.what());
    }
  }
  return grains;
}

namespace {

/// The outward unit normals of a mesh's faces (Newell's method) and its edges' directions.
struct Axes {
  std::vector<Eigen::Vector3d> normals, edges;
};

Axes axes_of(const geometry::PolygonMesh& m) {
  Axes a;
  for (const auto& f : m.faces) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < f.size(); ++k) {
      const Eigen::Vector3d& p = m.vertices[static_cast<std::size_t>(f[k])];
      const Eigen::Vector3d& q = m.vertices[static_cast<std::size_t>(f[(k + 1) % f.size()])];
      n += p.cross(q);
      if (f[k] < f[(k + 1) % f.size()]) a.edges.push_back((q - p).normalized());
    }
    if (n.norm() > 0.0) a.normals.push_back(n.normalized());
  }
  return a;
}

/// The overlap of the two vertex sets' projections on `n`.
double overlap_along(const Eigen::Vector3d& n, const geometry::PolygonMesh& a,
                     const geometry::PolygonMesh& b) {
  double lo_a = std::numeric_limits<double>::infinity(), hi_a = -lo_a, lo_b = lo_a, hi_b = -lo_a;
  for (const auto& v : a.vertices) {
    lo_a = std::min(lo_a, n.dot(v));
    hi_a = std::max(hi_a, n.dot(v));
  }
  for (const auto& v : b.vertices) {
    lo_b = std::min(lo_b, n.dot(v));
    hi_b = std::max(hi_b, n.dot(v));
  }
  return std::min(hi_a, hi_b) - std::max(lo_a, lo_b);
}

}  // namespace

double convex_overlap(const geometry::PolygonMesh& a, const geometry::PolygonMesh& b) {
  const Axes x = axes_of(a), y = axes_of(b);
  double depth = std::numeric_limits<double>::infinity();
  const auto take = [&](const Eigen::Vector3d& n) {
    depth = std::min(depth, overlap_along(n, a, b));
    return depth <= 0.0;
  };
  for (const auto* normals : {&x.normals, &y.normals})
    for (const auto& n : *normals)
      if (take(n)) return depth;
  for (const auto& e : x.edges) {
    for (const auto& f : y.edges) {
      const Eigen::Vector3d n = e.cross(f);
      if (n.norm() < 1e-9) continue;  // parallel edges: a face normal covers them
      if (take(n.normalized())) return depth;
    }
  }
  return depth;
}

}  // namespace cleave::io
