#include "physics/dem/wall.hpp"

#include <cmath>
#include <stdexcept>

namespace cleave::physics {

Wall Wall::plane(std::string name, const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  Wall w;
  w.kind = Kind::plane;
  w.name = std::move(name);
  w.origin = point;
  w.normal = normal.normalized();
  w.load_axis = w.normal;
  return w;
}

Wall Wall::platen(std::string name, const Eigen::Vector3d& centre, const Eigen::Vector3d& normal,
                  const Eigen::Vector3d& u, double half_u, double half_v) {
  Wall w = plane(std::move(name), centre, normal);
  w.kind = Kind::platen;
  w.u = (u - u.dot(w.normal) * w.normal).normalized();
  w.half_u = half_u;
  w.half_v = half_v;
  if (!(half_u > 0.0 && half_v > 0.0)) throw std::invalid_argument("platen sizes must be positive");
  return w;
}

Wall Wall::cylinder(std::string name, const Eigen::Vector3d& end, const Eigen::Vector3d& axis,
                    double length, double radius) {
  Wall w;
  w.kind = Kind::cylinder;
  w.name = std::move(name);
  w.origin = end;
  w.normal = axis.normalized();
  w.length = length;
  w.radius = radius;
  if (!(length > 0.0 && radius > 0.0)) throw std::invalid_argument("cylinder sizes must be positive");
  return w;
}

std::optional<PrimitiveContact> Wall::sphere_contact(const Eigen::Vector3d& c, double r,
                                                     double margin) const {
  if (kind == Kind::cylinder) {
    // The roller is a cylinder of radius `radius` around its axis segment.
    auto pc = sphere_cylinder(c, r, origin, origin + length * normal, radius, margin);
    if (pc) pc->normal = -pc->normal;  // kernel: from the sphere to the axis; here wall -> sphere
    return pc;
  }
  const double d = normal.dot(c - origin);
  const double pen = r - d;
  if (pen <= -margin) return std::nullopt;
  if (kind == Kind::platen) {
    const Eigen::Vector3d rel = c - origin;
    const Eigen::Vector3d v = normal.cross(u);
    if (std::abs(rel.dot(u)) > half_u || std::abs(rel.dot(v)) > half_v) return std::nullopt;
  }
  PrimitiveContact pc;
  pc.normal = normal;
  pc.penetration = pen;
  pc.point = c - (r - 0.5 * pen) * normal;
  return pc;
}

std::optional<PrimitiveContact> Wall::edge_contact(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                                   double r, double margin) const {
  if (kind != Kind::cylinder) return std::nullopt;
  const Eigen::Vector3d d = (q - p).normalized();
  if (d.cross(normal).squaredNorm() < 1e-12) return std::nullopt;  // parallel: vertices carry it
  return cylinder_cylinder(origin, origin + length * normal, radius, p, q, r, margin);
}

}  // namespace cleave::physics
