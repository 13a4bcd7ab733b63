#include "sim/run_history.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <limits>

#include "io/plot.hpp"
#include "io/result_dir.hpp"

namespace cleave::sim {

RunHistory::RunHistory(const io::Scenario& scenario, const physics::World& world,
                       std::filesystem::path out)
    : scenario_(scenario), out_(std::move(out)) {
  for (const auto& w : world.walls()) origin0_.push_back(w.origin);
  pe0_ = world.potential_energy();
  energy_ = CsvTable("energy.csv", EnergyRow::columns());
  walls_ = CsvTable("walls.csv", WallsRow::columns(world.walls()));
  loads_ = CsvTable("load_displacement.csv", LoadsRow::columns(world.walls()));
  bond_counts_ = CsvTable("bonds.csv", BondCountsRow::columns());
  if (writes_cracks()) cracks_ = CsvTable("cracks.csv", CracksRow::columns());
  if (scenario_.thermal.enabled) thermal_ = CsvTable("thermal.csv", ThermalRow::columns());
  if (const physics::PeriodicCell* cell = world.cell()) {
    cell_ = CsvTable("cell.csv", CellRow::columns());
    modulus_ = CsvTable("modulus.csv", ModulusRow::columns());
    cell0_ = cell->vectors().colwise().norm().transpose();
  }
  if (scenario_.fracture.enabled) splits_ = CsvTable("splits.csv", SplitRow::columns());
}

std::vector<CsvTable*> RunHistory::tables() {
  return {&energy_, &walls_,   &loads_, &bond_counts_, &cracks_,
          &splits_, &thermal_, &cell_,  &modulus_};
}
std::vector<const CsvTable*> RunHistory::tables() const {
  return {&energy_, &walls_,   &loads_, &bond_counts_, &cracks_,
          &splits_, &thermal_, &cell_,  &modulus_};
}

std::optional<std::string> RunHistory::record(const physics::World& world, const std::string& stage,
                                              const WorldReadings& now,
                                              std::optional<std::pair<double, double>> reading,
                                              const CrackTotals& cracks) {
  const double time = world.time();
  // Every table's row first, then checked, then written: a step's rows are written whole.
  std::vector<std::pair<CsvTable*, std::vector<Cell>>> rows;
  rows.emplace_back(
      &energy_,
      EnergyRow{time, now.kinetic, now.potential, now.contacts, now.overlap, stage}.cells());
  WallsRow walls{time, {}};
  LoadsRow loads{time, world.steps(), stage, {}, reading};
  for (std::size_t i = 0; i < world.walls().size(); ++i) {
    const physics::Wall& w = world.walls()[i];
    walls.reaction_N.push_back(w.reaction);
    loads.walls.push_back(read_wall(w, origin0_[i]));
  }
  rows.emplace_back(&walls_, walls.cells());
  rows.emplace_back(&loads_, loads.cells());
  if (!world.bonds().empty())
    rows.emplace_back(&bond_counts_, BondCountsRow{time, stage, world.bond_counts()}.cells());
  if (writes_cracks()) rows.emplace_back(&cracks_, CracksRow{time, stage, cracks}.cells());
  if (scenario_.thermal.enabled) {
    double sum = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    std::size_t bodies = 0;
    for (const physics::BodyId id : world.body_ids()) {
      const double t = world.temperature(id);
      sum += t;
      lo = std::min(lo, t);
      hi = std::max(hi, t);
      ++bodies;
    }
    const physics::BondCounts c = world.bond_counts();
    rows.emplace_back(&thermal_,
                      ThermalRow{time, stage, bodies == 0 ? 0.0 : sum / static_cast<double>(bodies),
                                 lo, hi, c.intact, c.broken(), cracks.transgranular}
                          .cells());
  }
  if (const physics::PeriodicCell* cell = world.cell()) {
    // The cell's size, its strain from the start, and the mean stress in it.
    CellRow row{time, stage, cell->vectors().colwise().norm().transpose(), {}, world.cell_stress()};
    row.strain = row.length_m.cwiseQuotient(cell0_) - Eigen::Vector3d::Ones();
    rows.emplace_back(&cell_, row.cells());
  }
  std::optional<std::string> bad;
  for (const auto& [table, cells] : rows) {
    if (!bad) bad = table->non_finite(cells);
  }
  if (physics::Domain* domain = world.domain(); domain && domain->any(bad.has_value()))
    bad = domain->first(bad);
  if (bad)
    return *bad +
           " is not finite (NaN or infinite) in the history row of this step, which is not written";
  for (const auto& [table, cells] : rows) table->add(cells);
  return std::nullopt;
}

void RunHistory::add_splits(const physics::World& world, const std::string& stage,
                            const std::vector<physics::TransgranularEvent>& events) {
  for (const auto& e : events) {
    std::string pieces;
    for (const auto& l : e.split.pieces) pieces += (pieces.empty() ? "" : " ") + l.path_string();
    const auto& r = e.cause.result;
    splits_.add(SplitRow{e.split.time, world.steps(), stage, e.split.parent.grain_id,
                         e.split.parent.path_string(), pieces, e.split.plane, e.split.normal,
                         e.split.point, r.mean_stress, e.cause.stresses.sigma, e.cause.stresses.tau,
                         r.k_i, r.k_ii, r.criterion, e.split.section_area}
                    .cells());
  }
}

/// The stage's uniaxial strain test of the periodic cell: the slopes of the normal
/// stresses against the strain along the stretched axis (least squares over the last 70 %
/// of the stage's rows of cell.csv, as written), read for an isotropic solid. The lateral
/// axes that are periodic are held (uniaxial strain), the others free:
///   both held: nu = s_l / (s_a + s_l), E = s_a - 2 nu s_l (s_l: the lateral slopes' mean);
///   one held:  nu = s_l / s_a, E = s_a (1 - nu^2) (plane stress);
///   none:      E = s_a (uniaxial stress; nu not measured).
std::string RunHistory::measure_modulus(const physics::World& world, const io::StageDef& stage,
                                        std::size_t splits) {
  int axis = 0;
  for (int k = 0; k < 3; ++k) {
    if (stage.cell_strain_rate[k] != 0.0) axis = k;
  }
  // The stage's rows, the first 30 % left out (the cell's stress catching up with its strain).
  auto rows = cell_.rows(stage.name);
  rows.erase(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(rows.size() * 3 / 10));
  double n = 0, se = 0, see = 0;
  Eigen::Vector3d ss = Eigen::Vector3d::Zero(), ses = Eigen::Vector3d::Zero();
  for (const auto& row : rows) {
    const double e = std::stod(row.at(5 + static_cast<std::size_t>(axis)));
    n += 1;
    se += e;
    see += e * e;
    for (int k = 0; k < 3; ++k) {
      const double sigma = std::stod(row.at(8 + static_cast<std::size_t>(k)));
      ss[k] += sigma;
      ses[k] += e * sigma;
    }
  }
  const double var = see - se * se / n;
  if (rows.size() < 2 || !(var > 0.0)) return "modulus not measured (the cell did not stretch)";
  const Eigen::Vector3d slope = (ses - ss * se / n) / var;
  std::vector<double> lateral;
  for (int k = 0; k < 3; ++k) {
    if (k != axis && world.cell()->periodic(k)) lateral.push_back(slope[k]);
  }
  double young = slope[axis], nu = std::numeric_limits<double>::quiet_NaN();
  if (lateral.size() == 2) {
    const double sl = 0.5 * (lateral[0] + lateral[1]);
    nu = sl / (slope[axis] + sl);
    young = slope[axis] - 2.0 * nu * sl;
  } else if (lateral.size() == 1) {
    nu = lateral[0] / slope[axis];
    young = slope[axis] * (1.0 - nu * nu);
  }
  double mean_k = std::numeric_limits<double>::quiet_NaN();
  if (scenario_.thermal.enabled) {
    const auto ids = world.body_ids();
    mean_k = 0.0;
    for (const physics::BodyId id : ids)
      mean_k += world.temperature(id) / static_cast<double>(ids.size());
  }
  const double strain = std::stod(rows.back().at(5 + static_cast<std::size_t>(axis)));
  auto finite = [](double v) { return std::isfinite(v) ? std::optional(v) : std::nullopt; };
  modulus_.add(ModulusRow{stage.name, world.time(), finite(mean_k), "xyz"[axis], strain, young,
                          finite(nu), world.bond_counts().broken(), splits}
                   .cells());
  std::string line = fmt::format("E = {:.4g} GPa", young * 1e-9);
  if (std::isfinite(nu)) line += fmt::format(", nu = {:.3f}", nu);
  if (std::isfinite(mean_k)) line += fmt::format(" at {:.0f} K", mean_k);
  return line;
}

/// modulus.svg: the measured Young's moduli against temperature (or against the stage
/// order when there is no [thermal]).
void RunHistory::write_modulus_plot() const {
  io::Plot plot;
  plot.title = fmt::format("{}: Young's modulus of the periodic cell", scenario_.name);
  const bool thermal = scenario_.thermal.enabled;
  plot.x_label = thermal ? "mean temperature (K)" : "modulus stage";
  plot.y_label = "Young's modulus E (GPa)";
  io::PlotSeries series;
  series.label = "E from the cell's uniaxial strain test";
  series.markers = true;
  int k = 0;
  for (const auto& row : modulus_.rows()) {
    series.x.push_back(thermal && !row.at(2).empty() ? std::stod(row.at(2)) : ++k);
    series.y.push_back(std::stod(row.at(5)) * 1e-9);
  }
  plot.series.push_back(std::move(series));
  io::write_plot_svg(out_ / "modulus.svg", plot);
}

/// microcracks.svg: broken bonds (intergranular) and grain splits (transgranular)
/// against the mean temperature, from thermal.csv.
void RunHistory::write_microcrack_plot(bool fracture) const {
  io::Plot plot;
  plot.title = fmt::format("{}: microcracks against temperature", scenario_.name);
  plot.x_label = "mean temperature (K)";
  plot.y_label = "cracks";
  io::PlotSeries bonds, splits;
  bonds.label = "broken bonds (intergranular)";
  splits.label = "grain splits (transgranular)";
  for (const auto& row : thermal_.rows()) {
    const double t = std::stod(row.at(2));
    bonds.x.push_back(t);
    bonds.y.push_back(std::stod(row.at(6)));
    splits.x.push_back(t);
    splits.y.push_back(std::stod(row.at(7)));
  }
  plot.series.push_back(std::move(bonds));
  if (fracture) plot.series.push_back(std::move(splits));
  io::write_plot_svg(out_ / "microcracks.svg", plot);
}

void RunHistory::write_stage_plot(const io::StageDef& stage, const std::string& file,
                                  double peak_load, double peak_displacement,
                                  const std::vector<double>& x,
                                  const std::vector<double>& y) const {
  io::Plot plot;
  plot.title = fmt::format("{}: stage '{}'", scenario_.name, stage.name);
  plot.x_label = "load-point displacement (mm)";
  plot.y_label = "load P (N)";
  io::PlotSeries series;
  series.label = fmt::format("load on {}", fmt::join(stage.load_walls, ", "));
  for (double v : x) series.x.push_back(v * 1e3);
  series.y = y;
  plot.series.push_back(std::move(series));
  if (peak_load > 0.0) {
    plot.markers.push_back(
        {peak_displacement * 1e3, peak_load, fmt::format("peak {:.4g} N", peak_load)});
  }
  io::write_plot_svg(out_ / file, plot);
}

void RunHistory::write(const physics::World& world, bool fracture, const std::string& stage) const {
  io::write_file_atomically(out_ / "energy.csv", energy_.text());
  io::write_file_atomically(out_ / "walls.csv", walls_.text());
  io::write_file_atomically(out_ / "load_displacement.csv", loads_.text());
  if (fracture) io::write_file_atomically(out_ / "splits.csv", splits_.text());
  if (writes_cracks()) io::write_file_atomically(out_ / "cracks.csv", cracks_.text());
  if (scenario_.thermal.enabled) io::write_file_atomically(out_ / "thermal.csv", thermal_.text());
  if (!cell_.text().empty()) io::write_file_atomically(out_ / "cell.csv", cell_.text());
  if (modulus_.has_rows()) {
    io::write_file_atomically(out_ / "modulus.csv", modulus_.text());
    write_modulus_plot();
  }
  if (scenario_.thermal.enabled && !world.bonds().empty()) write_microcrack_plot(fracture);
  if (!scenario_.bond.enabled) return;
  io::write_file_atomically(out_ / "bonds.csv", bond_counts_.text());
  CsvTable breaks("bond_breaks.csv", BondBreakRow::columns());
  const auto& all = world.bond_breaks();
  std::size_t k_stage = 0;
  for (std::size_t k = 0; k < all.size(); ++k) {
    while (k_stage < breaks_by_stage_.size() && k >= breaks_by_stage_[k_stage].first) ++k_stage;
    const std::string& name =
        k_stage < breaks_by_stage_.size() ? breaks_by_stage_[k_stage].second : stage;
    breaks.add(BondBreakRow{&all[k], name}.cells());
  }
  io::write_file_atomically(out_ / "bond_breaks.csv", breaks.text());
}

void RunHistory::put_start(physics::StateWriter& w) const {
  w.put(origin0_);
  w.put(pe0_);
}

void RunHistory::get_start(physics::StateReader& r) {
  origin0_ = r.vec3s();
  pe0_ = r.get<double>();
}

void RunHistory::put_tables(physics::StateWriter& w) const {
  for (const CsvTable* t : tables()) w.put(t->text());
  w.put(cell0_);
  w.count(breaks_by_stage_.size());
  for (const auto& [end, name] : breaks_by_stage_) {
    w.put<std::uint64_t>(end);
    w.put(name);
  }
}

void RunHistory::get_tables(physics::StateReader& r) {
  for (CsvTable* t : tables()) t->restore(r.string());
  cell0_ = r.vec3();
  breaks_by_stage_.resize(r.count(16));
  for (auto& [end, name] : breaks_by_stage_) {
    end = r.get<std::uint64_t>();
    name = r.string();
  }
}

}  // namespace cleave::sim
