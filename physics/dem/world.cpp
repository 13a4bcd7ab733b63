#include "physics/dem/world.hpp"
#include "physics/bonds/bond_batch.hpp"
#include "physics/bonds/grain_stress.hpp"
#include "physics/bonds/vec3.hpp"

#include <algorithm>
#include <bit>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <tuple>
#include <type_traits>
#include <stdexcept>
#include <string>

#include "physics/dem/gallop.hpp"
#include "physics/dem/integrator.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace cleave::physics {

World::World(WorldSettings settings)
    : settings_(std::move(settings)), search_(settings_.search) {
  if (!(settings_.dt > 0.0)) throw std::invalid_argument("time step must be positive");
  if (!(settings_.search_skin >= 0.0)) throw std::invalid_argument("search skin must be >= 0");
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
    thermal_.emplace_back();
  }
  thermal_[slot] = BodyThermal{};
  if (!roles_.empty()) {
    // One process of several: a new body (a split's piece) is everywhere, as the whole
    // world's; its owner is settled by the re-partition this starts (split_body sets it
    // meanwhile).
    roles_.resize(states_.size(), Role::dormant);
    roles_[slot] = Role::dormant;
    bodies_changed_ = true;
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
  forces_current_ = false;
  pairs_current_ = false;
  const BodyId id{slot, b.generation};
  set_angular_velocity(id, w);
  return id;
}

void World::remove_body(BodyId id) {
  if (!contains(id)) throw std::out_of_range("remove_body: stale or invalid body id");
  infos_[id.index].alive = false;
  free_slots_.push_back(id.index);
  --live_;
  pairs_current_ = false;
  // Contact history is keyed by slot: a body that later takes this slot must not inherit
  // the removed body's springs.
  const std::uint32_t slot = id.index;
  std::erase_if(history_, [slot](const HistoryEntry& e) {
    return ((e.key.a & kWallFlag) == 0 && e.key.a == slot) || e.key.b == slot;
  });
  std::erase_if(bonds_, [slot](const Bond& bd) { return bd.a == slot || bd.b == slot; });
  std::erase_if(offsets_, [slot](const PairOffset& o) { return o.a == slot || o.b == slot; });
}

Fragment fragment_placement(const RigidShape& parent, const RigidShape& piece, std::uint32_t shape) {
  Fragment f;
  f.shape = shape;
  // Both principal frames are given in the same shape coordinates.
  f.offset = parent.axes.transpose() * (piece.centroid - parent.centroid);
  f.turn = Eigen::Quaterniond(Eigen::Matrix3d(parent.axes.transpose() * piece.axes)).normalized();
  return f;
}

std::vector<BodyId> World::split_body(BodyId parent, const std::vector<Fragment>& pieces) {
  if (!contains(parent)) throw std::out_of_range("split_body: stale or invalid body id");
  if (pieces.empty()) throw std::invalid_argument("split_body: no pieces");
  const BodyState ps = states_[parent.index];
  const BodyInfo pi = infos_[parent.index];
  const BodyThermal pt = thermal_[parent.index];
  const double rho = pi.mass / shapes_[pi.shape].volume;
  const std::uint32_t old_slot = parent.index;
  // The parent's bonds, taken out before its slot is freed.
  std::vector<Bond> moved;
  // Neighbours whose overlap with the parent counted from a stored value: every piece
  // gets that value with them (a piece may touch a neighbour its bond did not follow).
  std::vector<std::pair<std::uint32_t, double>> stored;
  auto remember = [&](std::uint32_t other, double overlap) {
    if (overlap > 0.0) stored.emplace_back(other, overlap);
  };
  for (const Bond& bd : bonds_) {
    if (bd.a != old_slot && bd.b != old_slot) continue;
    moved.push_back(bd);
    double most = 0.0;
    for (const auto& o : bd.initial) most = std::max(most, o.overlap);
    remember(bd.a == old_slot ? bd.b : bd.a, most);
  }
  for (const PairOffset& o : offsets_) {
    if (o.a == old_slot) remember(o.b, o.overlap);
    if (o.b == old_slot) remember(o.a, o.overlap);
  }
  const Role parent_role = role(old_slot);
  remove_body(parent);  // drops the parent's bonds, offsets and contact history
  std::vector<BodyId> ids;
  for (const Fragment& f : pieces) {
    if (f.shape >= shapes_.size()) throw std::out_of_range("split_body: no shape " + std::to_string(f.shape));
    const Eigen::Vector3d x = ps.x + ps.q * f.offset;
    const BodyId id = add_body(f.shape, rho, x, ps.q * f.turn, ps.v + ps.w.cross(x - ps.x), ps.w,
                               pi.grain_id);
    infos_[id.index].fixed = pi.fixed;
    if (!roles_.empty()) roles_[id.index] = parent_role;  // the parent's owner holds its pieces
    // The piece is of the parent's material: its temperature, and its expansion tensor
    // turned into the piece's own frame.
    const Eigen::Matrix3d turn = f.turn.toRotationMatrix();
    thermal_[id.index] = pt;
    thermal_[id.index].alpha = turn.transpose() * pt.alpha * turn;
    thermal_[id.index].held = false;
    // It goes on expanding about the parent's centre: its bonds' and contacts' thermal gaps
    // carry on from where the parent's were (about its own centroid they would jump by
    // alpha dT times the distance between the two centroids at once).
    thermal_[id.index].centre = states_[id.index].q.conjugate() * (ps.x + ps.q * pt.centre - x);
    ids.push_back(id);
  }
  // Each bond follows its material point to the piece that holds it.
  for (Bond bd : moved) {
    const bool parent_is_a = bd.a == old_slot;
    const Eigen::Vector3d arm = parent_is_a ? bd.arm_a : bd.arm_b;
    const Eigen::Vector3d normal = parent_is_a ? bd.normal_a : bd.normal_b;
    const Eigen::Vector3d point = ps.x + ps.q * arm;  // world, at the split
    std::size_t best = 0;
    double best_depth = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const BodyState& s = states_[ids[k].index];
      const auto& faces = shapes_[infos_[ids[k].index].shape].primitives.faces;
      const Eigen::Vector3d local = s.q.conjugate() * (point - s.x);
      double depth = -std::numeric_limits<double>::infinity();  // largest signed distance
      for (const auto& face : faces) depth = std::max(depth, face.normal.dot(local) - face.offset);
      if (depth < best_depth) {
        best_depth = depth;
        best = k;
      }
    }
    const BodyState& s = states_[ids[best].index];
    const std::uint32_t slot = ids[best].index;
    const Eigen::Vector3d new_arm = s.q.conjugate() * (point - s.x);
    const Eigen::Vector3d new_normal = s.q.conjugate() * (ps.q * normal);
    // A beam's end stays the material point it was (the parent's centroid at bonding),
    // now of the piece; its directions turn into the piece's frame.
    auto into_piece = [&](const Eigen::Vector3d& v) -> Eigen::Vector3d { return s.q.conjugate() * (ps.q * v); };
    Bond::Beam& beam = bd.beam;
    if (parent_is_a) {
      bd.a = slot;
      bd.arm_a = new_arm;
      bd.normal_a = new_normal;
      beam.end_a = s.q.conjugate() * (ps.x + ps.q * beam.end_a - s.x);
      beam.axis_a = into_piece(beam.axis_a);
      beam.across_a = into_piece(beam.across_a);
    } else {
      bd.b = slot;
      bd.arm_b = new_arm;
      bd.normal_b = new_normal;
      beam.end_b = s.q.conjugate() * (ps.x + ps.q * beam.end_b - s.x);
      beam.axis_b = into_piece(beam.axis_b);
      beam.across_b = into_piece(beam.across_b);
    }
    if (bd.a > bd.b) {
      // A and B trade places: the normal turns round, and the loads on B become those on A.
      std::swap(bd.a, bd.b);
      std::swap(bd.arm_a, bd.arm_b);
      std::swap(bd.normal_a, bd.normal_b);
      bd.normal_a = -bd.normal_a;
      bd.normal_b = -bd.normal_b;
      bd.normal = -bd.normal;
      bd.state.shear = -bd.state.shear;
      bd.state.bending = -bd.state.bending;
      bd.force = -bd.force;
      bd.moment = -bd.moment;
      // In a periodic cell A's image is now the one joined: the other way round.
      bd.image = -bd.image;
      bd.shift = -bd.shift;
      bd.point += bd.shift;  // the same place, seen from the new A
      // The beam's axis runs from A to B: it turns round too (the twist reads the same).
      std::swap(beam.end_a, beam.end_b);
      std::swap(beam.axis_a, beam.axis_b);
      std::swap(beam.across_a, beam.across_b);
      beam.axis_a = -beam.axis_a;
      beam.axis_b = -beam.axis_b;
    }
    // The new piece's features are numbered anew: the largest stored overlap stands for all.
    double stored = 0.0;
    for (const auto& o : bd.initial) stored = std::max(stored, o.overlap);
    bd.initial.clear();
    if (stored > 0.0) bd.initial.push_back({Bond::kAnyFeature, Bond::kAnyFeature, stored});
    bonds_.push_back(std::move(bd));
  }
  std::sort(bonds_.begin(), bonds_.end(),
            [](const Bond& x, const Bond& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
  body_bonds_stale_ = true;
  // The pieces meet along the new crack with their dilations overlapping by the sum of
  // their radii: that overlap, and the parent's stored ones, count as zero.
  auto offset = [&](std::uint32_t a, std::uint32_t b, double overlap) {
    offsets_.push_back({std::min(a, b), std::max(a, b), overlap});
  };
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const double ri = shapes_[infos_[ids[i].index].shape].primitives.dilation_radius;
    for (std::size_t j = i + 1; j < ids.size(); ++j) {
      const double rj = shapes_[infos_[ids[j].index].shape].primitives.dilation_radius;
      offset(ids[i].index, ids[j].index, ri + rj);
    }
    for (const auto& [other, overlap] : stored) offset(ids[i].index, other, overlap);
  }
  std::sort(offsets_.begin(), offsets_.end(), [](const PairOffset& x, const PairOffset& y) {
    return std::tie(x.a, x.b, x.overlap) < std::tie(y.a, y.b, y.overlap);
  });
  // One entry per pair: the largest.
  std::vector<PairOffset> merged;
  for (const PairOffset& o : offsets_) {
    if (!merged.empty() && merged.back().a == o.a && merged.back().b == o.b) {
      merged.back().overlap = std::max(merged.back().overlap, o.overlap);
    } else {
      merged.push_back(o);
    }
  }
  offsets_ = std::move(merged);
  forces_current_ = false;
  return ids;
}

void World::set_fixed(BodyId id, bool fixed) {
  if (!contains(id)) throw std::out_of_range("set_fixed: stale or invalid body id");
  infos_[id.index].fixed = fixed;
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

BodyId World::id_at(std::uint32_t slot) const {
  if (slot >= infos_.size() || !infos_[slot].alive) {
    throw std::out_of_range("no live body in slot " + std::to_string(slot));
  }
  return {slot, infos_[slot].generation};
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

namespace {
/// Loops shorter than this run on one thread: for small worlds the cost of waking threads
/// every step exceeds the work (and oversubscribed cores make it far worse).
constexpr std::ptrdiff_t kParallelMin = 512;
/// Body slots per piece of the wall contacts (World::wall_contacts).
constexpr std::size_t kWallPiece = 512;
/// Pairs per chunk of the narrow phase (body_contacts); join_pending finds the chunks' lists
/// by it.
constexpr std::size_t kPairChunk = 256;

/// The contiguous block [begin, end) of n items that the calling thread takes, split over
/// the threads actually running (OpenMP may give fewer than asked): blocks follow thread
/// order, so joining them in order keeps the items' order.
struct Block {
  std::size_t thread, begin, end;
};
Block thread_block(std::size_t n) {
#ifdef _OPENMP
  const auto t = static_cast<std::size_t>(omp_get_thread_num());
  const auto teams = static_cast<std::size_t>(omp_get_num_threads());
#else
  const std::size_t t = 0, teams = 1;
#endif
  return {t, n * t / teams, n * (t + 1) / teams};
}

/// Broad test of a body (centre, bounding radius) against a wall's surface (planes) or axis
/// (cylinders): false when no point of it can touch.
bool wall_within_reach(const Wall& wall, const Eigen::Vector3d& centre, double reach) {
  if (wall.kind != Wall::Kind::cylinder) return !(wall.normal.dot(centre - wall.origin) > reach);
  const Eigen::Vector3d rel = centre - wall.origin;
  const double s = std::clamp(rel.dot(wall.normal), 0.0, wall.length);
  return !((rel - s * wall.normal).norm() > reach + wall.radius);
}

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

/// Bit of wall w in a body's wall_reach_ word: walls from 31 on share the last bit.
std::uint32_t wall_bit(std::size_t w) { return 1u << std::min<std::size_t>(w, 31); }

/// Items (pairs, bonds) listed by body: `ends(k)` gives item k's two slots (A, B); body i's
/// entries are list[start[i] .. start[i + 1]), each (k << 1) | (1 if it is the item's B), in
/// ascending k (a counting sort taking the items in order).
template <class Ends>
void list_by_body(std::size_t slots, std::size_t items, Ends&& ends, std::vector<std::uint32_t>& start,
                  std::vector<std::uint32_t>& list) {
  start.assign(slots + 1, 0);
  for (std::size_t k = 0; k < items; ++k) {
    const auto [a, b] = ends(k);
    ++start[a + 1];
    ++start[b + 1];
  }
  for (std::size_t i = 0; i < slots; ++i) start[i + 1] += start[i];
  list.resize(start.back());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < items; ++k) {
    const auto [a, b] = ends(k);
    const auto code = static_cast<std::uint32_t>(k << 1);
    list[fill[a]++] = code;
    list[fill[b]++] = code | 1u;
  }
}

int thread_count(int wanted) {
#ifdef _OPENMP
  return wanted > 0 ? wanted : omp_get_max_threads();
#else
  (void)wanted;
  return 1;
#endif
}
}  // namespace

const char* to_string(StepPhase phase) {
  static constexpr const char* kNames[kStepPhases] = {"kick_drift", "poses", "pair_search", "plan",
                                                      "narrow", "walls", "contact_law", "contact_sums",
                                                      "bond_law", "bond_sums", "damping", "closing_kick"};
  const auto k = static_cast<std::size_t>(phase);
  return k < kStepPhases ? kNames[k] : "unknown";
}

namespace {
std::int64_t clock_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

void World::set_timing(bool on) {
  timing_ = on;
  if (on) timings_ = StepTimings{};
}

void World::lap_to(StepPhase phase) {
  const std::int64_t now = clock_ns();
  timings_.seconds[static_cast<std::size_t>(phase)] += 1e-9 * static_cast<double>(now - lap_ns_);
  lap_ns_ = now;
}

void World::compute_forces() {
  if (domain_) domain_->before_forces(*this);  // ghosts current, roles set
  breaks_at_step_ = breaks_.size();
  // The diagonals of eq. 2.17's sums along with the forces (stress_sum_diagonals), when
  // asked for; not across processes (the ghosts' bonds change after the sums).
  stress_sums_current_ = stress_diagonals_current_ = false;
  summing_stress_ = domain_ == nullptr && want_stress_sums_;
  want_stress_sums_ = false;
  if (summing_stress_) stress_diagonals_.resize(states_.size());
  live_slots_.clear();
  for (std::uint32_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive && role(i) != Role::dormant) live_slots_.push_back(i);
  }
  posed_.resize(states_.size());
  wall_reach_.resize(states_.size());
  const int nt = thread_count(settings_.threads);
  const auto live = static_cast<std::ptrdiff_t>(live_slots_.size());
  // The neighbour search's pairs hold every pair that can touch until some point of some
  // body has moved half the skin since the search (its centre's move plus, for the turn,
  // 2 |q - q0| times its bounding radius: the pairs were kept by their boxes, which turn
  // with the body): the bodies that have are counted here, with the poses.
  const bool searched = pairs_current_ && searched_at_.size() == live_slots_.size() &&
                        searched_q_.size() == live_slots_.size();
  double limit = 0.5 * skin_;
  if (cell_on_) {
    // A pair's image moves with the cell vectors (by at most the sum of their changes).
    limit -= 0.5 * (cell_.vectors() - cell_at_search_).colwise().norm().sum();
  }
  const bool lazy = settings_.manifold_tolerance > 0.0;
  std::size_t moved = 0;
#pragma omp parallel for num_threads(nt) schedule(static) if (live >= kParallelMin) reduction(+ : moved)
  for (std::ptrdiff_t k = 0; k < live; ++k) {
    const std::uint32_t i = live_slots_[static_cast<std::size_t>(k)];
    states_[i].f = infos_[i].mass * settings_.gravity;
    states_[i].tau.setZero();
    // With manifolds, only the bodies a search or a wall reads get their vertices and
    // planes (body_contacts); the frame is all the carried contacts need.
    if (lazy) {
      posed_[i].update_frame(shapes_[infos_[i].shape], states_[i]);
    } else {
      posed_[i].update(shapes_[infos_[i].shape], states_[i]);
    }
    // The walls that may touch it (walls have moved for this step already).
    std::uint32_t reach = 0;
    const double bounding = shapes_[infos_[i].shape].bounding_radius();
    for (std::size_t w = 0; w < walls_.size(); ++w) {
      if (wall_within_reach(walls_[w], posed_[i].centre, bounding)) reach |= wall_bit(w);
    }
    wall_reach_[i] = reach;
    if (searched) {
      const auto j = static_cast<std::size_t>(k);
      const Eigen::Vector4d q = states_[i].q.coeffs(), q0 = searched_q_[j].coeffs();
      const double turn = std::sqrt(std::min((q - q0).squaredNorm(), (q + q0).squaredNorm()));
      const double reach = (states_[i].x - searched_at_[j]).norm() +
                           2.0 * shapes_[infos_[i].shape].bounding_radius() * turn;
      moved += !(reach < limit);
    }
  }
  for (auto& w : walls_) w.reaction.setZero();
  lap(StepPhase::poses);
  body_contacts(nt, !searched || moved > 0 || !(limit > 0.0));
  lap(StepPhase::narrow);
  wall_contacts(nt);
  join_pending();
  lap(StepPhase::walls);
  evaluate_and_apply(nt);
  bond_forces(nt);
  lap(StepPhase::bond_sums);
  summed_ = true;
  stress_diagonals_current_ = summing_stress_;
  // The temperatures the bonds (and a periodic cell) have followed up to now.
  if (thermal_on_) {
    for (BodyThermal& t : thermal_) t.bonded_at = t.temperature;
  }
  if (bond_params_.criterion != BondCriterion::limits && !bonds_.empty() && !bonds_held_) break_by_stress();
  if (settings_.in_plane) hold_in_plane();
  if (settings_.local_damping > 0.0) apply_local_damping(nt);
  if (domain_) domain_->after_forces(*this);
  lap(StepPhase::damping);
  summed_ = false;
  forces_current_ = true;
}

void World::set_domain(Domain* domain, std::vector<Role> roles) {
  domain_ = domain;
  set_roles(std::move(roles));
}

void World::set_roles(std::vector<Role> roles) {
  if (!roles.empty() && roles.size() != states_.size())
    throw std::invalid_argument("set_roles: one role per body slot");
  roles_ = std::move(roles);
  // Another set of bodies here: the pair list and its caches are searched afresh.
  pairs_current_ = false;
  near_.clear();
}

std::vector<World::WallForceAt> World::wall_forces() const {
  std::vector<WallForceAt> out;
  for_pending(wall_contacts_begin(), pending_count(), [&](std::size_t k, const Pending& p) {
    if ((p.key.a & kWallFlag) != 0) out.push_back({p.key.a & ~kWallFlag, p.key.b, k, forces_[k].force});
  });
  return out;
}

std::size_t World::owned_contact_count() const {
  std::size_t n = 0;
  for_pending(0, pending_count(), [&](std::size_t, const Pending& p) {
    const bool wall = (p.key.a & kWallFlag) != 0;
    n += owns(wall ? p.key.b : p.key.a);
  });
  return n;
}

void World::body_contacts(int nt, bool stale) {
  // Neighbour search with a Verlet skin (see compute_forces).
  if (stale) {
    spheres_.clear();
    double smallest = std::numeric_limits<double>::infinity();
    for (std::uint32_t slot : live_slots_) {
      const double r = shapes_[infos_[slot].shape].bounding_radius();
      spheres_.push_back({states_[slot].x, r});
      smallest = std::min(smallest, r);
    }
    skin_ = live_slots_.empty() ? 0.0 : settings_.search_skin * smallest;
    // The manifolds are the pairs' and follow them to the new list (both are sorted) when no
    // body came or went; otherwise they are searched afresh.
    std::vector<BodyPair> old_pairs;
    std::vector<ContactManifold> old_manifolds;
    if (settings_.manifold_tolerance > 0.0 && manifold_slots_ == live_slots_) {
      old_pairs = pairs_;
      old_manifolds = std::move(manifolds_);
    }
    find_body_pairs(search_, spheres_, skin_, pairs_);
    if (cell_on_) {
      pair_image_.resize(pairs_.size());
      for (std::size_t p = 0; p < pairs_.size(); ++p)
        pair_image_[p] = cell_.nearest_image(states_[live_slots_[pairs_[p].first]].x,
                                             states_[live_slots_[pairs_[p].second]].x);
      cell_at_search_ = cell_.vectors();
    }
    // Bounding spheres are loose around thick or long prisms (a 5 mm thick grain of 0.6 mm
    // side reaches 2.6 mm round): the pairs whose dilated boxes are a skin apart along some
    // axis are dropped; until the next search no point moves half the skin, so they cannot
    // meet. The contacts are the same, in the same order (pairs stay sorted).
    if (settings_.manifold_tolerance > 0.0)
      for (std::uint32_t slot : live_slots_) posed_[slot].update_geometry();  // boxes of all
    std::size_t kept = 0;
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      const PosedShape& a = posed_[live_slots_[pairs_[p].first]];
      const PosedShape& b = posed_[live_slots_[pairs_[p].second]];
      const double reach = a.radius + b.radius + skin_;
      Eigen::Vector3d b_lo = b.lo, b_hi = b.hi;
      if (cell_on_ && !pair_image_[p].isZero()) {
        const Eigen::Vector3d t = cell_.shift(pair_image_[p]);
        b_lo += t;
        b_hi += t;
      }
      if (((a.lo.array() - reach > b_hi.array()) || (b_lo.array() - reach > a.hi.array())).any()) continue;
      // One process of a decomposition: the pairs of two ghosts are their owners' to evaluate.
      if (!roles_.empty() && !owns(live_slots_[pairs_[p].first]) && !owns(live_slots_[pairs_[p].second])) continue;
      if (cell_on_) pair_image_[kept] = pair_image_[p];
      pairs_[kept++] = pairs_[p];
    }
    pairs_.resize(kept);
    body_pairs_stale_ = true;
    if (cell_on_) pair_image_.resize(kept);
    manifolds_.clear();
    if (settings_.manifold_tolerance > 0.0) {
      manifolds_.resize(pairs_.size());
      std::size_t j = 0;
      for (std::size_t i = 0; i < pairs_.size() && j < old_pairs.size(); ++i) {
        while (j < old_pairs.size() && old_pairs[j] < pairs_[i]) ++j;
        if (j < old_pairs.size() && old_pairs[j] == pairs_[i]) manifolds_[i] = std::move(old_manifolds[j]);
      }
      manifold_slots_ = live_slots_;
    }
    held_.clear();  // made again from the manifolds below
    near_.clear();
    searched_at_.clear();
    searched_q_.clear();
    for (std::uint32_t slot : live_slots_) {
      searched_at_.push_back(states_[slot].x);
      searched_q_.push_back(states_[slot].q);
    }
    pairs_current_ = true;
    lap(StepPhase::pair_search);
  }
  // The pairs in chunks of consecutive pairs, handed to the threads as they come free (the
  // cost of a pair varies a hundredfold); the chunks' contacts are joined in chunk order,
  // so the contact list (and everything after it) is the same for any number of threads.
  const std::size_t n = pairs_.size();
  if (static_cast<std::ptrdiff_t>(n) < kParallelMin) nt = 1;
  constexpr std::size_t kChunk = kPairChunk;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  if (chunk_pending_.size() < chunks) chunk_pending_.resize(chunks);
  if (cell_on_ && chunk_shift_.size() < chunks) chunk_shift_.resize(chunks);
  parts_.clear();
  for (std::size_t chunk = 0; chunk < chunks; ++chunk) parts_.push_back(&chunk_pending_[chunk].list);
  // Each pair's near features (narrow_phase.hpp), kept with the pair list: the search over
  // them gives what the full search would, bit for bit, and skips what cannot touch.
  const bool cached = settings_.feature_skin > 0.0;
  if (cached) near_.resize(n);
  const bool manifolds = settings_.manifold_tolerance > 0.0;
  if (manifolds && manifolds_.size() != n) manifolds_.assign(n, ContactManifold{});
  if (manifolds && held_.size() != n) {
    held_.resize(n);
    for (std::size_t p = 0; p < n; ++p) held_[p] = manifolds_[p].margin > 0.0;
  }
  if (manifolds) {
    plan_pairs(nt);
    lap(StepPhase::plan);
  }
  pair_first_.resize(n);
#pragma omp parallel num_threads(nt) if (nt > 1)
  {
    std::vector<FeatureContact> features;
    PosedShape image;  // B's image across a periodic face
#pragma omp for schedule(dynamic, 1)
    for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
      auto& out = chunk_pending_[chunk].list;
      out.clear();
      if (cell_on_) chunk_shift_[chunk].list.clear();
      const std::size_t begin = chunk * kChunk, end = std::min(n, begin + kChunk);
      for (std::size_t p = begin; p < end; ++p) {
        const std::uint32_t a = live_slots_[pairs_[p].first], b = live_slots_[pairs_[p].second];
        pair_first_[p] = static_cast<std::uint32_t>(out.size());
        features.clear();
        if (cell_on_) {
          // Every contact of the pair, in the pair's order, against B's image (searched in
          // full: the feature cache follows B itself, not its image; no manifolds).
          const bool shifted = !pair_image_[p].isZero();
          const Eigen::Vector3d t = shifted ? cell_.shift(pair_image_[p]) : Eigen::Vector3d::Zero();
          if (shifted) {
            shifted_copy(posed_[b], t, image);
            polyhedron_contacts(posed_[a], image, 0.0, features);
          } else if (cached) {
            polyhedron_contacts(posed_[a], posed_[b], settings_.feature_skin * (posed_[a].radius + posed_[b].radius),
                                near_[p], features);
          } else {
            polyhedron_contacts(posed_[a], posed_[b], 0.0, features);
          }
          std::sort(features.begin(), features.end(), [](const auto& x, const auto& y) {
            return std::tie(x.feature_a, x.feature_b) < std::tie(y.feature_a, y.feature_b);
          });
          for (const auto& fc : features) {
            if (fc.contact.penetration > 0.0) {
              out.push_back({{a, b, fc.feature_a, fc.feature_b}, fc.contact});
              chunk_shift_[chunk].list.push_back(t);
            }
          }
          continue;
        }
        const double radii = posed_[a].radius + posed_[b].radius;
        if (p + 4 < end) prefetch_posed(live_slots_[pairs_[p + 4].second]);  // as in plan_pairs
        if (manifolds && plan_[p] == kCarried) {
          // Straight into the list: held in feature order, overlapping only.
          for_carried_contacts(posed_[a], posed_[b], manifolds_[p],
                               [&](std::uint32_t fa, std::uint32_t fb, const PrimitiveContact& c) {
                                 out.push_back({{a, b, fa, fb}, c});
                               });
          continue;
        }
        if (manifolds && plan_[p] == kApart) {
          // the near features say nothing can touch: what the search would find
        } else {
          if (cached) {
            polyhedron_contacts(posed_[a], posed_[b], settings_.feature_skin * radii, near_[p], features);
          } else {
            polyhedron_contacts(posed_[a], posed_[b], 0.0, features);
          }
          // A pair that touches keeps its contacts from here on; one that does not is left to
          // the search (apart, it costs next to nothing).
          if (manifolds) {
            const bool touching = std::any_of(features.begin(), features.end(),
                                              [](const FeatureContact& f) { return f.contact.penetration > 0.0; });
            if (!touching && held_[p]) manifolds_[p].margin = 0.0;  // held_ follows it (restarts)
            held_[p] = touching;
            if (touching)
              capture_manifold(posed_[a], posed_[b], features, settings_.manifold_tolerance * radii, manifolds_[p]);
          }
        }
        // Ascending feature order within the pair keeps the keys ascending (see ContactKey).
        if (!manifolds || plan_[p] == kSearch)
          std::sort(features.begin(), features.end(), [](const auto& x, const auto& y) {
            return std::tie(x.feature_a, x.feature_b) < std::tie(y.feature_a, y.feature_b);
          });
        for (const auto& fc : features) {
          if (fc.contact.penetration > 0.0) {
            out.push_back({{a, b, fc.feature_a, fc.feature_b}, fc.contact});
          }
        }
      }
    }
  }
}

void World::plan_pairs(int nt) {
  // Which pairs carry their manifold's contacts, which the near features hold apart, and
  // which are searched; a body that a search will read gets its vertices and planes, one
  // that only a wall reads its vertices, the others keep their frame alone
  // (PosedShape::update_frame).
  const std::size_t n = pairs_.size();
  plan_.resize(n);
  need_geometry_.assign(states_.size(), 0);
  const bool cached = settings_.feature_skin > 0.0;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
  for (std::size_t p = 0; p < n; ++p) {
    const std::uint32_t a = live_slots_[pairs_[p].first], b = live_slots_[pairs_[p].second];
    // B's posed shape eight pairs ahead, which the pairs' order leaves scattered (A's come
    // in order): in a bonded disc its load held up a third of near_features_apart.
    if (p + 8 < n) prefetch_posed(live_slots_[pairs_[p + 8].second]);
    if (held_[p] && manifold_holds(posed_[a], posed_[b], manifolds_[p])) {
      plan_[p] = kCarried;
    } else if (cached && !held_[p] && near_features_apart(posed_[a], posed_[b], near_[p])) {
      plan_[p] = kApart;
    } else {
      plan_[p] = kSearch;
      std::atomic_ref<unsigned char>(need_geometry_[a]).store(1, std::memory_order_relaxed);
      std::atomic_ref<unsigned char>(need_geometry_[b]).store(1, std::memory_order_relaxed);
    }
  }
  const auto live = static_cast<std::ptrdiff_t>(live_slots_.size());
#pragma omp parallel for num_threads(nt) schedule(static) if (live >= kParallelMin)
  for (std::ptrdiff_t k = 0; k < live; ++k) {
    const std::uint32_t slot = live_slots_[static_cast<std::size_t>(k)];
    if (need_geometry_[slot] != 0) {
      posed_[slot].update_geometry();
    } else if (wall_reach_[slot] != 0) {
      posed_[slot].update_vertices();  // a wall reads its vertices alone
    }
  }
}

void World::wall_contacts(int nt) {
  // The body slots in pieces, handed to the threads as they come free; each piece lists its
  // contacts with every wall, and the pieces' lists are joined in order, wall by wall, as
  // one thread would list them, for any number of threads. Each list has cache lines of its
  // own (OwnLines): side by side, two threads' lists shared the line holding their ends, and
  // the settled pile's wall contacts took 0.156 ms a step on two threads, no less than on
  // one (0.152); 0.104 now.
  const auto slots = live_slots_.size();
  if (static_cast<std::ptrdiff_t>(slots) < kParallelMin || walls_.empty()) nt = 1;
  const std::size_t pieces = std::max<std::size_t>(1, (slots + kWallPiece - 1) / kWallPiece);
  const std::size_t lists = pieces * walls_.size();
  if (wall_pending_.size() < lists) wall_pending_.resize(lists);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1) if (nt > 1)
  for (std::size_t piece = 0; piece < pieces; ++piece) {
    for (std::uint32_t w = 0; w < walls_.size(); ++w) wall_pending_[w * pieces + piece].list.clear();
    // Body by body, wall by wall within: one pass over the bodies; each wall's list still
    // takes its contacts in body order.
    const std::size_t end = std::min(slots, (piece + 1) * kWallPiece);
    for (std::size_t k = piece * kWallPiece; k < end; ++k) {
      const std::uint32_t slot = live_slots_[k];
      if (!owns(slot)) continue;  // a ghost's wall contacts are its owner's
      const std::uint32_t reach = wall_reach_[slot];
      if (reach == 0) continue;
      const PosedShape& p = posed_[slot];
      for (std::uint32_t w = 0; w < walls_.size(); ++w) {
        auto& out = wall_pending_[w * pieces + piece].list;
        const Wall& wall = walls_[w];
        const std::uint32_t a = w | kWallFlag;
        if ((reach & wall_bit(w)) == 0) continue;
        if (w >= 31 && !wall_within_reach(wall, p.centre, shapes_[infos_[slot].shape].bounding_radius())) continue;
        for (std::uint32_t v = 0; v < p.vertices.size(); ++v) {
          if (auto c = wall.sphere_contact(p.vertices[v], p.radius); c && c->penetration > 0.0) {
            out.push_back({{a, slot, 0, feature_code(FeatureKind::vertex, v)}, *c});
          }
        }
        if (wall.kind == Wall::Kind::cylinder) {
          const auto& edges = p.primitives->edges;
          for (std::uint32_t e = 0; e < edges.size(); ++e) {
            auto c = wall.edge_contact(p.vertices[edges[e].a], p.vertices[edges[e].b], p.radius);
            if (c && c->penetration > 0.0) {
              out.push_back({{a, slot, 0, feature_code(FeatureKind::edge, e)}, *c});
            }
          }
        }
      }
    }
  }
  for (std::size_t k = 0; k < lists; ++k) parts_.push_back(&wall_pending_[k].list);
}

void World::join_pending() {
  part_start_.assign(parts_.size() + 1, 0);
  for (std::size_t k = 0; k < parts_.size(); ++k) part_start_[k + 1] = part_start_[k] + parts_[k]->size();
  contact_shift_.clear();
  if (cell_on_) {
    // The pairs' chunks come first, in order, then the walls' lists (no shift).
    contact_shift_.assign(part_start_.back(), Eigen::Vector3d::Zero());
    const std::size_t chunks = (pairs_.size() + kPairChunk - 1) / kPairChunk;
    for (std::size_t c = 0; c < chunks && c < parts_.size(); ++c)
      std::copy(chunk_shift_[c].list.begin(), chunk_shift_[c].list.end(), contact_shift_.begin() + static_cast<std::ptrdiff_t>(part_start_[c]));
  }
}

template <class F>
void World::for_pending(std::size_t begin, std::size_t end, F&& f) const {
  if (begin >= end) return;
  // The list holding contact `begin`: the last one starting at or before it.
  auto part = static_cast<std::size_t>(std::upper_bound(part_start_.begin(), part_start_.end(), begin) -
                                       part_start_.begin()) - 1;
  for (std::size_t k = begin; k < end; ++part) {
    const std::vector<Pending>& list = *parts_[part];
    const std::size_t stop = std::min(end, part_start_[part + 1]);
    for (std::size_t i = k - part_start_[part]; k < stop; ++k, ++i) f(k, list[i]);
  }
}

std::size_t World::history_index(const ContactKey& key) const {
  return static_cast<std::size_t>(
      std::lower_bound(history_.begin(), history_.end(), key,
                       [](const HistoryEntry& e, const ContactKey& k) { return e.key < k; }) -
      history_.begin());
}

const ContactHistory* World::previous_history(const ContactKey& key) const {
  const std::size_t i = history_index(key);
  return i < history_.size() && history_[i].key == key ? &history_[i].history : nullptr;
}

void World::evaluate_and_apply(int nt) {
  // The contact law for every contact, in parallel: each reads only the bodies' states and
  // the previous step's history, and writes its own slot.
  const std::size_t n = pending_count();
  forces_.resize(n);
  overlaps_.resize(n);
  next_history_.resize(n);
  // (Few contacts take one thread; their sums below go by body, on all of them.)
  const int law_threads = static_cast<std::ptrdiff_t>(n) < kParallelMin ? 1 : nt;
#pragma omp parallel num_threads(law_threads) if (law_threads > 1)
  {
    // Plain variables, not a structured binding: the lambda below captures them.
    const Block block = thread_block(n);
    const std::size_t begin = block.begin, end = block.end;
    // Keys ascend through the contacts, as through the history: one search, then a walk.
    std::size_t cursor = 0, bond_cursor = 0;
    PairDamping pair;
    // Four contacts with the same parameters go through contact_forces<4> together, with
    // contact_force's bits; those left over one at a time.
    const double dt = settings_.dt;
    ContactKinematics lane_kin[4];
    ContactDamping lane_damping[4];
    std::size_t lane_k[4];
    const ContactParams* lane_params = nullptr;
    int filled = 0;
    const ContactKinematics* const lane_in[4] = {&lane_kin[0], &lane_kin[1], &lane_kin[2], &lane_kin[3]};
    const ContactDamping* const lane_d[4] = {&lane_damping[0], &lane_damping[1], &lane_damping[2],
                                             &lane_damping[3]};
    auto one_at_a_time = [&] {
      for (int i = 0; i < filled; ++i)
        forces_[lane_k[i]] = contact_force(*lane_params, lane_kin[i], lane_damping[i],
                                           next_history_[lane_k[i]].history, dt);
      filled = 0;
    };
    for_pending(begin, end, [&](std::size_t k, const Pending& p) {
      if (k == begin) {
        cursor = history_index(p.key);
        if (!bonds_.empty()) {
          bond_cursor = static_cast<std::size_t>(
              std::lower_bound(bonds_.begin(), bonds_.end(), p.key.a,
                               [](const Bond& bd, std::uint32_t a) { return bd.a < a; }) -
              bonds_.begin());
        }
      }
      const ContactParams& params =
          (p.key.a & kWallFlag) != 0 ? settings_.particle_wall : settings_.particle_particle;
      // The walls' contacts follow the pairs': the quad so far goes first when they start.
      if (filled > 0 && &params != lane_params) one_at_a_time();
      ContactKinematics& kin = lane_kin[filled];
      contact_inputs(p, k, params, cursor, bond_cursor, pair, kin);
      overlaps_[k] = kin.overlap;
      lane_params = &params;
      lane_damping[filled] = pair.damping;
      lane_k[filled] = k;
      if (++filled < 4) return;
      ContactHistory* history[4];
      ContactForce* out[4];
      for (int i = 0; i < 4; ++i) {
        history[i] = &next_history_[lane_k[i]].history;
        out[i] = &forces_[lane_k[i]];
      }
      contact_forces<4>(params, lane_in, lane_d, history, out, dt);
      filled = 0;
    });
    one_at_a_time();
  }
  lap(StepPhase::contact_law);
  sum_forces(nt);
  lap(StepPhase::contact_sums);
}

void World::contact_inputs(const Pending& p, std::size_t k, const ContactParams& params,
                           std::size_t& cursor, std::size_t& bond_cursor, PairDamping& pair,
                           ContactKinematics& kin) {
  const bool wall = (p.key.a & kWallFlag) != 0;
  const std::uint32_t a = p.key.a & ~kWallFlag, b = p.key.b;
  const PrimitiveContact& c = p.contact;
  const BodyState& sb = states_[b];
  const BodyInfo& ib = infos_[b];
  kin.normal = c.normal;
  kin.overlap = c.penetration;
  // The relative motion in plain doubles (vec3.hpp: Eigen's bits, without its stalls).
  const V3 point = v3(c.point);
  V3 va_point, wa;
  if (wall) {
    va_point = v3(walls_[a].velocity);
    wa = {0.0, 0.0, 0.0};
  } else {
    const BodyState& sa = states_[a];
    wa = v3(sa.w);
    va_point = v3(sa.v) + cross(wa, point - v3(sa.x));
  }
  // B's centroid, or in a periodic cell its image's; a moving cell moves the two apart at L d.
  const V3 xb = contact_shift_.empty() ? v3(sb.x) : v3(sb.x) + v3(contact_shift_[k]);
  const V3 wb = v3(sb.w);
  kin.velocity = eigen((v3(sb.v) + cross(wb, point - xb)) - va_point);
  if (!wall && moving_cell_) kin.velocity += gradient_ * (eigen(xb) - states_[a].x);
  kin.spin = eigen(wb - wa);
  kin.lever = posed_[b].radius;
  bool bonded = false;
  if (!wall && (!bonds_.empty() || !offsets_.empty())) {
    // Overlaps count from the one stored at bonding (end of sec. 2.3.3) or at a split.
    double stored = bonds_.empty() ? 0.0 : initial_overlap(a, b, p.key.fa, p.key.fb, bond_cursor);
    if (!offsets_.empty()) stored = std::max(stored, pair_offset(a, b));
    kin.overlap -= stored;
    // A bonded pair's grains have grown or shrunk with temperature; their shapes have not.
    if (thermal_on_ && bond_cursor < bonds_.size() && bonds_[bond_cursor].a == a && bonds_[bond_cursor].b == b) {
      kin.overlap -= bonds_[bond_cursor].thermal_gap;
      bonded = true;
    }
  }
  if (thermal_on_ && !bonded) {
    // Any other contact: the gap its grains' expansion since their shapes were made opens at
    // the contact point, to first order (each grain about its centroid, as for the bonds).
    auto grown = [&](std::uint32_t slot, const Eigen::Vector3d& arm) -> Eigen::Vector3d {
      const BodyThermal& t = thermal_[slot];
      const double d = t.temperature - t.shaped_at;
      if (d == 0.0) return Eigen::Vector3d::Zero();
      const Eigen::Quaterniond& q = states_[slot].q;
      return rotated(q, t.alpha * (q.conjugate() * arm - t.centre)) * d;
    };
    Eigen::Vector3d opened = grown(b, c.point - eigen(xb));
    if (!wall) opened -= grown(a, c.point - states_[a].x);
    kin.overlap -= c.normal.dot(opened);
  }
  // The law updates the history in its place in next_history_ (not in a copy on the stack
  // copied there after: that copy read 16-byte pairs the law had just stored as halves).
  HistoryEntry& next = next_history_[k];
  next.key = p.key;
  ContactHistory& h = next.history;
  h = ContactHistory{};
  if (cursor > 0 && cursor <= history_.size() && p.key < history_[cursor - 1].key) {
    if (const ContactHistory* old = previous_history(p.key)) h = *old;  // out of order
  } else {
    while (cursor < history_.size() && history_[cursor].key < p.key) ++cursor;
    if (cursor < history_.size() && history_[cursor].key == p.key) h = history_[cursor].history;
  }
  // The damping coefficients (four square roots and three divisions) are the same for all
  // of a pair's contact points, which come one after another: made once per pair, and
  // kept for the next pair whose bodies have the same masses and moments (a specimen's
  // grains are mostly one shape: the settled pile's coefficients took 1.9 % of its step).
  if (!pair.valid || pair.a != p.key.a || pair.b != b) {
    const double mb = ib.mass, i2 = ib.inertia.minCoeff();
    const double ma = wall ? 0.0 : infos_[a].mass, i1 = wall ? 0.0 : infos_[a].inertia.minCoeff();
    if (!(pair.valid && pair.wall == wall && pair.mass_a == ma && pair.mass_b == mb &&
          pair.moment_a == i1 && pair.moment_b == i2)) {
      // The reduced mass and the reduced least principal moment (B's alone against a wall).
      double m_crit = mb, i_crit = i2;
      if (!wall) {
        m_crit = ma * mb / (ma + mb);
        i_crit = i1 * i2 / (i1 + i2);
      }
      pair.damping = contact_damping(params, m_crit, i_crit);
      pair.wall = wall;
      pair.mass_a = ma;
      pair.mass_b = mb;
      pair.moment_a = i1;
      pair.moment_b = i2;
    }
    pair.a = p.key.a;
    pair.b = b;
    pair.valid = true;
  }
}

void World::list_body_pairs() {
  list_by_body(states_.size(), pairs_.size(),
               [&](std::size_t p) { return std::pair{live_slots_[pairs_[p].first], live_slots_[pairs_[p].second]}; },
               body_pair_start_, body_pairs_);
  body_pairs_stale_ = false;
}

template <class F>
[[gnu::always_inline]] inline void World::for_pair_contacts_of(std::size_t slot, F&& f) const {
  // A pair's contacts are consecutive in its chunk's list, from pair_first_ to the next
  // pair's first (or the list's end).
  for (std::uint32_t e = body_pair_start_[slot]; e < body_pair_start_[slot + 1]; ++e) {
    const std::uint32_t p = body_pairs_[e] >> 1;
    const bool is_b = (body_pairs_[e] & 1u) != 0;
    const std::size_t chunk = p / kPairChunk;
    const std::vector<Pending>& list = chunk_pending_[chunk].list;
    const std::size_t stop = (p + 1) % kPairChunk != 0 && p + 1 < pairs_.size() ? pair_first_[p + 1] : list.size();
    const std::size_t base = part_start_[chunk];
    for (std::size_t j = pair_first_[p]; j < stop; ++j) f(is_b, list[j], base + j);
  }
}

void World::sum_forces(int nt) {
  // Every body's force and torque are summed in contact order, the same for any number of
  // threads. A body's contacts with other bodies come first in the list, pair by pair in the
  // pairs' order: each thread takes a block of bodies and walks each body's pairs
  // (body_pairs_), summing in registers. The walls' contacts follow in the list: each thread
  // then walks those and adds the ones of its bodies. Wall reactions are summed by the
  // first thread.
  const std::size_t n = pending_count();
  records_current_ = false;  // contacts() makes them from this evaluation when asked
  if (body_pairs_stale_ || body_pair_start_.size() != states_.size() + 1) list_body_pairs();
  const std::size_t slots = states_.size();
  // By body: a loaded disc's few hundred contacts still leave 10,000 bodies to sum (one
  // thread took 0.14 ms a step over them).
  if (static_cast<std::ptrdiff_t>(slots) < kParallelMin) nt = 1;
  const std::size_t wall_begin = wall_contacts_begin();
#pragma omp parallel num_threads(nt) if (nt > 1)
  {
    const Block block = thread_block(slots);  // captured below: not a structured binding
    const std::size_t t = block.thread, lo = block.begin, hi = block.end;
    // Plain doubles (vec3.hpp), with Eigen's bits. With summing_stress_, eq. 2.17's terms
    // too (stress_sums: B's lever from its image, A's force negated).
    auto body = [&](std::size_t i, auto stress) {
      constexpr bool kStress = decltype(stress)::value;
      const std::uint32_t first = body_pair_start_[i], last = body_pair_start_[i + 1];
      if (first == last) {
        if constexpr (kStress) stress_diagonals_[i].setZero();
        return;
      }
      BodyState& s = states_[i];
      const V3 x = v3(s.x);
      V3 f = v3(s.f), tau = v3(s.tau);
      StressDiagonal m;
      for_pair_contacts_of(i, [&](bool is_b, const Pending& c, std::size_t k) {
        const ContactForce& fc = forces_[k];
        const V3 force = v3(fc.force), moment = v3(fc.moment), point = v3(c.contact.point);
        if (is_b) {
          f = f + force;
          const V3 arm = contact_shift_.empty() ? point - x : (point - v3(contact_shift_[k])) - x;
          tau = tau + (cross(arm, force) + moment);
          if constexpr (kStress) m.add(arm, force);
        } else {
          f = f - force;
          tau = tau - (cross(point - x, force) + moment);
          if constexpr (kStress) m.add(point - x, -1.0 * force);
        }
      });
      s.f = eigen(f);
      s.tau = eigen(tau);
      if constexpr (kStress) m.store(stress_diagonals_[i]);
    };
    if (summing_stress_) {
      for (std::size_t i = lo; i < hi; ++i) body(i, std::true_type{});
    } else {
      for (std::size_t i = lo; i < hi; ++i) body(i, std::false_type{});
    }
    for_pending(wall_begin, n, [&](std::size_t k, const Pending& p) {
      const std::uint32_t a = p.key.a & ~kWallFlag, b = p.key.b;
      const ContactForce& fc = forces_[k];
      if (b >= lo && b < hi) {
        BodyState& sb = states_[b];
        const V3 force = v3(fc.force), arm = v3(p.contact.point) - v3(sb.x);
        sb.f = eigen(v3(sb.f) + force);
        sb.tau = eigen(v3(sb.tau) + (cross(arm, force) + v3(fc.moment)));
        if (summing_stress_) {
          StressDiagonal m;
          m.load(stress_diagonals_[b]);
          m.add(arm, force);
          m.store(stress_diagonals_[b]);
        }
      }
      if (t == 0) walls_[a].reaction -= fc.force;
    });
  }
  std::swap(history_, next_history_);
}

const std::vector<ContactRecord>& World::contacts() const {
  if (!records_current_) {
    // Each thread fills its own block of the records, in contact order.
    const std::size_t n = pending_count();
    records_.resize(n);
    const int nt = static_cast<std::ptrdiff_t>(n) < kParallelMin ? 1 : thread_count(settings_.threads);
#pragma omp parallel num_threads(nt) if (nt > 1)
    {
      const Block block = thread_block(n);
      for_pending(block.begin, block.end, [&](std::size_t k, const Pending& p) {
        const bool wall = (p.key.a & kWallFlag) != 0;
        records_[k] = {p.key.a & ~kWallFlag, p.key.b, wall, p.contact.point, p.contact.normal, overlaps_[k],
                       forces_[k].force,
                       contact_shift_.empty() ? Eigen::Vector3d::Zero() : contact_shift_[k]};
      });
    }
    records_current_ = true;
  }
  return records_;
}

void World::add_listener(StepListener* listener) {
  if (std::find(listeners_.begin(), listeners_.end(), listener) == listeners_.end()) listeners_.push_back(listener);
}

void World::remove_listener(StepListener* listener) {
  listeners_.erase(std::remove(listeners_.begin(), listeners_.end(), listener), listeners_.end());
}

void World::step() {
  StepNeeds needs;
  for (StepListener* l : listeners_) {
    l->before_step(*this);
    needs |= l->needs(*this);
  }
  want_stress_sums_ = needs.stress_sums;
  const double h = settings_.dt;
  if (timing_) {
    in_step_ = true;
    lap_ns_ = clock_ns();
  }
  if (cell_on_) {
    // The cell's velocity gradient this step: the one set, plus, when the grains expand,
    // their volume-mean expansion since the last evaluation over the step (the cell of a
    // free polycrystal follows its mean thermal strain; the grains' mismatch stays in them).
    gradient_ = cell_.velocity_gradient();
    if (thermal_on_) {
      Eigen::Matrix3d strain = Eigen::Matrix3d::Zero();
      double volume = 0.0;
      for (std::size_t i = 0; i < states_.size(); ++i) {
        if (!infos_[i].alive) continue;
        const double v = shapes_[infos_[i].shape].volume;
        const double dt = thermal_[i].temperature - thermal_[i].bonded_at;
        volume += v;
        if (dt == 0.0) continue;
        const Eigen::Matrix3d r = states_[i].q.toRotationMatrix();
        strain += v * dt * (r * thermal_[i].alpha * r.transpose());
      }
      if (volume > 0.0) gradient_ += strain / (volume * h);
    }
    if (stress_tau_ > 0.0 && forces_current_) {
      // Berendsen: the axes left free relax their mean normal stress (a cell in tension
      // shrinks, one in compression grows).
      const Eigen::Matrix3d sigma = cell_stress();
      const Eigen::Matrix3d set = cell_.velocity_gradient();
      for (int k = 0; k < 3; ++k) {
        if (cell_.periodic(k) && set(k, k) == 0.0) gradient_(k, k) -= sigma(k, k) / (stress_modulus_ * stress_tau_);
      }
    }
    moving_cell_ = !gradient_.isZero(0.0);
  }
  if (!forces_current_) {
    in_step_ = false;  // the first evaluation is not a step's
    compute_forces();
    if (timing_) {
      in_step_ = true;
      lap_ns_ = clock_ns();
    }
  }
  const int nt = thread_count(settings_.threads);
  const auto slots = static_cast<std::ptrdiff_t>(states_.size());
  // Each thread's block of bodies, kDriftBatch at a time: `take(i)` says whether body i is
  // in (acting on it alone first, if need be), `run(batch, infos, n)` acts on a batch (the
  // batch drift and kick: the same bits as one body at a time).
  auto in_batches = [&](auto take, auto run) {
#pragma omp parallel num_threads(nt) if (slots >= kParallelMin)
    {
      const Block block = thread_block(static_cast<std::size_t>(slots));
      BodyState* batch[kDriftBatch];
      const BodyInfo* batch_info[kDriftBatch];
      int queued = 0;
      for (std::size_t i = block.begin; i < block.end; ++i) {
        if (!take(i)) continue;
        batch[queued] = &states_[i];
        batch_info[queued] = &infos_[i];
        if (++queued == kDriftBatch) {
          run(batch, batch_info, queued);
          queued = 0;
        }
      }
      if (queued > 0) run(batch, batch_info, queued);
    }
  };
  in_batches(
      [&](std::size_t i) {
        if (!infos_[i].alive || !owns(static_cast<std::uint32_t>(i))) return false;
        if (!infos_[i].fixed) kick_momenta(states_[i], infos_[i], 0.5 * h);
        return true;
      },
      [&](BodyState* const* s, const BodyInfo* const* b, int n) {
        drift(s, b, n, h);
      });  // sets w
  if (cell_on_) {
    if (moving_cell_) {
      // The homogeneous deformation: centroids ride the affine field, the cell with them.
      const Eigen::Matrix3d step = h * gradient_;
      for (std::ptrdiff_t i = 0; i < slots; ++i) {
        if (infos_[i].alive) states_[i].x += step * (states_[i].x - cell_.origin());
      }
      cell_.deform(step);
    }
    wrap_bodies();
  }
  for (auto& w : walls_) w.origin += h * w.velocity;
  lap(StepPhase::kick_drift);
  compute_forces();
  in_batches(
      [&](std::size_t i) {
        return infos_[i].alive && !infos_[i].fixed && owns(static_cast<std::uint32_t>(i));
      },
      [&](BodyState* const* s, const BodyInfo* const* b, int n) {
        kick(s, b, n, 0.5 * h);
      });
  if (conductivity_ > 0.0) conduct(h);
  lap(StepPhase::closing_kick);
  if (in_step_) ++timings_.steps;
  in_step_ = false;
  time_ += h;
  ++steps_;
  for (StepListener* l : listeners_) l->after_step(*this);
}

bool World::by_body_current() const {
  // The per-body lists of the last evaluation (sum_forces, bond_forces) describe the contact
  // lists and bonds as they are: nothing has been split, added or loaded since.
  return (forces_current_ || summed_) && !body_pairs_stale_ && body_pair_start_.size() == states_.size() + 1 &&
         (bonds_.empty() || (!body_bonds_stale_ && body_bond_start_.size() == states_.size() + 1));
}

std::size_t World::wall_contacts_begin() const {
  const std::size_t chunks = (pairs_.size() + kPairChunk - 1) / kPairChunk;
  return chunks < part_start_.size() ? part_start_[chunks] : pending_count();
}

template <class F>
void World::for_forces_on(std::uint32_t slot, F&& f) const {
  // Contacts with other bodies, pair by pair in the pairs' order (the contact order), then
  // wall contacts (after every pair's in the list), then bonds in bond order: the order of
  // a walk over contacts() and bonds(). A's side: the force negated; B's: its lever from
  // its image.
  for_pair_contacts_of(slot, [&](bool is_b, const Pending& c, std::size_t k) {
    const V3 force = v3(forces_[k].force), point = v3(c.contact.point);
    if (is_b) {
      f(contact_shift_.empty() ? point : point - v3(contact_shift_[k]), force);
    } else {
      f(point, -1.0 * force);
    }
  });
  if (wall_reach_.size() == states_.size() && wall_reach_[slot] != 0) {  // it may touch a wall
    for_pending(wall_contacts_begin(), pending_count(), [&](std::size_t k, const Pending& p) {
      if (p.key.b == slot) f(v3(p.contact.point), v3(forces_[k].force));
    });
  }
  if (bonds_.empty()) return;
  if (domain_ == nullptr) {
    // From the bonds' small records (the bond law's, kept current by the breaks after it):
    // the bond point and force, B's lever from its image only in a periodic cell (a zero
    // shift subtracted changes no bit).
    for (std::uint32_t e = body_bond_start_[slot]; e < body_bond_start_[slot + 1]; ++e) {
      const std::uint32_t k = body_bonds_[e] >> 1;
      const BondPush& bp = bond_push_[k];
      if (!bp.live) continue;
      if ((body_bonds_[e] & 1u) != 0) {
        f(cell_on_ ? bp.point - v3(bonds_[k].shift) : bp.point, bp.force);
      } else {
        f(bp.point, -1.0 * bp.force);
      }
    }
    return;
  }
  // Several processes: the ghosts' bonds are updated after the sums (MpiDomain).
  for (std::uint32_t e = body_bond_start_[slot]; e < body_bond_start_[slot + 1]; ++e) {
    const Bond& bd = bonds_[body_bonds_[e] >> 1];
    if (!bd.intact()) continue;
    if ((body_bonds_[e] & 1u) != 0) {
      f(v3(bd.point) - v3(bd.shift), v3(bd.force));
    } else {
      f(v3(bd.point), -1.0 * v3(bd.force));
    }
  }
}

const std::vector<Eigen::Matrix3d>& World::stress_sums() const {
  if (stress_sums_current_ && by_body_current()) return stress_sums_;
  std::vector<Eigen::Matrix3d>& out = stress_sums_;
  out.assign(states_.size(), Eigen::Matrix3d::Zero());
  if (!by_body_current()) {
    // Lists out of date (a split or a load since the last evaluation): from the records.
    for (const ContactRecord& c : contacts()) {
      out[c.b] += (c.point - c.shift - states_[c.b].x) * c.force.transpose();
      if (!c.wall) out[c.a] -= (c.point - states_[c.a].x) * c.force.transpose();
    }
    for (const Bond& bd : bonds_) {
      if (!bd.intact()) continue;
      out[bd.b] += (bd.point - bd.shift - states_[bd.b].x) * bd.force.transpose();
      out[bd.a] -= (bd.point - states_[bd.a].x) * bd.force.transpose();
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (!infos_[i].alive) out[i].setZero();
    }
    return out;
  }
  sum_by_body<StressSum>(out);
  stress_sums_current_ = true;
  return out;
}

template <class Sum, class Out>
void World::sum_by_body(std::vector<Out>& out) const {
  const std::size_t slots = states_.size();
  const int nt = static_cast<std::ptrdiff_t>(slots) < kParallelMin ? 1 : thread_count(settings_.threads);
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
  for (std::size_t i = 0; i < slots; ++i) {
    if (!infos_[i].alive) continue;
    const V3 x = v3(states_[i].x);
    Sum m;
    for_forces_on(static_cast<std::uint32_t>(i), [&](const V3& point, const V3& force) { m.add(point - x, force); });
    m.store(out[i]);
  }
}

Eigen::Matrix3d World::stress_sum(std::uint32_t slot) const {
  if (slot >= states_.size() || !infos_[slot].alive) return Eigen::Matrix3d::Zero();
  if (!by_body_current()) return stress_sums()[slot];
  const V3 x = v3(states_[slot].x);
  StressSum m;
  for_forces_on(slot, [&](const V3& point, const V3& force) { m.add(point - x, force); });
  Eigen::Matrix3d out;
  m.store(out);
  return out;
}

const std::vector<Eigen::Vector3d>& World::stress_sum_diagonals() const {
  if (stress_diagonals_current_ && by_body_current()) return stress_diagonals_;
  stress_diagonals_.assign(states_.size(), Eigen::Vector3d::Zero());
  if (!by_body_current()) {
    const std::vector<Eigen::Matrix3d>& full = stress_sums();
    for (std::size_t i = 0; i < full.size(); ++i) stress_diagonals_[i] = full[i].diagonal();
    return stress_diagonals_;
  }
  sum_by_body<StressDiagonal>(stress_diagonals_);
  stress_diagonals_current_ = true;
  return stress_diagonals_;
}

void World::forces_on(std::uint32_t slot, std::vector<AppliedForce>& out) const {
  out.clear();
  if (slot >= states_.size() || !infos_[slot].alive) return;
  if (!by_body_current()) {
    for (const ContactRecord& c : contacts()) {
      if (c.b == slot) out.push_back({c.point - c.shift, c.force});
      if (!c.wall && c.a == slot) out.push_back({c.point, -c.force});
    }
    for (const Bond& bd : bonds_) {
      if (!bd.intact()) continue;
      if (bd.b == slot) out.push_back({bd.point - bd.shift, bd.force});
      if (bd.a == slot) out.push_back({bd.point, -bd.force});
    }
    return;
  }
  for_forces_on(slot, [&](const V3& point, const V3& force) { out.push_back({eigen(point), eigen(force)}); });
}

std::vector<Eigen::Matrix3d> World::body_stresses() const {
  // Eq. 2.17: the sums of d (x) f per body (contact order: deterministic).
  const std::vector<Eigen::Matrix3d>& sums = stress_sums();
  std::vector<Eigen::Matrix3d> out(sums.size(), Eigen::Matrix3d::Zero());
  for (std::size_t i = 0; i < sums.size(); ++i) {
    if (infos_[i].alive) out[i] = stress_from_sum(sums[i], shapes_[infos_[i].shape].volume);
  }
  return out;
}

double World::initial_overlap(std::uint32_t a, std::uint32_t b, std::uint32_t fa,
                              std::uint32_t fb, std::size_t& cursor) const {
  auto before = [&](const Bond& bd) { return bd.a < a || (bd.a == a && bd.b < b); };
  if (cursor > 0 && cursor <= bonds_.size() && !before(bonds_[cursor - 1])) {
    // Out of order (a new thread block starts mid-pair): search again.
    cursor = static_cast<std::size_t>(
        std::lower_bound(bonds_.begin(), bonds_.end(), std::pair{a, b},
                         [](const Bond& bd, std::pair<std::uint32_t, std::uint32_t> k) {
                           return std::pair{bd.a, bd.b} < k;
                         }) -
        bonds_.begin());
  }
  // Forward by gallop (gallop.hpp), to the bond a walk would stop at: a loaded disc's few
  // hundred contacts lie far apart among its 30,000 bonds, and a walk read a cache line of
  // every bond between them (the disc's contact law: 0.14 ms a step, 0.02 after).
  cursor = gallop(bonds_, cursor, before);
  if (cursor == bonds_.size() || bonds_[cursor].a != a || bonds_[cursor].b != b) return 0.0;
  // The features' own stored overlap; a feature pair that did not touch at bonding (the
  // search may name another vertex or edge for a contact of the same faces once they move,
  // as it does between coplanar faces) counts from the largest the pair stored.
  double most = 0.0;
  for (const Bond::Overlap& o : bonds_[cursor].initial) {
    if (o.fa == fa && o.fb == fb) return o.overlap;
    most = std::max(most, o.overlap);
  }
  return most;
}

double World::pair_offset(std::uint32_t a, std::uint32_t b) const {
  const auto it = std::lower_bound(offsets_.begin(), offsets_.end(), std::pair{a, b},
                                   [](const PairOffset& o, std::pair<std::uint32_t, std::uint32_t> k) {
                                     return std::pair{o.a, o.b} < k;
                                   });
  return it != offsets_.end() && it->a == a && it->b == b ? it->overlap : 0.0;
}

void World::set_bond_strength(std::size_t k, double factor) {
  if (k >= bonds_.size()) throw std::out_of_range("set_bond_strength: no such bond");
  if (!(factor > 0.0) || !std::isfinite(factor))
    throw std::invalid_argument("set_bond_strength: the factor must be finite and > 0");
  bonds_[k].strength = factor;
}

void World::set_expansion(BodyId id, const Eigen::Matrix3d& alpha_world) {
  if (!contains(id)) throw std::out_of_range("set_expansion: stale or invalid body id");
  if (!alpha_world.allFinite()) throw std::invalid_argument("set_expansion: the tensor must be finite");
  if ((alpha_world - alpha_world.transpose()).norm() > 1e-9 * alpha_world.norm())
    throw std::invalid_argument("set_expansion: the tensor must be symmetric");
  const Eigen::Matrix3d r = states_[id.index].q.toRotationMatrix();
  thermal_[id.index].alpha = r.transpose() * alpha_world * r;
  thermal_[id.index].shaped_at = thermal_[id.index].temperature;  // its shape has its size now
  if (!alpha_world.isZero(0.0)) thermal_on_ = true;
}

Eigen::Matrix3d World::expansion(BodyId id) const {
  if (!contains(id)) throw std::out_of_range("expansion: stale or invalid body id");
  const Eigen::Matrix3d r = states_[id.index].q.toRotationMatrix();
  return r * thermal_[id.index].alpha * r.transpose();
}

Eigen::Matrix3d World::crystal_expansion(const Eigen::Vector3d& c_axis, double alpha_a, double alpha_c) {
  if (!(c_axis.norm() > 0.0)) throw std::invalid_argument("crystal_expansion: the c-axis must not be zero");
  const Eigen::Vector3d c = c_axis.normalized();
  return alpha_a * Eigen::Matrix3d::Identity() + (alpha_c - alpha_a) * c * c.transpose();
}

void World::set_temperature(BodyId id, double kelvin) {
  if (!contains(id)) throw std::out_of_range("set_temperature: stale or invalid body id");
  if (!std::isfinite(kelvin)) throw std::invalid_argument("set_temperature: not a finite temperature");
  thermal_[id.index].temperature = kelvin;
}

void World::set_temperature(double kelvin) {
  if (!std::isfinite(kelvin)) throw std::invalid_argument("set_temperature: not a finite temperature");
  for (std::size_t i = 0; i < thermal_.size(); ++i) {
    if (infos_[i].alive) thermal_[i].temperature = kelvin;
  }
}

void World::ramp_temperature(double change, double target) {
  if (!std::isfinite(change) || !std::isfinite(target))
    throw std::invalid_argument("ramp_temperature: not a finite change or target");
  for (std::size_t i = 0; i < thermal_.size(); ++i) {
    BodyThermal& t = thermal_[i];
    if (!infos_[i].alive || t.held) continue;
    const double next = t.temperature + change;
    t.temperature = change > 0.0 ? std::min(next, std::max(target, t.temperature))
                                 : std::max(next, std::min(target, t.temperature));
  }
}

double World::temperature(BodyId id) const {
  if (!contains(id)) throw std::out_of_range("temperature: stale or invalid body id");
  return thermal_[id.index].temperature;
}

namespace {
/// The area of the polygon the contact points of two touching faces span (their overlap's
/// corners), seen along `normal`; 0 when they span no area (an edge or corner contact).
double contact_polygon_area(const std::vector<FeatureContact>& features, const Eigen::Vector3d& normal) {
  if (features.size() < 3) return 0.0;
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> corners;
  for (const FeatureContact& fc : features) corners.emplace_back(fc.contact.point.dot(u), fc.contact.point.dot(v));
  for (const auto& c : corners) centre += c / static_cast<double>(corners.size());
  std::sort(corners.begin(), corners.end(), [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    return std::atan2(p.y() - centre.y(), p.x() - centre.x()) < std::atan2(q.y() - centre.y(), q.x() - centre.x());
  });
  double twice = 0.0;  // shoelace
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector2d& p = corners[i];
    const Eigen::Vector2d& q = corners[(i + 1) % corners.size()];
    twice += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * std::abs(twice);
}
}  // namespace

void World::set_conduction(double conductivity, double heat_capacity) {
  if (!(conductivity >= 0.0) || !std::isfinite(conductivity))
    throw std::invalid_argument("set_conduction: the conductivity must be finite and >= 0");
  if (conductivity > 0.0 && !(heat_capacity > 0.0 && std::isfinite(heat_capacity)))
    throw std::invalid_argument("set_conduction: the heat capacity must be finite and > 0");
  conductivity_ = conductivity;
  heat_capacity_ = heat_capacity;
}

void World::set_temperature_held(BodyId id, bool held) {
  if (!contains(id)) throw std::out_of_range("set_temperature_held: stale or invalid body id");
  thermal_[id.index].held = held;
}

void World::conduct(double h) {
  // Explicit: each intact bond's heat over the step from the temperatures at its start,
  // summed per body in bond order (the same for any thread count).
  heat_.assign(states_.size(), 0.0);
  for (const Bond& bd : bonds_) {
    if (!bd.intact()) continue;
    const double d = (states_[bd.b].x + bd.shift - states_[bd.a].x).norm();
    const double q = conductivity_ * bd.transmission * (thermal_[bd.b].temperature - thermal_[bd.a].temperature) / d * h;
    heat_[bd.a] += q;
    heat_[bd.b] -= q;
  }
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive || thermal_[i].held || heat_[i] == 0.0) continue;
    thermal_[i].temperature += heat_[i] / (infos_[i].mass * heat_capacity_);
  }
}

std::size_t World::initialise_bonds(const BondParams& params, double distance) {
  if (!bonds_.empty()) throw std::logic_error("initialise_bonds: the bodies are already bonded");
  if (!(distance >= 0.0)) throw std::invalid_argument("initialise_bonds: distance must be >= 0");
  if (domain_) {
    // Bonding happens once: every process makes the whole world's bonds from the whole
    // world's state, as one process would (the same list everywhere), then goes back to
    // its own bodies.
    if (params.criterion != BondCriterion::limits)
      throw std::invalid_argument("initialise_bonds: a stress criterion is single-process for now");
    Domain* domain = domain_;
    domain->gather_all(*this);
    std::vector<Role> roles = std::move(roles_);
    domain_ = nullptr;
    roles_.clear();
    pairs_current_ = false;
    near_.clear();
    // Every body posed and searched afresh (the histories this evaluation advances are
    // cleared below, as after any bonding).
    forces_current_ = false;
    const std::size_t n = initialise_bonds(params, distance);
    domain_ = domain;
    set_roles(std::move(roles));
    return n;
  }
  if (!forces_current_) compute_forces();  // posed shapes and live slots of this state
  for (std::uint32_t slot : live_slots_) posed_[slot].update_geometry();  // a lazy pose may have skipped some
  std::vector<BoundingSphere> spheres;
  for (std::uint32_t slot : live_slots_) {
    spheres.push_back({states_[slot].x, shapes_[infos_[slot].shape].bounding_radius()});
  }
  std::vector<BodyPair> pairs;
  NeighbourSearch search(settings_.search);
  find_body_pairs(search, spheres, distance, pairs);
  std::vector<FeatureContact> features, touching;
  PosedShape image;
  for (const auto& [i, j] : pairs) {
    const std::uint32_t a = live_slots_[i], b = live_slots_[j];
    features.clear();
    // In a periodic cell the pair meets through B's nearest image.
    const Eigen::Vector3i n = cell_on_ ? cell_.nearest_image(states_[a].x, states_[b].x) : Eigen::Vector3i::Zero();
    const Eigen::Vector3d t = cell_on_ ? cell_.shift(n) : Eigen::Vector3d::Zero();
    if (!n.isZero()) shifted_copy(posed_[b], t, image);
    polyhedron_contacts(posed_[a], n.isZero() ? posed_[b] : image, distance, features);
    if (features.empty()) continue;
    Bond bd;
    bd.a = a;
    bd.b = b;
    bd.image = n;
    bd.shift = t;
    Eigen::Vector3d point = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
    for (const FeatureContact& fc : features) {
      point += fc.contact.point;
      normal += fc.contact.normal;
    }
    // The overlaps to count from: those of the search the steps make (no margin), which
    // may name other features for a contact than the search with a margin does.
    touching.clear();
    polyhedron_contacts(posed_[a], n.isZero() ? posed_[b] : image, 0.0, touching);
    for (const FeatureContact& fc : touching) {
      if (fc.contact.penetration > 0.0) bd.initial.push_back({fc.feature_a, fc.feature_b, fc.contact.penetration});
    }
    point /= static_cast<double>(features.size());
    if (normal.norm() < 1e-12) continue;  // opposed normals: no well-defined bond
    normal.normalize();
    const BodyState& sa = states_[a];
    const BodyState& sb = states_[b];
    const Eigen::Vector3d xb = sb.x + t;
    bd.arm_a = sa.q.conjugate() * (point - sa.x);
    bd.arm_b = sb.q.conjugate() * (point - xb);
    bd.normal_a = sa.q.conjugate() * normal;
    bd.normal_b = sb.q.conjugate() * normal;
    // The beam (BondLaw::beam) from centroid to centroid, with a direction across it.
    const Eigen::Vector3d chord = xb - sa.x;
    const Eigen::Vector3d axis = chord.normalized(), across = axis.unitOrthogonal();
    bd.beam.axis_a = sa.q.conjugate() * axis;
    bd.beam.axis_b = sb.q.conjugate() * axis;
    bd.beam.across_a = sa.q.conjugate() * across;
    bd.beam.across_b = sb.q.conjugate() * across;
    bd.beam.rest_length = chord.norm();
    bd.section.radius = std::min(posed_[a].radius, posed_[b].radius);
    bd.point = point;
    bd.normal = normal;
    bd.transmission = std::max(contact_polygon_area(features, normal), bd.section.area());
    bonds_.push_back(std::move(bd));
    body_bonds_stale_ = true;
  }
  bond_params_ = params;
  // Bonded at this temperature: their rest state is the present one.
  for (BodyThermal& t : thermal_) t.bonded_at = t.temperature;
  // The stress-free start: at rest, no shear or rolling springs, forces recomputed.
  for (std::uint32_t slot : live_slots_) {
    if (infos_[slot].fixed) continue;
    states_[slot].v.setZero();
    states_[slot].L.setZero();
    states_[slot].w.setZero();
  }
  history_.clear();
  forces_current_ = false;
  compute_forces();
  return bonds_.size();
}

void World::bond_forces(int nt) {
  const std::size_t n = bonds_.size();
  if (n == 0) return;
  if (static_cast<std::ptrdiff_t>(n) < kParallelMin) nt = 1;
  // Each bond reads the two bodies and writes only itself; the few that break this step
  // are listed by the thread that met them (blocks of bonds in thread order, so the lists
  // joined in thread order are in bond order).
  bond_failures_.resize(static_cast<std::size_t>(std::max(nt, 1)));
  for (auto& list : bond_failures_) list.clear();
  // A stress criterion replaces eq. 2.15's limits (break_by_stress applies it); held bonds
  // have none.
  BondParams base = bond_params_;
  if (base.criterion != BondCriterion::limits || bonds_held_) {
    base.tbn = base.tbs = std::numeric_limits<double>::infinity();
    if (base.law == BondLaw::beam) base.sigma_f = std::numeric_limits<double>::infinity();
  }
  const bool beams = base.law == BondLaw::beam;
  bond_push_.resize(n);
#pragma omp parallel num_threads(nt) if (nt > 1)
  {
    const Block block = thread_block(n);
    std::vector<BondFailureAt>& failed = bond_failures_[block.thread];
    // Each grain expands about its centroid (seed 003's l0(T), per crystal axis): the bond
    // point as a point of B moves by alpha_B arm_B dT_B, as a point of A by alpha_A arm_A
    // dT_A; the bond deforms by their difference on top of the rigid motions. Its normal
    // part is the gap the grains' thermal strain opens at the bond (negative: they grow into
    // each other), kept for the pair's contacts (a broken bond's too).
    auto thermal_free = [&](const Bond& bd, const BodyState& sa, const BodyState& sb) -> Eigen::Vector3d {
      const BodyThermal& ta = thermal_[bd.a];
      const BodyThermal& tb = thermal_[bd.b];
      const double dta = ta.temperature - ta.bonded_at, dtb = tb.temperature - tb.bonded_at;
      if (dta == 0.0 && dtb == 0.0) return Eigen::Vector3d::Zero();
      return rotated(sb.q, tb.alpha * (bd.arm_b - tb.centre)) * dtb - rotated(sa.q, ta.alpha * (bd.arm_a - ta.centre)) * dta;
    };
    // What the bond adds to each body, for the sum below (the same arithmetic the sum did
    // from the bond itself): a small record read by body, instead of the large bond.
    auto fill = [&](BondPush& out, const V3& point, const V3& force, const V3& moment) {
      out.force = force;
      out.moment = moment;
      out.point = point;
    };
    auto push = [&](std::size_t k) {
      const Bond& bd = bonds_[k];
      BondPush& out = bond_push_[k];
      out.live = bd.intact();
      if (out.live)
        fill(out, v3(bd.point), v3(bd.force), v3(bd.moment));
    };
    // A bond's own strengths (Bond::strength != 1): the run's parameters with them.
    auto strengthened = [&](const Bond& bd) {
      BondParams own = base;
      own.tbn *= bd.strength;
      own.tbs *= bd.strength;
      own.sigma_c *= bd.strength;
      return own;
    };
    BondConstants constants;
    double constants_radius = std::numeric_limits<double>::quiet_NaN();
    // Eqs 2.10, 2.11 and 2.15's constants of a bond: the run's, made again only when the
    // section changes from the bond before, or its own strengths'.
    auto constants_of = [&](const Bond& bd) -> BondConstants {
      if (bd.strength != 1.0) return bond_constants(strengthened(bd), bd.section);
      if (!(bd.section.radius == constants_radius)) {
        constants = bond_constants(base, bd.section);
        constants_radius = bd.section.radius;
      }
      return constants;
    };
    // Four (or two) intact bonds side by side of the plain bonded-particle law go through
    // bond_batch (bond_batch.hpp), with the bits of the loop below.
    static const Eigen::Vector3d kNoShift = Eigen::Vector3d::Zero();
    // (Made once a step: made in each call they were zeroed there, 17 % of this loop's own
    // samples.)
    BondConstants lane_c[4];
    BondLane lane_in[4];
    BondLaneResult lane_out[4];
    auto batch = [&](std::size_t k, auto width) {
      constexpr std::size_t kN = decltype(width)::value;
      for (std::size_t i = 0; i < kN; ++i) {
        Bond& bd = bonds_[k + i];
        lane_c[i] = constants_of(bd);
        if (cell_on_) bd.shift = cell_.shift(bd.image);
        const BodyState& sa = states_[bd.a];
        const BodyState& sb = states_[bd.b];
        lane_in[i] = {&sa.x,        &sa.v,     &sa.w,
                      &sa.q,        &sb.x,     &sb.v,
                      &sb.w,        &sb.q,     cell_on_ ? &bd.shift : &kNoShift,
                      &bd.arm_a,    &bd.arm_b, &bd.normal_a,
                      &bd.normal_b, &bd.state, &lane_c[i]};
      }
      bond_batch<kN>(lane_in, lane_out, settings_.dt);
      for (std::size_t i = 0; i < kN; ++i) {
        Bond& bd = bonds_[k + i];
        bd.point = eigen(lane_out[i].point);
        bd.normal = eigen(lane_out[i].normal);
        bd.force = eigen(lane_out[i].force);
        bd.moment = eigen(lane_out[i].moment);
        BondPush& out = bond_push_[k + i];
        if (lane_out[i].failure != BondFailure::none) {
          failed.push_back({k + i, lane_out[i].failure, lane_out[i].at_failure});
          out.live = false;
          continue;
        }
        out.live = true;
        fill(out, lane_out[i].point, lane_out[i].force, lane_out[i].moment);
      }
    };
    constexpr std::size_t kBondsAhead = 8;
    const bool plain = base.law == BondLaw::bonded_particle && !thermal_on_ &&
                       !(cell_on_ && moving_cell_) && roles_.empty();
    for (std::size_t k = block.begin; k < block.end; ++k) {
      // The records and bodies a few bonds ahead asked for now (bonds_ streams past the
      // caches, 576 bytes a bond of which the law reads the first five lines, a pattern
      // the hardware's prefetchers miss in part): the disc's bond law 1.24-1.26 -> 1.07-1.09
      // ms a step, alternated.
      // Four bonds ahead a turn (the quads' step; the pairs' ask for some twice).
      if (k + kBondsAhead + 3 < block.end) {
        for (std::size_t j = 0; j < 4; ++j) {
          const char* line = reinterpret_cast<const char*>(&bonds_[k + kBondsAhead + j]);
          for (int c = 0; c < 5; ++c) __builtin_prefetch(line + 64 * c, 1);
        }
        for (std::size_t j = 0; j < 4; j += 2) {
          const Bond& soon = bonds_[k + kBondsAhead / 2 + j];  // its line asked for before
          for (const std::uint32_t slot : {soon.a, soon.b}) {
            const char* body = reinterpret_cast<const char*>(&states_[slot]);
            __builtin_prefetch(body, 0);
            __builtin_prefetch(body + 64, 0);
          }
        }
      }
      if (plain && k + 3 < block.end && bonds_[k].intact() && bonds_[k + 1].intact() &&
          bonds_[k + 2].intact() && bonds_[k + 3].intact()) {
        batch(k, std::integral_constant<std::size_t, 4>{});
        k += 3;
        continue;
      }
      if (plain && k + 1 < block.end && bonds_[k].intact() && bonds_[k + 1].intact()) {
        batch(k, std::integral_constant<std::size_t, 2>{});
        ++k;
        continue;
      }
      Bond& bd = bonds_[k];
      if (!roles_.empty()) {
        // One process of a decomposition evaluates the bonds of the bodies it owns (those
        // across its boundary as their other owner does, bit for bit).
        const Role ra = roles_[bd.a], rb = roles_[bd.b];
        if (ra != Role::owned && rb != Role::owned) {
          push(k);  // its loads as last evaluated (the sum adds them to the ghosts, as before)
          continue;
        }
        if (bd.intact() && (ra == Role::dormant || rb == Role::dormant))
          throw std::logic_error("a bond reaches past this process's ghosts (the halo is too thin)");
      }
      const BodyState& sa = states_[bd.a];
      const BodyState& sb = states_[bd.b];
      if (!bd.intact()) {
        if (thermal_on_) {
          const Eigen::Vector3d n = (rotated(sa.q, bd.normal_a) + rotated(sb.q, bd.normal_b)).normalized();
          bd.thermal_gap += n.dot(thermal_free(bd, sa, sb));
        }
        bond_push_[k].live = false;
        continue;
      }
      // B's centroid, or its image's in a periodic cell (shift zero without one).
      if (cell_on_) bd.shift = cell_.shift(bd.image);
      const BondLane lane{&sa.x, &sa.v, &sa.w, &sa.q, &sb.x, &sb.v, &sb.w, &sb.q, cell_on_ ? &bd.shift : &kNoShift,
                          &bd.arm_a, &bd.arm_b, &bd.normal_a, &bd.normal_b, &bd.state, nullptr};
      const BondMotion<double> motion = bond_motion<1>(&lane);
      const V3 point = motion.point;
      bd.point = eigen(point);
      bd.normal = eigen(motion.normal);
      Eigen::Vector3d velocity = eigen(motion.velocity);
      const Eigen::Vector3d xb = eigen(motion.xb);
      if (cell_on_ && moving_cell_) velocity += gradient_ * (xb - sa.x);
      if (thermal_on_) {
        const Eigen::Vector3d free = thermal_free(bd, sa, sb);
        velocity += free / settings_.dt;
        bd.thermal_gap += bd.normal.dot(free);
        if (beams) {
          // The beam's chord grows as the grains it crosses do: from its end in A to the
          // bond point by A's expansion, from there to its end in B by B's.
          const BodyThermal& ta = thermal_[bd.a];
          const BodyThermal& tb = thermal_[bd.b];
          const Eigen::Vector3d growth =
              rotated(sa.q, ta.alpha * (bd.arm_a - bd.beam.end_a)) * (ta.temperature - ta.bonded_at) +
              rotated(sb.q, tb.alpha * (bd.beam.end_b - bd.arm_b)) * (tb.temperature - tb.bonded_at);
          const Eigen::Vector3d chord = xb + rotated(sb.q, bd.beam.end_b) - sa.x - rotated(sa.q, bd.beam.end_a);
          bd.beam.rest_length += chord.normalized().dot(growth);
        }
      }
      const BondParams* params = &base;
      BondParams own;
      if (bd.strength != 1.0) {
        own = strengthened(bd);
        params = &own;
      }
      if (beams) {
        beam_bond(bd, sa, sb, *params, failed, k);
        push(k);
        continue;
      }
      const BondResult r =
          bond_force(*params, constants_of(bd), bd.section, bd.normal, velocity, sb.w - sa.w, bd.state, settings_.dt);
      bd.force = r.force;
      bd.moment = r.moment;
      if (r.failure != BondFailure::none) failed.push_back({k, r.failure, r.at_failure});
      // push(k) from the values at hand (the same operands, so the same bits).
      BondPush& out = bond_push_[k];
      out.live = bd.intact();
      if (out.live) fill(out, point, v3(r.force), v3(r.moment));
    }
  }
  // Log the breaks in bond order.
  lap(StepPhase::bond_law);
  for (const auto& list : bond_failures_) {
    for (const BondFailureAt& f : list) {
      Bond& bd = bonds_[f.bond];
      bd.failure = f.failure;
      bond_push_[f.bond].live = false;
      bd.broken_at = time_;
      bd.force.setZero();
      bd.moment.setZero();
      breaks_.push_back({time_, steps_, f.bond, bd.a, bd.b, infos_[bd.a].grain_id, infos_[bd.b].grain_id,
                         bd.point, bd.normal, f.failure, f.at});
    }
  }
  // Sum onto the bodies in bond order, whatever the number of threads: each thread takes a
  // block of bodies and walks each body's bonds (body_bonds_), summing in registers.
  if (body_bonds_stale_ || body_bond_start_.size() != states_.size() + 1) list_body_bonds();
  const std::size_t slots = states_.size();
#pragma omp parallel num_threads(nt) if (nt > 1)
  {
    const Block block = thread_block(slots);
    auto body = [&](std::size_t i, auto stress) {
      constexpr bool kStress = decltype(stress)::value;
      const std::uint32_t first = body_bond_start_[i], last = body_bond_start_[i + 1];
      if (first == last) return;
      BodyState& s = states_[i];
      V3 f = v3(s.f), tau = v3(s.tau);
      StressDiagonal m;
      const V3 x = v3(s.x);
      if constexpr (kStress) m.load(stress_diagonals_[i]);
      for (std::uint32_t e = first; e < last; ++e) {
        const std::uint32_t k = body_bonds_[e] >> 1;
        const BondPush& bp = bond_push_[k];
        if (!bp.live) continue;
        // The torque about the body's centroid: the force's about it plus the moment (B's
        // lever from its image in a periodic cell).
        if ((body_bonds_[e] & 1u) != 0) {  // the bond's B
          const V3 lever = (cell_on_ ? bp.point - v3(bonds_[k].shift) : bp.point) - x;
          f = f + bp.force;
          tau = tau + (cross(lever, bp.force) + bp.moment);
          if constexpr (kStress) m.add(lever, bp.force);
        } else {
          const V3 lever = bp.point - x;
          f = f - bp.force;
          tau = tau - (cross(lever, bp.force) + bp.moment);
          if constexpr (kStress) m.add(lever, -1.0 * bp.force);
        }
      }
      s.f = eigen(f);
      s.tau = eigen(tau);
      if constexpr (kStress) m.store(stress_diagonals_[i]);
    };
    if (summing_stress_) {
      for (std::size_t i = block.begin; i < block.end; ++i) body(i, std::true_type{});
    } else {
      for (std::size_t i = block.begin; i < block.end; ++i) body(i, std::false_type{});
    }
  }
}

void World::list_body_bonds() {
  list_by_body(states_.size(), bonds_.size(), [&](std::size_t k) { return std::pair{bonds_[k].a, bonds_[k].b}; },
               body_bond_start_, body_bonds_);
  body_bonds_stale_ = false;
}

void World::set_cell(const PeriodicCell& cell) {
  if (!cell.vectors().allFinite() || !(cell.volume() > 0.0) || !cell.origin().allFinite())
    throw std::invalid_argument("set_cell: the cell vectors must be finite and span a volume");
  if (!cell.any_periodic()) throw std::invalid_argument("set_cell: no axis is periodic");
  if (settings_.manifold_tolerance > 0.0)
    throw std::invalid_argument("set_cell: a periodic cell uses the exact search (manifold_tolerance 0)");
  if (!bonds_.empty()) throw std::logic_error("set_cell: set the cell before the bonds are made");
  cell_ = cell;
  cell_on_ = true;
  wrap_bodies();
  pairs_current_ = false;
  forces_current_ = false;
}

void World::set_velocity_gradient(const Eigen::Matrix3d& l) {
  if (!cell_on_) throw std::logic_error("set_velocity_gradient: there is no periodic cell");
  if (!l.allFinite()) throw std::invalid_argument("set_velocity_gradient: not finite");
  cell_.set_velocity_gradient(l);
}

Eigen::Matrix3d World::cell_stress() const {
  if (!cell_on_) throw std::logic_error("cell_stress: there is no periodic cell");
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (const ContactRecord& c : contacts()) {
    if (c.wall) {
      sum += (c.point - states_[c.b].x) * c.force.transpose();
    } else {
      sum -= (states_[c.b].x + c.shift - states_[c.a].x) * c.force.transpose();
    }
  }
  for (const Bond& bd : bonds_) {
    if (bd.intact()) sum -= (states_[bd.b].x + bd.shift - states_[bd.a].x) * bd.force.transpose();
  }
  return 0.5 * (sum + sum.transpose()) / cell_.volume();
}

void World::find_body_pairs(NeighbourSearch& search, const std::vector<BoundingSphere>& spheres, double margin,
                            std::vector<BodyPair>& pairs) const {
  if (!cell_on_) {
    search.find_pairs(spheres, margin, pairs);
    return;
  }
  // The bodies in the master cell and, near its periodic faces, their images across them:
  // every pair within reach appears once as some pair of these, each named by its owners.
  double largest = 0.0;
  for (const BoundingSphere& s : spheres) largest = std::max(largest, s.radius);
  const double reach = 2.0 * largest + margin;
  for (int k = 0; k < 3; ++k) {
    if (cell_.periodic(k) && !(cell_.width(k) > 2.0 * reach)) {
      throw std::runtime_error("periodic cell too small: " + std::to_string(cell_.width(k)) + " m across axis " +
                               std::to_string(k) + ", a pair reaches " + std::to_string(reach) +
                               " m (2 x the largest bounding radius + the skin); the cell must be over twice that");
    }
  }
  std::vector<BoundingSphere> all(spheres.begin(), spheres.end());
  std::vector<std::uint32_t> owner(spheres.size());
  for (std::uint32_t i = 0; i < owner.size(); ++i) owner[i] = i;
  const Eigen::Vector3i lo(cell_.periodic(0) ? -1 : 0, cell_.periodic(1) ? -1 : 0, cell_.periodic(2) ? -1 : 0);
  const Eigen::Vector3i hi = -lo;
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    const Eigen::Vector3d home = spheres[i].centre - cell_.shift(cell_.outside(spheres[i].centre));
    all[i].centre = home;
    for (int x = lo[0]; x <= hi[0]; ++x) {
      for (int y = lo[1]; y <= hi[1]; ++y) {
        for (int z = lo[2]; z <= hi[2]; ++z) {
          if (x == 0 && y == 0 && z == 0) continue;
          const Eigen::Vector3d ghost = home + cell_.shift({x, y, z});
          const Eigen::Vector3d s = cell_.reduced(ghost);
          bool near = true;
          for (int k = 0; k < 3 && near; ++k) {
            const double band = reach / cell_.width(k);
            if (cell_.periodic(k)) near = s[k] > -band && s[k] < 1.0 + band;
          }
          if (!near) continue;
          all.push_back({ghost, spheres[i].radius});
          owner.push_back(i);
        }
      }
    }
  }
  std::vector<BodyPair> found;
  search.find_pairs(all, margin, found);
  pairs.clear();
  for (const auto& [p, q] : found) {
    const std::uint32_t i = owner[p], j = owner[q];
    if (i != j) pairs.emplace_back(std::min(i, j), std::max(i, j));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

void World::wrap_bodies() {
  // Which bodies leave, by how many cells; then every bond re-joins the same two images.
  std::vector<Eigen::Vector3i> moved;
  bool any = false;
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (!infos_[i].alive) continue;
    const Eigen::Vector3i m = cell_.outside(states_[i].x);
    if (m.isZero()) continue;
    if (!any) moved.assign(states_.size(), Eigen::Vector3i::Zero());
    any = true;
    moved[i] = m;
    states_[i].x -= cell_.shift(m);
  }
  if (!any) return;
  for (Bond& bd : bonds_) {
    // B's image x_B + H n stays where it was: n gains B's wrap and loses A's.
    bd.image += moved[bd.b] - moved[bd.a];
    bd.shift = cell_.shift(bd.image);
  }
}

void World::shifted_copy(const PosedShape& posed, const Eigen::Vector3d& shift, PosedShape& out) {
  out = posed;
  out.centre += shift;
  for (Eigen::Vector3d& v : out.vertices) v += shift;
  out.lo += shift;
  out.hi += shift;
  const std::size_t stride = out.plane_stride();
  for (std::size_t f = 0; f < out.faces; ++f) out.planes[3 * stride + f] += out.face_normal(f).dot(shift);
}

void World::beam_bond(Bond& bd, const BodyState& sa, const BodyState& sb, const BondParams& params,
                      std::vector<BondFailureAt>& failed, std::size_t k) {
  BeamPose pose;
  pose.end_a = sa.x + rotated(sa.q, bd.beam.end_a);
  pose.end_b = sb.x + bd.shift + rotated(sb.q, bd.beam.end_b);
  pose.axis_a = rotated(sa.q, bd.beam.axis_a);
  pose.axis_b = rotated(sb.q, bd.beam.axis_b);
  pose.across_a = rotated(sa.q, bd.beam.across_a);
  pose.across_b = rotated(sb.q, bd.beam.across_b);
  pose.rest_length = bd.beam.rest_length;
  const BeamResult r = beam_force(params, pose);
  // What the bond table and the break log show: the section's loads on B.
  const Eigen::Vector3d e = (pose.end_b - pose.end_a).normalized();
  bd.state.normal = r.axial;
  bd.state.shear = r.force_b + r.axial * e;
  bd.state.torsion = r.moment_b.dot(e);
  bd.state.bending = r.moment_b - bd.state.torsion * e;
  // The beam's own strength (criterion "limits"): its outer fibre's stress.
  if (r.peak_stress > params.sigma_f * bd.strength) {
    // Named by the larger part of that stress: the pull or the bending.
    const double pull = r.axial / BondSection{params.beam_radius}.area();
    const BondFailure mode = pull >= r.peak_stress - pull ? BondFailure::tension : BondFailure::bending;
    BondState at = bd.state;
    bd.state = BondState{};
    bd.state.broken = true;
    failed.push_back({k, mode, at});
    return;
  }
  // Force at B's end and B's moment, moved to the bond point (the convention of the sums).
  bd.force = r.force_b;
  bd.moment = r.moment_b + (pose.end_b - bd.point).cross(r.force_b);
}

void World::break_by_stress() {
  const std::vector<Eigen::Matrix3d> stress = body_stresses();
  for (std::size_t k = 0; k < bonds_.size(); ++k) {
    Bond& bd = bonds_[k];
    if (!bd.intact()) continue;
    const Eigen::Matrix3d mean = 0.5 * (stress[bd.a] + stress[bd.b]);
    double value = mean.trace() / 3.0;
    if (bond_params_.criterion == BondCriterion::rankine) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(mean, Eigen::EigenvaluesOnly);
      value = solver.eigenvalues().maxCoeff();
    }
    if (!(value > bond_params_.sigma_f * bd.strength)) continue;
    const BondState at = bd.state;
    bd.state = BondState{};
    bd.state.broken = true;
    bd.failure = BondFailure::tension;
    bd.broken_at = time_;
    bd.force.setZero();
    bd.moment.setZero();
    if (k < bond_push_.size()) bond_push_[k].live = false;
    stress_sums_current_ = stress_diagonals_current_ = false;  // the sums still hold this bond
    breaks_.push_back({time_, steps_, k, bd.a, bd.b, infos_[bd.a].grain_id, infos_[bd.b].grain_id, bd.point,
                       bd.normal, BondFailure::tension, at});
  }
}

void World::hold_in_plane() {
  // The momenta too, so that a body that had left the plane's motion (set by hand, or a
  // split piece whose principal axes round off the grain's) is put back on it: the kick
  // that follows derives w from L.
  for (const std::uint32_t i : live_slots_) {
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

void World::apply_local_damping(int nt) {
  const double alpha = settings_.local_damping;
  const auto live = static_cast<std::ptrdiff_t>(live_slots_.size());
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
    const std::uint32_t i = live_slots_[static_cast<std::size_t>(k)];
    if (infos_[i].fixed) continue;
    damp(states_[i].f, states_[i].v);
    damp(states_[i].tau, states_[i].w);
  }
}

BondCounts World::bond_counts() const {
  BondCounts c;
  for (const Bond& bd : bonds_) {
    switch (bd.failure) {
      case BondFailure::none: ++c.intact; break;
      case BondFailure::tension: ++c.tension; break;
      case BondFailure::shear: ++c.shear; break;
      case BondFailure::bending: ++c.bending; break;
      case BondFailure::torsion: ++c.torsion; break;
    }
  }
  return c;
}

namespace {
double kinetic(const BodyState& s, const BodyInfo& b) { return 0.5 * b.mass * s.v.squaredNorm() + 0.5 * s.w.dot(s.L); }
double potential(const BodyState& s, const BodyInfo& b, const Eigen::Vector3d& g) { return -b.mass * g.dot(s.x); }
}  // namespace

double World::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive) e += kinetic(states_[i], infos_[i]);
  }
  return e;
}

double World::potential_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive) e += potential(states_[i], infos_[i], settings_.gravity);
  }
  return e;
}

ExactSum World::owned_kinetic_energy() const {
  ExactSum e;
  for (std::uint32_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive && owns(i)) e.add(kinetic(states_[i], infos_[i]));
  }
  return e;
}

ExactSum World::owned_potential_energy() const {
  ExactSum e;
  for (std::uint32_t i = 0; i < states_.size(); ++i) {
    if (infos_[i].alive && owns(i)) e.add(potential(states_[i], infos_[i], settings_.gravity));
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
