#include "sim/run_tables.hpp"

#include <fmt/format.h>

#include <cmath>

namespace cleave::sim {

namespace {

std::string format_cell(const Cell& cell, Format format) {
  if (const double* v = std::get_if<double>(&cell)) {
    return format == Format::brief ? fmt::format("{:.6g}", *v) : fmt::format("{:.9g}", *v);
  }
  if (const long long* v = std::get_if<long long>(&cell)) return fmt::format("{}", *v);
  if (const std::string* v = std::get_if<std::string>(&cell)) return *v;
  return {};
}

long long integer(std::size_t v) {
  return static_cast<long long>(v);
}

Cell number_or_empty(const std::optional<double>& v) {
  return v ? Cell(*v) : Cell();
}

}  // namespace

CsvTable::CsvTable(std::string file, std::vector<Column> columns)
    : file_(std::move(file)), columns_(std::move(columns)) {
  for (std::size_t k = 0; k < columns_.size(); ++k) text_ += (k ? "," : "") + columns_[k].name;
  text_ += '\n';
}

std::optional<std::string> CsvTable::non_finite(const std::vector<Cell>& cells) const {
  for (std::size_t k = 0; k < cells.size() && k < columns_.size(); ++k) {
    if (const double* v = std::get_if<double>(&cells[k]); v && !std::isfinite(*v)) {
      return fmt::format("{} {}", file_, columns_[k].name);
    }
  }
  return std::nullopt;
}

void CsvTable::add(const std::vector<Cell>& cells) {
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (k) text_ += ',';
    text_ += format_cell(cells[k], k < columns_.size() ? columns_[k].format : Format::full);
  }
  text_ += '\n';
}

std::vector<std::vector<std::string>> CsvTable::rows(const std::string& stage) const {
  std::vector<std::vector<std::string>> rows;
  std::size_t at = text_.find('\n') + 1;
  while (at < text_.size()) {
    const std::size_t end = text_.find('\n', at);
    std::vector<std::string> cells;
    std::size_t a = at;
    while (true) {
      const std::size_t comma = text_.find(',', a);
      if (comma == std::string::npos || comma > end) {
        cells.push_back(text_.substr(a, end - a));
        break;
      }
      cells.push_back(text_.substr(a, comma - a));
      a = comma + 1;
    }
    if (stage.empty() || (cells.size() > 1 && cells[1] == stage)) rows.push_back(std::move(cells));
    at = end + 1;
  }
  return rows;
}

WallReading read_wall(const physics::Wall& w, const Eigen::Vector3d& origin0) {
  const Eigen::Vector3d moved = w.origin - origin0;
  if (w.load_axis.squaredNorm() == 0.0) return {w.reaction.norm(), moved.norm()};
  return {-w.reaction.dot(w.load_axis), moved.dot(w.load_axis)};
}

std::vector<Column> EnergyRow::columns() {
  return {{"time_s"},
          {"kinetic_J"},
          {"potential_J"},
          {"contacts", Format::integer},
          {"max_overlap_m", Format::brief},
          {"stage", Format::text}};
}
std::vector<Cell> EnergyRow::cells() const {
  return {time_s, kinetic_J, potential_J, integer(contacts), max_overlap_m, stage};
}

std::vector<Column> WallsRow::columns(const std::vector<physics::Wall>& walls) {
  std::vector<Column> c{{"time_s"}};
  for (const auto& w : walls) {
    for (const char* axis : {"x", "y", "z"}) c.push_back({fmt::format("{}_F{}_N", w.name, axis)});
  }
  return c;
}
std::vector<Cell> WallsRow::cells() const {
  std::vector<Cell> c{time_s};
  for (const Eigen::Vector3d& f : reaction_N) c.insert(c.end(), {f.x(), f.y(), f.z()});
  return c;
}

std::vector<Column> LoadsRow::columns(const std::vector<physics::Wall>& walls) {
  std::vector<Column> c{{"time_s"}, {"step", Format::integer}, {"stage", Format::text}};
  for (const auto& w : walls) {
    c.push_back({w.name + "_displacement_m"});
    c.push_back({w.name + "_force_N"});
  }
  c.push_back({"load_N"});
  c.push_back({"load_point_displacement_m"});
  return c;
}
std::vector<Cell> LoadsRow::cells() const {
  std::vector<Cell> c{time_s, static_cast<long long>(step), stage};
  for (const WallReading& r : walls) c.insert(c.end(), {r.displacement, r.force});
  if (load_N_displacement_m) {
    c.insert(c.end(), {load_N_displacement_m->first, load_N_displacement_m->second});
  } else {
    c.insert(c.end(), {Cell(), Cell()});
  }
  return c;
}

std::vector<Column> BondCountsRow::columns() {
  return {{"time_s"},
          {"stage", Format::text},
          {"intact", Format::integer},
          {"broken_tension", Format::integer},
          {"broken_shear", Format::integer},
          {"broken_bending", Format::integer},
          {"broken_torsion", Format::integer}};
}
std::vector<Cell> BondCountsRow::cells() const {
  return {time_s,
          stage,
          integer(counts.intact),
          integer(counts.tension),
          integer(counts.shear),
          integer(counts.bending),
          integer(counts.torsion)};
}

std::vector<Column> CracksRow::columns() {
  return {{"time_s"},
          {"stage", Format::text},
          {"intergranular_area_m2"},
          {"transgranular_area_m2"},
          {"transgranular_area_fraction"},
          {"intergranular_count", Format::integer},
          {"transgranular_count", Format::integer},
          {"transgranular_count_fraction"}};
}
std::vector<Cell> CracksRow::cells() const {
  return {time_s,
          stage,
          cracks.intergranular_area,
          cracks.transgranular_area,
          number_or_empty(cracks.transgranular_area_fraction()),
          integer(cracks.intergranular),
          integer(cracks.transgranular),
          number_or_empty(cracks.transgranular_count_fraction())};
}

std::vector<Column> ThermalRow::columns() {
  return {{"time_s"},
          {"stage", Format::text},
          {"mean_K"},
          {"min_K"},
          {"max_K"},
          {"bonds_intact", Format::integer},
          {"bonds_broken", Format::integer},
          {"grain_splits", Format::integer}};
}
std::vector<Cell> ThermalRow::cells() const {
  return {time_s,
          stage,
          mean_K,
          min_K,
          max_K,
          integer(bonds_intact),
          integer(bonds_broken),
          integer(grain_splits)};
}

std::vector<Column> CellRow::columns() {
  std::vector<Column> c{{"time_s"}, {"stage", Format::text}};
  for (const char* name : {"lx_m", "ly_m", "lz_m", "strain_x", "strain_y", "strain_z", "sxx_Pa",
                           "syy_Pa", "szz_Pa", "syz_Pa", "sxz_Pa", "sxy_Pa"}) {
    c.push_back({name});
  }
  return c;
}
std::vector<Cell> CellRow::cells() const {
  const Eigen::Matrix3d& s = stress_Pa;
  return {time_s,     stage,   length_m.x(), length_m.y(), length_m.z(), strain.x(), strain.y(),
          strain.z(), s(0, 0), s(1, 1),      s(2, 2),      s(1, 2),      s(0, 2),    s(0, 1)};
}

std::vector<Column> ModulusRow::columns() {
  return {{"stage", Format::text},
          {"time_s"},
          {"mean_K"},
          {"axis", Format::text},
          {"strain"},
          {"young_Pa"},
          {"poisson"},
          {"bonds_broken", Format::integer},
          {"grain_splits", Format::integer}};
}
std::vector<Cell> ModulusRow::cells() const {
  return {stage,
          time_s,
          number_or_empty(mean_K),
          std::string(1, axis),
          strain,
          young_Pa,
          number_or_empty(poisson),
          integer(bonds_broken),
          integer(grain_splits)};
}

std::vector<Column> SplitRow::columns() {
  return {{"time_s"},
          {"step", Format::integer},
          {"stage", Format::text},
          {"grain", Format::integer},
          {"parent", Format::text},
          {"pieces", Format::text},
          {"plane", Format::integer},
          {"nx", Format::brief},
          {"ny", Format::brief},
          {"nz", Format::brief},
          {"x_m"},
          {"y_m"},
          {"z_m"},
          {"mean_stress_Pa", Format::brief},
          {"sigma_Pa", Format::brief},
          {"tau_Pa", Format::brief},
          {"K_I_Pa_sqrt_m", Format::brief},
          {"K_II_Pa_sqrt_m", Format::brief},
          {"criterion", Format::brief},
          {"section_area_m2"}};
}
std::vector<Cell> SplitRow::cells() const {
  return {time_s,        static_cast<long long>(step),
          stage,         grain,
          parent,        pieces,
          plane,         normal.x(),
          normal.y(),    normal.z(),
          point_m.x(),   point_m.y(),
          point_m.z(),   mean_stress_Pa,
          sigma_Pa,      tau_Pa,
          K_I_Pa_sqrt_m, K_II_Pa_sqrt_m,
          criterion,     section_area_m2};
}

std::vector<Column> BondBreakRow::columns() {
  return {{"time_s"},
          {"step", Format::integer},
          {"stage", Format::text},
          {"bond", Format::integer},
          {"body_a", Format::integer},
          {"body_b", Format::integer},
          {"grain_a", Format::integer},
          {"grain_b", Format::integer},
          {"x_m"},
          {"y_m"},
          {"z_m"},
          {"nx", Format::brief},
          {"ny", Format::brief},
          {"nz", Format::brief},
          {"mode", Format::text},
          {"normal_force_N"},
          {"shear_force_N"},
          {"bending_moment_Nm"},
          {"torsion_moment_Nm"},
          {"face_area_m2"}};
}
std::vector<Cell> BondBreakRow::cells() const {
  const physics::BondBreak& b = *bond;
  return {b.time,
          static_cast<long long>(b.step),
          stage,
          integer(b.bond),
          static_cast<long long>(b.a),
          static_cast<long long>(b.b),
          static_cast<long long>(b.grain_a),
          static_cast<long long>(b.grain_b),
          b.point.x(),
          b.point.y(),
          b.point.z(),
          b.normal.x(),
          b.normal.y(),
          b.normal.z(),
          std::string(physics::to_string(b.mode)),
          b.loads.normal,
          b.loads.shear.norm(),
          b.loads.bending.norm(),
          std::abs(b.loads.torsion),
          b.face_area};
}

}  // namespace cleave::sim
