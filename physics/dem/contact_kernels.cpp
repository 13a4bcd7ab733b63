#include "physics/dem/contact_kernels.hpp"

#include <algorithm>
#include <cmath>

namespace cleave::physics {

namespace {

using Eigen::Vector3d;

/// Segments with |d1 x d2|^2 <= kParallelSin2 |d1|^2 |d2|^2, i.e. an angle below ~1e-6 rad,
/// are treated as parallel. Above it the line-line solution is well conditioned (its
/// parameters lose about 1e-16 / sin^2 of relative accuracy); below it the distance varies
/// by at most 1e-6 of the overlap length, so the middle of the overlap is as good as the
/// (ill-defined) exact closest pair.
constexpr double kParallelSin2 = 1e-12;

/// The contact between core points `core_a` (on A's skeleton: centre, axis or polygon) and
/// `core_b`, dilated by `ra` and `rb`, with unit `normal` from A to B: the point is the
/// midpoint of the surface points core_a + ra n and core_b - rb n.
inline PrimitiveContact contact_between(const Vector3d& core_a, double ra, const Vector3d& core_b,
                                        double rb, const Vector3d& normal, double penetration) {
  return PrimitiveContact{0.5 * (core_a + core_b) + (0.5 * (ra - rb)) * normal, normal,
                          penetration};
}

/// The contact between core points `core_a` and `core_b` (a centre, or the closest points
/// of two axes) dilated by `ra` and `rb`, when their distance is within reach: rejected on
/// the squared distance before the square root; coincident cores take `fallback` as their
/// normal.
std::optional<PrimitiveContact> contact_of_cores(const Vector3d& core_a, double ra,
                                                 const Vector3d& core_b, double rb,
                                                 double margin, const Vector3d& fallback) {
  const double reach = ra + rb + margin;
  if (!(reach > 0.0)) return std::nullopt;
  const Vector3d delta = core_b - core_a;
  const double dist2 = delta.squaredNorm();
  if (!(dist2 < reach * reach)) return std::nullopt;
  const double dist = std::sqrt(dist2);
  const double penetration = ra + rb - dist;
  if (!(penetration > -margin)) return std::nullopt;
  const Vector3d normal = dist > 0.0 ? Vector3d(delta / dist) : fallback;
  return contact_between(core_a, ra, core_b, rb, normal, penetration);
}

/// Cylinder-cylinder for (nearly) parallel segments p1 + s d1, p2 + t d2 (|d1|^2 = a1,
/// |d2|^2 = a2, both > 0). Both segments are projected on their common direction; where
/// the projections overlap over a positive length, the contact is between the points of
/// each segment that project onto the middle of that stretch. Otherwise the closest points
/// are segment ends, which the vertex spheres own.
std::optional<PrimitiveContact> parallel_cylinders(const Vector3d& p1, const Vector3d& d1,
                                                   double a1, double r1, const Vector3d& p2,
                                                   const Vector3d& d2, double a2, double r2,
                                                   double margin) {
  // Sum of the unit directions, d2's flipped to agree with d1's: symmetric in A and B, and
  // only ratios of projections on it are used, so it need not be normalised.
  const double sign = d1.dot(d2) >= 0.0 ? 1.0 : -1.0;
  const Vector3d axis = d1 / std::sqrt(a1) + (sign / std::sqrt(a2)) * d2;
  const double end1 = axis.dot(d1);  // segment 1 projects on [0, end1], end1 > 0
  const double start2 = axis.dot(p2 - p1);
  const double end2 = start2 + axis.dot(d2);
  const double lo = std::max(0.0, std::min(start2, end2));
  const double hi = std::min(end1, std::max(start2, end2));
  if (!(hi > lo)) return std::nullopt;
  const double mid = 0.5 * (lo + hi);
  const Vector3d core_a = p1 + (mid / end1) * d1;
  const Vector3d core_b = p2 + ((mid - start2) / (end2 - start2)) * d2;
  // Collinear overlapping axes: no preferred side, any direction across the axis will do.
  return contact_of_cores(core_a, r1, core_b, r2, margin, axis.unitOrthogonal());
}

}  // namespace

/// Sphere-sphere, App. B.2 / sec. 2.3.1: penetration = (R_S1 + R_S2) - D, D the distance
/// between the centres. Rejected on the squared distance before any square root.
std::optional<PrimitiveContact> sphere_sphere(const Eigen::Vector3d& ca, double ra,
                                              const Eigen::Vector3d& cb, double rb, double margin) noexcept {
  return contact_of_cores(ca, ra, cb, rb, margin, Vector3d::UnitZ());
}

/// Sphere-facet, App. B.2 / sec. 2.3.1: penetration = R_S - D, D the distance from the
/// centre to the facet's plane. Here the facet is the core polygon thickened by rf, so with
/// d the distance to the core plane, D = d - rf and penetration = rs + rf - d.
/// `outward` must be a unit vector. Cheap rejections first (side, then distance); the
/// point-in-polygon test runs only for spheres close enough to touch. A polygon with
/// repeated consecutive vertices or fewer than three has no strict inside and never answers.
std::optional<PrimitiveContact> sphere_facet(const Eigen::Vector3d& c, double rs,
                                             std::span<const Eigen::Vector3d> polygon,
                                             const Eigen::Vector3d& outward, double rf,
                                             double margin) noexcept {
  const std::size_t n = polygon.size();
  if (n < 3) return std::nullopt;
  const double d = outward.dot(c - polygon[0]);
  if (!(d >= 0.0)) return std::nullopt;
  const double penetration = rs + rf - d;
  if (!(penetration > -margin)) return std::nullopt;
  // Strictly left of every edge, seen from outside: (b - a) x (c - a) . outward > 0. The
  // component of c - a along `outward` drops out of the triple product.
  for (std::size_t i = 0; i < n; ++i) {
    const Vector3d& a = polygon[i];
    const Vector3d& b = polygon[i + 1 == n ? 0 : i + 1];
    if (!((b - a).cross(c - a).dot(outward) > 0.0)) return std::nullopt;
  }
  const Vector3d foot = c - d * outward;
  return contact_between(c, rs, foot, rf, -outward, penetration);
}

/// Sphere-cylinder, App. B.2 / sec. 2.3.1: penetration = (R_S + R_C) - D, D the distance
/// from the centre to the cylinder's axis. The foot parameter is checked before the
/// division, the squared distance before the square root. A centre on the axis gets some
/// unit normal across the axis.
std::optional<PrimitiveContact> sphere_cylinder(const Eigen::Vector3d& c, double rs,
                                                const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                                double rc, double margin) noexcept {
  const Vector3d axis = q - p;
  const double len2 = axis.squaredNorm();
  const double along = axis.dot(c - p);                     // foot parameter times len2
  if (!(along > 0.0 && along < len2)) return std::nullopt;  // also rejects len2 == 0
  const Vector3d foot = p + (along / len2) * axis;
  return contact_of_cores(c, rs, foot, rc, margin, axis.unitOrthogonal());
}

/// Cylinder-cylinder, App. B.2 / sec. 2.3.1: penetration = (R_C1 + R_C2) - D, D the closest
/// approach of the two axes.
///
/// Closest points of the lines p1 + s d1 and p2 + t d2 (standard vector geometry): with
/// w = p2 - p1 and n = d1 x d2, the connecting vector is perpendicular to both directions,
/// so it is (w.n / |n|^2) n, and crossing p1 + s d1 + (w.n/|n|^2) n = p2 + t d2 with d2 or
/// d1 and dotting with n gives s = (w x d2).n / |n|^2, t = (w x d1).n / |n|^2. For
/// non-parallel lines the distance is strictly convex in (s, t), so closest points strictly
/// inside both segments are exactly a line-line minimiser inside the open unit square; no
/// clamping is needed. The line distance |w.n| / |n| never exceeds the segment distance and
/// rejects far pairs before any division. Cross products rather than Gram determinants
/// (|d1|^2 |d2|^2 - (d1.d2)^2) avoid cancellation at small angles.
std::optional<PrimitiveContact> cylinder_cylinder(const Eigen::Vector3d& p1,
                                                  const Eigen::Vector3d& q1, double r1,
                                                  const Eigen::Vector3d& p2,
                                                  const Eigen::Vector3d& q2, double r2,
                                                  double margin) noexcept {
  const Vector3d d1 = q1 - p1;
  const Vector3d d2 = q2 - p2;
  const double a1 = d1.squaredNorm();
  const double a2 = d2.squaredNorm();
  if (!(a1 > 0.0 && a2 > 0.0)) return std::nullopt;
  const double reach = r1 + r2 + margin;
  if (!(reach > 0.0)) return std::nullopt;
  const Vector3d n = d1.cross(d2);
  const double nn = n.squaredNorm();
  if (!(nn > kParallelSin2 * a1 * a2)) {
    return parallel_cylinders(p1, d1, a1, r1, p2, d2, a2, r2, margin);
  }
  const Vector3d w = p2 - p1;
  const double wn = w.dot(n);
  if (!(wn * wn < reach * reach * nn)) return std::nullopt;
  const double inv_nn = 1.0 / nn;
  const double s = w.cross(d2).dot(n) * inv_nn;
  const double t = w.cross(d1).dot(n) * inv_nn;
  if (!(s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0)) return std::nullopt;
  const double inv_len = 1.0 / std::sqrt(nn);
  const double dist = std::abs(wn) * inv_len;
  const double penetration = r1 + r2 - dist;
  if (!(penetration > -margin)) return std::nullopt;
  // From A to B along the common perpendicular; for crossing axes (wn = 0), along d1 x d2,
  // which still flips when A and B are swapped.
  const Vector3d normal = (wn < 0.0 ? -inv_len : inv_len) * n;
  return contact_between(p1 + s * d1, r1, p2 + t * d2, r2, normal, penetration);
}

}  // namespace cleave::physics
