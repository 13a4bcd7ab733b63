/// \file
/// Scenario files: TOML read with toml++ and checked key by key. Every table and key, with its
/// unit, default and allowed values, is in scenarios/reference.toml (a test keeps it complete).

#include "io/scenario.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include "geometry/laguerre.hpp"
#include "io/budget.hpp"
#include "io/field_expression.hpp"
#include "io/material_library.hpp"
#include "io/mesh_grains.hpp"
#include "io/neper_tess.hpp"
#include "io/orientation_file.hpp"
#include "io/result_dir.hpp"
#include "io/toml_reader.hpp"

namespace cleave::io {

namespace {

using namespace toml_reader;
using geometry::KeepRule;
using geometry::Outline;

// ---- [scenario] ---------------------------------------------------------------------------

constexpr std::string_view kScenarioKeys[] = {"name", "description", "length_unit"};

/// A length unit of the file and its size in metres.
struct Unit {
  std::string_view name;
  double metres;
};
constexpr Unit kUnits[] = {{"m", 1.0}, {"mm", 1e-3}, {"um", 1e-6}};
constexpr const Unit* kDefaultUnit = &kUnits[1];

}  // namespace

double length_unit_metres(std::string_view name) {
  for (const Unit& u : kUnits) {
    if (u.name == name) return u.metres;
  }
  throw std::invalid_argument("length_unit_metres: no length unit '" + std::string(name) + "'");
}

std::string_view default_length_unit() {
  return kDefaultUnit->name;
}

namespace {

void read_scenario_table(const TableReader& t, Scenario& s, double& unit) {
  t.reject_unknown(kScenarioKeys);
  std::string default_name = std::filesystem::path(s.source).stem().string();
  if (default_name.empty()) default_name = s.source;
  s.name = t.string("name", default_name);
  if (s.name.empty()) t.fail(*t.find("name"), "name", "must not be empty");
  // The name is a folder in results/: one plain component, so that it cannot lead out.
  if (t.find("name") != nullptr && !is_plain_folder_name(s.name)) {
    t.fail(*t.find("name"), "name",
           fmt::format("'{}' must be a plain folder name (no '/', '\\' or leading '.'): the run writes "
                       "results/NAME",
                       s.name));
  }
  s.description = t.string("description", "");
  std::vector<Choice<const Unit*>> units;
  for (const Unit& u : kUnits) units.push_back({std::string(u.name), &u});
  const Unit& chosen = *t.choose("length_unit", units, std::optional(kDefaultUnit));
  s.length_unit = chosen.name;
  unit = chosen.metres;
}

// ---- [specimen] ---------------------------------------------------------------------------

constexpr std::string_view kSpecimenKeys[] = {
    "shape",       "size",        "diameter",    "thickness", "length", "height",
    "notch_width", "notch_depth", "keep",        "grains",    "gap",    "seed",
    "sizes",       "size_mean",   "size_spread", "file",      "scale",  "domain",
    "sides"};
constexpr std::string_view kCommonSpecimenKeys[] = {"shape", "keep"};
constexpr std::string_view kBoxKeys[] = {"size"};
constexpr std::string_view kDiscKeys[] = {"diameter", "thickness"};
constexpr std::string_view kBeamKeys[] = {"length", "height", "thickness", "notch_width",
                                          "notch_depth"};

/// A specimen shape: its name, the keys only it takes, and how it reads its outline from them.
struct ShapeSpec {
  std::string_view name;
  std::span<const std::string_view> keys;
  Outline (*read)(const TableReader& t);  // in SI: the reader converts
};

Outline read_box(const TableReader& t) {
  const std::vector<double> size = t.numbers("size", 3, Range::positive());
  return Outline::box(size[0], size[1], size[2]);
}

Outline read_disc(const TableReader& t) {
  const Number diameter = t.number("diameter", Range::positive());
  const Number thickness = t.number("thickness", Range::positive());
  return Outline::disc(diameter.value, thickness.value);
}

Outline read_beam(const TableReader& t) {
  const Number length = t.number("length", Range::positive());
  const Number height = t.number("height", Range::positive());
  const Number thickness = t.number("thickness", Range::positive());
  const Number width = t.number("notch_width", Range::non_negative(), 0.0);
  const Number depth = t.number("notch_depth", Range::non_negative(), 0.0);
  if (width.node != nullptr && width.value >= length.value) {
    t.fail(*width.node, "notch_width",
           fmt::format("must be < specimen.length = {}, found {}", t.written(*length.node),
                       t.written(*width.node)));
  }
  if (depth.node != nullptr && depth.value >= height.value) {
    t.fail(*depth.node, "notch_depth",
           fmt::format("must be < specimen.height = {}, found {}", t.written(*height.node),
                       t.written(*depth.node)));
  }
  // A notch needs both a width and a depth: blame the one that is zero (or absent).
  const std::pair<const Number*, std::string_view> sides[] = {{&width, "notch_width"},
                                                              {&depth, "notch_depth"}};
  for (int i = 0; i < 2; ++i) {
    const auto& [self, key] = sides[i];
    const auto& [other, other_key] = sides[1 - i];
    if (self->value > 0.0 || other->value == 0.0) continue;
    const std::string message = fmt::format(
        "must be > 0 when specimen.{} > 0 (a notch needs both a width and a depth)", other_key);
    if (self->node != nullptr) t.fail(*self->node, key, message);
    t.fail_absent(key, message);
  }
  return Outline::beam(length.value, height.value, thickness.value, width.value, depth.value);
}

// Specimens that make their own grains (no honeycomb lattice, no [grain] table).
constexpr std::string_view kVoronoiKeys[] = {"size",     "grains",    "gap",         "seed",
                                             "sizes",    "size_mean", "size_spread", "domain",
                                             "diameter", "thickness", "sides"};
constexpr std::string_view kVoronoiDiscKeys[] = {"diameter", "thickness", "sides"};
// Imported microstructures: a Neper .tess (its own domain) or a grain file in a box.
constexpr std::string_view kTessKeys[] = {"file", "scale"};
constexpr std::string_view kGrainFileKeys[] = {"size", "file", "scale"};
constexpr int kMaxVoronoiCells = 10000;

Outline read_no_outline(const TableReader&) {
  return Outline::box(1.0, 1.0, 1.0);
}

/// shape = "voronoi": the box `size`, or with domain = "disc" a disc along z (`diameter`,
/// `thickness`, `sides`); the other domain's keys are errors.
Outline read_voronoi_outline(const TableReader& t) {
  const bool disc = t.choose("domain", std::vector<Choice<bool>>{{"box", false}, {"disc", true}},
                             std::optional(false));
  for (std::string_view key : disc ? std::span<const std::string_view>(kBoxKeys)
                                   : std::span<const std::string_view>(kVoronoiDiscKeys)) {
    if (const toml::node* n = t.find(key)) {
      t.fail(*n, key,
             disc ? "applies to domain = \"box\"; a Voronoi disc takes diameter, thickness, sides"
                  : "applies to domain = \"disc\"; a Voronoi box takes size");
    }
  }
  return disc ? read_disc(t) : read_box(t);
}

constexpr ShapeSpec kShapes[] = {
    {"box", kBoxKeys, &read_box},
    {"disc", kDiscKeys, &read_disc},
    {"beam", kBeamKeys, &read_beam},
    {"voronoi", kVoronoiKeys, &read_voronoi_outline},
    {"mesh", {}, &read_no_outline},
    {"tess", kTessKeys, &read_no_outline},
    {"grain_file", kGrainFileKeys, &read_box},
};

/// shape = "voronoi": the cells' count, gap and point seed; the points are checked against
/// the gap here so a bad gap is reported at its key.
void read_voronoi(const TableReader& t, double unit, geometry::SpecimenDef& def) {
  def.kind = geometry::SpecimenKind::voronoi;
  def.voronoi.size = def.outline.size;
  if (def.outline.kind == Outline::Kind::disc) {
    def.voronoi.domain = geometry::VoronoiDomain::disc;
    def.voronoi.sides = static_cast<int>(t.integer("sides", 8, 64, 4096));
    if (def.voronoi.sides % 4 != 0) {
      t.fail(*t.find("sides"), "sides",
             fmt::format("must be a multiple of 4 (a flat side under each platen), found {}",
                         def.voronoi.sides));
    }
  }
  const std::vector<Choice<bool>> sizes = {{"voronoi", false}, {"lognormal", true}};
  def.voronoi.lognormal = t.choose("sizes", sizes, std::optional(false));
  const toml::node* mean_node = t.find("size_mean");
  if (!def.voronoi.lognormal) {
    for (std::string_view key : {"size_mean", "size_spread"}) {
      if (const toml::node* n = t.find(key))
        t.fail(*n, key, "applies to sizes = \"lognormal\" (Laguerre cells with log-normal sizes)");
    }
  } else {
    def.voronoi.size_spread = t.number("size_spread", Range::non_negative(), 0.35).value;
    if (mean_node != nullptr && t.find("grains") != nullptr) {
      t.fail(*mean_node, "size_mean",
             "give grains or size_mean, not both: size_mean sets the number of grains");
    }
  }
  std::int64_t cells = 0;
  if (def.voronoi.lognormal && mean_node != nullptr) {
    const Number mean = t.number("size_mean", Range::positive());
    try {
      cells = geometry::lognormal_grain_count(
          geometry::voronoi_domain(def.voronoi).volume().to_double(), mean.value,
          def.voronoi.size_spread);
    } catch (const std::invalid_argument& e) {
      t.fail(*mean_node, "size_mean", e.what());
    }
    if (cells > kMaxVoronoiCells) {
      t.fail(*mean_node, "size_mean",
             fmt::format("makes {} grains in the {}; at most {}", cells,
                         def.voronoi.domain == geometry::VoronoiDomain::disc ? "disc" : "box",
                         kMaxVoronoiCells));
    }
  } else {
    if (t.find("grains") == nullptr) {
      t.fail_absent("grains", def.voronoi.lognormal
                                  ? "missing required key: the number of cells (or size_mean)"
                                  : "missing required key: the number of Voronoi cells");
    }
    cells = t.integer("grains", 1, 1);
  }
  if (cells > kMaxVoronoiCells && t.find("grains") != nullptr) {
    t.fail(*t.find("grains"), "grains", fmt::format("must be <= {}, found {}", kMaxVoronoiCells, cells));
  }
  def.voronoi.cells = static_cast<int>(cells);
  const Number gap = t.number("gap", Range::non_negative(), 0.0);
  def.voronoi.gap = gap.value;
  def.voronoi.seed = static_cast<std::uint64_t>(t.integer("seed", 0, 1));
  const auto points = geometry::voronoi_points(def.voronoi);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const double d = (points[i] - points[j]).norm();
      if (d > def.voronoi.gap) continue;
      const std::string message = fmt::format(
          "points {} and {} of seed {} are {:.4g} apart, not more than the gap {}: their "
          "cells would vanish; use a smaller gap, fewer grains or another seed",
          j, i, def.voronoi.seed, d / unit, gap.node != nullptr ? t.written(*gap.node) : "0");
      if (gap.node != nullptr) t.fail(*gap.node, "gap", message);
      t.fail(*t.find("seed"), "seed", message);
    }
  }
}

void read_specimen_table(const TableReader& t, double unit, geometry::SpecimenDef& def) {
  t.reject_unknown(kSpecimenKeys);
  std::vector<Choice<const ShapeSpec*>> shapes;
  for (const ShapeSpec& spec : kShapes) shapes.push_back({std::string(spec.name), &spec});
  const ShapeSpec& shape = *t.choose("shape", shapes);

  const Entry foreign = first_in_file(*t.table(), [&](std::string_view key, const toml::node&) {
    return !contains(kCommonSpecimenKeys, key) && !contains(shape.keys, key);
  });
  if (foreign.key != nullptr) {
    const std::string key(foreign.key->str());
    std::vector<std::string_view> owners;
    for (const ShapeSpec& spec : kShapes) {
      if (contains(spec.keys, key)) owners.push_back(spec.name);
    }
    std::vector<std::string_view> takes(std::begin(kCommonSpecimenKeys),
                                        std::end(kCommonSpecimenKeys));
    takes.insert(takes.end(), shape.keys.begin(), shape.keys.end());
    t.fail(foreign.where(), key,
           fmt::format("does not apply to shape '{}' (only to {}); a {} takes {}", shape.name,
                       quoted_list(owners), shape.name, quoted_list(takes)));
  }

  def.outline = shape.read(t);
  if (shape.name == "voronoi" || shape.name == "mesh" || shape.name == "tess" ||
      shape.name == "grain_file") {
    if (const toml::node* keep = t.find("keep")) {
      t.fail(*keep, "keep", fmt::format("applies to the lattice shapes 'box', 'disc', 'beam'; "
                                        "shape '{}' makes its own grains", shape.name));
    }
    if (shape.name == "voronoi") read_voronoi(t, unit, def);
    if (shape.name != "voronoi") def.kind = geometry::SpecimenKind::meshes;
    return;
  }
  const std::vector<Choice<KeepRule>> rules = {{"cell_inside", KeepRule::cell_inside},
                                               {"centre_inside", KeepRule::centre_inside}};
  def.keep = t.choose("keep", rules, std::optional(KeepRule::cell_inside));
}

// ---- [grain] ------------------------------------------------------------------------------

constexpr std::string_view kGrainKeys[] = {"r", "r_bar", "t", "t_bar"};

/// A lattice length and the grain length within it (`bar`, default: the lattice length).
std::pair<double, double> read_pitch(const TableReader& t, std::string_view key,
                                     std::string_view bar_key) {
  const Number full = t.number(key, Range::positive());
  const Number bar = t.number(bar_key, Range::positive(), full.value);
  if (bar.value > full.value) {
    t.fail(*bar.node, bar_key,
           fmt::format("must not exceed grain.{} = {}, found {}", key, t.written(*full.node),
                       t.written(*bar.node)));
  }
  return {full.value, bar.value};
}

void read_grain_table(const TableReader& t, geometry::SpecimenDef& def) {
  t.reject_unknown(kGrainKeys);
  std::tie(def.r, def.r_bar) = read_pitch(t, "r", "r_bar");
  std::tie(def.t, def.t_bar) = read_pitch(t, "t", "t_bar");
}

// ---- [[mesh_grain]] and the grains of specimens off the lattice ----------------------------

constexpr std::string_view kMeshGrainKeys[] = {"file", "scale", "position", "convex_hull"};

/// The specimen shape named in the file, if it is a string.
std::string specimen_shape(const toml::table& root) {
  const auto* shape = root["specimen"]["shape"].as_string();
  return shape != nullptr ? shape->get() : std::string();
}

/// Mesh grains placed into each other: their shapes themselves intersect, which no contact
/// resolves (a first bond stage would even store the overlap as the rest state), so the later
/// grain's [[mesh_grain]] position (or file) is refused, naming both grains and the depth.
void check_mesh_grains_apart(const toml::table& root, const std::string& source,
                             const UnitContext* units,
                             const std::vector<geometry::CustomGrainDef>& grains,
                             const std::vector<std::size_t>& owners) {
  std::vector<geometry::PolygonMesh> meshes;
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& g : grains) {
    meshes.push_back(g.shape.to_mesh(g.name));
    boxes.emplace_back();
    for (const auto& v : meshes.back().vertices) boxes.back().extend(v);
  }
  const std::string unit =
      root["scenario"]["length_unit"].value_or(std::string(kDefaultUnit->name));
  for (std::size_t j = 1; j < meshes.size(); ++j) {
    for (std::size_t i = 0; i < j; ++i) {
      if (!boxes[i].intersects(boxes[j])) continue;
      // Faces that touch overlap by rounding only.
      const double tolerance =
          1e-9 * std::max(boxes[i].diagonal().norm(), boxes[j].diagonal().norm());
      const double depth = convex_overlap(meshes[i], meshes[j]);
      if (!(depth > tolerance)) continue;
      const auto* tables = root.get_as<toml::array>("mesh_grain");
      const std::size_t k = owners[j];
      const TableReader t(source, fmt::format("mesh_grain[{}]", k + 1), tables->get(k)->as_table(),
                          units);
      const std::string where = fmt::format("mesh_grain[{}]", owners[i] + 1);
      const std::string message = fmt::format(
          "grain {} ({}) and grain {} ({}, {}) intersect: their shapes reach {:.4g} {} into each "
          "other (the least distance that would part them), which no contact resolves; place the "
          "grains apart (position, scale)",
          j, grains[j].name, i, grains[i].name, where, depth / units->length_unit, unit);
      if (const toml::node* position = t.find("position")) t.fail(*position, "position", message);
      t.fail(*t.find("file"), "file", message);
    }
  }
}

/// For shape "voronoi" or "mesh": no [grain] table; for "mesh" every [[mesh_grain]] read,
/// its file loaded and checked, and the outline set to the grains' bounding box.
void read_own_grains(const toml::table& root, const std::string& source, const UnitContext* units,
                     geometry::SpecimenDef& def, std::vector<MeshGrainSpec>& specs) {
  const std::string shape = def.kind == geometry::SpecimenKind::voronoi ? "voronoi" : "mesh";
  if (const auto* grain = root.get_as<toml::table>("grain")) {
    TableReader(source, "grain", grain)
        .fail_table(fmt::format("[grain] sets the honeycomb lattice's cells; specimen shape '{}' "
                                "makes its own grains: remove [grain]",
                                shape));
  }
  const auto* tables = root.get_as<toml::array>("mesh_grain");
  if (def.kind != geometry::SpecimenKind::meshes) return;
  if (tables == nullptr || tables->empty()) {
    const TableReader t(source, "specimen", root.get_as<toml::table>("specimen"));
    t.fail(*t.find("shape"), "shape", "shape \"mesh\" takes its grains from [[mesh_grain]] tables; give at least one");
  }
  const std::filesystem::path folder = std::filesystem::path(source).parent_path();
  std::vector<std::size_t> owners;  // per grain: its [[mesh_grain]] table
  for (std::size_t i = 0; i < tables->size(); ++i) {
    const TableReader t(source, fmt::format("mesh_grain[{}]", i + 1), tables->get(i)->as_table(),
                        units);
    t.reject_unknown(kMeshGrainKeys);
    MeshGrainSpec spec;
    const std::string file = t.string("file");
    if (file.empty()) t.fail(*t.find("file"), "file", "must not be empty");
    spec.file = std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : folder / file;
    spec.scale = t.number("scale", Range::positive(), units->length_unit).value;  // 1 length unit
    if (t.find("position") != nullptr) {
      const auto at = t.numbers("position", 3, Range{});
      spec.offset = Eigen::Vector3d(at[0], at[1], at[2]);
    }
    spec.convex_hull = t.boolean("convex_hull", false);
    try {
      for (auto& g : load_mesh_grains(spec)) def.custom_grains.push_back(std::move(g));
    } catch (const MeshGrainError& e) {
      t.fail(*t.find("file"), "file", e.what());
    }
    spec.file = std::filesystem::absolute(spec.file);
    specs.push_back(spec);
    owners.resize(def.custom_grains.size(), i);
  }
  check_mesh_grains_apart(root, source, units, def.custom_grains, owners);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  for (const auto& g : def.custom_grains) {
    for (const auto& v : g.shape.vertices_approx()) hi = hi.cwiseMax(v);
  }
  def.outline = Outline::box(std::max(hi.x(), 1e-9), std::max(hi.y(), 1e-9), std::max(hi.z(), 1e-9));
}

/// shape = "tess" or "grain_file": the grains of a Neper .tess or of a grain file (its path
/// relative to the scenario's folder, lengths times `scale`), exact and tiling their domain;
/// their orientations go to specimen.orientations.
void read_imported_grains(const toml::table& root, const std::string& source,
                          const UnitContext* units, Scenario& s) {
  const std::string shape = specimen_shape(root);
  if (const auto* grain = root.get_as<toml::table>("grain")) {
    TableReader(source, "grain", grain)
        .fail_table(fmt::format("[grain] sets the honeycomb lattice's cells; specimen shape '{}' "
                                "takes its grains from its file: remove [grain]",
                                shape));
  }
  if (const auto* meshes = root.get_as<toml::array>("mesh_grain")) {
    const toml::node& first = *meshes->get(0);
    throw ScenarioError(source, line_of(first.source()), column_of(first.source()), "mesh_grain",
                        "[[mesh_grain]] tables need [specimen] shape = \"mesh\"");
  }
  const TableReader t(source, "specimen", root.get_as<toml::table>("specimen"), units);
  const std::string file = t.string("file");
  if (file.empty()) t.fail(*t.find("file"), "file", "must not be empty");
  const std::filesystem::path folder = std::filesystem::path(source).parent_path();
  TessellationFileSpec spec;
  spec.shape = shape;
  spec.file =
      std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : folder / file;
  spec.scale = t.number("scale", Range::positive(), units->length_unit).value;  // 1 length unit
  ImportedTessellation imported;
  try {
    imported = shape == "tess" ? read_neper_tess(spec.file, spec.scale)
                               : read_grain_file(spec.file, spec.scale, s.specimen.outline.size);
  } catch (const TessellationFileError& e) {
    t.fail(*t.find("file"), "file", e.what());
  } catch (const std::invalid_argument& e) {
    t.fail(*t.find("file"), "file", fmt::format("{}: {}", spec.file.string(), e.what()));
  }
  const std::string name = spec.file.filename().string();
  for (std::size_t i = 0; i < imported.cells.size(); ++i) {
    s.specimen.custom_grains.push_back(
        {fmt::format("{}#{}", name, imported.ids[i]), imported.cells[i]});
  }
  s.specimen.orientations = imported.orientations;
  if (shape == "tess") {  // the domain's extent, as for mesh grains
    Eigen::Vector3d hi = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
    for (const auto& g : s.specimen.custom_grains) {
      for (const auto& v : g.shape.vertices_approx()) hi = hi.cwiseMax(v);
    }
    s.specimen.outline =
        Outline::box(std::max(hi.x(), 1e-9), std::max(hi.y(), 1e-9), std::max(hi.z(), 1e-9));
  }
  spec.file = std::filesystem::absolute(spec.file);
  s.tessellation = spec;
}

// ---- [orientation] ------------------------------------------------------------------------

constexpr std::string_view kOrientationKeys[] = {"seed",   "family_mix",        "angles",        "law",
                                                 "euler", "spread",            "crystal_direction",
                                                 "specimen_axis", "file"};
constexpr int kAngles[] = {0, 60, 120};

std::vector<int> read_angles(const TableReader& t) {
  const toml::node* node = t.find("angles");
  if (node == nullptr) return {std::begin(kAngles), std::end(kAngles)};
  const auto* array = node->as_array();
  if (array == nullptr) {
    t.fail(*node, "angles",
           fmt::format("expected an array of angles (0, 60, 120), found {}", type_name(*node)));
  }
  if (array->empty()) t.fail(*node, "angles", "must not be empty; give some of 0, 60, 120");
  std::vector<int> angles;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    const auto* value = element.as_integer();
    if (value == nullptr) {
      t.fail(element, "angles",
             fmt::format("element {}: expected an integer angle, found {}", i + 1,
                         type_name(element)));
    }
    const std::int64_t angle = value->get();
    if (angle != 0 && angle != 60 && angle != 120) {
      t.fail(element, "angles",
             fmt::format("element {}: angle {} is not one of 0, 60, 120", i + 1, angle));
    }
    for (int seen : angles) {
      if (seen == angle) {
        t.fail(element, "angles", fmt::format("element {}: angle {} is repeated", i + 1, angle));
      }
    }
    angles.push_back(static_cast<int>(angle));
  }
  return angles;
}

Eigen::Vector3d direction(const TableReader& t, std::string_view key, const Eigen::Vector3d& fallback) {
  if (t.find(key) == nullptr) return fallback;
  const auto v = t.numbers(key, 3, Range{});
  const Eigen::Vector3d d(v[0], v[1], v[2]);
  if (!(d.norm() > 0.0)) t.fail(*t.find(key), key, "must not be the zero vector");
  return d;
}

/// [orientation]: the seed's honeycomb draw (family_mix, angles), or with [crystal] a law
/// of 3D orientations. Angles in the file are degrees.
void read_orientation_table(const TableReader& t, geometry::SpecimenDef& def) {
  using geometry::OrientationLaw;
  t.reject_unknown(kOrientationKeys);
  def.seed = static_cast<std::uint64_t>(t.integer("seed", 0, 1));
  def.family_mix = t.number("family_mix", {.lo = 0.0, .hi = 1.0}, 0.5).value;
  def.angles = read_angles(t);
  geometry::OrientationDef& o = def.orientation;
  o.law = t.choose<OrientationLaw>("law",
                                   {{"honeycomb", OrientationLaw::honeycomb},
                                    {"uniform", OrientationLaw::uniform},
                                    {"fibre", OrientationLaw::fibre},
                                    {"preferred", OrientationLaw::preferred},
                                    {"file", OrientationLaw::given},
                                    {"imported", OrientationLaw::imported}},
                                   !def.crystal.enabled         ? OrientationLaw::honeycomb
                                   : def.orientations.empty() ? OrientationLaw::uniform
                                                              : OrientationLaw::imported);
  if (o.law == OrientationLaw::imported && def.orientations.empty()) {
    t.fail(*t.find("law"), "law",
           "\"imported\" takes the orientations of the specimen's file (shape = \"tess\" with *ori, or "
           "\"grain_file\"); this specimen has none");
  }
  if (o.law != OrientationLaw::honeycomb && !def.crystal.enabled) {
    t.fail(*t.find("law"), "law", "3D orientations need a [crystal] table (the grains' crystal system and cleavage planes)");
  }
  auto only = [&](std::string_view key, bool allowed, std::string_view which) {
    if (!allowed && t.find(key) != nullptr) t.fail(*t.find(key), key, fmt::format("belongs to {}", which));
  };
  const bool honeycomb = o.law == OrientationLaw::honeycomb;
  only("family_mix", honeycomb, "law = \"honeycomb\" (the seed's 2.5D crystal)");
  only("angles", honeycomb, "law = \"honeycomb\" (the seed's 2.5D crystal)");
  only("euler", o.law == OrientationLaw::preferred, "law = \"preferred\"");
  only("spread", o.law == OrientationLaw::preferred || o.law == OrientationLaw::fibre,
       "law = \"fibre\" or \"preferred\"");
  only("crystal_direction", o.law == OrientationLaw::fibre, "law = \"fibre\"");
  only("specimen_axis", o.law == OrientationLaw::fibre, "law = \"fibre\"");
  only("file", o.law == OrientationLaw::given, "law = \"file\"");
  if (o.law == OrientationLaw::preferred) {
    const auto e = t.numbers("euler", 3, Range{});
    if (!(e[1] >= 0.0 && e[1] <= 180.0)) t.fail(*t.find("euler"), "euler", "Phi (the second angle) must be in [0, 180] degrees");
    o.euler_deg = {e[0], e[1], e[2]};
  }
  if (o.law == OrientationLaw::preferred || o.law == OrientationLaw::fibre) {
    o.spread_deg = t.number("spread", {.lo = 0.0, .hi = 180.0}, 0.0).value;
  }
  if (o.law == OrientationLaw::fibre) {
    o.crystal_direction = direction(t, "crystal_direction", Eigen::Vector3d::UnitZ());
    o.specimen_axis = direction(t, "specimen_axis", Eigen::Vector3d::UnitZ());
  }
  if (o.law == OrientationLaw::given) {
    const std::string file = t.string("file");
    const std::filesystem::path path = std::filesystem::path(t.source()).parent_path() / file;
    o.file = std::filesystem::absolute(path).string();
    try {
      o.given = read_orientation_file(path);
    } catch (const ScenarioError&) {
      throw;  // names the orientation file's own line
    } catch (const std::exception& e) {
      t.fail(*t.find("file"), "file", e.what());
    }
  }
}

// ---- [crystal], [[cleavage]] --------------------------------------------------------------

constexpr std::string_view kCrystalKeys[] = {"system", "c_over_a", "b_over_a", "preset"};
constexpr std::string_view kCleavageKeys[] = {"planes", "resistance", "k_ic", "sigma_f",
                                              "planes_per_variant"};

/// A [crystal] preset's cleavage families with their toughness (Pa sqrt(m)), for
/// read_cleavage_tables to turn into resistances once [fracture] is known.
struct PresetFamilies {
  std::vector<geometry::CleavageFamilyDef> families;
  std::vector<double> k_ic;
};

PresetFamilies read_crystal_table(const TableReader& t, geometry::CrystalDef& c) {
  t.reject_unknown(kCrystalKeys);
  PresetFamilies from_preset;
  if (t.table() == nullptr) return from_preset;
  c.enabled = true;
  std::optional<MaterialPreset> preset;
  if (t.find("preset") != nullptr) {
    const std::string name = t.string("preset");
    const auto file = resolve_material(name, std::filesystem::path(t.source()).parent_path());
    if (!file) t.fail(*t.find("preset"), "preset", fmt::format("no material '{}' (cleave materials lists them)", name));
    preset = load_material(*file);
    if (!preset->crystal) {
      t.fail(*t.find("preset"), "preset",
             fmt::format("{} has no [crystal] table (its single crystal's system and cleavage)", file->string()));
    }
  }
  const std::string system = preset && t.find("system") == nullptr ? preset->crystal->system : t.string("system");
  try {
    c.lattice.system = geometry::parse_crystal_system(system);
  } catch (const std::invalid_argument& e) {
    t.fail(*t.find("system"), "system", e.what());
  }
  using geometry::CrystalSystem;
  const bool has_c = c.lattice.system != CrystalSystem::cubic;
  const bool has_b = c.lattice.system == CrystalSystem::orthorhombic;
  if (!has_c && t.find("c_over_a") != nullptr) t.fail(*t.find("c_over_a"), "c_over_a", "a cubic crystal has c = a");
  if (!has_b && t.find("b_over_a") != nullptr)
    t.fail(*t.find("b_over_a"), "b_over_a", "only an orthorhombic crystal has b != a");
  auto ratio = [&](std::string_view key, const std::optional<MaterialProperty>& given) {
    return t.number(key, Range::positive(), preset && given ? std::optional(given->value) : std::nullopt).value;
  };
  if (has_c) c.lattice.c_over_a = ratio("c_over_a", preset ? preset->crystal->c_over_a : std::nullopt);
  if (has_b) c.lattice.b_over_a = ratio("b_over_a", preset ? preset->crystal->b_over_a : std::nullopt);
  if (preset) {
    for (const MaterialProperty& p : preset->crystal->cleavage) {
      geometry::CleavageFamilyDef f;
      try {
        f.family = geometry::parse_miller_family(p.key, c.lattice.system);
      } catch (const std::invalid_argument& e) {
        t.fail(*t.find("preset"), "preset", fmt::format("{}:{}: {}", preset->file, p.line, e.what()));
      }
      from_preset.families.push_back(f);
      from_preset.k_ic.push_back(p.value);
    }
  }
  return from_preset;
}

/// [[cleavage]]: the families every grain's crystal cleaves on, each with its resistance
/// (its K_Ic or strength over [fracture]'s).
void read_cleavage_tables(const toml::table& root, const std::string& source, UnitContext* units,
                          const FractureDef& fracture, const PresetFamilies& preset, geometry::CrystalDef& c) {
  const auto* tables = root.get_as<toml::array>("cleavage");
  if (tables == nullptr) {
    // The preset's families: lefm takes each one's K_Ic over [fracture]'s; a stress
    // criterion the same ratios to the weakest (strength ~ K_Ic / sqrt(pi a), one flaw size).
    const bool lefm = fracture.params.criterion == physics::GrainCriterion::lefm;
    double weakest = std::numeric_limits<double>::infinity();
    for (const double k : preset.k_ic) weakest = std::min(weakest, k);
    for (std::size_t i = 0; i < preset.families.size(); ++i) {
      geometry::CleavageFamilyDef f = preset.families[i];
      if (fracture.enabled) f.resistance = preset.k_ic[i] / (lefm ? fracture.params.k_ic : weakest);
      c.families.push_back(f);
    }
    return;
  }
  if (!c.enabled) {
    const toml::node& first = *tables->get(0);
    throw ScenarioError(source, line_of(first.source()), column_of(first.source()), "cleavage",
                        "[[cleavage]] tables need a [crystal] table (the crystal system they index)");
  }
  for (std::size_t i = 0; i < tables->size(); ++i) {
    const TableReader t(source, fmt::format("cleavage[{}]", i + 1), tables->get(i)->as_table(), units);
    t.reject_unknown(kCleavageKeys);
    geometry::CleavageFamilyDef f;
    try {
      f.family = geometry::parse_miller_family(t.string("planes"), c.lattice.system);
    } catch (const std::invalid_argument& e) {
      t.fail(*t.find("planes"), "planes", e.what());
    }
    for (std::size_t j = 0; j < c.families.size(); ++j) {
      if (c.families[j].family.text == f.family.text)
        t.fail(*t.find("planes"), "planes", fmt::format("cleavage[{}] names the same family", j + 1));
    }
    f.planes_per_variant = t.int_integer("planes_per_variant", 1, 1);
    const bool lefm = fracture.params.criterion == physics::GrainCriterion::lefm;
    int given = 0;
    for (std::string_view key : {"resistance", "k_ic", "sigma_f"}) given += t.find(key) != nullptr;
    if (given > 1) {
      t.fail_table("give one of resistance, k_ic (criterion lefm) and sigma_f (a stress criterion)");
    }
    if (given == 1 && !fracture.enabled) {
      t.fail_table("a family's resistance needs a [fracture] table (the criterion it scales)");
    }
    if (t.find("k_ic") != nullptr) {
      if (!lefm) t.fail(*t.find("k_ic"), "k_ic", "belongs to criterion = \"lefm\"; a stress criterion takes sigma_f");
      f.resistance = t.number("k_ic", Range::positive()).value / fracture.params.k_ic;
    } else if (t.find("sigma_f") != nullptr) {
      if (lefm) t.fail(*t.find("sigma_f"), "sigma_f", "belongs to a stress criterion; criterion = \"lefm\" takes k_ic");
      f.resistance = t.number("sigma_f", Range::positive()).value / fracture.params.sigma_f;
    } else {
      f.resistance = t.number("resistance", Range::positive(), 1.0).value;
    }
    c.families.push_back(f);
  }
}

// ---- [split], [output] --------------------------------------------------------------------

constexpr std::string_view kSplitKeys[] = {"min_fragment_fraction", "min_fragment_diameter"};

void read_split_table(const TableReader& t, SplitDef& split) {
  t.reject_unknown(kSplitKeys);
  split.min_fragment_fraction =
      t.number("min_fragment_fraction", {.lo = 0.0, .hi = 0.5, .hi_open = true},
               SplitDef{}.min_fragment_fraction)
          .value;
  split.min_fragment_diameter = t.number("min_fragment_diameter", Range::non_negative(), 0.0).value;
}

constexpr std::string_view kOutputKeys[] = {"mesh_format", "mesh_layout", "frame_meshes",
                                            "checkpoint_every"};

void read_output_table(const TableReader& t, OutputDef& output) {
  t.reject_unknown(kOutputKeys);
  std::vector<Choice<MeshFormat>> formats;
  for (MeshFormat f : {MeshFormat::stl_binary, MeshFormat::stl_ascii, MeshFormat::obj}) {
    formats.push_back({to_string(f), f});
  }
  std::vector<Choice<MeshLayout>> layouts;
  for (MeshLayout l : {MeshLayout::scene, MeshLayout::per_fragment}) {
    layouts.push_back({to_string(l), l});
  }
  output.mesh_format = t.choose("mesh_format", formats, std::optional(OutputDef{}.mesh_format));
  output.mesh_layout = t.choose("mesh_layout", layouts, std::optional(OutputDef{}.mesh_layout));
  output.frame_meshes = t.boolean("frame_meshes", false);
  output.checkpoint_every = static_cast<std::uint64_t>(t.integer("checkpoint_every", 0, 0));
}

// ---- [material], [contact], [dynamics], [[wall]] ------------------------------------------

constexpr std::string_view kMaterialKeys[] = {"density", "preset"};

/// [material]: the density, or a preset of the material library whose density it takes
/// (an explicit `density` beside the preset wins: a sweep can vary it).
void read_material_table(const TableReader& t, MaterialDef& m) {
  t.reject_unknown(kMaterialKeys);
  std::optional<double> density;
  if (t.find("preset") != nullptr) {
    m.preset = t.string("preset");
    const auto file =
        resolve_material(m.preset, std::filesystem::path(t.source()).parent_path());
    if (!file) {
      std::vector<std::string> names;
      for (const auto& f : library_files()) names.push_back(f.stem().string());
      t.fail(*t.find("preset"), "preset",
             fmt::format("no material '{}' (a name looks in {}, which holds {}; a path with "
                         "'/' is taken from the scenario's folder)",
                         m.preset, materials_dir().string(),
                         names.empty() ? std::string("nothing") : quoted_list(names)));
    }
    const MaterialPreset preset = load_material(*file);
    m.preset_file = file->string();
    density = preset.si("density");
  }
  m.density = t.number("density", Range::positive(), density.value_or(MaterialDef{}.density)).value;
}

// ---- [[phase]], [[boundary]] --------------------------------------------------------------

constexpr std::string_view kPhaseKeys[] = {"name",  "fraction",  "preset",  "density",
                                           "alpha", "stiffness", "strength"};
constexpr std::string_view kBoundaryKeys[] = {"phases", "stiffness", "strength"};

/// [[phase]] and [[boundary]]: the phases, their fractions (into the specimen's definition)
/// and the boundaries' own factors.
void read_phase_tables(const toml::table& root, const std::string& source, UnitContext* units,
                       Scenario& s) {
  const auto* phases = root.get_as<toml::array>("phase");
  const auto* boundaries = root.get_as<toml::array>("boundary");
  if (phases == nullptr) {
    if (boundaries != nullptr) {
      const toml::node& first = *boundaries->get(0);
      throw ScenarioError(source, line_of(first.source()), column_of(first.source()), "boundary",
                          "[[boundary]] tables need [[phase]] tables (the phases they join)");
    }
    return;
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < phases->size(); ++i) {
    const TableReader t(source, fmt::format("phase[{}]", i + 1), phases->get(i)->as_table(), units);
    t.reject_unknown(kPhaseKeys);
    PhaseDef p;
    p.position = {line_of(t.table()->source()), column_of(t.table()->source())};
    p.name = t.string("name");
    if (p.name.empty()) t.fail(*t.find("name"), "name", "a phase needs a name");
    for (std::size_t j = 0; j < s.phases.size(); ++j) {
      if (s.phases[j].name == p.name)
        t.fail(*t.find("name"), "name", fmt::format("phase[{}] is named '{}' too", j + 1, p.name));
    }
    p.fraction = t.number("fraction", {.lo = 0.0, .hi = 1.0}).value;
    sum += p.fraction;
    std::optional<double> density;
    if (t.find("preset") != nullptr) {
      p.preset = t.string("preset");
      const auto file = resolve_material(p.preset, std::filesystem::path(t.source()).parent_path());
      if (!file) {
        t.fail(*t.find("preset"), "preset",
               fmt::format("no material '{}' (cleave materials lists them)", p.preset));
      }
      p.preset_file = file->string();
      density = load_material(*file).si("density");
    }
    p.density = t.number("density", Range::positive(), density.value_or(s.material.density)).value;
    if (const Number alpha = t.number("alpha", Range{}, 0.0); alpha.node != nullptr) {
      if (!s.thermal.enabled)
        t.fail(*alpha.node, "alpha", "a phase's expansion needs a [thermal] table");
      p.alpha = alpha.value;
    }
    p.stiffness = t.number("stiffness", Range::positive(), 1.0).value;
    p.strength = t.number("strength", Range::positive(), 1.0).value;
    s.phases.push_back(p);
    s.specimen.phase_fractions.push_back(p.fraction);
    if (i + 1 == phases->size() && std::abs(sum - 1.0) > 1e-9) {
      t.fail(*t.find("fraction"), "fraction",
             fmt::format("the phases' fractions sum to {:.12g}, not 1 (within 1e-9)", sum));
    }
  }
  if (boundaries == nullptr) return;
  for (std::size_t i = 0; i < boundaries->size(); ++i) {
    const TableReader t(source, fmt::format("boundary[{}]", i + 1), boundaries->get(i)->as_table(),
                        units);
    t.reject_unknown(kBoundaryKeys);
    BoundaryDef b;
    const toml::node* node = t.find("phases");
    if (node == nullptr)
      t.fail_absent("phases", "name the two phases it joins: phases = [\"a\", \"b\"]");
    const auto* names = node->as_array();
    if (names == nullptr || names->size() != 2) {
      t.fail(*node, "phases", "expected two phase names, e.g. phases = [\"glass\", \"alumina\"]");
    }
    for (std::size_t k = 0; k < 2; ++k) {
      const toml::node& e = *names->get(k);
      const auto* name = e.as_string();
      if (name == nullptr)
        t.fail(e, "phases",
               fmt::format("element {}: expected a phase name, found {}", k + 1, type_name(e)));
      const auto it = std::find_if(s.phases.begin(), s.phases.end(),
                                   [&](const PhaseDef& p) { return p.name == name->get(); });
      if (it == s.phases.end()) {
        std::vector<std::string> known;
        for (const PhaseDef& p : s.phases) known.push_back(p.name);
        t.fail(e, "phases",
               fmt::format("element {}: no [[phase]] is named '{}' (the phases: {})", k + 1,
                           name->get(), quoted_list(known)));
      }
      b.phases[k] = static_cast<int>(it - s.phases.begin());
    }
    if (b.phases[0] == b.phases[1]) {
      t.fail(*node, "phases",
             "names one phase twice: its own boundaries take its [[phase]] stiffness and strength");
    }
    if (b.phases[0] > b.phases[1]) std::swap(b.phases[0], b.phases[1]);
    for (std::size_t j = 0; j < s.boundaries.size(); ++j) {
      if (s.boundaries[j].phases == b.phases)
        t.fail(*node, "phases", fmt::format("boundary[{}] joins the same two phases", j + 1));
    }
    b.stiffness = t.number("stiffness", Range::positive()).value;
    b.strength = t.number("strength", Range::positive()).value;
    s.boundaries.push_back(b);
  }
}

constexpr std::string_view kContactKeys[] = {"dilation_radius", "particle_particle",
                                             "particle_wall"};
constexpr std::string_view kContactParamKeys[] = {"kn",   "ks",   "kr",   "kt",
                                                  "c_res", "mu_s", "mu_r", "damping"};

/// One parameter set of table 2.3 (stiffnesses in N/m and N m/rad).
physics::ContactParams read_contact_params(const TableReader& t) {
  t.reject_unknown(kContactParamKeys);
  physics::ContactParams p;
  p.kn = t.number("kn", Range::positive()).value;
  p.ks = t.number("ks", Range::non_negative(), 0.0).value;
  p.kr = t.number("kr", Range::non_negative(), 0.0).value;
  p.kt = t.number("kt", Range::non_negative(), 0.0).value;
  p.c_res = t.number("c_res", {.lo = 1.0}, 1.0).value;
  p.mu_s = t.number("mu_s", Range::non_negative(), 0.0).value;
  p.mu_r = t.number("mu_r", Range::non_negative(), 0.0).value;
  p.damping_ratio = t.number("damping", Range::non_negative(), 0.1).value;
  return p;
}

void read_contact_table(const TableReader& t, const std::string& source, ContactDef& c,
                        bool required) {
  t.reject_unknown(kContactKeys);
  if (t.table() == nullptr) {
    if (required) t.fail_absent("dilation_radius", "a [dynamics] run needs a [contact] table");
    return;
  }
  const Number dilation = t.number("dilation_radius", Range::positive());
  c.dilation_radius = dilation.value;
  c.dilation_position = {line_of(dilation.node->source()), column_of(dilation.node->source())};
  for (std::string_view set : {"particle_particle", "particle_wall"}) {
    const toml::node* node = t.find(set);
    if (node == nullptr) t.fail_absent(set, "missing required table");
    if (!node->is_table()) {
      t.fail(*node, set, fmt::format("expected a table, found {}", type_name(*node)));
    }
    const TableReader sub(source, "contact." + std::string(set), node->as_table(), t.units());
    (set == "particle_particle" ? c.particle_particle : c.particle_wall) = read_contact_params(sub);
  }
}

constexpr std::string_view kDynamicsKeys[] = {
    "dt",        "duration", "gravity", "lift",         "frames",       "settle_ratio",
    "dt_safety", "search",   "threads", "local_damping", "density_scale", "manifold_tolerance",
    "in_plane"};

void read_dynamics_table(const TableReader& t, DynamicsDef& d, bool staged) {
  t.reject_unknown(kDynamicsKeys);
  if (t.table() == nullptr) return;
  d.enabled = true;
  const Number dt = t.number("dt", Range::positive());
  d.dt = dt.value;
  d.dt_position = {line_of(dt.node->source()), column_of(dt.node->source())};
  if (staged) {
    if (const toml::node* node = t.find("duration")) {
      t.fail(*node, "duration",
             "a staged run takes its length from its [[stage]] tables (steps or time); "
             "remove duration");
    }
  } else {
    d.duration = t.number("duration", Range::positive()).value;
  }
  d.local_damping =
      t.number("local_damping", {.lo = 0.0, .hi = 1.0, .hi_open = true}, 0.0).value;
  d.density_scale = t.number("density_scale", {.lo = 1.0}, 1.0).value;
  d.manifold_tolerance =
      t.number("manifold_tolerance", {.lo = 0.0, .hi = 1.0, .hi_open = true}, 0.0).value;
  d.in_plane = t.boolean("in_plane", false);
  if (const toml::node* node = t.find("in_plane")) {
    d.in_plane_position = {line_of(node->source()), column_of(node->source())};
  }
  if (t.find("gravity") != nullptr) {
    const auto g = t.numbers("gravity", 3, Range{});
    d.gravity = {g[0], g[1], g[2]};
  }
  d.lift = t.number("lift", Range::non_negative(), 0.0).value;
  d.frames = t.int_integer("frames", 0, 20);
  d.settle_ratio = t.number("settle_ratio", {.lo = 0.0, .hi = 1.0}, 0.0).value;
  d.dt_safety = t.number("dt_safety", {.lo = 0.0, .hi = 1.0, .lo_open = true}, 0.2).value;
  d.search = t.choose<physics::SearchMethod>(
      "search", {{"bounding_box", physics::SearchMethod::bounding_box},
                 {"basic", physics::SearchMethod::basic}},
      physics::SearchMethod::bounding_box);
  d.threads = t.int_integer("threads", 0, 0);
}

constexpr std::string_view kWallKeys[] = {"name",   "kind",   "point",    "normal",
                                          "u",      "size",   "length",   "radius",
                                          "velocity", "load_axis", "gap"};

physics::Wall read_wall(const TableReader& t, std::size_t index) {
  t.reject_unknown(kWallKeys);
  enum class Kind { plane, platen, cylinder };
  const Kind kind = t.choose<Kind>(
      "kind", {{"plane", Kind::plane}, {"platen", Kind::platen}, {"cylinder", Kind::cylinder}});
  const std::string name = t.string("name", fmt::format("wall_{}", index + 1));
  auto vec = [&](std::string_view key) -> Eigen::Vector3d {
    const auto v = t.numbers(key, 3, Range{});
    return Eigen::Vector3d(v[0], v[1], v[2]);
  };
  auto direction = [&](std::string_view key) -> Eigen::Vector3d {
    const Eigen::Vector3d v = vec(key);
    if (v.norm() == 0.0) t.fail(*t.find(key), key, "must not be the zero vector");
    return v;
  };
  const Eigen::Vector3d point = vec("point");
  const Eigen::Vector3d normal = direction("normal");
  // Keys that belong to another kind of wall are errors, as for specimen shapes.
  const std::vector<std::string_view> own = kind == Kind::platen     ? std::vector<std::string_view>{"u", "size"}
                                            : kind == Kind::cylinder ? std::vector<std::string_view>{"length", "radius"}
                                                                     : std::vector<std::string_view>{};
  for (std::string_view key : {"u", "size", "length", "radius"}) {
    if (t.find(key) != nullptr && std::find(own.begin(), own.end(), key) == own.end()) {
      t.fail(*t.find(key), key, "this key belongs to another kind of wall");
    }
  }
  physics::Wall w;
  switch (kind) {
    case Kind::plane:
      w = physics::Wall::plane(name, point, normal);
      break;
    case Kind::platen: {
      const Eigen::Vector3d u = direction("u");
      if (std::abs(u.normalized().dot(normal.normalized())) > 1.0 - 1e-9) {
        t.fail(*t.find("u"), "u", "must not be parallel to the normal");
      }
      const auto size = t.numbers("size", 2, Range::positive());
      w = physics::Wall::platen(name, point, normal, u, 0.5 * size[0], 0.5 * size[1]);
      break;
    }
    case Kind::cylinder:
      w = physics::Wall::cylinder(name, point, normal, t.number("length", Range::positive()).value,
                                  t.number("radius", Range::positive()).value);
      break;
  }
  if (t.find("velocity") != nullptr) w.velocity = vec("velocity");
  if (t.find("load_axis") != nullptr) w.load_axis = direction("load_axis").normalized();
  return w;
}

constexpr std::string_view kBondKeys[] = {"kbn", "kbs", "tbn", "tbs", "law", "sigma_c", "g_c",
                                          "strength_modulus", "criterion", "sigma_f",
                                          "young", "poisson", "radius"};

/// law = "beam" (seed 003, Andre et al. 2012): the beam's E_m, nu_m and R_m, and what breaks
/// it: its own outer-fibre stress against sigma_f (criterion "limits", the default; no
/// sigma_f: it never breaks) or a grain-stress criterion with sigma_f.
void read_beam_bond(const TableReader& t, BondDef& b) {
  for (std::string_view key : {"kbn", "kbs", "tbn", "tbs", "sigma_c", "g_c"}) {
    if (t.find(key) != nullptr)
      t.fail(*t.find(key), key, "the beam law takes young, poisson and radius (and sigma_f), not springs or bond strengths");
  }
  b.params.beam_young = t.number("young", Range::positive()).value;
  b.params.beam_poisson = t.number("poisson", Range{-1.0, 0.5, true, false}).value;
  b.params.beam_radius = t.number("radius", Range::positive()).value;
  b.params.criterion = t.choose<physics::BondCriterion>(
      "criterion", {{"limits", physics::BondCriterion::limits},
                    {"rankine", physics::BondCriterion::rankine},
                    {"hydrostatic", physics::BondCriterion::hydrostatic}},
      physics::BondCriterion::limits);
  if (b.params.criterion == physics::BondCriterion::limits) {
    b.params.sigma_f = t.number("sigma_f", Range::positive(), std::numeric_limits<double>::infinity()).value;
  } else {
    b.params.sigma_f = t.number("sigma_f", Range::positive()).value;
  }
  b.strength_modulus = t.number("strength_modulus", Range::positive(), 0.0).value;
}

void read_bond_table(const TableReader& t, BondDef& b) {
  t.reject_unknown(kBondKeys);
  if (t.table() == nullptr) return;
  b.enabled = true;
  b.params.law = t.choose<physics::BondLaw>(
      "law", {{"bonded_particle", physics::BondLaw::bonded_particle},
              {"cohesive", physics::BondLaw::cohesive},
              {"beam", physics::BondLaw::beam}},
      physics::BondLaw::bonded_particle);
  if (b.params.law == physics::BondLaw::beam) {
    read_beam_bond(t, b);
    return;
  }
  for (std::string_view key : {"young", "poisson", "radius"}) {
    if (t.find(key) != nullptr) t.fail(*t.find(key), key, "belongs to law = \"beam\"");
  }
  b.params.kbn = t.number("kbn", Range::positive()).value;
  b.params.kbs = t.number("kbs", Range::non_negative()).value;
  // Each law's own keys; those of the other law are errors.
  const bool cohesive = b.params.law == physics::BondLaw::cohesive;
  for (std::string_view key : {"tbn", "tbs", "sigma_c", "g_c"}) {
    const bool own = (key == "tbn" || key == "tbs") != cohesive;
    if (!own && t.find(key) != nullptr)
      t.fail(*t.find(key), key,
             cohesive ? "the cohesive law has no bond strengths tbn/tbs; it takes sigma_c and g_c"
                      : "sigma_c and g_c belong to law = \"cohesive\"");
  }
  b.params.criterion = t.choose<physics::BondCriterion>(
      "criterion", {{"limits", physics::BondCriterion::limits},
                    {"rankine", physics::BondCriterion::rankine},
                    {"hydrostatic", physics::BondCriterion::hydrostatic}},
      physics::BondCriterion::limits);
  const bool stress = b.params.criterion != physics::BondCriterion::limits;
  if (stress && cohesive) {
    t.fail(*t.find("criterion"), "criterion", "a stress criterion goes with law = \"bonded_particle\"");
  }
  if (!stress && t.find("sigma_f") != nullptr) {
    t.fail(*t.find("sigma_f"), "sigma_f", "applies only with criterion = \"rankine\" or \"hydrostatic\"");
  }
  if (stress) {
    for (std::string_view key : {"tbn", "tbs"}) {
      if (t.find(key) != nullptr)
        t.fail(*t.find(key), key, "a stress criterion replaces the bond strengths tbn/tbs; give sigma_f");
    }
  }
  if (cohesive) {
    b.params.sigma_c = t.number("sigma_c", Range::positive()).value;
    b.params.g_c = t.number("g_c", Range::positive()).value;
  } else if (stress) {
    b.params.sigma_f = t.number("sigma_f", Range::positive()).value;
    b.params.tbn = b.params.tbs = std::numeric_limits<double>::infinity();
  } else {
    b.params.tbn = t.number("tbn", Range::positive()).value;
    b.params.tbs = t.number("tbs", Range::positive()).value;
  }
  b.strength_modulus = t.number("strength_modulus", Range::positive(), 0.0).value;
}

constexpr std::string_view kFractureKeys[] = {"sigma_f_hyd", "k_ic",      "c",       "crack_length",
                                              "check_every", "criterion", "sigma_f", "inertia"};

void read_fracture_table(const TableReader& t, bool dynamics, FractureDef& f) {
  t.reject_unknown(kFractureKeys);
  if (t.table() == nullptr) return;
  if (!dynamics) t.fail_table("[fracture] needs a [dynamics] table");
  f.enabled = true;
  f.params.criterion = t.choose<physics::GrainCriterion>(
      "criterion", {{"lefm", physics::GrainCriterion::lefm},
                    {"rankine", physics::GrainCriterion::rankine},
                    {"hydrostatic", physics::GrainCriterion::hydrostatic}},
      physics::GrainCriterion::lefm);
  f.check_every = t.int_integer("check_every", 1, 1);
  if (f.params.criterion != physics::GrainCriterion::lefm) {
    for (std::string_view key : {"sigma_f_hyd", "k_ic", "c", "crack_length", "inertia"}) {
      if (t.find(key) != nullptr)
        t.fail(*t.find(key), key, "belongs to criterion = \"lefm\" (sec. 3.4); a stress criterion takes sigma_f");
    }
    f.params.sigma_f = t.number("sigma_f", Range::positive()).value;
    return;
  }
  if (t.find("sigma_f") != nullptr) {
    t.fail(*t.find("sigma_f"), "sigma_f", "applies only with criterion = \"rankine\" or \"hydrostatic\"");
  }
  f.params.sigma_f_hyd = t.number("sigma_f_hyd", Range{}).value;
  f.params.k_ic = t.number("k_ic", Range::positive()).value;
  f.params.c = t.number("c", Range::positive(), 0.816).value;
  f.params.crack_length = t.number("crack_length", Range::positive()).value;
  f.params.inertia = t.boolean("inertia", true);
}

constexpr std::string_view kMotionStageKeys[] = {"name",  "kind",      "wall_velocity",
                                                 "steps", "time",      "until",
                                                 "load_drop", "load_walls", "frames",
                                                 "ramp_time", "rate_scale", "temperature_rate",
                                                 "temperature_target", "quench_wall", "quench_temperature",
                                                 "quench_depth", "cell_strain_rate", "measure_modulus",
                                                 "temperature_gradient_rate", "temperature_field",
                                                 "hold_cracks"};

constexpr std::string_view kPeriodicKeys[] = {"axes", "stress_control_time", "stress_control_modulus"};

/// [periodic] axes = ["x", "y", "z"] (any non-empty set): the Voronoi specimen's box is a
/// periodic cell along those axes (its cells tile it periodically there).
void read_periodic_table(const TableReader& t, Scenario& s) {
  t.reject_unknown(kPeriodicKeys);
  if (t.table() == nullptr) return;
  if (!s.dynamics.enabled) t.fail_table("[periodic] needs a [dynamics] table");
  const toml::node* node = t.find("axes");
  if (node == nullptr) t.fail_absent("axes", "missing required key: the periodic axes, e.g. [\"x\", \"y\", \"z\"]");
  const auto* array = node->as_array();
  if (array == nullptr || array->empty())
    t.fail(*node, "axes", "expected a non-empty array of axis names \"x\", \"y\", \"z\"");
  for (std::size_t i = 0; i < array->size(); ++i) {
    const auto* name = array->get(i)->as_string();
    const std::string text = name != nullptr ? name->get() : std::string();
    if (text != "x" && text != "y" && text != "z")
      t.fail(*array->get(i), "axes", fmt::format("element {}: expected \"x\", \"y\" or \"z\"", i + 1));
    const auto k = static_cast<std::size_t>(text[0] - 'x');
    if (s.periodic.axes[k]) t.fail(*array->get(i), "axes", fmt::format("axis \"{}\" is named twice", text));
    s.periodic.axes[k] = true;
  }
  if (s.specimen.kind != geometry::SpecimenKind::voronoi)
    t.fail(*node, "axes", "a periodic cell is the box of a Voronoi specimen: [specimen] shape = \"voronoi\"");
  if (s.specimen.voronoi.domain == geometry::VoronoiDomain::disc)
    t.fail(*node, "axes",
           "a Voronoi disc has no periodic axes: a periodic cell is a box (domain = \"box\")");
  s.periodic.enabled = true;
  s.periodic.position = {line_of(node->source()), column_of(node->source())};
  const Number tau = t.number("stress_control_time", Range::positive(), 0.0);
  const Number modulus = t.number("stress_control_modulus", Range::positive(), 0.0);
  if ((tau.node == nullptr) != (modulus.node == nullptr)) {
    const bool has_tau = tau.node != nullptr;
    t.fail(has_tau ? *tau.node : *modulus.node, has_tau ? "stress_control_time" : "stress_control_modulus",
           "stress control takes both stress_control_time (s) and stress_control_modulus (Pa)");
  }
  s.periodic.stress_control_time = tau.value;
  s.periodic.stress_control_modulus = modulus.value;
  s.specimen.voronoi.periodic = s.periodic.axes;
}

constexpr std::string_view kThermalKeys[] = {"temperature", "alpha", "alpha_a", "alpha_b", "alpha_c",
                                             "c_axis",      "seed",         "conductivity", "heat_capacity",
                                             "gradient"};

void read_thermal_table(const TableReader& t, bool dynamics, bool crystal, ThermalDef& th) {
  t.reject_unknown(kThermalKeys);
  if (t.table() == nullptr) return;
  if (!dynamics) t.fail_table("[thermal] needs a [dynamics] table");
  th.enabled = true;
  th.temperature = t.number("temperature", Range::positive(), 293.15).value;
  if (const toml::node* node = t.find("gradient")) {
    th.gradient_at = {line_of(node->source()), column_of(node->source())};
    const auto g = t.numbers("gradient", 3, Range{});
    th.gradient = Eigen::Vector3d(g[0], g[1], g[2]);
  }
  const Number alpha = t.number("alpha", Range{}, 0.0);
  const Number aa = t.number("alpha_a", Range{}, alpha.value);
  const Number ac = t.number("alpha_c", Range{}, alpha.value);
  if (alpha.node != nullptr && (aa.node != nullptr || ac.node != nullptr)) {
    const toml::node& other = aa.node != nullptr ? *aa.node : *ac.node;
    t.fail(other, aa.node != nullptr ? "alpha_a" : "alpha_c",
           "give alpha (isotropic) or alpha_a and alpha_c (per crystal axis), not both");
  }
  if ((aa.node == nullptr) != (ac.node == nullptr)) {
    t.fail_absent(aa.node == nullptr ? "alpha_a" : "alpha_c", "alpha_a and alpha_c go together");
  }
  th.alpha_a = aa.value;
  th.alpha_c = ac.value;
  const Number ab = t.number("alpha_b", Range{}, aa.value);
  if (ab.node != nullptr && aa.node == nullptr) t.fail(*ab.node, "alpha_b", "alpha_b goes with alpha_a and alpha_c");
  th.alpha_b = ab.value;
  // With a 3D crystal its axes carry the coefficients; the seed's choices stay the default
  // without one.
  th.c_axis = t.choose<ThermalDef::Axis>("c_axis",
                                         {{"prism", ThermalDef::Axis::prism},
                                          {"random", ThermalDef::Axis::random},
                                          {"crystal", ThermalDef::Axis::crystal}},
                                         crystal ? ThermalDef::Axis::crystal : ThermalDef::Axis::prism);
  if (th.c_axis == ThermalDef::Axis::crystal && !crystal) {
    t.fail(*t.find("c_axis"), "c_axis", "\"crystal\" needs a [crystal] table (the grains' 3D crystals)");
  }
  if (th.alpha_b != th.alpha_a && th.c_axis != ThermalDef::Axis::crystal) {
    t.fail(*ab.node, "alpha_b",
           "three coefficients need each grain's a, b and c axes: c_axis = \"crystal\" with a [crystal] table");
  }
  th.seed = static_cast<std::uint64_t>(t.integer("seed", 0, 1));
  const Number conductivity = t.number("conductivity", Range::non_negative(), 0.0);
  th.conductivity = conductivity.value;
  if (th.conductivity > 0.0) {
    th.heat_capacity = t.number("heat_capacity", Range::positive()).value;
  } else if (const Number c = t.number("heat_capacity", Range::positive(), 0.0); c.node != nullptr) {
    th.heat_capacity = c.value;
  }
}
constexpr std::string_view kBondStageKeys[] = {"name", "kind", "distance"};

/// The names in an array of strings at `key`, each one a wall of the scenario.
std::vector<std::string> read_wall_names(const TableReader& t, std::string_view key,
                                         const std::vector<physics::Wall>& walls) {
  std::vector<std::string> names;
  const toml::node* node = t.find(key);
  if (node == nullptr) return names;
  const auto* array = node->as_array();
  if (array == nullptr) {
    t.fail(*node, key, fmt::format("expected an array of wall names, found {}", type_name(*node)));
  }
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& e = *array->get(i);
    const auto* name = e.as_string();
    if (name == nullptr) {
      t.fail(e, key, fmt::format("element {}: expected a wall name, found {}", i + 1, type_name(e)));
    }
    if (std::none_of(walls.begin(), walls.end(), [&](const auto& w) { return w.name == name->get(); })) {
      t.fail(e, key, fmt::format("element {}: no [[wall]] is named '{}'", i + 1, name->get()));
    }
    names.push_back(name->get());
  }
  return names;
}

StageDef read_stage(const TableReader& t, double unit, const Scenario& s) {
  StageDef st;
  st.position = {line_of(t.table()->source()), column_of(t.table()->source())};
  st.kind = t.choose<StageDef::Kind>(
      "kind", {{"motion", StageDef::Kind::motion}, {"bond", StageDef::Kind::bond}},
      StageDef::Kind::motion);
  t.reject_unknown(st.kind == StageDef::Kind::bond ? std::span<const std::string_view>(kBondStageKeys)
                                                   : std::span<const std::string_view>(kMotionStageKeys));
  st.name = t.string("name");
  if (st.name.empty()) t.fail(*t.find("name"), "name", "must not be empty");
  if (st.kind == StageDef::Kind::bond) {
    if (!s.bond.enabled) {
      t.fail(*t.find("kind"), "kind", "a bond stage needs a [bond] table with the bond parameters");
    }
    const Number distance = t.number("distance", Range::non_negative(), 0.0);
    st.bond_distance = distance.value;
    if (distance.node != nullptr)
      st.distance_position = {line_of(distance.node->source()), column_of(distance.node->source())};
    else
      st.distance_position = st.position;
    return st;
  }
  if (const toml::node* node = t.find("wall_velocity")) {
    const auto* table = node->as_table();
    if (table == nullptr) {
      t.fail(*node, "wall_velocity",
             fmt::format("expected a table of wall name = [vx, vy, vz], found {}", type_name(*node)));
    }
    const TableReader vt(s.source, t.name() + ".wall_velocity", table, t.units());
    for (const auto& [key, value] : *table) {
      const std::string name(key.str());
      if (std::none_of(s.walls.begin(), s.walls.end(), [&](const auto& w) { return w.name == name; })) {
        vt.fail(key_source(key, value), name, fmt::format("no [[wall]] is named '{}'", name));
      }
      const auto v = vt.numbers(name, 3, Range{});
      st.wall_velocity.emplace_back(name, Eigen::Vector3d(v[0], v[1], v[2]));
      st.wall_velocity_positions.push_back({line_of(value.source()), column_of(value.source())});
    }
  }
  const toml::node* steps = t.find("steps");
  const toml::node* time = t.find("time");
  if ((steps == nullptr) == (time == nullptr)) {
    if (steps != nullptr) t.fail(*time, "time", "give the stage's length as steps or time, not both");
    t.fail_absent("steps", "a motion stage needs its length: steps (integer > 0) or time (s > 0)");
  }
  if (steps != nullptr) st.steps = static_cast<std::uint64_t>(t.integer("steps", 1, 1));
  const toml::node* length = steps != nullptr ? steps : time;
  st.length_position = {line_of(length->source()), column_of(length->source())};
  if (time != nullptr) st.time = t.number("time", Range::positive()).value;
  st.until = t.choose<StageDef::Until>("until",
                                       {{"limit", StageDef::Until::limit},
                                        {"all_in_contact", StageDef::Until::all_in_contact},
                                        {"walls_touch", StageDef::Until::walls_touch},
                                        {"load_drop", StageDef::Until::load_drop}},
                                       StageDef::Until::limit);
  const Number drop = t.number("load_drop", {.lo = 0.0, .hi = 1.0, .lo_open = true, .hi_open = true}, 0.5);
  if (drop.node != nullptr && st.until != StageDef::Until::load_drop) {
    t.fail(*drop.node, "load_drop", "applies only with until = \"load_drop\"");
  }
  st.load_drop = drop.value;
  st.load_walls = read_wall_names(t, "load_walls", s.walls);
  if (st.load_walls.empty()) {
    for (const auto& [name, v] : st.wall_velocity) {
      if (v.norm() > 0.0) st.load_walls.push_back(name);
    }
  }
  if (st.load_walls.empty() &&
      (st.until == StageDef::Until::load_drop || st.until == StageDef::Until::walls_touch)) {
    t.fail(*t.find("until"), "until",
           fmt::format("'{}' needs walls to watch: give load_walls or move walls in "
                       "wall_velocity", to_string(st.until)));
  }
  st.frames = t.int_integer("frames", 0, 10);
  st.ramp_time = t.number("ramp_time", Range::non_negative(), 0.0).value;
  // The same test at another loading rate: faster walls over a shorter stage, or slower over
  // a longer one, folded in here (the as-run scenario holds the velocities and lengths run).
  const Number t_rate = t.number("temperature_rate", Range{}, 0.0);
  if (t_rate.node != nullptr && !s.thermal.enabled) {
    t.fail(*t_rate.node, "temperature_rate", "a temperature stage needs a [thermal] table");
  }
  st.temperature_rate = t_rate.value;
  if (st.temperature_rate != 0.0) {
    st.temperature_target = t.number("temperature_target", Range::positive()).value;
  } else if (const toml::node* target = t.find("temperature_target")) {
    t.fail(*target, "temperature_target", "applies only with a temperature_rate");
  }
  if (const toml::node* g = t.find("temperature_gradient_rate")) {
    if (!s.thermal.enabled) t.fail(*g, "temperature_gradient_rate", "a temperature stage needs a [thermal] table");
    const auto r = t.numbers("temperature_gradient_rate", 3, Range{});
    st.temperature_gradient_rate = Eigen::Vector3d(r[0], r[1], r[2]);
  }
  if (const toml::node* field = t.find("temperature_field")) {
    if (!s.thermal.enabled) t.fail(*field, "temperature_field", "a temperature stage needs a [thermal] table");
    for (std::string_view other : {"temperature_rate", "temperature_gradient_rate"}) {
      if (t.find(other) != nullptr)
        t.fail(*field, "temperature_field", fmt::format("prescribes every grain's temperature: leave out {}", other));
    }
    const std::string text = t.string("temperature_field");
    try {
      FieldExpression check(text);
    } catch (const std::invalid_argument& e) {
      t.fail(*field, "temperature_field", e.what());
    }
    st.temperature_field = lengths_in_metres(text, unit);  // kept in metres, as every length
  }
  if (const toml::node* quench = t.find("quench_wall")) {
    if (!s.thermal.enabled) t.fail(*quench, "quench_wall", "a thermal shock needs a [thermal] table");
    st.quench_wall = t.string("quench_wall");
    if (std::none_of(s.walls.begin(), s.walls.end(), [&](const auto& w) { return w.name == st.quench_wall; })) {
      t.fail(*quench, "quench_wall", fmt::format("no [[wall]] is named '{}'", st.quench_wall));
    }
    st.quench_temperature = t.number("quench_temperature", Range::positive()).value;
    st.quench_depth = t.number("quench_depth", Range::positive()).value;
  } else {
    for (std::string_view key : {"quench_temperature", "quench_depth"}) {
      if (t.find(key) != nullptr) t.fail(*t.find(key), key, "applies only with a quench_wall");
    }
  }
  if (const toml::node* cell = t.find("cell_strain_rate")) {
    if (!s.periodic.enabled) t.fail(*cell, "cell_strain_rate", "straining a cell needs a [periodic] table");
    const auto r = t.numbers("cell_strain_rate", 3, Range{});
    st.cell_strain_rate = Eigen::Vector3d(r[0], r[1], r[2]);
    for (int k = 0; k < 3; ++k) {
      if (r[static_cast<std::size_t>(k)] != 0.0 && !s.periodic.axes[static_cast<std::size_t>(k)])
        t.fail(*cell, "cell_strain_rate",
               fmt::format("element {}: the cell is not periodic along {}; only its periodic axes stretch", k + 1,
                           "xyz"[k]));
    }
  }
  st.measure_modulus = t.boolean("measure_modulus", false);
  if (st.measure_modulus && (st.cell_strain_rate.array() != 0.0).count() != 1) {
    t.fail(*t.find("measure_modulus"), "measure_modulus",
           "needs a cell_strain_rate along exactly one axis (a uniaxial strain test)");
  }
  st.hold_cracks = t.boolean("hold_cracks", false);
  if (st.hold_cracks && s.bond.params.law == physics::BondLaw::cohesive) {
    t.fail(*t.find("hold_cracks"), "hold_cracks", "the cohesive law's damage cannot be held; leave it out");
  }
  const double rate = t.number("rate_scale", Range::positive(), 1.0).value;
  if (rate != 1.0) {
    st.cell_strain_rate *= rate;
    for (auto& wv : st.wall_velocity) wv.second *= rate;
    if (st.steps > 0) st.steps = static_cast<std::uint64_t>(std::ceil(static_cast<double>(st.steps) / rate));
    st.time /= rate;
    st.ramp_time /= rate;
  }
  return st;
}

// ---- the file -----------------------------------------------------------------------------

constexpr std::string_view kTables[] = {
    "scenario", "specimen", "grain",   "orientation", "split", "output",   "material",
    "contact",  "dynamics", "wall",    "bond",        "stage", "fracture", "mesh_grain",
    "thermal",  "periodic", "crystal", "cleavage",    "phase", "boundary"};
constexpr std::string_view kRequiredTables[] = {"specimen", "grain"};

}  // namespace

const char* to_string(StageDef::Until until) {
  switch (until) {
    case StageDef::Until::limit: return "limit";
    case StageDef::Until::all_in_contact: return "all_in_contact";
    case StageDef::Until::walls_touch: return "walls_touch";
    case StageDef::Until::load_drop: return "load_drop";
  }
  return "?";
}

ScenarioError::ScenarioError(std::string file, int line, int column, std::string key,
                             std::string message)
    : std::runtime_error(format_error(file, line, column, key, message)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      key_(std::move(key)),
      message_(std::move(message)) {}

ScenarioError::ScenarioError(std::string what, std::string file, std::string key,
                             std::string message)
    : std::runtime_error(std::move(what)),
      file_(std::move(file)),
      line_(0),
      column_(0),
      key_(std::move(key)),
      message_(std::move(message)) {}

ScenarioError ScenarioError::in_override(const std::string& override_text, std::string file,
                                         std::string key, std::string message) {
  std::string what = format_error(override_text, 0, 0, key, message);
  return ScenarioError(std::move(what), std::move(file), std::move(key), std::move(message));
}

namespace {

/// A value as the file writes it, arrays included ("[12, 12, 4]").
std::string written_value(const toml::node& node) {
  if (const auto* a = node.as_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < a->size(); ++i) out += (i ? ", " : "") + written_value(*a->get(i));
    return out + "]";
  }
  return TableReader::written(node);
}

/// The keys that set how many grains the specimen holds, where the file has them: the
/// outline's sizes and the lattice's r and t, a Voronoi box's cell count, the mesh files.
std::vector<SizeKey> specimen_size_keys(const toml::table& root, const Scenario& s) {
  std::vector<SizeKey> keys;
  const auto add = [&](const toml::node* node, std::string key) {
    if (node == nullptr) return;
    keys.push_back({std::move(key),
                    {line_of(node->source()), column_of(node->source())},
                    written_value(*node)});
  };
  const auto* specimen = root.get_as<toml::table>("specimen");
  const auto* grain = root.get_as<toml::table>("grain");
  switch (s.specimen.kind) {
    case geometry::SpecimenKind::lattice:
      for (std::string_view key : {"size", "diameter", "length", "height", "thickness"})
        add(specimen ? specimen->get(key) : nullptr, "specimen." + std::string(key));
      for (std::string_view key : {"r", "t"})
        add(grain ? grain->get(key) : nullptr, "grain." + std::string(key));
      break;
    case geometry::SpecimenKind::voronoi:
      add(specimen ? specimen->get("grains") : nullptr, "specimen.grains");
      add(specimen ? specimen->get("size_mean") : nullptr, "specimen.size_mean");
      break;
    case geometry::SpecimenKind::meshes:
      if (s.tessellation) add(specimen ? specimen->get("file") : nullptr, "specimen.file");
      if (const auto* tables = root.get_as<toml::array>("mesh_grain"))
        for (std::size_t i = 0; i < tables->size() && i < 3; ++i)
          if (const auto* g = tables->get(i)->as_table())
            add(g->get("file"), fmt::format("mesh_grain[{}].file", i + 1));
      break;
  }
  return keys;
}

}  // namespace

Scenario parse_scenario(std::string_view text, const std::string& source) {
  const toml::table root = parse_root(text, source, kTables, "a scenario");
  for (std::string_view name : kTables) {
    const toml::node* node = root.get(name);
    if (name == "wall" || name == "stage" || name == "mesh_grain" || name == "cleavage" ||
        name == "phase" || name == "boundary") {  // arrays of tables
      if (node != nullptr && !node->is_array_of_tables()) {
        throw ScenarioError(source, line_of(node->source()), column_of(node->source()),
                            std::string(name),
                            fmt::format("expected [[{}]] tables, found {}", name, type_name(*node)));
      }
      continue;
    }
    if (node != nullptr && !node->is_table()) {
      throw ScenarioError(source, line_of(node->source()), column_of(node->source()),
                          std::string(name),
                          fmt::format("expected a table, found {}", type_name(*node)));
    }
    const std::string shape_name = specimen_shape(root);
    const bool own_grains = shape_name == "voronoi" || shape_name == "mesh" ||
                            shape_name == "tess" || shape_name == "grain_file";
    if (node == nullptr && contains(kRequiredTables, name) && !(name == "grain" && own_grains)) {
      throw ScenarioError(source, 1, 1, std::string(name),
                          fmt::format("missing required table [{}]", name));
    }
  }
  // Every number of a key with a dimension is read in SI (scenario_key_dimensions); bare
  // lengths are in the file's length unit, known once [scenario] is read.
  UnitContext units{scenario_key_dimensions(), kDefaultUnit->metres};
  const auto reader = [&](std::string_view name) {
    return TableReader(source, std::string(name), root.get_as<toml::table>(name), &units);
  };

  Scenario s;
  s.source = source;
  double unit = kDefaultUnit->metres;
  read_scenario_table(reader("scenario"), s, unit);
  units.length_unit = unit;
  read_specimen_table(reader("specimen"), unit, s.specimen);
  if (s.specimen.kind == geometry::SpecimenKind::lattice) {
    read_grain_table(reader("grain"), s.specimen);
    if (const auto* meshes = root.get_as<toml::array>("mesh_grain")) {
      const toml::node& first = *meshes->get(0);
      throw ScenarioError(source, line_of(first.source()), column_of(first.source()), "mesh_grain",
                          "[[mesh_grain]] tables need [specimen] shape = \"mesh\"");
    }
  } else if (specimen_shape(root) == "tess" || specimen_shape(root) == "grain_file") {
    read_imported_grains(root, source, &units, s);
  } else {
    read_own_grains(root, source, &units, s.specimen, s.mesh_grains);
  }
  const PresetFamilies preset_families = read_crystal_table(reader("crystal"), s.specimen.crystal);
  read_orientation_table(reader("orientation"), s.specimen);
  read_split_table(reader("split"), s.split);
  read_output_table(reader("output"), s.output);
  read_material_table(reader("material"), s.material);
  const auto* stages = root.get_as<toml::array>("stage");
  read_dynamics_table(reader("dynamics"), s.dynamics, stages != nullptr);
  read_contact_table(reader("contact"), source, s.contact, s.dynamics.enabled);
  if (const auto* walls = root.get_as<toml::array>("wall")) {
    for (std::size_t i = 0; i < walls->size(); ++i) {
      const TableReader t(source, fmt::format("wall[{}]", i + 1), walls->get(i)->as_table(),
                          &units);
      s.walls.push_back(read_wall(t, i));
      const Number gap = t.number("gap", Range::non_negative(), std::numeric_limits<double>::quiet_NaN());
      if (gap.node != nullptr && s.walls.back().kind == physics::Wall::Kind::cylinder) {
        t.fail(*gap.node, "gap", "places a plane or a platen against the specimen; a cylinder is placed by its point");
      }
      s.wall_gaps.push_back(gap.value);
      const toml::node* point = t.find("point");
      s.wall_points.push_back({line_of(point->source()), column_of(point->source())});
      for (std::size_t j = 0; j < i; ++j) {
        if (s.walls[j].name == s.walls[i].name) {
          t.fail(*t.find("name"), "name", fmt::format("another [[wall]] is named '{}'", s.walls[i].name));
        }
      }
    }
  }
  read_bond_table(reader("bond"), s.bond);
  read_fracture_table(reader("fracture"), s.dynamics.enabled, s.fracture);
  read_cleavage_tables(root, source, &units, s.fracture, preset_families, s.specimen.crystal);
  read_thermal_table(reader("thermal"), s.dynamics.enabled, s.specimen.crystal.enabled, s.thermal);
  read_periodic_table(reader("periodic"), s);
  read_phase_tables(root, source, &units, s);
  if (stages != nullptr) {
    if (!s.dynamics.enabled) {
      const toml::node& first = *stages->get(0);
      throw ScenarioError(source, line_of(first.source()), column_of(first.source()), "stage",
                          "[[stage]] tables need a [dynamics] table (dt, gravity, ...)");
    }
    std::size_t bond_stages = 0;
    for (std::size_t i = 0; i < stages->size(); ++i) {
      const TableReader t(source, fmt::format("stage[{}]", i + 1), stages->get(i)->as_table(),
                          &units);
      s.stages.push_back(read_stage(t, unit, s));
      for (std::size_t j = 0; j < i; ++j) {
        if (s.stages[j].name == s.stages[i].name) {
          t.fail(*t.find("name"), "name", fmt::format("another [[stage]] is named '{}'", s.stages[i].name));
        }
      }
      if (s.stages[i].kind == StageDef::Kind::bond && ++bond_stages > 1) {
        t.fail(*t.find("kind"), "kind", "bonds are initialised once; this is the second bond stage");
      }
    }
  }
  if (s.bond.enabled && std::none_of(s.stages.begin(), s.stages.end(), [](const StageDef& st) {
        return st.kind == StageDef::Kind::bond;
      })) {
    const toml::table& b = *root.get_as<toml::table>("bond");
    throw ScenarioError(source, line_of(b.source()), column_of(b.source()), "bond",
                        "[bond] is given but no [[stage]] of kind \"bond\" initialises the bonds");
  }
  // Before anything is built: a specimen that holds no grain, or more than memory allows.
  check_specimen_budget(s, specimen_size_keys(root, s));
  return s;
}

Scenario load_scenario(const std::filesystem::path& file) {
  return parse_scenario(read_scenario_text(file), file.string());
}

}  // namespace cleave::io
