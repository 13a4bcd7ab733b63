// `cleave check volume DIR [--voxel]`: exact volume conservation of a result folder.

#include <fmt/format.h>

#include <algorithm>

#include "commands.hpp"
#include "io/exact_store.hpp"
#include "io/result_dir.hpp"
#include "io/volume_check.hpp"

namespace cleave::app {

int check_volume_command(const CheckVolumeOptions& options) {
  io::ExactStore store;
  try {
    const io::Manifest manifest = io::read_manifest(options.dir);
    if (manifest.status == io::run_status::stopped) {
      // Cut by --max-steps: its files are whole up to that step, so its pieces can be checked.
      fmt::print(
          "note: {} is a run stopped before its end ({}); checking the pieces it ended with\n",
          options.dir.string(), manifest.reason);
    } else if (manifest.status != io::run_status::finished) {
      fmt::print(stderr, "cleave: error: {} holds an unfinished run (status '{}'{}{})\n",
                 options.dir.string(), manifest.status, manifest.reason.empty() ? "" : ": ",
                 manifest.reason);
      return 2;
    }
    store = io::read_exact_store(options.dir / "geometry.exact");
    const auto format = manifest.facts.find("mesh_format");
    const auto layout = manifest.facts.find("mesh_layout");
    if (options.voxel && format != manifest.facts.end() && layout != manifest.facts.end() &&
        format->second.rfind("stl", 0) == 0 && layout->second == "scene") {
      fmt::print(stderr,
                 "cleave: error: --voxel measures each fragment's own mesh, but {} holds one STL "
                 "scene (STL keeps no mesh names); run with --mesh-format obj or "
                 "--mesh-layout per_fragment\n",
                 options.dir.string());
      return 2;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 2;
  }

  const auto checks = io::check_exact_volumes(store);
  int mismatches = 0, outside = 0, split = 0;
  if (!options.summary_only) {
    fmt::print("{:>8} {:>9} {:>22} {:>22}  {:<9}  {}\n", "grain", "fragments", "grain volume [m^3]",
               "sum of fragments [m^3]", "exact", "fragments inside grain");
  }
  for (const auto& c : checks) {
    mismatches += !c.exact_equal;
    outside += !c.inside;
    split += c.fragments > 0;
    if (!options.summary_only || !c.exact_equal || !c.inside) {
      fmt::print("{:>8} {:>9} {:>22.15e} {:>22.15e}  {:<9}  {}\n", c.grain_id, c.fragments,
                 c.parent_volume, c.fragment_sum, c.exact_equal ? "equal" : "NOT EQUAL",
                 c.inside ? "yes" : "NO");
    }
  }
  fmt::print("exact volume check: {} grains ({} split into {} fragments): {}\n", checks.size(),
             split, store.fragments.size(),
             mismatches == 0 ? "every grain's fragments sum exactly to its volume"
                             : fmt::format("{} grain(s) do NOT conserve volume", mismatches));
  if (outside > 0) fmt::print("  {} grain(s) have a fragment reaching outside the grain\n", outside);
  int status = mismatches == 0 && outside == 0 ? 0 : 1;

  if (options.voxel) {
    std::vector<io::MeshVolumeCheck> meshes;
    try {
      meshes = io::check_mesh_volumes(store, options.dir / "meshes", options.voxels_per_length);
    } catch (const std::exception& e) {
      fmt::print(stderr, "cleave: error: {}\n", e.what());
      return 2;
    }
    int missing = 0, off = 0;
    double worst = 0.0;
    for (const auto& m : meshes) {
      if (!m.found) {
        ++missing;
        fmt::print("  mesh {:<24} MISSING from the export\n", m.name);
        continue;
      }
      worst = std::max(worst, m.relative_error);
      const bool bad = m.relative_error > options.voxel_tolerance;
      off += bad;
      if (bad || !options.summary_only) {
        fmt::print("  mesh {:<24} exact {:.6e}  voxel {:.6e}  rel. diff {:.2e}{}\n", m.name,
                   m.exact_volume, m.voxel_volume, m.relative_error,
                   bad ? "  NOT WATERTIGHT?" : "");
      }
    }
    fmt::print("voxel volume check (OpenVDB, {:g} voxels per length): {} meshes, largest relative "
               "difference {:.2e} (tolerance {:g}); {} missing, {} beyond tolerance\n",
               options.voxels_per_length, meshes.size(), worst, options.voxel_tolerance, missing,
               off);
    if (missing > 0 || off > 0) status = 1;
  }
  return status;
}

}  // namespace cleave::app
