#pragma once
/// \file
/// One `cleave run` as an object: scenario -> specimen -> cleavage slabs -> (dynamics) ->
/// result folder. The CLI (app/main.cpp) and the Python module (python/) both drive it:
///
///   auto sim = sim::Simulation::open("scenarios/brazilian.toml", options);
///   sim->start();                        // specimen, slabs, meshes, tables
///   while (!sim->done()) sim->advance(100);
///   const sim::RunReport report = sim->finish();  // last frame, tables, run.toml
///
/// The steps, the files and the final state hash are the same however the run is driven
/// (run() at once, advance() in chunks of any size, advance_stage()).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geometry/specimen.hpp"
#include "io/scenario.hpp"
#include "sim/dynamics.hpp"

namespace cleave::sim {

/// The cleave version (git describe at build time).
const char* version();

struct SimulationOptions {
  /// The result folder; empty: results/<scenario name> (a restart: the checkpoint's folder).
  std::filesystem::path out;
  bool quiet = false;           ///< no progress lines on stdout/stderr
  std::uint64_t max_steps = 0;  ///< stop the dynamics after this many steps (0: no limit)
  /// Overrides [output] checkpoint_every (a checkpoint every N steps; 0: only on a stop).
  std::optional<std::uint64_t> checkpoint_every;
  std::optional<std::string> mesh_format;  ///< overrides [output] mesh_format
  std::optional<std::string> mesh_layout;  ///< overrides [output] mesh_layout
  /// Polled between the phases and after every step: true stops the run cleanly (what is
  /// written stays, run.toml says interrupted, a checkpoint is written).
  std::function<bool()> stop_requested;
  /// Why it stopped, for run.toml ("stopped by SIGINT").
  std::function<std::string()> stop_reason;
  /// One process of several (RunHooks::domain); the caller keeps it alive.
  physics::Domain* domain = nullptr;
  /// Clock the parts of every step: timing.csv in the result folder, its table in the
  /// summary (RunHooks::timing).
  bool timing = false;
  /// How overrides are named in errors: "--set" gives "--set dynamics.dt=abc: key ...".
  std::string override_label = "--set";
  /// --replace: `out` may hold an earlier result of another scenario, an interrupted run
  /// with a checkpoint or a killed run; it is replaced (io::check_result_folder).
  bool replace = false;
};

/// How a run ended.
struct RunReport {
  /// stopped: `max_steps` ran out before the stages ended (run.toml: io::run_status::stopped).
  enum class Status { finished, interrupted, failed, stopped };
  Status status = Status::finished;
  /// interrupted: the reason; failed: what went wrong (a blow-up, a value that is not
  /// finite); stopped: the step and the stage it stopped in.
  std::string message;
  std::filesystem::path out;
  std::optional<DynamicsSummary> dynamics;  ///< with [dynamics]
};

class Simulation {
 public:
  /// A scenario file, with `overrides` ("table.key=value", as `cleave sweep --set` takes
  /// them, one value each) applied and recorded in run.toml's provenance. Throws
  /// io::ScenarioError (file:line:col: key '...': message; at a key an override sets,
  /// "--set KEY=VALUE: key '...': message") or io::SweepError (a malformed override), and
  /// std::invalid_argument when the result folder is not one it may write
  /// (io::check_result_folder; nothing is written or removed then).
  static std::unique_ptr<Simulation> open(const std::filesystem::path& scenario,
                                          SimulationOptions options,
                                          const std::vector<std::string>& overrides = {});
  /// Scenario text in memory; `source` names it in errors and in run.toml; relative mesh
  /// paths are taken from `base_dir`.
  static std::unique_ptr<Simulation> from_text(std::string text, std::string source,
                                               SimulationOptions options,
                                               const std::vector<std::string>& overrides = {},
                                               const std::filesystem::path& base_dir = ".");
  /// A run continued from its checkpoint (a file, or a result folder holding one); the
  /// scenario is the one saved in it. Throws io::CheckpointError or io::ScenarioError.
  static std::unique_ptr<Simulation> restart(const std::filesystem::path& checkpoint,
                                             SimulationOptions options);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  [[nodiscard]] const io::Scenario& scenario() const;
  [[nodiscard]] const std::filesystem::path& out() const;

  /// Removes the earlier run's files that open() found in the folder (io::check_result_folder:
  /// only what its manifest lists, and unfinished writes), writes run.toml ("running") and
  /// the scenario, builds the specimen, cuts every grain into its cleavage slabs and writes
  /// the meshes and tables; then makes the dynamics (with [dynamics]). Throws
  /// io::ScenarioError when the time step is above the stable limit and std::exception on
  /// other failures, with run.toml closed as failed. A stop asked for between its phases
  /// ends the run (done(), finish() says interrupted).
  void start();
  [[nodiscard]] bool started() const;

  /// Takes up to `steps` dynamic steps (start() first if needed); returns how many.
  std::uint64_t advance(std::uint64_t steps);
  /// Runs the stage under way to its end (see Dynamics::advance_stage).
  std::optional<StageSummary> advance_stage();
  /// Nothing is left to run (or the run stopped).
  [[nodiscard]] bool done() const;
  /// Runs what is left and writes the final outputs and run.toml. Throws std::exception
  /// on a failure other than a blow-up (run.toml closed as failed).
  RunReport finish();
  [[nodiscard]] bool finished() const;
  /// start() and finish().
  RunReport run();

  /// After start(): the specimen and the slabs cut at the start.
  [[nodiscard]] const geometry::Specimen& specimen() const;
  [[nodiscard]] const std::vector<geometry::Piece>& slabs() const;
  /// The dynamics (null without [dynamics], or before start()).
  [[nodiscard]] Dynamics* dynamics();
  [[nodiscard]] const Dynamics* dynamics() const;

 private:
  struct State;
  explicit Simulation(std::unique_ptr<State> state);
  std::unique_ptr<State> s_;
};

/// The text of specimen.csv and fragments.csv (also what the Python module returns);
/// `phases`: the [[phase]] names, for a last column `phase` (none when empty).
std::string specimen_csv(const geometry::Specimen& s, const std::vector<std::string>& phases = {});
std::string fragments_csv(const std::vector<geometry::Piece>& pieces);

}  // namespace cleave::sim
