#include "physics/world.hpp"

#include <stdexcept>
#include <string>

#include "physics/integrator.hpp"

namespace cleave::physics {

World::World(WorldSettings settings) : settings_(std::move(settings)) {
  if (!(settings_.dt > 0.0)) throw std::invalid_argument("time step must be positive");
}

std::uint32_t World::add_shape(RigidShape shape) {
  shapes_.push_back(std::move(shape));
  return static_cast<std::uint32_t>(shapes_.size() - 1);
}

BodyId World::add_body(std::uint32_t shape, double rho, const Eigen::Vector3d& x,
                       const Eigen::Quaterniond& q, const Eigen::Vector3d& v,
                       const Eigen::Vector3d& w, int grain_id) {
  if (shape >= shapes_.size()) throw std::out_of_range("add_body: no shape " + std::to_string(shape));
  if (!(rho > 0.0)) throw std::invalid_argument("add_body: density must be positive");
  std::uint32_t slot;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = static_cast<std::uint32_t>(states_.size());
    states_.emplace_back();
    infos_.emplace_back();
  }
  const RigidShape& s = shapes_[shape];
  BodyInfo& b = infos_[slot];
  b.shape = shape;
  b.mass = rho * s.volume;
  b.inv_mass = 1.0 / b.mass;
  b.inertia = rho * s.principal_moments;
  b.inv_inertia = b.inertia.cwiseInverse();
  b.grain_id = grain_id;
  b.alive = true;
  ++b.generation;
  BodyState& st = states_[slot];
  st = BodyState{};
  st.x = x;
  st.q = q.normalized();
  st.v = v;
  ++live_;
  forces_current_ = false;
  const BodyId id{slot, b.generation};
  set_angular_velocity(id, w);
  return id;
}

void World::remove_body(BodyId id) {
  if (!contains(id)) throw std::out_of_range("remove_body: stale or invalid body id");
  infos_[id.index].alive = false;
  free_slots_.push_back(id.index);
  --live_;
}

bool World::contains(BodyId id) const {
  return id.index < infos_.size() && infos_[id.index].alive &&
         infos_[id.index].generation == id.generation;
}

const BodyState& World::state(BodyId id) const {
  if (!contains(id)) throw std::out_of_range("stale or invalid body id");
  return states_[id.index];
}
BodyState& World::state(BodyId id) {
  if (!contains(id)) throw std::out_of_range("stale or invalid body id");
  return states_[id.index];
}
const BodyInfo& World::info(BodyId id) const {
  if (!contains(id)) throw std::out_of_range("stale or invalid body id");
  return infos_[id.index];
}

void World::set_angular_velocity(BodyId id, const Eigen::Vector3d& w) {
  BodyState& s = state(id);
  const BodyInfo& b = infos_[id.index];
  const Eigen::Vector3d w_body = s.q.conjugate() * w;
  s.L = s.q * b.inertia.cwiseProduct(w_body);
  s.w = w;
}

void World::compute_forces() {
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive) continue;
    states_[i].f = infos_[i].mass * settings_.gravity;
    states_[i].tau.setZero();
  }
  forces_current_ = true;
}

void World::step() {
  const double h = settings_.dt;
  if (!forces_current_) compute_forces();
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive) continue;
    kick(states_[i], infos_[i], 0.5 * h);
    drift(states_[i], infos_[i], h);
  }
  compute_forces();
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive) continue;
    kick(states_[i], infos_[i], 0.5 * h);
  }
  time_ += h;
  ++steps_;
}

double World::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive) continue;
    const BodyState& s = states_[i];
    e += 0.5 * infos_[i].mass * s.v.squaredNorm() + 0.5 * s.w.dot(s.L);
  }
  return e;
}

double World::potential_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive) e -= infos_[i].mass * settings_.gravity.dot(states_[i].x);
  }
  return e;
}

Eigen::Vector3d World::linear_momentum() const {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive) p += infos_[i].mass * states_[i].v;
  }
  return p;
}

Eigen::Vector3d World::angular_momentum() const {
  Eigen::Vector3d l = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive) continue;
    l += states_[i].L + states_[i].x.cross(infos_[i].mass * states_[i].v);
  }
  return l;
}

}  // namespace cleave::physics
