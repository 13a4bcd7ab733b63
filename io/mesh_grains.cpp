#include "io/mesh_grains.hpp"

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

}  // namespace cleave::io
