/// \file
/// libFuzzer target: the `cleave` command line (app/cli.hpp, the parser the executable uses)
/// and the override strings it takes: `--set KEY=VALUE` of run/measure as io::parse_overrides
/// reads them and `--set`/`--zip KEY=VALUES` of sweep as io::parse_sweep_axis and
/// io::sweep_points do, each then applied to scenarios/demo.toml and read
/// (io::read_sweep_point). Nothing is run.
/// The input is the argument list, one argument per line (argv[0] is "cleave").
/// Expected for bad input: CLI::ParseError (help and version included), io::SweepError and
/// io::ScenarioError. Anything else escaping -- another exception type, a crash, a sanitizer
/// report, a hang -- is a bug.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "app/cli.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/sweep.hpp"

namespace {

const std::filesystem::path kScenario = std::filesystem::path(CLEAVE_SOURCE_DIR) / "scenarios/demo.toml";

const std::string& scenario_text() {
  static const std::string text = cleave::io::read_file(kScenario);
  return text;
}

/// The scenario with one point's values set, read as `cleave run --set` / a sweep run would.
void read_with(const std::vector<cleave::io::SweepAxis>& axes, const cleave::io::SweepPoint& point) {
  std::vector<std::string> shown;
  for (std::size_t k = 0; k < axes.size(); ++k) shown.push_back("--set " + axes[k].key + "=" + point[k]);
  (void)cleave::io::read_sweep_point(scenario_text(), kScenario.string(), axes, point, shown,
                                     kScenario.parent_path());
}

void overrides(const std::vector<std::string>& sets) {
  if (sets.empty()) return;
  auto [axes, point] = cleave::io::parse_overrides(sets, "--set");
  read_with(axes, point);
}

void sweep(const std::vector<std::string>& sets, const std::vector<std::string>& zips) {
  std::vector<cleave::io::SweepAxis> axes;
  for (const auto& s : sets) axes.push_back(cleave::io::parse_sweep_axis(s));
  for (const auto& z : zips) {
    axes.push_back(cleave::io::parse_sweep_axis(z));
    axes.back().zipped = true;
  }
  if (axes.empty()) return;
  const auto points = cleave::io::sweep_points(axes, 64);
  if (!points.empty()) read_with(axes, points.front());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> args{"cleave"};
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    args.emplace_back(text.substr(start, end - start));
    start = end + 1;
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());

  cleave::app::Cli cli;
  try {
    cli.app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError&) {
    return 0;
  }
  (void)cli.usage_error();
  try {
    overrides(cli.run.sets);
    overrides(cli.measure.sets);
    sweep(cli.sweep.sets, cli.sweep.zips);
  } catch (const cleave::io::SweepError&) {
  } catch (const cleave::io::ScenarioError&) {
  }
  return 0;
}
