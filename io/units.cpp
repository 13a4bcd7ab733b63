#include "io/units.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <vector>

namespace cleave::io {

namespace {

// Each dimension's units, the SI one first. Sizes are products of exact decimal literals, so
// "1 mm" is 1 x 1e-3 m, the product a bare length in a length_unit = "mm" file gets.
constexpr UnitSpec kNone[] = {{"1", 1.0}};
constexpr UnitSpec kLength[] = {{"m", 1.0}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}, {"nm", 1e-9}};
constexpr UnitSpec kVelocity[] = {{"m/s", 1.0}, {"mm/s", 1e-3}, {"um/s", 1e-6}, {"cm/s", 1e-2}};
constexpr UnitSpec kAcceleration[] = {{"m/s^2", 1.0}, {"mm/s^2", 1e-3}};
constexpr UnitSpec kTime[] = {{"s", 1.0}, {"ms", 1e-3}, {"us", 1e-6}, {"ns", 1e-9}};
constexpr UnitSpec kRate[] = {{"1/s", 1.0}};
constexpr UnitSpec kStress[] = {{"Pa", 1.0},  {"kPa", 1e3},   {"MPa", 1e6},
                                {"GPa", 1e9}, {"N/m^2", 1.0}, {"N/mm^2", 1e6}};
constexpr UnitSpec kForce[] = {{"N", 1.0}, {"mN", 1e-3}, {"kN", 1e3}};
constexpr UnitSpec kStiffness[] = {
    {"N/m", 1.0}, {"N/mm", 1e3}, {"kN/m", 1e3}, {"MN/m", 1e6}, {"GN/m", 1e9}};
constexpr UnitSpec kStiffnessPerArea[] = {{"N/m^3", 1.0}, {"N/mm^3", 1e9}, {"GN/m^3", 1e9},
                                          {"GPa/m", 1e9}, {"MPa/m", 1e6},  {"Pa/m", 1.0}};
constexpr UnitSpec kRotationalStiffness[] = {{"N m/rad", 1.0}, {"N m", 1.0}, {"N mm/rad", 1e-3}};
constexpr UnitSpec kEnergyPerArea[] = {{"J/m^2", 1.0}, {"N/m", 1.0}, {"kJ/m^2", 1e3}};
constexpr UnitSpec kDensity[] = {{"kg/m^3", 1.0}, {"g/cm^3", 1e3}};
constexpr UnitSpec kMass[] = {{"kg", 1.0}, {"g", 1e-3}, {"mg", 1e-6}};
constexpr UnitSpec kEnergy[] = {{"J", 1.0}, {"mJ", 1e-3}, {"uJ", 1e-6}};
constexpr UnitSpec kTemperature[] = {{"K", 1.0}};
constexpr UnitSpec kTemperatureRate[] = {{"K/s", 1.0}, {"K/min", 1.0 / 60.0}};
constexpr UnitSpec kTemperatureGradient[] = {{"K/m", 1.0}, {"K/mm", 1e3}};
constexpr UnitSpec kTemperatureGradientRate[] = {{"K/(m s)", 1.0}, {"K/(mm s)", 1e3}};
constexpr UnitSpec kExpansion[] = {{"1/K", 1.0}, {"K^-1", 1.0}, {"1e-6/K", 1e-6}};
constexpr UnitSpec kConductivity[] = {{"W/(m K)", 1.0}};
constexpr UnitSpec kHeatCapacity[] = {{"J/(kg K)", 1.0}};
constexpr UnitSpec kToughness[] = {
    {"Pa m^0.5", 1.0}, {"MPa m^0.5", 1e6}, {"Pa sqrt(m)", 1.0}, {"MPa sqrt(m)", 1e6}};
constexpr UnitSpec kAngle[] = {{"rad", 1.0}, {"deg", 0.017453292519943295}};

std::string_view si_name(Dimension d) {
  return units_of(d).front().name;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

/// Every dimension, to say which one a misplaced unit belongs to.
constexpr Dimension kAll[] = {Dimension::length,
                              Dimension::velocity,
                              Dimension::acceleration,
                              Dimension::time,
                              Dimension::rate,
                              Dimension::stress,
                              Dimension::force,
                              Dimension::stiffness,
                              Dimension::stiffness_per_area,
                              Dimension::rotational_stiffness,
                              Dimension::energy_per_area,
                              Dimension::density,
                              Dimension::mass,
                              Dimension::energy,
                              Dimension::temperature,
                              Dimension::temperature_rate,
                              Dimension::temperature_gradient,
                              Dimension::temperature_gradient_rate,
                              Dimension::expansion,
                              Dimension::conductivity,
                              Dimension::heat_capacity,
                              Dimension::toughness,
                              Dimension::angle};

std::vector<std::string_view> split(std::string_view path) {
  std::vector<std::string_view> parts;
  while (true) {
    const auto dot = path.find('.');
    parts.push_back(path.substr(0, dot));
    if (dot == std::string_view::npos) return parts;
    path.remove_prefix(dot + 1);
  }
}

/// "wall[2]" -> "wall": a reader's name for one of an array of tables.
std::string_view without_index(std::string_view part) {
  return part.substr(0, part.find('['));
}

}  // namespace

std::span<const UnitSpec> units_of(Dimension d) {
  switch (d) {
    case Dimension::none:
      return kNone;
    case Dimension::length:
      return kLength;
    case Dimension::velocity:
      return kVelocity;
    case Dimension::acceleration:
      return kAcceleration;
    case Dimension::time:
      return kTime;
    case Dimension::rate:
      return kRate;
    case Dimension::stress:
      return kStress;
    case Dimension::force:
      return kForce;
    case Dimension::stiffness:
      return kStiffness;
    case Dimension::stiffness_per_area:
      return kStiffnessPerArea;
    case Dimension::rotational_stiffness:
      return kRotationalStiffness;
    case Dimension::energy_per_area:
      return kEnergyPerArea;
    case Dimension::density:
      return kDensity;
    case Dimension::mass:
      return kMass;
    case Dimension::energy:
      return kEnergy;
    case Dimension::temperature:
      return kTemperature;
    case Dimension::temperature_rate:
      return kTemperatureRate;
    case Dimension::temperature_gradient:
      return kTemperatureGradient;
    case Dimension::temperature_gradient_rate:
      return kTemperatureGradientRate;
    case Dimension::expansion:
      return kExpansion;
    case Dimension::conductivity:
      return kConductivity;
    case Dimension::heat_capacity:
      return kHeatCapacity;
    case Dimension::toughness:
      return kToughness;
    case Dimension::angle:
      return kAngle;
  }
  return kNone;
}

std::string describe(Dimension d) {
  const char* what = "a plain number";
  switch (d) {
    case Dimension::none:
      return what;
    case Dimension::length:
      what = "a length";
      break;
    case Dimension::velocity:
      what = "a velocity";
      break;
    case Dimension::acceleration:
      what = "an acceleration";
      break;
    case Dimension::time:
      what = "a time";
      break;
    case Dimension::rate:
      what = "a rate";
      break;
    case Dimension::stress:
      what = "a stress";
      break;
    case Dimension::force:
      what = "a force";
      break;
    case Dimension::stiffness:
      what = "a stiffness";
      break;
    case Dimension::stiffness_per_area:
      what = "a stiffness per area";
      break;
    case Dimension::rotational_stiffness:
      what = "a rotational stiffness";
      break;
    case Dimension::energy_per_area:
      what = "an energy per area";
      break;
    case Dimension::density:
      what = "a density";
      break;
    case Dimension::mass:
      what = "a mass";
      break;
    case Dimension::energy:
      what = "an energy";
      break;
    case Dimension::temperature:
      what = "a temperature";
      break;
    case Dimension::temperature_rate:
      what = "a rate of temperature";
      break;
    case Dimension::temperature_gradient:
      what = "a temperature gradient";
      break;
    case Dimension::temperature_gradient_rate:
      what = "a rate of temperature gradient";
      break;
    case Dimension::expansion:
      what = "an expansion coefficient";
      break;
    case Dimension::conductivity:
      what = "a thermal conductivity";
      break;
    case Dimension::heat_capacity:
      what = "a heat capacity";
      break;
    case Dimension::toughness:
      what = "a fracture toughness";
      break;
    case Dimension::angle:
      what = "an angle";
      break;
  }
  return fmt::format("{} ({})", what, si_name(d));
}

double parse_quantity(std::string_view text, Dimension d) {
  const std::string_view t = trim(text);
  double number = 0.0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), number);
  if (ec != std::errc() || end == t.data()) {
    throw UnitError(fmt::format(
        "expected a number and its unit, e.g. \"{}\", found \"{}\"",
        d == Dimension::none ? std::string("2.5") : "2.5 " + std::string(si_name(d)), text));
  }
  if (!std::isfinite(number))
    throw UnitError(fmt::format("expected a finite number, found \"{}\"", text));
  const std::string_view unit = trim(t.substr(static_cast<std::size_t>(end - t.data())));
  if (d == Dimension::none) {
    throw UnitError(fmt::format("is a plain number without a unit; found \"{}\"", text));
  }
  if (unit.empty()) {
    throw UnitError(
        fmt::format("expected a number, or a number with its unit as a string (e.g. \"{} {}\" "
                    "for {}); \"{}\" has no unit",
                    number, si_name(d), describe(d), text));
  }
  for (const UnitSpec& u : units_of(d)) {
    if (u.name == unit) return number * u.si;
  }
  std::string accepted;
  for (const UnitSpec& u : units_of(d))
    accepted += fmt::format("{}'{}'", accepted.empty() ? "" : ", ", u.name);
  for (Dimension other : kAll) {
    for (const UnitSpec& u : units_of(other)) {
      if (u.name == unit && other != d) {
        throw UnitError(
            fmt::format("'{}' is the unit of {}, but this key is {}; accepted units: {}", unit,
                        describe(other), describe(d), accepted));
      }
    }
  }
  throw UnitError(
      fmt::format("unknown unit '{}' for {}; accepted units: {}", unit, describe(d), accepted));
}

const KeyDimension* find_key_dimension(std::span<const KeyDimension> keys, std::string_view table,
                                       std::string_view key) {
  std::vector<std::string_view> path;
  for (std::string_view part : split(table)) path.push_back(without_index(part));
  path.push_back(key);
  for (const KeyDimension& k : keys) {
    const auto pattern = split(k.key);
    if (pattern.size() != path.size()) continue;
    bool match = true;
    for (std::size_t i = 0; i < path.size() && match; ++i)
      match = pattern[i] == "*" || pattern[i] == path[i];
    if (match) return &k;
  }
  return nullptr;
}

std::span<const KeyDimension> scenario_key_dimensions() {
  using D = Dimension;
  // The one table of a scenario key's dimension; the reference (docs/SCENARIO_FORMAT.md,
  // scenarios/reference.toml) names the same units. Keys not listed are plain numbers.
  static constexpr KeyDimension kKeys[] = {
      {"specimen.size", D::length, 1},
      {"specimen.diameter", D::length, 1},
      {"specimen.thickness", D::length, 1},
      {"specimen.length", D::length, 1},
      {"specimen.height", D::length, 1},
      {"specimen.notch_width", D::length, 1},
      {"specimen.notch_depth", D::length, 1},
      {"specimen.gap", D::length, 1},
      {"split.min_fragment_diameter", D::length, 1},
      {"specimen.size_mean", D::length, 1},
      {"specimen.scale", D::length, 1},
      {"mesh_grain.scale", D::length, 1},
      {"mesh_grain.position", D::length, 1},
      {"grain.r", D::length, 1},
      {"grain.r_bar", D::length, 1},
      {"grain.t", D::length, 1},
      {"grain.t_bar", D::length, 1},
      {"material.density", D::density},
      {"phase.density", D::density},
      {"phase.alpha", D::expansion},
      {"contact.dilation_radius", D::length, 1},
      {"contact.*.kn", D::stiffness},
      {"contact.*.ks", D::stiffness},
      {"contact.*.kr", D::rotational_stiffness},
      {"contact.*.kt", D::rotational_stiffness},
      {"dynamics.dt", D::time},
      {"dynamics.duration", D::time},
      {"dynamics.gravity", D::acceleration},
      {"dynamics.lift", D::length, 1},
      {"wall.point", D::length, 1},
      {"wall.size", D::length, 1},
      {"wall.length", D::length, 1},
      {"wall.radius", D::length, 1},
      {"wall.velocity", D::velocity, 1},
      {"wall.gap", D::length, 1},
      {"bond.kbn", D::stiffness_per_area},
      {"bond.kbs", D::stiffness_per_area},
      {"bond.tbn", D::stress},
      {"bond.tbs", D::stress},
      {"bond.sigma_c", D::stress},
      {"bond.g_c", D::energy_per_area},
      {"bond.sigma_f", D::stress},
      {"bond.young", D::stress},
      {"bond.radius", D::length, 1},
      {"fracture.sigma_f_hyd", D::stress},
      {"fracture.k_ic", D::toughness},
      {"fracture.crack_length", D::length, 1},
      {"fracture.sigma_f", D::stress},
      {"thermal.temperature", D::temperature},
      {"thermal.gradient", D::temperature_gradient, -1},
      {"thermal.alpha", D::expansion},
      {"thermal.alpha_a", D::expansion},
      {"thermal.alpha_b", D::expansion},
      {"thermal.alpha_c", D::expansion},
      {"cleavage.k_ic", D::toughness},
      {"cleavage.sigma_f", D::stress},
      {"thermal.conductivity", D::conductivity},
      {"thermal.heat_capacity", D::heat_capacity},
      {"periodic.stress_control_time", D::time},
      {"periodic.stress_control_modulus", D::stress},
      {"stage.wall_velocity.*", D::velocity, 1},
      {"stage.time", D::time},
      {"stage.ramp_time", D::time},
      {"stage.temperature_rate", D::temperature_rate},
      {"stage.temperature_target", D::temperature},
      {"stage.quench_temperature", D::temperature},
      {"stage.quench_depth", D::length, 1},
      {"stage.temperature_gradient_rate", D::temperature_gradient_rate, -1},
      {"stage.cell_strain_rate", D::rate},
      {"stage.distance", D::length, 1},
  };
  return kKeys;
}

std::span<const KeyDimension> validation_key_dimensions() {
  using D = Dimension;
  // Validation files: lengths in length_unit, everything else SI (the velocity too).
  static constexpr KeyDimension kKeys[] = {
      {"specimen.length", D::length, 1},
      {"specimen.breadth", D::length, 1},
      {"specimen.height", D::length, 1},
      {"specimen.initial_crack", D::length, 1},
      {"specimen.particle_radius", D::length, 1},
      {"specimen.intact_length", D::length, 1},
      {"material.young", D::stress},
      {"material.density", D::density},
      {"material.cohesive_strength", D::stress},
      {"material.fracture_energy", D::energy_per_area},
      {"material.g_Ic", D::energy_per_area},
      {"material.g_IIc", D::energy_per_area},
      {"loading.velocity", D::velocity},
      {"loading.ramp_time", D::time},
      {"loading.deflection", D::length, 1},
  };
  return kKeys;
}

}  // namespace cleave::io
