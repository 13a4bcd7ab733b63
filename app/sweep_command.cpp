// `cleave sweep`: one scenario run many times with keys set to each combination of values
// (--set KEY=VALUES ...; --zip KEY=VALUES keys vary together), in parallel over local cores, each
// run a child `cleave run` in its own result folder; then one table of what each run gave, a plot,
// and for a seed ensemble a Weibull fit of the strengths.

#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <thread>

#include "cleave_version.hpp"
#include "commands.hpp"
#include "io/budget.hpp"
#include "io/fragment_sizes.hpp"
#include "io/plot.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/sweep.hpp"
#include "run_control.hpp"

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
};

std::string fact(const Job& j, const std::string& key) {
  if (!j.has_manifest) return {};
  const auto it = j.manifest.facts.find(key);
  return it == j.manifest.facts.end() ? std::string() : it->second;
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

/// Starts `cleave run SCENARIO --out DIR -q` with stdout and stderr into LOG.
pid_t spawn_run(const Job& job, const SweepOptions& o, int threads) {
  std::vector<std::string> args = {"cleave", "run", job.scenario.string(), "--out",
                                   job.dir.string(), "--quiet"};
  if (o.max_steps > 0) {
    args.push_back("--max-steps");
    args.push_back(std::to_string(o.max_steps));
  }
  if (const io::MemoryLimit limit = io::memory_limit();
      limit.bytes > 0 && (o.jobs > 1 || !o.max_memory.empty())) {
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
      if (axes[k].values.size() > 1 && axes[k].key.find("seed") == std::string::npos)
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
  std::vector<io::SweepAxis> axes;
  std::vector<io::SweepPoint> points;
  std::string text;
  io::Scenario base;
  try {
    for (const auto& spec : o.sets) axes.push_back(io::parse_sweep_axis(spec));
    for (const auto& spec : o.zips) {
      axes.push_back(io::parse_sweep_axis(spec));
      axes.back().zipped = true;
    }
    points = io::sweep_points(axes);
    // Runs side by side share the memory: each point is checked against its part.
    if (const io::MemoryLimit all = io::memory_limit(); all.bytes > 0 && o.jobs > 1)
      io::set_memory_limit(all.bytes / static_cast<std::uint64_t>(o.jobs),
                           fmt::format("{} shared by --jobs {}",
                                       o.max_memory.empty() ? "the memory available now"
                                                            : "--max-memory " + o.max_memory,
                                       o.jobs));
    base = io::load_scenario(o.scenario);
    text = io::read_file(o.scenario);
  } catch (const io::ScenarioError& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: sweep: {}\n", e.what());
    return 2;
  }
  if (!base.dynamics.enabled) {
    fmt::print(stderr, "cleave: error: sweep: {} has no [dynamics]: nothing to compare\n",
               o.scenario.string());
    return 2;
  }
  if (o.jobs < 1) {
    fmt::print(stderr, "cleave: error: command line: --jobs must be at least 1\n");
    return 2;
  }
  const fs::path out = o.out.empty() ? fs::path("results") / (base.name + "_sweep") : o.out;
  io::FolderPlan plan;
  try {
    plan = io::check_result_folder(out, io::FolderClaim{"sweep", base.name, o.replace, false});
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "cleave: error: command line: {}\n", e.what());
    return 2;
  }
  const fs::path base_dir = fs::absolute(o.scenario).parent_path();
  std::vector<Job> jobs(points.size());
  std::vector<std::string> texts(points.size());
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
      shown.push_back(
          fmt::format("--{} {}={}", axes[k].zipped ? "zip" : "set", axes[k].key, points[i][k]));
    try {
      (void)io::read_sweep_point(text, o.scenario.string(), axes, points[i], shown, base_dir,
                                 &texts[i]);
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
  record.manifest.facts["scenario_name"] = base.name;
  for (const auto& a : axes) {
    std::string v;
    for (std::size_t k = 0; k < a.values.size(); ++k) v += (k ? "," : "") + a.values[k];
    record.manifest.facts[(a.zipped ? "zip." : "set.") + a.key] = v;
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
    fmt::print("cleave sweep: {} runs of {} ({} at a time, {} thread(s) each) -> {}\n",
               points.size(), o.scenario.string(), o.jobs, threads, out.string());
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
    } catch (const std::exception&) {
    }
    if (!o.quiet) {
      std::string set;
      for (std::size_t k = 0; k < axes.size(); ++k)
        set += fmt::format("{}{}={}", k ? " " : "", axes[k].key, points[j.index][k]);
      const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
      const double eta = elapsed / done * (jobs.size() - done);
      fmt::print("  {:>3}/{} {} ({}): {}, peak {} N, strength {} Pa, {} bonds broken, {} splits "
                 "[{:.1f} s]  ETA {:.0f} s\n",
                 done, jobs.size(), j.dir.filename().string(), set,
                 j.has_manifest ? j.manifest.status : fmt::format("exit {}", j.exit_code),
                 fact(j, "peak_load_N").empty() ? "-" : fact(j, "peak_load_N"),
                 fact(j, "brazilian_strength_Pa").empty() ? "-" : fact(j, "brazilian_strength_Pa"),
                 fact(j, "intergranular_breaks").empty() ? "-" : fact(j, "intergranular_breaks"),
                 fact(j, "transgranular_splits").empty() ? "-" : fact(j, "transgranular_splits"),
                 j.seconds, eta);
    }
  }
  if (stop_signal() != 0) stopped = true;

  // One row per run.
  std::string csv = "run";
  for (const auto& a : axes) csv += "," + csv_field(a.key);
  csv += ",status,exit_code,peak_load_N,strength_Pa,bonds_broken,splits,wall_s,folder\n";
  int failed = 0, cut = 0;  // cut: stopped by --max-steps, as asked (no strength counted)
  std::vector<double> strengths;
  for (const Job& j : jobs) {
    csv += j.dir.filename().string();
    for (const auto& v : points[j.index]) csv += "," + csv_field(v);
    const std::string status =
        j.pid < 0 ? "not started" : (j.has_manifest ? j.manifest.status : "no manifest");
    if (j.pid >= 0 && j.exit_code == 0 && status == io::run_status::stopped)
      ++cut;
    else if (j.pid >= 0 && (j.exit_code != 0 || status != io::run_status::finished))
      ++failed;
    csv += fmt::format(",{},{},{},{},{},{},{:.3f},{}\n", csv_field(status), j.exit_code,
                       fact(j, "peak_load_N"), fact(j, "brazilian_strength_Pa"),
                       fact(j, "intergranular_breaks"), fact(j, "transgranular_splits"),
                       j.seconds, csv_field(j.dir.string()));
    const double s = number(fact(j, "brazilian_strength_Pa"));
    if (status == io::run_status::finished && std::isfinite(s) && s > 0) strengths.push_back(s);
  }
  try {
    io::write_file_atomically(out / "summary.csv", csv);
    // The picture: the first swept key against the peak load (and strength), or for a seed
    // ensemble the Weibull plot.
    // Keys given one value (a longer stage for every run, a strength scatter, say) do not
    // count as swept: a seed alone among the varied keys makes an ensemble; a size (any
    // numeric key) varied with a seed, the size effect.
    std::vector<std::size_t> varied;
    for (std::size_t k = 0; k < axes.size(); ++k)
      if (axes[k].values.size() > 1) varied.push_back(k);
    const bool seeds = varied.size() == 1 && axes[varied[0]].key.find("seed") != std::string::npos;
    int seed_axis = -1, size_axis = -1;
    if (varied.size() == 2) {
      for (int a = 0; a < 2; ++a)
        if (axes[varied[a]].key.find("seed") != std::string::npos) {
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
      std::vector<double> x, peak, strength;
      bool numeric = true;
      for (const Job& j : jobs) {
        const double v = number(points[j.index][0]);
        numeric = numeric && std::isfinite(v);
        x.push_back(std::isfinite(v) ? v : static_cast<double>(j.index + 1));
        peak.push_back(number(fact(j, "peak_load_N")));
        strength.push_back(number(fact(j, "brazilian_strength_Pa")));
      }
      io::Plot p;
      p.title = fmt::format("{} runs of {}", jobs.size(), base.name);
      p.x_label = numeric ? axes[0].key : "run";
      p.y_label = "peak load (N)";
      p.series.push_back({"peak load", x, peak, "", true, false, 1.5});
      io::write_plot_svg(out / "summary.svg", p);
    }
    pool_fragments(out, axes, points, jobs, record, o.quiet);
    record.manifest.facts["runs_failed"] = std::to_string(failed);
    record.manifest.facts["runs_stopped"] = std::to_string(cut);
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
    fmt::print("cleave sweep: {} runs, {} failed{}, {:.1f} s -> {}\n", jobs.size(), failed,
               cut > 0 ? fmt::format(", {} stopped by --max-steps", cut) : std::string(),
               std::chrono::duration<double>(Clock::now() - t0).count(),
               (out / "summary.csv").string());
  return failed > 0 ? 1 : 0;
}

}  // namespace cleave::app
