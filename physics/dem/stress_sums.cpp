#include "physics/dem/stress_sums.hpp"

#include <stdexcept>

#include "physics/bonds/grain_stress.hpp"
#include "physics/dem/bodies.hpp"
#include "physics/dem/bonds.hpp"
#include "physics/dem/cell_control.hpp"
#include "physics/dem/contacts.hpp"
#include "physics/dem/step_threads.hpp"

namespace cleave::physics {

namespace {
using Pending = Contacts::Pending;

/// Calls f(point, force) (plain doubles) for each force acting on `slot`, in the order of
/// a walk over the contact records and the bonds (the lists by body current).
template <class F>
void for_forces_on(const StressSums::View& view, std::uint32_t slot, F&& f) {
  const Contacts& contacts = view.contacts;
  const std::vector<ContactForce>& forces = contacts.forces();
  const std::vector<Eigen::Vector3d>& shifts = contacts.shifts();
  // Contacts with other bodies, pair by pair in the pairs' order (the contact order), then
  // wall contacts (after every pair's in the list), then bonds in bond order: the order of
  // a walk over contacts() and bonds(). A's side: the force negated; B's: its lever from
  // its image.
  contacts.for_pair_contacts_of(slot, [&](bool is_b, const Pending& c, std::size_t k) {
    const V3 force = v3(forces[k].force), point = v3(c.contact.point);
    if (is_b) {
      f(shifts.empty() ? point : point - v3(shifts[k]), force);
    } else {
      f(point, -1.0 * force);
    }
  });
  const std::vector<std::uint32_t>& reach = contacts.wall_reach();
  if (reach.size() == view.bodies.slots() && reach[slot] != 0) {  // it may touch a wall
    contacts.for_pending(contacts.wall_contacts_begin(), contacts.pending_count(),
                         [&](std::size_t k, const Pending& p) {
                           if (p.key.b == slot) f(v3(p.contact.point), v3(forces[k].force));
                         });
  }
  const Bonds& bonds = view.bonds;
  if (bonds.empty()) return;
  const std::vector<Bond>& list = bonds.list();
  const std::vector<std::uint32_t>& start = bonds.body_start();
  const std::vector<std::uint32_t>& body_bonds = bonds.body_bonds();
  if (!view.decomposed) {
    // From the bonds' small records (the bond law's, kept current by the breaks after it):
    // the bond point and force, B's lever from its image only in a periodic cell (a zero
    // shift subtracted changes no bit).
    const bool cell_on = view.cell.on();
    for (std::uint32_t e = start[slot]; e < start[slot + 1]; ++e) {
      const std::uint32_t k = body_bonds[e] >> 1;
      const Bonds::Push& bp = bonds.pushes()[k];
      if (!bp.live) continue;
      if ((body_bonds[e] & 1u) != 0) {
        f(cell_on ? bp.point - v3(list[k].shift) : bp.point, bp.force);
      } else {
        f(bp.point, -1.0 * bp.force);
      }
    }
    return;
  }
  // Several processes: the ghosts' bonds are updated after the sums (MpiDomain).
  for (std::uint32_t e = start[slot]; e < start[slot + 1]; ++e) {
    const Bond& bd = list[body_bonds[e] >> 1];
    if (!bd.intact()) continue;
    if ((body_bonds[e] & 1u) != 0) {
      f(v3(bd.point) - v3(bd.shift), v3(bd.force));
    } else {
      f(v3(bd.point), -1.0 * v3(bd.force));
    }
  }
}

/// Sum::add(arm, force) over each live body's forces, in parallel, into out[slot]
/// (Sum::store).
template <class Sum, class Out>
void sum_by_body(const StressSums::View& view, std::vector<Out>& out) {
  const std::vector<BodyState>& states = view.bodies.states();
  const std::vector<BodyInfo>& infos = view.bodies.infos();
  const std::size_t slots = states.size();
  const int nt = static_cast<std::ptrdiff_t>(slots) < threads::kParallelMin
                     ? 1
                     : threads::thread_count(view.threads);
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
  for (std::size_t i = 0; i < slots; ++i) {
    if (!infos[i].alive) continue;
    const V3 x = v3(states[i].x);
    Sum m;
    for_forces_on(view, static_cast<std::uint32_t>(i),
                  [&](const V3& point, const V3& force) { m.add(point - x, force); });
    m.store(out[i]);
  }
}
}  // namespace

const std::vector<Eigen::Matrix3d>& StressSums::sums(const View& view) const {
  if (sums_current_ && view.by_body_current) return sums_;
  const std::vector<BodyState>& states = view.bodies.states();
  std::vector<Eigen::Matrix3d>& out = sums_;
  out.assign(states.size(), Eigen::Matrix3d::Zero());
  if (!view.by_body_current) {
    // Lists out of date (a split or a load since the last evaluation): from the records.
    for (const ContactRecord& c : view.contacts.records(view.threads)) {
      out[c.b] += (c.point - c.shift - states[c.b].x) * c.force.transpose();
      if (!c.wall) out[c.a] -= (c.point - states[c.a].x) * c.force.transpose();
    }
    for (const Bond& bd : view.bonds.list()) {
      if (!bd.intact()) continue;
      out[bd.b] += (bd.point - bd.shift - states[bd.b].x) * bd.force.transpose();
      out[bd.a] -= (bd.point - states[bd.a].x) * bd.force.transpose();
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (!view.bodies.infos()[i].alive) out[i].setZero();
    }
    return out;
  }
  sum_by_body<StressSum>(view, out);
  sums_current_ = true;
  return out;
}

Eigen::Matrix3d StressSums::sum(const View& view, std::uint32_t slot) const {
  if (slot >= view.bodies.slots() || !view.bodies.infos()[slot].alive)
    return Eigen::Matrix3d::Zero();
  if (!view.by_body_current) return sums(view)[slot];
  const V3 x = v3(view.bodies.states()[slot].x);
  StressSum m;
  for_forces_on(view, slot, [&](const V3& point, const V3& force) { m.add(point - x, force); });
  Eigen::Matrix3d out;
  m.store(out);
  return out;
}

const std::vector<Eigen::Vector3d>& StressSums::diagonals(const View& view) const {
  if (diagonals_current_ && view.by_body_current) return diagonals_;
  diagonals_.assign(view.bodies.slots(), Eigen::Vector3d::Zero());
  if (!view.by_body_current) {
    const std::vector<Eigen::Matrix3d>& full = sums(view);
    for (std::size_t i = 0; i < full.size(); ++i) diagonals_[i] = full[i].diagonal();
    return diagonals_;
  }
  sum_by_body<StressDiagonal>(view, diagonals_);
  diagonals_current_ = true;
  return diagonals_;
}

void StressSums::forces_on(const View& view, std::uint32_t slot,
                           std::vector<AppliedForce>& out) const {
  out.clear();
  if (slot >= view.bodies.slots() || !view.bodies.infos()[slot].alive) return;
  if (!view.by_body_current) {
    for (const ContactRecord& c : view.contacts.records(view.threads)) {
      if (c.b == slot) out.push_back({c.point - c.shift, c.force});
      if (!c.wall && c.a == slot) out.push_back({c.point, -c.force});
    }
    for (const Bond& bd : view.bonds.list()) {
      if (!bd.intact()) continue;
      if (bd.b == slot) out.push_back({bd.point - bd.shift, bd.force});
      if (bd.a == slot) out.push_back({bd.point, -bd.force});
    }
    return;
  }
  for_forces_on(view, slot, [&](const V3& point, const V3& force) {
    out.push_back({eigen(point), eigen(force)});
  });
}

std::vector<Eigen::Matrix3d> StressSums::body_stresses(const View& view) const {
  // Eq. 2.17: the sums of d (x) f per body (contact order: deterministic).
  const std::vector<Eigen::Matrix3d>& all = sums(view);
  std::vector<Eigen::Matrix3d> out(all.size(), Eigen::Matrix3d::Zero());
  const std::vector<BodyInfo>& infos = view.bodies.infos();
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (infos[i].alive)
      out[i] = stress_from_sum(all[i], view.bodies.shape_of(static_cast<std::uint32_t>(i)).volume);
  }
  return out;
}

Eigen::Matrix3d StressSums::cell_stress(const View& view) {
  if (!view.cell.on()) throw std::logic_error("cell_stress: there is no periodic cell");
  const std::vector<BodyState>& states = view.bodies.states();
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (const ContactRecord& c : view.contacts.records(view.threads)) {
    if (c.wall) {
      sum += (c.point - states[c.b].x) * c.force.transpose();
    } else {
      sum -= (states[c.b].x + c.shift - states[c.a].x) * c.force.transpose();
    }
  }
  for (const Bond& bd : view.bonds.list()) {
    if (bd.intact()) sum -= (states[bd.b].x + bd.shift - states[bd.a].x) * bd.force.transpose();
  }
  return 0.5 * (sum + sum.transpose()) / view.cell.cell().volume();
}

}  // namespace cleave::physics
