#pragma once
/// \file
/// Laguerre (power-diagram) polycrystals: each point p_i carries a weight w_i (m^2) and owns
/// the points x of the domain where its power |x - p_i|^2 - w_i is the least. Cells are exact
/// convex polyhedra: the domain clipped by the power bisectors (ExactPlane::power_bisector),
/// every coefficient formed exactly from the doubles, so the cells tile the domain and their
/// exact volumes sum to the domain's exactly. Weights can be fitted so each cell takes a given
/// volume (e.g. a log-normal grain-size distribution). No CGAL in this header or its source.

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/polygon_mesh.hpp"
#include "geometry/voronoi.hpp"

namespace cleave::geometry {

/// The exact cells, in point order, of `points` with power weights `weights` (same length)
/// inside the convex `domain`. A point's cell need not contain the point. Throws
/// std::invalid_argument for unequal lengths, no points, two equal points, or a point whose
/// cell is empty (named with its index; such a point is an error, never dropped).
/// `gap` > 0 moves each power bisector gap/2 towards each of its two cells (faces on the
/// domain stay), as VoronoiDef::gap does: the cells are then apart by `gap` and no longer
/// tile the domain.
std::vector<ExactPolyhedron> laguerre_cells(const ExactPolyhedron& domain,
                                            const std::vector<Eigen::Vector3d>& points,
                                            const std::vector<double>& weights, double gap = 0.0);

/// The exact cells of the box [0, size], periodic along the marked axes: there the points'
/// images one box over are neighbours too, so the cells tile the box as a periodic cell (a
/// cell near a periodic face reaches across it and matches its neighbours' images there, as
/// voronoi_cells does). Errors and `gap` as laguerre_cells.
std::vector<ExactPolyhedron> laguerre_box_cells(const Eigen::Vector3d& size,
                                                const std::array<bool, 3>& periodic,
                                                const std::vector<Eigen::Vector3d>& points,
                                                const std::vector<double>& weights,
                                                double gap = 0.0);

/// Cell volumes and neighbours from a double-precision clipper (for fitting and checks, not
/// for invariants): the domain given as a closed convex polygon mesh (faces CCW from outside).
struct LaguerreApprox {
  std::vector<double> volumes;
  /// Per cell: (neighbour index, shared face area) for every power face it kept (laguerre_
  /// cells_approx has no periodic axes: the neighbour is a point index).
  std::vector<std::vector<std::pair<int, double>>> faces;
};
LaguerreApprox laguerre_cells_approx(const PolygonMesh& domain,
                                     const std::vector<Eigen::Vector3d>& points,
                                     const std::vector<double>& weights);

/// The result of fitting weights to target volumes.
struct LaguerreFit {
  std::vector<double> weights;      ///< m^2
  int iterations = 0;               ///< Newton steps taken
  double max_relative_error = 0.0;  ///< max |V_i - T_i| / T_i of the double cells at the end
};

/// Weights whose cells take the volumes `targets` (which must sum to the domain's volume),
/// by damped Newton steps on the weights (Kitagawa, Merigot & Thibert 2019: dV_i/dw_j =
/// -A_ij / (2 |p_i - p_j|) for neighbours, dV_i/dw_i = sum_j A_ij / (2 |p_i - p_j|)), the step
/// halved until every cell keeps a volume and the largest error shrinks; starts from
/// w_i = r_i^2 with r_i the equivalent-sphere radius of T_i. Stops at `tolerance` (largest
/// relative volume error) or after `max_iterations`.
LaguerreFit fit_laguerre_weights(const PolygonMesh& domain,
                                 const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<double>& targets, double tolerance = 1e-3,
                                 int max_iterations = 60);

/// `n` grain volumes whose equivalent-sphere diameters d = (6 V / pi)^(1/3) are log-normal with
/// coefficient of variation `spread` (standard deviation / mean of d; sigma of ln d =
/// sqrt(ln(1 + spread^2))), then scaled so they sum to `total` (the scale leaves sigma of
/// ln d as it is). Each draw comes from its own stream of `seed` (Box-Muller on two uniforms).
std::vector<double> lognormal_volumes(int n, double spread, std::uint64_t seed, double total);

/// The number of grains whose log-normal equivalent diameters (mean `mean_diameter`,
/// coefficient of variation `spread`) fill `volume` on average:
/// volume / E[pi d^3 / 6], E[d^3] = exp(3 mu + 9 sigma^2 / 2), rounded, at least 1.
int lognormal_grain_count(double volume, double mean_diameter, double spread);

/// A fitted Laguerre tessellation of a box [0, size] or another convex domain.
struct LaguerreTessellation {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> targets;  ///< the volumes asked for (summing to the domain's)
  LaguerreFit fit;
  std::vector<ExactPolyhedron> cells;  ///< exact, in point order
};

/// Cells of the box [0, size] at `points` whose volumes match `targets` (scaled first so they
/// sum to the box's volume): weights fitted in doubles, then the exact cells built once.
/// Periodic along the marked axes as laguerre_box_cells. A `gap` is cut after the fit: the
/// cells are the fitted ones, each shrunk by gap/2 on every face it shares with another.
LaguerreTessellation fitted_laguerre(const Eigen::Vector3d& size,
                                     const std::vector<Eigen::Vector3d>& points,
                                     std::vector<double> targets,
                                     const std::array<bool, 3>& periodic = {false, false, false},
                                     double gap = 0.0);

/// The same in the convex `domain` (no periodic axes): targets scaled to its volume (in
/// doubles), the exact cells summing to its exact volume when `gap` is 0.
LaguerreTessellation fitted_laguerre(const ExactPolyhedron& domain,
                                     const std::vector<Eigen::Vector3d>& points,
                                     std::vector<double> targets, double gap = 0.0);

/// `cells` points uniform in the box (voronoi_points with `seed`) with log-normal target
/// volumes (lognormal_volumes with `spread` and `seed`), fitted as above.
LaguerreTessellation lognormal_laguerre(const Eigen::Vector3d& size, int cells, double spread,
                                        std::uint64_t seed,
                                        const std::array<bool, 3>& periodic = {false, false,
                                                                               false},
                                        double gap = 0.0);

/// The same for a Voronoi definition's domain (a box with its periodic axes, or a disc):
/// its `cells`, `seed`, `size_spread` and `gap`.
LaguerreTessellation lognormal_laguerre(const VoronoiDef& def);

}  // namespace cleave::geometry
