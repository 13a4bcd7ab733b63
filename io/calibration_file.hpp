#pragma once
/// \file
/// A calibration file (`cleave calibrate FILE`): which test scenarios measure which targets,
/// and the targets' defaults from a material preset.
///
///   [calibration]
///   preset = "sic_alpha"          # optional: targets default to its E, nu, tensile strength
///   elastic = "sic_elastic.toml"  # optional: the elastic test (E, nu), from this file's folder
///   brazilian = "sic_brazilian.toml"  # optional: the Brazilian test (sigma_t)
///   flexural = "sic_four_point.toml"  # optional, with brazilian: four-point bending (sigma_f)
///   senb = "sic_senb.toml"        # optional: the notched beam with [fracture] (K_Ic)
///   tolerance = 0.02              # optional (0, 0.5): relative, on every target
///   flexural_tolerance = 0.05     # optional (0, 0.5): relative, on sigma_f (default: tolerance)
///   max_trials = 8                # optional (>= 1): per loop
///
/// Errors are io::ScenarioError naming file:line:column and key.

#include <filesystem>
#include <optional>
#include <string>

namespace cleave::io {

struct CalibrationFile {
  std::string source;
  std::string preset_file;                  ///< resolved, empty without a preset
  std::filesystem::path elastic, brazilian, flexural, senb;  ///< empty: not given
  double tolerance = 0.02;
  std::optional<double> flexural_tolerance;
  int max_trials = 8;
};

CalibrationFile load_calibration(const std::filesystem::path& file);

}  // namespace cleave::io
