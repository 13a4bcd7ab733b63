#pragma once
/// \file
/// Incremental tangential springs (shear force, rolling moment) live in the plane across
/// the contact normal; as the normal turns with the bodies they are carried into the new
/// plane with their magnitude kept.

#include <Eigen/Dense>

namespace cleave::physics {

/// `v` turned into the plane across unit normal `n`, with its length kept (zero if `v` is
/// along `n`).
inline Eigen::Vector3d into_plane(const Eigen::Vector3d& v, const Eigen::Vector3d& n) {
  const double len = v.norm();
  if (len == 0.0) return v;
  const Eigen::Vector3d t = v - v.dot(n) * n;
  const double tl = t.norm();
  if (tl == 0.0) return Eigen::Vector3d::Zero();
  return t * (len / tl);
}

}  // namespace cleave::physics
