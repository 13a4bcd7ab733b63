#pragma once
/// \file
/// The `cleave` command line: every sub-command's options, parsed into the option structs of
/// commands.hpp. Kept apart from main() so that the fuzz target (fuzz/fuzz_cli.cpp) parses
/// the same options the executable does, without running anything.

#include <CLI/CLI.hpp>

#include <string>

#include "commands.hpp"

namespace cleave::app {

/// The parser and what it fills. Not copyable: CLI11 keeps pointers to the members.
struct Cli {
  Cli();
  Cli(const Cli&) = delete;
  Cli& operator=(const Cli&) = delete;

  /// After a successful parse: what the parser cannot check by itself (a scenario or a
  /// --restart, not both), as a message for stderr; empty when the command line is usable.
  [[nodiscard]] std::string usage_error() const;

  CLI::App app;
  RunOptions run;
  RunOptions restart;
  CheckVolumeOptions check;
  ValidateOptions validate;
  SweepOptions sweep;
  MaterialsOptions materials;
  MeasureOptions measure;
  CalibrateOptions calibrate;

  CLI::App* run_cmd = nullptr;
  CLI::App* restart_cmd = nullptr;
  CLI::App* check_cmd = nullptr;
  CLI::App* volume_cmd = nullptr;
  CLI::App* sweep_cmd = nullptr;
  CLI::App* validate_cmd = nullptr;
  CLI::App* materials_cmd = nullptr;
  CLI::App* measure_cmd = nullptr;
  CLI::App* calibrate_cmd = nullptr;
};

}  // namespace cleave::app
