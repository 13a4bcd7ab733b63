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

}  // namespace

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
  return part_load(g, t, part);
}

FaceLoad part_load(const FaceGeometry& g, const FaceTractions& t,
                   std::span<const Eigen::Vector3d> part) {
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

void SolidMassSum::add_face(std::span<const Eigen::Vector3d> polygon,
                            const Eigen::Vector3d& outward) {
  if (polygon.size() < 3) return;
  // Fan about the first vertex, oriented so that each triangle's normal is the outward one.
  const double sense = twice_area(polygon, outward) < 0.0 ? -1.0 : 1.0;
  const Eigen::Vector3d a = polygon[0] - origin_;
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    const Eigen::Vector3d b = polygon[i] - origin_, c = polygon[i + 1] - origin_;
    // Tetrahedron (origin, a, b, c): 6 V = det, integral of r = V (a + b + c) / 4 and
    // integral of r r^T = det / 120 (s s^T + a a^T + b b^T + c c^T), s = a + b + c.
    const double det = sense * a.dot(b.cross(c));
    const Eigen::Vector3d s = a + b + c;
    six_volume_ += det;
    first_ += det * s;
    second_ +=
        det * (s * s.transpose() + a * a.transpose() + b * b.transpose() + c * c.transpose());
  }
}

SolidMass SolidMassSum::result() const {
  SolidMass m;
  m.volume = six_volume_ / 6.0;
  if (!(m.volume > 0.0)) return m;
  const Eigen::Vector3d g = first_ / (24.0 * m.volume);  // from the origin
  m.centroid = origin_ + g;
  // Second moment about the centroid (parallel axes), then J = tr(C) 1 - C.
  const Eigen::Matrix3d c = second_ / 120.0 - m.volume * g * g.transpose();
  m.inertia = c.trace() * Eigen::Matrix3d::Identity() - c;
  return m;
}

SolidMassSum fragment_mass_sum(std::span<const Eigen::Vector3d> section, const CrackPlane& plane) {
  // About a point of the section: the fragment lies next to it, so the sums cancel little.
  Eigen::Vector3d origin = plane.point;
  if (!section.empty()) {
    origin.setZero();
    for (const auto& p : section) origin += p / static_cast<double>(section.size());
  }
  return SolidMassSum(origin);
}

SolidMass fragment_mass(std::span<const std::vector<Eigen::Vector3d>> faces,
                        std::span<const Eigen::Vector3d> outward,
                        std::span<const Eigen::Vector3d> section, const CrackPlane& plane) {
  thread_local std::vector<Eigen::Vector3d> part;
  SolidMassSum sum = fragment_mass_sum(section, plane);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    clip_polygon_into(faces[f], plane, part);
    sum.add_face(part, outward[f]);
  }
  sum.add_face(section, plane.normal);
  return sum.result();
}

FragmentInertia fragment_inertia(const RigidMotion& body, double rho, const SolidMass& fragment) {
  /// Eq. 3.8's d'Alembert force m a for a fragment that moves with its grain: the rigid
  /// body's acceleration field at the fragment's centroid.
  const Eigen::Vector3d r = fragment.centroid - body.centroid;
  const Eigen::Vector3d a =
      body.acceleration + body.alpha.cross(r) + body.omega.cross(body.omega.cross(r));
  const double m = rho * fragment.volume;
  const Eigen::Matrix3d j = rho * fragment.inertia;
  FragmentInertia out;
  out.force = m * (a - body.gravity);
  out.moment = j * body.alpha + body.omega.cross(j * body.omega);
  return out;
}

}  // namespace cleave::physics
