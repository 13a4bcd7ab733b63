#include "physics/dem/thermal_field.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "physics/dem/bonds.hpp"
#include "physics/dem/rigid_shape.hpp"

namespace cleave::physics {

void ThermalField::inherit(std::uint32_t slot, const BodyThermal& pt, const Eigen::Matrix3d& turn,
                           const BodyState& ps, const Eigen::Quaterniond& q,
                           const Eigen::Vector3d& x) {
  thermal_[slot] = pt;
  thermal_[slot].alpha = turn.transpose() * pt.alpha * turn;
  thermal_[slot].held = false;
  // It goes on expanding about the parent's centre: its bonds' and contacts' thermal gaps
  // carry on from where the parent's were (about its own centroid they would jump by
  // alpha dT times the distance between the two centroids at once).
  thermal_[slot].centre = q.conjugate() * (ps.x + ps.q * pt.centre - x);
}

void ThermalField::set_expansion(std::uint32_t slot, const Eigen::Quaterniond& q,
                                 const Eigen::Matrix3d& alpha_world) {
  if (!alpha_world.allFinite())
    throw std::invalid_argument("set_expansion: the tensor must be finite");
  if ((alpha_world - alpha_world.transpose()).norm() > 1e-9 * alpha_world.norm())
    throw std::invalid_argument("set_expansion: the tensor must be symmetric");
  const Eigen::Matrix3d r = q.toRotationMatrix();
  thermal_[slot].alpha = r.transpose() * alpha_world * r;
  thermal_[slot].shaped_at = thermal_[slot].temperature;  // its shape has its size now
  if (!alpha_world.isZero(0.0)) on_ = true;
}

Eigen::Matrix3d ThermalField::expansion(std::uint32_t slot, const Eigen::Quaterniond& q) const {
  const Eigen::Matrix3d r = q.toRotationMatrix();
  return r * thermal_[slot].alpha * r.transpose();
}

Eigen::Matrix3d ThermalField::crystal_expansion(const Eigen::Vector3d& c_axis, double alpha_a,
                                                double alpha_c) {
  if (!(c_axis.norm() > 0.0))
    throw std::invalid_argument("crystal_expansion: the c-axis must not be zero");
  const Eigen::Vector3d c = c_axis.normalized();
  return alpha_a * Eigen::Matrix3d::Identity() + (alpha_c - alpha_a) * c * c.transpose();
}

Eigen::Matrix3d ThermalField::crystal_expansion(const Eigen::Quaterniond& crystal,
                                                const Eigen::Vector3d& alpha_abc) {
  const Eigen::Matrix3d r = crystal.normalized().toRotationMatrix();
  return r * alpha_abc.asDiagonal() * r.transpose();
}

void ThermalField::set_temperature(std::uint32_t slot, double kelvin) {
  if (!std::isfinite(kelvin))
    throw std::invalid_argument("set_temperature: not a finite temperature");
  thermal_[slot].temperature = kelvin;
}

void ThermalField::set_temperature(const std::vector<BodyInfo>& infos, double kelvin) {
  if (!std::isfinite(kelvin))
    throw std::invalid_argument("set_temperature: not a finite temperature");
  for (std::size_t i = 0; i < thermal_.size(); ++i) {
    if (infos[i].alive) thermal_[i].temperature = kelvin;
  }
}

void ThermalField::ramp_temperature(const std::vector<BodyInfo>& infos, double change,
                                    double target) {
  if (!std::isfinite(change) || !std::isfinite(target))
    throw std::invalid_argument("ramp_temperature: not a finite change or target");
  for (std::size_t i = 0; i < thermal_.size(); ++i) {
    BodyThermal& t = thermal_[i];
    if (!infos[i].alive || t.held) continue;
    const double next = t.temperature + change;
    t.temperature = change > 0.0 ? std::min(next, std::max(target, t.temperature))
                                 : std::max(next, std::min(target, t.temperature));
  }
}

void ThermalField::set_conduction(double conductivity, double heat_capacity) {
  if (!(conductivity >= 0.0) || !std::isfinite(conductivity))
    throw std::invalid_argument("set_conduction: the conductivity must be finite and >= 0");
  if (conductivity > 0.0 && !(heat_capacity > 0.0 && std::isfinite(heat_capacity)))
    throw std::invalid_argument("set_conduction: the heat capacity must be finite and > 0");
  conductivity_ = conductivity;
  heat_capacity_ = heat_capacity;
}

void ThermalField::add_mean_strain_rate(const std::vector<BodyState>& states,
                                        const std::vector<BodyInfo>& infos,
                                        const std::vector<RigidShape>& shapes, double h,
                                        Eigen::Matrix3d& gradient) const {
  Eigen::Matrix3d strain = Eigen::Matrix3d::Zero();
  double volume = 0.0;
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (!infos[i].alive) continue;
    const double v = shapes[infos[i].shape].volume;
    const double dt = thermal_[i].temperature - thermal_[i].bonded_at;
    volume += v;
    if (dt == 0.0) continue;
    const Eigen::Matrix3d r = states[i].q.toRotationMatrix();
    strain += v * dt * (r * thermal_[i].alpha * r.transpose());
  }
  if (volume > 0.0) gradient += strain / (volume * h);
}

void ThermalField::conduct(const std::vector<BodyState>& states, const std::vector<BodyInfo>& infos,
                           const std::vector<Bond>& bonds, double h) {
  // Explicit: each intact bond's heat over the step from the temperatures at its start,
  // summed per body in bond order (the same for any thread count).
  heat_.assign(states.size(), 0.0);
  for (const Bond& bd : bonds) {
    if (!bd.intact()) continue;
    const double d = (states[bd.b].x + bd.shift - states[bd.a].x).norm();
    const double q = conductivity_ * bd.transmission *
                     (thermal_[bd.b].temperature - thermal_[bd.a].temperature) / d * h;
    heat_[bd.a] += q;
    heat_[bd.b] -= q;
  }
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (!infos[i].alive || thermal_[i].held || heat_[i] == 0.0) continue;
    thermal_[i].temperature += heat_[i] / (infos[i].mass * heat_capacity_);
  }
}

}  // namespace cleave::physics
