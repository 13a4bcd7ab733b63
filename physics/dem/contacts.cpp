// The contacts' detection: poses, the neighbour search, the narrow phase and the walls.

#include "physics/dem/contacts.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <tuple>

#include "physics/dem/bodies.hpp"
#include "physics/dem/cell_control.hpp"
#include "physics/dem/step_threads.hpp"

namespace cleave::physics {

using threads::kParallelMin;

namespace {
/// Broad test of a body (centre, bounding radius) against a wall's surface (planes) or axis
/// (cylinders): false when no point of it can touch.
[[gnu::always_inline]] inline bool wall_within_reach(const Wall& wall,
                                                     const Eigen::Vector3d& centre, double reach) {
  if (wall.kind != Wall::Kind::cylinder) return !(wall.normal.dot(centre - wall.origin) > reach);
  const Eigen::Vector3d rel = centre - wall.origin;
  const double s = std::clamp(rel.dot(wall.normal), 0.0, wall.length);
  return !((rel - s * wall.normal).norm() > reach + wall.radius);
}

/// Bit of wall w in a body's wall_reach_ word: walls from 31 on share the last bit.
std::uint32_t wall_bit(std::size_t w) {
  return 1u << std::min<std::size_t>(w, 31);
}

/// Ascending feature order within a pair keeps the keys ascending (see ContactKey).
void sort_by_features(std::vector<FeatureContact>& features) {
  std::sort(features.begin(), features.end(), [](const auto& x, const auto& y) {
    return std::tie(x.feature_a, x.feature_b) < std::tie(y.feature_a, y.feature_b);
  });
}
}  // namespace

bool Contacts::pose(Bodies& bodies, const std::vector<Wall>& walls, const CellControl& cell,
                    const WorldSettings& settings, int nt) {
  std::vector<BodyState>& states = bodies.states();
  const std::vector<BodyInfo>& infos = bodies.infos();
  const std::vector<RigidShape>& shapes = bodies.shapes();
  live_slots_.clear();
  for (std::uint32_t i = 0; i < states.size(); ++i) {
    if (infos[i].alive && bodies.role(i) != Role::dormant) live_slots_.push_back(i);
  }
  posed_.resize(states.size());
  wall_reach_.resize(states.size());
  const auto live = static_cast<std::ptrdiff_t>(live_slots_.size());
  // The neighbour search's pairs hold every pair that can touch until some point of some
  // body has moved half the skin since the search (its centre's move plus, for the turn,
  // 2 |q - q0| times its bounding radius: the pairs were kept by their boxes, which turn
  // with the body): the bodies that have are counted here, with the poses.
  const bool searched = pairs_current_ && searched_at_.size() == live_slots_.size() &&
                        searched_q_.size() == live_slots_.size();
  double limit = 0.5 * skin_;
  if (cell.on()) {
    // A pair's image moves with the cell vectors (by at most the sum of their changes).
    limit -= 0.5 * (cell.cell().vectors() - cell.at_search()).colwise().norm().sum();
  }
  const bool lazy = settings.manifold_tolerance > 0.0;
  std::size_t moved = 0;
#pragma omp parallel for num_threads(nt) schedule(static) if (live >= kParallelMin) reduction(+ : moved)
  for (std::ptrdiff_t k = 0; k < live; ++k) {
    const std::uint32_t i = live_slots_[static_cast<std::size_t>(k)];
    states[i].f = infos[i].mass * settings.gravity;
    states[i].tau.setZero();
    // With manifolds, only the bodies a search or a wall reads get their vertices and
    // planes (narrow); the frame is all the carried contacts need.
    if (lazy) {
      posed_[i].update_frame(shapes[infos[i].shape], states[i]);
    } else {
      posed_[i].update(shapes[infos[i].shape], states[i]);
    }
    // The walls that may touch it (walls have moved for this step already).
    std::uint32_t reach = 0;
    const double bounding = shapes[infos[i].shape].bounding_radius();
    for (std::size_t w = 0; w < walls.size(); ++w) {
      if (wall_within_reach(walls[w], posed_[i].centre, bounding)) reach |= wall_bit(w);
    }
    wall_reach_[i] = reach;
    if (searched) {
      const auto j = static_cast<std::size_t>(k);
      const double turn = turn_between(states[i].q, searched_q_[j]);
      const double reach = (states[i].x - searched_at_[j]).norm() +
                           2.0 * shapes[infos[i].shape].bounding_radius() * turn;
      moved += !(reach < limit);
    }
  }
  return !searched || moved > 0 || !(limit > 0.0);
}

void Contacts::search(const Bodies& bodies, const CellControl& cell,
                      const WorldSettings& settings) {
  // Neighbour search with a Verlet skin (see pose).
  const std::vector<BodyState>& states = bodies.states();
  const bool cell_on = cell.on();
  spheres_.clear();
  double smallest = std::numeric_limits<double>::infinity();
  for (std::uint32_t slot : live_slots_) {
    const double r = bodies.shape_of(slot).bounding_radius();
    spheres_.push_back({states[slot].x, r});
    smallest = std::min(smallest, r);
  }
  skin_ = live_slots_.empty() ? 0.0 : settings.search_skin * smallest;
  // The manifolds are the pairs' and follow them to the new list (both are sorted) when no
  // body came or went; otherwise they are searched afresh.
  std::vector<BodyPair> old_pairs;
  std::vector<ContactManifold> old_manifolds;
  if (settings.manifold_tolerance > 0.0 && manifold_slots_ == live_slots_) {
    old_pairs = pairs_;
    old_manifolds = std::move(manifolds_);
  }
  cell.find_pairs(search_, spheres_, skin_, pairs_);
  if (cell_on) {
    pair_image_.resize(pairs_.size());
    for (std::size_t p = 0; p < pairs_.size(); ++p)
      pair_image_[p] = cell.cell().nearest_image(states[live_slots_[pairs_[p].first]].x,
                                                 states[live_slots_[pairs_[p].second]].x);
  }
  // Bounding spheres are loose around thick or long prisms (a 5 mm thick grain of 0.6 mm
  // side reaches 2.6 mm round): the pairs whose dilated boxes are a skin apart along some
  // axis are dropped; until the next search no point moves half the skin, so they cannot
  // meet. The contacts are the same, in the same order (pairs stay sorted).
  if (settings.manifold_tolerance > 0.0)
    for (std::uint32_t slot : live_slots_) posed_[slot].update_geometry();  // boxes of all
  std::size_t kept = 0;
  const bool decomposed = !bodies.roles().empty();
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const PosedShape& a = posed_[live_slots_[pairs_[p].first]];
    const PosedShape& b = posed_[live_slots_[pairs_[p].second]];
    const double reach = a.radius + b.radius + skin_;
    Eigen::Vector3d b_lo = b.lo, b_hi = b.hi;
    if (cell_on && !pair_image_[p].isZero()) {
      const Eigen::Vector3d t = cell.cell().shift(pair_image_[p]);
      b_lo += t;
      b_hi += t;
    }
    if (((a.lo.array() - reach > b_hi.array()) || (b_lo.array() - reach > a.hi.array())).any())
      continue;
    // One process of a decomposition: the pairs of two ghosts are their owners' to evaluate.
    if (decomposed && !bodies.owns(live_slots_[pairs_[p].first]) &&
        !bodies.owns(live_slots_[pairs_[p].second]))
      continue;
    if (cell_on) pair_image_[kept] = pair_image_[p];
    pairs_[kept++] = pairs_[p];
  }
  pairs_.resize(kept);
  body_pairs_stale_ = true;
  if (cell_on) pair_image_.resize(kept);
  manifolds_.clear();
  if (settings.manifold_tolerance > 0.0) {
    manifolds_.resize(pairs_.size());
    std::size_t j = 0;
    for (std::size_t i = 0; i < pairs_.size() && j < old_pairs.size(); ++i) {
      while (j < old_pairs.size() && old_pairs[j] < pairs_[i]) ++j;
      if (j < old_pairs.size() && old_pairs[j] == pairs_[i])
        manifolds_[i] = std::move(old_manifolds[j]);
    }
    manifold_slots_ = live_slots_;
  }
  held_.clear();  // made again from the manifolds in plan
  near_.clear();
  searched_at_.clear();
  searched_q_.clear();
  for (std::uint32_t slot : live_slots_) {
    searched_at_.push_back(states[slot].x);
    searched_q_.push_back(states[slot].q);
  }
  pairs_current_ = true;
}

void Contacts::plan(const CellControl& cell, const WorldSettings& settings, int nt) {
  // The pairs in chunks of consecutive pairs (narrow), each chunk's contacts in a list of
  // its own: the lists in chunk order make the contact list.
  const std::size_t n = pairs_.size();
  if (static_cast<std::ptrdiff_t>(n) < kParallelMin) nt = 1;
  const std::size_t chunks = (n + kPairChunk - 1) / kPairChunk;
  if (chunk_pending_.size() < chunks) chunk_pending_.resize(chunks);
  if (cell.on() && chunk_shift_.size() < chunks) chunk_shift_.resize(chunks);
  parts_.clear();
  for (std::size_t chunk = 0; chunk < chunks; ++chunk)
    parts_.push_back(&chunk_pending_[chunk].list);
  // Each pair's near features (narrow_phase.hpp), kept with the pair list: the search over
  // them gives what the full search would, bit for bit, and skips what cannot touch.
  if (settings.feature_skin > 0.0) near_.resize(n);
  const bool manifolds = settings.manifold_tolerance > 0.0;
  if (manifolds && manifolds_.size() != n) manifolds_.assign(n, ContactManifold{});
  if (manifolds && held_.size() != n) {
    held_.resize(n);
    for (std::size_t p = 0; p < n; ++p) held_[p] = manifolds_[p].margin > 0.0;
  }
  if (manifolds) plan_pairs(nt, posed_.size(), settings.feature_skin > 0.0);
}

void Contacts::plan_pairs(int nt, std::size_t slots, bool cached) {
  // Which pairs carry their manifold's contacts, which the near features hold apart, and
  // which are searched; a body that a search will read gets its vertices and planes, one
  // that only a wall reads its vertices, the others keep their frame alone
  // (PosedShape::update_frame).
  const std::size_t n = pairs_.size();
  plan_.resize(n);
  need_geometry_.assign(slots, 0);
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

/// One thread's scratch space in the narrow phase.
struct Contacts::NarrowScratch {
  std::vector<FeatureContact> features;
  PosedShape image;  // B's image across a periodic face
};

void Contacts::narrow(const CellControl& cell, const WorldSettings& settings, int nt) {
  // The pairs in chunks of consecutive pairs, handed to the threads as they come free (the
  // cost of a pair varies a hundredfold); the chunks' contacts are joined in chunk order,
  // so the contact list (and everything after it) is the same for any number of threads.
  const std::size_t n = pairs_.size();
  if (static_cast<std::ptrdiff_t>(n) < kParallelMin) nt = 1;
  const std::size_t chunks = (n + kPairChunk - 1) / kPairChunk;
  const bool cell_on = cell.on();
  pair_first_.resize(n);
#pragma omp parallel num_threads(nt) if (nt > 1)
  {
    NarrowScratch scratch;
#pragma omp for schedule(dynamic, 1)
    for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
      auto& out = chunk_pending_[chunk].list;
      out.clear();
      if (cell_on) chunk_shift_[chunk].list.clear();
      const std::size_t begin = chunk * kPairChunk, end = std::min(n, begin + kPairChunk);
      for (std::size_t p = begin; p < end; ++p) {
        pair_first_[p] = static_cast<std::uint32_t>(out.size());
        scratch.features.clear();
        if (cell_on) {
          narrow_periodic_pair(p, cell, settings, out, chunk_shift_[chunk].list, scratch);
        } else {
          narrow_pair(p, end, settings, out, scratch);
        }
      }
    }
  }
}

[[gnu::always_inline]] inline void Contacts::narrow_pair(std::size_t p, std::size_t end,
                                                         const WorldSettings& settings,
                                                         std::vector<Pending>& out,
                                                         NarrowScratch& scratch) {
  const std::uint32_t a = live_slots_[pairs_[p].first], b = live_slots_[pairs_[p].second];
  std::vector<FeatureContact>& features = scratch.features;
  const bool cached = settings.feature_skin > 0.0;
  const bool manifolds = settings.manifold_tolerance > 0.0;
  const double radii = posed_[a].radius + posed_[b].radius;
  if (p + 4 < end) prefetch_posed(live_slots_[pairs_[p + 4].second]);  // as in plan_pairs
  if (manifolds && plan_[p] == kCarried) {
    // Straight into the list: held in feature order, overlapping only.
    for_carried_contacts(posed_[a], posed_[b], manifolds_[p],
                         [&](std::uint32_t fa, std::uint32_t fb, const PrimitiveContact& c) {
                           out.push_back({{a, b, fa, fb}, c});
                         });
    return;
  }
  if (manifolds && plan_[p] == kApart) {
    // the near features say nothing can touch: what the search would find
  } else {
    if (cached) {
      polyhedron_contacts(posed_[a], posed_[b], settings.feature_skin * radii, near_[p], features);
    } else {
      polyhedron_contacts(posed_[a], posed_[b], 0.0, features);
    }
    // A pair that touches keeps its contacts from here on; one that does not is left to
    // the search (apart, it costs next to nothing).
    if (manifolds) {
      const bool touching =
          std::any_of(features.begin(), features.end(),
                      [](const FeatureContact& f) { return f.contact.penetration > 0.0; });
      if (!touching && held_[p]) manifolds_[p].margin = 0.0;  // held_ follows it (restarts)
      held_[p] = touching;
      if (touching)
        capture_manifold(posed_[a], posed_[b], features, settings.manifold_tolerance * radii,
                         manifolds_[p]);
    }
  }
  // Ascending feature order within the pair keeps the keys ascending (see ContactKey).
  if (!manifolds || plan_[p] == kSearch) sort_by_features(features);
  for (const auto& fc : features) {
    if (fc.contact.penetration > 0.0) {
      out.push_back({{a, b, fc.feature_a, fc.feature_b}, fc.contact});
    }
  }
}

void Contacts::narrow_periodic_pair(std::size_t p, const CellControl& cell,
                                    const WorldSettings& settings, std::vector<Pending>& out,
                                    std::vector<Eigen::Vector3d>& shifts, NarrowScratch& scratch) {
  // Every contact of the pair, in the pair's order, against B's image (searched in full:
  // the feature cache follows B itself, not its image; no manifolds).
  const std::uint32_t a = live_slots_[pairs_[p].first], b = live_slots_[pairs_[p].second];
  std::vector<FeatureContact>& features = scratch.features;
  const bool shifted = !pair_image_[p].isZero();
  const Eigen::Vector3d t = shifted ? cell.cell().shift(pair_image_[p]) : Eigen::Vector3d::Zero();
  if (shifted) {
    CellControl::shifted_copy(posed_[b], t, scratch.image);
    polyhedron_contacts(posed_[a], scratch.image, 0.0, features);
  } else if (settings.feature_skin > 0.0) {
    polyhedron_contacts(posed_[a], posed_[b],
                        settings.feature_skin * (posed_[a].radius + posed_[b].radius), near_[p],
                        features);
  } else {
    polyhedron_contacts(posed_[a], posed_[b], 0.0, features);
  }
  sort_by_features(features);
  for (const auto& fc : features) {
    if (fc.contact.penetration > 0.0) {
      out.push_back({{a, b, fc.feature_a, fc.feature_b}, fc.contact});
      shifts.push_back(t);
    }
  }
}

void Contacts::walls(const Bodies& bodies, const std::vector<Wall>& walls, bool cell, int nt) {
  // The body slots in pieces, handed to the threads as they come free; each piece lists its
  // contacts with every wall, and the pieces' lists are joined in order, wall by wall, as
  // one thread would list them, for any number of threads. Each list has cache lines of its
  // own (OwnLines): side by side, two threads' lists shared the line holding their ends.
  const auto slots = live_slots_.size();
  if (static_cast<std::ptrdiff_t>(slots) < kParallelMin || walls.empty()) nt = 1;
  const std::size_t pieces = std::max<std::size_t>(1, (slots + kWallPiece - 1) / kWallPiece);
  const std::size_t lists = pieces * walls.size();
  if (wall_pending_.size() < lists) wall_pending_.resize(lists);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1) if (nt > 1)
  for (std::size_t piece = 0; piece < pieces; ++piece) {
    for (std::uint32_t w = 0; w < walls.size(); ++w) wall_pending_[w * pieces + piece].list.clear();
    // Body by body, wall by wall within: one pass over the bodies; each wall's list still
    // takes its contacts in body order.
    const std::size_t end = std::min(slots, (piece + 1) * kWallPiece);
    for (std::size_t k = piece * kWallPiece; k < end; ++k) {
      const std::uint32_t slot = live_slots_[k];
      if (!bodies.owns(slot)) continue;  // a ghost's wall contacts are its owner's
      const std::uint32_t reach = wall_reach_[slot];
      if (reach == 0) continue;
      const PosedShape& p = posed_[slot];
      for (std::uint32_t w = 0; w < walls.size(); ++w) {
        auto& out = wall_pending_[w * pieces + piece].list;
        const Wall& wall = walls[w];
        const std::uint32_t a = w | kWallFlag;
        if ((reach & wall_bit(w)) == 0) continue;
        if (w >= 31 && !wall_within_reach(wall, p.centre, bodies.shape_of(slot).bounding_radius()))
          continue;
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
  join_pending(cell);
}

void Contacts::join_pending(bool cell) {
  part_start_.assign(parts_.size() + 1, 0);
  for (std::size_t k = 0; k < parts_.size(); ++k)
    part_start_[k + 1] = part_start_[k] + parts_[k]->size();
  contact_shift_.clear();
  if (cell) {
    // The pairs' chunks come first, in order, then the walls' lists (no shift).
    contact_shift_.assign(part_start_.back(), Eigen::Vector3d::Zero());
    const std::size_t chunks = (pairs_.size() + kPairChunk - 1) / kPairChunk;
    for (std::size_t c = 0; c < chunks && c < parts_.size(); ++c)
      std::copy(chunk_shift_[c].list.begin(), chunk_shift_[c].list.end(),
                contact_shift_.begin() + static_cast<std::ptrdiff_t>(part_start_[c]));
  }
}

std::size_t Contacts::wall_contacts_begin() const {
  const std::size_t chunks = (pairs_.size() + kPairChunk - 1) / kPairChunk;
  return chunks < part_start_.size() ? part_start_[chunks] : pending_count();
}

std::vector<WallForceAt> Contacts::wall_forces() const {
  std::vector<WallForceAt> out;
  for_pending(wall_contacts_begin(), pending_count(), [&](std::size_t k, const Pending& p) {
    if ((p.key.a & kWallFlag) != 0)
      out.push_back({p.key.a & ~kWallFlag, p.key.b, k, forces_[k].force});
  });
  return out;
}

std::size_t Contacts::owned_count(const Bodies& bodies) const {
  std::size_t n = 0;
  for_pending(0, pending_count(), [&](std::size_t, const Pending& p) {
    const bool wall = (p.key.a & kWallFlag) != 0;
    n += bodies.owns(wall ? p.key.b : p.key.a);
  });
  return n;
}

void Contacts::pose_geometry() {
  for (std::uint32_t slot : live_slots_) posed_[slot].update_geometry();
}

void Contacts::forget_slot(std::uint32_t slot) {
  pairs_current_ = false;
  std::erase_if(history_, [slot](const HistoryEntry& e) {
    return ((e.key.a & kWallFlag) == 0 && e.key.a == slot) || e.key.b == slot;
  });
}

void Contacts::merge_histories(const std::vector<HistoryEntry>& arrived) {
  if (arrived.empty()) return;
  auto key_less = [](const HistoryEntry& p, const HistoryEntry& q) { return p.key < q.key; };
  std::vector<HistoryEntry> merged;
  merged.reserve(history_.size() + arrived.size());
  std::size_t a = 0, b = 0;
  while (a < history_.size() || b < arrived.size()) {
    if (b == arrived.size() || (a < history_.size() && key_less(history_[a], arrived[b]))) {
      merged.push_back(history_[a++]);
    } else if (a == history_.size() || key_less(arrived[b], history_[a])) {
      if (merged.empty() || merged.back().key != arrived[b].key) merged.push_back(arrived[b]);
      ++b;
    } else {
      merged.push_back(history_[a++]);
      ++b;
    }
  }
  history_ = std::move(merged);
}

void Contacts::restore(SearchMethod search, SearchState state, std::vector<HistoryEntry> history,
                       std::vector<ContactRecord> records, const Bodies& bodies) {
  search_ = NeighbourSearch(search);
  pairs_current_ = state.current;
  skin_ = state.skin;
  searched_at_ = std::move(state.at);
  searched_q_ = std::move(state.q);
  pairs_ = std::move(state.pairs);
  body_pairs_stale_ = true;
  pair_image_ = std::move(state.images);
  near_.clear();
  manifolds_ = std::move(state.manifolds);
  manifold_slots_ = std::move(state.manifold_slots);
  held_.clear();  // made again from the manifolds
  history_ = std::move(history);
  next_history_.clear();
  records_ = std::move(records);
  records_current_ = true;
  // The posed shapes of this state (initialise_bonds reads them when the forces are current).
  const std::vector<BodyState>& states = bodies.states();
  live_slots_.clear();
  posed_.assign(states.size(), PosedShape{});
  for (std::uint32_t i = 0; i < states.size(); ++i) {
    if (!bodies.infos()[i].alive) continue;
    live_slots_.push_back(i);
    posed_[i].update(bodies.shape_of(i), states[i]);
  }
  if (pairs_current_ && searched_at_.size() != live_slots_.size()) pairs_current_ = false;
}

}  // namespace cleave::physics
