/// \file
/// The material library's files (format in material_library.hpp), read with the scenario
/// files' table reader: unknown keys, missing or impossible values and unknown units are
/// errors naming the file, line, column and key.

#include "io/material_library.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "io/toml_reader.hpp"
#include "io/units.hpp"

#ifndef CLEAVE_MATERIALS_DIR_DEFAULT
#define CLEAVE_MATERIALS_DIR_DEFAULT "materials"
#endif

namespace cleave::io {

namespace {

using namespace toml_reader;

constexpr std::string_view kTables[] = {"material", "properties", "sources"};
constexpr std::string_view kAllTables[] = {"material", "properties", "sources", "crystal", "cleavage"};
constexpr std::string_view kCrystalKeys[] = {"system", "c_over_a", "b_over_a"};
constexpr std::string_view kMaterialKeys[] = {"name", "description", "structure"};
constexpr std::string_view kPropertyKeys[] = {"value", "unit", "source", "note"};

/// The range a property's SI value must lie in: positive, Poisson's ratio in [0, 0.5)
/// (a negative one is possible in principle but no ceramic has it; 0.5 is incompressible).
Range range_of(std::string_view key) {
  if (key == "poisson") return {0.0, 0.5, false, true};
  return Range::positive();
}

MaterialProperty read_property(const std::string& source, const toml::table& properties,
                               const PropertySpec& spec, const toml::table* sources,
                               std::string_view section = "properties") {
  const toml::node* node = properties.get(spec.key);
  const std::string key = fmt::format("{}.{}", section, spec.key);
  const auto* table = node->as_table();
  if (table == nullptr) {
    throw ScenarioError(source, line_of(node->source()), column_of(node->source()), key,
                        fmt::format("expected an inline table {{ value = ..., unit = \"...\", "
                                    "source = \"...\" }}, found {}",
                                    type_name(*node)));
  }
  const TableReader t(source, key, table);
  t.reject_unknown(kPropertyKeys);
  MaterialProperty p;
  p.key = std::string(spec.key);
  p.quantity = spec.quantity;
  p.line = line_of(node->source());
  p.unit = t.string("unit");
  const auto units = units_of(spec.quantity);
  const auto unit = std::find_if(units.begin(), units.end(),
                                 [&](const UnitChoice& u) { return u.name == p.unit; });
  if (unit == units.end()) {
    std::vector<std::string> names;
    for (const auto& u : units) names.emplace_back(u.name);
    t.fail(*t.find("unit"), "unit",
           fmt::format("unknown unit '{}' for {}; accepted: {}", p.unit, spec.meaning,
                       quoted_list(names)));
  }
  // The range is checked on the number as written: every accepted unit is a positive
  // multiple of the SI one, so the sign and the Poisson bounds read the same in both.
  p.written = t.number("value", range_of(spec.key)).value;
  p.value = p.written * unit->si;
  p.source = t.string("source");
  const toml::node* citation = sources != nullptr ? sources->get(p.source) : nullptr;
  if (citation == nullptr || citation->as_string() == nullptr) {
    t.fail(*t.find("source"), "source",
           fmt::format("source '{}' is not in [sources]; give its citation there as "
                       "{} = \"Author, title, journal, year\"",
                       p.source, p.source));
  }
  p.citation = citation->as_string()->get();
  p.note = t.string("note", std::string());
  return p;
}

}  // namespace

const char* si_unit(Quantity q) {
  switch (q) {
    case Quantity::density: return "kg/m^3";
    case Quantity::stress: return "Pa";
    case Quantity::toughness: return "Pa m^0.5";
    case Quantity::length: return "m";
    case Quantity::ratio: return "1";
  }
  return "?";
}

std::vector<UnitChoice> units_of(Quantity q) {
  // The scenario files' units (io/units.hpp): one table of units for both formats.
  Dimension d = Dimension::none;
  switch (q) {
    case Quantity::density:
      d = Dimension::density;
      break;
    case Quantity::stress:
      d = Dimension::stress;
      break;
    case Quantity::toughness:
      d = Dimension::toughness;
      break;
    case Quantity::length:
      d = Dimension::length;
      break;
    case Quantity::ratio:
      d = Dimension::none;
      break;
  }
  std::vector<UnitChoice> out;
  for (const UnitSpec& u : io::units_of(d)) out.push_back({u.name, u.si});
  return out;
}

const std::vector<PropertySpec>& property_specs() {
  static const std::vector<PropertySpec> specs = {
      {"density", Quantity::density, true, "the density"},
      {"young", Quantity::stress, true, "Young's modulus E"},
      {"poisson", Quantity::ratio, true, "Poisson's ratio"},
      {"tensile_strength", Quantity::stress, true, "the tensile strength"},
      {"flexural_strength", Quantity::stress, true, "the flexural strength"},
      {"k_ic", Quantity::toughness, true, "the fracture toughness K_Ic"},
      {"grain_size", Quantity::length, true, "the mean grain size"},
      {"cleavage_k_ic", Quantity::toughness, false, "the cleavage toughness of a grain"},
      {"weibull_modulus", Quantity::ratio, false, "the Weibull modulus"},
  };
  return specs;
}

const MaterialProperty* MaterialPreset::find(std::string_view key) const {
  for (const auto& p : properties) {
    if (p.key == key) return &p;
  }
  return nullptr;
}

double MaterialPreset::si(std::string_view key) const {
  const MaterialProperty* p = find(key);
  if (p == nullptr) {
    throw std::out_of_range(
        fmt::format("{}: material '{}' gives no properties.{}", file, name, key));
  }
  return p->value;
}

MaterialPreset parse_material(std::string_view text, const std::string& source) {
  const toml::table root = parse_root(text, source, kAllTables, "a material file");
  for (std::string_view name : kTables) {
    const toml::node* node = root.get(name);
    if (node == nullptr) {
      throw ScenarioError(source, 1, 1, std::string(name),
                          fmt::format("missing required table [{}]", name));
    }
    if (!node->is_table()) {
      throw ScenarioError(source, line_of(node->source()), column_of(node->source()),
                          std::string(name),
                          fmt::format("expected a table, found {}", type_name(*node)));
    }
  }
  MaterialPreset m;
  m.file = source;
  const TableReader material(source, "material", root.get_as<toml::table>("material"));
  material.reject_unknown(kMaterialKeys);
  m.name = material.string("name");
  m.description = material.string("description");
  m.amorphous = material.choose<bool>("structure", {{"polycrystal", false}, {"amorphous", true}},
                                      std::optional(false));

  const toml::table& properties = *root.get_as<toml::table>("properties");
  const TableReader props(source, "properties", &properties);
  std::vector<std::string_view> known;
  for (const auto& spec : property_specs()) known.push_back(spec.key);
  props.reject_unknown(known);
  const auto* sources = root.get_as<toml::table>("sources");
  for (const auto& spec : property_specs()) {
    const bool grainy = spec.key == "grain_size" || spec.key == "cleavage_k_ic";
    const toml::node* node = properties.get(spec.key);
    if (m.amorphous && grainy && node != nullptr) {
      props.fail(node->source(), spec.key,
                 "an amorphous material has no grains; leave it out or set [material] "
                 "structure = \"polycrystal\"");
    }
    if (node == nullptr) {
      if (spec.required && !(m.amorphous && grainy)) {
        props.fail_absent(spec.key, fmt::format("missing required property ({})", spec.meaning));
      }
      continue;
    }
    m.properties.push_back(read_property(source, properties, spec, sources));
  }
  std::sort(m.properties.begin(), m.properties.end(),
            [](const MaterialProperty& a, const MaterialProperty& b) { return a.line < b.line; });
  std::vector<const MaterialProperty*> cited;
  for (const auto& p : m.properties) cited.push_back(&p);
  if (const auto* crystal = root.get_as<toml::table>("crystal")) {
    const TableReader t(source, "crystal", crystal);
    t.reject_unknown(kCrystalKeys);
    MaterialCrystal c;
    c.line = line_of(crystal->source());
    c.system = t.string("system");
    for (std::string_view k : {"c_over_a", "b_over_a"}) {
      if (crystal->get(k) == nullptr) continue;
      auto& slot = k == "c_over_a" ? c.c_over_a : c.b_over_a;
      slot = read_property(source, *crystal, PropertySpec{k, Quantity::ratio, false, "axis ratio"}, sources, "crystal");
    }
    if (const auto* cleavage = root.get_as<toml::table>("cleavage")) {
      for (const auto& [key, node] : *cleavage) {
        c.cleavage.push_back(read_property(source, *cleavage,
                                           PropertySpec{key.str(), Quantity::toughness, false, "cleavage toughness"},
                                           sources, "cleavage"));
      }
    }
    // toml++ keeps a table's keys sorted; the families stay in the file's order.
    std::sort(c.cleavage.begin(), c.cleavage.end(),
              [](const MaterialProperty& a, const MaterialProperty& b) { return a.line < b.line; });
    m.crystal = std::move(c);
    if (m.crystal->c_over_a) cited.push_back(&*m.crystal->c_over_a);
    if (m.crystal->b_over_a) cited.push_back(&*m.crystal->b_over_a);
    for (const auto& p : m.crystal->cleavage) cited.push_back(&p);
  } else if (const auto* cleavage = root.get_as<toml::table>("cleavage")) {
    throw ScenarioError(source, line_of(cleavage->source()), column_of(cleavage->source()), "cleavage",
                        "[cleavage] needs a [crystal] table (the system its indices are in)");
  }
  // A source nobody names is most likely a typo in a property's `source`.
  const TableReader cites(source, "sources", sources);
  for (const auto& [key, node] : *sources) {
    if (node.as_string() == nullptr) {
      cites.fail(node.source(), key.str(),
                 fmt::format("expected the citation as a string, found {}", type_name(node)));
    }
    const std::string name(key.str());  // (clang 14: a lambda may not capture a binding)
    const bool used = std::any_of(cited.begin(), cited.end(),
                                  [&](const MaterialProperty* p) { return p->source == name; });
    if (!used) cites.fail(key_source(key, node), key.str(), "no property names this source");
  }
  return m;
}

MaterialPreset load_material(const std::filesystem::path& file) {
  return parse_material(read_scenario_text(file), file.string());
}

std::filesystem::path materials_dir() {
  if (const char* dir = std::getenv("CLEAVE_MATERIALS_DIR"); dir != nullptr && *dir != '\0') {
    return dir;
  }
  return CLEAVE_MATERIALS_DIR_DEFAULT;
}

std::optional<std::filesystem::path> resolve_material(std::string_view preset,
                                                      const std::filesystem::path& base_dir) {
  const bool is_path = preset.find('/') != std::string_view::npos || preset.ends_with(".toml");
  const std::filesystem::path file = is_path ? base_dir / std::filesystem::path(preset)
                                             : materials_dir() / (std::string(preset) + ".toml");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return std::nullopt;
  return file;
}

std::vector<std::filesystem::path> library_files() {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(materials_dir(), ec)) {
    if (entry.is_regular_file() && entry.path().extension() == ".toml") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string describe_material(const MaterialPreset& m) {
  std::string out = fmt::format("{}: {}\n  file {}\n", m.name, m.description, m.file);
  std::vector<const MaterialProperty*> all;  // every row, for the sources below
  const auto row = [&](const MaterialProperty& p) {
    all.push_back(&p);
    out += fmt::format("  {:<18} {:>10g} {:<10} = {:<12.6g} {:<9} [{}]{}\n", p.key, p.written, p.unit, p.value,
                       si_unit(p.quantity), p.source, p.note.empty() ? "" : "  " + p.note);
  };
  for (const auto& p : m.properties) row(p);
  if (m.crystal) {
    // The single crystal ([crystal] preset = NAME): its system, ratios, cleavage families.
    out += fmt::format("  crystal: {}\n", m.crystal->system);
    if (m.crystal->c_over_a) row(*m.crystal->c_over_a);
    if (m.crystal->b_over_a) row(*m.crystal->b_over_a);
    for (const auto& p : m.crystal->cleavage) row(p);
  }
  out += "  sources:\n";
  std::vector<std::string> listed;
  for (const MaterialProperty* q : all) {
    const MaterialProperty& p = *q;
    if (std::find(listed.begin(), listed.end(), p.source) != listed.end()) continue;
    listed.push_back(p.source);
    out += fmt::format("    [{}] {}\n", p.source, p.citation);
  }
  return out;
}

}  // namespace cleave::io
