// cleave: exact-polyhedron DEM fracture of brittle polycrystals. Command-line entry point.

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "cli.hpp"
#include "io/budget.hpp"
#ifdef CLEAVE_HAVE_MPI
#include "parallel/mpi_domain.hpp"
#endif

#ifndef CLEAVE_HAVE_MPI
namespace {
/// The number of processes mpirun started (1 when it did not), from its environment.
int mpirun_size() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    if (const char* s = std::getenv(v)) return std::max(1, std::atoi(s));
  }
  return 1;
}
}  // namespace
#endif

int main(int argc, char** argv) {
  using namespace cleave::app;
  auto cli = std::make_unique<Cli>();
  auto& [app, run, restart, check, validate, sweep, materials, measure, calibrate, run_cmd, restart_cmd,
         check_cmd, volume_cmd, sweep_cmd, validate_cmd, materials_cmd, measure_cmd, calibrate_cmd] = *cli;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end through here with 0; every other is a usage error: exit 2.
    return app.exit(e) == 0 ? 0 : 2;
  }

  // Several processes: `cleave run` splits the specimen among them (parallel/); nothing
  // else does, and a build without MPI says so rather than running N copies.
#ifdef CLEAVE_HAVE_MPI
  std::unique_ptr<cleave::parallel::MpiSession> mpi;
  if (cleave::parallel::launched_by_mpirun()) mpi = std::make_unique<cleave::parallel::MpiSession>(argc, argv);
  const int processes = mpi ? mpi->size() : 1;
  if (processes > 1 && !run_cmd->parsed() && !restart_cmd->parsed()) {
    if (!mpi || mpi->rank() == 0)
      fmt::print(stderr, "cleave: error: only `cleave run` runs on several MPI processes (mpirun -np {})\n", processes);
    return 2;
  }
  run.mpi_size = restart.mpi_size = mpi ? mpi->size() : 0;  // mpirun -np 1 too: the same code path
#else
  const int processes = mpirun_size();
  if (processes > 1) {
    fmt::print(stderr, "cleave: error: started by mpirun with {} processes, but this cleave was built without "
                       "MPI (install libopenmpi-dev and rebuild with -DCLEAVE_MPI=ON)\n", processes);
    return 2;
  }
#endif

  if (const std::string error = cli->usage_error(); !error.empty()) {
    fmt::print(stderr, "{}\n", error);
    return 2;
  }
  // --max-memory: the limit a specimen's estimate is checked against before it is built.
  const std::string& max_memory = run_cmd->parsed()       ? run.max_memory
                                  : restart_cmd->parsed() ? restart.max_memory
                                  : sweep_cmd->parsed()   ? sweep.max_memory
                                                          : validate.max_memory;
  if (!max_memory.empty()) {
    try {
      cleave::io::set_memory_limit(cleave::io::parse_memory_size(max_memory), "--max-memory " + max_memory);
    } catch (const std::invalid_argument& e) {
      fmt::print(stderr, "cleave: error: command line: --max-memory: {}\n", e.what());
      return 2;
    }
  }
  if (run_cmd->parsed()) return run_command(run);
  if (restart_cmd->parsed()) return run_command(restart);
  if (volume_cmd->parsed()) return check_volume_command(check);
  if (sweep_cmd->parsed()) return sweep_command(sweep);
  if (validate_cmd->parsed()) return validate_command(validate);
  if (materials_cmd->parsed()) return materials_command(materials);
  if (measure_cmd->parsed()) return measure_command(measure);
  if (calibrate_cmd->parsed()) return calibrate_command(calibrate);
  return 2;
}
