#include "io/sweep.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "io/units.hpp"

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
        throw SweepError(
            fmt::format("--set {}: '{}': expected name[N] with N = 1, 2, ...", key, part));
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

/// The node at a dotted key path, or null (nothing is created).
const toml::node* find_key(const toml::table& root, const std::vector<PathStep>& steps) {
  const toml::node* node = &root;
  for (const PathStep& step : steps) {
    const toml::table* t = node->as_table();
    if (t == nullptr) return nullptr;
    node = t->get(step.name);
    if (node == nullptr) return nullptr;
    if (step.index > 0) {
      const toml::array* arr = node->as_array();
      if (arr == nullptr || static_cast<std::size_t>(step.index) > arr->size()) return nullptr;
      node = arr->get(static_cast<std::size_t>(step.index - 1));
    }
  }
  return node;
}

/// Shortest text that reads back as `v` (fmt's default for a double).
std::string exact(double v) {
  return fmt::format("{}", v);
}

/// The grains' cleavage strength in Pa, a reference no file writes: a stress criterion's
/// sigma_f, or for `lefm` K_Ic / sqrt(pi a), the section stress whose K_I (eq. 3.23 of the
/// dissertation) is K_Ic. Read from [fracture] alone, as the scenario reader reads its values
/// (SI, lengths in the file's length_unit, or a number with its unit), so that the other
/// keys of a point need not be set yet.
double cleavage_strength(const toml::table& root, const std::string& source,
                         const SweepAxis& axis) {
  const toml::table* fracture = root["fracture"].as_table();
  if (fracture == nullptr)
    throw SweepError(fmt::format("--set {}: {} has no [fracture] table, so no cleavage strength",
                                 axis.name(), source));
  const auto value = [&](std::string_view key, Dimension d) {
    const toml::node* n = fracture->get(key);
    const auto fail = [&](const std::string& why) {
      const int line = n != nullptr ? static_cast<int>(n->source().begin.line) : 0;
      return SweepError(fmt::format("--set {}: fracture.{}{}: {}", axis.name(), key,
                                    line > 0 ? fmt::format(" at {}:{}", source, line)
                                             : fmt::format(" in {}", source),
                                    why));
    };
    if (n == nullptr) throw fail("missing, and the cleavage strength needs it");
    if (const auto text = n->value_exact<std::string>()) {
      try {
        return parse_quantity(*text, d);
      } catch (const UnitError& e) {
        throw fail(e.what());
      }
    }
    const auto number = n->value<double>();
    if (!number) throw fail("not a number");
    if (d != Dimension::length) return *number;
    const std::string unit =
        root["scenario"]["length_unit"].value_or(std::string(default_length_unit()));
    try {
      return *number * length_unit_metres(unit);
    } catch (const std::invalid_argument&) {
      throw fail(fmt::format("scenario.length_unit '{}' is not m, mm or um", unit));
    }
  };
  const std::string criterion = (*fracture)["criterion"].value_or(std::string("lefm"));
  double strength = 0.0;
  if (criterion != "lefm") {
    strength = value("sigma_f", Dimension::stress);
  } else {
    strength = value("k_ic", Dimension::toughness) /
               std::sqrt(std::numbers::pi * value("crack_length", Dimension::length));
  }
  if (!(strength > 0) || !std::isfinite(strength))
    throw SweepError(fmt::format("--set {}: the cleavage strength of {} is {} Pa, not positive",
                                 axis.name(), source, strength));
  return strength;
}

/// Axis k's value: its ratio times its reference's value in `root` (a number, or a number
/// with its unit, the unit kept).
std::string ratio_value(const toml::table& root, const std::string& source,
                        const std::vector<SweepAxis>& axes, std::size_t k,
                        const std::string& ratio_text) {
  const SweepAxis& axis = axes[k];
  double ratio = 0.0;
  if (!parse_double(ratio_text, ratio))
    throw SweepError(
        fmt::format("--set {}: a ratio is a number, found '{}'", axis.name(), ratio_text));
  if (axis.reference == kCleavageStrength)
    return exact(ratio * cleavage_strength(root, source, axis)) + " Pa";
  const toml::node* ref = find_key(root, split_key(axis.reference));
  if (ref == nullptr)
    throw SweepError(fmt::format(
        "--set {}: {} is not in {}: a ratio's reference must be written in the scenario (or "
        "set by another --set); its default is not read",
        axis.name(), axis.reference, source));
  // Where the reference's value came from, for an error about it.
  std::string where;
  for (const auto& other : axes)
    if (other.key == axis.reference && other.reference.empty()) where = " (as --set gives it)";
  if (where.empty() && ref->source().begin.line > 0)
    where = fmt::format(" at {}:{}", source, ref->source().begin.line);
  if (where.empty()) where = fmt::format(" in {}", source);
  if (const auto i = ref->value_exact<std::int64_t>()) {
    const double v = ratio * static_cast<double>(*i);
    if (std::trunc(v) == v && std::abs(v) < 9e15)
      return std::to_string(static_cast<std::int64_t>(v));
    return exact(v);
  }
  if (const auto d = ref->value_exact<double>()) return exact(ratio * *d);
  if (const auto text = ref->value_exact<std::string>()) {
    // "250 MPa": the number, then its unit.
    const std::string t = trim(*text);
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(t, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used > 0 && std::isfinite(v) && used < t.size() && (t[used] == ' ' || t[used] == '\t'))
      return exact(ratio * v) + " " + trim(t.substr(used));
    throw SweepError(
        fmt::format("--set {}: {}{} is \"{}\", not a number (nor a number with "
                    "its unit)",
                    axis.name(), axis.reference, where, *text));
  }
  throw SweepError(
      fmt::format("--set {}: {}{} is not a number", axis.name(), axis.reference, where));
}

}  // namespace

SweepAxis parse_sweep_axis(const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
    throw SweepError(
        fmt::format("--set '{}': expected KEY=VALUES, e.g. orientation.seed=1..20 "
                    "or bond.tbn=500,1000,2000",
                    spec));
  SweepAxis axis;
  axis.key = trim(spec.substr(0, eq));
  if (const auto slash = axis.key.find('/'); slash != std::string::npos) {
    axis.reference = trim(axis.key.substr(slash + 1));
    axis.key = trim(axis.key.substr(0, slash));
    if (axis.reference.empty() || axis.key.empty() || axis.reference.find('/') != std::string::npos)
      throw SweepError(
          fmt::format("--set '{}': a ratio is KEY/REFERENCE=RATIOS, e.g. "
                      "bond.tbn/fracture.sigma_f=0.1,1,10",
                      spec));
    split_key(axis.reference);
  }
  split_key(axis.key);  // validates the shape of the key
  const std::string values = trim(spec.substr(eq + 1));
  const auto dots = values.find("..");
  if (dots != std::string::npos) {
    long long lo = 0, hi = 0;
    if (!parse_int(trim(values.substr(0, dots)), lo) ||
        !parse_int(trim(values.substr(dots + 2)), hi))
      throw SweepError(fmt::format("--set '{}': a range is two integers, LO..HI", spec));
    if (hi < lo)
      throw SweepError(fmt::format("--set '{}': the range is empty ({} > {})", spec, lo, hi));
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
  if (!axis.reference.empty())
    for (const auto& v : axis.values) {
      double d = 0.0;
      if (!parse_double(v, d))
        throw SweepError(fmt::format("--set '{}': a ratio is a number, found '{}'", spec, v));
    }
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

std::string check_sweep_point(const std::string& text, const std::string& source,
                              const std::vector<SweepAxis>& axes, const SweepPoint& point,
                              const std::vector<std::string>& shown,
                              const std::filesystem::path& base_dir, const ScenarioReader& read,
                              std::vector<std::string>* absolute) {
  std::string applied;
  try {
    applied =
        axes.empty() ? text : apply_sweep_point(text, source, axes, point, base_dir, absolute);
  } catch (const SweepError& e) {
    // apply_sweep_point names a key as "--set KEY"; an override is named by its own text,
    // as it was given ("--set KEY=VALUE", "override KEY=VALUE").
    const std::string message = e.what();
    for (std::size_t k = 0; k < axes.size() && k < shown.size(); ++k) {
      const std::string prefix = "--set " + axes[k].name() + ":";
      if (message.rfind(prefix, 0) == 0)
        throw SweepError(shown[k] + ":" + message.substr(prefix.size()));
    }
    throw;
  }
  try {
    read(applied, source);
    return applied;
  } catch (const ScenarioError& e) {
    if (axes.empty()) throw;
    if (blamed_axis(e, axes) < 0) {
      // An error of the file itself is reported at its line in the file.
      try {
        read(text, source);
      } catch (const ScenarioError& original) {
        if (original.key() == e.key()) throw;
      }
    }
    throw blame_sweep_point(e, axes, shown);
  }
}

Scenario read_sweep_point(const std::string& text, const std::string& source,
                          const std::vector<SweepAxis>& axes, const SweepPoint& point,
                          const std::vector<std::string>& shown,
                          const std::filesystem::path& base_dir, std::string* text_as_run) {
  Scenario s;
  std::string applied = check_sweep_point(
      text, source, axes, point, shown, base_dir,
      [&](const std::string& t, const std::string& src) { s = parse_scenario(t, src); });
  if (text_as_run != nullptr) *text_as_run = std::move(applied);
  return s;
}

std::string apply_sweep_point(const std::string& scenario_text, const std::string& source,
                              const std::vector<SweepAxis>& axes, const SweepPoint& point,
                              const std::filesystem::path& base_dir,
                              std::vector<std::string>* absolute) {
  toml::table root;
  try {
    root = toml::parse(scenario_text, std::string_view(source));
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw SweepError(fmt::format("{}:{}:{}: {}", source, b.line, b.column, e.description()));
  }
  // The table that holds a key (created when missing), and the key's last name.
  const auto holder = [&](const std::size_t k) -> std::pair<toml::table*, std::string> {
    const auto steps = split_key(axes[k].key);
    toml::table* t = &root;
    for (std::size_t s = 0; s + 1 < steps.size(); ++s) {
      const PathStep& step = steps[s];
      toml::node* node = t->get(step.name);
      if (step.index > 0) {
        toml::array* arr = node ? node->as_array() : nullptr;
        if (arr == nullptr)
          throw SweepError(
              fmt::format("--set {}: {} has no [[{}]] tables", axes[k].name(), source, step.name));
        if (static_cast<std::size_t>(step.index) > arr->size())
          throw SweepError(fmt::format("--set {}: {} has only {} [[{}]] table(s)", axes[k].name(),
                                       source, arr->size(), step.name));
        t = arr->get(static_cast<std::size_t>(step.index - 1))->as_table();
        if (t == nullptr)
          throw SweepError(fmt::format("--set {}: {}[{}] is not a table", axes[k].name(), step.name,
                                       step.index));
      } else {
        if (node == nullptr) node = t->insert(step.name, toml::table{}).first->second.as_table();
        if (node == nullptr || !node->is_table())
          throw SweepError(fmt::format("--set {}: '{}' in {} is not a table", axes[k].name(),
                                       step.name, source));
        t = node->as_table();
      }
    }
    return {t, steps.back().name};
  };
  if (absolute != nullptr) *absolute = point;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    if (!axes[k].reference.empty()) continue;
    const auto [t, name] = holder(k);
    assign(*t, name, point[k]);
  }
  // Ratios after the plain values, so that a swept reference is the value each run has.
  for (std::size_t k = 0; k < axes.size(); ++k) {
    if (axes[k].reference.empty()) continue;
    const std::string value = ratio_value(root, source, axes, k, point[k]);
    const auto [t, name] = holder(k);
    assign(*t, name, value);
    if (absolute != nullptr) (*absolute)[k] = value;
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
    throw SweepError(
        fmt::format("a Weibull fit needs at least 3 strengths, found {}", strengths.size()));
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
    g.stddev = strengths.size() > 1
                   ? std::sqrt(g.stddev / static_cast<double>(strengths.size() - 1))
                   : 0.0;
    const bool spread = std::any_of(strengths.begin(), strengths.end(),
                                    [&](double s) { return s != strengths.front(); });
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
  if (normalised.size() >= 3 && std::any_of(normalised.begin(), normalised.end(),
                                            [&](double s) { return s != normalised.front(); }))
    e.pooled = fit_weibull(normalised);
  return e;
}

SampleStats sample_stats(const std::vector<double>& values) {
  SampleStats st;
  double sum = 0.0;
  for (double v : values)
    if (std::isfinite(v)) {
      sum += v;
      ++st.count;
    }
  if (st.count == 0) return {0, NAN, NAN};
  st.mean = sum / static_cast<double>(st.count);
  double squares = 0.0;
  for (double v : values)
    if (std::isfinite(v)) squares += (v - st.mean) * (v - st.mean);
  st.stddev = st.count > 1 ? std::sqrt(squares / static_cast<double>(st.count - 1)) : NAN;
  return st;
}

namespace {

std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

double cell_number(const std::string& s) {
  double v = 0.0;
  return parse_double(trim(s), v) ? v : NAN;
}

}  // namespace

std::string replicate_means_csv(const std::vector<std::string>& header,
                                const std::vector<std::vector<std::string>>& rows,
                                const std::vector<std::size_t>& group_columns,
                                const std::vector<std::size_t>& value_columns,
                                const std::vector<bool>& counted) {
  const auto cell = [](const std::vector<std::string>& row, std::size_t c) {
    return c < row.size() ? row[c] : std::string();
  };
  std::vector<std::vector<std::string>> keys;
  std::vector<std::vector<std::size_t>> members;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    std::vector<std::string> key;
    for (std::size_t c : group_columns) key.push_back(cell(rows[r], c));
    const auto it = std::find(keys.begin(), keys.end(), key);
    if (it == keys.end()) {
      keys.push_back(key);
      members.push_back({r});
    } else {
      members[static_cast<std::size_t>(it - keys.begin())].push_back(r);
    }
  }
  std::string csv;
  for (std::size_t c : group_columns) csv += csv_cell(cell(header, c)) + ",";
  csv += "runs,counted";
  for (std::size_t c : value_columns) {
    const std::string n = cell(header, c);
    csv += fmt::format(",{},{},{}", csv_cell(n + "_mean"), csv_cell(n + "_sd"), csv_cell(n + "_n"));
  }
  csv += "\n";
  const auto num = [](double v) {
    return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string();
  };
  for (std::size_t g = 0; g < keys.size(); ++g) {
    for (const auto& k : keys[g]) csv += csv_cell(k) + ",";
    std::size_t used = 0;
    for (std::size_t r : members[g]) used += r < counted.size() && counted[r] ? 1 : 0;
    csv += fmt::format("{},{}", members[g].size(), used);
    for (std::size_t c : value_columns) {
      std::vector<double> v;
      for (std::size_t r : members[g])
        if (r < counted.size() && counted[r]) v.push_back(cell_number(cell(rows[r], c)));
      const SampleStats st = sample_stats(v);
      csv += fmt::format(",{},{},{}", num(st.mean), num(st.stddev), st.count);
    }
    csv += "\n";
  }
  return csv;
}

std::map<std::string, std::string> read_flat_toml(const std::filesystem::path& file) {
  std::map<std::string, std::string> values;
  try {
    const toml::table t = toml::parse_file(file.string());
    for (const auto& [k, node] : t) {
      if (const auto d = node.value_exact<double>())
        values[std::string(k.str())] = fmt::format("{:.9g}", *d);
      else if (const auto i = node.value_exact<std::int64_t>())
        values[std::string(k.str())] = std::to_string(*i);
      else if (const auto s = node.value_exact<std::string>())
        values[std::string(k.str())] = *s;
      else if (const auto b = node.value_exact<bool>())
        values[std::string(k.str())] = *b ? "true" : "false";
    }
  } catch (const std::exception&) {
    values.clear();
  }
  return values;
}

}  // namespace cleave::io
