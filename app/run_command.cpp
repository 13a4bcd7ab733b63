// `cleave run`: scenario -> specimen -> cleavage slabs -> result folder.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>

#include "cleave_version.hpp"
#include "commands.hpp"
#include "io/checkpoint.hpp"
#include "io/exact_store.hpp"
#include "io/mesh_io.hpp"
#include "io/provenance.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"
#include "io/world_setup.hpp"
#include "dynamics_run.hpp"
#include "run_control.hpp"
#include "specimen_picture.hpp"

namespace cleave::app {

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

std::string specimen_csv(const Specimen& s) {
  std::string out = "grain_id,plane,row,i,j,k,x_m,y_m,z_m,family,angle_deg,slabs\n";
  for (const auto& g : s.grains) {
    const auto& c = g.site.centre;
    out += fmt::format("{},{},{},{},{},{},{:.17g},{:.17g},{:.17g},{},{},{}\n", g.id, g.site.plane,
                       g.site.row, g.site.i, g.site.j, g.site.k, c.x(), c.y(), c.z(),
                       to_string(g.orientation.family), g.orientation.angle_deg,
                       slab_count(g.orientation.family));
  }
  return out;
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

/// The specimen line for grains off the lattice (Voronoi cells, mesh grains).
std::string describe_own_grains(const Specimen& s) {
  const auto& def = s.def;
  if (def.kind == geometry::SpecimenKind::voronoi) {
    const Eigen::Vector3d mm = def.voronoi.size * 1e3;
    const geometry::ExactScalar cells = geometry::total_volume(s.shapes);
    const geometry::ExactScalar box = geometry::exact_box(Eigen::Vector3d::Zero(), def.voronoi.size).volume();
    return fmt::format("  specimen   {} Voronoi cells in a box {:g} x {:g} x {:g} mm (point seed {}, "
                       "gap {:g} mm); the cells' exact volumes {}",
                       s.grains.size(), mm.x(), mm.y(), mm.z(), def.voronoi.seed, def.voronoi.gap * 1e3,
                       cells == box ? std::string("sum exactly to the box's")
                                    : fmt::format("fill {:.2f}% of the box", 100 * cells.to_double() / box.to_double()));
  }
  std::string names;
  for (const auto& g : def.custom_grains) names += (names.empty() ? "" : ", ") + g.name;
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

}  // namespace

int run_command(const RunOptions& options) {
  install_stop_handlers();
  const Stopwatch total;
  auto say = [&](const std::string& line) {
    if (!options.quiet) fmt::print("{}\n", line);
  };

  io::Scenario scenario;
  // A restart: the checkpoint holds the scenario as run and the state to continue from.
  std::optional<io::Checkpoint> checkpoint;
  fs::path restart_file;
  try {
    if (!options.restart.empty()) {
      restart_file = io::checkpoint_file(options.restart);
      checkpoint.emplace(io::read_checkpoint(restart_file));
      scenario = io::parse_scenario(checkpoint->meta.scenario_text, checkpoint->meta.scenario_source);
    } else {
      scenario = io::load_scenario(options.scenario);
    }
    if (options.mesh_format) scenario.output.mesh_format = io::parse_mesh_format(*options.mesh_format);
    if (options.mesh_layout) scenario.output.mesh_layout = io::parse_mesh_layout(*options.mesh_layout);
  } catch (const io::ScenarioError& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 2;
  } catch (const io::CheckpointError& e) {
    fmt::print(stderr, "cleave: error: cannot restart: {}\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "cleave: error: command line: {}\n", e.what());
    return 2;
  }
  const fs::path out = !options.out.empty() ? options.out
                       : checkpoint        ? (restart_file.has_parent_path() ? restart_file.parent_path() : fs::path("."))
                                           : fs::path("results") / scenario.name;
  const std::uint64_t max_steps =
      options.max_steps > 0 || !checkpoint ? options.max_steps : checkpoint->meta.max_steps;

  // Whatever was in the folder is no longer a result until this run finishes.
  try {
    fs::create_directories(out);
    fs::remove(out / io::kManifestName);
    fs::remove(out / io::kChecksumsName);
    fs::remove_all(out / "meshes");
    if (!checkpoint) {
      // A restart keeps the frames before its checkpoint; a fresh run starts clean (and
      // drops any checkpoint of an earlier run, which is not this run's to continue).
      fs::remove_all(out / "frame_meshes");
      fs::remove(out / io::kCheckpointName);
    }
  } catch (const fs::filesystem_error& e) {
    fmt::print(stderr, "cleave: error: {}: {}\n", out.string(), e.what());
    return 1;
  }

  // run.toml says "running" from here on; close() gives the final status and the files.
  io::ResultRecord record(out);
  io::Manifest& manifest = record.manifest;
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
  if (checkpoint) {
    manifest.provenance["restarted_from"] = restart_file.string();
    manifest.provenance["restarted_at_step"] = std::to_string(checkpoint->world.steps());
  }
  // A run stopped by SIGINT/SIGTERM between two phases: what is written stays, marked so.
  auto interrupted = [&]() {
    const int sig = stop_signal();
    const std::string reason = fmt::format("stopped by {}", signal_name(sig));
    fmt::print(stderr, "cleave: {}; the result folder {} holds what was done so far (status "
                       "interrupted)\n", reason, out.string());
    manifest.provenance["ended_utc"] = io::utc_now();
    record.close_quietly(io::run_status::interrupted, reason);
    return exit_code_for_signal(sig);
  };
  std::string input;  // the scenario's text, as run (a checkpoint keeps it)
  try {
    input = checkpoint ? checkpoint->meta.scenario_text : io::read_file(options.scenario);
    manifest.provenance["scenario_sha256"] = io::sha256_hex(input);
    if (checkpoint) {
      // Files written since the interrupted run started are this run's too.
      record.resume(fs::file_time_type(fs::file_time_type::duration(checkpoint->meta.started_ticks)));
    } else {
      record.start();
    }
    io::write_file_atomically(out / "scenario.toml", input);
    io::write_file_atomically(out / io::kScenarioAsRunName, io::scenario_to_toml(scenario));
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    record.close_quietly(io::run_status::failed, e.what());
    return 1;
  }
  try {
    say(fmt::format("cleave {} | scenario {} ({})", CLEAVE_VERSION, scenario.name, scenario.source));
    Stopwatch step;
    const Specimen specimen = geometry::build_specimen(scenario.specimen);
    const auto& def = specimen.def;
    int three_slab = 0;
    for (const auto& g : specimen.grains) three_slab += g.orientation.family == geometry::CleavageFamily::a_11_20;
    if (def.kind == geometry::SpecimenKind::lattice) {
      say(fmt::format("  specimen   {} grains in a {}; r = {:g} mm, r_bar = {:g} mm, t = {:g} mm, "
                      "t_bar = {:g} mm ({:.2f} s)",
                      specimen.grains.size(), describe_outline(def.outline), def.r * 1e3,
                      def.r_bar * 1e3, def.t * 1e3, def.t_bar * 1e3, step.seconds()));
    } else {
      say(describe_own_grains(specimen) + fmt::format(" ({:.2f} s)", step.seconds()));
    }
    say(fmt::format("  crystals   {} grains <11-20> (3 slabs), {} grains <10-10> (2 slabs), seed {}",
                    three_slab, specimen.grains.size() - three_slab, def.seed));
    if (specimen.grains.empty()) throw std::runtime_error("the outline holds no whole grain cell");
    if (scenario.dynamics.enabled) {
      try {
        io::check_time_step(scenario, specimen);
      } catch (const io::ScenarioError& e) {
        fmt::print(stderr, "cleave: error: {}\n", e.what());
        record.close_quietly(io::run_status::failed, e.what());
        return 2;
      }
    }

    if (stop_signal() != 0) return interrupted();

    step = Stopwatch();
    const std::vector<Piece> pieces =
        geometry::split_into_slabs(specimen, scenario.split.min_fragment_fraction);
    std::size_t planned = 0;
    for (const auto& g : specimen.grains) planned += slab_count(g.orientation.family);
    say(fmt::format("  cleavage   {} exact slabs from {} grains ({:.2f} s){}", pieces.size(),
                    specimen.grains.size(), step.seconds(),
                    planned == pieces.size()
                        ? ""
                        : fmt::format("; {} cuts skipped: a part would be below the minimum "
                                      "fragment fraction {:g}",
                                      planned - pieces.size(), scenario.split.min_fragment_fraction)));

    if (stop_signal() != 0) return interrupted();

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
    io::write_exact_store(out / "geometry.exact", io::make_exact_store(specimen, pieces));
    io::write_file_atomically(out / "specimen.csv", specimen_csv(specimen));
    io::write_file_atomically(out / "fragments.csv", fragments_csv(pieces));
    io::write_file_atomically(out / "specimen.svg", specimen_picture_svg(specimen, pieces));
    say(fmt::format("  tables     specimen.csv, fragments.csv, geometry.exact, specimen.svg, "
                    "scenario.toml, {} ({:.2f} s)",
                    io::kScenarioAsRunName, step.seconds()));
    if (stop_signal() != 0) return interrupted();

    std::optional<DynamicsSummary> dynamics;
    if (scenario.dynamics.enabled) {
      RunHooks hooks;
      hooks.stop_requested = [] { return stop_signal() != 0; };
      // Checkpoints: every N steps if asked, and always when a signal stops the run.
      const io::CheckpointMeta meta{CLEAVE_VERSION, scenario.source, input, max_steps,
                                    static_cast<std::int64_t>(record.started().time_since_epoch().count())};
      const fs::path checkpoint_path = out / io::kCheckpointName;
      auto save = [&](const RunPoint& p) {
        const auto t0 = std::chrono::steady_clock::now();
        try {
          io::write_checkpoint_file(checkpoint_path, io::encode_checkpoint(meta, p.world, p.book, p.run_state()));
        } catch (const std::exception& e) {
          // The last good checkpoint stays; the run goes on.
          fmt::print(stderr, "\ncleave: warning: checkpoint at step {} not written: {}\n", p.world.steps(), e.what());
          return;
        }
        if (!options.quiet && stop_signal() != 0) {
          fmt::print(stderr, "\ncleave: checkpoint at step {} -> {} ({:.2f} s); continue with: cleave restart {}\n",
                     p.world.steps(), checkpoint_path.string(),
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), out.string());
        }
      };
      hooks.checkpoint_every = options.checkpoint_every.value_or(scenario.output.checkpoint_every);
      if (hooks.checkpoint_every > 0) hooks.on_checkpoint = save;
      hooks.on_interrupt = save;
      std::optional<RunResume> resume;
      if (checkpoint) {
        resume.emplace(RunResume{std::move(checkpoint->world), std::move(checkpoint->book),
                                 std::move(checkpoint->run_state)});
        say(fmt::format("  restart    from {} at step {}", restart_file.string(), resume->world.steps()));
      }
      dynamics = run_dynamics(scenario, specimen, out, options.quiet, max_steps, hooks,
                              resume ? &*resume : nullptr);
      const DynamicsSummary& d = *dynamics;
      std::string files = "bodies.pvd, contacts.pvd";
      if (scenario.bond.enabled) files += ", bonds.pvd";
      files += ", energy.csv, walls.csv, load_displacement.csv";
      if (scenario.bond.enabled) files += ", bonds.csv, bond_breaks.csv";
      for (const auto& st : d.stages) {
        if (!st.plot.empty()) files += ", " + st.plot;
      }
      say(fmt::format("  dynamics   {} steps, t = {:.4g} s, {} frames -> {}/{} ({:.1f} s, {:.1f} us/step)",
                      d.steps, d.time, d.frames, out.string(), files, d.wall_seconds,
                      1e6 * d.wall_seconds / std::max<double>(1, d.steps)));
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
      if (scenario.fracture.enabled) {
        // The result is now the pieces alive at the end: geometry.exact, fragments.csv and
        // the meshes describe them (each in its grain's place, as cut), so that `cleave
        // check volume` checks the run's own fragments.
        io::write_exact_store(out / "geometry.exact", io::make_exact_store(specimen, d.final_pieces));
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
      if (d.peak_load > 0.0) manifest.facts["peak_load_N"] = fmt::format("{:.9g}", d.peak_load);
      if (d.brazilian_strength) {
        const auto& o = specimen.def.outline;
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
                                                                               : "blew_up";
    }
    manifest.facts["grains"] = std::to_string(specimen.grains.size());
    manifest.facts["fragments"] = std::to_string(pieces.size());  // cleavage slabs at the start
    manifest.facts["mesh_format"] = io::to_string(scenario.output.mesh_format);
    manifest.facts["mesh_layout"] = io::to_string(scenario.output.mesh_layout);
    manifest.facts["length_unit_of_outputs"] = "m";
    manifest.facts["wall_seconds"] = fmt::format("{:.3f}", total.seconds());
    manifest.provenance["ended_utc"] = io::utc_now();
    if (dynamics && dynamics->ending == RunEnding::blew_up) {
      fmt::print(stderr, "cleave: error: {}\n", dynamics->failure);
      record.close_quietly(io::run_status::failed, dynamics->failure);
      return 1;
    }
    if (dynamics && dynamics->ending == RunEnding::interrupted) return interrupted();
    record.close(io::run_status::finished);
    say(fmt::format("done in {:.2f} s -> {}  (check it: cleave check volume {})", total.seconds(),
                    out.string(), out.string()));
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    manifest.provenance["ended_utc"] = io::utc_now();
    record.close_quietly(io::run_status::failed, e.what());
    return 1;
  }
}

}  // namespace cleave::app
