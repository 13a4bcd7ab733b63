#pragma once
/// \file
/// The tables a dynamic run writes (energy.csv, walls.csv, load_displacement.csv, bonds.csv,
/// cracks.csv, bond_breaks.csv, splits.csv, thermal.csv, cell.csv, modulus.csv): one row struct per
/// table, its columns named with their units, and one CSV writer for all of them that
/// formats every number by its column's precision and finds the first value that is not
/// finite.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "physics/dem/world.hpp"
#include "sim/crack_tally.hpp"

namespace cleave::sim {

/// How a column's values are written: numbers with 9 significant digits (what a value is
/// read back for) or 6 (directions, stresses and overlaps, read by eye), integers, text.
enum class Format { full, brief, integer, text };

struct Column {
  std::string name;  ///< with its unit: time_s, load_N
  Format format = Format::full;
};

/// One cell: a number, an integer, text, or nothing (an empty field).
using Cell = std::variant<std::monostate, double, long long, std::string>;

/// A CSV table built up row by row. Its text (header first) is what a checkpoint saves.
class CsvTable {
 public:
  CsvTable() = default;
  /// `file`: the table's name in the result folder, for messages (energy.csv).
  CsvTable(std::string file, std::vector<Column> columns);
  /// The first cell of `cells` holding a number that is not finite, as "<file> <column>".
  [[nodiscard]] std::optional<std::string> non_finite(const std::vector<Cell>& cells) const;
  /// Appends one row (as many cells as columns), as it is: the caller checks non_finite.
  void add(const std::vector<Cell>& cells);
  [[nodiscard]] bool has_rows() const { return text_.find('\n') + 1 < text_.size(); }
  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] const std::string& text() const { return text_; }
  /// The text of a checkpoint's table, header and rows.
  void restore(std::string text) { text_ = std::move(text); }
  /// The rows (header left out) whose column 1 is `stage` (all rows when empty), split.
  [[nodiscard]] std::vector<std::vector<std::string>> rows(const std::string& stage = {}) const;

 private:
  std::string file_;
  std::vector<Column> columns_;
  std::string text_;
};

/// What a testing machine reads off one wall: the force the specimen presses it with and
/// how far it has moved, both along its load axis (magnitudes when it has none).
struct WallReading {
  double force = 0.0, displacement = 0.0;
};
WallReading read_wall(const physics::Wall& w, const Eigen::Vector3d& origin0);

/// energy.csv
struct EnergyRow {
  double time_s = 0.0, kinetic_J = 0.0, potential_J = 0.0;
  std::size_t contacts = 0;
  double max_overlap_m = 0.0;
  std::string stage;
  static std::vector<Column> columns();
  [[nodiscard]] std::vector<Cell> cells() const;
};

/// walls.csv: each wall's reaction.
struct WallsRow {
  double time_s = 0.0;
  std::vector<Eigen::Vector3d> reaction_N;
  static std::vector<Column> columns(const std::vector<physics::Wall>& walls);
  [[nodiscard]] std::vector<Cell> cells() const;
};

/// load_displacement.csv: each wall's reading, and the stage's machine reading when it
/// has load walls.
struct LoadsRow {
  double time_s = 0.0;
  std::uint64_t step = 0;
  std::string stage;
  std::vector<WallReading> walls;
  std::optional<std::pair<double, double>> load_N_displacement_m;
  static std::vector<Column> columns(const std::vector<physics::Wall>& walls);
  [[nodiscard]] std::vector<Cell> cells() const;
};

/// bonds.csv
struct BondCountsRow {
  double time_s = 0.0;
  std::string stage;
  physics::BondCounts counts;
  static std::vector<Column> columns();
  [[nodiscard]] std::vector<Cell> cells() const;
};

/// cracks.csv: the crack areas and counts so far, and the transgranular fractions (empty
/// before the first crack).
struct CracksRow {
  double time_s = 0.0;
  std::string stage;
  CrackTotals cracks;
  static std::vector<Column> columns();
  [[nodiscard]] std::vector<Cell> cells() const;
};

/// thermal.csv
struct ThermalRow {
  double time_s = 0.0;
  std::string stage;
  double mean_K = 0.0, min_K = 0.0, max_K = 0.0;
  std::size_t bonds_intact = 0, bonds_broken = 0, grain_splits = 0;
  static std::vector<Column> columns();
  [[nodiscard]] std::vector<Cell> cells() const;
};

/// cell.csv: a periodic cell's edge lengths, its strain from the start, its mean stress.
struct CellRow {
  double time_s = 0.0;
  std::string stage;
  Eigen::Vector3d length_m = Eigen::Vector3d::Zero(), strain = Eigen::Vector3d::Zero();
  Eigen::Matrix3d stress_Pa = Eigen::Matrix3d::Zero();
  static std::vector<Column> columns();
  [[nodiscard]] std::vector<Cell> cells() const;
};

/// modulus.csv: one uniaxial strain test of a periodic cell.
struct ModulusRow {
  std::string stage;
  double time_s = 0.0;
  std::optional<double> mean_K;  ///< with [thermal]
  char axis = 'x';
  double strain = 0.0, young_Pa = 0.0;
  std::optional<double> poisson;  ///< measured when a lateral axis is held
  std::size_t bonds_broken = 0, grain_splits = 0;
  static std::vector<Column> columns();
  [[nodiscard]] std::vector<Cell> cells() const;
};

/// splits.csv: one transgranular crack.
struct SplitRow {
  double time_s = 0.0;
  std::uint64_t step = 0;
  std::string stage;
  int grain = 0;
  std::string parent, pieces;
  int plane = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero(), point_m = Eigen::Vector3d::Zero();
  double mean_stress_Pa = 0.0, sigma_Pa = 0.0, tau_Pa = 0.0, K_I_Pa_sqrt_m = 0.0,
         K_II_Pa_sqrt_m = 0.0, criterion = 0.0;
  double section_area_m2 = 0.0;  ///< SplitEvent::section_area
  static std::vector<Column> columns();
  [[nodiscard]] std::vector<Cell> cells() const;
};

/// bond_breaks.csv: one broken bond and its loads when it broke.
struct BondBreakRow {
  const physics::BondBreak* bond = nullptr;
  std::string stage;
  static std::vector<Column> columns();
  [[nodiscard]] std::vector<Cell> cells() const;
};

}  // namespace cleave::sim
