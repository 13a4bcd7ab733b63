#pragma once
/// \file
/// A Voronoi polycrystal: a box cut into the Voronoi cells of seeded random points, each
/// cell an exact convex polyhedron. A cell is the box clipped, exactly, by the bisector
/// plane of its point and every other point close enough to matter (ExactPlane::bisector,
/// ExactPolyhedron::split): with no gap the cells tile the box and their exact volumes sum
/// to the box's exactly. No CGAL in this header or its source.

#include <array>
#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "geometry/exact_polyhedron.hpp"

namespace cleave::geometry {

/// Plain definition of a Voronoi specimen. Lengths in metres.
struct VoronoiDef {
  Eigen::Vector3d size{4e-3, 4e-3, 1e-3};  ///< the box [0,x]x[0,y]x[0,z]
  int cells = 8;                          ///< number of seed points (grains), >= 1
  /// Distance between the faces of neighbouring cells: each bisector is moved gap/2 towards
  /// each cell (faces on the box stay where they are). 0: the cells tile the box.
  double gap = 0.0;
  std::uint64_t seed = 1;  ///< seed of the points (SplitMix64, one stream per point)
  /// Periodic along each axis: the points' images across the box's faces count as
  /// neighbours, so the cells tile the box as a periodic cell (a cell near a periodic face
  /// reaches across it, matching its neighbours' images there); along the other axes the
  /// cells are cut by the box.
  std::array<bool, 3> periodic{false, false, false};
  /// false: the Voronoi cells of the points. true: Laguerre cells of the same points whose
  /// volumes follow a log-normal distribution of equivalent-sphere diameters with
  /// coefficient of variation `size_spread` (geometry/laguerre.hpp, lognormal_laguerre);
  /// a gap is cut after the fit (the volumes are the tiling cells'); periodic axes as above.
  bool lognormal = false;
  double size_spread = 0.35;  ///< standard deviation / mean of the equivalent diameters
};

/// The seed points: point i is uniform in the box, drawn from its own stream of `seed`.
std::vector<Eigen::Vector3d> voronoi_points(const VoronoiDef& def);

/// An axis-aligned box [lo, hi] (coordinates taken exactly) as an exact polyhedron.
ExactPolyhedron exact_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

/// The cells, in point order, in box coordinates (cell i holds point i). Throws
/// std::invalid_argument for a non-positive size, cells < 1, a negative gap, two equal
/// points, or a gap so wide that a cell vanishes.
std::vector<ExactPolyhedron> voronoi_cells(const VoronoiDef& def);

}  // namespace cleave::geometry
