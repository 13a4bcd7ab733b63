// The contacts' forces: the contact law on every contact (in parallel) and the sums onto
// the bodies in contact order (Contacts::apply_law, Contacts::sum), and the records.

#include <algorithm>
#include <type_traits>

#include "physics/dem/bodies.hpp"
#include "physics/dem/bonds.hpp"
#include "physics/dem/cell_control.hpp"
#include "physics/dem/contacts.hpp"
#include "physics/dem/step_threads.hpp"
#include "physics/dem/stress_sums.hpp"
#include "physics/dem/thermal_field.hpp"

namespace cleave::physics {

using threads::kParallelMin;

std::size_t Contacts::history_index(const ContactKey& key) const {
  return static_cast<std::size_t>(
      std::lower_bound(history_.begin(), history_.end(), key,
                       [](const HistoryEntry& e, const ContactKey& k) { return e.key < k; }) -
      history_.begin());
}

const ContactHistory* Contacts::previous_history(const ContactKey& key) const {
  const std::size_t i = history_index(key);
  return i < history_.size() && history_[i].key == key ? &history_[i].history : nullptr;
}

void Contacts::apply_law(const Bodies& bodies, const std::vector<Wall>& walls, const Bonds& bonds,
                         const ThermalField& thermal, const CellControl& cell,
                         const WorldSettings& settings, int nt) {
  const LawInputs in{bodies, walls, bonds, thermal, cell};
  const std::vector<Bond>& bond_list = bonds.list();
  const std::size_t n = pending_count();
  forces_.resize(n);
  overlaps_.resize(n);
  next_history_.resize(n);
  // (Few contacts take one thread; their sums go by body, on all of them.)
  const int law_threads = static_cast<std::ptrdiff_t>(n) < kParallelMin ? 1 : nt;
#pragma omp parallel num_threads(law_threads) if (law_threads > 1)
  {
    // Plain variables, not a structured binding: the lambda below captures them.
    const threads::Block block = threads::thread_block(n);
    const std::size_t begin = block.begin, end = block.end;
    // Keys ascend through the contacts, as through the history: one search, then a walk.
    std::size_t cursor = 0, bond_cursor = 0;
    PairDamping pair;
    // Four contacts with the same parameters go through contact_forces<4> together, with
    // contact_force's bits; those left over one at a time.
    const double dt = settings.dt;
    ContactKinematics lane_kin[4];
    ContactDamping lane_damping[4];
    std::size_t lane_k[4];
    const ContactParams* lane_params = nullptr;
    int filled = 0;
    const ContactKinematics* const lane_in[4] = {&lane_kin[0], &lane_kin[1], &lane_kin[2],
                                                 &lane_kin[3]};
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
        if (!bond_list.empty()) {
          bond_cursor = static_cast<std::size_t>(
              std::lower_bound(bond_list.begin(), bond_list.end(), p.key.a,
                               [](const Bond& bd, std::uint32_t a) { return bd.a < a; }) -
              bond_list.begin());
        }
      }
      const ContactParams& params =
          (p.key.a & kWallFlag) != 0 ? settings.particle_wall : settings.particle_particle;
      // The walls' contacts follow the pairs': the quad so far goes first when they start.
      if (filled > 0 && &params != lane_params) one_at_a_time();
      ContactKinematics& kin = lane_kin[filled];
      contact_inputs(in, p, k, params, cursor, bond_cursor, pair, kin);
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
}

void Contacts::contact_inputs(const LawInputs& in, const Pending& p, std::size_t k,
                              const ContactParams& params, std::size_t& cursor,
                              std::size_t& bond_cursor, PairDamping& pair, ContactKinematics& kin) {
  const std::vector<BodyState>& states = in.bodies.states();
  const bool wall = (p.key.a & kWallFlag) != 0;
  const std::uint32_t a = p.key.a & ~kWallFlag, b = p.key.b;
  const PrimitiveContact& c = p.contact;
  const BodyState& sb = states[b];
  kin.normal = c.normal;
  kin.overlap = c.penetration;
  // The relative motion in plain doubles (vec3.hpp: Eigen's bits, without its stalls).
  const V3 point = v3(c.point);
  V3 va_point, wa;
  if (wall) {
    va_point = v3(in.walls[a].velocity);
    wa = {0.0, 0.0, 0.0};
  } else {
    const BodyState& sa = states[a];
    wa = v3(sa.w);
    va_point = v3(sa.v) + cross(wa, point - v3(sa.x));
  }
  // B's centroid, or in a periodic cell its image's; a moving cell moves the two apart at L d.
  const V3 xb = contact_shift_.empty() ? v3(sb.x) : v3(sb.x) + v3(contact_shift_[k]);
  const V3 wb = v3(sb.w);
  kin.velocity = eigen((v3(sb.v) + cross(wb, point - xb)) - va_point);
  if (!wall && in.cell.moving()) kin.velocity += in.cell.gradient() * (eigen(xb) - states[a].x);
  kin.spin = eigen(wb - wa);
  kin.lever = posed_[b].radius;
  discount_overlap(in, p, xb, bond_cursor, kin.overlap);
  // The law updates the history in its place in next_history_ (not in a copy on the stack
  // copied there after: that copy read 16-byte pairs the law had just stored as halves).
  HistoryEntry& next = next_history_[k];
  next.key = p.key;
  next.history = ContactHistory{};
  carry_history(p.key, cursor, next.history);
  pair_damping(in, p, params, pair);
}

[[gnu::always_inline]] inline void Contacts::discount_overlap(const LawInputs& in, const Pending& p,
                                                              const V3& xb,
                                                              std::size_t& bond_cursor,
                                                              double& overlap) const {
  const std::vector<BodyState>& states = in.bodies.states();
  const std::vector<Bond>& bonds = in.bonds.list();
  const bool thermal_on = in.thermal.on();
  const bool wall = (p.key.a & kWallFlag) != 0;
  const std::uint32_t a = p.key.a & ~kWallFlag, b = p.key.b;
  const PrimitiveContact& c = p.contact;
  bool bonded = false;
  if (!wall && (!bonds.empty() || in.bonds.has_offsets())) {
    // Overlaps count from the one stored at bonding (end of sec. 2.3.3) or at a split.
    double stored =
        bonds.empty() ? 0.0 : in.bonds.initial_overlap(a, b, p.key.fa, p.key.fb, bond_cursor);
    if (in.bonds.has_offsets()) stored = std::max(stored, in.bonds.pair_offset(a, b));
    overlap -= stored;
    // A bonded pair's grains have grown or shrunk with temperature; their shapes have not.
    if (thermal_on && bond_cursor < bonds.size() && bonds[bond_cursor].a == a &&
        bonds[bond_cursor].b == b) {
      overlap -= bonds[bond_cursor].thermal_gap;
      bonded = true;
    }
  }
  if (thermal_on && !bonded) {
    // Any other contact: the gap its grains' expansion since their shapes were made opens at
    // the contact point, to first order (each grain about its centroid, as for the bonds).
    Eigen::Vector3d opened = in.thermal.grown(b, states[b].q, c.point - eigen(xb));
    if (!wall) opened -= in.thermal.grown(a, states[a].q, c.point - states[a].x);
    overlap -= c.normal.dot(opened);
  }
}

[[gnu::always_inline]] inline void Contacts::carry_history(const ContactKey& key,
                                                           std::size_t& cursor,
                                                           ContactHistory& h) const {
  if (cursor > 0 && cursor <= history_.size() && key < history_[cursor - 1].key) {
    if (const ContactHistory* old = previous_history(key)) h = *old;  // out of order
  } else {
    while (cursor < history_.size() && history_[cursor].key < key) ++cursor;
    if (cursor < history_.size() && history_[cursor].key == key) h = history_[cursor].history;
  }
}

[[gnu::always_inline]] inline void Contacts::pair_damping(const LawInputs& in, const Pending& p,
                                                          const ContactParams& params,
                                                          PairDamping& pair) {
  // The damping coefficients (four square roots and three divisions) are the same for all
  // of a pair's contact points, which come one after another: made once per pair, and
  // kept for the next pair whose bodies have the same masses and moments (a specimen's
  // grains are mostly one shape).
  const std::vector<BodyInfo>& infos = in.bodies.infos();
  const bool wall = (p.key.a & kWallFlag) != 0;
  const std::uint32_t a = p.key.a & ~kWallFlag, b = p.key.b;
  if (pair.valid && pair.a == p.key.a && pair.b == b) return;
  const BodyInfo& ib = infos[b];
  const double mb = ib.mass, i2 = ib.inertia.minCoeff();
  const double ma = wall ? 0.0 : infos[a].mass, i1 = wall ? 0.0 : infos[a].inertia.minCoeff();
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

void Contacts::list_body_pairs(std::size_t slots) {
  threads::list_by_body(
      slots, pairs_.size(),
      [&](std::size_t p) {
        return std::pair{live_slots_[pairs_[p].first], live_slots_[pairs_[p].second]};
      },
      body_pair_start_, body_pairs_);
  body_pairs_stale_ = false;
}

void Contacts::sum(Bodies& bodies, std::vector<Wall>& walls,
                   std::vector<Eigen::Vector3d>* diagonals, int nt) {
  // Every body's force and torque are summed in contact order, the same for any number of
  // threads. A body's contacts with other bodies come first in the list, pair by pair in the
  // pairs' order: each thread takes a block of bodies and walks each body's pairs
  // (body_pairs_), summing in registers. The walls' contacts follow in the list: each thread
  // then walks those and adds the ones of its bodies. Wall reactions are summed by the
  // first thread.
  std::vector<BodyState>& states = bodies.states();
  const std::size_t n = pending_count();
  records_current_ = false;  // records() makes them from this evaluation when asked
  if (body_pairs_stale_ || body_pair_start_.size() != states.size() + 1)
    list_body_pairs(states.size());
  const std::size_t slots = states.size();
  // By body: a loaded disc's few hundred contacts still leave all its bodies to sum.
  if (static_cast<std::ptrdiff_t>(slots) < kParallelMin) nt = 1;
  const std::size_t wall_begin = wall_contacts_begin();
  const bool summing_stress = diagonals != nullptr;
#pragma omp parallel num_threads(nt) if (nt > 1)
  {
    const threads::Block block =
        threads::thread_block(slots);  // captured below: not a structured binding
    const std::size_t t = block.thread, lo = block.begin, hi = block.end;
    // Plain doubles (vec3.hpp), with Eigen's bits. With the diagonals, eq. 2.17's terms
    // too (stress_sums: B's lever from its image, A's force negated).
    auto body = [&](std::size_t i, auto stress) {
      constexpr bool kStress = decltype(stress)::value;
      const std::uint32_t first = body_pair_start_[i], last = body_pair_start_[i + 1];
      if (first == last) {
        if constexpr (kStress) (*diagonals)[i].setZero();
        return;
      }
      BodyState& s = states[i];
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
      if constexpr (kStress) m.store((*diagonals)[i]);
    };
    if (summing_stress) {
      for (std::size_t i = lo; i < hi; ++i) body(i, std::true_type{});
    } else {
      for (std::size_t i = lo; i < hi; ++i) body(i, std::false_type{});
    }
    for_pending(wall_begin, n, [&](std::size_t k, const Pending& p) {
      const std::uint32_t a = p.key.a & ~kWallFlag, b = p.key.b;
      const ContactForce& fc = forces_[k];
      if (b >= lo && b < hi) {
        BodyState& sb = states[b];
        const V3 force = v3(fc.force), arm = v3(p.contact.point) - v3(sb.x);
        sb.f = eigen(v3(sb.f) + force);
        sb.tau = eigen(v3(sb.tau) + (cross(arm, force) + v3(fc.moment)));
        if (summing_stress) {
          StressDiagonal m;
          m.load((*diagonals)[b]);
          m.add(arm, force);
          m.store((*diagonals)[b]);
        }
      }
      if (t == 0) walls[a].reaction -= fc.force;
    });
  }
  std::swap(history_, next_history_);
}

const std::vector<ContactRecord>& Contacts::records(int wanted) const {
  if (!records_current_) {
    // Each thread fills its own block of the records, in contact order.
    const std::size_t n = pending_count();
    records_.resize(n);
    const int nt =
        static_cast<std::ptrdiff_t>(n) < kParallelMin ? 1 : threads::thread_count(wanted);
#pragma omp parallel num_threads(nt) if (nt > 1)
    {
      const threads::Block block = threads::thread_block(n);
      for_pending(block.begin, block.end, [&](std::size_t k, const Pending& p) {
        const bool wall = (p.key.a & kWallFlag) != 0;
        records_[k] = {p.key.a & ~kWallFlag,
                       p.key.b,
                       wall,
                       p.contact.point,
                       p.contact.normal,
                       overlaps_[k],
                       forces_[k].force,
                       contact_shift_.empty() ? Eigen::Vector3d::Zero() : contact_shift_[k]};
      });
    }
    records_current_ = true;
  }
  return records_;
}

}  // namespace cleave::physics
