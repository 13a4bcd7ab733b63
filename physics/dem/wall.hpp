#pragma once
/// \file
/// Walls: rigid boundaries that move with a prescribed velocity and record the reaction
/// force the bodies exert on them every step. An infinite plane (a floor), a finite
/// rectangular platen (a loading plate) and a finite cylinder (a roller of a bending rig).
/// Walls have no dilation: a body's dilated primitives touch the wall's surface.

#include <Eigen/Dense>
#include <optional>
#include <string>

#include "physics/dem/contact_kernels.hpp"

namespace cleave::physics {

struct Wall {
  enum class Kind { plane, platen, cylinder } kind = Kind::plane;
  std::string name;
  /// plane/platen: a point of the surface (platen: its centre); cylinder: one end of the axis.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  /// plane/platen: unit normal pointing to the side the bodies are on; cylinder: unit axis.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  /// platen: unit in-plane direction of its first side (the second is normal x u).
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();
  double half_u = 0.0, half_v = 0.0;  ///< platen half sizes
  double length = 0.0;                ///< cylinder axis length
  double radius = 0.0;                ///< cylinder radius
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< prescribed, m/s
  Eigen::Vector3d reaction = Eigen::Vector3d::Zero();  ///< force of the bodies on it, last step
  /// The axis a testing machine would read this wall's load and displacement along (unit;
  /// planes and platens: their normal, pointing into the specimen; zero: none given, read
  /// magnitudes).
  Eigen::Vector3d load_axis = Eigen::Vector3d::Zero();

  static Wall plane(std::string name, const Eigen::Vector3d& point, const Eigen::Vector3d& normal);
  static Wall platen(std::string name, const Eigen::Vector3d& centre, const Eigen::Vector3d& normal,
                     const Eigen::Vector3d& u, double half_u, double half_v);
  static Wall cylinder(std::string name, const Eigen::Vector3d& end, const Eigen::Vector3d& axis,
                       double length, double radius);

  /// Contact of a sphere (a body's vertex) with the wall; normal from the wall towards the
  /// sphere.
  [[nodiscard]] std::optional<PrimitiveContact> sphere_contact(const Eigen::Vector3d& c, double r,
                                                               double margin = 0.0) const;
  /// Contact of a cylinder (a body's edge p-q) with a cylinder wall, where their axes
  /// cross; none for planes and platens (their vertices already carry the contact).
  [[nodiscard]] std::optional<PrimitiveContact> edge_contact(const Eigen::Vector3d& p,
                                                             const Eigen::Vector3d& q, double r,
                                                             double margin = 0.0) const;
};

}  // namespace cleave::physics
