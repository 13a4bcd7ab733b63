#pragma once
/// \file
/// A dynamic run of a specimen, the time loop of `cleave run` as a library: the grains become bodies of a physics::World and move
/// under gravity, walls and bonds. A run is a plain one ([dynamics] duration, stopping when
/// the grains settle) or staged ([[stage]] tables, sec. 2.5.2: compaction, bond
/// initialisation, loading). It writes ParaView frames and the histories users plot.

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geometry/specimen.hpp"
#include "io/fragment_sizes.hpp"
#include "io/scenario.hpp"
#include "physics/dem/world.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "sim/crack_tally.hpp"
#include "sim/world_assembly.hpp"

namespace cleave::sim {

/// How one stage went.
struct StageSummary {
  std::string name;
  io::StageDef::Kind kind = io::StageDef::Kind::motion;
  std::uint64_t steps = 0;     ///< steps taken in the stage
  double start = 0.0, end = 0.0;  ///< simulated time, s
  /// "limit" (ran its length), the event that ended it, or "bonded" (a bond stage).
  std::string ended_by;
  bool event_missed = false;   ///< it waited for an event that did not come within its limit
  double peak_load = 0.0;      ///< largest load on its load walls, N
  double peak_displacement = 0.0;  ///< load-point displacement at that peak, m
  std::size_t bonds_broken = 0;
  std::size_t splits = 0;      ///< grains or fragments split (transgranular cracks)
  std::string plot;            ///< load-displacement picture written for it (file name)
  /// The run's cracks so far (CrackTally) when the stage began, when it ended and at its
  /// peak load (when it has one); `cracks_end.since(cracks_start)` opened in the stage.
  CrackTotals cracks_start, cracks_end, cracks_at_peak;
};

/// What a testing machine reads off the loading walls. Walls whose load axes agree are one
/// crosshead (four-point bending: both loading rollers); the load is the force on a
/// crosshead, averaged over the crossheads (Brazilian, compression: each platen carries the
/// load P, not 2P), and the load-point displacement is the sum over the crossheads of their
/// mean travel from `origins` (indexed by wall; two platens closing in: the closure).
struct MachineReading {
  double load = 0.0;          ///< N
  double displacement = 0.0;  ///< m
};
MachineReading machine_reading(const physics::World& world, const std::vector<std::size_t>& load_walls,
                               const std::vector<Eigen::Vector3d>& origins);

/// How a dynamic run ended.
enum class RunEnding {
  completed,    ///< every stage ran to its end
  interrupted,  ///< RunHooks::stop_requested said stop (SIGINT/SIGTERM)
  /// The step guard found a non-finite state (body, wall, cell) or a body moving too far, or
  /// a history row or frame would have held a value that is not finite (not written).
  blew_up,
  /// `max_steps` ran out before the stages ended: the stage it fell in says ended_by
  /// "max_steps"; the stages after it did not run.
  stopped,
};

/// Where a run is, for the hooks: the world and the stage it is in.
struct RunPoint {
  const physics::World& world;
  const std::string& stage;     ///< its name
  std::size_t stage_index;      ///< in scenario.stages (0 for a plain run)
  std::uint64_t stage_steps;    ///< steps taken in the stage so far
  /// The book of transgranular fracture (null without [fracture]).
  const physics::FractureBook* book = nullptr;
  /// The run loop's own state at this point (stage progress, the histories written so far,
  /// frame series), encoded for a checkpoint (io/checkpoint.hpp); RunResume takes it back.
  std::function<std::string()> run_state;
};

/// What a run restarted from a checkpoint continues from (io::read_checkpoint gives it).
struct RunResume {
  physics::World world;
  std::optional<physics::FractureBook> book;
  std::string run_state;  ///< RunPoint::run_state() at the checkpoint
  /// The stable step of the scenario (check_time_step), for what a blow-up says; 0: not
  /// compared.
  double stable_dt = 0.0;
};

/// What the caller of a Dynamics plugs into its step loop. Every member may be empty.
struct RunHooks {
  /// Polled after every step; true stops the run cleanly after that step (its outputs
  /// are written and the summary says interrupted). `cleave run` asks run_control.hpp.
  std::function<bool()> stop_requested;
  /// Called once when stop_requested stopped the run, before the outputs are written (and
  /// before the extra history row of the interrupted step): `cleave run` writes the
  /// checkpoint a restart continues from.
  std::function<void(const RunPoint&)> on_interrupt;
  /// Called every `checkpoint_every` steps (0: never; counted in World::steps), after the
  /// step, its fracture check, its history row and frame: `cleave run` writes a checkpoint.
  std::function<void(const RunPoint&)> on_checkpoint;
  std::uint64_t checkpoint_every = 0;
  /// The step guard's limit on a body's movement in one step, as a fraction of its
  /// bounding radius (physics/dem/step_guard.hpp).
  double max_move_fraction = 0.1;
  /// One process of a domain decomposition (`mpirun -np N cleave run`; parallel::MpiDomain):
  /// the run attaches the world to it and reads the whole world's energies, contacts and
  /// events through it. Null: the whole world in this process.
  physics::Domain* domain = nullptr;
  /// Clock the parts of every step (World::set_timing) and the transgranular check: the run
  /// writes timing.csv and the summary carries its table (`cleave run --timing`).
  bool timing = false;
};

struct DynamicsSummary {
  RunEnding ending = RunEnding::completed;
  /// With blew_up: the message (step, body or wall, suggested dt; physics::describe), or the
  /// step and the item whose value was not finite.
  std::string failure;
  std::uint64_t steps = 0;
  double time = 0.0;
  double kinetic_energy = 0.0;
  double released_energy = 0.0;    ///< potential energy released since the start
  double max_overlap = 0.0;        ///< largest contact overlap seen, m
  double lowest_point = 0.0;       ///< lowest body vertex at the end (world z), m
  bool settled = false;            ///< KE fell below settle_ratio x released energy
  int frames = 0;
  double wall_seconds = 0.0;
  /// RunHooks::timing: where the steps' time went, one line a part (as timing.csv).
  std::string timing;
  std::vector<StageSummary> stages;  ///< one per [[stage]] (empty for a plain run)
  std::size_t bonds = 0;             ///< bonds made at bond initialisation
  physics::BondCounts bond_counts;
  double peak_load = 0.0;            ///< largest load of any stage, N
  std::size_t splits = 0;            ///< transgranular cracks (grain splits)
  CrackTotals cracks;                ///< the crack areas and counts at the end
  /// The cracks at the peak load (peak_load's stage's cracks_at_peak); none without a peak.
  std::optional<CrackTotals> cracks_at_peak;
  /// With [fracture]: every live piece at the end (exact shape in its grain's frame,
  /// placed at the grain's lattice centre), for geometry.exact and the volume check.
  std::vector<geometry::Piece> final_pieces;
  /// The fragments at the end: clusters of the bodies joined by intact bonds
  /// (sim/fragments.hpp), each with its bodies, exact volume (rounded) and mass.
  std::vector<io::FragmentRecord> fragments;
  /// The fragments' exact volumes sum exactly to the specimen's grains' (no body was lost).
  bool fragment_volume_exact = false;
  /// Disc specimens: the Brazilian tensile strength 2P/(pi D t) of the peak load (sec. 2.5.4).
  std::optional<double> brazilian_strength;
  /// physics::World::state_hash of the final state: a run restarted from a checkpoint ends
  /// with the same hash as the run done without interruption.
  std::uint64_t state_hash = 0;
};

/// A dynamic run under way: [dynamics] (and its [[stage]]s) of a scenario on its specimen,
/// writing into a result folder: frames/ (bodies_*.vtp, contacts_*.vtp, bonds_*.vtp),
/// bodies.pvd, contacts.pvd, bonds.pvd, energy.csv, walls.csv, load_displacement.csv,
/// bonds.csv, bond_breaks.csv, splits.csv and a load-displacement picture (SVG) per loading
/// stage. It moves on in steps (advance) or stage by stage (advance_stage), in any mix: the
/// steps, and so the outputs and the final state hash, are the same however it is driven.
/// `max_steps` > 0 caps the total number of steps. A run stopped by `hooks.stop_requested`
/// or by the step guard (a blow-up) still writes its frames and tables up to where it
/// stopped; the summary's `ending` says which.
///
/// With `resume` (moved from), the run continues from a checkpoint of the same scenario
/// and specimen instead of starting: the world, the fracture book and the loop's state
/// are those saved, and the outputs of `out` continue where the checkpoint left them.
///
/// Without `resume`, the run starts from `assembled` (moved from) when given: the world
/// assemble_world made of the same scenario and specimen; otherwise it assembles its own.
///
/// The scenario and the specimen must outlive the run.
class Dynamics {
 public:
  Dynamics(const io::Scenario& scenario, const geometry::Specimen& specimen,
           const std::filesystem::path& out, bool quiet, std::uint64_t max_steps = 0,
           const RunHooks& hooks = {}, RunResume* resume = nullptr,
           AssembledWorld* assembled = nullptr);
  ~Dynamics();
  Dynamics(const Dynamics&) = delete;
  Dynamics& operator=(const Dynamics&) = delete;

  /// Takes up to `steps` steps, going from stage to stage as their events come; returns
  /// how many it took (fewer once the run is done: every stage ran, or it stopped).
  std::uint64_t advance(std::uint64_t steps);
  /// Runs the stage under way (or the next one) to its end: its event, its limit, a stop
  /// or a blow-up. Returns its summary; nullopt when the run was already done.
  std::optional<StageSummary> advance_stage();
  /// Every stage ran, or the run stopped (interrupted, blew up, max_steps).
  [[nodiscard]] bool done() const;
  /// Runs what is left, writes the last frame and the tables, and returns the summary.
  /// Once finished, the run takes no more steps.
  DynamicsSummary finish();
  [[nodiscard]] bool finished() const;

  [[nodiscard]] const physics::World& world() const;
  /// The world to change between steps (a wall's velocity or place). A new stage sets the
  /// walls' velocities as its table says.
  [[nodiscard]] physics::World& world();
  /// The book of transgranular fracture (null without [fracture]).
  [[nodiscard]] const physics::FractureBook* book() const;
  /// The name of the stage under way (or the last one), "run" for a plain run.
  [[nodiscard]] const std::string& stage() const;
  /// The stages ended so far, and the run's totals so far.
  [[nodiscard]] const DynamicsSummary& summary() const;

 private:
  class Runner;
  std::unique_ptr<Runner> runner_;
};

/// The whole run at once: Dynamics(...).finish(). The caller checks the time step first
/// (sim::check_time_step).
DynamicsSummary run_dynamics(const io::Scenario& scenario, const geometry::Specimen& specimen,
                             const std::filesystem::path& out, bool quiet,
                             std::uint64_t max_steps = 0, const RunHooks& hooks = {},
                             RunResume* resume = nullptr);

}  // namespace cleave::sim
