#include "physics/dem/rigid_shape.hpp"

namespace cleave::physics {

Eigen::Quaterniond RigidShape::orientation_for(const Eigen::Quaterniond& shape_rotation) const {
  return (shape_rotation * Eigen::Quaterniond(axes)).normalized();
}

RigidShape make_rigid_shape(const geometry::ExactPolyhedron& shape, double dilation_radius) {
  const geometry::MassProperties mp = shape.mass_properties();
  RigidShape out;
  out.volume = mp.volume;
  out.principal_moments = mp.principal_moments;
  out.centroid = mp.centroid;
  out.axes = mp.principal_axes;  // right-handed, columns = principal axes
  // Primitives about the centroid in shape axes, then turned into the principal frame.
  geometry::ContactPrimitives p =
      geometry::make_contact_primitives(shape.to_mesh(), mp.centroid, dilation_radius);
  const Eigen::Matrix3d to_principal = out.axes.transpose();
  for (auto& v : p.vertices) v = to_principal * v;
  for (auto& f : p.faces) {
    f.normal = to_principal * f.normal;
    f.centroid = to_principal * f.centroid;
  }
  p.origin = Eigen::Vector3d::Zero();
  geometry::finish_primitives(p);  // edge directions in the principal frame
  out.primitives = std::move(p);
  return out;
}

}  // namespace cleave::physics
