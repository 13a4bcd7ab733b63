#include "physics/dem/bonds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

#include "physics/dem/bodies.hpp"
#include "physics/dem/cell_control.hpp"
#include "physics/dem/step_threads.hpp"

namespace cleave::physics {

namespace {
/// The area of the polygon the contact points of two touching faces span (their overlap's
/// corners), seen along `normal`; 0 when they span no area (an edge or corner contact).
double contact_polygon_area(const std::vector<FeatureContact>& features,
                            const Eigen::Vector3d& normal) {
  if (features.size() < 3) return 0.0;
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> corners;
  for (const FeatureContact& fc : features)
    corners.emplace_back(fc.contact.point.dot(u), fc.contact.point.dot(v));
  for (const auto& c : corners) centre += c / static_cast<double>(corners.size());
  std::sort(corners.begin(), corners.end(),
            [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
              return std::atan2(p.y() - centre.y(), p.x() - centre.x()) <
                     std::atan2(q.y() - centre.y(), q.x() - centre.x());
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

void Bonds::make(const BondParams& params, double distance, const Bodies& bodies,
                 const std::vector<PosedShape>& posed, const std::vector<std::uint32_t>& live,
                 const CellControl& cell, SearchMethod method) {
  const std::vector<BodyState>& states = bodies.states();
  std::vector<BoundingSphere> spheres;
  for (std::uint32_t slot : live)
    spheres.push_back({states[slot].x, bodies.shape_of(slot).bounding_radius()});
  std::vector<BodyPair> pairs;
  NeighbourSearch search(method);
  cell.find_pairs(search, spheres, distance, pairs);
  std::vector<FeatureContact> features, touching;
  PosedShape image;
  const bool cell_on = cell.on();
  for (const auto& [i, j] : pairs) {
    const std::uint32_t a = live[i], b = live[j];
    features.clear();
    // In a periodic cell the pair meets through B's nearest image.
    const Eigen::Vector3i n =
        cell_on ? cell.cell().nearest_image(states[a].x, states[b].x) : Eigen::Vector3i::Zero();
    const Eigen::Vector3d t = cell_on ? cell.cell().shift(n) : Eigen::Vector3d::Zero();
    if (!n.isZero()) CellControl::shifted_copy(posed[b], t, image);
    polyhedron_contacts(posed[a], n.isZero() ? posed[b] : image, distance, features);
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
    polyhedron_contacts(posed[a], n.isZero() ? posed[b] : image, 0.0, touching);
    for (const FeatureContact& fc : touching) {
      if (fc.contact.penetration > 0.0)
        bd.initial.push_back({fc.feature_a, fc.feature_b, fc.contact.penetration});
    }
    point /= static_cast<double>(features.size());
    if (normal.norm() < 1e-12) continue;  // opposed normals: no well-defined bond
    normal.normalize();
    const BodyState& sa = states[a];
    const BodyState& sb = states[b];
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
    bd.section.radius = std::min(posed[a].radius, posed[b].radius);
    bd.point = point;
    bd.normal = normal;
    bd.transmission = std::max(contact_polygon_area(features, normal), bd.section.area());
    bonds_.push_back(std::move(bd));
    body_bonds_stale_ = true;
  }
  params_ = params;
}

namespace {
/// A bond's own factor `what` (strength, stiffness), checked: finite and > 0.
void set_factor(std::vector<Bond>& bonds, std::size_t k, double factor, double Bond::*member,
                const char* what) {
  const std::string name = std::string("set_bond_") + what;
  if (k >= bonds.size()) throw std::out_of_range(name + ": no such bond");
  if (!(factor > 0.0) || !std::isfinite(factor))
    throw std::invalid_argument(name + ": the factor must be finite and > 0");
  bonds[k].*member = factor;
}
}  // namespace

void Bonds::set_strength(std::size_t k, double factor) {
  set_factor(bonds_, k, factor, &Bond::strength, "strength");
}

void Bonds::set_stiffness(std::size_t k, double factor) {
  set_factor(bonds_, k, factor, &Bond::stiffness, "stiffness");
}

BondCounts Bonds::counts() const {
  BondCounts c;
  for (const Bond& bd : bonds_) {
    switch (bd.failure) {
      case BondFailure::none:
        ++c.intact;
        break;
      case BondFailure::tension:
        ++c.tension;
        break;
      case BondFailure::shear:
        ++c.shear;
        break;
      case BondFailure::bending:
        ++c.bending;
        break;
      case BondFailure::torsion:
        ++c.torsion;
        break;
    }
  }
  return c;
}

std::size_t Bonds::break_by_stress(const std::vector<Eigen::Matrix3d>& stress,
                                   const std::vector<BodyInfo>& infos, double time,
                                   std::uint64_t step) {
  std::size_t broke = 0;
  for (std::size_t k = 0; k < bonds_.size(); ++k) {
    Bond& bd = bonds_[k];
    if (!bd.intact()) continue;
    const Eigen::Matrix3d mean = 0.5 * (stress[bd.a] + stress[bd.b]);
    double value = mean.trace() / 3.0;
    if (params_.criterion == BondCriterion::rankine) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(mean, Eigen::EigenvaluesOnly);
      value = solver.eigenvalues().maxCoeff();
    }
    if (!(value > params_.sigma_f * bd.strength)) continue;
    const BondState at = bd.state;
    bd.state = BondState{};
    bd.state.broken = true;
    bd.failure = BondFailure::tension;
    bd.broken_at = time;
    bd.force.setZero();
    bd.moment.setZero();
    if (k < push_.size()) push_[k].live = false;
    ++broke;
    breaks_.push_back({time, step, k, bd.a, bd.b, infos[bd.a].grain_id, infos[bd.b].grain_id,
                       bd.point, bd.normal, BondFailure::tension, at, bd.transmission});
  }
  return broke;
}

void Bonds::list_body_bonds(std::size_t slots) {
  threads::list_by_body(
      slots, bonds_.size(),
      [&](std::size_t k) {
        return std::pair{bonds_[k].a, bonds_[k].b};
      },
      body_bond_start_, body_bonds_);
  body_bonds_stale_ = false;
}

void Bonds::forget_slot(std::uint32_t slot) {
  std::erase_if(bonds_, [slot](const Bond& bd) { return bd.a == slot || bd.b == slot; });
  std::erase_if(offsets_, [slot](const PairOffset& o) { return o.a == slot || o.b == slot; });
}

Bonds::Parted Bonds::part(std::uint32_t old_slot) const {
  Parted parted;
  // Neighbours whose overlap with the parent counted from a stored value: every piece
  // gets that value with them (a piece may touch a neighbour its bond did not follow).
  auto remember = [&](std::uint32_t other, double overlap) {
    if (overlap > 0.0) parted.stored.emplace_back(other, overlap);
  };
  for (const Bond& bd : bonds_) {
    if (bd.a != old_slot && bd.b != old_slot) continue;
    parted.moved.push_back(bd);
    double most = 0.0;
    for (const auto& o : bd.initial) most = std::max(most, o.overlap);
    remember(bd.a == old_slot ? bd.b : bd.a, most);
  }
  for (const PairOffset& o : offsets_) {
    if (o.a == old_slot) remember(o.b, o.overlap);
    if (o.b == old_slot) remember(o.a, o.overlap);
  }
  return parted;
}

namespace {
/// The piece (index into `ids`) that holds `point` (world): the one whose shape it is
/// deepest inside (the least largest signed distance to a face plane).
std::size_t piece_holding(const Eigen::Vector3d& point, const std::vector<BodyId>& ids,
                          const Bodies& bodies) {
  std::size_t best = 0;
  double best_depth = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const BodyState& s = bodies.states()[ids[k].index];
    const auto& faces = bodies.shape_of(ids[k].index).primitives.faces;
    const Eigen::Vector3d local = s.q.conjugate() * (point - s.x);
    double depth = -std::numeric_limits<double>::infinity();  // largest signed distance
    for (const auto& face : faces) depth = std::max(depth, face.normal.dot(local) - face.offset);
    if (depth < best_depth) {
      best_depth = depth;
      best = k;
    }
  }
  return best;
}

/// A and B trade places: the normal turns round, and the loads on B become those on A.
void swap_ends(Bond& bd) {
  Bond::Beam& beam = bd.beam;
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
}  // namespace

void Bonds::follow_split(Parted parted, std::uint32_t old_slot, const BodyState& ps,
                         const std::vector<BodyId>& ids, const Bodies& bodies) {
  // Each bond follows its material point to the piece that holds it.
  for (Bond bd : parted.moved) {
    const bool parent_is_a = bd.a == old_slot;
    const Eigen::Vector3d arm = parent_is_a ? bd.arm_a : bd.arm_b;
    const Eigen::Vector3d normal = parent_is_a ? bd.normal_a : bd.normal_b;
    const Eigen::Vector3d point = ps.x + ps.q * arm;  // world, at the split
    const std::size_t best = piece_holding(point, ids, bodies);
    const BodyState& s = bodies.states()[ids[best].index];
    const std::uint32_t slot = ids[best].index;
    const Eigen::Vector3d new_arm = s.q.conjugate() * (point - s.x);
    const Eigen::Vector3d new_normal = s.q.conjugate() * (ps.q * normal);
    // A beam's end stays the material point it was (the parent's centroid at bonding),
    // now of the piece; its directions turn into the piece's frame.
    auto into_piece = [&](const Eigen::Vector3d& v) -> Eigen::Vector3d {
      return s.q.conjugate() * (ps.q * v);
    };
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
    if (bd.a > bd.b) swap_ends(bd);
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
    const double ri = bodies.shape_of(ids[i].index).primitives.dilation_radius;
    for (std::size_t j = i + 1; j < ids.size(); ++j) {
      const double rj = bodies.shape_of(ids[j].index).primitives.dilation_radius;
      offset(ids[i].index, ids[j].index, ri + rj);
    }
    for (const auto& [other, overlap] : parted.stored) offset(ids[i].index, other, overlap);
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
}

void Bonds::follow_wrap(const std::vector<Eigen::Vector3i>& moved, const PeriodicCell& cell) {
  if (moved.empty()) return;
  for (Bond& bd : bonds_) {
    // B's image x_B + H n stays where it was: n gains B's wrap and loses A's.
    bd.image += moved[bd.b] - moved[bd.a];
    bd.shift = cell.shift(bd.image);
  }
}

BondDynamic Bonds::dynamic(std::size_t k) const {
  const Bond& b = bonds_[k];
  return {k,       b.state,  b.failure, b.broken_at, b.thermal_gap, b.beam.rest_length,
          b.point, b.normal, b.force,   b.moment,    b.shift};
}

void Bonds::apply(const BondDynamic& d) {
  Bond& b = bonds_[d.index];
  b.state = d.state;
  b.failure = d.failure;
  b.broken_at = d.broken_at;
  b.thermal_gap = d.thermal_gap;
  b.beam.rest_length = d.rest_length;
  b.point = d.point;
  b.normal = d.normal;
  b.force = d.force;
  b.moment = d.moment;
  b.shift = d.shift;
}

void Bonds::restore(std::vector<Bond> bonds, std::vector<PairOffset> offsets,
                    const BondParams& params, std::vector<BondBreak> breaks) {
  bonds_ = std::move(bonds);
  body_bonds_stale_ = true;
  offsets_ = std::move(offsets);
  params_ = params;
  breaks_ = std::move(breaks);
}

}  // namespace cleave::physics
