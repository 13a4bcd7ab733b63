#pragma once
/// \file
/// The double-precision data the dynamics needs from one exact shape, derived once when a
/// shape is created (never inside the step loop): principal moments of inertia per unit
/// density and contact primitives, all in the shape's principal frame (origin at the
/// centroid, axes along the principal axes, so the inertia tensor is diagonal).

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "geometry/contact_primitives.hpp"
#include "geometry/exact_polyhedron.hpp"

namespace cleave::physics {

struct RigidShape {
  double volume = 0.0;
  /// Principal moments per unit density, ascending (I1 <= I2 <= I3).
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();
  /// Where the principal frame sits in the shape frame: p_shape = centroid + axes * p_principal.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  /// Spheres, cylinders and facets in the principal frame.
  geometry::ContactPrimitives primitives;

  [[nodiscard]] double bounding_radius() const { return primitives.bounding_radius; }
  /// Orientation (principal frame -> world) of a body whose shape frame is the world frame
  /// turned by `shape_rotation`.
  [[nodiscard]] Eigen::Quaterniond orientation_for(
      const Eigen::Quaterniond& shape_rotation = Eigen::Quaterniond::Identity()) const;
};

/// Mass properties (exact, rounded once) and contact primitives of `shape`, re-expressed in
/// its principal frame, with the given dilation radius.
RigidShape make_rigid_shape(const geometry::ExactPolyhedron& shape, double dilation_radius);

}  // namespace cleave::physics
