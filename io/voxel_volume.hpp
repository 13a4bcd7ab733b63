#pragma once
/// \file
/// Independent volume measurement of a mesh through OpenVDB: mesh -> narrow-band level
/// set -> volume. It does not trust the mesh's connectivity, so a mesh that is not
/// watertight shows up as a volume far from the exact one.

#include "geometry/polygon_mesh.hpp"

namespace cleave::io {

/// Volume of `mesh` (closed, outward) measured on a level set with voxels of edge
/// `voxel_size` (same unit as the mesh). Throws std::invalid_argument for voxel_size <= 0.
double voxel_volume(const geometry::PolygonMesh& mesh, double voxel_size);

}  // namespace cleave::io
