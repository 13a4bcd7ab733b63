#include "physics/dem/bodies.hpp"

#include <bit>
#include <cmath>

#include "physics/dem/integrator.hpp"
#include "physics/dem/step_threads.hpp"

namespace cleave::physics {

using threads::kParallelMin;

std::uint32_t Bodies::add_shape(RigidShape shape) {
  shapes_.push_back(std::move(shape));
  return static_cast<std::uint32_t>(shapes_.size() - 1);
}

BodyId Bodies::add(std::uint32_t shape, double rho, const Eigen::Vector3d& x,
                   const Eigen::Quaterniond& q, const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                   int grain_id) {
  if (shape >= shapes_.size())
    throw std::out_of_range("add_body: no shape " + std::to_string(shape));
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
  if (!roles_.empty()) {
    // One process of several: a new body (a split's piece) is everywhere, as the whole
    // world's; its owner is settled by the re-partition this starts (split_body sets it
    // meanwhile).
    roles_.resize(states_.size(), Role::dormant);
    roles_[slot] = Role::dormant;
    changed_ = true;
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
  b.fixed = false;
  ++b.generation;
  BodyState& st = states_[slot];
  st = BodyState{};
  st.x = x;
  st.q = q.normalized();
  st.v = v;
  ++live_;
  set_angular_velocity(slot, w);
  return {slot, b.generation};
}

void Bodies::remove(BodyId id) {
  infos_[id.index].alive = false;
  free_slots_.push_back(id.index);
  --live_;
}

BodyId Bodies::id_at(std::uint32_t slot) const {
  if (slot >= infos_.size() || !infos_[slot].alive) {
    throw std::out_of_range("no live body in slot " + std::to_string(slot));
  }
  return {slot, infos_[slot].generation};
}

std::vector<BodyId> Bodies::ids() const {
  std::vector<BodyId> ids;
  for (std::uint32_t i = 0; i < infos_.size(); ++i) {
    if (infos_[i].alive) ids.push_back({i, infos_[i].generation});
  }
  return ids;
}

void Bodies::set_angular_velocity(std::uint32_t slot, const Eigen::Vector3d& w) {
  BodyState& s = states_[slot];
  const BodyInfo& b = infos_[slot];
  const Eigen::Vector3d w_body = s.q.conjugate() * w;
  s.L = s.q * b.inertia.cwiseProduct(w_body);
  s.w = w;
}

void Bodies::set_roles(std::vector<Role> roles) {
  if (!roles.empty() && roles.size() != states_.size())
    throw std::invalid_argument("set_roles: one role per body slot");
  roles_ = std::move(roles);
}

namespace {
/// Each thread's block of bodies, kDriftBatch at a time: `take(i)` says whether body i is
/// in (acting on it alone first, if need be), `run(batch, infos, n)` acts on a batch (the
/// batch drift and kick: the same bits as one body at a time).
template <class Take, class Run>
void in_batches(std::vector<BodyState>& states, const std::vector<BodyInfo>& infos, int nt,
                Take&& take, Run&& run) {
  const auto slots = static_cast<std::ptrdiff_t>(states.size());
#pragma omp parallel num_threads(nt) if (slots >= kParallelMin)
  {
    const threads::Block block = threads::thread_block(static_cast<std::size_t>(slots));
    BodyState* batch[kDriftBatch];
    const BodyInfo* batch_info[kDriftBatch];
    int queued = 0;
    for (std::size_t i = block.begin; i < block.end; ++i) {
      if (!take(i)) continue;
      batch[queued] = &states[i];
      batch_info[queued] = &infos[i];
      if (++queued == kDriftBatch) {
        run(batch, batch_info, queued);
        queued = 0;
      }
    }
    if (queued > 0) run(batch, batch_info, queued);
  }
}
}  // namespace

void Bodies::kick_drift(double h, int nt) {
  in_batches(
      states_, infos_, nt,
      [&](std::size_t i) {
        if (!infos_[i].alive || !owns(static_cast<std::uint32_t>(i))) return false;
        if (!infos_[i].fixed) kick_momenta(states_[i], infos_[i], 0.5 * h);
        return true;
      },
      [&](BodyState* const* s, const BodyInfo* const* b, int n) {
        drift(s, b, n, h);
      });  // sets w
}

void Bodies::closing_kick(double h, int nt) {
  in_batches(
      states_, infos_, nt,
      [&](std::size_t i) {
        return infos_[i].alive && !infos_[i].fixed && owns(static_cast<std::uint32_t>(i));
      },
      [&](BodyState* const* s, const BodyInfo* const* b, int n) { kick(s, b, n, 0.5 * h); });
}

void Bodies::hold_in_plane(const std::vector<std::uint32_t>& live) {
  // The momenta too, so that a body that had left the plane's motion (set by hand, or a
  // split piece whose principal axes round off the grain's) is put back on it: the kick
  // that follows derives w from L.
  for (const std::uint32_t i : live) {
    if (infos_[i].fixed) continue;
    BodyState& s = states_[i];
    s.f.z() = 0.0;
    s.tau.x() = 0.0;
    s.tau.y() = 0.0;
    s.v.z() = 0.0;
    s.L.x() = 0.0;
    s.L.y() = 0.0;
  }
}

void Bodies::apply_local_damping(double alpha, const std::vector<std::uint32_t>& live_slots,
                                 int nt) {
  const auto live = static_cast<std::ptrdiff_t>(live_slots.size());
  if (live < kParallelMin) nt = 1;
  // f_c -= alpha |f_c| sgn(v_c) where v_c is not zero; without branches (a settling body's
  // velocity components change sign at random, and the branches were mispredicted): the
  // damped value is made for every component and kept by a mask, the same bits.
  auto damp = [alpha](Eigen::Vector3d& f, const Eigen::Vector3d& v) {
    for (int c = 0; c < 3; ++c) {
      // alpha |f_c| times +1 or -1: the sign bit flipped where v_c is not positive (x (-1)
      // is exact, so the same bits).
      const std::uint64_t flip = static_cast<std::uint64_t>(!(v[c] > 0.0)) << 63;
      const double damped =
          f[c] - std::bit_cast<double>(std::bit_cast<std::uint64_t>(alpha * std::abs(f[c])) ^ flip);
      const std::uint64_t keep = std::uint64_t{0} - static_cast<std::uint64_t>(v[c] != 0.0);
      f[c] = std::bit_cast<double>((std::bit_cast<std::uint64_t>(damped) & keep) |
                                   (std::bit_cast<std::uint64_t>(f[c]) & ~keep));
    }
  };
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
  for (std::ptrdiff_t k = 0; k < live; ++k) {
    const std::uint32_t i = live_slots[static_cast<std::size_t>(k)];
    if (infos_[i].fixed) continue;
    damp(states_[i].f, states_[i].v);
    damp(states_[i].tau, states_[i].w);
  }
}

namespace {
double kinetic(const BodyState& s, const BodyInfo& b) {
  return 0.5 * b.mass * s.v.squaredNorm() + 0.5 * s.w.dot(s.L);
}
double potential(const BodyState& s, const BodyInfo& b, const Eigen::Vector3d& g) {
  return -b.mass * g.dot(s.x);
}
}  // namespace

double Bodies::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive) e += kinetic(states_[i], infos_[i]);
  }
  return e;
}

double Bodies::potential_energy(const Eigen::Vector3d& gravity) const {
  double e = 0.0;
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive) e += potential(states_[i], infos_[i], gravity);
  }
  return e;
}

ExactSum Bodies::owned_kinetic_energy() const {
  ExactSum e;
  for (std::uint32_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive && owns(i)) e.add(kinetic(states_[i], infos_[i]));
  }
  return e;
}

ExactSum Bodies::owned_potential_energy(const Eigen::Vector3d& gravity) const {
  ExactSum e;
  for (std::uint32_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive && owns(i)) e.add(potential(states_[i], infos_[i], gravity));
  }
  return e;
}

Eigen::Vector3d Bodies::linear_momentum() const {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive) p += infos_[i].mass * states_[i].v;
  }
  return p;
}

Eigen::Vector3d Bodies::angular_momentum() const {
  Eigen::Vector3d l = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive) continue;
    l += states_[i].L + states_[i].x.cross(infos_[i].mass * states_[i].v);
  }
  return l;
}

void Bodies::restore(std::vector<RigidShape> shapes, std::vector<BodyState> states,
                     std::vector<BodyInfo> infos, std::vector<std::uint32_t> free_slots,
                     std::size_t live) {
  shapes_ = std::move(shapes);
  states_ = std::move(states);
  infos_ = std::move(infos);
  free_slots_ = std::move(free_slots);
  live_ = live;
}

Fragment fragment_placement(const RigidShape& parent, const RigidShape& piece,
                            std::uint32_t shape) {
  Fragment f;
  f.shape = shape;
  // Both principal frames are given in the same shape coordinates.
  f.offset = parent.axes.transpose() * (piece.centroid - parent.centroid);
  f.turn = Eigen::Quaterniond(Eigen::Matrix3d(parent.axes.transpose() * piece.axes)).normalized();
  return f;
}

}  // namespace cleave::physics
