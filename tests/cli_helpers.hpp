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

/// Runs a shell command line and waits for it: its stdout and exit status.
inline CliOutcome run_shell(const std::string& cmd) {
  CliOutcome o;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return o;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) o.output.append(buf, n);
  const int status = pclose(pipe);
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

/// Runs `cleave ARGS` through the shell and waits for it.
inline CliOutcome run_cleave(const std::string& args) {
  return run_shell(std::string(CLEAVE_BINARY) + " " + args + " 2>&1");
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

/// A few hexagonal prisms dropped onto a floor (scenarios/demo_drop.toml, smaller): a run of
/// seconds at most. `name` and the [dynamics] lines (duration, frames, ...) are spliced in.
inline std::string drop_scenario(const std::string& name, const std::string& dynamics) {
  return "[scenario]\nname = \"" + name + R"("
[specimen]
shape = "box"
size = [4.0, 4.0, 1.0]
[grain]
r = 1.0
r_bar = 0.9
t = 1.0
t_bar = 0.85
[orientation]
seed = 7
[contact]
dilation_radius = 0.05
[contact.particle_particle]
kn = 5000.0
ks = 2000.0
c_res = 2.0
mu_s = 0.3
[contact.particle_wall]
kn = 10000.0
ks = 2000.0
c_res = 10.0
mu_s = 0.3
[dynamics]
dt = 1.2e-6
lift = 20.0
)" + dynamics +
         R"(
[[wall]]
name = "floor"
kind = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
)";
}

}  // namespace cleave::testing
