// `cleave sweep`: one scenario run many times with keys set to each combination of values
// (--set KEY=VALUES ...; --zip KEY=VALUES keys vary together; KEY/REF=RATIOS a key as a multiple
// of another; --seeds N replicates), in parallel over local cores, each run a child `cleave run`,
// `measure` or `validate` in its own result folder; then one table of what each run gave, the
// replicates' means and spreads, a plot, and for a seed ensemble a Weibull fit of the strengths.

#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <thread>
#include <tuple>

#include "cleave_version.hpp"
#include "commands.hpp"
#include "io/budget.hpp"
#include "io/fragment_sizes.hpp"
#include "io/plot.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/sweep.hpp"
#include "io/validation_scenario.hpp"
#include "run_control.hpp"
#include "sim/measure.hpp"

extern char** environ;

namespace cleave::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Job {
  std::size_t index = 0;
  fs::path scenario, dir, log;
  pid_t pid = -1;
  Clock::time_point start;
  int exit_code = -1;
  double seconds = 0.0;
  io::Manifest manifest;
  bool has_manifest = false;
  /// What the run gave: its run.toml's facts, and a measurement's measure.toml over them.
  std::map<std::string, std::string> results;
};

std::string fact(const Job& j, const std::string& key) {
  const auto it = j.results.find(key);
  return it == j.results.end() ? std::string() : it->second;
}

/// A column of summary.csv after the status: its name and the result key it shows.
struct Column {
  std::string name, key;
};

/// The results each command's rows show. A validation's stage errors depend on the stages
/// its scenario checks, so they are the keys its runs gave.
std::vector<Column> result_columns(const SweepOptions& o, const std::vector<Job>& jobs) {
  std::vector<Column> c;
  if (o.command == "run") {
    c = {{"peak_load_N", "peak_load_N"},
         {"strength_Pa", "brazilian_strength_Pa"},
         {"bonds_broken", "intergranular_breaks"},
         {"splits", "transgranular_splits"}};
  } else if (o.command == "measure") {
    const sim::Test t = *sim::parse_test(o.test);
    // The judged value's key carries its unit (tensile_strength_Pa, k_ic_Pa_sqrt_m, ...).
    c.push_back({sim::judged_key(t), sim::judged_key(t)});
    if (sim::judged_key(t) != sim::value_key(t))
      c.push_back({sim::value_key(t), sim::value_key(t)});
    if (t == sim::Test::elastic) c.push_back({"poisson", "poisson"});
    for (const char* k : {"peak_load_N", "first_crack_load_N", "kinetic_ratio"})
      c.push_back({k, k});
    c.push_back({"bonds_broken", "intergranular_breaks"});
    c.push_back({"splits", "transgranular_splits"});
  } else {
    c.push_back({"verdict", "validation"});
    std::set<std::tuple<int, int, std::string>> stages;  // by stage, then mean, max, slope
    for (const Job& j : jobs)
      for (const auto& entry : j.results) {
        const std::string& k = entry.first;
        int n = 0;
        char kind[16] = {};
        if (std::sscanf(k.c_str(), "stage%d_%15[a-z]_error", &n, kind) != 2 ||
            k != fmt::format("stage{}_{}_error", n, kind))
          continue;
        const std::string m = kind;
        stages.insert({n, m == "mean" ? 0 : m == "max" ? 1 : 2, k});
      }
    for (const auto& st : stages) c.push_back({std::get<2>(st), std::get<2>(st)});
    for (const char* k : {"peak_error", "peak_load_N", "closed_form_peak_N"}) c.push_back({k, k});
  }
  for (const auto& k : o.columns)
    if (std::none_of(c.begin(), c.end(),
                     [&](const Column& x) { return x.key == k || x.name == k; }))
      c.push_back({k, k});
  return c;
}

/// A usage error of the options alone (empty: none).
std::string usage_error(const SweepOptions& o) {
  if (o.command == "measure" && !sim::parse_test(o.test))
    return o.test.empty()
               ? "--command measure needs --test elastic|brazilian|flexural|senb"
               : fmt::format("--test {}: the tests are elastic, brazilian, flexural, senb", o.test);
  if (o.command != "measure" && !o.test.empty())
    return fmt::format("--test {} is for --command measure", o.test);
  if (o.command != "run" && o.max_steps > 0)
    return fmt::format("--max-steps is for --command run; cleave {} runs to its end", o.command);
  if (o.command != "validate" && o.cohesive_beam_only)
    return "--cohesive-beam-only is for --command validate";
  if (o.seeds == 0 && !o.seed_key.empty())
    return "--seed-key names the key --seeds sets: give --seeds N";
  if (o.seeds > 0 && o.command == "validate" && o.seed_key.empty())
    return "--seeds: a validation's lattice draws nothing at random; name the key to vary with "
           "--seed-key";
  return {};
}

double number(const std::string& s) {
  if (s.empty()) return std::nan("");
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  return end && *end == '\0' ? v : std::nan("");
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

/// Starts `cleave COMMAND [TEST] SCENARIO --out DIR -q` with stdout and stderr into LOG.
pid_t spawn_run(const Job& job, const SweepOptions& o, int threads) {
  std::vector<std::string> args = {"cleave", o.command};
  if (o.command == "measure") args.push_back(o.test);
  for (const std::string& a :
       {job.scenario.string(), std::string("--out"), job.dir.string(), std::string("--quiet")})
    args.push_back(a);
  if (o.max_steps > 0) {
    args.push_back("--max-steps");
    args.push_back(std::to_string(o.max_steps));
  }
  if (o.cohesive_beam_only) args.push_back("--cohesive-beam-only");
  // cleave measure takes no memory limit.
  if (const io::MemoryLimit limit = io::memory_limit();
      o.command != "measure" && limit.bytes > 0 && (o.jobs > 1 || !o.max_memory.empty())) {
    args.push_back("--max-memory");
    args.push_back(std::to_string(limit.bytes));
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e)
    if (std::string_view(*e).substr(0, 16) != "OMP_NUM_THREADS=") env.emplace_back(*e);
  env.push_back(fmt::format("OMP_NUM_THREADS={}", threads));
  std::vector<char*> envp;
  for (auto& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, job.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error(fmt::format("cannot start a run: {}", std::strerror(rc)));
  return pid;
}

/// size_effect.csv and size_effect.svg of a size-and-seed sweep (io::fit_size_effect).
void write_size_effect(const std::filesystem::path& out, const std::string& key, const io::SizeEffect& e,
                       io::ResultRecord& record, bool quiet) {
  std::string csv = fmt::format("{},runs,mean_strength_Pa,stddev_Pa,weibull_modulus,weibull_scale_Pa\n",
                                csv_field(key));
  io::PlotSeries runs{"runs", {}, {}, "", true, false, 0.01}, means{"mean", {}, {}, "", true, false, 1.5};
  for (const auto& g : e.groups) {
    csv += fmt::format("{:.9g},{},{:.9g},{:.9g},{},{}\n", g.size, g.strengths.size(), g.mean, g.stddev,
                       g.weibull ? fmt::format("{:.6g}", g.weibull->modulus) : "",
                       g.weibull ? fmt::format("{:.9g}", g.weibull->scale) : "");
    for (double s : g.strengths) {
      runs.x.push_back(std::log10(g.size));
      runs.y.push_back(std::log10(s / 1e6));
    }
    means.x.push_back(std::log10(g.size));
    means.y.push_back(std::log10(g.mean / 1e6));
  }
  const double m = e.pooled ? e.pooled->modulus : NAN;
  csv += fmt::format("# mean strength = {:.6g} Pa x {}^-{:.6g} (least squares on the logarithms); pooled "
                     "Weibull modulus m = {:.6g} (each strength over its size's mean); Weibull's weakest "
                     "link for a volume growing as size^2 (a disc or plate of fixed thickness): "
                     "exponent 2/m = {:.6g}\n",
                     e.prefactor, key, e.exponent, m, 2.0 / m);
  io::write_file_atomically(out / "size_effect.csv", csv);
  io::Plot p;
  p.title = std::isfinite(m) ? fmt::format("size effect: strength ~ size^-{:.3g}; Weibull m = {:.3g} predicts 2/m = {:.3g}",
                                           e.exponent, m, 2.0 / m)
                              : fmt::format("size effect: strength ~ size^-{:.3g} (no scatter: no Weibull modulus)",
                                            e.exponent);
  p.x_label = fmt::format("log10({})", key);
  p.y_label = "log10(strength / MPa)";
  const double x0 = means.x.front(), x1 = means.x.back();
  const double y0 = means.y.front();
  io::PlotSeries fit{fmt::format("fit, slope -{:.3g}", e.exponent),
                     {x0, x1},
                     {std::log10(e.prefactor / 1e6) - e.exponent * x0, std::log10(e.prefactor / 1e6) - e.exponent * x1},
                     "", false, true, 1.5};
  p.series = {runs, means, fit};
  if (std::isfinite(m) && m > 0) {
    p.series.push_back({fmt::format("Weibull, slope -2/m = -{:.3g}", 2.0 / m), {x0, x1},
                        {y0, y0 - 2.0 / m * (x1 - x0)}, "", false, true, 1.0});
  }
  io::write_plot_svg(out / "size_effect.svg", p);
  record.manifest.facts["size_effect_exponent"] = fmt::format("{:.6g}", e.exponent);
  if (std::isfinite(m)) record.manifest.facts["weibull_modulus_pooled"] = fmt::format("{:.6g}", m);
  if (!quiet && std::isfinite(m)) {
    fmt::print("  size effect over {} sizes of {}: mean strength ~ size^-{:.4g}; pooled Weibull m = {:.4g} "
               "(weakest link for a volume ~ size^2: 2/m = {:.4g}) -> size_effect.csv, size_effect.svg\n",
               e.groups.size(), key, e.exponent, m, 2.0 / m);
  } else if (!quiet) {
    fmt::print("  size effect over {} sizes of {}: mean strength ~ size^-{:.4g}; every size's runs gave one "
               "strength, so there is no scatter for a Weibull modulus (orientation seeds change a "
               "strength only when grains split before the peak, with [fracture]) -> size_effect.csv, "
               "size_effect.svg\n",
               e.groups.size(), key, e.exponent);
  }
}

/// Whether an axis varies a seed: its runs are replicates of one another (a Weibull
/// ensemble, a size effect's scatter, a pooled fragment distribution), not a parameter.
bool is_seed(const io::SweepAxis& axis) {
  return axis.key.find("seed") != std::string::npos;
}

/// The fragment size distributions of the finished runs pooled per combination of the keys
/// that are not seeds (seeds are replicates), io::write_pooled_fragment_sizes.
void pool_fragments(const fs::path& out, const std::vector<io::SweepAxis>& axes,
                    const std::vector<io::SweepPoint>& points, const std::vector<Job>& jobs,
                    io::ResultRecord& record, bool quiet) {
  std::vector<std::pair<std::string, std::vector<fs::path>>> groups;
  for (const Job& j : jobs) {
    if (!j.has_manifest || j.manifest.status != io::run_status::finished) continue;
    std::string label;
    for (std::size_t k = 0; k < axes.size(); ++k)
      if (axes[k].values.size() > 1 && !is_seed(axes[k]))
        label += fmt::format("{}{}={}", label.empty() ? "" : " ", axes[k].key, points[j.index][k]);
    if (label.empty()) label = "all";
    auto it =
        std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == label; });
    if (it == groups.end()) it = groups.insert(groups.end(), {label, {}});
    it->second.push_back(j.dir);
  }
  const auto files = io::write_pooled_fragment_sizes(out, groups);
  if (!files.empty())
    record.manifest.facts["fragments_pooled_groups"] = std::to_string(groups.size());
  if (!quiet && !files.empty())
    fmt::print("  fragment sizes pooled over {} group(s) of runs -> {}\n", groups.size(),
               fmt::format("{}", fmt::join(files, ", ")));
}

}  // namespace

int sweep_command(const SweepOptions& o) {
  const auto t0 = Clock::now();
  // Everything about the inputs is checked before any run starts.
  if (const std::string e = usage_error(o); !e.empty()) {
    fmt::print(stderr, "cleave: error: command line: {}\n", e);
    return 2;
  }
  std::vector<io::SweepAxis> axes;
  std::vector<io::SweepPoint> points;
  std::string text;
  std::string base_name;
  bool dynamics = true;
  // Each command's reader of its scenario format.
  const io::ScenarioReader read = [&](const std::string& t, const std::string& source) {
    if (o.command == "validate")
      (void)io::parse_validation_scenario(t, source);
    else
      (void)io::parse_scenario(t, source);
  };
  int replicate = -1;  // the --seeds axis
  try {
    for (const auto& spec : o.sets) axes.push_back(io::parse_sweep_axis(spec));
    for (const auto& spec : o.zips) {
      axes.push_back(io::parse_sweep_axis(spec));
      axes.back().zipped = true;
    }
    if (o.seeds > 0) {
      // Last, so that a combination's replicates are neighbouring rows.
      axes.push_back(io::parse_sweep_axis(fmt::format(
          "{}=1..{}", o.seed_key.empty() ? std::string("orientation.seed") : o.seed_key, o.seeds)));
      replicate = static_cast<int>(axes.size()) - 1;
    }
    points = io::sweep_points(axes);
    // Runs side by side share the memory: each point is checked against its part.
    if (const io::MemoryLimit all = io::memory_limit(); all.bytes > 0 && o.jobs > 1)
      io::set_memory_limit(all.bytes / static_cast<std::uint64_t>(o.jobs),
                           fmt::format("{} shared by --jobs {}",
                                       o.max_memory.empty() ? "the memory available now"
                                                            : "--max-memory " + o.max_memory,
                                       o.jobs));
    if (o.command == "validate") {
      base_name = io::load_validation_scenario(o.scenario).name;
    } else {
      const io::Scenario base = io::load_scenario(o.scenario);
      base_name = base.name;
      dynamics = base.dynamics.enabled;
    }
    text = io::read_file(o.scenario);
  } catch (const io::ScenarioError& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: sweep: {}\n", e.what());
    return 2;
  }
  if (!dynamics) {
    fmt::print(stderr, "cleave: error: sweep: {} has no [dynamics]: nothing to compare\n",
               o.scenario.string());
    return 2;
  }
  if (o.jobs < 1) {
    fmt::print(stderr, "cleave: error: command line: --jobs must be at least 1\n");
    return 2;
  }
  const fs::path out = o.out.empty() ? fs::path("results") / (base_name + "_sweep") : o.out;
  io::FolderPlan plan;
  try {
    plan = io::check_result_folder(out, io::FolderClaim{"sweep", base_name, o.replace, false});
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "cleave: error: command line: {}\n", e.what());
    return 2;
  }
  const fs::path base_dir = fs::absolute(o.scenario).parent_path();
  std::vector<Job> jobs(points.size());
  std::vector<std::string> texts(points.size());
  std::vector<io::SweepPoint> absolute(points.size());  // each axis' value as written
  for (std::size_t i = 0; i < points.size(); ++i) {
    Job& j = jobs[i];
    j.index = i;
    const std::string name = fmt::format("run_{:03}", i + 1);
    j.scenario = out / "scenarios" / (name + ".toml");
    j.dir = out / name;
    j.log = out / (name + ".log");
    // A key the scenario cannot take fails here, before anything runs, naming the value.
    std::vector<std::string> shown;
    for (std::size_t k = 0; k < axes.size(); ++k)
      shown.push_back(static_cast<int>(k) == replicate
                          ? fmt::format("--seeds {} ({}={})", o.seeds, axes[k].key, points[i][k])
                          : fmt::format("--{} {}={}", axes[k].zipped ? "zip" : "set",
                                        axes[k].name(), points[i][k]));
    try {
      texts[i] = io::check_sweep_point(text, o.scenario.string(), axes, points[i], shown, base_dir,
                                       read, &absolute[i]);
    } catch (const io::ScenarioError& e) {
      fmt::print(stderr, "cleave: error: sweep: {}\n", e.what());
      return 2;
    } catch (const std::exception& e) {
      fmt::print(stderr, "cleave: error: sweep: {}\n", e.what());
      return 2;
    }
  }
  // run.toml says "running" from before the first file, so that every file is the sweep's.
  io::ResultRecord record(out);
  record.manifest.provenance["cleave_version"] = CLEAVE_VERSION;
  record.manifest.provenance["command"] = "sweep";
  record.manifest.facts["scenario"] = o.scenario.string();
  record.manifest.facts["scenario_name"] = base_name;
  record.manifest.facts["command"] = o.command;
  if (o.command == "measure") record.manifest.facts["test"] = o.test;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const auto& a = axes[k];
    if (static_cast<int>(k) == replicate) {
      record.manifest.facts["seeds"] = std::to_string(o.seeds);
      record.manifest.facts["seed_key"] = a.key;
      continue;
    }
    std::string v;
    for (std::size_t i = 0; i < a.values.size(); ++i) v += (i ? "," : "") + a.values[i];
    record.manifest.facts[(a.zipped ? "zip." : "set.") + a.name()] = v;
  }
  record.manifest.facts["runs"] = std::to_string(points.size());
  try {
    io::clear_result_folder(out, plan);
    fs::create_directories(out);
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: sweep: {}\n", e.what());
    return 1;
  }
  try {
    record.start();
    fs::create_directories(out / "scenarios");
    for (std::size_t i = 0; i < points.size(); ++i)
      io::write_file_atomically(jobs[i].scenario, texts[i]);
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: sweep: {}\n", e.what());
    record.close_quietly(io::run_status::failed, e.what());
    return 1;
  }
  install_stop_handlers();

  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const int threads = std::max(1, static_cast<int>(cores) / o.jobs);
  if (!o.quiet)
    fmt::print("cleave sweep: {} {}s of {} ({} at a time, {} thread(s) each) -> {}\n",
               points.size(), o.command == "measure" ? "measurement" : o.command,
               o.scenario.string(), o.jobs, threads, out.string());
  std::size_t next = 0, done = 0;
  std::map<pid_t, std::size_t> running;
  bool stopped = false;
  while (done < jobs.size()) {
    while (!stopped && next < jobs.size() && static_cast<int>(running.size()) < o.jobs) {
      if (stop_signal() != 0) {
        stopped = true;
        break;
      }
      Job& j = jobs[next++];
      j.start = Clock::now();
      try {
        j.pid = spawn_run(j, o, threads);
      } catch (const std::exception& e) {
        fmt::print(stderr, "cleave: error: sweep: {}\n", e.what());
        stopped = true;
        break;
      }
      running[j.pid] = j.index;
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    Job& j = jobs[it->second];
    running.erase(it);
    ++done;
    j.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    j.seconds = std::chrono::duration<double>(Clock::now() - j.start).count();
    try {
      j.manifest = io::read_manifest(j.dir);
      j.has_manifest = true;
      j.results = j.manifest.facts;
    } catch (const std::exception&) {
    }
    if (o.command == "measure")
      for (const auto& [k, v] : io::read_flat_toml(j.dir / "measure.toml")) j.results[k] = v;
    if (!o.quiet) {
      std::string set;
      for (std::size_t k = 0; k < axes.size(); ++k)
        set += fmt::format("{}{}={}", k ? " " : "", axes[k].name(), points[j.index][k]);
      std::string got;
      for (const Column& c : result_columns(o, {j}))
        got += fmt::format(", {} {}", c.name, fact(j, c.key).empty() ? "-" : fact(j, c.key));
      const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
      const double eta = elapsed / done * (jobs.size() - done);
      fmt::print("  {:>3}/{} {} ({}): {}{} [{:.1f} s]  ETA {:.0f} s\n", done, jobs.size(),
                 j.dir.filename().string(), set,
                 j.has_manifest ? j.manifest.status : fmt::format("exit {}", j.exit_code), got,
                 j.seconds, eta);
    }
  }
  if (stop_signal() != 0) stopped = true;

  // One row per run: the axes (a ratio's with the absolute value beside it), then the results.
  const std::vector<Column> columns = result_columns(o, jobs);
  std::vector<std::string> header = {"run"};
  std::vector<std::size_t> group_columns;  // the axes but the replicates'
  for (std::size_t k = 0; k < axes.size(); ++k) {
    if (static_cast<int>(k) != replicate) group_columns.push_back(header.size());
    header.push_back(axes[k].name());
    if (!axes[k].reference.empty()) {
      if (static_cast<int>(k) != replicate) group_columns.push_back(header.size());
      header.push_back(axes[k].key);
    }
  }
  header.insert(header.end(), {"status", "exit_code"});
  std::vector<std::size_t> value_columns;
  for (const Column& c : columns) {
    value_columns.push_back(header.size());
    header.push_back(c.name);
  }
  value_columns.push_back(header.size());
  header.insert(header.end(), {"wall_s", "folder"});
  std::vector<std::vector<std::string>> rows;
  std::vector<bool> counted;
  int failed = 0, cut = 0;  // cut: stopped by --max-steps, as asked (no strength counted)
  int verdicts_failed = 0;
  std::vector<double> strengths;
  for (const Job& j : jobs) {
    std::vector<std::string> row = {j.dir.filename().string()};
    for (std::size_t k = 0; k < axes.size(); ++k) {
      row.push_back(points[j.index][k]);
      if (!axes[k].reference.empty()) row.push_back(absolute[j.index][k]);
    }
    const std::string status =
        j.pid < 0 ? "not started" : (j.has_manifest ? j.manifest.status : "no manifest");
    // A validation that ran and failed its bounds exits 1: its verdict is the result.
    const bool judged = o.command == "validate" && j.exit_code == 1 &&
                        status == io::run_status::finished && fact(j, "validation") == "fail";
    if (j.pid >= 0 && j.exit_code == 0 && status == io::run_status::stopped)
      ++cut;
    else if (j.pid >= 0 && !judged && (j.exit_code != 0 || status != io::run_status::finished))
      ++failed;
    if (o.command == "validate" && fact(j, "validation") == "fail") ++verdicts_failed;
    row.push_back(status);
    row.push_back(std::to_string(j.exit_code));
    for (const Column& c : columns) row.push_back(fact(j, c.key));
    row.push_back(fmt::format("{:.3f}", j.seconds));
    row.push_back(j.dir.string());
    rows.push_back(std::move(row));
    counted.push_back(status == io::run_status::finished);
    const double s = number(fact(j, "brazilian_strength_Pa"));
    if (o.command == "run" && status == io::run_status::finished && std::isfinite(s) && s > 0)
      strengths.push_back(s);
  }
  std::string csv;
  for (std::size_t c = 0; c < header.size(); ++c) csv += (c ? "," : "") + csv_field(header[c]);
  csv += "\n";
  for (const auto& row : rows) {
    for (std::size_t c = 0; c < row.size(); ++c) csv += (c ? "," : "") + csv_field(row[c]);
    csv += "\n";
  }
  try {
    io::write_file_atomically(out / "summary.csv", csv);
    if (replicate >= 0) {
      // Only the numeric results: a column no run gave a number in is left out.
      std::vector<std::size_t> numeric;
      for (std::size_t c : value_columns)
        for (std::size_t r = 0; r < rows.size(); ++r)
          if (counted[r] && std::isfinite(number(rows[r][c]))) {
            numeric.push_back(c);
            break;
          }
      io::write_file_atomically(
          out / "summary_mean.csv",
          io::replicate_means_csv(header, rows, group_columns, numeric, counted));
      if (!o.quiet)
        fmt::print(
            "  {} replicates of each combination: mean, sample standard deviation and count "
            "of each result -> summary_mean.csv\n",
            o.seeds);
    }
    // The picture: the first swept key against the peak load (and strength), or for a seed
    // ensemble the Weibull plot.
    // Keys given one value (a longer stage for every run, a strength scatter, say) do not
    // count as swept: a seed alone among the varied keys makes an ensemble; a size (any
    // numeric key) varied with a seed, the size effect.
    std::vector<std::size_t> varied;
    for (std::size_t k = 0; k < axes.size(); ++k)
      if (axes[k].values.size() > 1) varied.push_back(k);
    const bool seeds = varied.size() == 1 && o.command == "run" && is_seed(axes[varied[0]]);
    int seed_axis = -1, size_axis = -1;
    if (varied.size() == 2 && o.command == "run") {
      for (int a = 0; a < 2; ++a)
        if (is_seed(axes[varied[a]]) && axes[varied[1 - a]].reference.empty()) {
          seed_axis = static_cast<int>(varied[a]);
          size_axis = static_cast<int>(varied[1 - a]);
        }
    }
    std::vector<std::pair<double, double>> sized;
    if (seed_axis >= 0) {
      for (const Job& j : jobs) {
        const double size = number(points[j.index][size_axis]);
        const double s = number(fact(j, "brazilian_strength_Pa"));
        const std::string status = j.has_manifest ? j.manifest.status : "";
        if (status == io::run_status::finished && std::isfinite(size) && std::isfinite(s) && s > 0)
          sized.emplace_back(size, s);
      }
    }
    std::set<double> sizes;
    for (const auto& [size, s] : sized) sizes.insert(size);
    if (seed_axis >= 0 && sizes.size() >= 2) {
      write_size_effect(out, axes[size_axis].key, io::fit_size_effect(sized), record, o.quiet);
    } else if (seeds && strengths.size() >= 3) {
      const io::WeibullFit fit = io::fit_weibull(strengths);
      std::string w = "rank,strength_Pa,ln_strength,ln_ln_1_over_1_minus_F\n";
      for (std::size_t i = 0; i < fit.sorted.size(); ++i)
        w += fmt::format("{},{:.9g},{:.9g},{:.9g}\n", i + 1, fit.sorted[i], fit.ln_strength[i],
                         fit.ln_ln[i]);
      w += fmt::format("# Weibull modulus m = {:.6g}, scale s0 = {:.9g} Pa, R^2 = {:.6f} "
                       "(median ranks (i - 0.3) / (n + 0.4), least squares)\n",
                       fit.modulus, fit.scale, fit.r_squared);
      io::write_file_atomically(out / "weibull.csv", w);
      io::Plot p;
      p.title = fmt::format("Weibull plot of {} strengths: m = {:.3g}, s0 = {:.4g} Pa",
                            fit.sorted.size(), fit.modulus, fit.scale);
      p.x_label = "ln(strength / Pa)";
      p.y_label = "ln(ln(1 / (1 - F)))";
      io::PlotSeries pts{"runs", fit.ln_strength, fit.ln_ln, "", true, false, 0.01};
      const double x0 = fit.ln_strength.front(), x1 = fit.ln_strength.back();
      io::PlotSeries line{"fit", {x0, x1},
                          {fit.modulus * (x0 - std::log(fit.scale)),
                           fit.modulus * (x1 - std::log(fit.scale))},
                          "", false, true, 1.5};
      p.series = {pts, line};
      io::write_plot_svg(out / "weibull.svg", p);
      record.manifest.facts["weibull_modulus"] = fmt::format("{:.6g}", fit.modulus);
      record.manifest.facts["weibull_scale_Pa"] = fmt::format("{:.9g}", fit.scale);
      if (!o.quiet)
        fmt::print("  Weibull fit of {} strengths: m = {:.4g}, s0 = {:.5g} Pa (R^2 = {:.4f}) -> "
                   "weibull.csv, weibull.svg\n",
                   fit.sorted.size(), fit.modulus, fit.scale, fit.r_squared);
    } else {
      // The first axis against the command's headline result.
      const std::string shown_key =
          columns.front().key == "validation" ? "peak_load_N" : columns.front().key;
      std::vector<double> x, y;
      bool numeric = true;
      for (const Job& j : jobs) {
        const double v = number(points[j.index][0]);
        numeric = numeric && std::isfinite(v);
        x.push_back(std::isfinite(v) ? v : static_cast<double>(j.index + 1));
        y.push_back(number(fact(j, shown_key)));
      }
      io::Plot p;
      p.title = fmt::format("{} {}s of {}", jobs.size(),
                            o.command == "measure" ? "measurement" : o.command, base_name);
      p.x_label = numeric ? axes[0].name() : "run";
      p.y_label = shown_key == "peak_load_N" ? "peak load (N)" : shown_key;
      p.series.push_back(
          {shown_key == "peak_load_N" ? "peak load" : shown_key, x, y, "", true, false, 1.5});
      io::write_plot_svg(out / "summary.svg", p);
    }
    pool_fragments(out, axes, points, jobs, record, o.quiet);
    record.manifest.facts["runs_failed"] = std::to_string(failed);
    record.manifest.facts["runs_stopped"] = std::to_string(cut);
    if (o.command == "validate")
      record.manifest.facts["validations_failed"] = std::to_string(verdicts_failed);
    if (stopped) {
      const int sig = stop_signal();
      record.close(io::run_status::interrupted,
                   fmt::format("stopped by {} after {} of {} runs", signal_name(sig ? sig : 2),
                               done, jobs.size()));
      if (!o.quiet) fmt::print("cleave sweep: interrupted -> {}\n", out.string());
      return exit_code_for_signal(sig ? sig : 2);
    }
    if (failed > 0)
      record.close(io::run_status::failed, fmt::format("{} of {} runs failed (see summary.csv "
                                                       "and their .log files)", failed, jobs.size()));
    else if (cut > 0)
      record.close(
          io::run_status::stopped,
          fmt::format("{} of {} runs stopped by --max-steps {} before their stages ended (their "
                      "strengths are left out of the fits)",
                      cut, jobs.size(), o.max_steps));
    else
      record.close(io::run_status::finished);
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: sweep: {}\n", e.what());
    record.close_quietly(io::run_status::failed, e.what());
    return 1;
  }
  if (!o.quiet)
    fmt::print("cleave sweep: {} runs, {} failed{}{}, {:.1f} s -> {}\n", jobs.size(), failed,
               cut > 0 ? fmt::format(", {} stopped by --max-steps", cut) : std::string(),
               o.command == "validate"
                   ? fmt::format(" ({} of the validations within their bounds)",
                                 static_cast<int>(jobs.size()) - failed - verdicts_failed)
                   : std::string(),
               std::chrono::duration<double>(Clock::now() - t0).count(),
               (out / "summary.csv").string());
  return failed > 0 ? 1 : 0;
}

}  // namespace cleave::app
