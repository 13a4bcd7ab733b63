#pragma once
/// \file
/// Bodies: stable ids, hot per-step state kept apart from cold properties.

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cstdint>

#include "physics/bonds/vec3.hpp"

namespace cleave::physics {

/// A stable handle: array slot + generation. A slot reused after its body was removed gets
/// a new generation, so a stale handle is detected instead of reaching the wrong body.
struct BodyId {
  std::uint32_t index = ~0u;
  std::uint32_t generation = 0;
  [[nodiscard]] bool valid() const { return index != ~0u; }
  friend bool operator==(const BodyId&, const BodyId&) = default;
};

/// What changes every step (kept small and contiguous).
struct BodyState {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  ///< centroid position, world
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  ///< principal frame -> world
  Eigen::Vector3d v = Eigen::Vector3d::Zero();    ///< velocity of the centroid
  Eigen::Vector3d L = Eigen::Vector3d::Zero();    ///< angular momentum about the centroid, world
  Eigen::Vector3d w = Eigen::Vector3d::Zero();    ///< angular velocity, world (derived from L)
  Eigen::Vector3d f = Eigen::Vector3d::Zero();    ///< force accumulated this step
  Eigen::Vector3d tau = Eigen::Vector3d::Zero();  ///< torque about the centroid this step
};

/// q * v, with the arithmetic of Eigen's QuaternionBase::_transformVector (the same bits),
/// always inlined: GCC leaves Eigen's out of line at -O2, and the bond and integrator loops
/// call it several times per item (vec3.hpp's rotated on Eigen vectors).
[[gnu::always_inline]] inline Eigen::Vector3d rotated(const Eigen::Quaterniond& q, const Eigen::Vector3d& v) {
  return eigen(rotated(q, v3(v)));
}

/// A body's temperature and thermal expansion (seed 003's l0(T) rule, per crystal axis).
/// The grain's shape keeps its reference size: its expansion acts through its bonds (their
/// rest state follows it) and through the overlaps its bonded neighbours count from.
struct BodyThermal {
  double temperature = 0.0;  ///< K (only differences matter)
  double bonded_at = 0.0;    ///< the temperature the body's bonds last followed, K
  /// Linear expansion coefficients in the body's principal frame, 1/K: a material point at
  /// r from the centroid moves by alpha r dT (symmetric; alpha_a I + (alpha_c - alpha_a) c c^T
  /// for a hexagonal or trigonal crystal with c-axis c).
  Eigen::Matrix3d alpha = Eigen::Matrix3d::Zero();
  bool held = false;  ///< conduction leaves its temperature as set
  /// The temperature the body's (rigid) shape has its size at, K: set with its expansion.
  /// Contacts count their overlap from the gap the two grains' expansion since then opens.
  double shaped_at = 0.0;
  /// The point its expansion is about, from the centroid, in the principal frame: zero for
  /// a grain; for a piece of a split one, its parent's (a piece's material has moved with the
  /// parent's expansion until the split, so its bonds and contacts go on from there).
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
};

/// What a body is (changes only when bodies are created, split or removed).
struct BodyInfo {
  std::uint32_t shape = 0;       ///< index into the world's shapes
  double mass = 0.0;
  double inv_mass = 0.0;
  Eigen::Vector3d inertia = Eigen::Vector3d::Zero();      ///< principal moments (kg m^2)
  Eigen::Vector3d inv_inertia = Eigen::Vector3d::Zero();  ///< their inverses
  int grain_id = -1;             ///< the grain it is (or came from); -1 for none
  std::uint32_t generation = 0;
  bool alive = false;
  bool fixed = false;            ///< prescribed motion: forces do not change its velocities
};

}  // namespace cleave::physics
