#include "io/orientation_file.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>

#include "geometry/orientation.hpp"
#include "io/scenario.hpp"

namespace cleave::io {

namespace {

struct Token {
  std::string_view text;
  int column;  ///< 1-based
};

std::vector<Token> split(std::string_view line) {
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) out.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return out;
}

/// One data line: the grain index (with the index layout) and the angles in degrees.
struct Row {
  long long grain = -1;
  double phi1 = 0, Phi = 0, phi2 = 0;
  int line = 0, grain_column = 0;
};

}  // namespace

std::vector<Eigen::Quaterniond> read_orientation_file(const std::filesystem::path& file,
                                                      std::optional<std::size_t> grain_count) {
  const std::string source = file.string();
  const auto fail = [&](int line, int column, const std::string& key, const std::string& what) {
    throw ScenarioError(source, line, column, key, what);
  };
  std::ifstream in(file);
  if (!in) fail(0, 0, "", "cannot open the orientation file");

  std::vector<Row> rows;
  std::size_t layout = 0;  // 3 or 4 columns, fixed by the first data line
  int layout_line = 0;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::string_view view(text);
    if (const auto hash = view.find('#'); hash != std::string_view::npos)
      view = view.substr(0, hash);
    if (!view.empty() && view.back() == '\r') view.remove_suffix(1);
    const auto tokens = split(view);
    if (tokens.empty()) continue;
    if (tokens.size() != 3 && tokens.size() != 4)
      fail(line, tokens.front().column, "",
           fmt::format("expected 3 columns (phi1 Phi phi2) or 4 (grain phi1 Phi phi2), found {}",
                       tokens.size()));
    if (layout == 0) {
      layout = tokens.size();
      layout_line = line;
    } else if (tokens.size() != layout) {
      fail(line, tokens.front().column, "",
           fmt::format("{} columns, but line {} has {}: use one layout for the whole file",
                       tokens.size(), layout_line, layout));
    }
    Row row;
    row.line = line;
    std::size_t k = 0;
    if (layout == 4) {
      const Token& t = tokens[k++];
      const char* end = t.text.data() + t.text.size();
      const auto [ptr, ec] = std::from_chars(t.text.data(), end, row.grain);
      if (ec != std::errc() || ptr != end)
        fail(line, t.column, "grain",
             fmt::format("'{}' is not a grain index (0, 1, 2, ...)", t.text));
      if (row.grain < 0)
        fail(line, t.column, "grain", fmt::format("grain index {} is negative", row.grain));
      row.grain_column = t.column;
    }
    double* angles[3] = {&row.phi1, &row.Phi, &row.phi2};
    const char* names[3] = {"phi1", "Phi", "phi2"};
    for (int a = 0; a < 3; ++a, ++k) {
      const Token& t = tokens[k];
      const char* end = t.text.data() + t.text.size();
      const auto [ptr, ec] = std::from_chars(t.text.data(), end, *angles[a]);
      if (ec != std::errc() || ptr != end || !std::isfinite(*angles[a]))
        fail(line, t.column, names[a],
             fmt::format("'{}' is not a finite number of degrees", t.text));
    }
    if (row.Phi < 0.0 || row.Phi > 180.0)
      fail(line, tokens[k - 2].column, "Phi",
           fmt::format("{} degrees is outside [0, 180]", tokens[k - 2].text));
    rows.push_back(row);
  }
  if (in.bad()) fail(0, 0, "", "read error in the orientation file");
  if (rows.empty()) fail(0, 0, "", "no orientations (every line is blank or a comment)");
  const std::size_t n = grain_count.value_or(rows.size());
  if (grain_count && rows.size() != n)
    fail(0, 0, "",
         fmt::format("{} orientations for {} grains: give one line per grain", rows.size(), n));

  if (layout == 4) {
    std::map<long long, int> first_line;  // grain index -> the line that gave it
    for (const Row& r : rows)
      if (const auto [it, fresh] = first_line.emplace(r.grain, r.line); !fresh)
        fail(r.line, r.grain_column, "grain",
             fmt::format("grain {} is given twice (first on line {})", r.grain, it->second));
    for (const Row& r : rows)
      if (static_cast<std::size_t>(r.grain) >= n) {
        std::size_t missing = 0;
        while (first_line.count(static_cast<long long>(missing))) ++missing;
        fail(r.line, r.grain_column, "grain",
             fmt::format("grain {} is out of range: {} grains have indices 0 to {}, and grain {} "
                         "has no line",
                         r.grain, n, n - 1, missing));
      }
  }
  // n lines and no index twice or out of range: every grain has its line.
  constexpr double deg = std::numbers::pi / 180.0;
  std::vector<Eigen::Quaterniond> out(n);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    out[layout == 4 ? static_cast<std::size_t>(r.grain) : i] =
        geometry::from_bunge(r.phi1 * deg, r.Phi * deg, r.phi2 * deg);
  }
  return out;
}

void write_orientation_file(const std::filesystem::path& file,
                            const std::vector<Eigen::Quaterniond>& orientations) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write the orientation file '" + file.string() + "'");
  out << "# grain phi1 Phi phi2: Bunge Euler angles in degrees; the rows of\n"
         "# g = Rz(phi2) Rx(Phi) Rz(phi1) are the crystal axes in specimen coordinates\n";
  constexpr double deg = 180.0 / std::numbers::pi;
  for (std::size_t i = 0; i < orientations.size(); ++i) {
    const auto e = geometry::to_bunge(orientations[i]);
    out << fmt::format("{} {} {} {}\n", i, e[0] * deg, e[1] * deg, e[2] * deg);
  }
  if (!out) throw std::runtime_error("write error in the orientation file '" + file.string() + "'");
}

}  // namespace cleave::io
