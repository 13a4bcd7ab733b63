// Fragment size statistics: the mass fraction passing, its Rosin-Rammler fit, the power law
// of the cumulative number, the table, its picture and a sweep's pooled tables.

#include "io/fragment_sizes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "io/result_dir.hpp"

namespace cleave::io {

namespace {

namespace fs = std::filesystem;

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string fit_columns(const FragmentSizes& s) {
  const auto& rr = s.rosin_rammler;
  const auto& pl = s.power_law;
  return fmt::format("{},{},{},{},{}", rr ? fmt::format("{:.9g}", rr->d0) : "",
                     rr ? fmt::format("{:.6g}", rr->n) : "", pl ? fmt::format("{:.6g}", pl->b) : "",
                     pl ? fmt::format("{:.9g}", pl->d_min) : "",
                     pl ? std::to_string(pl->points) : "");
}

}  // namespace

double equivalent_diameter(double volume) {
  return std::cbrt(6.0 * volume / M_PI);
}

std::optional<RosinRammlerFit> fit_rosin_rammler(const std::vector<double>& d,
                                                 const std::vector<double>& weight) {
  if (d.size() != weight.size()) throw std::invalid_argument("fit_rosin_rammler: sizes differ");
  // Diameters over their weighted geometric mean, so that x^n stays representable.
  double sw = 0, swl = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (!(d[i] > 0) || !(weight[i] > 0)) continue;
    sw += weight[i];
    swl += weight[i] * std::log(d[i]);
  }
  if (!(sw > 0)) return std::nullopt;
  const double ref = std::exp(swl / sw);
  std::vector<double> lx, w;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (!(d[i] > 0) || !(weight[i] > 0)) continue;
    lx.push_back(std::log(d[i] / ref));
    w.push_back(weight[i] / sw);
  }
  const auto [lo_it, hi_it] = std::minmax_element(lx.begin(), lx.end());
  if (lx.size() < 2 || *hi_it - *lo_it < 1e-12) return std::nullopt;
  const double lx_max = *hi_it;  // a plain value: clang cannot capture a structured binding
  const double mean_lx = std::inner_product(w.begin(), w.end(), lx.begin(), 0.0);  // 0 by ref
  // The score in n of the profile likelihood; it falls from +inf to mean - max ln x < 0.
  auto score = [&](double n) {
    double top = 0, bottom = 0;
    for (std::size_t i = 0; i < lx.size(); ++i) {
      const double p = w[i] * std::exp(n * (lx[i] - lx_max));  // scaled by x_max^-n
      top += p * lx[i];
      bottom += p;
    }
    return 1.0 / n + mean_lx - top / bottom;
  };
  double a = std::log(1e-3), b = std::log(1e3);
  if (score(std::exp(a)) <= 0 || score(std::exp(b)) >= 0) return std::nullopt;
  for (int it = 0; it < 200 && b - a > 1e-13; ++it) {
    const double m = 0.5 * (a + b);
    (score(std::exp(m)) > 0 ? a : b) = m;
  }
  const double n = std::exp(0.5 * (a + b));
  double mean_xn = 0;  // sum w (x / x_max)^n
  for (std::size_t i = 0; i < lx.size(); ++i) mean_xn += w[i] * std::exp(n * (lx[i] - lx_max));
  return RosinRammlerFit{ref * std::exp(lx_max + std::log(mean_xn) / n), n};
}

std::optional<PowerLawFit> fit_power_law(std::vector<double> d, std::size_t min_points) {
  d.erase(
      std::remove_if(d.begin(), d.end(), [](double v) { return !(v > 0) || !std::isfinite(v); }),
      d.end());
  std::sort(d.begin(), d.end());
  min_points = std::max<std::size_t>(min_points, 2);
  if (d.size() < min_points || d.front() == d.back()) return std::nullopt;
  // Suffix sums of ln d give each tail's likelihood in O(1).
  const std::size_t total = d.size();
  std::vector<double> suffix(total + 1, 0.0);
  for (std::size_t i = total; i-- > 0;) suffix[i] = suffix[i + 1] + std::log(d[i]);
  // Candidates: the first index of each distinct diameter, thinned to about 400 of them.
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i + min_points <= total; ++i)
    if (i == 0 || d[i] != d[i - 1]) starts.push_back(i);
  if (starts.size() > 400) {
    std::vector<std::size_t> thin;
    for (std::size_t k = 0; k < 400; ++k) thin.push_back(starts[k * starts.size() / 400]);
    starts = std::move(thin);
  }
  std::optional<PowerLawFit> best;
  for (std::size_t s : starts) {
    const std::size_t k = total - s;
    const double sum_ln = suffix[s] - static_cast<double>(k) * std::log(d[s]);
    if (!(sum_ln > 0)) continue;
    const double b = static_cast<double>(k) / sum_ln;
    double ks = 0;
    for (std::size_t i = s; i < total; ++i) {
      const double model = 1.0 - std::pow(d[s] / d[i], b);
      const double below = static_cast<double>(i - s) / k,
                   above = static_cast<double>(i - s + 1) / k;
      ks = std::max({ks, std::abs(model - below), std::abs(model - above)});
    }
    // Equal diameters: their steps lie between the first's lower and the last's upper
    // value, which the loop compares too, so ties need no care.
    if (!best || ks < best->ks_distance) best = PowerLawFit{b, d[s], d.back(), k, ks};
  }
  return best;
}

FragmentSizes analyse_fragment_sizes(std::vector<FragmentRecord> fragments) {
  FragmentSizes s;
  std::stable_sort(
      fragments.begin(), fragments.end(),
      [](const FragmentRecord& a, const FragmentRecord& b) { return a.volume < b.volume; });
  s.fragments = std::move(fragments);
  double largest = 0;
  for (const auto& f : s.fragments) {
    s.total_mass += f.mass;
    s.total_volume += f.volume;
    largest = std::max(largest, f.mass);
    s.diameter.push_back(equivalent_diameter(f.volume));
  }
  s.largest_mass_fraction = s.total_mass > 0 ? largest / s.total_mass : 0.0;
  s.passing.resize(s.fragments.size());
  double below = 0;
  for (std::size_t i = 0; i < s.fragments.size();) {
    std::size_t j = i;
    while (j < s.fragments.size() && s.diameter[j] == s.diameter[i]) below += s.fragments[j++].mass;
    for (std::size_t k = i; k < j; ++k)
      s.passing[k] = s.total_mass > 0 ? below / s.total_mass : 0.0;
    i = j;
  }
  std::vector<double> mass;
  for (const auto& f : s.fragments) mass.push_back(f.mass);
  s.rosin_rammler = fit_rosin_rammler(s.diameter, mass);
  s.power_law = fit_power_law(s.diameter);
  return s;
}

std::string fragment_sizes_csv(const FragmentSizes& s) {
  std::string out = "bodies,volume_m3,mass_kg,diameter_m,passing\n";
  for (std::size_t i = 0; i < s.fragments.size(); ++i) {
    const auto& f = s.fragments[i];
    out += fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g}\n", f.bodies, f.volume, f.mass,
                       s.diameter[i], s.passing[i]);
  }
  out += fmt::format(
      "# {} fragments (clusters of bodies joined by intact bonds); largest mass "
      "fraction {:.6g}\n",
      s.fragments.size(), s.largest_mass_fraction);
  if (s.rosin_rammler)
    out += fmt::format(
        "# Rosin-Rammler P(d) = 1 - exp(-(d/d0)^n): d0 = {:.6g} m, n = {:.6g} "
        "(maximum likelihood, each fragment weighted by its mass)\n",
        s.rosin_rammler->d0, s.rosin_rammler->n);
  else
    out += "# Rosin-Rammler: no fit (fewer than two distinct diameters)\n";
  if (s.power_law)
    out += fmt::format(
        "# power law N(>d) ~ d^-b: b = {:.6g} over d >= {:.6g} m ({} fragments, "
        "Kolmogorov-Smirnov distance {:.4g}; Clauset et al. 2009)\n",
        s.power_law->b, s.power_law->d_min, s.power_law->points, s.power_law->ks_distance);
  else
    out += "# power law: no fit (fewer than 10 fragments, or all of one size)\n";
  return out;
}

std::vector<FragmentRecord> read_fragment_sizes_csv(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read");
  std::vector<FragmentRecord> out;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 || line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    FragmentRecord f;
    try {
      if (cells.size() < 3) throw std::invalid_argument("columns");
      f.bodies = std::stoul(cells[0]);
      f.volume = std::stod(cells[1]);
      f.mass = std::stod(cells[2]);
    } catch (const std::exception&) {
      throw std::runtime_error(
          fmt::format("{}:{}: expected bodies,volume_m3,mass_kg,...", path.string(), number));
    }
    out.push_back(f);
  }
  return out;
}

Plot fragment_sizes_plot(const FragmentSizes& s, const std::string& title) {
  Plot p;
  p.title = title;
  p.x_label = "log10(equivalent diameter / mm)";
  p.y_label = "cumulative mass fraction passing";
  PlotSeries pts{"fragments", {}, {}, "", true, false, 1.0};
  for (std::size_t i = 0; i < s.fragments.size(); ++i) {
    pts.x.push_back(std::log10(s.diameter[i] * 1e3));
    pts.y.push_back(s.passing[i]);
  }
  p.series.push_back(pts);
  if (s.rosin_rammler && !s.diameter.empty()) {
    const auto& rr = *s.rosin_rammler;
    const double lo = std::log10(std::min(s.diameter.front(), rr.d0) * 1e3) - 0.2;
    const double hi = std::log10(std::max(s.diameter.back(), rr.d0) * 1e3) + 0.1;
    PlotSeries fit{fmt::format("Rosin-Rammler d0 = {:.3g} mm, n = {:.3g}", rr.d0 * 1e3, rr.n),
                   {},
                   {},
                   "",
                   false,
                   true,
                   1.5};
    for (int k = 0; k <= 100; ++k) {
      const double x = lo + (hi - lo) * k / 100.0;
      fit.x.push_back(x);
      fit.y.push_back(1.0 - std::exp(-std::pow(std::pow(10.0, x) * 1e-3 / rr.d0, rr.n)));
    }
    p.series.push_back(fit);
  }
  return p;
}

void add_fragment_facts(std::map<std::string, std::string>& facts, const FragmentSizes& s) {
  facts["fragments.count"] = std::to_string(s.fragments.size());
  facts["fragments.largest_mass_fraction"] = fmt::format("{:.9g}", s.largest_mass_fraction);
  if (s.rosin_rammler) {
    facts["fragments.rosin_rammler_d0_m"] = fmt::format("{:.9g}", s.rosin_rammler->d0);
    facts["fragments.rosin_rammler_n"] = fmt::format("{:.6g}", s.rosin_rammler->n);
  }
  if (s.power_law) {
    facts["fragments.power_law_exponent"] = fmt::format("{:.6g}", s.power_law->b);
    facts["fragments.power_law_d_min_m"] = fmt::format("{:.9g}", s.power_law->d_min);
    facts["fragments.power_law_points"] = std::to_string(s.power_law->points);
  }
}

std::vector<std::string> write_pooled_fragment_sizes(
    const fs::path& out, const std::vector<std::pair<std::string, std::vector<fs::path>>>& runs) {
  std::string summary =
      "group,runs,fragments,fragments_per_run,largest_mass_fraction_mean,rosin_rammler_d0_m,"
      "rosin_rammler_n,power_law_exponent,power_law_d_min_m,power_law_points\n";
  std::string table = "group,bodies,volume_m3,mass_kg,diameter_m,passing\n";
  Plot plot;
  plot.title = "fragment sizes, runs pooled";
  plot.x_label = "log10(equivalent diameter / mm)";
  plot.y_label = "cumulative mass fraction passing";
  bool any = false;
  for (const auto& [group, dirs] : runs) {
    std::vector<FragmentRecord> pooled;
    std::size_t used = 0;
    double largest = 0;
    for (const auto& dir : dirs) {
      const fs::path file = dir / "fragment_sizes.csv";
      if (!fs::exists(file)) continue;
      auto one = read_fragment_sizes_csv(file);
      if (one.empty()) continue;
      largest += analyse_fragment_sizes(one).largest_mass_fraction;
      ++used;
      pooled.insert(pooled.end(), one.begin(), one.end());
    }
    if (used == 0) continue;
    any = true;
    const FragmentSizes s = analyse_fragment_sizes(std::move(pooled));
    summary +=
        fmt::format("{},{},{},{:.6g},{:.6g},{}\n", csv_field(group), used, s.fragments.size(),
                    static_cast<double>(s.fragments.size()) / used, largest / used, fit_columns(s));
    for (std::size_t i = 0; i < s.fragments.size(); ++i)
      table += fmt::format("{},{},{:.17g},{:.17g},{:.17g},{:.17g}\n", csv_field(group),
                           s.fragments[i].bodies, s.fragments[i].volume, s.fragments[i].mass,
                           s.diameter[i], s.passing[i]);
    PlotSeries curve{group, {}, {}, "", true, false, 1.5};
    for (std::size_t i = 0; i < s.fragments.size(); ++i) {
      curve.x.push_back(std::log10(s.diameter[i] * 1e3));
      curve.y.push_back(s.passing[i]);
    }
    plot.series.push_back(std::move(curve));
  }
  if (!any) return {};
  write_file_atomically(out / "fragments_pooled.csv", summary);
  write_file_atomically(out / "fragment_sizes_pooled.csv", table);
  write_plot_svg(out / "fragments_pooled.svg", plot);
  return {"fragments_pooled.csv", "fragment_sizes_pooled.csv", "fragments_pooled.svg"};
}

}  // namespace cleave::io
