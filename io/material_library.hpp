#pragma once
/// \file
/// The material library: `materials/*.toml`, one real material a file, each property with
/// its value, its unit as written and the source it comes from. A scenario takes one with
/// `[material] preset = "sic_alpha"` (its density, and the macroscopic values `cleave
/// measure` compares with and `cleave calibrate` aims at); `cleave materials` lists them.
///
/// File format (materials/sic_alpha.toml is a complete example):
///
///   [material]
///   name = "sic_alpha"              # required: what a scenario's preset names
///   description = "..."            # required
///   structure = "polycrystal"      # optional: "polycrystal" (default) | "amorphous" (no
///                                  #   grains: grain_size and cleavage_k_ic are left out)
///   [properties]                   # each an inline table {value, unit, source, note}
///   density = { value = 3.16, unit = "g/cm^3", source = "munro1997" }
///   young = ...  poisson = ...  tensile_strength = ...  flexural_strength = ...  k_ic = ...
///   grain_size = ...               # required for a polycrystal
///   cleavage_k_ic = ...            # optional: the single crystal's toughness on cleavage
///   weibull_modulus = ...          # optional
///   [crystal]                      # optional: the single crystal ([crystal] preset = NAME)
///   system = "trigonal"            #   cubic | hexagonal | trigonal | orthorhombic
///   c_over_a = { value = 2.730, unit = "1", source = "..." }  # b_over_a the same way
///   [cleavage]                     # optional, with [crystal]: each family's toughness
///   "{11-20}" = { value = 2.4, unit = "MPa m^0.5", source = "..." }
///   [sources]                      # every source a property names, with its citation
///   munro1997 = "R. G. Munro, ..."
///
/// Every error is an io::ScenarioError "FILE:LINE:COL: key 'properties.young': message".

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cleave::io {

/// What a property measures, which sets the units it may be written in.
enum class Quantity { density, stress, toughness, length, ratio };

/// One property of a material: SI value and what the file says.
struct MaterialProperty {
  std::string key;        ///< "young"
  Quantity quantity = Quantity::ratio;
  double value = 0.0;     ///< SI: kg/m^3, Pa, Pa m^0.5, m, 1
  double written = 0.0;   ///< the number as written in the file
  std::string unit;       ///< the unit as written ("GPa")
  std::string source;     ///< key into [sources]
  std::string citation;   ///< the source's text
  std::string note;       ///< optional remark (test method, conditions)
  int line = 0;           ///< where it is written
};

/// A material's single crystal: its system, axis ratios and the toughness of each cleavage
/// family (MaterialProperty::key is the family, "{11-20}").
struct MaterialCrystal {
  std::string system;
  std::optional<MaterialProperty> c_over_a;
  std::optional<MaterialProperty> b_over_a;
  std::vector<MaterialProperty> cleavage;
  int line = 0;  ///< of [crystal]
};

struct MaterialPreset {
  std::string file;         ///< the file it was read from
  std::string name;         ///< [material] name
  std::string description;
  bool amorphous = false;   ///< structure = "amorphous"
  std::vector<MaterialProperty> properties;  ///< in file order
  std::optional<MaterialCrystal> crystal;    ///< [crystal] and [cleavage], when given

  /// The property `key`, or null when the file does not give it.
  [[nodiscard]] const MaterialProperty* find(std::string_view key) const;
  /// The SI value of a property the file must give (every required one is there after
  /// reading); throws std::out_of_range naming the file for an optional one left out.
  [[nodiscard]] double si(std::string_view key) const;
};

/// The SI unit a quantity is stored in: "kg/m^3", "Pa", "Pa m^0.5", "m", "1".
const char* si_unit(Quantity q);
/// The unit names a quantity may be written in, and each one's size in SI.
struct UnitChoice {
  std::string_view name;
  double si;
};
std::vector<UnitChoice> units_of(Quantity q);

/// The keys of [properties], in the order the listing prints them, with their quantity
/// and whether every material must give them (grain_size: every polycrystal).
struct PropertySpec {
  std::string_view key;
  Quantity quantity;
  bool required;
  std::string_view meaning;
};
const std::vector<PropertySpec>& property_specs();

MaterialPreset parse_material(std::string_view text, const std::string& source);
MaterialPreset load_material(const std::filesystem::path& file);

/// The folder of the library: $CLEAVE_MATERIALS_DIR when set, else the source tree's
/// materials/ (compiled in).
std::filesystem::path materials_dir();
/// The file a scenario's `preset` names: a value with a '/' or ending in ".toml" is a path
/// (relative to `base_dir`, the scenario's folder); a bare name is materials_dir()/NAME.toml.
/// Returns nothing when that file does not exist.
std::optional<std::filesystem::path> resolve_material(std::string_view preset,
                                                      const std::filesystem::path& base_dir);
/// Every *.toml of materials_dir(), sorted by name.
std::vector<std::filesystem::path> library_files();

/// A preset as a table for `cleave materials show`: one line a property, its value in the
/// unit written and in SI, and its source.
std::string describe_material(const MaterialPreset& m);

}  // namespace cleave::io
