#pragma once
/// \file
/// Incremental tangential springs (shear force, rolling moment) live in the plane across
/// the contact normal; as the normal turns with the bodies they are carried into the new
/// plane with their magnitude kept.

#include <Eigen/Dense>

#include "physics/bonds/vec3.hpp"

namespace cleave::physics {

/// `v` turned into the plane across unit normal `n`, with its length kept (zero if `v` is
/// along `n`). In plain doubles (vec3.hpp), for the laws' loops.
[[gnu::always_inline]] inline V3 into_plane(const V3& v, const V3& n) {
  const double len = norm(v);
  if (len == 0.0) return v;
  const V3 t = v - dot(v, n) * n;
  const double tl = norm(t);
  if (tl == 0.0) return {0.0, 0.0, 0.0};
  return t * (len / tl);
}

/// The same on Eigen vectors, with the same bits.
inline Eigen::Vector3d into_plane(const Eigen::Vector3d& v, const Eigen::Vector3d& n) {
  return eigen(into_plane(v3(v), v3(n)));
}

}  // namespace cleave::physics
