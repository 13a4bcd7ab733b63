#pragma once
/// \file
/// Running the `cleave` executable from a test (CLEAVE_BINARY, set by tests/CMakeLists.txt)
/// and reading back the CSV tables it writes.

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace cleave::testing {

struct CliOutcome {
  int code = -1;       ///< exit status (-1: did not exit normally)
  std::string output;  ///< stdout and stderr
};

/// Runs `cleave ARGS` through the shell and waits for it.
inline CliOutcome run_cleave(const std::string& args) {
  const std::string cmd = std::string(CLEAVE_BINARY) + " " + args + " 2>&1";
  CliOutcome o;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return o;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) o.output.append(buf, n);
  const int status = pclose(pipe);
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

/// The rows of a CSV file as text cells (header included; lines starting with # skipped).
inline std::vector<std::vector<std::string>> read_csv_cells(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace cleave::testing
