#include "physics/dem/exchange.hpp"

#include <algorithm>
#include <cstring>

namespace cleave::physics {

namespace {
bool key_less(const HistoryEntry& p, const HistoryEntry& q) {
  return p.key < q.key;
}
}  // namespace

void Exchange::pack_state(std::uint32_t slot, char* out) const {
  std::memcpy(out, &bodies_.states()[slot], kStateBytes);
}

void Exchange::unpack_state(std::uint32_t slot, const char* in) {
  std::memcpy(static_cast<void*>(&bodies_.states()[slot]), in, kStateBytes);
}

std::vector<HistoryEntry> Exchange::histories_of(std::uint32_t slot) const {
  std::vector<HistoryEntry> out;
  for (const HistoryEntry& e : contacts_.histories()) {
    if (e.key.a == slot || e.key.b == slot) out.push_back(e);
  }
  return out;
}

void Exchange::merge_histories(std::vector<HistoryEntry> arrived) {
  std::sort(arrived.begin(), arrived.end(), key_less);
  contacts_.merge_histories(arrived);
}

std::vector<std::vector<std::uint32_t>> Exchange::bonds_by_slot() const {
  std::vector<std::vector<std::uint32_t>> out(bodies_.slots());
  const std::vector<Bond>& bonds = bonds_.list();
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    out[bonds[k].a].push_back(static_cast<std::uint32_t>(k));
    out[bonds[k].b].push_back(static_cast<std::uint32_t>(k));
  }
  return out;
}

void Exchange::set_wall_reactions(const std::vector<WallForceAt>& forces) {
  for (auto& w : walls_) w.reaction.setZero();
  for (const auto& f : forces) walls_[f.wall].reaction -= f.force;
}

std::vector<HistoryEntry> Exchange::owned_histories() const {
  std::vector<HistoryEntry> out;
  for (const HistoryEntry& e : contacts_.histories()) {
    const bool wall = (e.key.a & Contacts::kWallFlag) != 0;
    if (bodies_.owns(wall ? e.key.b : e.key.a)) out.push_back(e);
  }
  return out;
}

void Exchange::set_histories(std::vector<HistoryEntry> history) {
  std::sort(history.begin(), history.end(), key_less);
  contacts_.set_histories(std::move(history));
}

}  // namespace cleave::physics
