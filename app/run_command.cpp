// `cleave run` / `cleave restart`: the command line over sim::Simulation; this file maps
// what happens to the messages and exit codes of the CLI (2: bad input, 1: a failed run,
// 128 + signal: interrupted; 0: finished, or stopped by --max-steps as asked).

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <filesystem>
#include <string>

#include "commands.hpp"
#include "io/checkpoint.hpp"
#include "io/scenario.hpp"
#include "io/sweep.hpp"
#include "run_control.hpp"
#include "sim/simulation.hpp"

#ifdef CLEAVE_HAVE_MPI
#include <memory>

#include "parallel/mpi_domain.hpp"
#endif

namespace cleave::app {

namespace {

std::string this_host() {
  std::array<char, 256> buf{};
  return ::gethostname(buf.data(), buf.size() - 1) == 0 ? std::string(buf.data())
                                                        : std::string("host");
}

#ifdef CLEAVE_HAVE_MPI
/// The scratch folder of MPI rank `rank` of this process: the host and pid in its name say
/// whose it is, so that a later run can tell one left by a killed run.
std::filesystem::path scratch_folder(int rank) {
  return std::filesystem::temp_directory_path() /
         fmt::format("cleave-rank{}-{}-{}", rank, this_host(), static_cast<long>(::getpid()));
}
#endif

/// Removes the scratch folders (cleave-rankN-HOST-PID in the temp folder) that runs on this
/// host left when they were killed: those whose process is gone (and cleave-rankN-PID, the
/// name earlier versions gave them). A kill(2) that cannot tell (another user's process)
/// keeps the folder.
void remove_stale_scratch() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path tmp = fs::temp_directory_path(ec);
  if (ec) return;
  const std::string host = this_host();
  for (auto it = fs::directory_iterator(tmp, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const std::string prefix = "cleave-rank";
    std::error_code kind;
    if (name.rfind(prefix, 0) != 0 || it->is_symlink(kind) || !it->is_directory(kind)) continue;
    // cleave-rank<N>-<host>-<pid>, or cleave-rank<N>-<pid>
    const auto dash = name.find('-', prefix.size());
    const auto last = name.rfind('-');
    if (dash == std::string::npos ||
        (last != dash && name.substr(dash + 1, last - dash - 1) != host))
      continue;
    const std::string rank = name.substr(prefix.size(), dash - prefix.size());
    const std::string pid = name.substr(last + 1);
    if (rank.empty() || pid.empty() || pid.size() > 9 ||
        rank.find_first_not_of("0123456789") != std::string::npos ||
        pid.find_first_not_of("0123456789") != std::string::npos)
      continue;
    if (::kill(static_cast<pid_t>(std::stol(pid)), 0) == 0 || errno != ESRCH) continue;
    std::error_code rm;
    fs::remove_all(it->path(), rm);
  }
}

}  // namespace

int run_command(const RunOptions& options) {
  install_stop_handlers();
  remove_stale_scratch();
  sim::SimulationOptions so;
  so.out = options.out;
  so.quiet = options.quiet;
  so.max_steps = options.max_steps;
  so.checkpoint_every = options.checkpoint_every;
  so.timing = options.timing;
  so.mesh_format = options.mesh_format;
  so.mesh_layout = options.mesh_layout;
  so.replace = options.replace;
  so.stop_requested = [] { return stop_signal() != 0; };
  so.stop_reason = [] { return fmt::format("stopped by {}", signal_name(stop_signal())); };

#ifdef CLEAVE_HAVE_MPI
  // Several processes (mpirun -np N): each steps its region of the specimen; the first
  // writes the result folder, the others work in a scratch folder removed at the end.
  std::unique_ptr<parallel::MpiDomain> domain;
  std::filesystem::path scratch;
  struct Cleanup {
    std::filesystem::path* dir;
    ~Cleanup() {
      std::error_code ec;
      if (!dir->empty()) std::filesystem::remove_all(*dir, ec);
    }
  } cleanup{&scratch};
  if (options.mpi_size >= 1) {
    domain = std::make_unique<parallel::MpiDomain>();
    so.domain = domain.get();
    if (domain->rank() != 0) {
      scratch = scratch_folder(domain->rank());
      so.out = scratch;
      so.quiet = true;
    }
  }
#endif

  std::unique_ptr<sim::Simulation> run;
  try {
    run = options.restart.empty() ? sim::Simulation::open(options.scenario, so, options.sets)
                                  : sim::Simulation::restart(options.restart, so);
  } catch (const io::ScenarioError& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 2;
  } catch (const io::CheckpointError& e) {
    fmt::print(stderr, "cleave: error: cannot restart: {}\n", e.what());
    return 2;
  } catch (const io::SweepError& e) {  // a malformed --set
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "cleave: error: command line: {}\n", e.what());
    return 2;
  }

  sim::RunReport report;
  try {
    report = run->run();
  } catch (const io::ScenarioError& e) {  // the time step is above the stable limit
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "cleave: error: {}\n", e.what());
    return 1;
  }
#ifdef CLEAVE_HAVE_MPI
  if (domain) {
    // What the decomposition cost, per process (a collective call: every process is here).
    const auto stats = domain->all_stats();
    if (domain->rank() == 0 && !options.quiet) {
      fmt::print(stderr, "cleave: {} MPI processes (halo {:.4g} m):\n", stats.size(), domain->halo());
      for (std::size_t r = 0; r < stats.size(); ++r) {
        const auto& st = stats[r];
        fmt::print(stderr,
                   "  rank {}: {} bodies owned, {} ghosts; {} re-partitions ({} re-cut, {:.3f} s); "
                   "{} bodies migrated; MPI {:.3f} s; {:.1f} kB of ghost states sent per exchange, {:.1f} MB sent in all\n",
                   r, st.owned, st.ghosts, st.repartitions, st.rebalances, st.rebalance_seconds, st.migrated,
                   st.communication_seconds,
                   st.exchanges ? static_cast<double>(st.ghost_bytes) / 1e3 / static_cast<double>(st.exchanges) : 0.0,
                   static_cast<double>(st.bytes_sent) / 1e6);
      }
    }
  }
#endif
  switch (report.status) {
    case sim::RunReport::Status::finished:
      return 0;
    case sim::RunReport::Status::stopped:
      // The user asked for the limit: not an error, but the result is not the whole run.
      if (!options.quiet) {
        fmt::print(stderr,
                   "cleave: {}; the result folder {} holds the run up to there (status "
                   "stopped)\n",
                   report.message, report.out.string());
      }
      return 0;
    case sim::RunReport::Status::failed:
      fmt::print(stderr, "cleave: error: {}\n", report.message);
      return 1;
    case sim::RunReport::Status::interrupted:
      fmt::print(stderr, "cleave: {}; the result folder {} holds what was done so far (status "
                         "interrupted)\n", report.message, report.out.string());
      if (std::filesystem::exists(report.out / io::kCheckpointName)) {
        fmt::print(stderr, "cleave: continue it with: cleave restart {}\n", report.out.string());
      } else {
        fmt::print(stderr, "cleave: it stopped before its dynamics began (no checkpoint): run it again\n");
      }
      return exit_code_for_signal(stop_signal());
  }
  return 1;
}

}  // namespace cleave::app
