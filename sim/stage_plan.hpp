#pragma once
/// \file
/// The stages of a run and where the one under way is: each stage's step limit (its steps,
/// or its time over the World's dt, cut by --max-steps), how often it logs and writes frames,
/// the event that may end it early (until: settled, all in contact, walls touch, load drop),
/// the progress line, and what a checkpoint saves of a stage.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "io/scenario.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"
#include "sim/boundary_conditions.hpp"
#include "sim/dynamics.hpp"

namespace cleave::sim {

/// Where the loop of one stage is: what a checkpoint saves of it besides the world.
struct StageProgress {
  StageSummary st;
  std::size_t breaks0 = 0;                    ///< bond breaks before the stage
  std::vector<Eigen::Vector3d> stage_origin;  ///< wall origins at the stage's start
  std::vector<double> plot_x, plot_y;         ///< its load-displacement picture so far
  bool event = false;                         ///< its ending event has come
};

void put_summary(physics::StateWriter& w, const StageSummary& st);
StageSummary get_summary(physics::StateReader& r);
void put_progress(physics::StateWriter& w, const StageProgress& p);
StageProgress get_progress(physics::StateReader& r);

/// The one stage of a plain run: as long as the duration (over the World's dt), its walls
/// at the velocities they start with.
io::StageDef plain_stage(const io::Scenario& scenario, const physics::World& world);

/// A motion stage under way: what its loop keeps from step to step.
struct StageRun {
  const io::StageDef* stage = nullptr;
  bool plain = false;
  StageProgress progress;
  std::vector<std::size_t> load_walls;
  std::uint64_t limit = 0, frame_every = 0, log_every = 1;
  std::uint64_t i = 1;  ///< the stage's next step, counted from 1
  std::chrono::steady_clock::time_point t0, last_print;
  bool halt = false;    ///< interrupted or blew up: the run ends after this step
  bool capped = false;  ///< --max-steps cut its limit: the run ends if it reaches it
  std::optional<StageConditions> conditions;  ///< registered on the World while it runs

  /// Sets the limit, log and frame intervals from the stage, the World's dt and
  /// `max_steps` (0: none), and the next step from the progress.
  void plan(const physics::World& world, std::uint64_t max_steps);
  [[nodiscard]] bool continues() const { return i <= limit && !progress.event && !halt; }
  /// Step i (just taken) is logged: at the log interval, the last, or the event's.
  [[nodiscard]] bool logs(std::uint64_t step) const {
    return step % log_every == 0 || step == limit || progress.event;
  }
  [[nodiscard]] bool frames(std::uint64_t step) const {
    return frame_every && step % frame_every == 0;
  }
};

/// What the until-criteria read after a step, for the whole world.
struct StageReadings {
  double load = 0.0;       ///< the machine's load on the stage's load walls, N
  std::size_t broken = 0;  ///< bonds broken in the stage
  bool settled = false;    ///< a plain run's KE fell below settle_ratio x released energy
  bool all_in_contact = false;
};

/// Whether the stage's ending event came with this step.
bool stage_event(const StageRun& r, const physics::World& world, const StageReadings& now);

/// Every body touches another body (its dilated surface overlaps another's); on several
/// processes, every process's bodies. `touched` is scratch space.
bool all_in_contact(const physics::World& world, std::vector<char>& touched);

/// The progress line of step i: the stage, the step, the time and the counts, the ETA.
std::string progress_line(const StageRun& r, const physics::World& world, std::size_t contacts,
                          double kinetic, std::size_t splits, bool fracture, double load,
                          bool may_settle);

}  // namespace cleave::sim
