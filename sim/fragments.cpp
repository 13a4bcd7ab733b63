// Fragments: the clusters of bodies joined by intact bonds (union-find over the bonds).

#include "sim/fragments.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <stdexcept>

namespace cleave::sim {

std::vector<std::vector<std::uint32_t>> connected_clusters(
    std::size_t count, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& links) {
  std::vector<std::uint32_t> parent(count);
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];  // path halving
    return i;
  };
  for (const auto& [a, b] : links) {
    if (a >= count || b >= count)
      throw std::out_of_range("connected_clusters: link beyond the items");
    const std::uint32_t ra = root(a), rb = root(b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);  // the smaller index is the root
  }
  std::vector<std::vector<std::uint32_t>> clusters;
  std::vector<std::int64_t> index(count, -1);  // root -> cluster
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint32_t r = root(i);
    if (index[r] < 0) {
      index[r] = static_cast<std::int64_t>(clusters.size());
      clusters.emplace_back();
    }
    clusters[static_cast<std::size_t>(index[r])].push_back(i);
  }
  return clusters;
}

std::vector<BondedFragment> bonded_fragments(
    const physics::World& world,
    const std::function<geometry::ExactScalar(std::uint32_t slot)>& exact_volume) {
  const auto& infos = world.slot_infos();
  // The live bodies, numbered densely.
  std::vector<std::uint32_t> slot_of;
  std::vector<std::int64_t> item(infos.size(), -1);
  for (std::uint32_t s = 0; s < infos.size(); ++s) {
    if (!infos[s].alive) continue;
    item[s] = static_cast<std::int64_t>(slot_of.size());
    slot_of.push_back(s);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> links;
  for (const physics::Bond& b : world.bonds()) {
    if (!b.intact() || b.a >= item.size() || b.b >= item.size()) continue;
    if (item[b.a] < 0 || item[b.b] < 0) continue;
    links.emplace_back(static_cast<std::uint32_t>(item[b.a]),
                       static_cast<std::uint32_t>(item[b.b]));
  }
  std::vector<BondedFragment> out;
  for (const auto& cluster : connected_clusters(slot_of.size(), links)) {
    BondedFragment f;
    for (std::uint32_t i : cluster) {
      const std::uint32_t s = slot_of[i];
      f.slots.push_back(s);
      f.mass += infos[s].mass;
      f.volume = f.volume + exact_volume(s);
    }
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace cleave::sim
