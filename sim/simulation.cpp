// One run: scenario -> specimen -> cleavage slabs -> (dynamics) -> result folder.

#include "sim/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <tuple>

#include "cleave_version.hpp"
#include "io/checkpoint.hpp"
#include "io/exact_store.hpp"
#include "io/fragment_sizes.hpp"
#include "io/mesh_io.hpp"
#include "io/plot.hpp"
#include "io/provenance.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"
#include "io/sweep.hpp"
#include "sim/specimen_picture.hpp"
#include "sim/world_assembly.hpp"

namespace cleave::sim {

namespace {

namespace fs = std::filesystem;
using geometry::Piece;
using geometry::Specimen;

class Stopwatch {
 public:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// The specimen line for grains off the lattice (Voronoi cells, mesh grains).
std::string describe_own_grains(const Specimen& s) {
  const auto& def = s.def;
  if (def.kind == geometry::SpecimenKind::voronoi) {
    const Eigen::Vector3d mm = def.voronoi.size * 1e3;
    const geometry::ExactScalar cells = geometry::total_volume(s.shapes);
    const geometry::ExactScalar domain = geometry::voronoi_domain(def.voronoi).volume();
    const bool disc = def.voronoi.domain == geometry::VoronoiDomain::disc;
    const std::string name = disc ? "disc" : "box";
    return fmt::format(
        "  specimen   {} {} in a {} (point seed {}, gap {:g} mm); the cells' exact volumes {}",
        s.grains.size(),
        def.voronoi.lognormal
            ? fmt::format("Laguerre cells (log-normal sizes, spread {:g})", def.voronoi.size_spread)
            : std::string("Voronoi cells"),
        disc ? fmt::format("disc {:g} mm across, {:g} mm thick ({}-gon)", mm.x(), mm.z(),
                           def.voronoi.sides)
             : fmt::format("box {:g} x {:g} x {:g} mm", mm.x(), mm.y(), mm.z()),
        def.voronoi.seed, def.voronoi.gap * 1e3,
        cells == domain ? "sum exactly to the " + name + "'s"
                        : fmt::format("fill {:.2f}% of the {}",
                                      100 * cells.to_double() / domain.to_double(), name));
  }
  std::string names;
  for (std::size_t i = 0; i < def.custom_grains.size(); ++i) {
    if (i == 3 && def.custom_grains.size() > 4) {  // an imported tessellation has many
      names += fmt::format(", ... {}", def.custom_grains.back().name);
      break;
    }
    names += (names.empty() ? "" : ", ") + def.custom_grains[i].name;
  }
  return fmt::format("  specimen   {} grains from meshes: {}", s.grains.size(), names);
}

std::string describe_outline(const geometry::Outline& o) {
  const Eigen::Vector3d mm = o.size * 1e3;
  switch (o.kind) {
    case geometry::Outline::Kind::disc:
      return fmt::format("disc, diameter {:g} mm, thickness {:g} mm", mm.x(), mm.z());
    case geometry::Outline::Kind::beam:
      return fmt::format("beam {:g} x {:g} x {:g} mm", mm.x(), mm.y(), mm.z());
    default:
      return fmt::format("box {:g} x {:g} x {:g} mm", mm.x(), mm.y(), mm.z());
  }
}

/// run.toml's crack facts under `prefix` (sec. 1.3 of seed 000: which way a polycrystal
/// cracks): the areas (m^2) and counts of both kinds and their fractions, "nan" before the
/// first crack (0/0); each kind's fraction and the other's sum to one.
void put_cracks(io::Manifest& manifest, const std::string& prefix, const CrackTotals& c) {
  auto fraction = [](std::optional<double> v) {
    return v ? fmt::format("{:.9g}", *v) : std::string("nan");
  };
  manifest.facts[prefix + "intergranular_area_m2"] = fmt::format("{:.9g}", c.intergranular_area);
  manifest.facts[prefix + "transgranular_area_m2"] = fmt::format("{:.9g}", c.transgranular_area);
  manifest.facts[prefix + "intergranular_area_fraction"] =
      fraction(c.intergranular_area_fraction());
  manifest.facts[prefix + "transgranular_area_fraction"] =
      fraction(c.transgranular_area_fraction());
  manifest.facts[prefix + "intergranular_count"] = std::to_string(c.intergranular);
  manifest.facts[prefix + "transgranular_count"] = std::to_string(c.transgranular);
  manifest.facts[prefix + "intergranular_count_fraction"] =
      fraction(c.intergranular_count_fraction());
  manifest.facts[prefix + "transgranular_count_fraction"] =
      fraction(c.transgranular_count_fraction());
}

}  // namespace


const char* version() { return CLEAVE_VERSION; }

std::string specimen_csv(const Specimen& s, const std::vector<std::string>& phases) {
  // With [[phase]] tables, each grain's phase by name (last column).
  std::string out =
      "grain_id,plane,row,i,j,k,x_m,y_m,z_m,family,angle_deg,slabs,phi1_deg,Phi_deg,phi2_deg";
  out += phases.empty() ? "\n" : ",phase\n";
  for (const auto& g : s.grains) {
    const auto& c = g.site.centre;
    // The crystal as Bunge angles (docs/ORIENTATIONS.md), as EBSD software and Neper write it.
    const auto e = geometry::to_bunge(g.crystal);
    constexpr double deg = 180.0 / M_PI;
    out += fmt::format("{},{},{},{},{},{},{:.17g},{:.17g},{:.17g},{},{},{},{:.12g},{:.12g},{:.12g}\n", g.id,
                       g.site.plane, g.site.row, g.site.i, g.site.j, g.site.k, c.x(), c.y(), c.z(),
                       to_string(g.orientation.family), g.orientation.angle_deg,
                       s.def.crystal.enabled ? 1 : slab_count(g.orientation.family), e[0] * deg, e[1] * deg,
                       e[2] * deg);
    if (!phases.empty()) {
      out.back() = ',';
      out += phases.at(static_cast<std::size_t>(g.phase)) + "\n";
    }
  }
  return out;
}

const char* orientation_law_name(geometry::OrientationLaw law) {
  switch (law) {
    case geometry::OrientationLaw::honeycomb: return "honeycomb (c along z)";
    case geometry::OrientationLaw::uniform: return "uniform";
    case geometry::OrientationLaw::fibre: return "fibre";
    case geometry::OrientationLaw::preferred: return "preferred";
    case geometry::OrientationLaw::given: return "from a file";
    case geometry::OrientationLaw::imported: return "from the specimen's file";
  }
  return "?";
}

std::string fragments_csv(const std::vector<Piece>& pieces) {
  // Mass properties per distinct shape (grains share their slab shapes).
  std::map<const geometry::ExactPolyhedron*, geometry::MassProperties> props;
  std::string out =
      "name,grain_id,path,family,angle_deg,volume_m3,centroid_x_m,centroid_y_m,centroid_z_m\n";
  for (const auto& p : pieces) {
    auto it = props.find(p.shape.get());
    if (it == props.end()) it = props.emplace(p.shape.get(), p.shape->mass_properties()).first;
    const Eigen::Vector3d c = p.position + it->second.centroid;
    out += fmt::format("{},{},{},{},{},{:.17g},{:.17g},{:.17g},{:.17g}\n", p.lineage.name(),
                       p.lineage.grain_id, p.lineage.path_string(), to_string(p.orientation.family),
                       p.orientation.angle_deg, it->second.volume, c.x(), c.y(), c.z());
  }
  return out;
}

struct Simulation::State {
  SimulationOptions options;
  Stopwatch total;
  io::Scenario scenario;
  std::string input;  ///< the scenario's text, as run (a checkpoint keeps it)
  /// The overrides applied to the file's text (cleave run --set), as axes of one point, and
  /// how each is named in errors.
  std::vector<io::SweepAxis> override_axes;
  std::vector<std::string> overrides, overrides_shown;
  /// A restart: the checkpoint holds the scenario as run and the state to continue from.
  std::optional<io::Checkpoint> checkpoint;
  double stable_dt = 0.0;  ///< a restart's stable step (check_time_step), for its messages
  /// A fresh run's world, made (and its start checked) before the slabs and meshes.
  std::optional<AssembledWorld> assembled;
  fs::path restart_file;
  fs::path out;
  io::FolderPlan folder;  ///< what start() clears of an earlier run in `out`
  std::uint64_t max_steps = 0;
  std::optional<io::ResultRecord> record;
  std::optional<Specimen> specimen;
  std::vector<Piece> pieces;
  std::optional<io::CheckpointMeta> meta;
  std::unique_ptr<Dynamics> dynamics;
  bool started = false, finished = false;
  std::optional<RunReport> report;  ///< set when the run ended (finished, interrupted)

  void say(const std::string& line) const {
    if (!options.quiet) fmt::print("{}\n", line);
  }
  /// Several processes: only the first writes the meshes, geometry.exact and the tables
  /// (the others work in a scratch folder that is removed; a 10^5-grain specimen's meshes
  /// and exact store take most of its start).
  bool writes_results() const { return !options.domain || options.domain->rank() == 0; }
  bool stop() const { return options.stop_requested && options.stop_requested(); }
  std::string stop_reason() const { return options.stop_reason ? options.stop_reason() : "stopped"; }

  /// Applies the options' overrides of [output] and works out the folder and the limit.
  void settle() {
    if (options.mesh_format) scenario.output.mesh_format = io::parse_mesh_format(*options.mesh_format);
    if (options.mesh_layout) scenario.output.mesh_layout = io::parse_mesh_layout(*options.mesh_layout);
    out = !options.out.empty() ? options.out
          : checkpoint         ? (restart_file.has_parent_path() ? restart_file.parent_path() : fs::path("."))
                               : fs::path("results") / scenario.name;
    max_steps = options.max_steps > 0 || !checkpoint ? options.max_steps : checkpoint->meta.max_steps;
    io::FolderClaim claim{"run", scenario.name, options.replace, false};
    if (checkpoint) {
      // A restart in the checkpoint's own folder continues there; elsewhere it is a new result.
      std::error_code ec;
      const fs::path home =
          restart_file.has_parent_path() ? restart_file.parent_path() : fs::path(".");
      claim.restart = fs::weakly_canonical(fs::absolute(out), ec) ==
                      fs::weakly_canonical(fs::absolute(home), ec);
    }
    folder = io::check_result_folder(out, claim);
  }

  /// A run stopped between two phases: what is written stays, marked so.
  void interrupted() {
    const std::string reason = stop_reason();
    record->manifest.provenance["ended_utc"] = io::utc_now();
    record->close_quietly(io::run_status::interrupted, reason);
    report = RunReport{RunReport::Status::interrupted, reason, out, std::nullopt};
    finished = true;
  }

  /// run.toml closed as failed, then the exception goes on.
  [[noreturn]] void fail(const std::exception& e) {
    record->manifest.provenance["ended_utc"] = io::utc_now();
    record->close_quietly(io::run_status::failed, e.what());
    finished = true;
    throw;
  }

  void start();
  void make_dynamics();
  RunReport finish();
};

void Simulation::State::start() {
  started = true;
  // Whatever was in the folder is no longer a result until this run finishes.
  try {
    // Exactly the earlier run's files (check_result_folder), and a killed run's unfinished
    // writes; a restart keeps the frames before its checkpoint.
    io::clear_result_folder(out, folder);
    fs::create_directories(out);
    fs::remove(out / io::kManifestName);
    fs::remove(out / io::kChecksumsName);
    fs::remove_all(out / "meshes");
  } catch (const fs::filesystem_error& e) {
    finished = true;
    throw std::runtime_error(fmt::format("{}: {}", out.string(), e.what()));
  } catch (const std::exception&) {
    finished = true;
    throw;
  }

  // run.toml says "running" from here on; close() gives the final status and the files.
  record.emplace(out);
  io::Manifest& manifest = record->manifest;
  manifest.facts["cleave_version"] = CLEAVE_VERSION;
  manifest.facts["scenario"] = scenario.source;
  manifest.facts["scenario_name"] = scenario.name;
  manifest.provenance = io::library_versions();
  manifest.provenance["cleave_version"] = CLEAVE_VERSION;
  manifest.provenance["command"] = "run";
  manifest.provenance["scenario"] = scenario.source;
  manifest.provenance["scenario_as_run"] = io::kScenarioAsRunName;
  manifest.provenance["seed"] = std::to_string(scenario.specimen.seed);  // of the orientations
  if (scenario.specimen.kind == geometry::SpecimenKind::voronoi)
    manifest.provenance["voronoi_seed"] = std::to_string(scenario.specimen.voronoi.seed);
  manifest.provenance["started_utc"] = io::utc_now();
  if (max_steps > 0) manifest.provenance["max_steps"] = std::to_string(max_steps);
  if (!overrides.empty()) {
    std::string joined;
    for (const auto& o : overrides) joined += (joined.empty() ? "" : "; ") + o;
    manifest.provenance["overrides"] = joined;  // scenario.toml holds the text as run
  }
  if (checkpoint) {
    manifest.provenance["restarted_from"] = restart_file.string();
    manifest.provenance["restarted_at_step"] = std::to_string(checkpoint->world.steps());
  }
  try {
    manifest.provenance["scenario_sha256"] = io::sha256_hex(input);
    if (checkpoint) {
      // Files written since the interrupted run started are this run's too.
      record->resume(fs::file_time_type(fs::file_time_type::duration(checkpoint->meta.started_ticks)));
    } else {
      record->start();
    }
    io::write_file_atomically(out / "scenario.toml", input);
    io::write_file_atomically(out / io::kScenarioAsRunName, io::scenario_to_toml(scenario));
  } catch (const std::exception& e) {
    fail(e);
  }
  try {
    say(fmt::format("cleave {} | scenario {} ({})", CLEAVE_VERSION, scenario.name, scenario.source));
    Stopwatch step;
    specimen.emplace(geometry::build_specimen(scenario.specimen));
    const auto& def = specimen->def;
    int three_slab = 0;
    for (const auto& g : specimen->grains) three_slab += g.orientation.family == geometry::CleavageFamily::a_11_20;
    if (def.kind == geometry::SpecimenKind::lattice) {
      say(fmt::format("  specimen   {} grains in a {}; r = {:g} mm, r_bar = {:g} mm, t = {:g} mm, "
                      "t_bar = {:g} mm ({:.2f} s)",
                      specimen->grains.size(), describe_outline(def.outline), def.r * 1e3,
                      def.r_bar * 1e3, def.t * 1e3, def.t_bar * 1e3, step.seconds()));
    } else {
      say(describe_own_grains(*specimen) + fmt::format(" ({:.2f} s)", step.seconds()));
    }
    if (def.crystal.enabled) {
      std::string families;
      const std::vector<int> of_plane = geometry::plane_families(def.crystal);
      const std::size_t planes = of_plane.size();
      for (std::size_t f = 0; f < def.crystal.families.size(); ++f) {
        const auto& family = def.crystal.families[f];
        families += fmt::format("{}{} x{} (resistance {:g})", families.empty() ? "" : ", ", family.family.text,
                                std::count(of_plane.begin(), of_plane.end(), static_cast<int>(f)), family.resistance);
      }
      say(fmt::format("  crystals   {} {} grains, orientations {}, seed {}; {} cleavage planes a grain{}{}",
                      specimen->grains.size(), geometry::to_string(def.crystal.lattice.system),
                      orientation_law_name(def.orientation.law), def.seed, planes,
                      families.empty() ? "" : ": ", families));
    } else {
      say(fmt::format("  crystals   {} grains <11-20> (3 slabs), {} grains <10-10> (2 slabs), seed {}",
                      three_slab, specimen->grains.size() - three_slab, def.seed));
    }
    if (specimen->grains.empty()) throw std::runtime_error("the outline holds no whole grain cell");
    // The time step and, for a fresh run, its start (sim::check_start) before the slabs and
    // meshes; the world made for the check is the one the run starts from.
    if (scenario.dynamics.enabled && checkpoint)
      stable_dt = sim::check_time_step(scenario, *specimen);
    if (scenario.dynamics.enabled && !checkpoint) {
      assembled.emplace(sim::assemble_world(scenario, *specimen));
      if (writes_results()) {
        for (const io::ScenarioError& w : sim::start_warnings(scenario, *specimen)) {
          // With overrides the scenario was parsed from a rewritten text: its lines are not
          // the file's, so a warning names the override (or lists them), as errors do.
          const io::ScenarioError shown =
              override_axes.empty() ? w : io::blame_sweep_point(w, override_axes, overrides_shown);
          fmt::print(stderr, "cleave: warning: {}\n", shown.what());
        }
      }
    }

    if (stop()) return interrupted();

    step = Stopwatch();
    pieces = geometry::split_into_slabs(*specimen, scenario.split.min_fragment_fraction);
    std::size_t planned = 0;
    for (const auto& g : specimen->grains) planned += slab_count(g.orientation.family);
    if (specimen->def.crystal.enabled) {
      say(fmt::format("  cleavage   the {} grains stay whole until a plane's criterion splits them ([fracture])",
                      specimen->grains.size()));
    } else say(fmt::format("  cleavage   {} exact slabs from {} grains ({:.2f} s){}", pieces.size(),
                    specimen->grains.size(), step.seconds(),
                    planned == pieces.size()
                        ? ""
                        : fmt::format("; {} cuts skipped: a part would be below the minimum "
                                      "fragment fraction {:g}",
                                      planned - pieces.size(), scenario.split.min_fragment_fraction)));

    if (stop()) return interrupted();

    if (!writes_results()) {
      if (scenario.dynamics.enabled) make_dynamics();
      return;
    }
    step = Stopwatch();
    std::vector<geometry::PolygonMesh> meshes;
    meshes.reserve(pieces.size());
    for (const auto& p : pieces) meshes.push_back(p.shape->to_mesh(p.lineage.name(), p.position));
    const auto mesh_files = io::write_meshes(meshes, out / "meshes", "fragments",
                                             scenario.output.mesh_format, scenario.output.mesh_layout);
    say(fmt::format("  meshes     {} fragment meshes -> {}/meshes ({}, {}, {} file(s), {:.2f} s)",
                    meshes.size(), out.string(), io::to_string(scenario.output.mesh_format),
                    io::to_string(scenario.output.mesh_layout), mesh_files.size(), step.seconds()));

    step = Stopwatch();
    io::write_exact_store(out / "geometry.exact", io::make_exact_store(*specimen, pieces));
    std::vector<std::string> phase_names;
    for (const io::PhaseDef& p : scenario.phases) phase_names.push_back(p.name);
    io::write_file_atomically(out / "specimen.csv", specimen_csv(*specimen, phase_names));
    io::write_file_atomically(out / "fragments.csv", fragments_csv(pieces));
    io::write_file_atomically(out / "specimen.svg", specimen_picture_svg(*specimen, pieces));
    say(fmt::format("  tables     specimen.csv, fragments.csv, geometry.exact, specimen.svg, "
                    "scenario.toml, {} ({:.2f} s)",
                    io::kScenarioAsRunName, step.seconds()));
    if (stop()) return interrupted();
    if (scenario.dynamics.enabled) make_dynamics();
  } catch (const std::exception& e) {
    fail(e);
  }
}

void Simulation::State::make_dynamics() {
  RunHooks hooks;
  hooks.stop_requested = [this] { return stop(); };
  // Checkpoints: every N steps if asked, and always when a stop ends the run.
  meta = io::CheckpointMeta{CLEAVE_VERSION, scenario.source, input, max_steps,
                            static_cast<std::int64_t>(record->started().time_since_epoch().count())};
  auto save = [this](const RunPoint& p) {
    // Several processes: the first writes the whole world (gathered by the run loop).
    if (options.domain && options.domain->rank() != 0) return;
    const fs::path checkpoint_path = out / io::kCheckpointName;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      io::write_checkpoint_file(checkpoint_path, io::encode_checkpoint(*meta, p.world, p.book, p.run_state()));
    } catch (const std::exception& e) {
      // The last good checkpoint stays; the run goes on.
      fmt::print(stderr, "\ncleave: warning: checkpoint at step {} not written: {}\n", p.world.steps(), e.what());
      return;
    }
    if (!options.quiet && stop()) {
      fmt::print(stderr, "\ncleave: checkpoint at step {} -> {} ({:.2f} s); continue with: cleave restart {}\n",
                 p.world.steps(), checkpoint_path.string(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), out.string());
    }
  };
  hooks.checkpoint_every = options.checkpoint_every.value_or(scenario.output.checkpoint_every);
  if (hooks.checkpoint_every > 0) hooks.on_checkpoint = save;
  hooks.on_interrupt = save;
  hooks.domain = options.domain;
  hooks.timing = options.timing;
  std::optional<RunResume> resume;
  if (checkpoint) {
    resume.emplace(RunResume{std::move(checkpoint->world), std::move(checkpoint->book),
                             std::move(checkpoint->run_state), stable_dt});
    say(fmt::format("  restart    from {} at step {}", restart_file.string(), resume->world.steps()));
  }
  dynamics =
      std::make_unique<Dynamics>(scenario, *specimen, out, options.quiet, max_steps, hooks,
                                 resume ? &*resume : nullptr, assembled ? &*assembled : nullptr);
  assembled.reset();  // moved into the run
}

RunReport Simulation::State::finish() {
  if (report) return *report;
  if (finished) throw std::logic_error("the run failed; it has nothing more to give");
  io::Manifest& manifest = record->manifest;
  try {
    std::optional<DynamicsSummary> result;
    if (dynamics) {
      result = dynamics->finish();
      const DynamicsSummary& d = *result;
      std::string files = "bodies.pvd, contacts.pvd";
      if (scenario.bond.enabled) files += ", bonds.pvd";
      if (!scenario.walls.empty()) files += ", walls.pvd";
      if (scenario.bond.enabled || scenario.fracture.enabled) files += ", cracks.pvd";
      files += ", energy.csv, walls.csv, load_displacement.csv";
      if (scenario.bond.enabled) files += ", bonds.csv, bond_breaks.csv";
      const bool cracks = scenario.bond.enabled || scenario.fracture.enabled;
      if (cracks) files += ", cracks.csv";
      if (scenario.thermal.enabled) files += ", thermal.csv";
      if (scenario.thermal.enabled && scenario.bond.enabled) files += ", microcracks.svg";
      if (scenario.periodic.enabled) files += ", cell.csv, cell.pvd";
      if (std::any_of(scenario.stages.begin(), scenario.stages.end(), [](const io::StageDef& st) { return st.measure_modulus; }))
        files += ", modulus.csv, modulus.svg";
      for (const auto& st : d.stages) {
        if (!st.plot.empty()) files += ", " + st.plot;
      }
      say(fmt::format("  dynamics   {} steps, t = {:.4g} s, {} frames -> {}/{} ({:.1f} s, {:.1f} us/step)",
                      d.steps, d.time, d.frames, out.string(), files, d.wall_seconds,
                      1e6 * d.wall_seconds / std::max<double>(1, d.steps)));
      if (!d.timing.empty()) say(d.timing + "\n             (" + (out / "timing.csv").string() + ")");
      if (scenario.stages.empty()) {
        say(fmt::format("             {}: kinetic energy {:.3g} J = {:.2e} of the {:.3g} J released; "
                        "largest overlap {:.3g} um ({:.1f}% of the dilation radius); lowest point "
                        "z = {:.4g} mm",
                        d.settled ? "settled" : "not settled", d.kinetic_energy,
                        d.kinetic_energy / std::max(d.released_energy, 1e-300), d.released_energy,
                        d.max_overlap * 1e6, 100 * d.max_overlap / scenario.contact.dilation_radius,
                        d.lowest_point * 1e3));
      }
      for (const auto& st : d.stages) {
        std::string line = fmt::format("             stage {:<12} {:>8} steps, t = {:.4g}..{:.4g} s, ended by {}",
                                       st.name, st.steps, st.start, st.end, st.ended_by);
        if (st.event_missed) line += " (its event did not come: check the stage)";
        if (st.peak_load > 0.0) line += fmt::format(", peak load {:.4g} N", st.peak_load);
        if (st.bonds_broken > 0) line += fmt::format(", {} bonds broke", st.bonds_broken);
        say(line);
        const std::string key = "stage_" + st.name;
        manifest.facts[key + "_steps"] = std::to_string(st.steps);
        manifest.facts[key + "_ended_by"] = st.ended_by;
        manifest.facts[key + "_peak_load_N"] = fmt::format("{:.9g}", st.peak_load);
        manifest.facts[key + "_bonds_broken"] = std::to_string(st.bonds_broken);
        if (cracks) {
          put_cracks(manifest, key + "_cracks_", st.cracks_end.since(st.cracks_start));
          if (st.peak_load > 0.0)
            put_cracks(manifest, key + "_cracks_at_peak_",
                       st.cracks_at_peak.since(st.cracks_start));
        }
      }
      if (cracks) {
        const CrackTotals& c = d.cracks;
        auto percent = [](std::optional<double> v) {
          return v ? fmt::format("{:.1f} %", 100.0 * *v) : std::string("none yet");
        };
        say(fmt::format(
            "  crack area {:.4g} mm^2 intergranular ({} bonds), {:.4g} mm^2 transgranular ({} "
            "splits): transgranular {} by area, {} by count -> cracks.csv, cracks.pvd",
            c.intergranular_area * 1e6, c.intergranular, c.transgranular_area * 1e6,
            c.transgranular, percent(c.transgranular_area_fraction()),
            percent(c.transgranular_count_fraction())));
        put_cracks(manifest, "cracks_", c);
        if (d.cracks_at_peak) put_cracks(manifest, "cracks_at_peak_", *d.cracks_at_peak);
      }
      if (scenario.bond.enabled) {
        const auto& c = d.bond_counts;
        say(fmt::format("  bonds      {} made; {} intact, {} broken: tension {}, shear {}, bending {}, "
                        "torsion {} (intergranular cracks; every break in bond_breaks.csv)",
                        d.bonds, c.intact, c.broken(), c.tension, c.shear, c.bending, c.torsion));
        manifest.facts["bonds"] = std::to_string(d.bonds);
        manifest.facts["bonds_intact"] = std::to_string(c.intact);
        manifest.facts["bonds_broken_tension"] = std::to_string(c.tension);
        manifest.facts["bonds_broken_shear"] = std::to_string(c.shear);
        manifest.facts["bonds_broken_bending"] = std::to_string(c.bending);
        manifest.facts["bonds_broken_torsion"] = std::to_string(c.torsion);
      }
      if (scenario.fracture.enabled && writes_results()) {
        // The result is now the pieces alive at the end: geometry.exact, fragments.csv and
        // the meshes describe them (each in its grain's place, as cut), so that `cleave
        // check volume` checks the run's own fragments.
        io::write_exact_store(out / "geometry.exact", io::make_exact_store(*specimen, d.final_pieces));
        io::write_file_atomically(out / "fragments.csv", fragments_csv(d.final_pieces));
        std::vector<geometry::PolygonMesh> final_meshes;
        for (const auto& p : d.final_pieces) final_meshes.push_back(p.shape->to_mesh(p.lineage.name(), p.position));
        fs::remove_all(out / "meshes");
        io::write_meshes(final_meshes, out / "meshes", "fragments", scenario.output.mesh_format,
                         scenario.output.mesh_layout);
        say(fmt::format("  cracks     {} intergranular (bonds broken), {} transgranular (grains split); "
                        "{} pieces at the end -> splits.csv, geometry.exact, meshes/",
                        d.bond_counts.broken(), d.splits, d.final_pieces.size()));
        manifest.facts["transgranular_splits"] = std::to_string(d.splits);
        manifest.facts["intergranular_breaks"] = std::to_string(d.bond_counts.broken());
        manifest.facts["final_pieces"] = std::to_string(d.final_pieces.size());
      }
      if (writes_results() && !d.fragments.empty()) {
        // Fragments in the fragmentation sense: clusters of bodies joined by intact bonds.
        const io::FragmentSizes sizes = io::analyse_fragment_sizes(d.fragments);
        io::write_file_atomically(out / "fragment_sizes.csv", io::fragment_sizes_csv(sizes));
        io::write_plot_svg(
            out / "fragment_sizes.svg",
            io::fragment_sizes_plot(
                sizes, fmt::format("{}: {} fragments", scenario.name, sizes.fragments.size())));
        io::add_fragment_facts(manifest.facts, sizes);
        manifest.facts["fragments.volume_equals_specimen"] =
            d.fragment_volume_exact ? "true" : "false";
        std::string fits;
        if (sizes.rosin_rammler)
          fits += fmt::format("; Rosin-Rammler d0 = {:.4g} mm, n = {:.3g}",
                              sizes.rosin_rammler->d0 * 1e3, sizes.rosin_rammler->n);
        if (sizes.power_law)
          fits += fmt::format("; N(>d) ~ d^-{:.3g} over d >= {:.4g} mm", sizes.power_law->b,
                              sizes.power_law->d_min * 1e3);
        say(fmt::format(
            "  fragments  {} (bodies joined by intact bonds), the largest {:.3g} of the mass{}; "
            "volumes {} -> fragment_sizes.csv, fragment_sizes.svg",
            sizes.fragments.size(), sizes.largest_mass_fraction, fits,
            d.fragment_volume_exact ? "sum exactly to the specimen's"
                                    : "do not sum to the specimen's (bodies were lost)"));
      }
      if (d.peak_load > 0.0) manifest.facts["peak_load_N"] = fmt::format("{:.9g}", d.peak_load);
      if (d.brazilian_strength) {
        const auto& o = specimen->def.outline;
        say(fmt::format("  strength   Brazilian: 2P/(pi D t) = 2 x {:.4g} N / (pi x {:g} mm x {:g} mm) "
                        "= {:.4g} Pa",
                        d.peak_load, o.size.x() * 1e3, o.size.z() * 1e3, *d.brazilian_strength));
        manifest.facts["brazilian_strength_Pa"] = fmt::format("{:.9g}", *d.brazilian_strength);
      }
      manifest.facts["dynamics_steps"] = std::to_string(d.steps);
      manifest.facts["final_state_hash"] = fmt::format("{:016x}", d.state_hash);
      manifest.facts["dynamics_time_s"] = fmt::format("{:.9g}", d.time);
      manifest.facts["dynamics_settled"] = d.settled ? "true" : "false";
      manifest.facts["kinetic_energy_J"] = fmt::format("{:.9g}", d.kinetic_energy);
      manifest.facts["released_energy_J"] = fmt::format("{:.9g}", d.released_energy);
      manifest.facts["max_overlap_m"] = fmt::format("{:.9g}", d.max_overlap);
      manifest.facts["lowest_point_m"] = fmt::format("{:.9g}", d.lowest_point);
      manifest.facts["dynamics_ending"] = d.ending == RunEnding::completed     ? "completed"
                                          : d.ending == RunEnding::interrupted ? "interrupted"
                                          : d.ending == RunEnding::stopped     ? "stopped"
                                                                               : "blew_up";
    }
    manifest.facts["grains"] = std::to_string(specimen->grains.size());
    manifest.facts["fragments"] = std::to_string(pieces.size());  // cleavage slabs at the start
    manifest.facts["mesh_format"] = io::to_string(scenario.output.mesh_format);
    manifest.facts["mesh_layout"] = io::to_string(scenario.output.mesh_layout);
    manifest.facts["length_unit_of_outputs"] = "m";
    manifest.facts["wall_seconds"] = fmt::format("{:.3f}", total.seconds());
    manifest.provenance["ended_utc"] = io::utc_now();
    finished = true;
    if (result && result->ending == RunEnding::blew_up) {
      record->close_quietly(io::run_status::failed, result->failure);
      report = RunReport{RunReport::Status::failed, result->failure, out, result};
      return *report;
    }
    if (result && result->ending == RunEnding::interrupted) {
      const std::string reason = stop_reason();
      record->close_quietly(io::run_status::interrupted, reason);
      report = RunReport{RunReport::Status::interrupted, reason, out, result};
      return *report;
    }
    if (result && result->ending == RunEnding::stopped) {
      // The step limit the user set ran out before the stages ended: what ran is written
      // and complete, but it is not the scenario's whole run.
      const auto cut =
          std::find_if(result->stages.rbegin(), result->stages.rend(),
                       [](const StageSummary& st) { return st.ended_by == "max_steps"; });
      const std::string stage = cut != result->stages.rend() ? cut->name : std::string("run");
      const std::uint64_t stage_steps = cut != result->stages.rend() ? cut->steps : result->steps;
      const std::string reason = fmt::format(
          "stopped at step {} by the step limit (max_steps = {}), in stage '{}' after {} of its "
          "steps; "
          "the rest of the scenario did not run",
          result->steps, max_steps, stage, stage_steps);
      manifest.facts["stopped_at_step"] = std::to_string(result->steps);
      manifest.facts["stopped_in_stage"] = stage;
      record->close(io::run_status::stopped, reason);
      report = RunReport{RunReport::Status::stopped, reason, out, result};
      return *report;
    }
    record->close(io::run_status::finished);
    say(fmt::format("done in {:.2f} s -> {}  (check it: cleave check volume {})", total.seconds(),
                    out.string(), out.string()));
    report = RunReport{RunReport::Status::finished, {}, out, result};
    return *report;
  } catch (const std::exception& e) {
    fail(e);
  }
}

Simulation::Simulation(std::unique_ptr<State> state) : s_(std::move(state)) {}
Simulation::~Simulation() = default;

std::unique_ptr<Simulation> Simulation::open(const fs::path& scenario, SimulationOptions options,
                                             const std::vector<std::string>& overrides) {
  if (overrides.empty()) {
    auto s = std::make_unique<State>();
    s->options = std::move(options);
    s->scenario = io::load_scenario(scenario);
    s->input = io::read_file(scenario);
    s->settle();
    return std::unique_ptr<Simulation>(new Simulation(std::move(s)));
  }
  if (!fs::is_regular_file(scenario)) {
    throw io::ScenarioError(scenario.string(), 0, 0, "", "file does not exist or is not a file");
  }
  return from_text(io::read_file(scenario), scenario.string(), std::move(options), overrides,
                   scenario.has_parent_path() ? scenario.parent_path() : fs::path("."));
}

std::unique_ptr<Simulation> Simulation::from_text(std::string text, std::string source,
                                                  SimulationOptions options,
                                                  const std::vector<std::string>& overrides,
                                                  const fs::path& base_dir) {
  auto s = std::make_unique<State>();
  s->options = std::move(options);
  if (overrides.empty()) {
    s->scenario = io::parse_scenario(text, source);
    s->input = std::move(text);
  } else {
    io::SweepPoint point;
    std::tie(s->override_axes, point) = io::parse_overrides(overrides, s->options.override_label);
    s->overrides = overrides;
    for (const auto& o : overrides)
      s->overrides_shown.push_back(s->options.override_label + " " + o);
    s->scenario = io::read_sweep_point(text, source, s->override_axes, point, s->overrides_shown,
                                       base_dir, &s->input);
  }
  s->settle();
  return std::unique_ptr<Simulation>(new Simulation(std::move(s)));
}

std::unique_ptr<Simulation> Simulation::restart(const fs::path& checkpoint, SimulationOptions options) {
  auto s = std::make_unique<State>();
  s->options = std::move(options);
  s->restart_file = io::checkpoint_file(checkpoint);
  s->checkpoint.emplace(io::read_checkpoint(s->restart_file));
  s->scenario = io::parse_scenario(s->checkpoint->meta.scenario_text, s->checkpoint->meta.scenario_source);
  s->input = s->checkpoint->meta.scenario_text;
  s->settle();
  return std::unique_ptr<Simulation>(new Simulation(std::move(s)));
}

const io::Scenario& Simulation::scenario() const { return s_->scenario; }
const fs::path& Simulation::out() const { return s_->out; }
void Simulation::start() {
  if (s_->started) throw std::logic_error("the run has started already");
  try {
    s_->start();
  } catch (const io::ScenarioError& e) {  // the time step, say: at an override, not a line
    if (s_->override_axes.empty()) throw;
    throw io::blame_sweep_point(e, s_->override_axes, s_->overrides_shown);
  }
}
bool Simulation::started() const { return s_->started; }

std::uint64_t Simulation::advance(std::uint64_t steps) {
  if (!s_->started) start();
  if (s_->finished || !s_->dynamics) return 0;
  try {
    return s_->dynamics->advance(steps);
  } catch (const std::exception& e) {
    s_->fail(e);
  }
}

std::optional<StageSummary> Simulation::advance_stage() {
  if (!s_->started) start();
  if (s_->finished || !s_->dynamics) return std::nullopt;
  try {
    return s_->dynamics->advance_stage();
  } catch (const std::exception& e) {
    s_->fail(e);
  }
}

bool Simulation::done() const {
  return s_->finished || (s_->started && (!s_->dynamics || s_->dynamics->done()));
}
RunReport Simulation::finish() {
  if (!s_->started) start();
  return s_->finish();
}
bool Simulation::finished() const { return s_->finished; }
RunReport Simulation::run() {
  start();
  return finish();
}

const Specimen& Simulation::specimen() const {
  if (!s_->specimen) throw std::logic_error("the specimen is built by start()");
  return *s_->specimen;
}
const std::vector<Piece>& Simulation::slabs() const { return s_->pieces; }
Dynamics* Simulation::dynamics() { return s_->dynamics.get(); }
const Dynamics* Simulation::dynamics() const { return s_->dynamics.get(); }

}  // namespace cleave::sim
