#pragma once
/// \file
/// The `cleave` sub-commands. Each returns the process exit code.

#include <filesystem>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace cleave::app {

struct RunOptions {
  std::filesystem::path scenario;
  std::filesystem::path out;               ///< empty: results/<scenario name>
  std::optional<std::string> mesh_format;  ///< overrides [output] mesh_format
  std::optional<std::string> mesh_layout;  ///< overrides [output] mesh_layout
  std::vector<std::string> sets;           ///< KEY=VALUE overrides, one per --set
  bool quiet = false;
  std::uint64_t max_steps = 0;  ///< stop a [dynamics] run after this many steps (0: no limit)
  /// Continue from this checkpoint (a file, or a result folder holding `checkpoint`)
  /// instead of starting: the scenario is the one saved in it, `out` defaults to its folder,
  /// and `max_steps` 0 keeps the checkpointed run's limit.
  std::filesystem::path restart;
  /// Overrides [output] checkpoint_every (a checkpoint every N steps; 0: only on a signal).
  std::optional<std::uint64_t> checkpoint_every;
  /// Processes mpirun started (0: not started by mpirun). From 1 up the run steps as one
  /// process of a domain decomposition (parallel::MpiDomain), which gives one answer for any
  /// number of processes.
  int mpi_size = 0;
  bool timing = false;  ///< --timing: timing.csv, where each step's time goes
  bool replace = false;  ///< --replace: see sim::SimulationOptions::replace
  std::string max_memory;  ///< --max-memory as given (empty: the memory available now)
};

/// Builds the specimen, splits every grain into its cleavage slabs and writes the result
/// folder (meshes, tables, exact geometry, manifest).
int run_command(const RunOptions& options);

struct CheckVolumeOptions {
  std::filesystem::path dir;
  bool voxel = false;
  double voxels_per_length = 15.0;
  double voxel_tolerance = 0.05;
  bool summary_only = false;
};

/// Exact volume conservation per grain (and, with --voxel, each mesh through OpenVDB).
/// Exit 0 when every grain's fragments sum exactly to its volume, 1 otherwise.
int check_volume_command(const CheckVolumeOptions& options);

struct ValidateOptions {
  std::filesystem::path scenario;
  std::filesystem::path out;  ///< empty: results/<scenario name>
  bool quiet = false;
  /// Solve the beam theory with the cohesive zone only and judge it, as the measured curve,
  /// against the closed forms with the scenario's bounds: where LEFM holds for a sigma_c,
  /// in seconds, before a lattice run of hours. The lattice is not run.
  bool cohesive_beam_only = false;
  bool replace = false;  ///< --replace: an earlier result of another run in `out` is replaced
  std::string max_memory;  ///< --max-memory as given (empty: the memory available now)
};

/// Runs a validation scenario (DCB, ENF or MMB on the cubic lattice, seed 002 sec. 7) and
/// writes measured and closed-form load-deflection curves, the errors per stage and a plot.
/// Exit 0 when every checked stage (and the peak) is within its tolerance, 1 when one is not,
/// 2 on bad input or a failed run.
int validate_command(const ValidateOptions& options);

struct SweepOptions {
  std::string command = "run";  ///< what each run is: run | measure | validate
  std::string test;             ///< --command measure: elastic | brazilian | flexural | senb
  std::filesystem::path scenario;
  std::vector<std::string> sets;  ///< KEY=VALUES, one per --set: a product
  std::vector<std::string> zips;  ///< KEY=VALUES, one per --zip: varied together
  int jobs = 1;                   ///< runs at a time
  std::filesystem::path out;      ///< empty: results/<scenario name>_sweep
  std::uint64_t max_steps = 0;    ///< passed to each run (0: none)
  bool quiet = false;
  bool replace = false;  ///< --replace: an earlier result of another run in `out` is replaced
  /// --max-memory as given (empty: none); each run gets the limit shared by `jobs` runs.
  std::string max_memory;
  /// Replicates: each combination run with `seed_key` = 1..seeds (0: none), the last and
  /// fastest-varying factor; summary_mean.csv gives their mean and spread.
  int seeds = 0;
  std::string seed_key;              ///< empty: orientation.seed
  bool cohesive_beam_only = false;   ///< --command validate: passed to each validate
  std::vector<std::string> columns;  ///< more summary.csv columns: keys of run.toml's facts
};

/// Runs the scenario once per combination of the --set values (io/sweep.hpp; the --zip
/// values together, one factor of the product; the --seeds last), `jobs` at a time as child
/// `cleave run`s (or `measure`, `validate`), and writes summary.csv (one row per run: the
/// values, status, the command's results, time), with --seeds summary_mean.csv, a plot, and
/// for a seed ensemble the Weibull fit (weibull.csv, weibull.svg). Exit 0 when every run
/// finished (or stopped by --max-steps, as asked: status stopped, left out of the fits; a
/// validation's fail verdict is a result, not a failure), 1 when one did not, 2 on bad input
/// (nothing is run), 130/143 when interrupted.
int sweep_command(const SweepOptions& options);

struct MaterialsOptions {
  std::string name;  ///< empty: list the library; else show this preset
};

/// Lists the material library (materials/*.toml) or shows one preset with its units and
/// sources. Exit 0, or 2 when the library or the preset cannot be read.
int materials_command(const MaterialsOptions& options);

struct MeasureOptions {
  std::string test;                ///< elastic | brazilian | flexural | senb
  std::filesystem::path scenario;
  std::vector<std::string> sets;   ///< KEY=VALUE overrides
  std::filesystem::path out;       ///< empty: results/<scenario name>
  bool quiet = false;
  /// --converge: the loading-rate study (sim::converge_loading_rate) instead of one run.
  bool converge = false;
  double tolerance = 0.02;
  int max_runs = 5;
};

/// Runs a test scenario and measures a macroscopic property (sim/measure.hpp): prints it
/// with its formula and writes DIR/measure.toml. Exit 0 when measured, 1 when the run or
/// the test failed (no load drop, not such a rig), 2 on bad input.
int measure_command(const MeasureOptions& options);

struct CalibrateOptions {
  std::filesystem::path file;        ///< the calibration file (io/calibration_file.hpp)
  std::vector<std::string> targets;  ///< KEY=VALUE: E, nu, sigma_t (SI)
  std::optional<double> tolerance;   ///< overrides the file's
  std::filesystem::path out;         ///< empty: results/<file stem>
  bool quiet = false;
};

/// Calibrates bond parameters to E, nu and sigma_t (sim/calibrate.hpp). Exit 0 when every
/// target is met within the tolerance, 1 when not (or a trial failed), 2 on bad input.
int calibrate_command(const CalibrateOptions& options);

}  // namespace cleave::app
