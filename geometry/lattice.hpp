#pragma once
/// \file
/// The hexagonal prismatic honeycomb lattice of sec. 2.2.2, table 2.1 and App. A
/// (seed 000), and the outlines that cut specimens out of it.
///
/// Lattice points (table 2.1), with h = 3r/2:
///   plane A, row 1: ( sqrt3 i r,            r + (j-1) h, t/2 + (k-1) t )
///   plane A, row 2: ( sqrt3/2 (2i-1) r,     r + (j-1) h, t/2 + (k-1) t )
///   plane B, row 1: ( sqrt3 i r,            r + j h,     ... )
///   plane B, row 2: ( sqrt3/2 (2i-1) r,     r + j h,     ... )
/// Rows alternate 1, 2, 1, ... upward within a plane; planes alternate A, B, A, ... upward.
///
/// Two readings of the printed table are fixed here (see docs/ARCHITECTURE.md):
/// - Layer k sits at z = t/2 + (k-1) t for every k; odd layers are plane A, even layers
///   plane B. (Read literally, B at t/2 + k t would coincide with the next A layer.)
/// - The printed index ranges (and those of the App. A MATLAB code) disagree with each
///   other and put grains outside the box. cleave instead keeps every lattice point of the
///   infinite lattice whose *cell* (hexagon of side r, thickness t around the point) lies
///   inside the outline. Plane B rows then start at j = 0 (y = r), like plane A.
/// With r = t = 1 a 12 x 12 x 4 box holds 6 grains per row, 7 rows per layer and 4 layers:
/// the 168 grains of the drop test (sec. 2.5.1).

#include <Eigen/Dense>
#include <vector>

namespace cleave::geometry {

struct LatticeSite {
  Eigen::Vector3d centre;  ///< lattice point (grain centre), SI
  char plane = 'A';        ///< 'A' or 'B'
  int row = 1;             ///< row type 1 or 2 of table 2.1
  int i = 0, j = 0, k = 0; ///< table indices (j counted as in the table for each plane)
};

/// Which lattice points an outline keeps.
enum class KeepRule {
  cell_inside,    ///< the whole cell (side r, thickness t) lies inside the outline
  centre_inside,  ///< the lattice point lies inside the outline
};

/// A region of space a specimen is cut out of. Implementations answer whether a point is
/// inside; convex outlines keep a cell when all its 12 corners are inside.
struct Outline {
  enum class Kind { box, disc, beam } kind = Kind::box;
  Eigen::Vector3d size{0, 0, 0};  ///< bounding box [0,x]x[0,y]x[0,z]
  // disc: axis along z through (size.x/2, size.y/2), diameter size.x (== size.y)
  // beam: the box with an optional centred notch cut up from y = 0
  double notch_width = 0.0;
  double notch_depth = 0.0;

  static Outline box(double a, double b, double c);
  static Outline disc(double diameter, double thickness);
  static Outline beam(double length, double height, double thickness, double notch_width = 0.0,
                      double notch_depth = 0.0);

  [[nodiscard]] bool contains(const Eigen::Vector3d& p, double tol) const;
  /// True when the hexagonal cell (side r, thickness t, centred at c) lies inside.
  [[nodiscard]] bool contains_cell(const Eigen::Vector3d& c, double r, double t) const;
};

/// All lattice points of table 2.1 (side r, layer pitch t) kept by `outline` under `rule`,
/// ordered by layer k, then row, then i. Throws std::invalid_argument for r <= 0 or t <= 0.
std::vector<LatticeSite> honeycomb_sites(double r, double t, const Outline& outline,
                                         KeepRule rule = KeepRule::cell_inside);

/// Corner n (0..5) of a regular hexagon of side `side` centred at the origin in the xy plane,
/// at angle 90 - 60 n degrees (corner 0 on +y), as in App. A (GrainVertices.m).
/// Corners are built from one rounded value s = side*sqrt(3)/2 so that the hexagon is
/// exactly symmetric in binary floating point.
Eigen::Vector2d hexagon_corner(double side, int n);

}  // namespace cleave::geometry
