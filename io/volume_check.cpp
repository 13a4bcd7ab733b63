#include "io/volume_check.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "io/mesh_io.hpp"
#include "io/voxel_volume.hpp"

namespace cleave::io {

namespace {
/// Exact volumes of the store's shapes, each computed once.
std::vector<geometry::ExactScalar> shape_volumes(const ExactStore& store) {
  std::vector<geometry::ExactScalar> v;
  v.reserve(store.shapes.size());
  for (const auto& s : store.shapes) v.push_back(s.volume());
  return v;
}
double surface_area(const geometry::PolygonMesh& mesh) {
  double area = 0.0;
  for (const auto& f : mesh.faces) {
    for (std::size_t i = 1; i + 1 < f.size(); ++i) {
      area += 0.5 * (mesh.vertices[f[i]] - mesh.vertices[f[0]])
                        .cross(mesh.vertices[f[i + 1]] - mesh.vertices[f[0]])
                        .norm();
    }
  }
  return area;
}
}  // namespace

std::vector<GrainVolumeCheck> check_exact_volumes(const ExactStore& store) {
  const auto volume = shape_volumes(store);
  struct Sum {
    geometry::ExactScalar total;
    int count = 0;
    std::vector<const ExactStore::Placement*> parts;
  };
  std::map<int, Sum> sums;
  for (const auto& f : store.fragments) {
    Sum& s = sums[f.lineage.grain_id];
    s.total = s.total + volume[f.shape];
    ++s.count;
    s.parts.push_back(&f);
  }
  std::vector<GrainVolumeCheck> out;
  for (const auto& g : store.grains) {
    GrainVolumeCheck c;
    c.grain_id = g.lineage.grain_id;
    const geometry::ExactScalar& parent = volume[g.shape];
    c.parent_volume = parent.to_double();
    auto it = sums.find(c.grain_id);
    if (it == sums.end()) {  // intact: the grain itself is what is alive
      c.fragment_sum = c.parent_volume;
      c.exact_equal = true;
      c.inside = true;
    } else {
      c.fragments = it->second.count;
      c.fragment_sum = it->second.total.to_double();
      c.exact_equal = it->second.total == parent;
      const geometry::ExactPolyhedron grain = store.shapes[g.shape].translated(g.position);
      c.inside = std::all_of(it->second.parts.begin(), it->second.parts.end(), [&](const auto* f) {
        return store.shapes[f->shape].translated(f->position).is_inside(grain);
      });
      sums.erase(it);
    }
    out.push_back(c);
  }
  for (const auto& [grain, s] : sums) {  // fragments of a grain the store does not have
    out.push_back(GrainVolumeCheck{grain, s.count, 0.0, s.total.to_double(), false, false});
  }
  return out;
}

std::vector<MeshVolumeCheck> check_mesh_volumes(const ExactStore& store,
                                                const std::filesystem::path& mesh_dir,
                                                double voxels_per_length) {
  if (!std::filesystem::is_directory(mesh_dir)) {
    throw std::runtime_error(mesh_dir.string() + ": no mesh folder to measure");
  }
  std::map<std::string, geometry::PolygonMesh> meshes;
  for (const auto& entry : std::filesystem::directory_iterator(mesh_dir)) {
    const auto ext = entry.path().extension().string();
    if (ext != ".stl" && ext != ".obj") continue;
    for (auto& m : read_meshes(entry.path())) {
      // Per-fragment STL files carry no mesh name: the file stem is the lineage name.
      if (m.name.empty() || meshes.count(m.name)) m.name = entry.path().stem().string();
      meshes[m.name] = std::move(m);
    }
  }
  if (meshes.empty()) throw std::runtime_error(mesh_dir.string() + ": holds no mesh file");
  std::vector<MeshVolumeCheck> out;
  for (const auto& f : store.fragments) {
    MeshVolumeCheck c;
    c.name = f.lineage.name();
    c.exact_volume = store.shapes[f.shape].volume().to_double();
    auto it = meshes.find(c.name);
    if (it != meshes.end()) {
      c.found = true;
      // Characteristic thickness 6V/A (the edge of a cube): thin slabs get finer voxels.
      const double thickness = 6.0 * c.exact_volume / surface_area(it->second);
      const double voxel = thickness / voxels_per_length;
      c.voxel_volume = voxel_volume(it->second, voxel);
      c.relative_error = std::abs(c.voxel_volume - c.exact_volume) / c.exact_volume;
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace cleave::io
