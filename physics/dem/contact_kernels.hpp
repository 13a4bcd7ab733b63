#pragma once
/// \file
/// Contact kernels between the primitives of dilated polyhedra (sec. 2.3.1 and App. B of
/// the dissertation, seed 000): vertices are spheres, edges are cylinders (finite segments
/// with hemispherical ends left to the vertex spheres), faces are flat polygons thickened
/// by the dilation radius. Each kernel returns the contact point, the unit normal and the
/// penetration = (sum of radii) - distance, App. B.
///
/// Conventions shared by every kernel:
/// - The normal points from the first primitive (A) towards the second (B): a repulsive
///   force on B is +F n, on A it is -F n.
/// - The contact point is the midpoint of the two surface points along the normal (the
///   middle of the overlap region).
/// - A result is returned when penetration > -margin (margin >= 0 lets bonded contacts see
///   pairs that are close but not touching); otherwise std::nullopt.
/// - Each kernel restricts itself along its feature: a facet answers only when the sphere
///   centre projects strictly inside the polygon; a cylinder only when the closest points
///   lie strictly inside the segment(s); the ends belong to the vertex spheres. It does
///   not restrict the directions around an edge or a corner: choosing which feature pair
///   holds a touch (so nothing is counted twice) is the caller's job (narrow_phase.cpp).
/// - `outward` normals must be unit vectors. Degenerate normals: a sphere centre on a
///   cylinder axis gets some unit direction perpendicular to the axis; crossing axes get
///   +-(d1 x d2); segments within about 1e-6 rad of parallel are treated as parallel.

#include <Eigen/Dense>
#include <optional>
#include <span>

namespace cleave::physics {

struct PrimitiveContact {
  Eigen::Vector3d point;   ///< contact point (world)
  Eigen::Vector3d normal;  ///< unit, from A towards B
  double penetration = 0;  ///< sum of radii minus distance; > 0 when overlapping
};

/// Sphere A (centre ca, radius ra) against sphere B (cb, rb). Coincident centres: normal +z.
std::optional<PrimitiveContact> sphere_sphere(const Eigen::Vector3d& ca, double ra,
                                              const Eigen::Vector3d& cb, double rb,
                                              double margin = 0.0) noexcept;

/// Sphere A (centre c, radius rs) against the facet B: a planar convex polygon `polygon`
/// (CCW seen from outside, i.e. from the side `outward` points to) thickened by `rf`.
/// One-sided: only a centre on the outer side (signed distance d >= 0 along `outward`) that
/// projects strictly inside the polygon counts. Distance d; penetration rs + rf - d; the
/// normal (A towards B) is -outward.
std::optional<PrimitiveContact> sphere_facet(const Eigen::Vector3d& c, double rs,
                                             std::span<const Eigen::Vector3d> polygon,
                                             const Eigen::Vector3d& outward, double rf,
                                             double margin = 0.0) noexcept;

/// Sphere A (c, rs) against the cylinder B around segment p-q with radius rc. Only when the
/// closest point of the segment to c is strictly between p and q.
std::optional<PrimitiveContact> sphere_cylinder(const Eigen::Vector3d& c, double rs,
                                                const Eigen::Vector3d& p,
                                                const Eigen::Vector3d& q, double rc,
                                                double margin = 0.0) noexcept;

/// Cylinder A (segment p1-q1, radius r1) against cylinder B (p2-q2, r2): closest approach of
/// the two segments, only when both closest points are strictly inside their segments.
/// Parallel (or nearly parallel) segments that overlap along their length give one contact
/// at the middle of the overlapping stretch.
std::optional<PrimitiveContact> cylinder_cylinder(const Eigen::Vector3d& p1,
                                                  const Eigen::Vector3d& q1, double r1,
                                                  const Eigen::Vector3d& p2,
                                                  const Eigen::Vector3d& q2, double r2,
                                                  double margin = 0.0) noexcept;

}  // namespace cleave::physics
