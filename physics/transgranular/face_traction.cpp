#include "physics/transgranular/face_traction.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace cleave::physics {

namespace {

/// Area integrals of 1, x, y, x^2, y^2, x y over a polygon given in 2D (shoelace forms).
struct PolygonIntegrals {
  double a = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0, sxy = 0.0;
};

PolygonIntegrals polygon_integrals(std::span<const Eigen::Vector2d> v) {
  PolygonIntegrals s;
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = v[i];
    const Eigen::Vector2d& q = v[(i + 1) % n];
    const double w = p.x() * q.y() - q.x() * p.y();
    s.a += w;
    s.sx += (p.x() + q.x()) * w;
    s.sy += (p.y() + q.y()) * w;
    s.sxx += (p.x() * p.x() + p.x() * q.x() + q.x() * q.x()) * w;
    s.syy += (p.y() * p.y() + p.y() * q.y() + q.y() * q.y()) * w;
    s.sxy += (p.x() * q.y() + 2.0 * p.x() * p.y() + 2.0 * q.x() * q.y() + q.x() * p.y()) * w;
  }
  s.a /= 2.0;
  s.sx /= 6.0;
  s.sy /= 6.0;
  s.sxx /= 12.0;
  s.syy /= 12.0;
  s.sxy /= 24.0;
  return s;
}

}  // namespace

Eigen::Vector2d FaceGeometry::to_local(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d d = p - origin;
  return {d.dot(x_axis), d.dot(y_axis)};
}

Eigen::Vector3d FaceGeometry::to_world(double x, double y) const {
  return origin + x * x_axis + y * y_axis;
}

FaceGeometry face_geometry(std::span<const Eigen::Vector3d> polygon, const Eigen::Vector3d& normal,
                           const Eigen::Vector3d& x_axis) {
  if (polygon.size() < 3) throw std::invalid_argument("face_geometry: fewer than 3 vertices");
  FaceGeometry g;
  g.normal = normal.normalized();
  const Eigen::Vector3d x = x_axis - x_axis.dot(g.normal) * g.normal;
  if (x.norm() <= 1e-12 * x_axis.norm()) {
    throw std::invalid_argument("face_geometry: x axis along the normal");
  }
  g.x_axis = x.normalized();
  g.y_axis = g.normal.cross(g.x_axis);
  // Local coordinates about the vertex mean keep the shoelace sums well conditioned.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : polygon) mean += p;
  mean /= static_cast<double>(polygon.size());
  g.origin = mean;
  std::vector<Eigen::Vector2d> local;
  local.reserve(polygon.size());
  for (const auto& p : polygon) local.push_back(g.to_local(p));
  PolygonIntegrals s = polygon_integrals(local);
  if (s.a < 0.0) {  // clockwise about the normal: every integral flips sign
    s.a = -s.a;
    s.sx = -s.sx;
    s.sy = -s.sy;
    s.sxx = -s.sxx;
    s.syy = -s.syy;
    s.sxy = -s.sxy;
  }
  if (!(s.a > 0.0)) throw std::invalid_argument("face_geometry: polygon has no area");
  // Eq. 3.13 about the centroid (parallel axes); the first moments vanish there.
  const double cx = s.sx / s.a, cy = s.sy / s.a;
  g.origin = g.to_world(cx, cy);
  g.area = s.a;
  g.q_x = 0.0;
  g.q_y = 0.0;
  g.i_xx = s.sxx - s.a * cx * cx;
  g.i_yy = s.syy - s.a * cy * cy;
  g.i_xy = s.sxy - s.a * cx * cy;
  return g;
}

FaceGeometry face_geometry(std::span<const Eigen::Vector3d> polygon) {
  if (polygon.size() < 3) throw std::invalid_argument("face_geometry: fewer than 3 vertices");
  Eigen::Vector3d n = Eigen::Vector3d::Zero();  // Newell: twice the vector area
  const std::size_t m = polygon.size();
  for (std::size_t i = 0; i < m; ++i) n += polygon[i].cross(polygon[(i + 1) % m]);
  if (!(n.norm() > 0.0)) throw std::invalid_argument("face_geometry: polygon has no area");
  return face_geometry(polygon, n, polygon[1] - polygon[0]);
}

Eigen::Vector3d moment_about(const FaceLoad& load, const Eigen::Vector3d& p) {
  return load.moment + (load.point - p).cross(load.force);
}

double FaceTractions::t_s() const {
  return std::hypot(t_x, t_y);
}

FaceTractions tractions_from_resultant(const FaceGeometry& g, const Eigen::Vector3d& force,
                                       const Eigen::Vector3d& moment) {
  FaceTractions t;
  t.force = force;
  t.moment = moment;
  const double A = g.area;
  // Right-hand sides of eq. 3.14 in the face frame (see the header for the reading).
  const double fx = force.dot(g.x_axis);
  const double fy = force.dot(g.y_axis);
  const double fz = force.dot(g.normal);
  const double xfz = -moment.dot(g.y_axis);  // sum x_n f_z^n
  const double yfz = moment.dot(g.x_axis);   // sum y_n f_z^n
  /// Uniform shear tractions, eq. 3.14a-b of the dissertation.
  t.t_x = fx / A;
  t.t_y = fy / A;
  /// Twisting moment, eq. 3.14f / 3.18.
  t.m_z = moment.dot(g.normal);
  /// Consistent normal traction, eq. 3.15 solved with the adjugate B of eqs 3.16-3.17.
  const double Qx = g.q_x, Qy = g.q_y, Ixx = g.i_xx, Iyy = g.i_yy, Ixy = g.i_xy;
  const double detI = Ixx * Iyy - Ixy * Ixy;
  const double b12 = Qx * Ixy - Qy * Iyy;
  const double b13 = Qy * Ixy - Qx * Ixx;
  const double b22 = A * Iyy - Qx * Qx;
  const double b23 = Qy * Qx - A * Ixy;
  const double b33 = A * Ixx - Qy * Qy;
  const double detK = A * detI + Qy * b12 + Qx * b13;
  if (!(std::abs(detK) > 0.0)) throw std::invalid_argument("tractions: singular face (eq. 3.15)");
  t.t_o = (detI * fz + b12 * xfz + b13 * yfz) / detK;
  t.c1 = (b12 * fz + b22 * xfz + b23 * yfz) / detK;
  t.c2 = (b13 * fz + b23 * xfz + b33 * yfz) / detK;
  return t;
}

FaceTractions face_tractions(const FaceGeometry& g, std::span<const PointForce> forces) {
  // Resultant force and moment about the origin, arms projected onto the face plane.
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), m = Eigen::Vector3d::Zero();
  for (const auto& pf : forces) {
    const Eigen::Vector2d xy = g.to_local(pf.point);
    const Eigen::Vector3d arm = xy.x() * g.x_axis + xy.y() * g.y_axis;
    f += pf.force;
    m += arm.cross(pf.force);
  }
  /// Consistent tractions, eqs 3.14-3.16 of the dissertation.
  return tractions_from_resultant(g, f, m);
}

FaceLoad face_load(const FaceGeometry& g, const FaceTractions& t) {
  const double A = g.area;
  // Integrals of the field over the face (eqs 3.11-3.13 read backwards).
  const double n_int = t.t_o * A + t.c1 * g.q_y + t.c2 * g.q_x;        // integral t_n dA
  const double x_int = t.t_o * g.q_y + t.c1 * g.i_xx + t.c2 * g.i_xy;  // integral x t_n dA
  const double y_int = t.t_o * g.q_x + t.c1 * g.i_xy + t.c2 * g.i_yy;  // integral y t_n dA
  FaceLoad load;
  load.point = g.origin;
  /// Total face force, eq. 3.20: t_n A n + t_x A m + t_y A l.
  load.force = n_int * g.normal + t.t_x * A * g.x_axis + t.t_y * A * g.y_axis;
  /// Its moment: bending from the linear normal field; about the normal, the twist M_z of
  /// eq. 3.18 (the uniform shear itself carries only t_y Q_y - t_x Q_x of it, zero about the
  /// centroid).
  load.moment = y_int * g.x_axis - x_int * g.y_axis + t.m_z * g.normal;
  return load;
}

FaceLoad integrate_tractions(const FaceGeometry& g, const FaceTractions& t,
                             std::span<const Eigen::Vector3d> polygon) {
  FaceLoad load;
  load.point = g.origin;
  if (polygon.size() < 3) return load;
  // Points in the face plane relative to the origin.
  std::vector<Eigen::Vector2d> p;
  p.reserve(polygon.size());
  for (const auto& v : polygon) p.push_back(g.to_local(v));
  const Eigen::Vector3d shear = t.t_x * g.x_axis + t.t_y * g.y_axis;
  auto arm = [&](const Eigen::Vector2d& q) -> Eigen::Vector3d {
    return q.x() * g.x_axis + q.y() * g.y_axis;
  };
  auto traction = [&](const Eigen::Vector2d& q) -> Eigen::Vector3d {
    return shear + t.t_n(q.x(), q.y()) * g.normal;
  };
  // Fan of triangles from the first vertex; the signed area makes the sense irrelevant.
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const Eigen::Vector2d &a = p[0], &b = p[i], &c = p[i + 1];
    const Eigen::Vector2d e1 = b - a, e2 = c - a;
    const double area = 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
    const Eigen::Vector2d mid[3] = {0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)};
    for (const auto& q : mid) {
      const Eigen::Vector3d tq = traction(q);
      load.force += (area / 3.0) * tq;
      load.moment += (area / 3.0) * arm(q).cross(tq);
    }
  }
  // A clockwise polygon integrates to minus the field: orient by the total signed area.
  double signed_area = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d& a = p[i];
    const Eigen::Vector2d& b = p[(i + 1) % p.size()];
    signed_area += a.x() * b.y() - b.x() * a.y();
  }
  if (signed_area < 0.0) {
    load.force = -load.force;
    load.moment = -load.moment;
  }
  return load;
}

}  // namespace cleave::physics
