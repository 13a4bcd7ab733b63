#pragma once
/// \file
/// A file of one crystal orientation per grain: Bunge Euler angles in degrees (the convention of
/// geometry/orientation.hpp), plain text.
///
///   # comments run from '#' to the end of the line; blank lines are ignored
///   10.0  35.3  45.0        # phi1 Phi phi2: the line's rank is the grain (0, 1, 2, ...)
///
/// or, with a grain index column (0-based, every grain exactly once, any order):
///
///   0   10.0  35.3  45.0    # grain phi1 Phi phi2
///   1  200.0  90.0   0.0
///
/// One layout per file. Phi must lie in [0, 180]; phi1 and phi2 may be any finite angle. A Neper
/// .ori file written with `-oridescriptor euler-bunge` has the first layout.
///
/// Errors are io::ScenarioError naming file:line:column and the column's name as key
/// ("phi1", "Phi", "phi2", "grain"); errors about the whole file (unreadable, empty, a grain
/// without a line, a count that differs from the specimen's) name the file only.

#include <Eigen/Geometry>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

namespace cleave::io {

/// The orientations in grain order. With `grain_count`, the file must hold exactly that many.
std::vector<Eigen::Quaterniond> read_orientation_file(
    const std::filesystem::path& file, std::optional<std::size_t> grain_count = std::nullopt);

/// Writes `grain phi1 Phi phi2` lines (degrees, shortest round-trip decimals) under a header
/// comment; read_orientation_file reads it back to the same rotations.
void write_orientation_file(const std::filesystem::path& file,
                            const std::vector<Eigen::Quaterniond>& orientations);

}  // namespace cleave::io
