#include "physics/transgranular/fracture_criterion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace cleave::physics {

BeamStresses beam_stresses(const FaceGeometry& g, std::span<const Eigen::Vector3d> polygon,
                           const FaceTractions& t) {
  BeamStresses s;
  /// Normal stress, eq. 3.24: sigma = N / A + M y / I at the most tensile fibre, i.e. the
  /// largest value of eq. 3.15's linear field over the section (a vertex).
  s.sigma = -std::numeric_limits<double>::infinity();
  for (const auto& v : polygon) {
    const Eigen::Vector2d xy = g.to_local(v);
    s.sigma = std::max(s.sigma, t.t_n(xy.x(), xy.y()));
  }
  if (polygon.empty()) s.sigma = t.t_o;
  /// Shear stress, eq. 3.24: tau = V Q / (I b) with V = t_s A.
  const double ts = t.t_s();
  s.shear_force = ts * g.area;
  if (!(ts > 0.0) || polygon.size() < 3) return s;
  const Eigen::Vector2d dir(t.t_x / ts, t.t_y / ts);  // shear direction, section frame
  const Eigen::Vector3d sd = dir.x() * g.x_axis + dir.y() * g.y_axis;
  const Eigen::Vector3d along = g.normal.cross(sd);  // the chord's direction
  const Eigen::Vector3d& c = g.origin;
  // I about the chord: integral of (r . s)^2 dA.
  s.inertia =
      dir.x() * dir.x() * g.i_xx + 2.0 * dir.x() * dir.y() * g.i_xy + dir.y() * dir.y() * g.i_yy;
  // Q: the part of the section beyond the chord (on the +s side), about the chord.
  const std::vector<Eigen::Vector3d> part = clip_polygon(polygon, CrackPlane{c, -sd});
  if (part.empty()) return s;
  const FaceGeometry pg = face_geometry(part, g.normal, g.x_axis);
  s.q = pg.area * (pg.origin - c).dot(sd);
  // b: the chord through the centroid (a convex section crosses it once on each side).
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = polygon[i];
    const Eigen::Vector3d& b = polygon[(i + 1) % n];
    const double da = (a - c).dot(sd), db = (b - c).dot(sd);
    auto take = [&](const Eigen::Vector3d& p) {
      const double u = (p - c).dot(along);
      lo = std::min(lo, u);
      hi = std::max(hi, u);
    };
    if (da == 0.0) take(a);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) take(a + (da / (da - db)) * (b - a));
  }
  s.chord = hi > lo ? hi - lo : 0.0;
  if (s.inertia > 0.0 && s.chord > 0.0) s.tau = s.shear_force * s.q / (s.inertia * s.chord);
  return s;
}

BeamStresses beam_stresses(const CrackPlaneLoad& crack) {
  return beam_stresses(crack.section, crack.polygon, crack.tractions);
}

FractureResult fracture_check(const FractureParams& p, const Eigen::Matrix3d& grain_stress,
                              double sigma, double tau) {
  FractureResult r;
  /// Hydrostatic gate, eq. 3.22: tr(sigma) / 3 >= sigma_f^hyd (tension positive).
  r.mean_stress = grain_stress.trace() / 3.0;
  r.gate = r.mean_stress >= p.sigma_f_hyd;
  /// Stress intensity factors, eq. 3.23.
  const double root = std::sqrt(M_PI * p.crack_length);
  r.k_i = sigma * root;
  r.k_ii = std::abs(tau) * root;
  /// Mixed-mode criterion, eq. 3.25 (only an opening K_I counts).
  const double ki = std::max(r.k_i, 0.0) / p.k_ic;
  const double kii = r.k_ii / (p.c * p.k_ic);
  r.criterion = ki * ki + kii * kii;
  r.fails = r.gate && r.criterion >= 1.0;
  return r;
}

FractureResult fracture_check(const FractureParams& p, const Eigen::Matrix3d& grain_stress,
                              const BeamStresses& s) {
  return fracture_check(p, grain_stress, s.sigma, s.tau);
}

}  // namespace cleave::physics
