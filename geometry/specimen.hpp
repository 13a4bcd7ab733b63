#pragma once
/// \file
/// A specimen: grains on the honeycomb lattice inside an outline, each with a
/// crystallographic orientation; and the fragments they are cut into.

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geometry/crystal.hpp"
#include "geometry/crystal_system.hpp"
#include "geometry/exact_polyhedron.hpp"
#include "geometry/lattice.hpp"
#include "geometry/voronoi.hpp"

namespace cleave::geometry {

/// Where a specimen's grains come from.
enum class SpecimenKind {
  lattice,  ///< hexagonal prisms on the honeycomb lattice inside `outline` (the seed's model)
  voronoi,  ///< the Voronoi cells of random points in a box or a disc (`voronoi`)
  meshes,   ///< convex shapes given one by one (`custom_grains`, e.g. from mesh files)
};

/// How the grains' 3D crystal orientations are drawn ([orientation] law, with [crystal]).
enum class OrientationLaw {
  honeycomb,  ///< the seed's: c along z, turned by the drawn angle (0/60/120 degrees) about it
  uniform,    ///< uniform over SO(3)
  fibre,      ///< a crystal direction along a specimen axis, the turn about it uniform
  preferred,  ///< one orientation with a spread
  given,      ///< one per grain, read from a file
  imported,   ///< the specimen file's own (a Neper .tess, a grain file): SpecimenDef::orientations
};

/// The orientation law and its parameters, as a scenario gives them (degrees).
struct OrientationDef {
  OrientationLaw law = OrientationLaw::honeycomb;
  std::array<double, 3> euler_deg{0.0, 0.0, 0.0};  ///< preferred: Bunge (phi1, Phi, phi2)
  double spread_deg = 0.0;                         ///< fibre, preferred
  Eigen::Vector3d crystal_direction = Eigen::Vector3d::UnitZ();  ///< fibre: crystal frame
  Eigen::Vector3d specimen_axis = Eigen::Vector3d::UnitZ();      ///< fibre: specimen frame
  std::vector<Eigen::Quaterniond> given;                       ///< given: in grain order
  std::string file;                                            ///< given: read from (absolute)
};

/// One grain given by its shape (SpecimenKind::meshes).
struct CustomGrainDef {
  std::string name;       ///< where it came from, for tables and messages (e.g. "cube.obj")
  ExactPolyhedron shape;  ///< closed, convex, in specimen coordinates (metres)
};

/// Plain definition of a specimen (what a scenario file's [specimen], [grain] and
/// [orientation] tables map onto). Lengths in metres.
struct SpecimenDef {
  SpecimenKind kind = SpecimenKind::lattice;
  Outline outline = Outline::box(12e-3, 12e-3, 4e-3);
  KeepRule keep = KeepRule::cell_inside;
  double r = 1e-3;       ///< lattice side length (table 2.1)
  double r_bar = 1e-3;   ///< grain side length, <= r; r - r_bar leaves the grain-boundary gap
  double t = 1e-3;       ///< lattice layer pitch (table 2.1)
  double t_bar = 1e-3;   ///< grain thickness, <= t (App. C uses 1.0 in a 1.3 pitch)
  double family_mix = 0.5;             ///< probability of the <11-20> (three-slab) family
  std::vector<int> angles{0, 60, 120}; ///< allowed angles, each 0, 60 or 120
  std::uint64_t seed = 1;  ///< of the orientations
  /// [crystal]: every grain a 3D crystal with these cleavage families; disabled: the
  /// seed's honeycomb crystal (family_mix and angles).
  CrystalDef crystal;
  OrientationDef orientation;  ///< with `crystal`: how its orientations are drawn
  VoronoiDef voronoi;      ///< SpecimenKind::voronoi (its size is also `outline`'s)
  std::vector<CustomGrainDef> custom_grains;  ///< SpecimenKind::meshes, in grain id order
  /// Per grain (in grain id order), its crystal orientation as given by an imported
  /// microstructure: the rotation from crystal to specimen coordinates. Empty: none given.
  std::vector<Eigen::Quaterniond> orientations;
  /// [[phase]] tables: each phase's volume fraction (summing to 1), in table order; each
  /// grain gets one (assign_phases, drawn from `seed`). Empty: one phase, every grain's 0.
  std::vector<double> phase_fractions;
};

struct Grain {
  int id = 0;                  ///< 0-based, in lattice order (or cell / file order)
  /// Its lattice point (centre). Grains not on the lattice have their reference point here
  /// (Voronoi: the cell's point; meshes: the rounded centroid), plane 'A', row 1, i = j = 0
  /// and k = 1 when the grain touches the specimen's lowest level (k = 2 otherwise).
  LatticeSite site;
  CrystalOrientation orientation;
  /// The grain's crystal, crystal -> specimen coordinates. The honeycomb crystal: the turn
  /// by orientation.angle_deg about z.
  Eigen::Quaterniond crystal = Eigen::Quaterniond::Identity();
  int shape = 0;  ///< index into Specimen::shapes
  int phase = 0;  ///< index into SpecimenDef::phase_fractions (0 with one phase)
};

/// Grains plus their exact shapes (in grain frames: a grain is its shape moved by its
/// site's centre).
struct Specimen {
  SpecimenDef def;
  std::vector<Grain> grains;
  /// Lattice specimens: the one prism all grains share (side r_bar, thickness t_bar,
  /// centred at the origin). Other specimens: shapes[0].
  ExactPolyhedron prism;
  /// Every distinct grain shape; shapes[0] is `prism` for lattice specimens.
  std::vector<ExactPolyhedron> shapes;

  [[nodiscard]] const ExactPolyhedron& shape_of(const Grain& g) const {
    return shapes.at(static_cast<std::size_t>(g.shape));
  }
};

/// Builds the specimen: for SpecimenKind::lattice the lattice sites whose cell fits the
/// outline; for voronoi the cells of `def.voronoi` (each moved so its point is the grain
/// frame's origin, exactly; log-normal Laguerre cells so the mean of their vertices is); for
/// meshes each custom grain moved so its rounded centroid is the origin (exactly). Orientations are
/// drawn per grain id in every case. Throws std::invalid_argument for impossible definitions
/// (non-positive sizes, r_bar > r, t_bar > t, family_mix outside [0, 1], angles other than
/// 0/60/120, no custom grains). With phase_fractions, each grain's phase (assign_phases).
Specimen build_specimen(const SpecimenDef& def);

/// The exact cleavage planes of grain `g` (grain coordinates): the honeycomb crystal's
/// (ExactPolyhedron::cleavage_planes, family 0), or with a 3D crystal
/// crystal_cleavage_planes of its shape at its orientation.
CleavagePlanes grain_cleavage_planes(const Specimen& specimen, const Grain& g);

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

/// Splits every grain into its cleavage slabs (grains of a 3D crystal stay whole: they
/// split on their planes under load, [fracture]); cuts leaving a part below
/// `min_fragment_fraction` of the piece they cut are skipped. Grains sharing a shape and an
/// orientation share their slab shapes (each distinct orientation is cut once).
std::vector<Piece> split_into_slabs(const Specimen& specimen, double min_fragment_fraction = 0.0);

}  // namespace cleave::geometry
