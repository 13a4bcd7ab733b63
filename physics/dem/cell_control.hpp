#pragma once
/// \file
/// The periodic cell's owner: the cell, its strain rate (set, thermal, and Berendsen's
/// stress control), the bodies' wrap into it and the search for pairs across its faces.

#include <Eigen/Dense>
#include <vector>

#include "physics/dem/body.hpp"
#include "physics/dem/narrow_phase.hpp"
#include "physics/dem/neighbour_search.hpp"
#include "physics/dem/periodic_cell.hpp"

namespace cleave::physics {

/// A periodic cell (off until set) and this step's velocity gradient.
class CellControl {
 public:
  /// Throws std::invalid_argument unless `cell` is finite, spans a volume and has a periodic axis.
  static void check(const PeriodicCell& cell);
  /// Sets the cell (checked first).
  void set(const PeriodicCell& cell) {
    cell_ = cell;
    on_ = true;
  }
  [[nodiscard]] bool on() const { return on_; }
  [[nodiscard]] const PeriodicCell& cell() const { return cell_; }
  /// The cell, or null without one.
  [[nodiscard]] const PeriodicCell* get() const { return on_ ? &cell_ : nullptr; }
  void set_velocity_gradient(const Eigen::Matrix3d& l);
  /// Berendsen's pressure control (World::set_stress_control); tau = 0: off.
  void set_stress_control(double modulus, double tau) {
    stress_modulus_ = modulus;
    stress_tau_ = tau;
  }
  [[nodiscard]] bool stress_controlled() const { return stress_tau_ > 0.0; }

  /// This step's velocity gradient from the set one: plus `thermal_rate` (the grains' mean
  /// expansion rate), and with `sigma` (the cell's stress, when controlled) the axes left free
  /// relaxing their mean normal stress.
  void begin_step(const Eigen::Matrix3d& gradient, const Eigen::Matrix3d* sigma);
  /// The gradient of this step (the set one, plus the thermal and controlled rates).
  [[nodiscard]] const Eigen::Matrix3d& gradient() const { return gradient_; }
  /// Whether the gradient is not zero: bodies ride the affine field, relative velocities gain L d.
  [[nodiscard]] bool moving() const { return moving_; }
  /// The homogeneous deformation over the step h: centroids ride the affine field, the cell
  /// with them (when moving).
  void deform(std::vector<BodyState>& states, const std::vector<BodyInfo>& infos, double h);
  /// The centroids that left the cell go back in by a cell vector; returns by how many cells
  /// each moved (empty when none did), for the bonds to follow (Bonds::follow_wrap).
  std::vector<Eigen::Vector3i> wrap(std::vector<BodyState>& states,
                                    const std::vector<BodyInfo>& infos) const;

  /// Every pair of `spheres` within `margin` of each other, as NeighbourSearch::find_pairs
  /// gives them; in a periodic cell through the faces too (each pair once, whichever image).
  void find_pairs(NeighbourSearch& search, const std::vector<BoundingSphere>& spheres,
                  double margin, std::vector<BodyPair>& pairs) const;
  /// `posed` moved by `shift` (B's image in a periodic cell).
  static void shifted_copy(const PosedShape& posed, const Eigen::Vector3d& shift, PosedShape& out);

  /// The cell vectors at the last neighbour search (a pair's image moves with their change).
  [[nodiscard]] const Eigen::Matrix3d& at_search() const { return at_search_; }
  void note_search() { at_search_ = cell_.vectors(); }

  /// A checkpoint's cell.
  void restore(bool on, const PeriodicCell& cell, const Eigen::Matrix3d& at_search) {
    on_ = on;
    cell_ = cell;
    at_search_ = at_search;
  }

 private:
  PeriodicCell cell_;
  bool on_ = false;
  Eigen::Matrix3d gradient_ =
      Eigen::Matrix3d::Zero();  // this step's: the cell's L plus its thermal rate
  bool moving_ = false;         // gradient_ is not zero
  double stress_modulus_ = 0.0, stress_tau_ = 0.0;       // set_stress_control
  Eigen::Matrix3d at_search_ = Eigen::Matrix3d::Zero();  // the cell vectors at the last search
};

}  // namespace cleave::physics
