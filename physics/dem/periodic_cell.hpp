#pragma once
/// \file
/// A periodic cell (issue 23; the cell of Yade's Cell and LIGGGHTS' triclinic boxes): a
/// parallelepiped x = origin + H s, s in [0, 1)^3, whose columns h_k are the cell vectors,
/// periodic along any of them. A body interacts with the images of the others shifted by
/// H n (n integer on the periodic axes), the nearest one only: the cell must be wider, along
/// each periodic axis, than twice the longest reach of a pair, so that no pair meets twice.
///
/// Straining: the cell deforms homogeneously with a velocity gradient L, dH/dt = L H, and
/// the bodies' centroids follow the same affine field, x <- x + dt L (x - origin); their
/// velocities are what they move with on top of it (the fluctuation). Two bodies' material
/// points at one place therefore move apart at L (x_B + H n - x_A) plus their own motion.

#include <Eigen/Dense>

#include <array>
#include <cmath>

namespace cleave::physics {

class PeriodicCell {
 public:
  PeriodicCell() = default;
  /// A cell of vectors `h` (columns, m) from `origin`, periodic along the axes marked.
  PeriodicCell(const Eigen::Matrix3d& h, const Eigen::Vector3d& origin, std::array<bool, 3> periodic)
      : origin_(origin), periodic_(periodic) {
    set_vectors(h);
  }
  /// An axis-aligned box [lo, hi], periodic along the axes marked.
  static PeriodicCell box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::array<bool, 3> periodic) {
    return PeriodicCell((hi - lo).asDiagonal(), lo, periodic);
  }

  [[nodiscard]] const Eigen::Matrix3d& vectors() const { return h_; }
  [[nodiscard]] const Eigen::Matrix3d& inverse() const { return h_inv_; }
  [[nodiscard]] const Eigen::Vector3d& origin() const { return origin_; }
  [[nodiscard]] const std::array<bool, 3>& periodic() const { return periodic_; }
  [[nodiscard]] bool periodic(int k) const { return periodic_[static_cast<std::size_t>(k)]; }
  [[nodiscard]] bool any_periodic() const { return periodic_[0] || periodic_[1] || periodic_[2]; }
  [[nodiscard]] const Eigen::Matrix3d& velocity_gradient() const { return l_; }
  void set_velocity_gradient(const Eigen::Matrix3d& l) { l_ = l; }
  void set_vectors(const Eigen::Matrix3d& h) {
    h_ = h;
    h_inv_ = h.inverse();
  }

  [[nodiscard]] double volume() const { return std::abs(h_.determinant()); }
  /// The distance between the cell's two faces across axis k: 1 / |row k of H^-1|.
  [[nodiscard]] double width(int k) const { return 1.0 / h_inv_.row(k).norm(); }
  /// The cell coordinates s of a point: x = origin + H s.
  [[nodiscard]] Eigen::Vector3d reduced(const Eigen::Vector3d& x) const { return h_inv_ * (x - origin_); }
  /// The world translation of image n.
  [[nodiscard]] Eigen::Vector3d shift(const Eigen::Vector3i& n) const { return h_ * n.cast<double>(); }
  /// The image of B nearest to A: the n (zero on the axes that are not periodic) for which
  /// x_B + H n is closest to x_A in cell coordinates.
  [[nodiscard]] Eigen::Vector3i nearest_image(const Eigen::Vector3d& xa, const Eigen::Vector3d& xb) const {
    const Eigen::Vector3d s = h_inv_ * (xb - xa);
    Eigen::Vector3i n = Eigen::Vector3i::Zero();
    for (int k = 0; k < 3; ++k) {
      if (periodic(k)) n[k] = -static_cast<int>(std::lround(s[k]));
    }
    return n;
  }
  /// How many cells a point lies beyond the master cell along each periodic axis: x - H m
  /// is in the master cell (zero on the other axes).
  [[nodiscard]] Eigen::Vector3i outside(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d s = reduced(x);
    Eigen::Vector3i m = Eigen::Vector3i::Zero();
    for (int k = 0; k < 3; ++k) {
      if (periodic(k)) m[k] = static_cast<int>(std::floor(s[k]));
    }
    return m;
  }
  /// One step of a homogeneous deformation: H <- (I + step) H, step = dt L over the step
  /// (World::step adds the grains' mean thermal strain rate to the cell's L).
  void deform(const Eigen::Matrix3d& step) { set_vectors(h_ + step * h_); }

 private:
  Eigen::Matrix3d h_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d h_inv_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  std::array<bool, 3> periodic_{false, false, false};
  Eigen::Matrix3d l_ = Eigen::Matrix3d::Zero();
};

}  // namespace cleave::physics
