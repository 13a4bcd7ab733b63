#pragma once
/// \file
/// A specimen: grains on the honeycomb lattice inside an outline, each with a
/// crystallographic orientation; and the fragments they are cut into.

#include <Eigen/Dense>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geometry/crystal.hpp"
#include "geometry/exact_polyhedron.hpp"
#include "geometry/lattice.hpp"

namespace cleave::geometry {

/// Plain definition of a specimen (what a scenario file's [specimen], [grain] and
/// [orientation] tables map onto). Lengths in metres.
struct SpecimenDef {
  Outline outline = Outline::box(12e-3, 12e-3, 4e-3);
  KeepRule keep = KeepRule::cell_inside;
  double r = 1e-3;       ///< lattice side length (table 2.1)
  double r_bar = 1e-3;   ///< grain side length, <= r; r - r_bar leaves the grain-boundary gap
  double t = 1e-3;       ///< lattice layer pitch (table 2.1)
  double t_bar = 1e-3;   ///< grain thickness, <= t (App. C uses 1.0 in a 1.3 pitch)
  double family_mix = 0.5;             ///< probability of the <11-20> (three-slab) family
  std::vector<int> angles{0, 60, 120}; ///< allowed angles, each 0, 60 or 120
  std::uint64_t seed = 1;
};

struct Grain {
  int id = 0;                  ///< 0-based, in lattice order
  LatticeSite site;            ///< its lattice point (centre)
  CrystalOrientation orientation;
};

/// Grains plus the one exact prism shape they all share (in the grain frame, centred).
struct Specimen {
  SpecimenDef def;
  std::vector<Grain> grains;
  ExactPolyhedron prism;  ///< side r_bar, thickness t_bar, centred at the origin
};

/// Builds the lattice, keeps the grains inside the outline and draws their orientations.
/// Throws std::invalid_argument for impossible definitions (non-positive sizes, r_bar > r,
/// t_bar > t, family_mix outside [0, 1], angles other than 0/60/120).
Specimen build_specimen(const SpecimenDef& def);

/// Where a fragment came from: its grain and the path of split choices, e.g. grain 17,
/// path {1, 0} is slab 1 of grain 17, then the part below a later plane: "17.1.0".
struct Lineage {
  int grain_id = 0;
  std::vector<int> path;

  /// "grain_0017" for an intact grain, "grain_0017.1.0" for a fragment.
  [[nodiscard]] std::string name() const;
  /// "17.1.0"
  [[nodiscard]] std::string path_string() const;
};

/// An intact grain or a fragment: an exact shape placed in the world by a translation
/// (its shape frame is the grain frame, centred on the lattice point).
struct Piece {
  Lineage lineage;
  std::shared_ptr<const ExactPolyhedron> shape;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< grain centre in the world
  CrystalOrientation orientation;                       ///< the grain's
};

/// Splits every grain into its cleavage slabs; cuts leaving a part below
/// `min_fragment_fraction` of the piece they cut are skipped. Grains sharing a shape and an
/// orientation share their slab shapes (each distinct orientation is cut once).
std::vector<Piece> split_into_slabs(const Specimen& specimen, double min_fragment_fraction = 0.0);

}  // namespace cleave::geometry
