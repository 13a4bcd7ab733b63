#pragma once
/// \file
/// The histories of a dynamic run (run_tables.hpp) as the run fills them: a row of every
/// table at each logged step, the splits and bond breaks, the periodic cell's modulus tests,
/// and at the end the files and their pictures (load-displacement, modulus, microcracks).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/scenario.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"
#include "physics/transgranular/transgranular.hpp"
#include "sim/run_tables.hpp"

namespace cleave::sim {

/// What the whole world reads at a logged step (on several processes, summed over them).
struct WorldReadings {
  double kinetic = 0.0, potential = 0.0;
  std::size_t contacts = 0;
  double overlap = 0.0;  ///< the largest contact overlap, m
};

class RunHistory {
 public:
  /// The tables' headers from the world at the start (its walls, its cell); the scenario
  /// must outlive the history.
  RunHistory(const io::Scenario& scenario, const physics::World& world, std::filesystem::path out);

  /// One row of every history at the world's present step, `stage` the stage's name,
  /// `reading` its (load, load-point displacement) when it has load walls, `cracks` the
  /// cracks so far (CrackTally). A row holding a
  /// value that is not finite is not written (on several processes: on any of them):
  /// returns the sentence naming the first such column; nullopt when written.
  std::optional<std::string> record(const physics::World& world, const std::string& stage,
                                    const WorldReadings& now,
                                    std::optional<std::pair<double, double>> reading,
                                    const CrackTotals& cracks);
  /// splits.csv rows of a step's transgranular cracks.
  void add_splits(const physics::World& world, const std::string& stage,
                  const std::vector<physics::TransgranularEvent>& events);
  /// The bond breaks so far belong to `stage` (bond_breaks.csv names each break's stage).
  void end_stage(std::size_t breaks, const std::string& stage) {
    breaks_by_stage_.emplace_back(breaks, stage);
  }
  /// The stage's uniaxial strain test of the periodic cell from its rows of cell.csv: a row
  /// of modulus.csv, and a line for the log.
  std::string measure_modulus(const physics::World& world, const io::StageDef& stage,
                              std::size_t splits);
  /// load_displacement_<stage>.svg from the stage's points; `file` its name.
  void write_stage_plot(const io::StageDef& stage, const std::string& file, double peak_load,
                        double peak_displacement, const std::vector<double>& x,
                        const std::vector<double>& y) const;
  /// Every table and picture into the result folder; `stage`: the stage under way, for
  /// breaks after the last ended stage.
  void write(const physics::World& world, bool fracture, const std::string& stage) const;

  /// The walls' origins and the potential energy at the start of the run.
  [[nodiscard]] const std::vector<Eigen::Vector3d>& wall_origins() const { return origin0_; }
  [[nodiscard]] double start_potential() const { return pe0_; }

  /// Whether the run writes cracks.csv (it has bonds or [fracture]).
  [[nodiscard]] bool writes_cracks() const {
    return scenario_.bond.enabled || scenario_.fracture.enabled;
  }

  /// A checkpoint's run state, in its order: the start (origins, potential), the tables,
  /// then the cell's start and the stages' break counts.
  void put_start(physics::StateWriter& w) const;
  void get_start(physics::StateReader& r);
  void put_tables(physics::StateWriter& w) const;
  void get_tables(physics::StateReader& r);

 private:
  std::vector<CsvTable*> tables();
  std::vector<const CsvTable*> tables() const;
  void write_modulus_plot() const;
  void write_microcrack_plot(bool fracture) const;

  const io::Scenario& scenario_;
  std::filesystem::path out_;
  std::vector<Eigen::Vector3d> origin0_;
  double pe0_ = 0.0;
  Eigen::Vector3d cell0_ = Eigen::Vector3d::Ones();  // the cell's edge lengths at the start
  std::vector<std::pair<std::size_t, std::string>> breaks_by_stage_;  // (end index, stage)
  CsvTable energy_, walls_, loads_, bond_counts_, cracks_, splits_, thermal_, cell_, modulus_;
};

}  // namespace cleave::sim
