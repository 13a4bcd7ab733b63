#include "io/sweep.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>

namespace cleave::io {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

bool parse_int(const std::string& s, long long& out) {
  const char* end = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && p == end;
}

bool parse_double(const std::string& s, double& out) {
  if (s.empty()) return false;
  std::istringstream in(s);
  in.imbue(std::locale::classic());
  in >> out;
  return in && in.peek() == std::char_traits<char>::eof() && std::isfinite(out);
}

/// One step of a key path: a name, and for `name[N]` the 1-based index into an array.
struct PathStep {
  std::string name;
  int index = 0;  // 0: a table
};

std::vector<PathStep> split_key(const std::string& key) {
  std::vector<PathStep> steps;
  std::stringstream ss(key);
  std::string part;
  while (std::getline(ss, part, '.')) {
    PathStep step;
    const auto open = part.find('[');
    if (open != std::string::npos) {
      long long n = 0;
      if (part.back() != ']' || !parse_int(part.substr(open + 1, part.size() - open - 2), n) ||
          n < 1)
        throw SweepError(fmt::format("--set {}: '{}': expected name[N] with N = 1, 2, ...", key,
                                     part));
      step.index = static_cast<int>(n);
      part = part.substr(0, open);
    }
    if (part.empty()) throw SweepError(fmt::format("--set {}: empty name in the key", key));
    step.name = part;
    steps.push_back(step);
  }
  if (steps.size() < 2 || steps.back().index != 0)
    throw SweepError(fmt::format(
        "--set {}: expected table.key (e.g. bond.tbn, stage[2].velocity), found '{}'", key, key));
  return steps;
}

void assign(toml::table& table, const std::string& name, const std::string& value) {
  long long i = 0;
  double d = 0.0;
  if (parse_int(value, i))
    table.insert_or_assign(name, static_cast<std::int64_t>(i));
  else if (parse_double(value, d))
    table.insert_or_assign(name, d);
  else if (value == "true" || value == "false")
    table.insert_or_assign(name, value == "true");
  else
    table.insert_or_assign(name, value);
}

}  // namespace

SweepAxis parse_sweep_axis(const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
    throw SweepError(fmt::format("--set '{}': expected KEY=VALUES, e.g. orientation.seed=1..20 "
                                 "or bond.tbn=500,1000,2000",
                                 spec));
  SweepAxis axis;
  axis.key = trim(spec.substr(0, eq));
  split_key(axis.key);  // validates the shape of the key
  const std::string values = trim(spec.substr(eq + 1));
  const auto dots = values.find("..");
  if (dots != std::string::npos) {
    long long lo = 0, hi = 0;
    if (!parse_int(trim(values.substr(0, dots)), lo) || !parse_int(trim(values.substr(dots + 2)), hi))
      throw SweepError(fmt::format("--set '{}': a range is two integers, LO..HI", spec));
    if (hi < lo) throw SweepError(fmt::format("--set '{}': the range is empty ({} > {})", spec, lo, hi));
    // The length in unsigned arithmetic: hi - lo of two far-apart long longs overflows (and
    // wrapped negative, it passed, and the loop allocated until bad_alloc).
    if (static_cast<unsigned long long>(hi) - static_cast<unsigned long long>(lo) >= 100000)
      throw SweepError(
          fmt::format("--set '{}': the range is too long (at most 100000 values)", spec));
    for (long long v = lo; v <= hi; ++v) axis.values.push_back(std::to_string(v));
  } else {
    std::stringstream ss(values);
    std::string v;
    while (std::getline(ss, v, ',')) {
      v = trim(v);
      if (v.empty()) throw SweepError(fmt::format("--set '{}': an empty value in the list", spec));
      axis.values.push_back(v);
    }
  }
  if (axis.values.empty()) throw SweepError(fmt::format("--set '{}': no values", spec));
  return axis;
}

std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes, std::size_t limit) {
  if (axes.empty())
    throw SweepError("a sweep needs at least one --set KEY=VALUES or --zip KEY=VALUES");
  for (const auto& a : axes)
    if (a.values.empty())
      throw SweepError(fmt::format("--{} {}: no values", a.zipped ? "zip" : "set", a.key));
  for (std::size_t i = 0; i < axes.size(); ++i)
    for (std::size_t j = i + 1; j < axes.size(); ++j)
      if (axes[i].key == axes[j].key)
        throw SweepError(fmt::format("{} is given twice", axes[i].key));
  // The factors of the product: each --set axis, and the zipped axes as one.
  std::vector<std::vector<std::size_t>> factors;
  int zip_factor = -1;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    if (!axes[k].zipped) {
      factors.push_back({k});
      continue;
    }
    if (zip_factor < 0) {
      zip_factor = static_cast<int>(factors.size());
      factors.emplace_back();
    }
    const auto& first = axes[factors[static_cast<std::size_t>(zip_factor)].empty()
                                 ? k
                                 : factors[static_cast<std::size_t>(zip_factor)].front()];
    if (axes[k].values.size() != first.values.size())
      throw SweepError(
          fmt::format("--zip {} has {} values but --zip {} has {}: zipped keys vary together, "
                      "so each needs as many values",
                      axes[k].key, axes[k].values.size(), first.key, first.values.size()));
    factors[static_cast<std::size_t>(zip_factor)].push_back(k);
  }
  std::size_t total = 1;
  for (const auto& f : factors) {
    const std::size_t n = axes[f.front()].values.size();
    if (total > limit / n) throw SweepError(fmt::format("the sweep has more than {} runs", limit));
    total *= n;
  }
  std::vector<SweepPoint> points;
  points.reserve(total);
  std::vector<std::size_t> at(factors.size(), 0);
  for (std::size_t n = 0; n < total; ++n) {
    SweepPoint p(axes.size());
    for (std::size_t f = 0; f < factors.size(); ++f)
      for (std::size_t k : factors[f]) p[k] = axes[k].values[at[f]];
    points.push_back(std::move(p));
    for (std::size_t f = factors.size(); f-- > 0;) {
      if (++at[f] < axes[factors[f].front()].values.size()) break;
      at[f] = 0;
    }
  }
  return points;
}

std::pair<std::vector<SweepAxis>, SweepPoint> parse_overrides(
    const std::vector<std::string>& overrides, std::string_view label) {
  std::vector<SweepAxis> axes;
  SweepPoint point;
  for (const auto& o : overrides) {
    SweepAxis axis;
    try {
      axis = parse_sweep_axis(o);
    } catch (const SweepError& e) {
      // parse_sweep_axis speaks of --set; an override given otherwise is named as given.
      std::string message = e.what();
      if (label != "--set" && message.rfind("--set ", 0) == 0)
        message = std::string(label) + message.substr(5);
      throw SweepError(message);
    }
    if (axis.values.size() != 1)
      throw SweepError(fmt::format("{} {}: give one value (cleave sweep takes several)", label, o));
    for (const auto& a : axes)
      if (a.key == axis.key)
        throw SweepError(fmt::format("{} {}: {} is set twice", label, o, axis.key));
    point.push_back(axis.values.front());
    axes.push_back(std::move(axis));
  }
  return {axes, point};
}

namespace {

/// The axis that sets the key an error is at (or a key within it); -1: none.
int blamed_axis(const ScenarioError& e, const std::vector<SweepAxis>& axes) {
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const std::string& key = axes[k].key;
    if (e.key() == key || e.key().rfind(key + ".", 0) == 0) return static_cast<int>(k);
  }
  return -1;
}

}  // namespace

ScenarioError blame_sweep_point(const ScenarioError& e, const std::vector<SweepAxis>& axes,
                                const std::vector<std::string>& shown) {
  if (const int k = blamed_axis(e, axes); k >= 0)
    return ScenarioError::in_override(shown[static_cast<std::size_t>(k)], e.file(), e.key(),
                                      e.message());
  std::string with;
  for (std::size_t k = 0; k < shown.size(); ++k) with += (k ? ", " : "") + shown[k];
  return ScenarioError(e.file(), 0, 0, e.key(), fmt::format("{} (with {})", e.message(), with));
}

Scenario read_sweep_point(const std::string& text, const std::string& source,
                          const std::vector<SweepAxis>& axes, const SweepPoint& point,
                          const std::vector<std::string>& shown,
                          const std::filesystem::path& base_dir, std::string* text_as_run) {
  std::string applied;
  try {
    applied = axes.empty() ? text : apply_sweep_point(text, source, axes, point, base_dir);
  } catch (const SweepError& e) {
    // apply_sweep_point names a key as "--set KEY"; an override is named by its own text,
    // as it was given ("--set KEY=VALUE", "override KEY=VALUE").
    const std::string message = e.what();
    for (std::size_t k = 0; k < axes.size() && k < shown.size(); ++k) {
      const std::string prefix = "--set " + axes[k].key + ":";
      if (message.rfind(prefix, 0) == 0)
        throw SweepError(shown[k] + ":" + message.substr(prefix.size()));
    }
    throw;
  }
  try {
    Scenario s = parse_scenario(applied, source);
    if (text_as_run != nullptr) *text_as_run = std::move(applied);
    return s;
  } catch (const ScenarioError& e) {
    if (axes.empty()) throw;
    if (blamed_axis(e, axes) < 0) {
      // An error of the file itself is reported at its line in the file.
      try {
        (void)parse_scenario(text, source);
      } catch (const ScenarioError& original) {
        if (original.key() == e.key()) throw;
      }
    }
    throw blame_sweep_point(e, axes, shown);
  }
}

std::string apply_sweep_point(const std::string& scenario_text, const std::string& source,
                              const std::vector<SweepAxis>& axes, const SweepPoint& point,
                              const std::filesystem::path& base_dir) {
  toml::table root;
  try {
    root = toml::parse(scenario_text, std::string_view(source));
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw SweepError(fmt::format("{}:{}:{}: {}", source, b.line, b.column, e.description()));
  }
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const auto steps = split_key(axes[k].key);
    toml::table* t = &root;
    for (std::size_t s = 0; s + 1 < steps.size(); ++s) {
      const PathStep& step = steps[s];
      toml::node* node = t->get(step.name);
      if (step.index > 0) {
        toml::array* arr = node ? node->as_array() : nullptr;
        if (arr == nullptr)
          throw SweepError(fmt::format("--set {}: {} has no [[{}]] tables", axes[k].key, source,
                                       step.name));
        if (static_cast<std::size_t>(step.index) > arr->size())
          throw SweepError(fmt::format("--set {}: {} has only {} [[{}]] table(s)", axes[k].key,
                                       source, arr->size(), step.name));
        t = arr->get(static_cast<std::size_t>(step.index - 1))->as_table();
        if (t == nullptr)
          throw SweepError(fmt::format("--set {}: {}[{}] is not a table", axes[k].key, step.name,
                                       step.index));
      } else {
        if (node == nullptr) node = t->insert(step.name, toml::table{}).first->second.as_table();
        if (node == nullptr || !node->is_table())
          throw SweepError(fmt::format("--set {}: '{}' in {} is not a table", axes[k].key,
                                       step.name, source));
        t = node->as_table();
      }
    }
    assign(*t, steps.back().name, point[k]);
  }
  // Mesh files named relative to the original scenario stay found from anywhere.
  if (toml::array* grains = root["mesh_grain"].as_array())
    for (auto& node : *grains)
      if (toml::table* g = node.as_table())
        if (auto file = (*g)["file"].value<std::string>())
          if (std::filesystem::path(*file).is_relative())
            g->insert_or_assign(
                "file", (std::filesystem::absolute(base_dir) / *file).lexically_normal().string());
  // So are material presets given as a path (a plain name is looked up in the library).
  if (toml::table* material = root["material"].as_table())
    if (auto preset = (*material)["preset"].value<std::string>())
      if ((preset->find('/') != std::string::npos || preset->ends_with(".toml")) &&
          std::filesystem::path(*preset).is_relative())
        material->insert_or_assign(
            "preset", (std::filesystem::absolute(base_dir) / *preset).lexically_normal().string());
  std::ostringstream out;
  out << root;
  return out.str() + "\n";
}

double median_rank(std::size_t i, std::size_t n) {
  return (static_cast<double>(i) - 0.3) / (static_cast<double>(n) + 0.4);
}

WeibullFit fit_weibull(std::vector<double> strengths) {
  if (strengths.size() < 3)
    throw SweepError(fmt::format("a Weibull fit needs at least 3 strengths, found {}",
                                 strengths.size()));
  for (double s : strengths)
    if (!(s > 0.0) || !std::isfinite(s))
      throw SweepError(fmt::format("a Weibull fit needs positive strengths, found {}", s));
  std::sort(strengths.begin(), strengths.end());
  if (strengths.front() == strengths.back())
    throw SweepError("a Weibull fit needs strengths that differ; all are equal");
  WeibullFit fit;
  const std::size_t n = strengths.size();
  double sx = 0, sy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = std::log(strengths[i]);
    const double y = std::log(-std::log(1.0 - median_rank(i + 1, n)));
    fit.ln_strength.push_back(x);
    fit.ln_ln.push_back(y);
    sx += x;
    sy += y;
  }
  const double mx = sx / n, my = sy / n;
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = fit.ln_strength[i] - mx, dy = fit.ln_ln[i] - my;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  // y = m x - m ln s0.
  fit.modulus = sxy / sxx;
  fit.scale = std::exp(mx - my / fit.modulus);
  fit.r_squared = syy > 0 ? sxy * sxy / (sxx * syy) : 1.0;
  fit.sorted = std::move(strengths);
  return fit;
}

SizeEffect fit_size_effect(const std::vector<std::pair<double, double>>& size_strength) {
  std::map<double, std::vector<double>> by_size;
  for (const auto& [size, strength] : size_strength) {
    if (!(size > 0.0) || !std::isfinite(size))
      throw SweepError(fmt::format("a size effect needs positive sizes, found {}", size));
    if (!(strength > 0.0) || !std::isfinite(strength))
      throw SweepError(fmt::format("a size effect needs positive strengths, found {}", strength));
    by_size[size].push_back(strength);
  }
  if (by_size.size() < 2)
    throw SweepError(fmt::format("a size effect needs at least 2 sizes, found {}", by_size.size()));
  SizeEffect e;
  std::vector<double> normalised;
  double sx = 0, sy = 0;
  for (const auto& entry : by_size) {
    const std::vector<double>& strengths = entry.second;  // a plain reference: lambdas take it
    SizeGroup g;
    g.size = entry.first;
    g.strengths = strengths;
    for (double s : strengths) g.mean += s;
    g.mean /= static_cast<double>(strengths.size());
    for (double s : strengths) g.stddev += (s - g.mean) * (s - g.mean);
    g.stddev = strengths.size() > 1 ? std::sqrt(g.stddev / static_cast<double>(strengths.size() - 1)) : 0.0;
    const bool spread = std::any_of(strengths.begin(), strengths.end(), [&](double s) { return s != strengths.front(); });
    if (strengths.size() >= 3 && spread) g.weibull = fit_weibull(strengths);
    for (double s : strengths) normalised.push_back(s / g.mean);
    sx += std::log(g.size);
    sy += std::log(g.mean);
    e.groups.push_back(std::move(g));
  }
  // ln mean = ln A - k ln size.
  const double n = static_cast<double>(e.groups.size()), mx = sx / n, my = sy / n;
  double sxx = 0, sxy = 0;
  for (const auto& g : e.groups) {
    sxx += (std::log(g.size) - mx) * (std::log(g.size) - mx);
    sxy += (std::log(g.size) - mx) * (std::log(g.mean) - my);
  }
  e.exponent = -sxy / sxx;
  e.prefactor = std::exp(my + e.exponent * mx);
  if (normalised.size() >= 3 &&
      std::any_of(normalised.begin(), normalised.end(), [&](double s) { return s != normalised.front(); }))
    e.pooled = fit_weibull(normalised);
  return e;
}

}  // namespace cleave::io
