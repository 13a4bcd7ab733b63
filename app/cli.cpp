// cleave's command line: the sub-commands and their options (CLI11).

#include "cli.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "cleave_version.hpp"

namespace cleave::app {

namespace {
/// A real number in [lo, hi] (lo excluded when `open_lo`): NaN, infinities and text refused
/// with the range, which CLI11 puts after the option's name ("--voxel-tolerance: ..."). NaN
/// passed CLI::Range and CLI::PositiveNumber: every comparison with it is false.
CLI::Validator real_in(double lo, double hi, bool open_lo = false) {
  std::ostringstream range;
  range << (open_lo ? "> " : ">= ") << lo << " and <= " << hi;
  return CLI::Validator(
      [=, range = range.str()](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        const bool number = !text.empty() && end == text.c_str() + text.size() && std::isfinite(v);
        if (number && (open_lo ? v > lo : v >= lo) && v <= hi) return {};
        return "expected a number " + range + ", got " + text;
      },
      "NUMBER " + range.str());
}
}  // namespace

Cli::Cli() : app{"cleave: exact-polyhedron DEM of brittle polycrystals (grains, cleavage, cracks)"} {
  app.set_version_flag("--version", std::string("cleave ") + CLEAVE_VERSION);
  app.require_subcommand(1);

  run_cmd = app.add_subcommand("run", "Run a scenario file and write a result folder");
  run_cmd->add_option("scenario", run.scenario, "Scenario file (TOML); not with --restart");
  run_cmd->add_option("--out,-o", run.out, "Result folder (default: results/<scenario name>)");
  run_cmd->add_option("--mesh-format", run.mesh_format, "stl | stl_ascii | obj (overrides the scenario)");
  run_cmd->add_option("--mesh-layout", run.mesh_layout, "scene | per_fragment (overrides the scenario)");
  run_cmd->add_option(
      "--set", run.sets,
      "KEY=VALUE: set a key of the scenario (table.key, table.sub.key, stage[N].key; "
      "a number, true/false, or a string such as \"250 MPa\"), repeatable; as "
      "cleave sweep --set with one value");
  run_cmd->add_flag("--quiet,-q", run.quiet, "Print only errors");
  run_cmd->add_flag("--replace", run.replace,
                    "Replace an earlier cleave result in the folder: of another scenario, an interrupted "
                    "run with a checkpoint, or one that did not end (an earlier run of the same "
                    "scenario is replaced without it); only the files its run.toml lists are removed");
  run_cmd->add_flag("--timing", run.timing,
                    "Clock each part of the steps (search, narrow phase, contact and bond laws, ...): "
                    "DIR/timing.csv and a table at the end");
  // Step counts: whole numbers, so that -1 cannot wrap to 2^64 - 1 nor 1e23 pass.
  const CLI::Validator steps{[](std::string& text) -> std::string {
                               if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
                                 return "a number of steps is a whole number, 0 or more: " + text;
                               if (text.size() > 15) return "at most 10^15 steps: " + text;
                               return {};
                             },
                             "STEPS"};
  run_cmd->add_option("--max-steps", run.max_steps,
                      "Stop the dynamics after this many steps (a quick look; 0: no limit)")->check(steps);
  run_cmd->add_option("--restart", run.restart,
                      "Continue from a checkpoint (DIR/checkpoint or DIR) instead of a scenario");
  run_cmd->add_option("--checkpoint-every", run.checkpoint_every,
                      "Write DIR/checkpoint every N steps (overrides [output] checkpoint_every; "
                      "one is always written on SIGINT/SIGTERM)")->check(steps);
  // Checked by main(): io::parse_memory_size (this parser links no io).
  const std::string memory_help =
      "Refuse a specimen whose estimated memory is above SIZE (e.g. 4G, 512M; default: the "
      "memory available now)";
  run_cmd->add_option("--max-memory", run.max_memory, memory_help)->type_name("SIZE");

  restart_cmd = app.add_subcommand(
      "restart", "Continue an interrupted run from its checkpoint (same as run --restart)");
  restart_cmd->add_option("checkpoint", restart.restart, "DIR/checkpoint, or the result folder DIR")
      ->required();
  restart_cmd->add_option("--out,-o", restart.out, "Result folder (default: the checkpoint's folder)");
  restart_cmd->add_flag("--quiet,-q", restart.quiet, "Print only errors");
  restart_cmd->add_flag("--replace", restart.replace,
                        "With --out: replace an earlier cleave result there, as run --replace does");
  restart_cmd->add_flag("--timing", restart.timing, "As for run: DIR/timing.csv, the restarted steps");
  restart_cmd->add_option("--max-steps", restart.max_steps,
                          "Total step limit (default: the interrupted run's --max-steps)")->check(steps);
  restart_cmd->add_option("--checkpoint-every", restart.checkpoint_every,
                          "Write a checkpoint every N steps (overrides the scenario)")->check(steps);
  restart_cmd->add_option("--max-memory", restart.max_memory, memory_help)->type_name("SIZE");

  check_cmd = app.add_subcommand("check", "Check a result folder");
  check_cmd->require_subcommand(1);

  volume_cmd = check_cmd->add_subcommand(
      "volume", "Exact volume conservation per grain: fragments must sum to the grain");
  volume_cmd->add_option("dir", check.dir, "Result folder written by `cleave run`")->required();
  volume_cmd->add_flag("--voxel", check.voxel,
                       "Also measure every exported mesh through OpenVDB (flags leaky meshes)");
  volume_cmd
      ->add_option("--voxels-per-length", check.voxels_per_length,
                   "Voxels across each fragment's thickness 6V/A")
      ->check(real_in(4.0, 400.0))
      ->capture_default_str();
  volume_cmd
      ->add_option("--voxel-tolerance", check.voxel_tolerance,
                   "Largest accepted relative volume difference of a mesh")
      ->check(real_in(0.0, 1.0))
      ->capture_default_str();
  volume_cmd->add_flag("--summary", check.summary_only, "Print the summary only, not every grain");

  sweep_cmd = app.add_subcommand(
      "sweep",
      "Run, measure or validate a scenario for every combination of --set values (--zip values "
      "together, --seeds replicates), in parallel, and summarise");
  sweep_cmd->add_option("scenario", sweep.scenario, "Scenario file (TOML)")->required();
  sweep_cmd
      ->add_option("--command,-c", sweep.command,
                   "What each run is: run (default) | measure (with --test) | validate")
      ->check(CLI::IsMember({"run", "measure", "validate"}));
  sweep_cmd->add_option("--test", sweep.test,
                        "--command measure: elastic | brazilian | flexural | senb");
  sweep_cmd->add_option("--set", sweep.sets,
                        "KEY=VALUES: a key (table.key, stage[N].key) and a comma list or LO..HI; "
                        "KEY/REF=RATIOS: KEY set to each ratio times REF's value in the "
                        "scenario (REF fracture.cleavage_strength: the grains' cleavage "
                        "strength, Pa); repeat for a product");
  sweep_cmd->add_option(
      "--zip", sweep.zips,
      "KEY=VALUES as --set, but every --zip key takes its i-th value in the same "
      "run (equal numbers of values): N runs, not N^2; a product with the --set keys");
  // Each job is a process: a bound keeps a typo from starting thousands.
  sweep_cmd->add_option("--jobs,-j", sweep.jobs, "Runs at a time (default 1)")
      ->check(CLI::Range(1, 1024));
  sweep_cmd->add_option("--out,-o", sweep.out, "Folder (default: results/<scenario name>_sweep)");
  sweep_cmd->add_option("--max-steps", sweep.max_steps, "Passed to every run")->check(steps);
  sweep_cmd->add_flag("--quiet,-q", sweep.quiet, "Print only errors");
  sweep_cmd->add_flag("--replace", sweep.replace,
                      "Replace an earlier cleave result in the folder, as run --replace does");
  sweep_cmd->add_option("--max-memory", sweep.max_memory, memory_help + " (shared by --jobs)")
      ->type_name("SIZE");
  sweep_cmd
      ->add_option("--seeds", sweep.seeds,
                   "N replicates of every combination, the seed key set to 1..N; their mean "
                   "and spread in summary_mean.csv")
      ->check(CLI::Range(1, 100000));
  sweep_cmd->add_option("--seed-key", sweep.seed_key,
                        "The key --seeds sets (default orientation.seed; e.g. specimen.seed)");
  sweep_cmd->add_flag("--cohesive-beam-only", sweep.cohesive_beam_only,
                      "--command validate: passed to each validate (no lattice run)");
  sweep_cmd->add_option("--column", sweep.columns,
                        "A fact of each run's run.toml as one more summary.csv column, repeatable");

  validate_cmd = app.add_subcommand(
      "validate",
      "Run a fracture test of scenarios/validation/ (DCB, ENF, MMB) against its closed form");
  validate_cmd->add_option("scenario", validate.scenario, "Validation scenario file (TOML)")
      ->required();
  validate_cmd->add_option("--out,-o", validate.out,
                           "Result folder (default: results/<scenario name>)");
  validate_cmd->add_flag("--quiet,-q", validate.quiet, "Print only errors");
  validate_cmd->add_flag("--replace", validate.replace,
                         "Replace an earlier cleave result in the folder, as run --replace does");
  validate_cmd->add_option("--max-memory", validate.max_memory, memory_help)->type_name("SIZE");
  validate_cmd->add_flag("--cohesive-beam-only", validate.cohesive_beam_only,
                         "Do not run the lattice: judge beam theory with the scenario's cohesive "
                         "zone against the closed forms (where LEFM holds for its sigma_c)");

  materials_cmd = app.add_subcommand(
      "materials", "List the material library (materials/*.toml), or show one preset's sources");
  materials_cmd->add_option("name", materials.name, "A preset to show (e.g. sic_alpha)");

  measure_cmd = app.add_subcommand(
      "measure", "Measure E and nu, sigma_t, sigma_f or K_Ic of a bonded specimen's test scenario");
  measure_cmd->add_option("test", measure.test, "elastic | brazilian | flexural | senb")->required();
  measure_cmd->add_option("scenario", measure.scenario, "Scenario file of the test (TOML)")->required();
  measure_cmd->add_option("--set", measure.sets, "KEY=VALUE override (table.key), repeatable");
  measure_cmd->add_option("--out,-o", measure.out, "Result folder (default: results/<scenario name>)");
  measure_cmd->add_flag("--quiet,-q", measure.quiet, "Print only the result");
  measure_cmd->add_flag("--converge", measure.converge,
                        "Quasi-static check: rerun at half the loading rate until the value changes by "
                        "less than --tolerance (DIR/rate_*/, DIR/convergence.csv and .svg)");
  measure_cmd
      ->add_option("--tolerance", measure.tolerance, "--converge: relative change (default 0.02)")
      ->check(real_in(0.0, 1.0, true));
  measure_cmd->add_option("--max-runs", measure.max_runs, "--converge: most runs (default 5)")
      ->check(CLI::Range(2, 12));

  calibrate_cmd = app.add_subcommand(
      "calibrate", "Find the bond (and grain-fracture) parameters that give a bonded specimen E, nu, sigma_t, sigma_f and K_Ic targets");
  calibrate_cmd->add_option("file", calibrate.file, "Calibration file (TOML: the test scenarios, a preset)")
      ->required();
  calibrate_cmd->add_option("--target", calibrate.targets,
                            "KEY=VALUE: E=415e9, nu=0.16, sigma_t=250e6, sigma_f=359e6, K_Ic=3.1e6 (default: the file's preset)");
  // As the calibration file's tolerance (io/calibration_file.cpp): above 0, at most 0.5.
  calibrate_cmd
      ->add_option("--tolerance", calibrate.tolerance, "Relative, on every target (default 0.02)")
      ->check(real_in(0.0, 0.5, true));
  calibrate_cmd->add_option("--out,-o", calibrate.out, "Folder (default: results/<file name>)");
  calibrate_cmd->add_flag("--quiet,-q", calibrate.quiet, "Print only the result");
}

std::string Cli::usage_error() const {
  if (run_cmd->parsed()) {
    if (run.scenario.empty() == run.restart.empty())
      return "cleave run: give a scenario file or --restart CHECKPOINT (one of them)";
    if (!run.restart.empty() && !run.sets.empty())
      return "cleave run: --set changes a scenario; a restart continues the checkpoint's "
             "scenario as it was run";
  }
  return {};
}

}  // namespace cleave::app
