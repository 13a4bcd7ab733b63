#pragma once
/// \file
/// Units written with a value in a scenario file ("250 MPa", "0.6 mm", "15 us"): the
/// dimensions a key can have, the units each accepts and their size in SI, and the table of
/// which key has which dimension (one table per file format, used by the TOML reader).
///
/// A value with a unit is its number times the unit's size in SI (1 mm = 1e-3 m: the same
/// product as a bare length in a file of length_unit = "mm", so both give the same bits).
/// A bare number keeps its meaning: SI, except lengths (and what contains a length:
/// velocities, temperature gradients) in the file's length_unit.

#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cleave::io {

/// What a scenario number measures; `none`: a plain number (a ratio, a count).
enum class Dimension {
  none,
  length,                     ///< m
  velocity,                   ///< m/s
  acceleration,               ///< m/s^2
  time,                       ///< s
  rate,                       ///< 1/s (a strain rate)
  stress,                     ///< Pa (also a pressure or a modulus)
  force,                      ///< N
  stiffness,                  ///< N/m (a spring)
  stiffness_per_area,         ///< N/m^3 (a spring per bond area, eq. 2.9)
  rotational_stiffness,       ///< N m/rad
  energy_per_area,            ///< J/m^2 = N/m (a fracture energy)
  density,                    ///< kg/m^3
  mass,                       ///< kg
  energy,                     ///< J
  temperature,                ///< K
  temperature_rate,           ///< K/s
  temperature_gradient,       ///< K/m
  temperature_gradient_rate,  ///< K/(m s)
  expansion,                  ///< 1/K
  conductivity,               ///< W/(m K)
  heat_capacity,              ///< J/(kg K)
  toughness,                  ///< Pa m^0.5
  angle,                      ///< rad
};

/// One way to write a unit of a dimension and its size in SI.
struct UnitSpec {
  std::string_view name;  ///< as written after the number: "MPa", "mm/s", "N/m^3"
  double si;              ///< the unit in SI units: 1e6 for MPa
};

/// The units a dimension accepts, the SI one first.
std::span<const UnitSpec> units_of(Dimension d);
/// "a stress (Pa)", "a length (m)": for error messages.
std::string describe(Dimension d);

/// A value with a unit that cannot be read or is of another dimension; the message says
/// what was expected (the reader adds the file, line and key).
class UnitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// "250 MPa" as a stress: 2.5e8 (the number times the unit's size). Throws UnitError for a
/// malformed text, an unknown unit, or a unit of another dimension ("5 mm" as a stress).
double parse_quantity(std::string_view text, Dimension d);

/// A key of a file format and its dimension. `key` is a dotted path with `*` for any one
/// part ("stage.wall_velocity.*"); array-of-table indices are left out ("wall.velocity"
/// for wall[2].velocity). `length_power`: a bare number is in SI times the file's length
/// unit to this power (1 for lengths and velocities in mm and mm/s, -1 for K per mm).
struct KeyDimension {
  std::string_view key;
  Dimension dimension;
  int length_power = 0;
};

/// The dimension of `table`.`key` (table as a reader names it: "wall[2]", "stage[1].wall_velocity")
/// in `keys`; a key not listed is a plain number (Dimension::none).
const KeyDimension* find_key_dimension(std::span<const KeyDimension> keys, std::string_view table,
                                       std::string_view key);

/// The keys of scenario files (scenarios/reference.toml) and their dimensions.
std::span<const KeyDimension> scenario_key_dimensions();
/// The keys of validation scenario files (scenarios/validation/).
std::span<const KeyDimension> validation_key_dimensions();

}  // namespace cleave::io
