#include "sim/dynamics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>

#include "io/result_dir.hpp"
#include "physics/dem/world.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "physics/transgranular/transgranular.hpp"
#include "sim/boundary_conditions.hpp"
#include "sim/checkpoint_policy.hpp"
#include "sim/fragments.hpp"
#include "sim/frames.hpp"
#include "sim/phases.hpp"
#include "sim/run_history.hpp"
#include "sim/stage_plan.hpp"
#include "sim/step_checks.hpp"
#include "sim/world_assembly.hpp"

namespace cleave::sim {

namespace {

namespace fs = std::filesystem;
using io::StageDef;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double lowest_vertex(const physics::World& world) {
  double z = std::numeric_limits<double>::infinity();
  for (const physics::BodyId id : world.body_ids()) {
    const physics::BodyState& s = world.state(id);
    const auto& prim = world.shape(world.info(id).shape).primitives;
    for (const auto& v : prim.vertices) z = std::min(z, (s.x + s.q * v).z());
  }
  return z;
}

}  // namespace

MachineReading machine_reading(const physics::World& world, const std::vector<std::size_t>& load_walls,
                               const std::vector<Eigen::Vector3d>& origins) {
  std::vector<Eigen::Vector3d> axes;
  std::vector<double> force, travel;
  std::vector<int> members;
  for (std::size_t w : load_walls) {
    const physics::Wall& wall = world.walls()[w];
    const WallReading r = read_wall(wall, origins[w]);
    std::size_t k = 0;
    while (k < axes.size() && !(wall.load_axis.squaredNorm() > 0.0 && axes[k].dot(wall.load_axis) > 0.99)) ++k;
    if (k == axes.size()) {
      axes.push_back(wall.load_axis);
      force.push_back(0.0);
      travel.push_back(0.0);
      members.push_back(0);
    }
    force[k] += r.force;
    travel[k] += r.displacement;
    ++members[k];
  }
  MachineReading out;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    out.load += force[k] / static_cast<double>(axes.size());
    out.displacement += travel[k] / members[k];
  }
  return out;
}

/// One dynamic run, stage after stage, and everything it writes.
class Dynamics::Runner {
 public:
  /// `start`: the world the run begins with (assembled, or a checkpoint's).
  Runner(AssembledWorld start, const io::Scenario& scenario, const geometry::Specimen& specimen,
         fs::path out, bool quiet, std::uint64_t max_steps, const RunHooks& hooks,
         RunResume* resume)
      : scenario_(scenario),
        specimen_(specimen),
        out_(std::move(out)),
        quiet_(quiet),
        max_steps_(max_steps),
        hooks_(hooks),
        world_(std::move(start.world)),
        checks_(hooks.max_move_fraction, start.stable_dt, hooks_.stop_requested),
        history_(scenario, world_, out_),
        frames_(out_, scenario, specimen),
        checkpoints_(hooks_) {
    fs::create_directories(out_ / "frames");
    world_.add_listener(&checks_);
    if (resume) {
      // Everything else comes from the checkpoint (run()).
      if (scenario_.fracture.enabled != resume->book.has_value()) {
        throw std::runtime_error("the checkpoint does not match the scenario: [fracture] is " +
                                 std::string(scenario_.fracture.enabled ? "on" : "off") +
                                 " in the scenario but the checkpoint has " +
                                 (resume->book ? "a" : "no") + " fracture book");
      }
      book_ = std::move(resume->book);
      resume_state_ = std::move(resume->run_state);
      resuming_ = true;
    } else if (scenario_.fracture.enabled) {
      // Every grain may split along its cleavage planes (chapter 3): the book knows its
      // exact shape (world shape k is specimen shape k, sim::make_world) and orientation.
      book_.emplace(scenario_.contact.dilation_radius, scenario_.split.min_fragment_fraction);
      for (std::size_t k = 0; k < specimen_.shapes.size(); ++k) {
        book_->add_shape(static_cast<std::uint32_t>(k),
                         std::make_shared<const geometry::ExactPolyhedron>(specimen_.shapes[k]));
      }
      for (const physics::BodyId id : world_.body_ids()) {
        const int grain = world_.info(id).grain_id;
        const auto& g = specimen_.grains.at(static_cast<std::size_t>(grain));
        if (specimen_.def.crystal.enabled) {
          book_->add_grain(world_, id, grain, geometry::grain_cleavage_planes(specimen_, g).planes);
        } else {
          book_->add_grain(world_, id, grain, g.orientation);
        }
      }
    }
    if (book_ && scenario_.split.min_fragment_diameter > 0.0) {
      const double d = scenario_.split.min_fragment_diameter;
      book_->set_min_piece_volume(std::numbers::pi / 6.0 * d * d * d);
    }
    if (book_ && specimen_.def.crystal.enabled) {
      // Each plane's family sets its resistance; from the scenario, fresh or resumed.
      const auto& crystal = specimen_.def.crystal;
      std::vector<double> per_plane;
      for (const int f : geometry::plane_families(crystal))
        per_plane.push_back(crystal.families.at(static_cast<std::size_t>(f)).resistance);
      book_->set_plane_resistance(std::move(per_plane));
    }
    if (book_) {
      fracture_.emplace(*book_, scenario_.fracture.params,
                        static_cast<std::uint64_t>(scenario_.fracture.check_every));
      checks_.set_fracture(&*fracture_);
    }
    world_.set_timing(hooks_.timing);
    if (hooks_.domain) {
      // One process of several (mpirun): what the decomposition does not carry yet is refused
      // before anything runs.
      auto refuse = [](const std::string& what) {
        throw std::invalid_argument(what + " is not yet supported on several MPI processes; run it on one");
      };
      if (scenario_.thermal.enabled) refuse("[thermal]");
      if (world_.cell()) refuse("a periodic cell ([periodic])");
      if (scenario_.dynamics.manifold_tolerance > 0.0) refuse("[dynamics] manifold_tolerance > 0");
      if (scenario_.bond.enabled && scenario_.bond.params.criterion != physics::BondCriterion::limits)
        refuse("[bond] criterion = \"" + std::string(scenario_.bond.params.criterion == physics::BondCriterion::rankine ? "rankine" : "hydrostatic") + "\"");
      hooks_.domain->attach(world_);
      root_ = hooks_.domain->rank() == 0;
    }
  }

  /// Where the run starts: its first frame, or the loop's state of a checkpoint.
  void start() {
    stage_ = scenario_.stages.empty() ? "run" : scenario_.stages.front().name;
    if (resuming_) {
      resumed_.emplace(decode_run_state(resume_state_, run_state(), scenario_, world_));
      next_stage_ = stage_index_;
      cracks_.rebuild(world_, book(), sum_.splits);
    } else {
      write_frame();
    }
    if (scenario_.stages.empty()) plain_ = plain_stage(scenario_, world_);
    started_ = true;
  }

  bool plain() const { return scenario_.stages.empty(); }

  /// A stage is left to run.
  bool has_next() const {
    return plain() ? next_stage_ == 0 : next_stage_ < scenario_.stages.size() && !stopped_;
  }

  /// Begins the next stage (a bond stage is over at once). False when none is left.
  bool open_next() {
    if (!has_next()) return false;
    if (!plain()) stage_index_ = next_stage_;
    const StageDef& def = plain() ? plain_ : scenario_.stages[next_stage_];
    ++next_stage_;
    begin_stage(def, plain(), resumed_ ? &*resumed_ : nullptr);
    resumed_.reset();
    return true;
  }

  bool done() const { return finished_ || (started_ && !stage_run_ && !has_next()); }
  bool finished() const { return finished_; }

  std::uint64_t advance(std::uint64_t steps) {
    if (finished_) return 0;
    if (!started_) start();
    std::uint64_t taken = 0;
    while (taken < steps) {
      if (!stage_run_) {
        if (!open_next()) break;
        continue;
      }
      if (!continues()) {
        end_stage();
        continue;
      }
      step_once();
      ++taken;
    }
    if (stage_run_ && !continues()) end_stage();
    return taken;
  }

  std::optional<StageSummary> advance_stage() {
    if (finished_) return std::nullopt;
    if (!started_) start();
    if (!stage_run_) {
      if (!open_next()) return std::nullopt;
      if (!stage_run_) return sum_.stages.back();  // a bond stage
    }
    while (continues()) step_once();
    end_stage();
    return sum_.stages.back();
  }

  DynamicsSummary finish() {
    if (finished_) return sum_;
    advance(std::numeric_limits<std::uint64_t>::max());  // to the end: it stops only when done
    // A blown-up state with non-finite values makes no frame; the last good one stays.
    const bool garbage = sum_.ending == RunEnding::blew_up && !finite_state();
    if (domain()) domain()->gather_all(world_, true);  // every process holds the whole world
    if (world_.steps() != frames_.last_step() && !garbage) write_frame(true);
    if (hooks_.timing) write_timing();
    history_.write(world_, book_.has_value(), stage_);
    sum_.steps = world_.steps();
    sum_.time = world_.time();
    sum_.kinetic_energy = world_.kinetic_energy();
    sum_.released_energy = history_.start_potential() - world_.potential_energy();
    sum_.lowest_point = lowest_vertex(world_);
    sum_.bond_counts = world_.bond_counts();
    cracks_.add_breaks(world_);
    sum_.cracks = cracks_.totals();
    if (book_) {
      for (const auto& e : book_->entries(world_)) {
        const auto& grain = specimen_.grains.at(static_cast<std::size_t>(e.lineage.grain_id));
        sum_.final_pieces.push_back({e.lineage, e.shape, grain.site.centre, grain.orientation});
      }
    }
    collect_fragments();
    for (const auto& st : sum_.stages) {
      if (st.peak_load > sum_.peak_load) sum_.cracks_at_peak = st.cracks_at_peak;
      sum_.peak_load = std::max(sum_.peak_load, st.peak_load);
    }
    const geometry::Outline& outline = specimen_.def.outline;
    if (outline.kind == geometry::Outline::Kind::disc && sum_.peak_load > 0.0) {
      /// Brazilian tensile strength sigma = 2P / (pi D t), sec. 2.5.4 of the dissertation.
      sum_.brazilian_strength = 2.0 * sum_.peak_load / (M_PI * outline.size.x() * outline.size.z());
    }
    sum_.state_hash = world_.state_hash();
    sum_.wall_seconds = seconds_since(t0_);
    finished_ = true;
    return sum_;
  }

  /// The fragments at the end (clusters of bodies joined by intact bonds), each body's
  /// volume exact from its shape: the book's piece, or its grain's shape without [fracture].
  void collect_fragments() {
    std::map<const geometry::ExactPolyhedron*, geometry::ExactScalar> volumes;
    auto volume_of = [&](const geometry::ExactPolyhedron& shape) {
      auto it = volumes.find(&shape);
      if (it == volumes.end()) it = volumes.emplace(&shape, shape.volume()).first;
      return it->second;
    };
    std::map<std::uint32_t, const geometry::ExactPolyhedron*> pieces;
    if (book_) {
      for (const auto& e : book_->entries(world_)) pieces[e.id.index] = e.shape.get();
    }
    const auto& infos = world_.slot_infos();
    const auto fragments = bonded_fragments(world_, [&](std::uint32_t slot) {
      if (const auto it = pieces.find(slot); it != pieces.end()) return volume_of(*it->second);
      if (infos[slot].grain_id < 0) return geometry::ExactScalar();  // no grain: no specimen volume
      const auto& grain = specimen_.grains.at(static_cast<std::size_t>(infos[slot].grain_id));
      return volume_of(specimen_.shape_of(grain));
    });
    geometry::ExactScalar total, specimen;
    for (const auto& f : fragments) {
      sum_.fragments.push_back({f.slots.size(), f.volume.to_double(), f.mass});
      total = total + f.volume;
    }
    for (const auto& g : specimen_.grains) specimen = specimen + volume_of(specimen_.shape_of(g));
    sum_.fragment_volume_exact = total == specimen;
  }

  const physics::World& world() const { return world_; }
  physics::World& world() { return world_; }
  const physics::FractureBook* book() const { return book_ ? &*book_ : nullptr; }
  const std::string& stage() const { return stage_; }
  const DynamicsSummary& summary() const { return sum_; }

 private:
  bool continues() const { return stage_run_->continues(); }

  /// Begins one stage from its start, or from `resume` (a checkpoint taken inside it). A
  /// bond stage is over when this returns; a motion stage is left in stage_run_, its
  /// boundary conditions registered on the World.
  void begin_stage(const StageDef& stage, bool plain, const StageProgress* resume) {
    StageProgress progress;
    if (resume) {
      progress = *resume;
    } else {
      progress.st.name = stage.name;
      progress.st.kind = stage.kind;
      progress.st.start = world_.time();
      progress.breaks0 = world_.bond_breaks().size();
      cracks_.add_breaks(world_);
      progress.st.cracks_start = progress.st.cracks_end = cracks_.totals();
    }
    stage_ = stage.name;
    if (stage.kind == StageDef::Kind::bond) {
      bond_stage(stage, progress);
      return;
    }
    StageRun& r = stage_run_.emplace();
    r.stage = &stage;
    r.plain = plain;
    r.progress = std::move(progress);
    current_ = &r.progress;
    world_.hold_bonds(stage.hold_cracks);
    if (fracture_) fracture_->hold(stage.hold_cracks);
    r.conditions.emplace(world_, stage, r.progress.st.steps);
    begin_stage_conditions(world_, scenario_, stage, resume != nullptr);
    for (const auto& name : stage.load_walls) r.load_walls.push_back(wall_index(world_, name));
    if (!resume) {
      for (const auto& w : world_.walls()) r.progress.stage_origin.push_back(w.origin);
    }
    r.plan(world_, max_steps_);
  }

  /// Bond initialisation (sec. 2.5.2): bonds between the grains within the stage's distance,
  /// their overlaps stored, at rest.
  void bond_stage(const StageDef& stage, StageProgress& progress) {
    StageSummary& st = progress.st;
    current_ = &progress;
    sum_.bonds = world_.initialise_bonds(scenario_.bond.params, stage.bond_distance);
    if (scenario_.bond.strength_modulus > 0.0 || !scenario_.phases.empty()) {
      // Each bond's own stiffness and strength: its two grains' phases (sim/phases.hpp), the
      // strength times a draw from the microstructure's seed and its two grains.
      for (std::size_t k = 0; k < world_.bonds().size(); ++k) {
        const physics::Bond& bd = world_.bonds()[k];
        const int ga = world_.slot_infos()[bd.a].grain_id, gb = world_.slot_infos()[bd.b].grain_id;
        const BondFactors f =
            bond_factors(scenario_, specimen_.grains.at(static_cast<std::size_t>(ga)).phase,
                         specimen_.grains.at(static_cast<std::size_t>(gb)).phase);
        const double drawn = scenario_.bond.strength_modulus > 0.0
                                 ? physics::bond_strength_factor(scenario_.specimen.seed, ga, gb,
                                                                 scenario_.bond.strength_modulus)
                                 : 1.0;
        world_.set_bond_strength(k, f.strength * drawn);
        world_.set_bond_stiffness(k, f.stiffness);
      }
    }
    st.ended_by = "bonded";
    st.end = world_.time();
    if (!quiet_) {
      std::fprintf(stderr, "%s  stage %-12s %zu bonds within %.3g mm (overlaps stored, at rest)\n",
                   progress_shown_ ? "\n" : "", stage.name.c_str(), sum_.bonds,
                   stage.bond_distance * 1e3);
      progress_shown_ = false;
    }
    record(largest_overlap(), std::nullopt);
    write_frame();
    sum_.stages.push_back(st);
    current_ = nullptr;
  }

  /// Step i of the stage under way: the step (its boundary conditions, guard and
  /// transgranular check run inside it as the World's listeners), its splits, the stage's
  /// reading and event, the histories, frames, checkpoints, a stop, the progress line.
  void step_once() {
    StageRun& r = *stage_run_;
    const std::uint64_t i = r.i++;
    if (!take_step(r)) return;
    cracks_.add_breaks(world_);
    take_splits(r);
    const double overlap =
        checks_.verdict().overlap ? *checks_.verdict().overlap : max_overlap(world_);
    sum_.max_overlap = std::max(sum_.max_overlap, overlap);
    const MachineReading reading = read_machine(r);
    r.progress.event = stage_event(r, world_, stage_readings(r, reading.load));
    if (r.logs(i)) log_row(r, overlap, reading);
    if (sum_.ending != RunEnding::blew_up && r.frames(i)) write_frame();
    // A value that is not finite in a row or frame of this step ends the run here (failed),
    // before a checkpoint would keep the state.
    if (sum_.ending == RunEnding::blew_up) return;
    const RunPoint point = run_point(r);
    checkpoints_.after_step(world_, point);
    if (stop_requested()) {
      sum_.ending = RunEnding::interrupted;
      // The checkpoint first: a restart continues the histories as if never stopped.
      checkpoints_.on_interrupt(world_, point);
      if (!r.logs(i)) record(overlap, load_reading(r, reading));
      r.halt = stopped_ = true;
    }
    show_progress(r, i, reading.load);
  }

  /// World::step, then the guard's verdict: false when the step blew up (then recorded and
  /// the run halts).
  bool take_step(StageRun& r) {
    try {
      world_.step();
    } catch (const std::exception&) {
      // A non-finite state can stop the step part-way (the neighbour search refuses it):
      // that is a blow-up to report as such; anything else is an error of its own.
      if (!checks_.after_throw(world_)) throw;
    }
    ++r.progress.st.steps;
    const StepVerdict& verdict = checks_.verdict();
    if (!verdict.failure) return true;
    sum_.ending = RunEnding::blew_up;
    sum_.failure = *verdict.failure;
    record(verdict.overlap ? *verdict.overlap : max_overlap(world_), std::nullopt);
    r.halt = stopped_ = true;
    return false;
  }

  /// The transgranular check's splits of this step: logged, counted, and the pieces the
  /// time step may not be stable for said once.
  void take_splits(StageRun& r) {
    if (!fracture_) return;
    const std::vector<physics::TransgranularEvent> events = fracture_->take_events();
    if (events.empty()) return;
    history_.add_splits(world_, stage_, events);
    cracks_.add_splits(world_, *book_, events);
    sum_.splits += events.size();
    r.progress.st.splits += events.size();
    warn_light_pieces(events);
  }

  /// The stage's machine reading, and its peak so far.
  MachineReading read_machine(StageRun& r) {
    const MachineReading m = machine_reading(world_, r.load_walls, r.progress.stage_origin);
    StageSummary& st = r.progress.st;
    if (!r.load_walls.empty() && m.load > st.peak_load) {
      st.peak_load = m.load;
      st.peak_displacement = m.displacement;
      st.cracks_at_peak = cracks_.totals();
    }
    return m;
  }

  static std::optional<std::pair<double, double>> load_reading(const StageRun& r,
                                                               const MachineReading& m) {
    return r.load_walls.empty() ? std::nullopt : std::optional(std::pair(m.load, m.displacement));
  }

  /// What the stage's until-criterion reads (on several processes only that one's
  /// reductions are made).
  StageReadings stage_readings(const StageRun& r, double load) {
    StageReadings now{load, world_.bond_breaks().size() - r.progress.breaks0};
    if (r.stage->until == StageDef::Until::limit && r.plain) now.settled = settled();
    if (r.stage->until == StageDef::Until::all_in_contact)
      now.all_in_contact = all_in_contact(world_, touched_);
    return now;
  }

  /// A logged step: the histories' row, and the load-displacement picture's point.
  void log_row(StageRun& r, double overlap, const MachineReading& m) {
    if (record(overlap, load_reading(r, m)) && !r.load_walls.empty()) {
      r.progress.plot_x.push_back(m.displacement);
      r.progress.plot_y.push_back(m.load);
    }
  }

  RunPoint run_point(const StageRun& r) {
    return RunPoint{world_,       r.stage->name,
                    stage_index_, r.progress.st.steps,
                    book(),       [this] { return encode_run_state(run_state(), *current_); }};
  }

  /// Several processes stop after the same step (the request was read with the verdict).
  bool stop_requested() const {
    return domain() ? checks_.verdict().stop : hooks_.stop_requested && hooks_.stop_requested();
  }

  void show_progress(StageRun& r, std::uint64_t i, double load) {
    if (quiet_ || !root_ ||
        !(seconds_since(r.last_print) > 1.0 || i == r.limit || r.progress.event || r.halt))
      return;
    r.last_print = std::chrono::steady_clock::now();
    const std::string line =
        progress_line(r, world_, domain() ? last_contacts_ : world_.contacts().size(),
                      domain() ? last_kinetic_ : world_.kinetic_energy(), sum_.splits,
                      book_.has_value(), load, r.plain && scenario_.dynamics.settle_ratio > 0.0);
    std::fputs(line.c_str(), stderr);
    progress_shown_ = true;
  }

  /// What follows the last step of a motion stage: its summary, plot and log line.
  void end_stage() {
    StageRun& r = *stage_run_;
    const StageDef& stage = *r.stage;
    const bool plain = r.plain;
    StageSummary& st = r.progress.st;
    const bool event = r.progress.event;
    const auto& load_walls = r.load_walls;
    st.end = world_.time();
    st.bonds_broken = world_.bond_breaks().size() - r.progress.breaks0;
    cracks_.add_breaks(world_);
    st.cracks_end = cracks_.totals();
    st.ended_by = event ? (plain ? "settled" : io::to_string(stage.until)) : "limit";
    if (sum_.ending == RunEnding::interrupted) st.ended_by = "interrupted";
    if (sum_.ending == RunEnding::blew_up) st.ended_by = "blew_up";
    if (r.capped && !event && !r.halt) {
      stopped_ = true;  // --max-steps reached inside this stage
      st.ended_by = "max_steps";
      sum_.ending = RunEnding::stopped;
    }
    st.event_missed = !event && !r.halt && !stopped_ && stage.until != StageDef::Until::limit;
    if (plain) sum_.settled = event;
    if (!load_walls.empty() && r.progress.plot_x.size() >= 2) {
      st.plot = fmt::format("load_displacement_{}.svg", stage.name);
      history_.write_stage_plot(stage, st.plot, st.peak_load, st.peak_displacement,
                                r.progress.plot_x, r.progress.plot_y);
    }
    history_.end_stage(world_.bond_breaks().size(), stage.name);
    std::string modulus_line;
    if (stage.measure_modulus) modulus_line = history_.measure_modulus(world_, stage, sum_.splits);
    if (!quiet_) {
      std::string line = fmt::format("\n{:>8}ended by {} after {} steps", "", st.ended_by, st.steps);
      if (!modulus_line.empty()) line += "; " + modulus_line;
      if (st.event_missed) line += fmt::format(" (the {} event did not come)", io::to_string(stage.until));
      if (!load_walls.empty()) {
        line += fmt::format("; peak load {:.4g} N at {:.4g} um load-point displacement", st.peak_load,
                            st.peak_displacement * 1e6);
      }
      if (!world_.bonds().empty()) line += fmt::format("; {} bonds broke", st.bonds_broken);
      if (book_) line += fmt::format("; {} grains split", st.splits);
      std::fprintf(stderr, "%s\n", line.c_str());
      progress_shown_ = false;
    }
    sum_.stages.push_back(st);
    current_ = nullptr;
    world_.hold_bonds(false);
    stage_run_.reset();
  }

  RunState run_state() { return {stage_index_, stage_, sum_, history_, frames_}; }

  /// A piece is lighter than its grain, and a thin one turns faster on the same springs:
  /// the step checked for the grains may not be stable for it. By the same (conservative:
  /// the stiffest spring at the bounding radius) bound, say so once. Where such a piece
  /// touches a platen or roller, the run may blow up a few steps later, or first throw a
  /// load spike that a load_drop stage would take for the peak.
  void warn_light_pieces(const std::vector<physics::TransgranularEvent>& events) {
    const double dt = world_.settings().dt;
    for (const auto& e : events) {
      for (const physics::BodyId id : e.split.ids) {
        if (piece_warned_) break;
        const physics::BodyInfo& info = world_.info(id);
        const double limit = stable_time_step(scenario_, info.mass, info.inertia.minCoeff(),
                                              world_.shape(info.shape).bounding_radius());
        if (dt > limit) {
          piece_warned_ = true;
          if (!root_) break;  // several processes: the first says it
          fmt::print(stderr,
                     "cleave: warning: step {}: grain {} split into a piece of {:.3g} kg (smallest "
                     "principal "
                     "moment {:.3g} kg m^2) whose stable step by the grains' bound is {:.3g} s, "
                     "below dt = "
                     "{:.3g} s; if the run blows up or its load spikes after a split, use "
                     "[dynamics] dt <= "
                     "{:.3g} s\n",
                     world_.steps(), e.split.parent.grain_id, info.mass, info.inertia.minCoeff(),
                     limit, dt, limit);
        }
      }
    }
  }

  /// Every live body's state is finite.
  bool finite_state() const {
    for (const physics::BodyId id : world_.body_ids()) {
      const physics::BodyState& s = world_.state(id);
      if (!s.x.allFinite() || !s.q.coeffs().allFinite() || !s.v.allFinite() || !s.L.allFinite()) return false;
    }
    return true;
  }

  bool settled() {
    const double released = history_.start_potential() - potential_energy();
    const double ratio = scenario_.dynamics.settle_ratio;
    return ratio > 0.0 && released > 0.0 && contact_count() > 0 && kinetic_energy() < ratio * released;
  }

  // Readings of the whole world; on several processes each adds its own bodies' share
  // (exactly, so the sums are the same on any number of them). Every process calls them at
  // the same points of the run.
  physics::Domain* domain() const { return world_.domain(); }
  double kinetic_energy() const {
    return domain() ? domain()->sum(world_.owned_kinetic_energy()) : world_.kinetic_energy();
  }
  double potential_energy() const {
    return domain() ? domain()->sum(world_.owned_potential_energy()) : world_.potential_energy();
  }
  std::size_t contact_count() const {
    return domain() ? domain()->count(world_.owned_contact_count()) : world_.contacts().size();
  }
  double largest_overlap() const {
    const double mine = max_overlap(world_);
    return domain() ? domain()->max(mine) : mine;
  }

  /// One row of every history; `reading` is the stage's (load, load-point displacement)
  /// when it has load walls. A row holding a value that is not finite is not written: the
  /// run fails there (non_finite). Returns whether the row was written.
  bool record(double overlap, std::optional<std::pair<double, double>> reading) {
    const WorldReadings now{kinetic_energy(), potential_energy(), contact_count(), overlap};
    cracks_.add_breaks(world_);
    if (const auto bad = history_.record(world_, stage_, now, reading, cracks_.totals())) {
      non_finite(*bad);
      return false;
    }
    last_kinetic_ = now.kinetic;
    last_contacts_ = now.contacts;
    return true;
  }

  /// The run fails at this step: something it would write is not finite (`what`, naming the
  /// body, wall or column). The first failure stays; the run stops after this step.
  void non_finite(const std::string& what) {
    if (sum_.ending == RunEnding::blew_up) return;
    sum_.ending = RunEnding::blew_up;
    sum_.failure = fmt::format("the run failed at step {} (t = {:.3g} s): {}", world_.steps(),
                               world_.time(), what);
    stopped_ = true;
    if (stage_run_) stage_run_->halt = true;
  }

  /// `gathered`: on several processes, the whole world is here already. Returns whether
  /// the frame was written (a value not finite fails the run instead).
  bool write_frame(bool gathered = false) {
    const auto bad = frames_.write(world_, book(), root_, gathered);
    sum_.frames = frames_.frames();
    if (bad) non_finite(*bad);
    return !bad;
  }

  /// timing.csv: seconds in each part of the steps since the run (or its restart) began,
  /// milliseconds a step and share, the transgranular check after them; the summary's table.
  void write_timing() {
    const physics::StepTimings& t = world_.timings();
    const double steps = static_cast<double>(std::max<std::uint64_t>(t.steps, 1));
    const double check_seconds = fracture_ ? fracture_->seconds() : 0.0;
    const double total = t.total() + check_seconds;
    std::string csv = "part,wall_s,wall_ms_per_step,share,steps\n";
    std::string table = fmt::format("  timing     {} steps clocked, {:.3f} ms a step:", t.steps, 1e3 * total / steps);
    auto row = [&](const char* name, double seconds) {
      const double share = total > 0.0 ? seconds / total : 0.0;
      csv += fmt::format("{},{:.6f},{:.6f},{:.4f},{}\n", name, seconds, 1e3 * seconds / steps, share, t.steps);
      table += fmt::format("\n             {:<20} {:9.4f} ms/step {:5.1f} %", name, 1e3 * seconds / steps, 100.0 * share);
    };
    for (std::size_t k = 0; k < physics::kStepPhases; ++k)
      row(physics::to_string(static_cast<physics::StepPhase>(k)), t.seconds[k]);
    if (book_) row("transgranular_check", check_seconds);
    csv += fmt::format("total,{:.6f},{:.6f},1,{}\n", total, 1e3 * total / steps, t.steps);
    if (root_) io::write_file_atomically(out_ / "timing.csv", csv);
    sum_.timing = table;
  }

  const io::Scenario& scenario_;
  const geometry::Specimen& specimen_;
  fs::path out_;
  bool quiet_;
  bool root_ = true;  // the process that prints (the first of several)
  double last_kinetic_ = 0.0;  // the last history row's, for the progress line
  std::size_t last_contacts_ = 0;
  std::uint64_t max_steps_;
  RunHooks hooks_;
  bool piece_warned_ = false;  ///< a split made a piece the time step may not be stable for (said once)
  std::size_t stage_index_ = 0;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
  physics::World world_;
  StepChecks checks_;  // registered first: the guard sees every step before the conditions
  RunHistory history_;
  FrameWriter frames_;
  CheckpointPolicy checkpoints_;
  CrackTally cracks_;  // the crack areas so far (made again from the world on a restart)
  std::optional<physics::FractureBook> book_;
  std::optional<physics::TransgranularCheck> fracture_;  // with book_, run through checks_
  std::string stage_;
  std::vector<char> touched_;
  StageProgress* current_ = nullptr;  // the stage under way (for checkpoints)
  bool resuming_ = false;
  std::string resume_state_;
  bool stopped_ = false;
  bool progress_shown_ = false;
  DynamicsSummary sum_;
  StageDef plain_;                        // the one stage of a plain run
  std::optional<StageProgress> resumed_;  // the checkpointed stage, until it begins
  std::optional<StageRun> stage_run_;     // the motion stage under way
  std::size_t next_stage_ = 0;
  bool started_ = false, finished_ = false;
};

Dynamics::Dynamics(const io::Scenario& scenario, const geometry::Specimen& specimen,
                   const fs::path& out, bool quiet, std::uint64_t max_steps, const RunHooks& hooks,
                   RunResume* resume, AssembledWorld* assembled)
    : runner_(std::make_unique<Runner>(
          resume      ? AssembledWorld{std::move(resume->world), resume->stable_dt}
          : assembled ? std::move(*assembled)
                      : assemble_world(scenario, specimen),
          scenario, specimen, out, quiet, max_steps, hooks, resume)) {}
Dynamics::~Dynamics() = default;
std::uint64_t Dynamics::advance(std::uint64_t steps) { return runner_->advance(steps); }
std::optional<StageSummary> Dynamics::advance_stage() { return runner_->advance_stage(); }
bool Dynamics::done() const { return runner_->done(); }
DynamicsSummary Dynamics::finish() { return runner_->finish(); }
bool Dynamics::finished() const { return runner_->finished(); }
const physics::World& Dynamics::world() const { return runner_->world(); }
physics::World& Dynamics::world() { return runner_->world(); }
const physics::FractureBook* Dynamics::book() const { return runner_->book(); }
const std::string& Dynamics::stage() const { return runner_->stage(); }
const DynamicsSummary& Dynamics::summary() const { return runner_->summary(); }

DynamicsSummary run_dynamics(const io::Scenario& scenario, const geometry::Specimen& specimen,
                             const fs::path& out, bool quiet, std::uint64_t max_steps,
                             const RunHooks& hooks, RunResume* resume) {
  return Dynamics(scenario, specimen, out, quiet, max_steps, hooks, resume).finish();
}

}  // namespace cleave::sim
