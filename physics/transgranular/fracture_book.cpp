#include "physics/transgranular/fracture_book.hpp"

#include <limits>
#include <map>
#include <stdexcept>

#include "physics/dem/exact_sum.hpp"

namespace cleave::physics {

FractureBook::FractureBook(double dilation_radius, double min_fragment_fraction)
    : dilation_(dilation_radius), min_fraction_(min_fragment_fraction) {}

void FractureBook::add_shape(std::uint32_t shape_index,
                             std::shared_ptr<const geometry::ExactPolyhedron> shape) {
  shapes_[shape_index] = {shape, make_rigid_shape(*shape, dilation_)};
}

void FractureBook::add_grain(const World& world, BodyId id, int grain_id,
                             const geometry::CrystalOrientation& orientation) {
  const auto it = shapes_.find(world.info(id).shape);
  if (it == shapes_.end()) throw std::logic_error("FractureBook: body's shape is not registered");
  add_grain(world, id, grain_id, it->second.exact->cleavage_planes(orientation));
}

double FractureBook::resistance(int plane) const {
  return plane >= 0 && static_cast<std::size_t>(plane) < resistance_.size() ? resistance_[static_cast<std::size_t>(plane)]
                                                                            : 1.0;
}

void FractureBook::add_grain(const World& world, BodyId id, int grain_id,
                             std::vector<geometry::ExactPlane> planes) {
  const std::uint32_t shape = world.info(id).shape;
  if (shapes_.find(shape) == shapes_.end()) throw std::logic_error("FractureBook: body's shape is not registered");
  if (by_slot_.size() <= id.index) by_slot_.resize(id.index + 1);
  Record& r = by_slot_[id.index];
  r = Record{};
  r.generation = id.generation;
  r.used = true;
  r.lineage.grain_id = grain_id;
  r.shape = shape;
  r.planes = std::make_shared<const std::vector<geometry::ExactPlane>>(std::move(planes));
  for (int k = 0; k < static_cast<int>(r.planes->size()); ++k) r.candidates.push_back(k);
}

bool FractureBook::knows(BodyId id) const {
  return id.index < by_slot_.size() && by_slot_[id.index].used &&
         by_slot_[id.index].generation == id.generation;
}

const FractureBook::Record& FractureBook::record(BodyId id) const {
  if (id.index >= by_slot_.size() || !by_slot_[id.index].used ||
      by_slot_[id.index].generation != id.generation) {
    throw std::out_of_range("FractureBook: body is not registered");
  }
  return by_slot_[id.index];
}
FractureBook::Record& FractureBook::record(BodyId id) {
  return const_cast<Record&>(static_cast<const FractureBook&>(*this).record(id));
}

const std::vector<int>& FractureBook::candidates(BodyId id) const { return record(id).candidates; }
const std::vector<geometry::ExactPlane>& FractureBook::planes(BodyId id) const {
  return *record(id).planes;
}
const geometry::Lineage& FractureBook::lineage(BodyId id) const { return record(id).lineage; }
const geometry::ExactPolyhedron& FractureBook::exact_shape(BodyId id) const {
  return *shapes_.at(record(id).shape).exact;
}

const geometry::ExactScalar& FractureBook::projected(std::uint32_t shape,
                                                     const geometry::ExactPlane& plane) const {
  auto key = std::pair{shape, plane.to_string()};
  auto it = projected_.find(key);
  if (it == projected_.end()) {
    it =
        projected_.emplace(std::move(key), shapes_.at(shape).exact->projected_area_on(plane)).first;
  }
  return it->second;
}

double FractureBook::section_area(BodyId id, int plane) const {
  const Record& r = record(id);
  const geometry::ExactPlane& p = r.planes->at(static_cast<std::size_t>(plane));
  return p.area_of_projection(projected(r.shape, p));
}

double FractureBook::opened_at(BodyId id, int plane) const {
  for (const auto& [p, time] : record(id).opened) {
    if (p == plane) return time;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double FractureBook::grain_section_area(const World& world, int grain_id) const {
  const std::vector<geometry::ExactPlane>* planes = nullptr;
  std::vector<geometry::ExactScalar> sums;
  for (const BodyId id : world.body_ids()) {
    if (!knows(id)) continue;
    const Record& r = record(id);
    if (r.lineage.grain_id != grain_id || r.lineage.path.empty()) continue;
    planes = r.planes.get();
    sums.resize(planes->size());
    for (std::size_t k = 0; k < planes->size(); ++k)
      sums[k] = sums[k] + projected(r.shape, (*planes)[k]);
  }
  ExactSum area;
  for (std::size_t k = 0; k < sums.size(); ++k) area.add((*planes)[k].area_of_projection(sums[k]));
  return area.value();
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> FractureBook::world_plane(const World& world, BodyId id,
                                                                      int plane) const {
  const Record& r = record(id);
  const geometry::ExactPlane& p = r.planes->at(static_cast<std::size_t>(plane));
  const RigidShape& shape = world.shape(world.info(id).shape);
  const BodyState& s = world.state(id);
  // Grain coordinates -> principal frame -> world.
  const Eigen::Vector3d n = p.normal_approx();
  const Eigen::Vector3d on = n * p.offset_approx();
  return {s.q * (shape.axes.transpose() * n),
          s.x + s.q * (shape.axes.transpose() * (on - shape.centroid))};
}

SplitEvent FractureBook::split(World& world, BodyId id, int plane) {
  Record& r = record(id);
  SplitEvent event;
  event.time = world.time();
  event.parent = r.lineage;
  event.plane = plane;
  const geometry::ExactPlane& cut = r.planes->at(static_cast<std::size_t>(plane));
  const auto key = std::pair{r.shape, cut.to_string()};
  auto found = cuts_.find(key);
  if (found == cuts_.end()) {
    // The exact cut, once per (shape, plane): CGAL-backed, so never in the step loop.
    const geometry::SplitResult parts = shapes_.at(r.shape).exact->split(cut, min_fraction_);
    std::vector<std::uint32_t> made;
    if (parts.ok()) {
      std::vector<std::pair<std::shared_ptr<const geometry::ExactPolyhedron>, RigidShape>> two;
      for (const auto* part : {&*parts.below, &*parts.above}) {
        auto exact = std::make_shared<const geometry::ExactPolyhedron>(*part);
        RigidShape rigid = make_rigid_shape(*exact, dilation_);
        two.emplace_back(std::move(exact), std::move(rigid));
      }
      // A piece the contact search cannot take would meet nothing, and one below the
      // smallest volume is not split off: the cut is refused.
      const bool fits = within_contact_limits(two[0].second.primitives) &&
                        within_contact_limits(two[1].second.primitives) &&
                        two[0].second.volume >= min_volume_ && two[1].second.volume >= min_volume_;
      for (auto& [exact, rigid] : two) {
        if (!fits) break;
        const std::uint32_t index = world.add_shape(std::move(rigid));
        shapes_[index] = {exact, world.shape(index)};
        made.push_back(index);
      }
    }
    found = cuts_.emplace(key, std::move(made)).first;
  }
  if (found->second.empty()) {
    std::erase(r.candidates, plane);
    return event;
  }
  const auto [normal, point] = world_plane(world, id, plane);
  event.normal = normal;
  event.point = world.state(id).x;
  event.section_area = cut.area_of_projection(projected(found->second[0], cut));
  const RigidShape parent_shape = world.shape(r.shape);
  std::vector<Fragment> pieces;
  for (std::uint32_t index : found->second) {
    pieces.push_back(fragment_placement(parent_shape, world.shape(index), index));
  }
  const Record parent = r;  // r dies with the parent's slot
  event.ids = world.split_body(id, pieces);
  for (std::size_t k = 0; k < event.ids.size(); ++k) {
    const BodyId child = event.ids[k];
    if (by_slot_.size() <= child.index) by_slot_.resize(child.index + 1);
    Record& c = by_slot_[child.index];
    c = Record{};
    c.generation = child.generation;
    c.used = true;
    c.lineage = parent.lineage;
    c.lineage.path.push_back(static_cast<int>(k));
    c.shape = found->second[k];
    c.planes = parent.planes;
    c.opened = parent.opened;
    c.opened.emplace_back(plane, event.time);
    // The plane just used is spent; the others stay candidates while they cut the piece
    // (a refused cut drops them later).
    for (int p : parent.candidates) {
      if (p != plane) c.candidates.push_back(p);
    }
    event.pieces.push_back(c.lineage);
  }
  return event;
}

std::vector<FractureBook::Entry> FractureBook::entries(const World& world) const {
  std::vector<Entry> out;
  for (const BodyId id : world.body_ids()) {
    if (id.index >= by_slot_.size() || !by_slot_[id.index].used ||
        by_slot_[id.index].generation != id.generation) {
      continue;
    }
    const Record& r = by_slot_[id.index];
    out.push_back({id, r.lineage, shapes_.at(r.shape).exact});
  }
  return out;
}

FractureBook::Saved FractureBook::save() const {
  Saved saved;
  saved.dilation_radius = dilation_;
  saved.min_fragment_fraction = min_fraction_;
  for (const auto& [index, shape] : shapes_) saved.shapes.emplace_back(index, shape.exact);
  for (const auto& [key, pieces] : cuts_) saved.cuts.push_back({key.first, key.second, pieces});
  std::map<const std::vector<geometry::ExactPlane>*, int> set_index;
  for (const Record& r : by_slot_) {
    Saved::Body b;
    b.generation = r.generation;
    b.used = r.used;
    b.lineage = r.lineage;
    b.shape = r.shape;
    b.candidates = r.candidates;
    b.opened = r.opened;
    if (r.planes) {
      auto [it, fresh] = set_index.try_emplace(r.planes.get(), static_cast<int>(saved.plane_sets.size()));
      if (fresh) saved.plane_sets.push_back(r.planes);
      b.plane_set = it->second;
    }
    saved.bodies.push_back(std::move(b));
  }
  return saved;
}

FractureBook FractureBook::restore(const Saved& saved, const World& world) {
  FractureBook book(saved.dilation_radius, saved.min_fragment_fraction);
  for (const auto& [index, exact] : saved.shapes) {
    if (!exact || index >= world.shape_count()) {
      throw std::invalid_argument("FractureBook::restore: a shape is missing from the world");
    }
    book.shapes_[index] = {exact, world.shape(index)};
  }
  for (const Saved::Cut& c : saved.cuts) book.cuts_[{c.shape, c.plane}] = c.pieces;
  for (const Saved::Body& b : saved.bodies) {
    Record r;
    r.generation = b.generation;
    r.used = b.used;
    r.lineage = b.lineage;
    r.shape = b.shape;
    r.candidates = b.candidates;
    r.opened = b.opened;
    if (b.plane_set >= 0) {
      if (static_cast<std::size_t>(b.plane_set) >= saved.plane_sets.size()) {
        throw std::invalid_argument("FractureBook::restore: a plane set index is out of range");
      }
      r.planes = saved.plane_sets[static_cast<std::size_t>(b.plane_set)];
      for (int c : r.candidates) {
        if (c < 0 || static_cast<std::size_t>(c) >= r.planes->size()) {
          throw std::invalid_argument("FractureBook::restore: a candidate plane is out of range");
        }
      }
    } else if (b.used) {
      throw std::invalid_argument("FractureBook::restore: a body has no cleavage planes");
    }
    if (b.used && !book.shapes_.contains(b.shape)) {
      throw std::invalid_argument("FractureBook::restore: a body's shape is not registered");
    }
    book.by_slot_.push_back(std::move(r));
  }
  return book;
}

}  // namespace cleave::physics
