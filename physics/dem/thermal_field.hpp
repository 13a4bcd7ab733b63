#pragma once
/// \file
/// The thermal field's owner: each body's temperature and expansion tensor, and heat
/// conduction through the bonds (seed 003).

#include <Eigen/Dense>
#include <vector>

#include "physics/dem/body.hpp"
#include "physics/dem/rigid_shape.hpp"

namespace cleave::physics {

struct Bond;

/// Temperatures and expansions by body slot (BodyThermal), and the conduction's constants.
class ThermalField {
 public:
  /// A slot (new or reused) starts with no temperature or expansion; `slots`: the bodies' count.
  void reset(std::uint32_t slot, std::size_t slots) {
    if (thermal_.size() < slots) thermal_.resize(slots);
    thermal_[slot] = BodyThermal{};
  }
  /// A split's piece in `slot`, of its parent's material (`parent`, the parent's record; its
  /// state `ps`): its temperature, its expansion tensor turned into the piece's frame by
  /// `turn` (piece -> parent), expanding about the parent's centre (piece at `x`, turned `q`).
  void inherit(std::uint32_t slot, const BodyThermal& parent, const Eigen::Matrix3d& turn,
               const BodyState& ps, const Eigen::Quaterniond& q, const Eigen::Vector3d& x);

  /// World::set_expansion for the body in `slot`, turned `q`.
  void set_expansion(std::uint32_t slot, const Eigen::Quaterniond& q,
                     const Eigen::Matrix3d& alpha_world);
  [[nodiscard]] Eigen::Matrix3d expansion(std::uint32_t slot, const Eigen::Quaterniond& q) const;
  [[nodiscard]] static Eigen::Matrix3d crystal_expansion(const Eigen::Vector3d& c_axis,
                                                         double alpha_a, double alpha_c);
  /// An orthorhombic crystal's: R diag(alpha_a, alpha_b, alpha_c) R^T, R the crystal's
  /// rotation (crystal -> world).
  [[nodiscard]] static Eigen::Matrix3d crystal_expansion(const Eigen::Quaterniond& crystal,
                                                         const Eigen::Vector3d& alpha_abc);
  void set_temperature(std::uint32_t slot, double kelvin);
  /// Every live body's.
  void set_temperature(const std::vector<BodyInfo>& infos, double kelvin);
  void ramp_temperature(const std::vector<BodyInfo>& infos, double change, double target);
  [[nodiscard]] double temperature(std::uint32_t slot) const { return thermal_[slot].temperature; }
  void set_held(std::uint32_t slot, bool held) { thermal_[slot].held = held; }
  void set_conduction(double conductivity, double heat_capacity);
  [[nodiscard]] double conductivity() const { return conductivity_; }
  [[nodiscard]] double heat_capacity() const { return heat_capacity_; }
  /// Whether some body has a non-zero expansion tensor (thermal terms are computed).
  [[nodiscard]] bool on() const { return on_; }
  [[nodiscard]] const std::vector<BodyThermal>& slots() const { return thermal_; }
  [[nodiscard]] const BodyThermal& operator[](std::uint32_t slot) const { return thermal_[slot]; }

  /// The bonds (and a periodic cell) have followed the temperatures up to now.
  void mark_bonded() {
    for (BodyThermal& t : thermal_) t.bonded_at = t.temperature;
  }
  /// Adds to `gradient` the volume-mean thermal strain of the live bodies since the last
  /// force evaluation, over the step h (a free periodic cell follows it).
  void add_mean_strain_rate(const std::vector<BodyState>& states,
                            const std::vector<BodyInfo>& infos,
                            const std::vector<RigidShape>& shapes, double h,
                            Eigen::Matrix3d& gradient) const;
  /// Explicit conduction over the step h through the intact bonds (World::set_conduction).
  void conduct(const std::vector<BodyState>& states, const std::vector<BodyInfo>& infos,
               const std::vector<Bond>& bonds, double h);

  /// How far the material point at `arm` (world, from the centroid) of the body in `slot`
  /// (turned `q`) has moved by its expansion since its shape was made.
  [[nodiscard]] Eigen::Vector3d grown(std::uint32_t slot, const Eigen::Quaterniond& q,
                                      const Eigen::Vector3d& arm) const {
    const BodyThermal& t = thermal_[slot];
    const double d = t.temperature - t.shaped_at;
    if (d == 0.0) return Eigen::Vector3d::Zero();
    return rotated(q, t.alpha * (q.conjugate() * arm - t.centre)) * d;
  }

  /// A checkpoint's field.
  void restore(std::vector<BodyThermal> thermal, bool on, double conductivity,
               double heat_capacity) {
    thermal_ = std::move(thermal);
    on_ = on;
    conductivity_ = conductivity;
    heat_capacity_ = heat_capacity;
  }

 private:
  std::vector<BodyThermal> thermal_;  // by slot
  bool on_ = false;                   // some body expands
  double conductivity_ = 0.0, heat_capacity_ = 0.0;
  std::vector<double> heat_;  // by slot: this step's conducted heat (J)
};

}  // namespace cleave::physics
