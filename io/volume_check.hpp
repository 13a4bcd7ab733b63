#pragma once
/// \file
/// Volume conservation checks of a result folder: exact (rational) per grain, and an
/// independent voxel measurement of each exported mesh through OpenVDB.

#include <filesystem>
#include <string>
#include <vector>

#include "io/exact_store.hpp"

namespace cleave::io {

struct GrainVolumeCheck {
  int grain_id = 0;
  int fragments = 0;         ///< fragments alive for this grain (0: the grain is intact)
  double parent_volume = 0;  ///< rounded, for the report
  double fragment_sum = 0;   ///< rounded, for the report
  bool exact_equal = false;  ///< the exact comparison
  bool inside = false;       ///< every fragment lies inside the grain (exact, world frame)
};

/// For every grain: its exact volume against the exact sum of its fragments' volumes (an
/// intact grain, with no fragments, is compared with itself), and whether every fragment,
/// placed in the world, lies inside the placed grain (exact predicates). Fragments naming a
/// grain that does not exist are reported as a grain with parent volume 0.
std::vector<GrainVolumeCheck> check_exact_volumes(const ExactStore& store);

struct MeshVolumeCheck {
  std::string name;           ///< lineage name of the fragment
  double exact_volume = 0.0;  ///< from the exact shape, rounded
  double voxel_volume = 0.0;  ///< measured on the exported mesh through OpenVDB
  double relative_error = 0.0;
  bool found = false;         ///< a mesh of that name was in the export
};

/// Reads every mesh file in `mesh_dir`, matches meshes to fragments by lineage name and
/// measures each on a level set with `voxels_per_length` voxels across its characteristic
/// thickness 6V/A (a cube's edge; thin slabs get finer voxels). Throws std::runtime_error if the folder holds no readable mesh.
std::vector<MeshVolumeCheck> check_mesh_volumes(const ExactStore& store,
                                                const std::filesystem::path& mesh_dir,
                                                double voxels_per_length);

}  // namespace cleave::io
