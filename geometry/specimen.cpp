#include "geometry/specimen.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

#include "geometry/laguerre.hpp"
#include "geometry/orientation.hpp"
#include "geometry/phases.hpp"

namespace cleave::geometry {

namespace {
void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}
}  // namespace

namespace {

/// Each grain's crystal: the honeycomb's turn about z, or with [crystal] its law's draw.
void orient_grains(const SpecimenDef& def, std::vector<Grain>& grains) {
  const OrientationDef& o = def.orientation;
  // Orientations read from a file: the orientation file's or the specimen file's own.
  const std::vector<Eigen::Quaterniond>* read =
      o.law == OrientationLaw::given ? &o.given : o.law == OrientationLaw::imported ? &def.orientations : nullptr;
  if (def.crystal.enabled && read != nullptr && read->size() != grains.size()) {
    throw std::invalid_argument(std::string(o.law == OrientationLaw::given ? "the orientation file" : "the specimen file") +
                                " gives " + std::to_string(read->size()) + " orientations for " +
                                std::to_string(grains.size()) + " grains; give one per grain");
  }
  constexpr double deg = M_PI / 180.0;
  const double spread = o.spread_deg * deg;
  const Eigen::Quaterniond mean = from_bunge(o.euler_deg[0] * deg, o.euler_deg[1] * deg, o.euler_deg[2] * deg);
  for (Grain& g : grains) {
    const auto id = static_cast<std::uint64_t>(g.id);
    if (!def.crystal.enabled || o.law == OrientationLaw::honeycomb) {
      g.crystal = Eigen::Quaterniond(
          Eigen::AngleAxisd(g.orientation.angle_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()));
      continue;
    }
    switch (o.law) {
      case OrientationLaw::uniform: g.crystal = uniform_orientation(def.seed, id); break;
      case OrientationLaw::fibre:
        g.crystal = fibre_orientation(def.seed, id, o.crystal_direction.normalized(),
                                      o.specimen_axis.normalized(), spread);
        break;
      case OrientationLaw::preferred: g.crystal = preferred_orientation(def.seed, id, mean, spread); break;
      case OrientationLaw::given:
      case OrientationLaw::imported: g.crystal = (*read)[static_cast<std::size_t>(g.id)]; break;
      case OrientationLaw::honeycomb: break;
    }
  }
}

/// Grains that are not on the lattice: each shape (specimen coordinates) moved exactly so
/// `centres[i]` is its grain frame's origin.
Specimen place_grains(const SpecimenDef& def, const std::vector<ExactPolyhedron>& shapes,
                      const std::vector<Eigen::Vector3d>& centres) {
  require(!shapes.empty(), "the specimen has no grains");
  std::vector<ExactPolyhedron> local;
  double lowest = std::numeric_limits<double>::infinity();
  std::vector<double> lows;
  for (std::size_t g = 0; g < shapes.size(); ++g) {
    local.push_back(shapes[g].translated(-centres[g]));
    double low = std::numeric_limits<double>::infinity();
    for (const auto& v : shapes[g].vertices_approx()) low = std::min(low, v.z());
    lows.push_back(low);
    lowest = std::min(lowest, low);
  }
  Specimen s{def, {}, local.front(), local};
  for (std::size_t g = 0; g < shapes.size(); ++g) {
    Grain grain;
    grain.id = static_cast<int>(g);
    grain.site.centre = centres[g];
    grain.site.k = lows[g] == lowest ? 1 : 2;
    grain.orientation = draw_orientation(def.seed, g, def.family_mix, def.angles);
    grain.shape = static_cast<int>(g);
    s.grains.push_back(grain);
  }
  orient_grains(def, s.grains);
  return s;
}

}  // namespace

namespace {
Specimen build_grains(const SpecimenDef& def) {
  if (def.kind != SpecimenKind::lattice) {
    require(def.family_mix >= 0.0 && def.family_mix <= 1.0, "family_mix must be in [0, 1]");
    require(!def.angles.empty(), "angles must not be empty");
    for (int a : def.angles) require(a == 0 || a == 60 || a == 120, "angles must be 0, 60 or 120");
  }
  if (def.kind == SpecimenKind::voronoi && def.voronoi.lognormal) {
    const VoronoiDef& v = def.voronoi;
    LaguerreTessellation t = lognormal_laguerre(v);
    // A Laguerre cell need not hold its point: the frame's origin is the mean of its
    // (rounded) vertices, inside the convex cell and cheap beside its exact centroid.
    std::vector<Eigen::Vector3d> centres;
    for (const auto& cell : t.cells) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      const auto vertices = cell.vertices_approx();
      for (const auto& v : vertices) mean += v / static_cast<double>(vertices.size());
      centres.push_back(mean);
    }
    return place_grains(def, t.cells, centres);
  }
  if (def.kind == SpecimenKind::voronoi) {
    const std::vector<ExactPolyhedron> cells = voronoi_cells(def.voronoi);
    return place_grains(def, cells, voronoi_points(def.voronoi));
  }
  if (def.kind == SpecimenKind::meshes) {
    require(!def.custom_grains.empty(), "a mesh specimen needs at least one grain");
    require(def.orientations.empty() || def.orientations.size() == def.custom_grains.size(),
            "one orientation per grain, or none");
    std::vector<ExactPolyhedron> shapes;
    std::vector<Eigen::Vector3d> centres;
    for (const auto& c : def.custom_grains) {
      shapes.push_back(c.shape);
      centres.push_back(c.shape.mass_properties().centroid);
    }
    return place_grains(def, shapes, centres);
  }
  require(def.r > 0.0, "r must be positive");
  require(def.t > 0.0, "t must be positive");
  require(def.r_bar > 0.0 && def.r_bar <= def.r, "r_bar must be in (0, r]");
  require(def.t_bar > 0.0 && def.t_bar <= def.t, "t_bar must be in (0, t]");
  require(def.family_mix >= 0.0 && def.family_mix <= 1.0, "family_mix must be in [0, 1]");
  require(!def.angles.empty(), "angles must not be empty");
  for (int a : def.angles) require(a == 0 || a == 60 || a == 120, "angles must be 0, 60 or 120");
  for (int d = 0; d < 3; ++d) require(def.outline.size[d] > 0.0, "specimen sizes must be positive");

  Specimen s{def, {}, ExactPolyhedron::hexagonal_prism(def.r_bar, def.t_bar), {}};
  s.shapes.push_back(s.prism);
  const auto sites = honeycomb_sites(def.r, def.t, def.outline, def.keep);
  s.grains.reserve(sites.size());
  for (std::size_t g = 0; g < sites.size(); ++g) {
    Grain grain;
    grain.id = static_cast<int>(g);
    grain.site = sites[g];
    grain.orientation = draw_orientation(def.seed, g, def.family_mix, def.angles);
    s.grains.push_back(grain);
  }
  orient_grains(def, s.grains);
  return s;
}
}  // namespace

Specimen build_specimen(const SpecimenDef& def) {
  Specimen s = build_grains(def);
  if (!def.phase_fractions.empty()) {
    std::vector<double> volumes;
    volumes.reserve(s.grains.size());
    for (const Grain& g : s.grains) volumes.push_back(s.shape_of(g).volume_approx());
    const std::vector<int> phases = assign_phases(volumes, def.phase_fractions, def.seed);
    for (std::size_t i = 0; i < s.grains.size(); ++i) s.grains[i].phase = phases[i];
  }
  return s;
}

CleavagePlanes grain_cleavage_planes(const Specimen& specimen, const Grain& g) {
  if (specimen.def.crystal.enabled) {
    return crystal_cleavage_planes(specimen.shape_of(g), specimen.def.crystal, g.crystal);
  }
  CleavagePlanes out;
  out.planes = specimen.shape_of(g).cleavage_planes(g.orientation);
  out.family.assign(out.planes.size(), 0);
  return out;
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
  // Lattice grains share one prism, so each distinct (shape, orientation) is cut once.
  std::map<std::tuple<int, int, int>, std::vector<std::shared_ptr<const ExactPolyhedron>>> cache;
  std::vector<Piece> pieces;
  for (const Grain& g : specimen.grains) {
    if (specimen.def.crystal.enabled) {
      pieces.push_back(Piece{Lineage{g.id, {}},
                             std::make_shared<const ExactPolyhedron>(specimen.shape_of(g)),
                             g.site.centre, g.orientation});
      continue;
    }
    const auto key = std::make_tuple(g.shape, static_cast<int>(g.orientation.family),
                                     g.orientation.angle_deg);
    auto it = cache.find(key);
    if (it == cache.end()) {
      std::vector<std::shared_ptr<const ExactPolyhedron>> shapes;
      for (auto& slab : specimen.shape_of(g).cleavage_slabs(g.orientation, min_fragment_fraction)) {
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
