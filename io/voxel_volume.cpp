#include "io/voxel_volume.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetMeasure.h>
#include <openvdb/tools/MeshToVolume.h>

#include <cmath>
#include <cstddef>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

// The only translation unit that includes OpenVDB (its headers are heavy to compile).

namespace cleave::io {

namespace {

/// Narrow band half width on each side of the surface, in voxels.
constexpr float kHalfBandVoxels = 3.0f;

/// Triangles with points already in grid index space, kept in double so that the division
/// by the voxel size does not round more than OpenVDB's own arithmetic does.
/// Implements OpenVDB's MeshDataAdapter interface (see tools/MeshToVolume.h).
struct IndexSpaceTriangles {
  std::vector<openvdb::Vec3d> points;
  std::vector<openvdb::Vec3I> triangles;

  [[nodiscard]] std::size_t polygonCount() const { return triangles.size(); }
  [[nodiscard]] std::size_t pointCount() const { return points.size(); }
  [[nodiscard]] std::size_t vertexCount(std::size_t) const { return 3; }
  void getIndexSpacePoint(std::size_t n, std::size_t v, openvdb::Vec3d& pos) const {
    pos = points[triangles[n][static_cast<int>(v)]];
  }
};

void initialize_openvdb_once() {
  static std::once_flag flag;
  std::call_once(flag, [] { openvdb::initialize(); });
}

}  // namespace

double voxel_volume(const geometry::PolygonMesh& mesh, double voxel_size) {
  if (!(voxel_size > 0.0) || !std::isfinite(voxel_size)) {
    throw std::invalid_argument("voxel_volume: voxel_size must be a finite positive length, got " +
                                std::to_string(voxel_size));
  }
  const geometry::PolygonMesh tri = mesh.triangulated();
  if (tri.faces.empty()) {
    throw std::invalid_argument("voxel_volume: mesh '" + mesh.name + "' has no faces");
  }

  // Work in index space with unit voxels: OpenVDB's transforms refuse scales as small as
  // SI grain sizes (a 1e-5 m voxel reads as "zero scale"), so the mesh is moved next to
  // the origin and divided by the voxel size, and the volume scaled back at the end.
  IndexSpaceTriangles data;
  data.points.reserve(tri.vertices.size());
  const Eigen::Vector3d origin = tri.vertices.front();
  for (const Eigen::Vector3d& p : tri.vertices) {
    const Eigen::Vector3d q = (p - origin) / voxel_size;
    data.points.emplace_back(q.x(), q.y(), q.z());
  }
  data.triangles.reserve(tri.faces.size());
  const auto n = static_cast<long long>(tri.vertices.size());
  for (const auto& f : tri.faces) {
    for (int v : f) {
      if (v < 0 || v >= n) {
        throw std::invalid_argument("voxel_volume: mesh '" + mesh.name + "' refers to vertex " +
                                    std::to_string(v) + " of " + std::to_string(n));
      }
    }
    data.triangles.emplace_back(f[0], f[1], f[2]);
  }

  initialize_openvdb_once();
  try {
    const openvdb::math::Transform::Ptr unit = openvdb::math::Transform::createLinearTransform(1.0);
    const openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        data, *unit, kHalfBandVoxels, kHalfBandVoxels);
    return openvdb::tools::levelSetVolume(*grid, /*useWorldSpace=*/false) * voxel_size *
           voxel_size * voxel_size;
  } catch (const openvdb::Exception& e) {
    throw std::runtime_error("voxel_volume: OpenVDB failed on mesh '" + mesh.name +
                             "': " + e.what());
  }
}

}  // namespace cleave::io
