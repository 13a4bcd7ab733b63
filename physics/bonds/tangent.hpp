#pragma once
/// \file
/// Incremental tangential springs (shear force, rolling moment) live in the plane across
/// the contact normal; as the normal turns with the bodies they are carried into the new
/// plane with their magnitude kept.

#include <Eigen/Dense>

#include "physics/bonds/vec3.hpp"

namespace cleave::physics {

/// `v` turned into the plane across unit normal `n`, with its length kept (zero if `v` is
/// along `n`), lane by lane (vec3.hpp).
template <class T>
[[gnu::always_inline]] inline Vec3<T> into_plane(const Vec3<T>& v, const Vec3<T>& n) {
  const T len = norm(v);
  if (simd::all(len == 0.0)) return v;  // unloaded springs: no roots to take
  const Vec3<T> t = v - dot(v, n) * n;
  const T tl = norm(t);
  const T zero(0.0);
  return select(len == 0.0, v, select(tl == 0.0, Vec3<T>{zero, zero, zero}, t * (len / tl)));
}

/// The same on Eigen vectors, with the same bits.
inline Eigen::Vector3d into_plane(const Eigen::Vector3d& v, const Eigen::Vector3d& n) {
  return eigen(into_plane(v3(v), v3(n)));
}

}  // namespace cleave::physics
