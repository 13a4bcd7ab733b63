#pragma once
/// \file
/// A top view of a specimen's bottom layer as SVG: every fragment's footprint, coloured by
/// its grain's cleavage family and angle. Opens in any browser.

#include <string>
#include <vector>

#include "geometry/specimen.hpp"

namespace cleave::sim {

std::string specimen_picture_svg(const geometry::Specimen& specimen,
                                 const std::vector<geometry::Piece>& pieces);

}  // namespace cleave::sim
