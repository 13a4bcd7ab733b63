#pragma once
/// \file
/// A Voronoi polycrystal: a box (or a disc) cut into the Voronoi cells of seeded random points,
/// each cell an exact convex polyhedron. A cell is the domain clipped, exactly, by the bisector
/// plane of its point and every other point close enough to matter (ExactPlane::bisector,
/// ExactPolyhedron::split): with no gap the cells tile the domain and their exact volumes sum
/// to the domain's exactly. No CGAL in this header or its source.

#include <array>
#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "geometry/exact_polyhedron.hpp"

namespace cleave::geometry {

/// The region a Voronoi specimen's cells tile.
enum class VoronoiDomain {
  box,   ///< [0,x]x[0,y]x[0,z] of `size`
  disc,  ///< a cylinder along z in that box (disc_prism): diameter size.x == size.y
};

/// Plain definition of a Voronoi specimen. Lengths in metres.
struct VoronoiDef {
  Eigen::Vector3d size{4e-3, 4e-3, 1e-3};  ///< the box [0,x]x[0,y]x[0,z] (a disc's bounding box)
  VoronoiDomain domain = VoronoiDomain::box;
  int sides = 64;  ///< disc: the sides of its regular polygon (a multiple of 4, >= 8)
  int cells = 8;                          ///< number of seed points (grains), >= 1
  /// Distance between the faces of neighbouring cells: each bisector is moved gap/2 towards
  /// each cell (faces on the box stay where they are). 0: the cells tile the box.
  double gap = 0.0;
  std::uint64_t seed = 1;  ///< seed of the points (SplitMix64, one stream per point)
  /// Periodic along each axis: the points' images across the box's faces count as
  /// neighbours, so the cells tile the box as a periodic cell (a cell near a periodic face
  /// reaches across it, matching its neighbours' images there); along the other axes the
  /// cells are cut by the box. A box only: a disc has no periodic axes.
  std::array<bool, 3> periodic{false, false, false};
  /// false: the Voronoi cells of the points. true: Laguerre cells of the same points whose
  /// volumes follow a log-normal distribution of equivalent-sphere diameters with
  /// coefficient of variation `size_spread` (geometry/laguerre.hpp, lognormal_laguerre);
  /// a gap is cut after the fit (the volumes are the tiling cells'); periodic axes as above.
  bool lognormal = false;
  double size_spread = 0.35;  ///< standard deviation / mean of the equivalent diameters
};

/// The seed points: point i is uniform in the domain, drawn from its own stream of `seed`
/// (in a disc: uniform in its bounding box, drawn again until it falls inside the polygon).
std::vector<Eigen::Vector3d> voronoi_points(const VoronoiDef& def);

/// An axis-aligned box [lo, hi] (coordinates taken exactly) as an exact polyhedron.
ExactPolyhedron exact_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

/// The corners, counter-clockwise seen from +z, of the regular `sides`-gon circumscribed
/// about the circle of diameter `diameter` centred at (diameter/2, diameter/2): its sides
/// touch the circle, one side lies on each of the lines x = 0, x = diameter, y = 0 and
/// y = diameter (where platens along x or y meet it), and its area is
/// N r^2 tan(pi/N) = pi r^2 (tan(pi/N) / (pi/N)) for N sides and r = diameter/2 (0.08 % more
/// than the circle's for N = 64). The corners are doubles, mirrored so the polygon is
/// symmetric about both axes and the diagonal. Throws std::invalid_argument for a
/// non-positive diameter or sides not a multiple of 4 of at least 8.
std::vector<Eigen::Vector2d> disc_polygon(double diameter, int sides);

/// The prism over disc_polygon from z = 0 to z = thickness, its corners taken exactly: an
/// exact convex polyhedron of sides + 2 faces.
ExactPolyhedron exact_disc_prism(double diameter, double thickness, int sides);

/// The domain of `def`: exact_box(0, size) or exact_disc_prism(size.x, size.z, sides).
ExactPolyhedron voronoi_domain(const VoronoiDef& def);

/// The cells, in point order, in domain coordinates (cell i holds point i). Throws
/// std::invalid_argument for a non-positive size, cells < 1, a negative gap, two equal
/// points, a gap so wide that a cell vanishes, or a disc whose size.x and size.y differ,
/// whose sides are not a multiple of 4 of at least 8, or that has periodic axes.
std::vector<ExactPolyhedron> voronoi_cells(const VoronoiDef& def);

}  // namespace cleave::geometry
