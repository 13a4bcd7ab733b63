#pragma once
// The tangent rule as it reads with Eigen's vectors, and a bitwise comparison: what the
// scalar forms of the laws (physics/bonds/vec3.hpp) are checked against, to the bit.
#include <Eigen/Dense>
#include <cstring>

namespace cleave::test {

/// physics::into_plane written with Eigen's vectors (cleave's form before vec3.hpp).
inline Eigen::Vector3d eigen_into_plane(const Eigen::Vector3d& v, const Eigen::Vector3d& n) {
  const double len = v.norm();
  if (len == 0.0) return v;
  const Eigen::Vector3d t = v - v.dot(n) * n;
  const double tl = t.norm();
  if (tl == 0.0) return Eigen::Vector3d::Zero();
  return t * (len / tl);
}

inline bool same_bits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0;
}

}  // namespace cleave::test
