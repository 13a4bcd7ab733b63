#include "io/plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>
#include <string_view>
#include <utility>

#include "io/result_dir.hpp"
#include "io/xml_text.hpp"

// Layout: a white background, the title on top, the data rectangle ("plot-area") with light
// grid lines at the ticks, tick marks and labels outside it on the left and bottom, the axis
// labels beyond them, the series (polylines, then point circles), the annotated markers, and
// the legend last, in the corner of the data rectangle that the data cross least. Margins
// follow the estimated widths of the tick labels (0.6 em per character, a fair guess for
// sans-serif digits), so long labels do not run off the picture.

namespace cleave::io {

namespace {

constexpr double kFontSize = 12.0;
constexpr double kCharWidth = 0.6 * kFontSize;
constexpr double kTickLength = 5.0;
constexpr double kLargestValue = 1e300;     // larger magnitudes are skipped like NaN
constexpr double kTinyMagnitude = 1e-290;   // nice_ticks: ranges this close to 0 are 0
constexpr double kMinRelativeSpan = 1e-10;  // nice_ticks: narrower ranges are widened
constexpr std::size_t kMaxPointsPerSeries = 4000;

// Okabe & Ito (2008), colour-blind-safe; yellow last, as it is faint on white.
constexpr std::array<const char*, 8> kPalette = {"#0072B2", "#D55E00", "#009E73", "#E69F00",
                                                 "#CC79A7", "#56B4E9", "#000000", "#F0E442"};

struct Pt {
  double x, y;
};

struct Box {
  double x0, y0, x1, y1;  // pixels, x0 < x1, y0 < y1
};

bool usable(double v) {
  return std::isfinite(v) && std::abs(v) <= kLargestValue;
}

/// A pixel coordinate for the SVG text: never NaN or inf (the callers only pass finite
/// values; this is the last guard).
double px(double v) {
  return std::isfinite(v) ? v : 0.0;
}


std::string escaped(std::string_view text) {
  std::string out;
  append_xml_escaped(out, text);
  return out;
}

/// Estimated rendered width of `text` in pixels: UTF-8 code points times the character width.
double text_width(std::string_view text, double char_width = kCharWidth) {
  std::size_t n = 0;
  for (char c : text) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return static_cast<double>(n) * char_width;
}

/// 10^n for |n| up to 308, through std::pow (exact up to 10^22).
double pow10(int n) {
  return std::pow(10.0, n);
}

/// Labels for `ticks`: "{:.Pg}" with the smallest precision P >= 6 at which every label reads
/// back within a thousandth of the tick spacing, so adjacent labels stay distinct.
std::vector<std::string> tick_labels(const std::vector<double>& ticks) {
  const double spacing =
      ticks.size() > 1 ? (ticks.back() - ticks.front()) / static_cast<double>(ticks.size() - 1)
                       : 1.0;
  std::vector<std::string> labels(ticks.size());
  for (int precision = 6; precision <= 17; ++precision) {
    bool ok = true;
    for (std::size_t i = 0; i < ticks.size(); ++i) {
      labels[i] = fmt::format("{:.{}g}", ticks[i] + 0.0, precision);  // + 0.0: no "-0"
      double back = 0;
      const auto res = std::from_chars(labels[i].data(), labels[i].data() + labels[i].size(), back);
      if (res.ec != std::errc{} || !(std::abs(back - ticks[i]) <= 1e-3 * spacing)) ok = false;
    }
    if (ok) break;
  }
  return labels;
}

/// Splits the first min(x, y) points of `s` into runs of usable points.
std::vector<std::vector<Pt>> finite_runs(const PlotSeries& s) {
  std::vector<std::vector<Pt>> runs;
  const std::size_t n = std::min(s.x.size(), s.y.size());
  bool open = false;
  for (std::size_t i = 0; i < n; ++i) {
    if (usable(s.x[i]) && usable(s.y[i])) {
      if (!open) runs.emplace_back();
      runs.back().push_back({s.x[i], s.y[i]});
      open = true;
    } else {
      open = false;
    }
  }
  return runs;
}

/// Keeps the first and last points of `run` and, of each `bucket` consecutive points, the
/// ones with the lowest and the highest y, all in their original order.
std::vector<Pt> thin_run(const std::vector<Pt>& run, std::size_t bucket) {
  if (bucket <= 1 || run.size() <= 2) return run;
  std::vector<Pt> out;
  std::size_t last = 0;
  out.push_back(run.front());
  auto keep = [&](std::size_t i) {
    if (i != last) out.push_back(run[i]);
    last = i;
  };
  for (std::size_t b = 0; b < run.size(); b += bucket) {
    const std::size_t e = std::min(b + bucket, run.size());
    std::size_t lo = b, hi = b;
    for (std::size_t i = b + 1; i < e; ++i) {
      if (run[i].y < run[lo].y) lo = i;
      if (run[i].y > run[hi].y) hi = i;
    }
    keep(std::min(lo, hi));
    keep(std::max(lo, hi));
  }
  keep(run.size() - 1);
  return out;
}

/// Liang-Barsky: whether the segment a-b meets the box.
bool segment_meets(const Box& r, Pt a, Pt b) {
  double t0 = 0, t1 = 1;
  auto clip = [&](double p, double q) {
    if (p == 0) return q >= 0;
    const double t = q / p;
    if (p < 0) {
      if (t > t1) return false;
      t0 = std::max(t0, t);
    } else {
      if (t < t0) return false;
      t1 = std::min(t1, t);
    }
    return true;
  };
  const double dx = b.x - a.x, dy = b.y - a.y;
  return clip(-dx, a.x - r.x0) && clip(dx, r.x1 - a.x) && clip(-dy, a.y - r.y0) &&
         clip(dy, r.y1 - a.y);
}

bool inside(const Box& r, Pt p) {
  return p.x >= r.x0 && p.x <= r.x1 && p.y >= r.y0 && p.y <= r.y1;
}

struct DrawnSeries {
  std::vector<std::vector<Pt>> runs;  // pixels, thinned
  std::string colour;                 // escaped
  std::string label;                  // escaped
  double line_width = 1.5;
  bool markers = false, dashed = false;
};

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int target) {
  constexpr double kMax = std::numeric_limits<double>::max();
  target = std::clamp(target, 2, 100);
  if (!std::isfinite(lo) && !std::isfinite(hi)) {
    lo = 0;
    hi = 1;
  } else if (!std::isfinite(lo)) {
    lo = hi;
  } else if (!std::isfinite(hi)) {
    hi = lo;
  }
  if (lo > hi) std::swap(lo, hi);
  const double mag = std::max(std::abs(lo), std::abs(hi));
  if (mag < kTinyMagnitude) {
    lo = std::min(lo, -1.0);
    hi = std::max(hi, 1.0);
  } else if (hi == lo) {
    lo -= 0.1 * mag;
    hi += 0.1 * mag;
  } else if (hi - lo < kMinRelativeSpan * mag) {
    const double centre = lo + 0.5 * (hi - lo);
    lo = centre - 0.5 * kMinRelativeSpan * mag;
    hi = centre + 0.5 * kMinRelativeSpan * mag;
  }
  lo = std::clamp(lo, -kMax, kMax);
  hi = std::clamp(hi, -kMax, kMax);
  const std::vector<double> fallback{lo, hi};
  const double span = hi - lo;
  if (!std::isfinite(span)) return fallback;

  const double raw = span / (target - 1);
  int e = static_cast<int>(std::floor(std::log10(raw)));
  double norm = raw / pow10(e);
  if (norm >= 10) {  // log10 rounded down across a power of ten
    ++e;
    norm /= 10;
  } else if (norm < 1) {
    --e;
    norm *= 10;
  }
  double nice = norm < 1.5 ? 1 : norm < 3 ? 2 : norm < 7 ? 5 : 10;
  if (nice == 10) {
    nice = 1;
    ++e;
  }
  if (e > 308 || e < -308) return fallback;
  // k * nice / 10^-e rather than k * nice * 10^e, so that e.g. 3 * 0.1 gives 0.3 exactly.
  const double scale = pow10(std::abs(e));
  auto tick = [&](long long k) {
    const double m = static_cast<double>(k) * nice;
    return e >= 0 ? m * scale : m / scale;
  };
  const double step = tick(1);
  const double k_lo = std::floor(lo / step), k_hi = std::ceil(hi / step);
  constexpr double kMaxK = 4e15;  // well inside the exact integers of a double
  if (!(std::abs(k_lo) < kMaxK && std::abs(k_hi) < kMaxK)) return fallback;
  auto k0 = static_cast<long long>(k_lo), k1 = static_cast<long long>(k_hi);
  // floor/ceil of a rounded quotient can be one off either way: settle on exact cover.
  while (tick(k0) > lo) --k0;
  while (tick(k0 + 1) <= lo) ++k0;
  while (tick(k1) < hi) ++k1;
  while (tick(k1 - 1) >= hi) --k1;
  if (k1 - k0 > 1000) return fallback;
  std::vector<double> ticks;
  for (long long k = k0; k <= k1; ++k) ticks.push_back(tick(k));
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    if (!std::isfinite(ticks[i]) || (i > 0 && !(ticks[i] > ticks[i - 1]))) return fallback;
  }
  return ticks;
}

std::string render_svg(const Plot& plot) {
  // ---- data: runs of usable points, ranges
  std::vector<std::vector<std::vector<Pt>>> data;
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  double y_min = x_min, y_max = x_max;
  auto extend = [&](Pt p) {
    x_min = std::min(x_min, p.x);
    x_max = std::max(x_max, p.x);
    y_min = std::min(y_min, p.y);
    y_max = std::max(y_max, p.y);
  };
  for (const PlotSeries& s : plot.series) {
    data.push_back(finite_runs(s));
    for (const auto& run : data.back()) {
      for (Pt p : run) extend(p);
    }
  }
  for (const PlotMarker& m : plot.markers) {
    if (usable(m.x) && usable(m.y)) extend({m.x, m.y});
  }
  const bool no_data = !(x_min <= x_max);
  if (no_data) {
    x_min = y_min = 0;
    x_max = y_max = 1;
  }
  // ---- layout: fewer ticks than the default 6 where y ticks would be closer than 2 em or x
  // labels closer than 2 em to each other; the picture grows where even that does not fit.
  const double top = plot.title.empty() ? 16.0 : 40.0;
  const double bottom = kTickLength + 4.0 + kFontSize + (plot.x_label.empty() ? 8.0 : 30.0);
  const int height = std::max(plot.height, static_cast<int>(std::ceil(top + bottom)) + 80);
  std::vector<double> yt;
  for (int target = 6; target >= 2; --target) {
    yt = nice_ticks(y_min, y_max, target);
    const double spacing = (height - top - bottom) / static_cast<double>(yt.size() - 1);
    if (spacing >= 2 * kFontSize) break;
  }
  const std::vector<std::string> yl = tick_labels(yt);
  double y_label_width = 0;
  for (const auto& l : yl) y_label_width = std::max(y_label_width, text_width(l));
  const double y_axis_width =
      (plot.y_label.empty() ? 8.0 : 30.0) + y_label_width + kTickLength + 4.0;
  std::vector<double> xt;
  std::vector<std::string> xl;
  double left = 0, right = 0;
  int width = 0;
  for (int target = 6; target >= 2; --target) {
    xt = nice_ticks(x_min, x_max, target);
    xl = tick_labels(xt);
    double widest = 0;
    for (const auto& l : xl) widest = std::max(widest, text_width(l));
    left = std::max({40.0, y_axis_width, text_width(xl.front()) / 2 + 4.0});
    right = std::max(16.0, text_width(xl.back()) / 2 + 6.0);
    const double needed = static_cast<double>(xt.size() - 1) * (widest + 2 * kFontSize);
    if (plot.width - left - right >= needed || target == 2) {
      width =
          std::max(plot.width, static_cast<int>(std::ceil(left + right + std::max(100.0, needed))));
      break;
    }
  }
  const Box area{left, top, width - right, height - bottom};

  auto map_x = [&](double x) {
    const double f = (x - xt.front()) / (xt.back() - xt.front());
    return std::clamp(px(area.x0 + f * (area.x1 - area.x0)), area.x0, area.x1);
  };
  auto map_y = [&](double y) {
    const double f = (y - yt.front()) / (yt.back() - yt.front());
    return std::clamp(px(area.y1 - f * (area.y1 - area.y0)), area.y0, area.y1);
  };

  // ---- series in pixels, thinned
  std::vector<DrawnSeries> drawn;
  std::size_t next_colour = 0;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& s = plot.series[i];
    DrawnSeries d;
    d.colour = escaped(s.colour.empty() ? kPalette[next_colour++ % kPalette.size()] : s.colour);
    d.label = escaped(s.label.empty() ? fmt::format("series {}", i + 1) : s.label);
    d.line_width = std::isfinite(s.line_width) && s.line_width > 0 ? s.line_width : 1.5;
    d.markers = s.markers;
    d.dashed = s.dashed;
    std::size_t total = 0;
    for (const auto& run : data[i]) total += run.size();
    const std::size_t bucket =
        total > kMaxPointsPerSeries
            ? (total + (kMaxPointsPerSeries / 2 - 3)) / (kMaxPointsPerSeries / 2 - 2)
            : 1;
    for (const auto& run : data[i]) {
      std::vector<Pt> pix = thin_run(run, bucket);
      for (Pt& p : pix) p = {map_x(p.x), map_y(p.y)};
      d.runs.push_back(std::move(pix));
    }
    drawn.push_back(std::move(d));
  }

  std::string out;
  auto it = std::back_inserter(out);
  fmt::format_to(it,
                 "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                 "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" "
                 "viewBox=\"0 0 {0} {1}\" font-family=\"sans-serif\" font-size=\"{2}\">\n"
                 "<rect class=\"background\" x=\"0\" y=\"0\" width=\"{0}\" height=\"{1}\" "
                 "fill=\"white\"/>\n",
                 width, height, kFontSize);
  if (!plot.title.empty()) {
    fmt::format_to(it,
                   "<text class=\"title\" x=\"{:.2f}\" y=\"24\" text-anchor=\"middle\" "
                   "font-size=\"15\" font-weight=\"bold\">{}</text>\n",
                   width / 2.0, escaped(plot.title));
  }

  // ---- grid, frame, ticks, labels
  out += "<g class=\"grid\" stroke=\"#e3e3e3\" stroke-width=\"1\">\n";
  for (double t : xt) {
    const double x = map_x(t);
    fmt::format_to(it, "<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\"/>\n", x,
                   area.y0, area.y1);
  }
  for (double t : yt) {
    const double y = map_y(t);
    fmt::format_to(it, "<line x1=\"{1:.2f}\" y1=\"{0:.2f}\" x2=\"{2:.2f}\" y2=\"{0:.2f}\"/>\n", y,
                   area.x0, area.x1);
  }
  out += "</g>\n";
  fmt::format_to(it,
                 "<rect class=\"plot-area\" x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" "
                 "height=\"{:.2f}\" fill=\"none\" stroke=\"#444\" stroke-width=\"1\"/>\n",
                 area.x0, area.y0, area.x1 - area.x0, area.y1 - area.y0);
  out += "<g class=\"axes\" stroke=\"#444\" stroke-width=\"1\">\n";
  for (double t : xt) {
    fmt::format_to(it,
                   "<line class=\"tick x\" data-value=\"{0:.17g}\" x1=\"{1:.2f}\" y1=\"{2:.2f}\" "
                   "x2=\"{1:.2f}\" y2=\"{3:.2f}\"/>\n",
                   t + 0.0, map_x(t), area.y1, area.y1 + kTickLength);
  }
  for (double t : yt) {
    fmt::format_to(it,
                   "<line class=\"tick y\" data-value=\"{0:.17g}\" x1=\"{2:.2f}\" y1=\"{1:.2f}\" "
                   "x2=\"{3:.2f}\" y2=\"{1:.2f}\"/>\n",
                   t + 0.0, map_y(t), area.x0 - kTickLength, area.x0);
  }
  out += "</g>\n<g class=\"tick-labels\" fill=\"#222\">\n";
  for (std::size_t i = 0; i < xt.size(); ++i) {
    fmt::format_to(it,
                   "<text class=\"tick-label x\" x=\"{:.2f}\" y=\"{:.2f}\" "
                   "text-anchor=\"middle\">{}</text>\n",
                   map_x(xt[i]), area.y1 + kTickLength + 3.0 + kFontSize, escaped(xl[i]));
  }
  for (std::size_t i = 0; i < yt.size(); ++i) {
    fmt::format_to(it,
                   "<text class=\"tick-label y\" x=\"{:.2f}\" y=\"{:.2f}\" "
                   "text-anchor=\"end\">{}</text>\n",
                   area.x0 - kTickLength - 3.0, map_y(yt[i]) + 0.35 * kFontSize, escaped(yl[i]));
  }
  out += "</g>\n";
  if (!plot.x_label.empty()) {
    fmt::format_to(it,
                   "<text class=\"axis-label x\" x=\"{:.2f}\" y=\"{:.2f}\" "
                   "text-anchor=\"middle\" font-size=\"13\">{}</text>\n",
                   (area.x0 + area.x1) / 2, height - 10.0, escaped(plot.x_label));
  }
  if (!plot.y_label.empty()) {
    fmt::format_to(it,
                   "<text class=\"axis-label y\" transform=\"translate(18,{:.2f}) rotate(-90)\" "
                   "text-anchor=\"middle\" font-size=\"13\">{}</text>\n",
                   (area.y0 + area.y1) / 2, escaped(plot.y_label));
  }
  if (no_data) {
    fmt::format_to(it,
                   "<text class=\"no-data\" x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"middle\" "
                   "fill=\"#888\">no data</text>\n",
                   (area.x0 + area.x1) / 2, (area.y0 + area.y1) / 2);
  }

  // ---- series
  std::string buf;
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    const DrawnSeries& d = drawn[i];
    const std::string dash = d.dashed ? " stroke-dasharray=\"6 4\"" : "";
    for (const auto& run : d.runs) {
      if (run.size() == 1) {
        fmt::format_to(it,
                       "<circle class=\"point lone\" data-series=\"{}\" cx=\"{:.2f}\" "
                       "cy=\"{:.2f}\" r=\"2.5\" fill=\"{}\"/>\n",
                       i, run[0].x, run[0].y, d.colour);
        continue;
      }
      // Consecutive points that round to the same pixel pair are written once.
      std::string points, prev;
      std::size_t written = 0;
      for (Pt p : run) {
        buf = fmt::format("{:.2f},{:.2f}", p.x, p.y);
        if (buf == prev) continue;
        if (!points.empty()) points += ' ';
        points += buf;
        prev = buf;
        ++written;
      }
      if (written == 1) points += ' ' + prev;  // a polyline needs two points to show
      fmt::format_to(it,
                     "<polyline class=\"series\" data-series=\"{}\" fill=\"none\" stroke=\"{}\" "
                     "stroke-width=\"{:.2f}\" stroke-linejoin=\"round\"{} points=\"{}\"/>\n",
                     i, d.colour, d.line_width, dash, points);
    }
    if (d.markers) {
      for (const auto& run : d.runs) {
        for (Pt p : run) {
          fmt::format_to(it,
                         "<circle class=\"point\" data-series=\"{}\" cx=\"{:.2f}\" cy=\"{:.2f}\" "
                         "r=\"2.5\" fill=\"{}\"/>\n",
                         i, p.x, p.y, d.colour);
        }
      }
    }
  }

  // ---- annotated markers
  std::vector<Pt> marker_pixels;
  for (const PlotMarker& m : plot.markers) {
    if (!(usable(m.x) && usable(m.y))) continue;
    const Pt p{map_x(m.x), map_y(m.y)};
    marker_pixels.push_back(p);
    const double w = text_width(m.label);
    const bool to_left = p.x + 7 + w > area.x1;
    const double tx = to_left ? p.x - 7 : p.x + 7;
    const double ty = p.y - 7 - kFontSize < area.y0 ? p.y + 7 + kFontSize : p.y - 7;
    // The label's ends and middle count as marker pixels too, so the legend avoids them.
    const double far = to_left ? tx - w : tx + w;
    for (double x : {tx, 0.5 * (tx + far), far}) {
      marker_pixels.push_back({x, ty});
      marker_pixels.push_back({x, ty - kFontSize});
    }
    fmt::format_to(it,
                   "<g class=\"marker\"><circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"4\" "
                   "fill=\"white\" stroke=\"#222\" stroke-width=\"1.5\"/>"
                   "<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"{}\" fill=\"#222\" "
                   "stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\">{}</text></g>\n",
                   p.x, p.y, tx, ty, to_left ? "end" : "start", escaped(m.label));
  }

  // ---- legend, in the corner the data cross least (ties: top right, top left, bottom right,
  // bottom left)
  if (!drawn.empty()) {
    constexpr double kPad = 8, kRow = 18, kSample = 24, kInset = 8;
    double text_w = 0;
    for (const PlotSeries& s : plot.series) {
      text_w = std::max(text_w, text_width(s.label.empty() ? "series 00" : s.label));
    }
    const double lw = kPad + kSample + 6 + text_w + kPad;
    const double lh = kPad + kRow * static_cast<double>(drawn.size()) + kPad - 4;
    const std::array<Box, 4> corners = {
        Box{area.x1 - kInset - lw, area.y0 + kInset, area.x1 - kInset, area.y0 + kInset + lh},
        Box{area.x0 + kInset, area.y0 + kInset, area.x0 + kInset + lw, area.y0 + kInset + lh},
        Box{area.x1 - kInset - lw, area.y1 - kInset - lh, area.x1 - kInset, area.y1 - kInset},
        Box{area.x0 + kInset, area.y1 - kInset - lh, area.x0 + kInset + lw, area.y1 - kInset}};
    std::size_t best = 0, best_score = std::numeric_limits<std::size_t>::max();
    for (std::size_t c = 0; c < corners.size(); ++c) {
      std::size_t score = 0;
      for (const DrawnSeries& d : drawn) {
        for (const auto& run : d.runs) {
          if (run.size() == 1) score += inside(corners[c], run[0]);
          for (std::size_t k = 1; k < run.size(); ++k) {
            score += segment_meets(corners[c], run[k - 1], run[k]);
          }
        }
      }
      for (Pt p : marker_pixels) score += 4 * inside(corners[c], p);
      if (score < best_score) {
        best = c;
        best_score = score;
      }
    }
    const Box& b = corners[best];
    fmt::format_to(it,
                   "<g class=\"legend\">\n<rect class=\"legend-box\" x=\"{:.2f}\" y=\"{:.2f}\" "
                   "width=\"{:.2f}\" height=\"{:.2f}\" fill=\"white\" fill-opacity=\"0.85\" "
                   "stroke=\"#999\" stroke-width=\"1\"/>\n",
                   b.x0, b.y0, lw, lh);
    for (std::size_t i = 0; i < drawn.size(); ++i) {
      const DrawnSeries& d = drawn[i];
      const double y = b.y0 + kPad + kRow * (static_cast<double>(i) + 0.5) - 2;
      fmt::format_to(it,
                     "<g class=\"legend-entry\" data-series=\"{}\"><line x1=\"{:.2f}\" "
                     "y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"{}\" "
                     "stroke-width=\"{:.2f}\"{}/>",
                     i, b.x0 + kPad, y, b.x0 + kPad + kSample, y, d.colour, d.line_width,
                     d.dashed ? " stroke-dasharray=\"6 4\"" : "");
      if (d.markers) {
        fmt::format_to(it, "<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"2.5\" fill=\"{}\"/>",
                       b.x0 + kPad + kSample / 2, y, d.colour);
      }
      fmt::format_to(it, "<text x=\"{:.2f}\" y=\"{:.2f}\" fill=\"#222\">{}</text></g>\n",
                     b.x0 + kPad + kSample + 6, y + 0.35 * kFontSize, d.label);
    }
    out += "</g>\n";
  }
  out += "</svg>\n";
  return out;
}

void write_plot_svg(const std::filesystem::path& path, const Plot& plot) {
  write_file_atomically(path, render_svg(plot));
}

}  // namespace cleave::io
