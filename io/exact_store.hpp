#pragma once
/// \file
/// `geometry.exact`: the exact shapes of a result and where each grain and fragment uses
/// them, so `cleave check volume` can recompute every volume in exact arithmetic from the
/// result folder alone.
///
/// Format (text, one record per line):
///   cleave-exact 1
///   shape ID            followed by ExactPolyhedron::to_exact_text(), then "end"
///   grain ID shape S position X Y Z
///   fragment PATH shape S position X Y Z       (PATH like 17.1.0: grain id, then splits)
/// Positions are doubles written with 17 significant digits (they round-trip exactly).

#include <Eigen/Dense>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/specimen.hpp"

namespace cleave::io {

struct ExactStore {
  struct Placement {
    geometry::Lineage lineage;  ///< path empty for an intact grain
    int shape = 0;              ///< index into shapes
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
  };
  std::vector<geometry::ExactPolyhedron> shapes;
  std::vector<Placement> grains;
  std::vector<Placement> fragments;
};

/// Collects the distinct shapes of a specimen's grains and of `pieces` (shared shapes are
/// stored once).
ExactStore make_exact_store(const geometry::Specimen& specimen,
                            const std::vector<geometry::Piece>& pieces);

std::string to_text(const ExactStore& store);
/// Parses the text; throws std::runtime_error "SOURCE:LINE: message" on malformed input.
ExactStore parse_exact_store(const std::string& text, const std::string& source);

void write_exact_store(const std::filesystem::path& file, const ExactStore& store);
ExactStore read_exact_store(const std::filesystem::path& file);

}  // namespace cleave::io
