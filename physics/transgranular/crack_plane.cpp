#include "physics/transgranular/crack_plane.hpp"

#include <cmath>

namespace cleave::physics {

namespace {

/// Twice the signed area of a polygon about unit normal n.
double twice_area(std::span<const Eigen::Vector3d> p, const Eigen::Vector3d& n) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (std::size_t i = 1; i + 1 < p.size(); ++i) s += (p[i] - p[0]).cross(p[i + 1] - p[0]);
  return s.dot(n);
}

/// clip_polygon into `out` (cleared first; its storage kept for the next call).
void clip_polygon_into(std::span<const Eigen::Vector3d> polygon, const CrackPlane& plane,
                       std::vector<Eigen::Vector3d>& out) {
  out.clear();
  const std::size_t n = polygon.size();
  if (n == 0) return;
  const Eigen::Vector3d nn = plane.normal.normalized();
  auto dist = [&](const Eigen::Vector3d& p) { return (p - plane.point).dot(nn); };
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = polygon[i];
    const Eigen::Vector3d& b = polygon[(i + 1) % n];
    const double da = dist(a), db = dist(b);
    if (da <= 0.0) out.push_back(a);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
      out.push_back(a + (da / (da - db)) * (b - a));
    }
  }
  if (out.size() < 3) out.clear();
}

}  // namespace

std::vector<Eigen::Vector3d> clip_polygon(std::span<const Eigen::Vector3d> polygon,
                                          const CrackPlane& plane) {
  std::vector<Eigen::Vector3d> out;
  clip_polygon_into(polygon, plane, out);
  return out;
}

FaceLoad face_part_load(const FaceGeometry& g, const FaceTractions& t,
                        std::span<const Eigen::Vector3d> face_polygon, const CrackPlane& plane) {
  // One buffer a thread: the check calls this for every face and plane of each body it
  // assesses (an allocation each, once).
  thread_local std::vector<Eigen::Vector3d> part;
  clip_polygon_into(face_polygon, plane, part);
  FaceLoad load;
  load.point = g.origin;
  if (part.empty()) return load;
  // The traction field over the part (sec. 3.3's smoothing of cut faces).
  load = integrate_tractions(g, t, part);
  // The twist the uniform shear does not carry (eq. 3.18's M_z), shared by area.
  const double field_twist = t.t_y * g.q_y - t.t_x * g.q_x;
  const double share = std::abs(twice_area(part, g.normal)) / (2.0 * g.area);
  load.moment += share * (t.m_z - field_twist) * g.normal;
  return load;
}

CrackPlaneLoad crack_plane_load(std::span<const FaceLoad> fragment_faces,
                                const Eigen::Vector3d& fragment_centroid,
                                std::span<const Eigen::Vector3d> section_polygon,
                                const CrackPlane& plane, const Eigen::Vector3d& x_axis,
                                const FragmentInertia& inertia) {
  CrackPlaneLoad c;
  c.polygon.assign(section_polygon.begin(), section_polygon.end());
  c.section = face_geometry(section_polygon, plane.normal, x_axis);
  /// F_centroid = sum F^i, M_centroid = sum (M^i + R^i x F^i), sec. 3.3 (after eq. 3.20).
  for (const FaceLoad& f : fragment_faces) {
    c.applied_force += f.force;
    c.applied_moment += moment_about(f, fragment_centroid);
  }
  /// Equilibrium of the fragment, sec. 3.3, with d'Alembert's terms as in eq. 3.8.
  c.force = inertia.force - c.applied_force;
  const Eigen::Vector3d moment_g = inertia.moment - c.applied_moment;
  // Moved from the fragment centroid to the section centroid.
  c.moment = moment_g + (fragment_centroid - c.section.origin).cross(c.force);
  /// Crack-plane tractions, eq. 3.21 (means), linear normal part by eq. 3.15.
  c.tractions = tractions_from_resultant(c.section, c.force, c.moment);
  return c;
}

}  // namespace cleave::physics
