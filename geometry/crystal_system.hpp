#pragma once
/// \file
/// A grain's crystal in 3D: its lattice (crystal system and axis ratios), the cleavage plane
/// families it breaks along, and the exact planes those put through a grain of any shape
/// at any orientation. The seed's honeycomb crystal (crystal.hpp: c along the prism axis,
/// vertical planes at 0/60/120 degrees) is the 2.5D special case the dissertation uses;
/// sec. 4.3 names "more orientations" as the next step.
///
/// Frames: the crystal's Cartesian frame has x along the a axis and z along c (hexagonal and
/// trigonal: a1 along x, a2 at 120 degrees from it in the basal plane). An orientation is a
/// unit quaternion q taking crystal coordinates to specimen coordinates, v_s = q v_c
/// (docs/ORIENTATIONS.md).
///
/// Indices: Miller (hkl) for cubic and orthorhombic crystals, Miller-Bravais (hkil) with
/// i = -(h + k) for hexagonal and trigonal ones, both as written in crystallography:
/// "{10-12}" is h = 1, k = 0, i = -1, l = 2.

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/orientation.hpp"

namespace cleave::geometry {

/// The crystal systems cleave knows, each with the proper rotations of its holohedry's
/// Laue class: cubic O (24), hexagonal D6 (12), trigonal D3 (6, the 2-fold axes along the
/// a axes, as in corundum's R-3c), orthorhombic D2 (4).
enum class CrystalSystem : std::uint8_t { cubic, hexagonal, trigonal, orthorhombic };

std::string to_string(CrystalSystem system);
/// "cubic" | "hexagonal" | "trigonal" | "orthorhombic"; throws std::invalid_argument.
CrystalSystem parse_crystal_system(const std::string& text);
/// The system's proper point group (orientation.hpp), whose rotations make a family's planes.
PointGroup point_group(CrystalSystem system);

/// A crystal lattice: its system and axis ratios (a = 1). Cubic: b = c = 1; hexagonal and
/// trigonal: b = 1, c/a free; orthorhombic: both free.
struct CrystalLattice {
  CrystalSystem system = CrystalSystem::cubic;
  double b_over_a = 1.0;
  double c_over_a = 1.0;
  friend bool operator==(const CrystalLattice&, const CrystalLattice&) = default;
};

/// A plane family's indices as written, e.g. "{0001}", "{10-12}", "{111}".
struct MillerFamily {
  int h = 0, k = 0, l = 0;  ///< Miller indices (Miller-Bravais: i = -(h + k) is implied)
  std::string text;         ///< as given, braces included
  friend bool operator==(const MillerFamily&, const MillerFamily&) = default;
};

/// Parses "{hkl}" (cubic, orthorhombic) or "{hkil}" (hexagonal, trigonal): single digits,
/// each optionally preceded by '-'; checks i = -(h + k) and that not all are zero. Throws
/// std::invalid_argument saying what is wrong.
MillerFamily parse_miller_family(const std::string& text, CrystalSystem system);

/// The unit normal of plane (hkl) in the crystal frame: the reciprocal lattice vector
/// h a* + k b* + l c*, normalised.
Eigen::Vector3d plane_normal(const CrystalLattice& lattice, const MillerFamily& family);

/// The family's distinct planes: the normal's images under the system's rotations, one per
/// pair +-n, in the order first met (crystal frame, unit). E.g. cubic {100}: 3, {110}: 6,
/// {111}: 4; hexagonal {0001}: 1, {10-10}: 3, {11-20}: 3; trigonal {10-12}: 3.
std::vector<Eigen::Vector3d> family_normals(const CrystalLattice& lattice,
                                            const MillerFamily& family);

/// A family a grain cleaves on: its planes and their resistance.
struct CleavageFamilyDef {
  MillerFamily family;
  /// The family's cleavage resistance relative to the criterion's ([fracture] k_ic or
  /// sigma_f): its K_Ic (or strength) is this times the criterion's.
  double resistance = 1.0;
  /// Parallel planes per variant, at i / (n + 1) of the grain's extent along the normal
  /// (1: one plane halving the extent).
  int planes_per_variant = 1;
  friend bool operator==(const CleavageFamilyDef&, const CleavageFamilyDef&) = default;
};

/// The crystal every grain of a specimen has ([crystal] in a scenario); absent: the seed's
/// honeycomb crystal (crystal.hpp).
struct CrystalDef {
  bool enabled = false;
  CrystalLattice lattice;
  std::vector<CleavageFamilyDef> families;
  friend bool operator==(const CrystalDef&, const CrystalDef&) = default;
};

/// A grain's cleavage planes (grain coordinates) and, for each, the index of its family in
/// CrystalDef::families (0 for the honeycomb crystal).
struct CleavagePlanes {
  std::vector<ExactPlane> planes;
  std::vector<int> family;
};

/// The family (index into crystal.families) of each of a grain's cleavage planes, in the
/// order crystal_cleavage_planes makes them: the same for every grain of the crystal.
std::vector<int> plane_families(const CrystalDef& crystal);

/// The exact cleavage planes of `shape` (grain coordinates, specimen axes) whose crystal is
/// `crystal` turned by `orientation` (crystal -> specimen): per family, per variant normal
/// n = q n_c, planes_per_variant planes across the shape's extent along n. Each plane's
/// normal is n's double components taken exactly (so it agrees with q n_c to round-off),
/// its offset the extent's fraction taken exactly. Family by family, variant by variant.
CleavagePlanes crystal_cleavage_planes(const ExactPolyhedron& shape, const CrystalDef& crystal,
                                       const Eigen::Quaterniond& orientation);

}  // namespace cleave::geometry
