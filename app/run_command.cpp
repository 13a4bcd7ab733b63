// `cleave run` / `cleave restart`: the command line over sim::Simulation; this file maps
// what happens to the messages and exit codes of the CLI (2: bad input, 1: a failed run,
// 128 + signal: stopped).

#include <fmt/format.h>

#include "commands.hpp"
#include "io/checkpoint.hpp"
#include "io/scenario.hpp"
#include "run_control.hpp"
#include "sim/simulation.hpp"

namespace cleave::app {

int run_command(const RunOptions& options) {
  install_stop_handlers();
  sim::SimulationOptions so;
  so.out = options.out;
  so.quiet = options.quiet;
  so.max_steps = options.max_steps;
  so.checkpoint_every = options.checkpoint_every;
  so.mesh_format = options.mesh_format;
  so.mesh_layout = options.mesh_layout;
  so.stop_requested = [] { return stop_signal() != 0; };
  so.stop_reason = [] { return fmt::format("stopped by {}", signal_name(stop_signal())); };

  std::unique_ptr<sim::Simulation> run;
  try {
    run = options.restart.empty() ? sim::Simulation::open(options.scenario, so)
                                  : sim::Simulation::restart(options.restart, so);
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
  switch (report.status) {
    case sim::RunReport::Status::finished:
      return 0;
    case sim::RunReport::Status::failed:
      fmt::print(stderr, "cleave: error: {}\n", report.message);
      return 1;
    case sim::RunReport::Status::interrupted:
      fmt::print(stderr, "cleave: {}; the result folder {} holds what was done so far (status "
                         "interrupted)\n", report.message, report.out.string());
      return exit_code_for_signal(stop_signal());
  }
  return 1;
}

}  // namespace cleave::app
