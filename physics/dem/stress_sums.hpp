#pragma once
/// \file
/// Eq. 2.17's sums by body (the Love-Weber stress of each grain), and the periodic cell's
/// average stress, from the forces of the last evaluation.

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "physics/bonds/vec3.hpp"

namespace cleave::physics {

class Bodies;
class Bonds;
class CellControl;
class Contacts;

/// Eq. 2.17's sum of one body in registers: m(r, c) += arm(r) force(c), each term rounded
/// as Eigen's outer product added to a matrix rounds it (a product, then a sum).
struct StressSum {
  double m[9] = {};
  [[gnu::always_inline]] void add(const V3& arm, const V3& force) {
    const double a[3] = {arm.x, arm.y, arm.z}, g[3] = {force.x, force.y, force.z};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[3 * r + c] += a[r] * g[c];
  }
  void store(Eigen::Matrix3d& s) const {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) s(r, c) = m[3 * r + c];
  }
};

/// The diagonal of a StressSum alone: d(r) += arm(r) force(r), the same bits as its m(r, r).
struct StressDiagonal {
  double d[3] = {};
  [[gnu::always_inline]] void add(const V3& arm, const V3& force) {
    d[0] += arm.x * force.x;
    d[1] += arm.y * force.y;
    d[2] += arm.z * force.z;
  }
  void load(const Eigen::Vector3d& s) {
    for (int r = 0; r < 3; ++r) d[r] = s[r];
  }
  void store(Eigen::Vector3d& s) const {
    for (int r = 0; r < 3; ++r) s[r] = d[r];
  }
};

/// One force of the last evaluation acting on a body at a point (world axes): a contact's
/// or an intact bond's (B's point taken at its image in a periodic cell).
struct AppliedForce {
  Eigen::Vector3d point, force;
};

/// The sums, made when first asked for after an evaluation (or with the forces, when a
/// listener asked: StepNeeds::stress_sums).
class StressSums {
 public:
  /// What the sums read: the owners, and whether their lists by body describe them.
  struct View {
    const Bodies& bodies;
    const Contacts& contacts;
    const Bonds& bonds;
    const CellControl& cell;
    bool by_body_current;  ///< the lists by body are this evaluation's
    bool decomposed;       ///< one process of a domain (the ghosts' bonds change after the sums)
    int threads;           ///< WorldSettings::threads
  };

  /// Whether the next evaluation sums the diagonals with the forces (a step's listeners' needs).
  void want_diagonals(bool want) { want_ = want; }
  /// An evaluation starts (`alone`: not one process of several); the sums are out of date.
  void begin_evaluation(bool alone, std::size_t slots) {
    sums_current_ = diagonals_current_ = false;
    summing_ = alone && want_;
    want_ = false;
    if (summing_) diagonals_.resize(slots);
  }
  /// Where the force sums add eq. 2.17's diagonal terms this evaluation (null: nowhere).
  [[nodiscard]] std::vector<Eigen::Vector3d>* summing() { return summing_ ? &diagonals_ : nullptr; }
  /// The force sums are done: the diagonals are this evaluation's when summed with them.
  void end_sums() { diagonals_current_ = summing_; }
  /// A bond broke after the sums: they still hold it.
  void invalidate() { sums_current_ = diagonals_current_ = false; }

  [[nodiscard]] const std::vector<Eigen::Matrix3d>& sums(const View& view) const;
  [[nodiscard]] Eigen::Matrix3d sum(const View& view, std::uint32_t slot) const;
  [[nodiscard]] const std::vector<Eigen::Vector3d>& diagonals(const View& view) const;
  void forces_on(const View& view, std::uint32_t slot, std::vector<AppliedForce>& out) const;
  /// Eq. 2.17 of every body, by slot.
  [[nodiscard]] std::vector<Eigen::Matrix3d> body_stresses(const View& view) const;
  /// World::cell_stress.
  [[nodiscard]] static Eigen::Matrix3d cell_stress(const View& view);

 private:
  mutable std::vector<Eigen::Matrix3d> sums_;
  mutable std::vector<Eigen::Vector3d> diagonals_;
  mutable bool sums_current_ = false, diagonals_current_ = false;
  bool want_ = false, summing_ = false;
};

}  // namespace cleave::physics
