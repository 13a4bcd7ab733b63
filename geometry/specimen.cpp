#include "geometry/specimen.hpp"

#include <cstdio>
#include <map>
#include <stdexcept>

namespace cleave::geometry {

namespace {
void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}
}  // namespace

Specimen build_specimen(const SpecimenDef& def) {
  require(def.r > 0.0, "r must be positive");
  require(def.t > 0.0, "t must be positive");
  require(def.r_bar > 0.0 && def.r_bar <= def.r, "r_bar must be in (0, r]");
  require(def.t_bar > 0.0 && def.t_bar <= def.t, "t_bar must be in (0, t]");
  require(def.family_mix >= 0.0 && def.family_mix <= 1.0, "family_mix must be in [0, 1]");
  require(!def.angles.empty(), "angles must not be empty");
  for (int a : def.angles) require(a == 0 || a == 60 || a == 120, "angles must be 0, 60 or 120");
  for (int d = 0; d < 3; ++d) require(def.outline.size[d] > 0.0, "specimen sizes must be positive");

  Specimen s{def, {}, ExactPolyhedron::hexagonal_prism(def.r_bar, def.t_bar)};
  const auto sites = honeycomb_sites(def.r, def.t, def.outline, def.keep);
  s.grains.reserve(sites.size());
  for (std::size_t g = 0; g < sites.size(); ++g) {
    Grain grain;
    grain.id = static_cast<int>(g);
    grain.site = sites[g];
    grain.orientation = draw_orientation(def.seed, g, def.family_mix, def.angles);
    s.grains.push_back(grain);
  }
  return s;
}

std::string Lineage::path_string() const {
  std::string out = std::to_string(grain_id);
  for (int p : path) out += "." + std::to_string(p);
  return out;
}

std::string Lineage::name() const {
  char buf[32];
  std::snprintf(buf, sizeof buf, "grain_%04d", grain_id);
  std::string out = buf;
  for (int p : path) out += "." + std::to_string(p);
  return out;
}

std::vector<Piece> split_into_slabs(const Specimen& specimen, double min_fragment_fraction) {
  // Grains share one prism, so each distinct orientation is cut once.
  std::map<std::pair<int, int>, std::vector<std::shared_ptr<const ExactPolyhedron>>> cache;
  std::vector<Piece> pieces;
  for (const Grain& g : specimen.grains) {
    const auto key = std::make_pair(static_cast<int>(g.orientation.family), g.orientation.angle_deg);
    auto it = cache.find(key);
    if (it == cache.end()) {
      std::vector<std::shared_ptr<const ExactPolyhedron>> shapes;
      for (auto& slab : specimen.prism.cleavage_slabs(g.orientation, min_fragment_fraction)) {
        shapes.push_back(std::make_shared<const ExactPolyhedron>(std::move(slab)));
      }
      it = cache.emplace(key, std::move(shapes)).first;
    }
    for (std::size_t k = 0; k < it->second.size(); ++k) {
      pieces.push_back(Piece{Lineage{g.id, {static_cast<int>(k)}}, it->second[k], g.site.centre,
                             g.orientation});
    }
  }
  return pieces;
}

}  // namespace cleave::geometry
