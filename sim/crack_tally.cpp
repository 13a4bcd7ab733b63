#include "sim/crack_tally.hpp"

#include <set>

namespace cleave::sim {

namespace {
std::optional<double> share(double part, double whole) {
  return whole > 0.0 ? std::optional(part / whole) : std::nullopt;
}
}  // namespace

std::optional<double> CrackTotals::transgranular_area_fraction() const {
  return share(transgranular_area, intergranular_area + transgranular_area);
}
// The intergranular fractions are one minus the transgranular ones: 1 - t then + t rounds
// back to one for t in [0, 1], so the pair sums to one in double arithmetic too.
std::optional<double> CrackTotals::intergranular_area_fraction() const {
  const auto t = transgranular_area_fraction();
  return t ? std::optional(1.0 - *t) : std::nullopt;
}
std::optional<double> CrackTotals::transgranular_count_fraction() const {
  return share(static_cast<double>(transgranular),
               static_cast<double>(intergranular + transgranular));
}
std::optional<double> CrackTotals::intergranular_count_fraction() const {
  const auto t = transgranular_count_fraction();
  return t ? std::optional(1.0 - *t) : std::nullopt;
}

CrackTotals CrackTotals::since(const CrackTotals& before) const {
  return {intergranular_area - before.intergranular_area,
          transgranular_area - before.transgranular_area, intergranular - before.intergranular,
          transgranular - before.transgranular};
}

void put_totals(physics::StateWriter& w, const CrackTotals& c) {
  w.put(c.intergranular_area);
  w.put(c.transgranular_area);
  w.put<std::uint64_t>(c.intergranular);
  w.put<std::uint64_t>(c.transgranular);
}

CrackTotals get_totals(physics::StateReader& r) {
  CrackTotals c;
  c.intergranular_area = r.get<double>();
  c.transgranular_area = r.get<double>();
  c.intergranular = r.get<std::uint64_t>();
  c.transgranular = r.get<std::uint64_t>();
  return c;
}

void CrackTally::add_breaks(const physics::World& world) {
  const auto& breaks = world.bond_breaks();
  if (breaks_seen_ == breaks.size()) return;
  for (; breaks_seen_ < breaks.size(); ++breaks_seen_)
    intergranular_.add(breaks[breaks_seen_].face_area);
  intergranular_area_ = intergranular_.value();
}

void CrackTally::add_splits(const physics::World& world, const physics::FractureBook& book,
                            std::span<const physics::TransgranularEvent> events) {
  std::set<int> grains;
  for (const auto& e : events) grains.insert(e.split.parent.grain_id);
  for (const int g : grains) grain_area_[g] = book.grain_section_area(world, g);
  splits_ += events.size();
  sum_grains();
}

void CrackTally::sum_grains() {
  physics::ExactSum sum;
  for (const auto& [grain, area] : grain_area_) sum.add(area);
  transgranular_area_ = sum.value();
}

void CrackTally::rebuild(const physics::World& world, const physics::FractureBook* book,
                         std::size_t splits) {
  *this = CrackTally{};
  add_breaks(world);
  splits_ = splits;
  if (book == nullptr) return;
  std::set<int> grains;
  for (const auto& e : book->entries(world)) {
    if (!e.lineage.path.empty()) grains.insert(e.lineage.grain_id);
  }
  for (const int g : grains) grain_area_[g] = book->grain_section_area(world, g);
  sum_grains();
}

CrackTotals CrackTally::totals() const {
  return {intergranular_area_, transgranular_area_, breaks_seen_, splits_};
}

}  // namespace cleave::sim
