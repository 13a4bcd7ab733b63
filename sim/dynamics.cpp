#include "sim/dynamics.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "io/field_expression.hpp"
#include "io/mesh_io.hpp"
#include "io/paraview_frames.hpp"
#include "io/plot.hpp"
#include "io/result_dir.hpp"
#include "io/vtk_output.hpp"
#include "sim/world_assembly.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "physics/bonds/grain_stress.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/step_guard.hpp"
#include "physics/transgranular/transgranular.hpp"
#include "physics/dem/world.hpp"

namespace cleave::sim {

namespace {

namespace fs = std::filesystem;
using io::StageDef;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// A body's shape in its world pose.
geometry::PolygonMesh world_mesh(const physics::World& world, physics::BodyId id) {
  const physics::BodyState& s = world.state(id);
  const auto& prim = world.shape(world.info(id).shape).primitives;
  geometry::PolygonMesh mesh;
  const Eigen::Matrix3d R = s.q.toRotationMatrix();
  for (const auto& v : prim.vertices) mesh.vertices.push_back(s.x + R * v);
  for (const auto& f : prim.faces) mesh.faces.push_back(f.vertices);
  return mesh;
}

/// The largest contact overlap of the last force evaluation, m.
double max_overlap(const physics::World& world) {
  double overlap = 0.0;
  for (const auto& c : world.contacts()) overlap = std::max(overlap, c.overlap);
  return overlap;
}

/// The body frame: every body's world mesh and its fields.
io::BodyFrame body_frame(const physics::World& world, const geometry::Specimen& specimen) {
  io::BodyFrame frame;
  const std::vector<Eigen::Matrix3d> stress = world.body_stresses();
  auto& ids = frame.body_fields.ids;
  auto& vec = frame.body_fields.vectors;
  auto& sca = frame.body_fields.scalars;
  for (const physics::BodyId id : world.body_ids()) {
    const physics::BodyState& s = world.state(id);
    const physics::BodyInfo& b = world.info(id);
    frame.meshes.push_back(world_mesh(world, id));
    ids["body_id"].push_back(id.index);
    ids["grain_id"].push_back(b.grain_id);
    const auto& o = specimen.grains.at(static_cast<std::size_t>(b.grain_id)).orientation;
    ids["family_11_20"].push_back(o.family == geometry::CleavageFamily::a_11_20 ? 1 : 0);
    ids["angle_deg"].push_back(o.angle_deg);
    // The crystal's c axis (the prism axis, z of the shape frame) in the world.
    const auto& shape = world.shape(b.shape);
    vec["c_axis"].push_back(s.q * (shape.axes.transpose() * Eigen::Vector3d::UnitZ()));
    vec["velocity_m_per_s"].push_back(s.v);
    vec["angular_velocity_rad_per_s"].push_back(s.w);
    sca["speed_m_per_s"].push_back(s.v.norm());
    // Grain stress (eq. 2.17) from the contacts: mean (hydrostatic), von Mises, principal.
    const Eigen::Matrix3d& sigma = stress[id.index];
    sca["mean_stress_Pa"].push_back(physics::mean_stress(sigma));
    sca["von_mises_Pa"].push_back(physics::von_mises(sigma));
    vec["principal_stress_Pa"].push_back(physics::principal_stresses(sigma));
    // Eq. 2.18: the in-plane (xy) invariants the seed plots for its one-plane specimens.
    const physics::PlaneInvariants pq = physics::plane_invariants(sigma);
    sca["p_xy_Pa"].push_back(pq.p);
    sca["q_xy_Pa"].push_back(pq.q);
    sca["theta_xy_deg"].push_back(pq.theta * 180.0 / M_PI);
  }
  return frame;
}

/// A periodic cell's twelve edges as lines, `axis` the cell vector each runs along (0, 1, 2)
/// and `periodic` whether the cell is periodic along it.
io::LinkFrame cell_frame(const physics::PeriodicCell& cell) {
  io::LinkFrame frame;
  auto corner = [&](int bits) {
    return Eigen::Vector3d(cell.origin() + cell.vectors() * Eigen::Vector3d(bits & 1, (bits >> 1) & 1, (bits >> 2) & 1));
  };
  for (int bits = 0; bits < 8; ++bits) {
    for (int k = 0; k < 3; ++k) {
      if (bits & (1 << k)) continue;
      frame.a.push_back(corner(bits));
      frame.b.push_back(corner(bits | (1 << k)));
      frame.fields.ids["axis"].push_back(k);
      frame.fields.ids["periodic"].push_back(cell.periodic(k) ? 1 : 0);
    }
  }
  return frame;
}

/// Contacts as points (zero-length links) at their contact points.
io::LinkFrame contact_frame(const physics::World& world) {
  io::LinkFrame frame;
  for (const auto& c : world.contacts()) {
    frame.a.push_back(c.point);
    frame.b.push_back(c.point);
    frame.fields.vectors["force_N"].push_back(c.force);
    frame.fields.vectors["normal"].push_back(c.normal);
    frame.fields.scalars["overlap_m"].push_back(c.overlap);
    frame.fields.ids["with_wall"].push_back(c.wall ? 1 : 0);
  }
  return frame;
}

/// The bond network as lines between the two grains' centroids (the beams of figs 2.18 and
/// 2.22): intact (1) or broken (0), the failure mode, and the bond's loads.
io::LinkFrame bond_frame(const physics::World& world) {
  io::LinkFrame frame;
  auto& f = frame.fields;
  for (const physics::Bond& b : world.bonds()) {
    frame.a.push_back(world.state(world.id_at(b.a)).x);
    frame.b.push_back(world.state(world.id_at(b.b)).x);
    f.ids["intact"].push_back(b.intact() ? 1 : 0);
    f.ids["failure_mode"].push_back(static_cast<long long>(b.failure));
    f.scalars["normal_force_N"].push_back(b.state.normal);
    f.scalars["shear_force_N"].push_back(b.state.shear.norm());
    f.scalars["bending_moment_Nm"].push_back(b.state.bending.norm());
    f.scalars["torsion_moment_Nm"].push_back(std::abs(b.state.torsion));
    f.vectors["force_N"].push_back(b.force);
  }
  return frame;
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

/// The progress line's ETA: the time left to the stage's step limit when the limit ends it;
/// an upper bound when settling may end a plain run sooner; none when an event (a load drop, walls
/// touching) ends it, since its time limit says nothing about when that comes.
std::string eta_text(const io::StageDef& stage, bool may_settle, double seconds_left) {
  if (may_settle) return fmt::format("  ETA <= {:.0f} s   ", seconds_left);
  if (stage.until == io::StageDef::Until::limit) return fmt::format("  ETA {:.0f} s   ", seconds_left);
  return fmt::format("  until {}   ", io::to_string(stage.until));
}

/// What a testing machine reads off one wall: the force the specimen presses it with and
/// how far it has moved, both along its load axis (magnitudes when it has none).
struct WallReading {
  double force = 0.0, displacement = 0.0;
};

WallReading read_wall(const physics::Wall& w, const Eigen::Vector3d& origin0) {
  const Eigen::Vector3d moved = w.origin - origin0;
  if (w.load_axis.squaredNorm() == 0.0) return {w.reaction.norm(), moved.norm()};
  return {-w.reaction.dot(w.load_axis), moved.dot(w.load_axis)};
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

namespace {

/// Where the loop of one stage is: what a checkpoint saves of it besides the world.
struct StageProgress {
  StageSummary st;
  std::size_t breaks0 = 0;                    ///< bond breaks before the stage
  std::vector<Eigen::Vector3d> stage_origin;  ///< wall origins at the stage's start
  std::vector<double> plot_x, plot_y;         ///< its load-displacement picture so far
  bool event = false;                         ///< its ending event has come
};

/// A motion stage under way: what its loop keeps from step to step.
struct StageRun {
  const StageDef* stage = nullptr;
  bool plain = false;
  StageProgress progress;
  std::vector<std::size_t> load_walls;
  std::uint64_t limit = 0, frame_every = 0, log_every = 1;
  std::uint64_t i = 1;  ///< the stage's next step, counted from 1
  std::chrono::steady_clock::time_point t0, last_print;
  bool halt = false;  ///< interrupted or blew up: the run ends after this step
  bool capped = false;  ///< --max-steps cut its limit: the run ends if it reaches it
  std::optional<io::FieldExpression> temperature_field;  ///< the stage's, when it has one
};

/// The layout of the run state in a checkpoint (Runner::encode_run_state).
constexpr std::uint32_t kRunStateLayout = 3;  // 2: thermal.csv; 3: cell.csv, modulus.csv

void put_summary(physics::StateWriter& w, const StageSummary& st) {
  w.put(st.name);
  w.put(st.kind);
  w.put(st.steps);
  w.put(st.start);
  w.put(st.end);
  w.put(st.ended_by);
  w.put(st.event_missed);
  w.put(st.peak_load);
  w.put(st.peak_displacement);
  w.put<std::uint64_t>(st.bonds_broken);
  w.put<std::uint64_t>(st.splits);
  w.put(st.plot);
}

StageSummary get_summary(physics::StateReader& r) {
  StageSummary st;
  st.name = r.string();
  st.kind = r.get_enum(StageDef::Kind::bond);
  st.steps = r.get<std::uint64_t>();
  st.start = r.get<double>();
  st.end = r.get<double>();
  st.ended_by = r.string();
  st.event_missed = r.get_bool();
  st.peak_load = r.get<double>();
  st.peak_displacement = r.get<double>();
  st.bonds_broken = r.get<std::uint64_t>();
  st.splits = r.get<std::uint64_t>();
  st.plot = r.string();
  return st;
}

}  // namespace

/// One dynamic run, stage after stage, and everything it writes.
class Dynamics::Runner {
 public:
  Runner(const io::Scenario& scenario, const geometry::Specimen& specimen, fs::path out,
         bool quiet, std::uint64_t max_steps, const RunHooks& hooks, RunResume* resume)
      : scenario_(scenario),
        specimen_(specimen),
        out_(std::move(out)),
        quiet_(quiet),
        max_steps_(max_steps),
        hooks_(hooks),
        guard_(hooks.max_move_fraction),
        world_(resume ? std::move(resume->world) : sim::make_world(scenario, specimen)),
        bodies_pvd_(out_ / "bodies.pvd"),
        contacts_pvd_(out_ / "contacts.pvd"),
        bonds_pvd_(out_ / "bonds.pvd"),
        cell_pvd_(out_ / "cell.pvd"),
        walls_pvd_(out_ / "walls.pvd"),
        cracks_pvd_(out_ / "cracks.pvd") {
    fs::create_directories(out_ / "frames");
    world_.add_listener(&sums_for_check_);
    for (const auto& w : world_.walls()) origin0_.push_back(w.origin);
    pe0_ = world_.potential_energy();
    energy_ = "time_s,kinetic_J,potential_J,contacts,max_overlap_m,stage\n";
    walls_ = "time_s";
    loads_ = "time_s,step,stage";
    for (const auto& w : world_.walls()) {
      walls_ += fmt::format(",{0}_Fx_N,{0}_Fy_N,{0}_Fz_N", w.name);
      loads_ += fmt::format(",{0}_displacement_m,{0}_force_N", w.name);
    }
    walls_ += "\n";
    loads_ += ",load_N,load_point_displacement_m\n";
    bond_counts_ = "time_s,stage,intact,broken_tension,broken_shear,broken_bending,broken_torsion\n";
    if (scenario_.thermal.enabled) thermal_ = "time_s,stage,mean_K,min_K,max_K,bonds_intact,bonds_broken,grain_splits\n";
    if (const physics::PeriodicCell* cell = world_.cell()) {
      cell_ = "time_s,stage,lx_m,ly_m,lz_m,strain_x,strain_y,strain_z,sxx_Pa,syy_Pa,szz_Pa,syz_Pa,sxz_Pa,sxy_Pa\n";
      modulus_ = "stage,time_s,mean_K,axis,strain,young_Pa,poisson,bonds_broken,grain_splits\n";
      cell0_ = cell->vectors().colwise().norm().transpose();
    }
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
        book_->add_grain(world_, id, grain, specimen_.grains.at(static_cast<std::size_t>(grain)).orientation);
      }
      splits_ =
          "time_s,step,stage,grain,parent,pieces,plane,nx,ny,nz,x_m,y_m,z_m,mean_stress_Pa,sigma_Pa,"
          "tau_Pa,K_I_Pa_sqrt_m,K_II_Pa_sqrt_m,criterion\n";
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
    const io::DynamicsDef& dyn = scenario_.dynamics;
    stage_ = scenario_.stages.empty() ? "run" : scenario_.stages.front().name;
    if (resuming_) {
      resumed_.emplace(decode_run_state(resume_state_));
      next_stage_ = stage_index_;
    } else {
      write_frame();
    }
    if (scenario_.stages.empty()) {
      // A plain run: one stage as long as the duration, ended early once settled.
      plain_.name = "run";
      plain_.steps = static_cast<std::uint64_t>(std::ceil(dyn.duration / dyn.dt));
      plain_.frames = dyn.frames;
      for (std::size_t i = 0; i < world_.walls().size(); ++i) {
        plain_.wall_velocity.emplace_back(world_.walls()[i].name, world_.walls()[i].velocity);
      }
    }
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
    if (world_.steps() != last_frame_step_ && !garbage) write_frame(true);
    write_tables();
    sum_.steps = world_.steps();
    sum_.time = world_.time();
    sum_.kinetic_energy = world_.kinetic_energy();
    sum_.released_energy = pe0_ - world_.potential_energy();
    sum_.lowest_point = lowest_vertex(world_);
    sum_.bond_counts = world_.bond_counts();
    if (book_) {
      for (const auto& e : book_->entries(world_)) {
        const auto& grain = specimen_.grains.at(static_cast<std::size_t>(e.lineage.grain_id));
        sum_.final_pieces.push_back({e.lineage, e.shape, grain.site.centre, grain.orientation});
      }
    }
    for (const auto& st : sum_.stages) sum_.peak_load = std::max(sum_.peak_load, st.peak_load);
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

  const physics::World& world() const { return world_; }
  physics::World& world() { return world_; }
  const physics::FractureBook* book() const { return book_ ? &*book_ : nullptr; }
  const std::string& stage() const { return stage_; }
  const DynamicsSummary& summary() const { return sum_; }

 private:

  bool continues() const {
    const StageRun& r = *stage_run_;
    return r.i <= r.limit && !r.progress.event && !r.halt;
  }

  /// Begins one stage from its start, or from `resume` (a checkpoint taken inside it). A
  /// bond stage is over when this returns; a motion stage is left in stage_run_.
  void begin_stage(const StageDef& stage, bool plain, const StageProgress* resume) {
    StageProgress progress;
    if (resume) progress = *resume;
    StageSummary& st = progress.st;
    std::size_t& breaks0 = progress.breaks0;
    if (!resume) {
      st.name = stage.name;
      st.kind = stage.kind;
      st.start = world_.time();
      breaks0 = world_.bond_breaks().size();
    }
    stage_ = stage.name;
    if (stage.kind == StageDef::Kind::bond) {
      current_ = &progress;
      sum_.bonds = world_.initialise_bonds(scenario_.bond.params, stage.bond_distance);
      if (scenario_.bond.strength_modulus > 0.0) {
        // Each bond's own strength, drawn from the microstructure's seed and its two grains.
        for (std::size_t k = 0; k < world_.bonds().size(); ++k) {
          const physics::Bond& bd = world_.bonds()[k];
          world_.set_bond_strength(
              k, physics::bond_strength_factor(scenario_.specimen.seed, world_.slot_infos()[bd.a].grain_id,
                                               world_.slot_infos()[bd.b].grain_id, scenario_.bond.strength_modulus));
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
      return;
    }
    StageRun& r = stage_run_.emplace();
    r.stage = &stage;
    r.plain = plain;
    r.progress = std::move(progress);
    current_ = &r.progress;
    world_.hold_bonds(stage.hold_cracks);
    if (!stage.temperature_field.empty()) r.temperature_field.emplace(stage.temperature_field);
    // Walls move as the stage says; the others stand still (a resumed stage has them so).
    if (!resume) {
      for (std::size_t i = 0; i < world_.walls().size(); ++i) world_.wall(i).velocity.setZero();
      for (const auto& [name, v] : stage.wall_velocity) wall(name).velocity = v;
      if (scenario_.thermal.enabled) quench(stage);
      // A periodic cell stretches at the stage's rates (and stands still without them).
      if (world_.cell()) world_.set_velocity_gradient(stage.cell_strain_rate.asDiagonal());
    }
    // A stress-free cell outside its strain tests ([periodic] stress_control_time).
    if (world_.cell()) {
      const io::PeriodicDef& p = scenario_.periodic;
      world_.set_stress_control(p.stress_control_modulus,
                                stage.cell_strain_rate.isZero(0.0) ? p.stress_control_time : 0.0);
    }
    for (const auto& name : stage.load_walls) r.load_walls.push_back(wall_index(name));
    if (!resume) {
      for (const auto& w : world_.walls()) r.progress.stage_origin.push_back(w.origin);
    }

    std::uint64_t limit = stage.steps > 0 ? stage.steps
                                          : static_cast<std::uint64_t>(std::ceil(stage.time / scenario_.dynamics.dt));
    if (max_steps_ > 0) {
      const std::uint64_t started_at = world_.steps() - r.progress.st.steps;  // the stage's first step
      const std::uint64_t left = max_steps_ > started_at ? max_steps_ - started_at : 0;
      if (left < limit) {
        limit = left;
        r.capped = true;  // the run ends with this stage unless its event comes first
      }
    }
    r.limit = limit;
    r.frame_every = stage.frames > 0 ? std::max<std::uint64_t>(1, limit / stage.frames) : 0;
    r.log_every = std::max<std::uint64_t>(1, limit / 1000);
    r.t0 = std::chrono::steady_clock::now();
    r.i = r.progress.st.steps + 1;  // 1, or the step after the checkpoint
  }

  /// Sets each of `ids` not held by a quench to `kelvin(id)`; a value not above 0 K stops the
  /// run naming the stage, its key, the grain, its centroid and the step.
  template <class F>
  void prescribe_temperatures(const StageDef& stage, const char* key, const std::vector<physics::BodyId>& ids,
                              F&& kelvin) {
    for (const physics::BodyId id : ids) {
      if (world_.slot_thermal()[id.index].held) continue;
      const double t = kelvin(id);
      if (!(t > 0.0)) {
        const Eigen::Vector3d& x = world_.state(id).x;
        throw std::runtime_error(fmt::format("stage '{}': {} gives {:.4g} K at grain {} (x = [{:.6g}, {:.6g}, {:.6g}] m) "
                                             "at step {} of the stage (t = {:.4g} s); keep every grain above 0 K",
                                             stage.name, key, t, world_.info(id).grain_id, x.x(), x.y(), x.z(),
                                             stage_run_->progress.st.steps + 1, world_.time()));
      }
      world_.set_temperature(id, t);
    }
  }

  /// Step i of the stage under way: the step, its fracture check, the events, the
  /// histories, frames and hooks.
  void step_once() {
    StageRun& r = *stage_run_;
    const StageDef& stage = *r.stage;
    const bool plain = r.plain;
    const std::uint64_t i = r.i;
    const std::uint64_t limit = r.limit;
    StageSummary& st = r.progress.st;
    const std::vector<std::size_t>& load_walls = r.load_walls;
    const std::vector<Eigen::Vector3d>& stage_origin = r.progress.stage_origin;
    bool& event = r.progress.event;
    bool& halt = r.halt;
    ++r.i;
    if (stage.ramp_time > 0.0) {
      // The walls' velocities at the middle of this step, on the stage's linear ramp.
      const double t = (static_cast<double>(st.steps) + 0.5) * scenario_.dynamics.dt;
      const double f = std::min(1.0, t / stage.ramp_time);
      for (const auto& [name, v] : stage.wall_velocity) wall(name).velocity = f * v;
    }
    if (stage.temperature_rate != 0.0) {
      // The stage's uniform heating or cooling, this step's share, up to its target.
      world_.ramp_temperature(stage.temperature_rate * scenario_.dynamics.dt, stage.temperature_target);
    }
    if (!stage.temperature_gradient_rate.isZero(0.0)) {
      // The stage's growing linear field, this step's share, about the grains' mean centroid
      // now (held grains keep theirs).
      const auto ids = world_.body_ids();
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (const physics::BodyId id : ids) centre += world_.state(id).x / static_cast<double>(ids.size());
      const double h = scenario_.dynamics.dt;
      prescribe_temperatures(stage, "temperature_gradient_rate", ids, [&](physics::BodyId id) {
        return world_.temperature(id) + h * stage.temperature_gradient_rate.dot(world_.state(id).x - centre);
      });
    }
    if (r.temperature_field) {
      // The stage's prescribed field T(x, y, z, t) at each grain's centroid, t at the end of
      // this step (seconds since the stage began).
      const double t = static_cast<double>(st.steps + 1) * scenario_.dynamics.dt;
      prescribe_temperatures(stage, "temperature_field", world_.body_ids(), [&](physics::BodyId id) {
        const Eigen::Vector3d& x = world_.state(id).x;
        return (*r.temperature_field)(x.x(), x.y(), x.z(), t);
      });
    }
    guard_.before_step(world_);
    bool completed = true;
    // A step whose end the transgranular check reads sums eq. 2.17's terms with its forces.
    sums_for_check_.on = book_ && !stage.hold_cracks &&
                         (world_.steps() + 1) % static_cast<std::uint64_t>(scenario_.fracture.check_every) == 0;
    try {
      world_.step();
    } catch (const std::exception&) {
      // A non-finite state can stop the step part-way (the neighbour search refuses it):
      // that is a blow-up to report as such; anything else is an error of its own.
      if (!guard_.check(world_, false)) throw;
      completed = false;
    }
    ++st.steps;
    std::optional<std::string> failure;
    if (const auto blow_up = guard_.check(world_, completed)) failure = physics::describe(*blow_up, stable_dt_);
    std::optional<double> overlap_now;  // several processes: read with the blow-up and the stop
    bool stop_now = false;
    if (domain()) {
      // One reduction a step for what every process must agree on: the largest overlap,
      // a stop request, and whether (and where first) the step blew up.
      stop_now = hooks_.stop_requested && hooks_.stop_requested();
      std::array<double, 3> v{max_overlap(world_), stop_now ? 1.0 : 0.0,
                              failure ? static_cast<double>(domain()->size() - domain()->rank()) : 0.0};
      domain()->max(v);
      overlap_now = v[0];
      stop_now = v[1] > 0.0;
      if (v[2] > 0.0) failure = domain()->first(failure);  // the lowest process that saw one
    }
    if (failure) {
      sum_.ending = RunEnding::blew_up;
      sum_.failure = *failure;
      record(overlap_now ? *overlap_now : max_overlap(world_), std::nullopt);
      halt = stopped_ = true;
      return;
    }
    if (book_ && !stage.hold_cracks && world_.steps() % static_cast<std::uint64_t>(scenario_.fracture.check_every) == 0) {
      st.splits += split_grains();
    }
    const double overlap = overlap_now ? *overlap_now : max_overlap(world_);
    sum_.max_overlap = std::max(sum_.max_overlap, overlap);
    const auto [load, closure] = machine_reading(world_, load_walls, stage_origin);
    if (!load_walls.empty() && load > st.peak_load) {
      st.peak_load = load;
      st.peak_displacement = closure;
    }
    const std::size_t broken = world_.bond_breaks().size() - r.progress.breaks0;
    switch (stage.until) {
      case StageDef::Until::limit:
        if (plain) event = settled();
        break;
      case StageDef::Until::all_in_contact:
        event = all_in_contact();
        break;
      case StageDef::Until::walls_touch:
        event = std::all_of(load_walls.begin(), load_walls.end(), [&](std::size_t w) {
          return world_.walls()[w].reaction.squaredNorm() > 0.0;
        });
        break;
      case StageDef::Until::load_drop:
        // After the peak, once bonds have broken or grains split (or there are no bonds to
        // break): load that eases off before anything has broken (a rig settling) does not
        // end a test. A crack may run through grains alone (transgranular fracture on,
        // strong bonds): its splits count as the fracture that ends the test.
        event = st.peak_load > 0.0 && load < stage.load_drop * st.peak_load &&
                (broken > 0 || st.splits > 0 || world_.bonds().empty());
        break;
    }
    if (i % r.log_every == 0 || i == limit || event) {
      if (record(overlap,
                 load_walls.empty() ? std::nullopt : std::optional(std::pair(load, closure))) &&
          !load_walls.empty()) {
        r.progress.plot_x.push_back(closure);
        r.progress.plot_y.push_back(load);
      }
    }
    if (sum_.ending != RunEnding::blew_up && r.frame_every && (i % r.frame_every == 0))
      write_frame();
    // A value that is not finite in a row or frame of this step ends the run here (failed),
    // before a checkpoint would keep the state.
    if (sum_.ending == RunEnding::blew_up) return;
    const RunPoint point{world_, stage.name, stage_index_, st.steps, book_ ? &*book_ : nullptr,
                         [this] { return encode_run_state(); }};
    if (hooks_.on_checkpoint && hooks_.checkpoint_every > 0 &&
        world_.steps() % hooks_.checkpoint_every == 0) {
      if (domain()) domain()->gather_all(world_);  // the whole world into the checkpoint
      hooks_.on_checkpoint(point);
    }
    // Several processes stop after the same step (the request was read with the overlap).
    const bool stop = domain() ? stop_now : hooks_.stop_requested && hooks_.stop_requested();
    if (stop) {
      sum_.ending = RunEnding::interrupted;
      // The checkpoint first: a restart continues the histories as if never stopped.
      if (hooks_.on_interrupt) {
        if (domain()) domain()->gather_all(world_);
        hooks_.on_interrupt(point);
      }
      if (i % r.log_every != 0 && i != limit && !event) {
        record(overlap, load_walls.empty() ? std::nullopt : std::optional(std::pair(load, closure)));
      }
      halt = stopped_ = true;
    }
    if (!quiet_ && root_ && (seconds_since(r.last_print) > 1.0 || i == limit || event || halt)) {
      r.last_print = std::chrono::steady_clock::now();
      const double elapsed = seconds_since(r.t0);
      const double left = elapsed / static_cast<double>(i) * static_cast<double>(limit - i);
      std::string line = fmt::format(
          "\r  stage {:<12} step {}/{}  t = {:.4g} s  bodies {}  contacts {}  KE {:.3g} J",
          stage.name, i, limit, world_.time(), world_.body_count(),
          domain() ? last_contacts_ : world_.contacts().size(), domain() ? last_kinetic_ : world_.kinetic_energy());
      if (!world_.bonds().empty()) {
        line += fmt::format("  bonds {}/{} broken", world_.bond_counts().broken(), world_.bonds().size());
      }
      if (book_) line += fmt::format("  splits {}", sum_.splits);
      if (!load_walls.empty()) line += fmt::format("  load {:.4g} N", load);
      line += eta_text(stage, plain && scenario_.dynamics.settle_ratio > 0.0, left);
      std::fputs(line.c_str(), stderr);
      progress_shown_ = true;
    }
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
      write_plot(stage, st, r.progress.plot_x, r.progress.plot_y);
    }
    breaks_by_stage_.emplace_back(world_.bond_breaks().size(), stage.name);
    std::string modulus_line;
    if (stage.measure_modulus) modulus_line = measure_modulus(stage);
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

  /// The loop's own state for a checkpoint, taken inside a motion stage (run_stage).
  std::string encode_run_state() const {
    if (!current_) throw std::logic_error("encode_run_state: not inside a stage");
    physics::StateWriter w;
    w.put(kRunStateLayout);
    w.put<std::uint64_t>(stage_index_);
    w.put(stage_);
    put_summary(w, current_->st);
    w.put<std::uint64_t>(current_->breaks0);
    w.put(current_->stage_origin);
    w.put(current_->plot_x);
    w.put(current_->plot_y);
    w.put(current_->event);
    w.put<std::int32_t>(sum_.frames);
    w.put(sum_.max_overlap);
    w.put<std::uint64_t>(sum_.bonds);
    w.put<std::uint64_t>(sum_.splits);
    w.count(sum_.stages.size());
    for (const auto& st : sum_.stages) put_summary(w, st);
    w.put(origin0_);
    w.put(pe0_);
    for (const std::string* s : {&energy_, &walls_, &loads_, &bond_counts_, &splits_, &thermal_, &cell_, &modulus_})
      w.put(*s);
    w.put(cell0_);
    w.count(breaks_by_stage_.size());
    for (const auto& [end, name] : breaks_by_stage_) {
      w.put<std::uint64_t>(end);
      w.put(name);
    }
    w.put(last_frame_step_);
    for (const io::PvdSeries* pvd : {&bodies_pvd_, &contacts_pvd_, &bonds_pvd_, &cell_pvd_}) {
      w.count(pvd->entries().size());
      for (const auto& e : pvd->entries()) {
        w.put(e.time);
        w.put(e.file);
        w.put<std::int32_t>(e.part);
      }
    }
    return w.take();
  }

  /// Takes back what encode_run_state saved; returns the progress of the stage it was in
  /// (and sets stage_index_ to that stage).
  StageProgress decode_run_state(const std::string& bytes) {
    physics::StateReader r(bytes);
    StageProgress p;
    try {
      if (const auto layout = r.get<std::uint32_t>(); layout != kRunStateLayout) {
        r.fail(fmt::format("run state layout {} is not supported (this build reads {})", layout, kRunStateLayout));
      }
      stage_index_ = r.get<std::uint64_t>();
      const std::size_t stages = std::max<std::size_t>(1, scenario_.stages.size());
      if (stage_index_ >= stages) r.fail("the stage index is beyond the scenario's stages");
      stage_ = r.string();
      const std::string expected = scenario_.stages.empty() ? "run" : scenario_.stages[stage_index_].name;
      if (stage_ != expected) {
        r.fail(fmt::format("the checkpoint is in stage '{}' but the scenario's stage {} is '{}'", stage_,
                           stage_index_ + 1, expected));
      }
      p.st = get_summary(r);
      p.breaks0 = r.get<std::uint64_t>();
      p.stage_origin = r.vec3s();
      p.plot_x = r.numbers<double>();
      p.plot_y = r.numbers<double>();
      p.event = r.get_bool();
      sum_.frames = r.get<std::int32_t>();
      sum_.max_overlap = r.get<double>();
      sum_.bonds = r.get<std::uint64_t>();
      sum_.splits = r.get<std::uint64_t>();
      sum_.stages.resize(r.count(8));
      for (auto& st : sum_.stages) st = get_summary(r);
      origin0_ = r.vec3s();
      pe0_ = r.get<double>();
      for (std::string* s : {&energy_, &walls_, &loads_, &bond_counts_, &splits_, &thermal_, &cell_, &modulus_})
        *s = r.string();
      cell0_ = r.vec3();
      breaks_by_stage_.resize(r.count(16));
      for (auto& [end, name] : breaks_by_stage_) {
        end = r.get<std::uint64_t>();
        name = r.string();
      }
      last_frame_step_ = r.get<std::uint64_t>();
      for (io::PvdSeries* pvd : {&bodies_pvd_, &contacts_pvd_, &bonds_pvd_, &cell_pvd_}) {
        std::vector<io::PvdSeries::Entry> entries(r.count(16));
        for (auto& e : entries) {
          e.time = r.get<double>();
          e.file = r.string();
          e.part = r.get<std::int32_t>();
        }
        pvd->restore(std::move(entries));
      }
      // The walls and cracks are written with every bodies frame (write_frame): their lists
      // are the bodies' under their own names.
      for (auto [pvd, name] : {std::pair{&walls_pvd_, "walls_"}, std::pair{&cracks_pvd_, "cracks_"}}) {
        if (!(pvd == &walls_pvd_ ? writes_walls() : writes_cracks())) continue;
        std::vector<io::PvdSeries::Entry> entries = bodies_pvd_.entries();
        for (auto& e : entries) e.file.replace(e.file.find("bodies_"), 7, name);
        pvd->restore(std::move(entries));
      }
      if (!r.done()) r.fail("unread bytes after the run state");
      if (origin0_.size() != world_.walls().size() || p.stage_origin.size() != world_.walls().size()) {
        r.fail("the walls of the run state do not match the world's");
      }
    } catch (const physics::StateError& e) {
      throw std::runtime_error(fmt::format("checkpoint run state: {}", e.what()));
    }
    return p;
  }

  /// The transgranular check of sec. 3.4 on every body; logs each split. Returns how many.
  std::size_t split_grains() {
    const auto t0 = std::chrono::steady_clock::now();
    const auto events = physics::transgranular_step(world_, *book_, scenario_.fracture.params);
    if (hooks_.timing) check_seconds_ += seconds_since(t0);
    for (const auto& e : events) {
      std::string pieces;
      for (const auto& l : e.split.pieces) pieces += (pieces.empty() ? "" : " ") + l.path_string();
      const auto& r = e.cause.result;
      splits_ += fmt::format(
          "{:.9g},{},{},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n",
          e.split.time, world_.steps(), stage_, e.split.parent.grain_id, e.split.parent.path_string(), pieces,
          e.split.plane, e.split.normal.x(), e.split.normal.y(), e.split.normal.z(), e.split.point.x(),
          e.split.point.y(), e.split.point.z(), r.mean_stress, e.cause.stresses.sigma, e.cause.stresses.tau,
          r.k_i, r.k_ii, r.criterion);
    }
    sum_.splits += events.size();
    // A piece is lighter than its grain, and a thin one turns faster on the same springs:
    // the step checked for the grains may not be stable for it. By the same (conservative:
    // the stiffest spring at the bounding radius) bound, say so once. Where such a piece
    // touches a platen or roller, the run may blow up a few steps later, or first throw a
    // load spike that a load_drop stage would take for the peak.
    for (const auto& e : events) {
      for (const physics::BodyId id : e.split.ids) {
        if (piece_warned_) break;
        const physics::BodyInfo& info = world_.info(id);
        const double limit = sim::stable_time_step(scenario_, info.mass, info.inertia.minCoeff(),
                                                  world_.shape(info.shape).bounding_radius());
        if (scenario_.dynamics.dt > limit) {
          piece_warned_ = true;
          if (!root_) break;  // several processes: the first says it
          fmt::print(stderr,
                     "cleave: warning: step {}: grain {} split into a piece of {:.3g} kg (smallest principal "
                     "moment {:.3g} kg m^2) whose stable step by the grains' bound is {:.3g} s, below dt = "
                     "{:.3g} s; if the run blows up or its load spikes after a split, use [dynamics] dt <= "
                     "{:.3g} s\n",
                     world_.steps(), e.split.parent.grain_id, info.mass, info.inertia.minCoeff(), limit,
                     scenario_.dynamics.dt, limit);
        }
      }
    }
    return events.size();
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
    const double released = pe0_ - potential_energy();
    const double ratio = scenario_.dynamics.settle_ratio;
    return ratio > 0.0 && released > 0.0 && contact_count() > 0 && kinetic_energy() < ratio * released;
  }

  /// Every body touches another body (its dilated surface overlaps another's).
  bool all_in_contact() {
    touched_.clear();
    for (const auto& c : world_.contacts()) {
      if (c.wall || c.overlap <= 0.0) continue;
      const std::size_t top = std::max(c.a, c.b) + 1;
      if (touched_.size() < top) touched_.resize(top, 0);
      touched_[c.a] = touched_[c.b] = 1;
    }
    bool all = true;
    for (const physics::BodyId id : world_.body_ids()) {
      if (!world_.owns(id.index)) continue;  // one process of several answers for its own bodies
      if (id.index >= touched_.size() || !touched_[id.index]) {
        all = false;
        break;
      }
    }
    return domain() ? !domain()->any(!all) : all;
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

  std::size_t wall_index(const std::string& name) const {
    for (std::size_t i = 0; i < world_.walls().size(); ++i) {
      if (world_.walls()[i].name == name) return i;
    }
    throw std::logic_error("no wall named " + name);  // the scenario reader checked names
  }
  physics::Wall& wall(const std::string& name) { return world_.wall(wall_index(name)); }

  /// A stage's thermal shock: the grains within quench_depth of the wall's plane held at
  /// quench_temperature; those a previous stage held are let go first. (The held flags are
  /// part of the world's state, so a resumed stage has them already.)
  void quench(const StageDef& stage) {
    for (const physics::BodyId id : world_.body_ids()) world_.set_temperature_held(id, false);
    if (stage.quench_wall.empty()) return;
    const physics::Wall& w = wall(stage.quench_wall);
    const Eigen::Vector3d n = w.normal.normalized();
    for (const physics::BodyId id : world_.body_ids()) {
      if (std::abs((world_.state(id).x - w.origin).dot(n)) > stage.quench_depth) continue;
      world_.set_temperature(id, stage.quench_temperature);
      world_.set_temperature_held(id, true);
    }
  }

  /// One row of every history; `reading` is the stage's (load, load-point displacement)
  /// when it has load walls. A row holding a value that is not finite is not written: the
  /// run fails there (non_finite) and the tables keep only finite rows. Returns whether the
  /// row was written.
  bool record(double overlap, std::optional<std::pair<double, double>> reading) {
    const double kinetic = kinetic_energy(), potential = potential_energy();
    const std::size_t contacts = contact_count();
    // What the row would say that is not finite: the first such column, named.
    std::string bad;
    auto check = [&bad](bool finite, auto&& name) {
      if (bad.empty() && !finite) bad = name();
    };
    check(std::isfinite(kinetic),
          [] { return std::string("the kinetic energy (energy.csv kinetic_J)"); });
    check(std::isfinite(potential),
          [] { return std::string("the potential energy (energy.csv potential_J)"); });
    check(std::isfinite(overlap),
          [] { return std::string("the largest overlap (energy.csv max_overlap_m)"); });
    std::vector<WallReading> wall_readings;
    for (std::size_t i = 0; i < world_.walls().size(); ++i) {
      const auto& w = world_.walls()[i];
      wall_readings.push_back(read_wall(w, origin0_[i]));
      auto name = [&](const char* what) {
        return [&, what] { return fmt::format("wall {} ('{}'): its {}", i, w.name, what); };
      };
      check(w.reaction.allFinite(), name("reaction (walls.csv)"));
      check(std::isfinite(wall_readings.back().displacement),
            name("displacement (load_displacement.csv)"));
      check(std::isfinite(wall_readings.back().force), name("force (load_displacement.csv)"));
    }
    if (reading) {
      check(std::isfinite(reading->first),
            [] { return std::string("the load (load_displacement.csv load_N)"); });
      check(std::isfinite(reading->second),
            [] { return std::string("the load-point displacement (load_displacement.csv)"); });
    }
    double sum = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    std::size_t bodies = 0;
    if (scenario_.thermal.enabled) {
      for (const physics::BodyId id : world_.body_ids()) {
        const double t = world_.temperature(id);
        check(std::isfinite(t), [&] {
          return fmt::format("body {} (grain {}): its temperature (thermal.csv)", id.index,
                             world_.info(id).grain_id);
        });
        sum += t;
        lo = std::min(lo, t);
        hi = std::max(hi, t);
        ++bodies;
      }
    }
    Eigen::Vector3d cell_l, cell_e;
    Eigen::Matrix3d cell_sg;
    const physics::PeriodicCell* cell = world_.cell();
    if (cell) {
      // The cell's size, its strain from the start, and the mean stress in it.
      cell_l = cell->vectors().colwise().norm().transpose();
      cell_e = cell_l.cwiseQuotient(cell0_) - Eigen::Vector3d::Ones();
      cell_sg = world_.cell_stress();
      check(cell_l.allFinite() && cell_e.allFinite(),
            [] { return std::string("the periodic cell's size (cell.csv)"); });
      check(cell_sg.allFinite(),
            [] { return std::string("the periodic cell's stress (cell.csv)"); });
    }
    std::optional<std::string> failure;
    if (!bad.empty()) failure = bad;
    if (domain() && domain()->any(failure.has_value())) failure = domain()->first(failure);
    if (failure) {
      non_finite(*failure +
                 " is not finite (NaN or infinite) in the history row of this step, which is not "
                 "written");
      return false;
    }

    last_kinetic_ = kinetic;
    last_contacts_ = contacts;
    energy_ += fmt::format("{:.9g},{:.9g},{:.9g},{},{:.6g},{}\n", world_.time(), kinetic, potential,
                           contacts, overlap, stage_);
    walls_ += fmt::format("{:.9g}", world_.time());
    loads_ += fmt::format("{:.9g},{},{}", world_.time(), world_.steps(), stage_);
    for (std::size_t i = 0; i < world_.walls().size(); ++i) {
      const auto& w = world_.walls()[i];
      walls_ += fmt::format(",{:.9g},{:.9g},{:.9g}", w.reaction.x(), w.reaction.y(), w.reaction.z());
      loads_ +=
          fmt::format(",{:.9g},{:.9g}", wall_readings[i].displacement, wall_readings[i].force);
    }
    walls_ += "\n";
    loads_ += reading ? fmt::format(",{:.9g},{:.9g}\n", reading->first, reading->second) : ",,\n";
    if (!world_.bonds().empty()) {
      const physics::BondCounts c = world_.bond_counts();
      bond_counts_ += fmt::format("{:.9g},{},{},{},{},{},{}\n", world_.time(), stage_, c.intact,
                                  c.tension, c.shear, c.bending, c.torsion);
    }
    if (scenario_.thermal.enabled) {
      const physics::BondCounts c = world_.bond_counts();
      thermal_ += fmt::format("{:.9g},{},{:.9g},{:.9g},{:.9g},{},{},{}\n", world_.time(), stage_,
                              bodies == 0 ? 0.0 : sum / static_cast<double>(bodies), lo, hi,
                              c.intact, c.tension + c.shear + c.bending + c.torsion, sum_.splits);
    }
    if (cell) {
      const Eigen::Vector3d& l = cell_l;
      const Eigen::Vector3d& e = cell_e;
      const Eigen::Matrix3d& sg = cell_sg;
      cell_ += fmt::format("{:.9g},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n",
                           world_.time(), stage_, l.x(), l.y(), l.z(), e.x(), e.y(), e.z(), sg(0, 0), sg(1, 1), sg(2, 2),
                           sg(1, 2), sg(0, 2), sg(0, 1));
    }
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

  bool writes_walls() const { return !world_.walls().empty(); }
  bool writes_cracks() const { return scenario_.bond.enabled || book_.has_value(); }

  /// `gathered`: on several processes, the whole world is here already. A frame holding a
  /// value that is not finite is not written: the run fails there (non_finite), naming the
  /// item. Returns whether it was written.
  bool write_frame(bool gathered = false) {
    if (domain() && !gathered) domain()->gather_all(world_, true);  // the whole world, its contacts too
    // A second frame at the step of the last one (the bond stage right after the first
    // frame) replaces it: every series lists each time once.
    const bool again = sum_.frames > 0 && world_.steps() == last_frame_step_;
    // Built first, then checked, then written: a frame is written whole or not at all.
    std::optional<io::BodyFrame> bodies, walls, cracks;
    std::optional<io::LinkFrame> contacts, bonds, cell_edges;
    std::optional<std::string> bad;
    if (root_) {  // several processes: the first writes the frames
      bodies = body_frame(world_, specimen_);
      contacts = contact_frame(world_);
      if (scenario_.bond.enabled) bonds = bond_frame(world_);
      if (const physics::PeriodicCell* cell = world_.cell()) cell_edges = cell_frame(*cell);
      if (writes_walls()) walls = io::wall_frame(world_);
      if (writes_cracks()) cracks = io::crack_frame(world_, book_ ? &*book_ : nullptr);
      const std::vector<physics::BodyId> ids = world_.body_ids();
      auto body_name = [&](std::size_t row) {
        return row < ids.size() ? fmt::format("body {} (grain {})", ids[row].index,
                                              world_.info(ids[row]).grain_id)
                                : fmt::format("body row {}", row);
      };
      auto wall_name = [&](std::size_t row) {
        return row < world_.walls().size()
                   ? fmt::format("wall {} ('{}')", row, world_.walls()[row].name)
                   : fmt::format("wall row {}", row);
      };
      auto numbered = [](const char* what) {
        return [what](std::size_t row) { return fmt::format("{} {}", what, row); };
      };
      if (!bad && bodies) bad = non_finite_in(*bodies, "bodies", body_name);
      if (!bad && contacts) bad = non_finite_in(*contacts, "contacts", numbered("contact"));
      if (!bad && bonds) bad = non_finite_in(*bonds, "bonds", numbered("bond"));
      if (!bad && cell_edges) bad = non_finite_in(*cell_edges, "cell", numbered("cell edge"));
      if (!bad && walls) bad = non_finite_in(*walls, "walls", wall_name);
      // A crack face's broken_at_s is NaN on purpose for split sections (no bond broke): only
      // its place is checked.
      if (!bad && cracks) bad = non_finite_in(cracks->meshes, "cracks", numbered("crack face"));
    }
    if (domain() && domain()->any(bad.has_value())) bad = domain()->first(bad);
    if (bad) {
      non_finite(
          *bad +
          " is not finite (NaN or infinite) in the frame of this step, which is not written");
      return false;
    }
    if (!root_) {
      if (!again) ++sum_.frames;
      last_frame_step_ = world_.steps();
      return true;
    }
    const std::string stem = fmt::format("{:06d}", again ? sum_.frames - 1 : sum_.frames);
    const fs::path dir = "frames";
    auto write = [&](io::PvdSeries& pvd, const std::string& kind, const auto& frame) {
      const fs::path file = dir / (kind + "_" + stem + ".vtp");
      io::write_vtp(out_ / file, frame);
      pvd.add(world_.time(), file);
    };
    write(bodies_pvd_, "bodies", *bodies);
    write(contacts_pvd_, "contacts", *contacts);
    if (bonds) write(bonds_pvd_, "bonds", *bonds);
    if (cell_edges) write(cell_pvd_, "cell", *cell_edges);
    if (walls) write(walls_pvd_, "walls", *walls);
    if (cracks) write(cracks_pvd_, "cracks", *cracks);
    if (scenario_.output.frame_meshes) write_frame_meshes(stem);
    if (!again) ++sum_.frames;
    last_frame_step_ = world_.steps();
    return true;
  }

  /// The first value of a frame that is not finite, as "<item>: its <field> (<file>)".
  template <class Name>
  static std::optional<std::string> non_finite_in(const io::FieldSet& fields, const char* file,
                                                  Name&& item) {
    for (const auto& [field, values] : fields.scalars) {
      for (std::size_t k = 0; k < values.size(); ++k)
        if (!std::isfinite(values[k]))
          return fmt::format("{}: its {} ({} frame)", item(k), field, file);
    }
    for (const auto& [field, values] : fields.vectors) {
      for (std::size_t k = 0; k < values.size(); ++k)
        if (!values[k].allFinite())
          return fmt::format("{}: its {} ({} frame)", item(k), field, file);
    }
    return std::nullopt;
  }
  template <class Name>
  static std::optional<std::string> non_finite_in(const std::vector<geometry::PolygonMesh>& meshes,
                                                  const char* file, Name&& item) {
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      for (const Eigen::Vector3d& v : meshes[k].vertices)
        if (!v.allFinite())
          return fmt::format("{}: its place (a vertex of its mesh, {} frame)", item(k), file);
    }
    return std::nullopt;
  }
  template <class Name>
  static std::optional<std::string> non_finite_in(const io::BodyFrame& frame, const char* file,
                                                  Name&& item) {
    if (auto bad = non_finite_in(frame.meshes, file, item)) return bad;
    return non_finite_in(frame.body_fields, file, item);
  }
  template <class Name>
  static std::optional<std::string> non_finite_in(const io::LinkFrame& frame, const char* file,
                                                  Name&& item) {
    for (std::size_t k = 0; k < frame.a.size(); ++k) {
      if (!frame.a[k].allFinite() || (k < frame.b.size() && !frame.b[k].allFinite()))
        return fmt::format("{}: its end points ({} frame)", item(k), file);
    }
    return non_finite_in(frame.fields, file, item);
  }

  /// Every body as a mesh in its world pose, named by its lineage (grain_0017.1.0), in a
  /// folder of the frame's own (frame_meshes/frame_NNNNNN/): per-fragment files of
  /// different frames never meet.
  void write_frame_meshes(const std::string& stem) {
    std::vector<geometry::PolygonMesh> meshes;
    for (const physics::BodyId id : world_.body_ids()) {
      geometry::PolygonMesh mesh = world_mesh(world_, id);
      mesh.name = book_ && book_->knows(id) ? book_->lineage(id).name()
                                            : geometry::Lineage{world_.info(id).grain_id, {}}.name();
      meshes.push_back(std::move(mesh));
    }
    const fs::path folder = out_ / "frame_meshes" / ("frame_" + stem);
    fs::remove_all(folder);  // a frame rewritten at the same step, or after a restart
    io::write_meshes(meshes, folder, "frame_" + stem, scenario_.output.mesh_format,
                     scenario_.output.mesh_layout);
  }

  /// Rows of a CSV history (header first) whose column `stage` (index 1) is `name`, split.
  static std::vector<std::vector<std::string>> rows_of(const std::string& csv, const std::string& name) {
    std::vector<std::vector<std::string>> rows;
    std::size_t at = csv.find('\n') + 1;
    while (at < csv.size()) {
      const std::size_t end = csv.find('\n', at);
      std::vector<std::string> cells;
      std::size_t a = at;
      while (true) {
        const std::size_t comma = csv.find(',', a);
        if (comma == std::string::npos || comma > end) {
          cells.push_back(csv.substr(a, end - a));
          break;
        }
        cells.push_back(csv.substr(a, comma - a));
        a = comma + 1;
      }
      if (name.empty() || (cells.size() > 1 && cells[1] == name)) rows.push_back(std::move(cells));
      at = end + 1;
    }
    return rows;
  }

  /// The stage's uniaxial strain test of the periodic cell: the slopes of the normal
  /// stresses against the strain along the stretched axis (least squares over the last 70 %
  /// of the stage's rows of cell.csv), read for an isotropic solid. The lateral axes that are periodic are
  /// held (uniaxial strain), the others free:
  ///   both held: nu = s_l / (s_a + s_l), E = s_a - 2 nu s_l (s_l: the lateral slopes' mean);
  ///   one held:  nu = s_l / s_a, E = s_a (1 - nu^2) (plane stress);
  ///   none:      E = s_a (uniaxial stress; nu not measured).
  /// Appends a row to modulus.csv and returns a line for the log.
  std::string measure_modulus(const StageDef& stage) {
    int axis = 0;
    for (int k = 0; k < 3; ++k) {
      if (stage.cell_strain_rate[k] != 0.0) axis = k;
    }
    // The stage's rows, the first 30 % left out (the cell's stress catching up with its strain).
    auto rows = rows_of(cell_, stage.name);
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
      if (k != axis && world_.cell()->periodic(k)) lateral.push_back(slope[k]);
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
      const auto ids = world_.body_ids();
      mean_k = 0.0;
      for (const physics::BodyId id : ids) mean_k += world_.temperature(id) / static_cast<double>(ids.size());
    }
    const physics::BondCounts c = world_.bond_counts();
    const double strain = std::stod(rows.back().at(5 + static_cast<std::size_t>(axis)));
    auto field = [](double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); };
    modulus_ += fmt::format("{},{:.9g},{},{},{:.9g},{:.9g},{},{},{}\n", stage.name, world_.time(), field(mean_k), "xyz"[axis],
                            strain, young, field(nu), c.broken(), sum_.splits);
    std::string line = fmt::format("E = {:.4g} GPa", young * 1e-9);
    if (std::isfinite(nu)) line += fmt::format(", nu = {:.3f}", nu);
    if (std::isfinite(mean_k)) line += fmt::format(" at {:.0f} K", mean_k);
    return line;
  }

  /// modulus.svg: the measured Young's moduli against temperature (or against the stage
  /// order when there is no [thermal]).
  void write_modulus_plot() {
    io::Plot plot;
    plot.title = fmt::format("{}: Young's modulus of the periodic cell", scenario_.name);
    const bool thermal = scenario_.thermal.enabled;
    plot.x_label = thermal ? "mean temperature (K)" : "modulus stage";
    plot.y_label = "Young's modulus E (GPa)";
    io::PlotSeries series;
    series.label = "E from the cell's uniaxial strain test";
    series.markers = true;
    int k = 0;
    for (const auto& row : rows_of(modulus_, "")) {
      series.x.push_back(thermal && !row.at(2).empty() ? std::stod(row.at(2)) : ++k);
      series.y.push_back(std::stod(row.at(5)) * 1e-9);
    }
    plot.series.push_back(std::move(series));
    io::write_plot_svg(out_ / "modulus.svg", plot);
  }

  /// microcracks.svg: broken bonds (intergranular) and grain splits (transgranular)
  /// against the mean temperature, from thermal.csv.
  void write_microcrack_plot() {
    io::Plot plot;
    plot.title = fmt::format("{}: microcracks against temperature", scenario_.name);
    plot.x_label = "mean temperature (K)";
    plot.y_label = "cracks";
    io::PlotSeries bonds, splits;
    bonds.label = "broken bonds (intergranular)";
    splits.label = "grain splits (transgranular)";
    for (const auto& row : rows_of(thermal_, "")) {
      const double t = std::stod(row.at(2));
      bonds.x.push_back(t);
      bonds.y.push_back(std::stod(row.at(6)));
      splits.x.push_back(t);
      splits.y.push_back(std::stod(row.at(7)));
    }
    plot.series.push_back(std::move(bonds));
    if (book_) plot.series.push_back(std::move(splits));
    io::write_plot_svg(out_ / "microcracks.svg", plot);
  }

  void write_plot(const StageDef& stage, const StageSummary& st, const std::vector<double>& x,
                  const std::vector<double>& y) {
    io::Plot plot;
    plot.title = fmt::format("{}: stage '{}'", scenario_.name, stage.name);
    plot.x_label = "load-point displacement (mm)";
    plot.y_label = "load P (N)";
    io::PlotSeries series;
    series.label = fmt::format("load on {}", fmt::join(stage.load_walls, ", "));
    for (double v : x) series.x.push_back(v * 1e3);
    series.y = y;
    plot.series.push_back(std::move(series));
    if (st.peak_load > 0.0) {
      plot.markers.push_back({st.peak_displacement * 1e3, st.peak_load,
                              fmt::format("peak {:.4g} N", st.peak_load)});
    }
    io::write_plot_svg(out_ / st.plot, plot);
  }

  /// timing.csv: seconds in each part of the steps since the run (or its restart) began,
  /// milliseconds a step and share, the transgranular check after them; the summary's table.
  void write_timing() {
    const physics::StepTimings& t = world_.timings();
    const double steps = static_cast<double>(std::max<std::uint64_t>(t.steps, 1));
    const double total = t.total() + check_seconds_;
    std::string csv = "part,wall_s,wall_ms_per_step,share,steps\n";
    std::string table = fmt::format("  timing     {} steps clocked, {:.3f} ms a step:", t.steps, 1e3 * total / steps);
    auto row = [&](const char* name, double seconds) {
      const double share = total > 0.0 ? seconds / total : 0.0;
      csv += fmt::format("{},{:.6f},{:.6f},{:.4f},{}\n", name, seconds, 1e3 * seconds / steps, share, t.steps);
      table += fmt::format("\n             {:<20} {:9.4f} ms/step {:5.1f} %", name, 1e3 * seconds / steps, 100.0 * share);
    };
    for (std::size_t k = 0; k < physics::kStepPhases; ++k)
      row(physics::to_string(static_cast<physics::StepPhase>(k)), t.seconds[k]);
    if (book_) row("transgranular_check", check_seconds_);
    csv += fmt::format("total,{:.6f},{:.6f},1,{}\n", total, 1e3 * total / steps, t.steps);
    if (root_) io::write_file_atomically(out_ / "timing.csv", csv);
    sum_.timing = table;
  }

  void write_tables() {
    if (hooks_.timing) write_timing();
    io::write_file_atomically(out_ / "energy.csv", energy_);
    io::write_file_atomically(out_ / "walls.csv", walls_);
    io::write_file_atomically(out_ / "load_displacement.csv", loads_);
    if (book_) io::write_file_atomically(out_ / "splits.csv", splits_);
    if (scenario_.thermal.enabled) io::write_file_atomically(out_ / "thermal.csv", thermal_);
    if (!cell_.empty()) io::write_file_atomically(out_ / "cell.csv", cell_);
    if (modulus_.find('\n') + 1 < modulus_.size()) {
      io::write_file_atomically(out_ / "modulus.csv", modulus_);
      write_modulus_plot();
    }
    if (scenario_.thermal.enabled && !world_.bonds().empty()) write_microcrack_plot();
    if (!scenario_.bond.enabled) return;
    io::write_file_atomically(out_ / "bonds.csv", bond_counts_);
    std::string breaks =
        "time_s,step,stage,bond,body_a,body_b,grain_a,grain_b,x_m,y_m,z_m,nx,ny,nz,mode,"
        "normal_force_N,shear_force_N,bending_moment_Nm,torsion_moment_Nm\n";
    const auto& all = world_.bond_breaks();
    std::size_t stage = 0;
    for (std::size_t k = 0; k < all.size(); ++k) {
      while (stage < breaks_by_stage_.size() && k >= breaks_by_stage_[stage].first) ++stage;
      const std::string name = stage < breaks_by_stage_.size() ? breaks_by_stage_[stage].second : stage_;
      const physics::BondBreak& b = all[k];
      breaks += fmt::format(
          "{:.9g},{},{},{},{},{},{},{},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{},{:.9g},{:.9g},{:.9g},{:.9g}\n",
          b.time, b.step, name, b.bond, b.a, b.b, b.grain_a, b.grain_b, b.point.x(), b.point.y(),
          b.point.z(), b.normal.x(), b.normal.y(), b.normal.z(), physics::to_string(b.mode),
          b.loads.normal, b.loads.shear.norm(), b.loads.bending.norm(), std::abs(b.loads.torsion));
    }
    io::write_file_atomically(out_ / "bond_breaks.csv", breaks);
  }

  const io::Scenario& scenario_;
  const geometry::Specimen& specimen_;
  fs::path out_;
  bool quiet_;
  bool root_ = true;  // the process that prints (the first of several)
  double check_seconds_ = 0.0;  // RunHooks::timing: the transgranular checks' wall time
  double last_kinetic_ = 0.0;       // the last history row's, for the progress line
  std::size_t last_contacts_ = 0;
  std::uint64_t max_steps_;
  RunHooks hooks_;
  physics::StepGuard guard_;
  bool piece_warned_ = false;  ///< a split made a piece the time step may not be stable for (said once)
  std::size_t stage_index_ = 0;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
  physics::World world_;
  /// Asks a step for eq. 2.17's sums when the transgranular check reads its end.
  struct SumsForCheck final : physics::StepListener {
    bool on = false;
    [[nodiscard]] physics::StepNeeds needs(const physics::World&) const override { return {.stress_sums = on}; }
  } sums_for_check_;
  double stable_dt_ = sim::stable_time_step(scenario_, specimen_);  // for blow-up messages
  io::PvdSeries bodies_pvd_, contacts_pvd_, bonds_pvd_, cell_pvd_, walls_pvd_, cracks_pvd_;
  std::vector<Eigen::Vector3d> origin0_;
  double pe0_ = 0.0;
  std::string energy_, walls_, loads_, bond_counts_, splits_, thermal_;
  std::string cell_, modulus_;  // cell.csv, modulus.csv (periodic cells)
  Eigen::Vector3d cell0_ = Eigen::Vector3d::Ones();  // the cell's edge lengths at the start
  std::optional<physics::FractureBook> book_;
  std::string stage_;
  std::vector<std::pair<std::size_t, std::string>> breaks_by_stage_;  // (end index, stage)
  std::vector<char> touched_;
  std::uint64_t last_frame_step_ = ~0ull;
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
                   RunResume* resume)
    : runner_(std::make_unique<Runner>(scenario, specimen, out, quiet, max_steps, hooks, resume)) {}
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
