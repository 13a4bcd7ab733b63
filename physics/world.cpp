#include "physics/world.hpp"

#include <algorithm>
#include <tuple>
#include <stdexcept>
#include <string>

#include "physics/integrator.hpp"

namespace cleave::physics {

World::World(WorldSettings settings)
    : settings_(std::move(settings)), search_(settings_.search) {
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

std::size_t World::add_wall(Wall wall) {
  walls_.push_back(std::move(wall));
  forces_current_ = false;
  return walls_.size() - 1;
}

std::vector<BodyId> World::body_ids() const {
  std::vector<BodyId> ids;
  for (std::uint32_t i = 0; i < infos_.size(); ++i) {
    if (infos_[i].alive) ids.push_back({i, infos_[i].generation});
  }
  return ids;
}

void World::compute_forces() {
  live_slots_.clear();
  posed_.resize(states_.size());
  for (std::uint32_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive) continue;
    live_slots_.push_back(i);
    states_[i].f = infos_[i].mass * settings_.gravity;
    states_[i].tau.setZero();
    posed_[i].update(shapes_[infos_[i].shape], states_[i]);
  }
  for (auto& w : walls_) w.reaction.setZero();
  records_.clear();
  next_history_.clear();
  history_cursor_ = 0;
  body_contacts();
  wall_contacts();
  std::swap(history_, next_history_);
  forces_current_ = true;
}

void World::body_contacts() {
  spheres_.clear();
  for (std::uint32_t slot : live_slots_) {
    spheres_.push_back({states_[slot].x, shapes_[infos_[slot].shape].bounding_radius()});
  }
  search_.find_pairs(spheres_, 0.0, pairs_);
  for (const auto& [i, j] : pairs_) {
    const std::uint32_t a = live_slots_[i], b = live_slots_[j];
    feature_buffer_.clear();
    polyhedron_contacts(posed_[a], posed_[b], 0.0, feature_buffer_);
    // Ascending feature order within the pair keeps the keys ascending (see ContactKey).
    std::sort(feature_buffer_.begin(), feature_buffer_.end(), [](const auto& x, const auto& y) {
      return std::tie(x.feature_a, x.feature_b) < std::tie(y.feature_a, y.feature_b);
    });
    for (const auto& fc : feature_buffer_) apply(a, b, false, fc.contact, fc.feature_a, fc.feature_b);
  }
}

void World::wall_contacts() {
  for (std::uint32_t w = 0; w < walls_.size(); ++w) {
    const Wall& wall = walls_[w];
    for (std::uint32_t slot : live_slots_) {
      const PosedShape& p = posed_[slot];
      const double reach = shapes_[infos_[slot].shape].bounding_radius();
      // Broad test against the wall's surface (planes) or axis (cylinders).
      if (wall.kind != Wall::Kind::cylinder) {
        if (wall.normal.dot(p.centre - wall.origin) > reach) continue;
      } else {
        const Eigen::Vector3d rel = p.centre - wall.origin;
        const double t = std::clamp(rel.dot(wall.normal), 0.0, wall.length);
        if ((rel - t * wall.normal).norm() > reach + wall.radius) continue;
      }
      for (std::uint32_t v = 0; v < p.vertices.size(); ++v) {
        if (auto c = wall.sphere_contact(p.vertices[v], p.radius)) {
          apply(w, slot, true, *c, 0, feature_code(FeatureKind::vertex, v));
        }
      }
      if (wall.kind == Wall::Kind::cylinder) {
        const auto& edges = p.primitives->edges;
        for (std::uint32_t e = 0; e < edges.size(); ++e) {
          if (auto c = wall.edge_contact(p.vertices[edges[e].a], p.vertices[edges[e].b], p.radius)) {
            apply(w, slot, true, *c, 0, feature_code(FeatureKind::edge, e));
          }
        }
      }
    }
  }
}

const ContactHistory* World::previous_history(const ContactKey& key) {
  // Keys arrive in ascending order: walk forward; fall back to a binary search if not.
  if (history_cursor_ > 0 && history_cursor_ <= history_.size() &&
      key < history_[history_cursor_ - 1].key) {
    history_cursor_ = 0;
  }
  if (history_cursor_ == 0 && !history_.empty() && key > history_.front().key) {
    history_cursor_ = static_cast<std::size_t>(
        std::lower_bound(history_.begin(), history_.end(), key,
                         [](const HistoryEntry& e, const ContactKey& k) { return e.key < k; }) -
        history_.begin());
  }
  while (history_cursor_ < history_.size() && history_[history_cursor_].key < key) ++history_cursor_;
  if (history_cursor_ < history_.size() && history_[history_cursor_].key == key) {
    return &history_[history_cursor_].history;
  }
  return nullptr;
}

void World::apply(std::uint32_t a, std::uint32_t b, bool wall, const PrimitiveContact& c,
                  std::uint32_t feature_a, std::uint32_t feature_b) {
  if (c.penetration <= 0.0) return;
  BodyState& sb = states_[b];
  const BodyInfo& ib = infos_[b];
  ContactKinematics k;
  k.normal = c.normal;
  k.overlap = c.penetration;
  const Eigen::Vector3d rb = c.point - sb.x;
  Eigen::Vector3d va_point, wa;
  double m_crit, i_crit;
  if (wall) {
    va_point = walls_[a].velocity;
    wa.setZero();
    m_crit = ib.mass;
    i_crit = ib.inertia.minCoeff();
  } else {
    const BodyState& sa = states_[a];
    const BodyInfo& ia = infos_[a];
    va_point = sa.v + sa.w.cross(c.point - sa.x);
    wa = sa.w;
    m_crit = ia.mass * ib.mass / (ia.mass + ib.mass);
    const double i1 = ia.inertia.minCoeff(), i2 = ib.inertia.minCoeff();
    i_crit = i1 * i2 / (i1 + i2);
  }
  k.velocity = sb.v + sb.w.cross(rb) - va_point;
  k.spin = sb.w - wa;
  k.m_crit = m_crit;
  k.i_crit = i_crit;
  k.lever = posed_[b].radius;
  const ContactKey key{wall ? (a | kWallFlag) : a, b, feature_a, feature_b};
  ContactHistory h;
  if (const ContactHistory* old = previous_history(key)) h = *old;
  const ContactParams& params = wall ? settings_.particle_wall : settings_.particle_particle;
  const ContactForce f = contact_force(params, k, h, settings_.dt);
  next_history_.push_back({key, h});
  sb.f += f.force;
  sb.tau += rb.cross(f.force) + f.moment;
  if (wall) {
    walls_[a].reaction -= f.force;
  } else {
    BodyState& sa = states_[a];
    sa.f -= f.force;
    sa.tau -= (c.point - sa.x).cross(f.force) + f.moment;
  }
  records_.push_back({a, b, wall, c.point, c.normal, c.penetration, f.force});
}

void World::step() {
  const double h = settings_.dt;
  if (!forces_current_) compute_forces();
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive) continue;
    kick(states_[i], infos_[i], 0.5 * h);
    drift(states_[i], infos_[i], h);
  }
  for (auto& w : walls_) w.origin += h * w.velocity;
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
