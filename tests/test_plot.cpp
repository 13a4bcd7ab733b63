// Tests io/plot: nice_ticks by its properties over many random ranges, and render_svg by
// reading the SVG back with a small XML tag reader written here (it also checks that every
// element opened is closed and that text and attributes hold no raw '<' or stray '&'). Pixel
// positions are predicted from the tick marks the SVG itself reports, never from the
// renderer's layout constants.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "io/plot.hpp"
#include "io/result_dir.hpp"

namespace {

namespace fs = std::filesystem;
using cleave::io::nice_ticks;
using cleave::io::Plot;
using cleave::io::PlotMarker;
using cleave::io::PlotSeries;
using cleave::io::render_svg;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------- a minimal XML reader

struct Element {
  std::string name;
  std::map<std::string, std::string> attrs;  // values unescaped
  std::string text;                          // direct character data, unescaped
};

struct Doc {
  bool ok = true;
  std::string error;
  std::vector<Element> elements;  // in document order
};

/// Decodes the five predefined entities and numeric references; returns false for a '&'
/// that starts none of them.
bool unescape(std::string_view in, std::string& out) {
  out.clear();
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i] != '&') {
      out += in[i];
      continue;
    }
    const std::size_t semi = in.find(';', i);
    if (semi == std::string_view::npos) return false;
    const std::string_view ent = in.substr(i + 1, semi - i - 1);
    if (ent == "amp") {
      out += '&';
    } else if (ent == "lt") {
      out += '<';
    } else if (ent == "gt") {
      out += '>';
    } else if (ent == "quot") {
      out += '"';
    } else if (ent == "apos") {
      out += '\'';
    } else if (ent.size() > 1 && ent[0] == '#' &&
               std::all_of(ent.begin() + 1, ent.end(), [](char c) { return std::isdigit(c); })) {
      out += '?';
    } else {
      return false;
    }
    i = semi;
  }
  return true;
}

/// Reads `svg` as a sequence of tags: one optional <?xml ...?> head, then elements that must
/// nest properly, with exactly one root element. Sets ok = false with a reason otherwise.
Doc parse_xml(const std::string& svg) {
  Doc doc;
  auto fail = [&](const std::string& why, std::size_t at) {
    if (doc.ok) doc.error = why + " at offset " + std::to_string(at);
    doc.ok = false;
  };
  std::vector<std::size_t> open;  // indices into elements
  std::size_t roots = 0;
  std::size_t i = 0;
  if (svg.compare(0, 5, "<?xml") == 0) {
    i = svg.find("?>");
    if (i == std::string::npos) {
      fail("unterminated XML declaration", 0);
      return doc;
    }
    i += 2;
  }
  std::string decoded;
  while (i < svg.size() && doc.ok) {
    if (svg[i] != '<') {
      const std::size_t next = std::min(svg.find('<', i), svg.size());
      const std::string_view text(svg.data() + i, next - i);
      if (text.find('>') != std::string_view::npos) fail("raw '>' in text", i);
      if (!unescape(text, decoded)) fail("bad entity in text", i);
      if (open.empty()) {
        if (text.find_first_not_of(" \t\r\n") != std::string_view::npos) {
          fail("text outside the root element", i);
        }
      } else {
        doc.elements[open.back()].text += decoded;
      }
      i = next;
      continue;
    }
    const bool closing = i + 1 < svg.size() && svg[i + 1] == '/';
    std::size_t j = i + (closing ? 2 : 1);
    const std::size_t name_start = j;
    while (j < svg.size() && (std::isalnum(static_cast<unsigned char>(svg[j])) || svg[j] == '-' ||
                              svg[j] == '_' || svg[j] == ':')) {
      ++j;
    }
    const std::string name = svg.substr(name_start, j - name_start);
    if (name.empty()) {
      fail("tag without a name", i);
      break;
    }
    Element e;
    e.name = name;
    bool self_closing = false;
    for (;;) {
      while (j < svg.size() && std::isspace(static_cast<unsigned char>(svg[j]))) ++j;
      if (j >= svg.size()) {
        fail("unterminated tag", i);
        break;
      }
      if (svg[j] == '>') {
        ++j;
        break;
      }
      if (svg[j] == '/' && j + 1 < svg.size() && svg[j + 1] == '>') {
        if (closing) fail("'/>' in a closing tag", j);
        self_closing = true;
        j += 2;
        break;
      }
      if (closing) {
        fail("attribute in a closing tag", j);
        break;
      }
      const std::size_t a0 = j;
      while (j < svg.size() && svg[j] != '=' && svg[j] != '>' &&
             !std::isspace(static_cast<unsigned char>(svg[j]))) {
        ++j;
      }
      const std::string attr = svg.substr(a0, j - a0);
      if (attr.empty() || j + 1 >= svg.size() || svg[j] != '=' || svg[j + 1] != '"') {
        fail("malformed attribute", a0);
        break;
      }
      const std::size_t v0 = j + 2;
      const std::size_t v1 = svg.find('"', v0);
      if (v1 == std::string::npos) {
        fail("unterminated attribute value", v0);
        break;
      }
      const std::string_view value(svg.data() + v0, v1 - v0);
      if (value.find('<') != std::string_view::npos) fail("raw '<' in an attribute", v0);
      if (!unescape(value, decoded)) fail("bad entity in an attribute", v0);
      if (e.attrs.count(attr)) fail("duplicate attribute " + attr, a0);
      e.attrs[attr] = decoded;
      j = v1 + 1;
    }
    if (!doc.ok) break;
    if (closing) {
      if (open.empty() || doc.elements[open.back()].name != name) {
        fail("</" + name + "> does not close the open element", i);
        break;
      }
      open.pop_back();
    } else {
      if (open.empty()) ++roots;
      doc.elements.push_back(e);
      if (!self_closing) open.push_back(doc.elements.size() - 1);
    }
    i = j;
  }
  if (doc.ok && !open.empty()) fail("<" + doc.elements[open.back()].name + "> never closed", i);
  if (doc.ok && roots != 1) fail("not exactly one root element", 0);
  if (doc.ok && (doc.elements.empty() || doc.elements[0].name != "svg")) {
    fail("the root is not <svg>", 0);
  }
  return doc;
}

bool has_class(const Element& e, const std::string& cls) {
  const auto it = e.attrs.find("class");
  if (it == e.attrs.end()) return false;
  std::size_t p = 0;
  const std::string& c = it->second;
  while (p < c.size()) {
    const std::size_t q = std::min(c.find(' ', p), c.size());
    if (c.compare(p, q - p, cls) == 0 && q - p == cls.size()) return true;
    p = q + 1;
  }
  return false;
}

std::vector<Element> find_all(const Doc& doc, const std::string& name, const std::string& cls) {
  std::vector<Element> out;
  for (const Element& e : doc.elements) {
    if (e.name == name && (cls.empty() || has_class(e, cls))) out.push_back(e);
  }
  return out;
}

double number(const std::string& s) {
  double v = kNaN;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  if (res.ec != std::errc{} || res.ptr != s.data() + s.size()) {
    ADD_FAILURE() << "not a number: '" << s << "'";
    return kNaN;
  }
  return v;
}

double attr_number(const Element& e, const std::string& attr) {
  const auto it = e.attrs.find(attr);
  if (it == e.attrs.end()) {
    ADD_FAILURE() << "<" << e.name << "> has no " << attr;
    return kNaN;
  }
  return number(it->second);
}

struct XY {
  double x, y;
};

std::vector<XY> points_of(const Element& polyline) {
  std::vector<XY> out;
  const std::string& s = polyline.attrs.at("points");
  std::size_t p = 0;
  while (p < s.size()) {
    std::size_t q = std::min(s.find(' ', p), s.size());
    const std::string pair = s.substr(p, q - p);
    const std::size_t comma = pair.find(',');
    if (comma == std::string::npos) {
      ADD_FAILURE() << "bad point '" << pair << "'";
      return out;
    }
    out.push_back({number(pair.substr(0, comma)), number(pair.substr(comma + 1))});
    p = q + 1;
  }
  return out;
}

struct Rect {
  double x0, y0, x1, y1;
};

Rect plot_area(const Doc& doc) {
  const auto rects = find_all(doc, "rect", "plot-area");
  if (rects.size() != 1) {
    ADD_FAILURE() << rects.size() << " plot-area rects";
    return {kNaN, kNaN, kNaN, kNaN};
  }
  const Element& r = rects[0];
  const double x = attr_number(r, "x"), y = attr_number(r, "y");
  return {x, y, x + attr_number(r, "width"), y + attr_number(r, "height")};
}

/// The axis as the SVG reports it: (value, pixel) of each tick mark.
struct Axis {
  std::vector<double> values, pixels;
  /// Pixel of `v` by linear interpolation between the first and the last tick.
  double predict(double v) const {
    return pixels.front() + (v - values.front()) / (values.back() - values.front()) *
                                (pixels.back() - pixels.front());
  }
};

Axis axis(const Doc& doc, char which) {
  Axis a;
  for (const Element& e : find_all(doc, "line", std::string(1, which))) {
    if (!has_class(e, "tick")) continue;
    a.values.push_back(attr_number(e, "data-value"));
    a.pixels.push_back(attr_number(e, which == 'x' ? "x1" : "y1"));
    EXPECT_EQ(e.attrs.at(which == 'x' ? "x1" : "y1"), e.attrs.at(which == 'x' ? "x2" : "y2"));
  }
  EXPECT_GE(a.values.size(), 2u) << which << " ticks";
  return a;
}

Doc parse_ok(const std::string& svg) {
  Doc doc = parse_xml(svg);
  EXPECT_TRUE(doc.ok) << doc.error;
  return doc;
}

/// No "nan"/"inf" word anywhere (as fmt would print a non-finite double), and every numeric
/// attribute and point finite.
void expect_finite(const std::string& svg, const std::string& what) {
  static const std::regex bad("(^|[^a-z])(nan|inf)([^a-z]|$)", std::regex::icase);
  EXPECT_FALSE(std::regex_search(svg, bad)) << what << ":\n" << svg;
  const Doc doc = parse_ok(svg);
  for (const Element& e : doc.elements) {
    for (const char* a : {"x", "y", "x1", "y1", "x2", "y2", "cx", "cy", "r", "width", "height"}) {
      if (e.attrs.count(a)) {
        EXPECT_TRUE(std::isfinite(attr_number(e, a))) << what << " " << a;
      }
    }
    if (e.attrs.count("points")) {
      for (XY p : points_of(e)) {
        EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y)) << what;
      }
    }
  }
}

PlotSeries series(std::string label, std::vector<double> x, std::vector<double> y) {
  PlotSeries s;
  s.label = std::move(label);
  s.x = std::move(x);
  s.y = std::move(y);
  return s;
}

Plot two_series_plot() {
  Plot p;
  p.title = "platen test";
  p.x_label = "platen displacement (mm)";
  p.y_label = "load (N)";
  std::vector<double> x, y1, y2;
  for (int i = 0; i <= 60; ++i) {
    x.push_back(0.05 * i);
    y1.push_back(4.0 * x.back() - 0.9 * x.back() * x.back());
    y2.push_back(2.0 + std::sin(x.back()));
  }
  p.series.push_back(series("top platen", x, y1));
  p.series.push_back(series("bottom platen", x, y2));
  p.series[1].dashed = true;
  p.series[1].markers = true;
  p.markers.push_back({1.0, 3.1, "peak 3.1 N"});
  return p;
}

// ---------------------------------------------------------------- nice_ticks

/// Checks the nice_ticks contract for [lo, hi] (lo <= hi) and returns the step.
double check_ticks(const std::vector<double>& t, double lo, double hi, int target,
                   bool check_count) {
  SCOPED_TRACE(testing::Message() << "lo=" << lo << " hi=" << hi << " target=" << target);
  EXPECT_GE(t.size(), 2u);
  if (t.size() < 2) return kNaN;
  for (double v : t) EXPECT_TRUE(std::isfinite(v));
  for (std::size_t i = 1; i < t.size(); ++i) EXPECT_LT(t[i - 1], t[i]) << "ascending";
  EXPECT_LE(t.front(), lo) << "covers the low end";
  EXPECT_GE(t.back(), hi) << "covers the high end";
  const double step = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  // The step is 1, 2 or 5 times a power of ten.
  const double mantissa = step / std::pow(10.0, std::floor(std::log10(step)));
  const bool one_two_five = std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 2e-6 ||
                            std::abs(mantissa - 5) < 5e-6 || std::abs(mantissa - 10) < 1e-5;
  EXPECT_TRUE(one_two_five) << "step " << step << " mantissa " << mantissa;
  const double mag = std::max(std::abs(t.front()), std::abs(t.back()));
  const double tol = 1e-6 * step + 8 * mag * std::numeric_limits<double>::epsilon();
  for (std::size_t i = 1; i < t.size(); ++i) EXPECT_NEAR(t[i] - t[i - 1], step, tol);
  // Ticks sit on multiples of the exact nice step (so 0 is a tick whenever it is in range).
  const int e = static_cast<int>(std::floor(std::log10(step)));
  const double m = std::round(mantissa);
  const double nice_step = e >= 0 ? m * std::pow(10.0, e) : m / std::pow(10.0, -e);
  for (double v : t) EXPECT_NEAR(v, std::round(v / nice_step) * nice_step, tol) << v;
  if (check_count) {
    // No spare tick at either end (degenerate ranges are padded, so only here).
    EXPECT_GT(t[1], lo - tol);
    EXPECT_LT(t[t.size() - 2], hi + tol);
    EXPECT_GE(t.size(), target >= 4 ? 3u : 2u);
    EXPECT_LE(t.size(), static_cast<std::size_t>(2 * target + 3));
  }
  return step;
}

TEST(NiceTicks, RandomRangesGiveOneTwoFiveStepsCoveringTheRange) {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> exponent(-12, 12), targets(2, 12);
  for (int n = 0; n < 20000; ++n) {
    const int target = n % 3 == 0 ? 6 : targets(rng);
    double lo = 0, hi = 0;
    switch (n % 5) {
      case 0:  // width 1e-9 somewhere in [-1, 1]
        lo = 2 * unit(rng) - 1;
        hi = lo + 1e-9;
        break;
      case 1: {  // entirely negative
        const double s = std::pow(10.0, exponent(rng));
        hi = -s * unit(rng);
        lo = hi - s * (0.01 + unit(rng));
        break;
      }
      case 2: {  // across zero
        const double s = std::pow(10.0, exponent(rng));
        lo = -s * unit(rng);
        hi = s * unit(rng) + 1e-3 * s;
        break;
      }
      default: {  // offset from zero by up to 10^4 widths, either sign
        const double w = std::pow(10.0, exponent(rng)) * (0.001 + unit(rng));
        lo = (2 * unit(rng) - 1) * w * std::pow(10.0, 4 * unit(rng));
        hi = lo + w;
        break;
      }
    }
    ASSERT_LT(lo, hi);
    check_ticks(nice_ticks(lo, hi, target), lo, hi, target, true);
    if (HasFailure()) break;  // one range's report is enough
  }
}

TEST(NiceTicks, CleanRangesEndOnTheirBoundsAndIncludeZero) {
  const auto a = nice_ticks(0, 1);
  EXPECT_EQ(a.front(), 0.0);
  EXPECT_EQ(a.back(), 1.0);
  const auto b = nice_ticks(-50, 50);
  check_ticks(b, -50, 50, 6, true);
  EXPECT_NE(std::find(b.begin(), b.end(), 0.0), b.end());
  // 0..1 in about 6 ticks: the step must be 0.2 (0.1 gives 11 ticks, 0.5 gives 3).
  check_ticks(a, 0, 1, 6, true);
  EXPECT_EQ(a.size(), 6u);
}

TEST(NiceTicks, ReversedAndDegenerateArgumentsStillGiveValidTicks) {
  check_ticks(nice_ticks(7.5, -2.5), -2.5, 7.5, 6, true);
  EXPECT_EQ(nice_ticks(7.5, -2.5), nice_ticks(-2.5, 7.5));
  struct Case {
    double lo, hi, cover_lo, cover_hi;
  };
  const double big = std::numeric_limits<double>::max();
  for (const Case& c :
       {Case{5, 5, 5, 5}, Case{0, 0, 0, 0}, Case{-3e-7, -3e-7, -3e-7, -3e-7}, Case{kNaN, 2, 2, 2},
        Case{-4, kInf, -4, -4}, Case{kNaN, kNaN, 0, 1}, Case{-kInf, kInf, 0, 1},
        Case{1, 1 + 1e-15, 1, 1 + 1e-15}, Case{1e6, 1e6 + 1e-9, 1e6, 1e6 + 1e-9},
        Case{1e-320, 1e-320, 1e-320, 1e-320}, Case{-1e300, 1e300, -1e300, 1e300},
        Case{1e300, 1e300, 1e300, 1e300}}) {
    SCOPED_TRACE(testing::Message() << c.lo << " .. " << c.hi);
    check_ticks(nice_ticks(c.lo, c.hi), c.cover_lo, c.cover_hi, 6, false);
  }
  // At the very end of the doubles nice steps overflow; the result must still be finite,
  // ascending and covering.
  for (auto [lo, hi] : {std::pair{-big, big}, std::pair{big, big}, std::pair{0.0, big}}) {
    const auto t = nice_ticks(lo, hi);
    ASSERT_GE(t.size(), 2u);
    for (double v : t) EXPECT_TRUE(std::isfinite(v));
    for (std::size_t i = 1; i < t.size(); ++i) EXPECT_LT(t[i - 1], t[i]);
    EXPECT_LE(t.front(), std::min(lo, hi));
    EXPECT_GE(t.back(), std::max(lo, hi));
  }
}

// ---------------------------------------------------------------- render_svg

TEST(XmlReader, RejectsBrokenDocuments) {
  EXPECT_TRUE(parse_xml("<svg><g><line/></g><text>a &amp; b</text></svg>").ok);
  EXPECT_FALSE(parse_xml("<svg><g></svg>").ok);
  EXPECT_FALSE(parse_xml("<svg><g>").ok);
  EXPECT_FALSE(parse_xml("<svg></g></svg>").ok);
  EXPECT_FALSE(parse_xml("<svg><text>a<b</text></svg>").ok);
  EXPECT_FALSE(parse_xml("<svg><text>a & b</text></svg>").ok);
  EXPECT_FALSE(parse_xml("<svg><text x=\"<\">a</text></svg>").ok);
  EXPECT_FALSE(parse_xml("<svg/><svg/>").ok);
}

TEST(RenderSvg, TwoSeriesGiveTwoPolylinesAndTwoLegendEntries) {
  const Plot p = two_series_plot();
  const std::string svg = render_svg(p);
  const Doc doc = parse_ok(svg);
  const auto lines = find_all(doc, "polyline", "series");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].attrs.at("data-series"), "0");
  EXPECT_EQ(lines[1].attrs.at("data-series"), "1");
  EXPECT_EQ(points_of(lines[0]).size(), p.series[0].x.size());
  EXPECT_NE(lines[0].attrs.at("stroke"), lines[1].attrs.at("stroke")) << "palette colours";
  EXPECT_EQ(lines[1].attrs.count("stroke-dasharray"), 1u);
  EXPECT_EQ(lines[0].attrs.count("stroke-dasharray"), 0u);
  EXPECT_EQ(find_all(doc, "circle", "point").size(), p.series[1].x.size()) << "markers = true";

  // Every legend entry is a <g> holding a sample line in the series' colour and the label.
  std::vector<std::string> legend_text, legend_colour;
  std::string current;
  for (std::size_t i = 0; i < doc.elements.size(); ++i) {
    if (doc.elements[i].name == "g" && has_class(doc.elements[i], "legend-entry")) {
      EXPECT_EQ(doc.elements[i].attrs.at("data-series"), std::to_string(legend_text.size()));
      ASSERT_LT(i + 1, doc.elements.size());
      ASSERT_EQ(doc.elements[i + 1].name, "line");
      legend_colour.push_back(doc.elements[i + 1].attrs.at("stroke"));
      for (std::size_t j = i + 1; j < doc.elements.size(); ++j) {
        if (doc.elements[j].name == "text") {
          legend_text.push_back(doc.elements[j].text);
          break;
        }
      }
    }
  }
  ASSERT_EQ(legend_text.size(), 2u);
  EXPECT_EQ(legend_text[0], "top platen");
  EXPECT_EQ(legend_text[1], "bottom platen");
  EXPECT_EQ(legend_colour[0], lines[0].attrs.at("stroke"));
  EXPECT_EQ(legend_colour[1], lines[1].attrs.at("stroke"));
  EXPECT_EQ(find_all(doc, "g", "legend").size(), 1u);

  // Title, axis labels and the marker's label are there.
  std::set<std::string> texts;
  for (const auto& e : find_all(doc, "text", "")) texts.insert(e.text);
  for (const char* t : {"platen test", "platen displacement (mm)", "load (N)", "peak 3.1 N"}) {
    EXPECT_EQ(texts.count(t), 1u) << t;
  }
  EXPECT_EQ(find_all(doc, "g", "marker").size(), 1u);
}

TEST(RenderSvg, ExplicitColoursAreUsedAndOutputIsDeterministic) {
  Plot p = two_series_plot();
  p.series[0].colour = "rgb(10,20,30)";
  const std::string svg = render_svg(p);
  EXPECT_EQ(svg, render_svg(p));
  const auto lines = find_all(parse_ok(svg), "polyline", "series");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].attrs.at("stroke"), "rgb(10,20,30)");
  // Ten auto-coloured series: the first eight differ (the palette has eight colours).
  Plot many;
  for (int i = 0; i < 10; ++i) many.series.push_back(series("", {0, 1}, {0.0 + i, 1.0 + i}));
  std::set<std::string> colours;
  const auto all = find_all(parse_ok(render_svg(many)), "polyline", "series");
  ASSERT_EQ(all.size(), 10u);
  for (int i = 0; i < 8; ++i) colours.insert(all[i].attrs.at("stroke"));
  EXPECT_EQ(colours.size(), 8u);
}

TEST(RenderSvg, PolylinesLieInsideThePlotArea) {
  std::mt19937_64 rng(77);
  std::normal_distribution<double> noise(0.0, 3.0);
  for (int trial = 0; trial < 20; ++trial) {
    Plot p = two_series_plot();
    p.width = 300 + 40 * trial;
    p.height = 200 + 25 * trial;
    for (auto& s : p.series) {
      for (double& y : s.y) y = y * std::pow(10.0, trial - 10) + noise(rng);
      for (double& x : s.x) x = x * 1e3 - 700;
    }
    const Doc doc = parse_ok(render_svg(p));
    const Rect r = plot_area(doc);
    constexpr double kTol = 0.0051;  // coordinates are rounded to 0.01
    std::size_t count = 0;
    for (const auto& line : find_all(doc, "polyline", "series")) {
      for (XY q : points_of(line)) {
        ++count;
        EXPECT_GE(q.x, r.x0 - kTol);
        EXPECT_LE(q.x, r.x1 + kTol);
        EXPECT_GE(q.y, r.y0 - kTol);
        EXPECT_LE(q.y, r.y1 + kTol);
      }
    }
    EXPECT_GT(count, 100u);
    // The tick marks at the ends of each axis lie on the plot area's edges.
    const Axis ax = axis(doc, 'x'), ay = axis(doc, 'y');
    EXPECT_NEAR(ax.pixels.front(), r.x0, 0.011);
    EXPECT_NEAR(ax.pixels.back(), r.x1, 0.011);
    EXPECT_NEAR(ay.pixels.front(), r.y1, 0.011);
    EXPECT_NEAR(ay.pixels.back(), r.y0, 0.011);
  }
}

TEST(RenderSvg, XIsMonotoneAndYIsFlipped) {
  Plot p;
  std::vector<double> x, y;
  for (int i = 0; i < 50; ++i) {
    x.push_back(-3.0 + 0.1 * i);
    y.push_back(std::exp(0.05 * i));
  }
  p.series.push_back(series("rising", x, y));
  const auto lines = find_all(parse_ok(render_svg(p)), "polyline", "series");
  ASSERT_EQ(lines.size(), 1u);
  const auto pts = points_of(lines[0]);
  ASSERT_EQ(pts.size(), 50u);
  for (std::size_t i = 1; i < pts.size(); ++i) {
    EXPECT_GT(pts[i].x, pts[i - 1].x) << "larger x, further right";
    EXPECT_LT(pts[i].y, pts[i - 1].y) << "larger y, higher up (smaller pixel y)";
  }
}

TEST(RenderSvg, PointsMapToThePixelsPredictedFromTheTicks) {
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    Plot p;
    p.width = 400 + static_cast<int>(600 * unit(rng));
    p.height = 300 + static_cast<int>(400 * unit(rng));
    const double sx = std::pow(10.0, -6 + 12 * unit(rng)), ox = (unit(rng) - 0.3) * 5 * sx;
    const double sy = std::pow(10.0, -6 + 12 * unit(rng)), oy = (unit(rng) - 0.7) * 5 * sy;
    std::vector<double> x, y;
    for (int i = 0; i < 7; ++i) {
      x.push_back(ox + sx * unit(rng));
      y.push_back(oy + sy * unit(rng));
    }
    std::sort(x.begin(), x.end());
    p.series.push_back(series("s", x, y));
    const Doc doc = parse_ok(render_svg(p));
    const Axis ax = axis(doc, 'x'), ay = axis(doc, 'y');
    // The data range lies inside [first tick, last tick] on both axes.
    EXPECT_LE(ax.values.front(), x.front());
    EXPECT_GE(ax.values.back(), x.back());
    EXPECT_LE(ay.values.front(), *std::min_element(y.begin(), y.end()));
    EXPECT_GE(ay.values.back(), *std::max_element(y.begin(), y.end()));
    // The tick marks themselves are evenly spaced in pixels (a linear axis).
    for (const Axis* a : {&ax, &ay}) {
      for (std::size_t i = 0; i < a->values.size(); ++i) {
        EXPECT_NEAR(a->pixels[i], a->predict(a->values[i]), 0.011);
      }
    }
    const auto lines = find_all(doc, "polyline", "series");
    ASSERT_EQ(lines.size(), 1u);
    const auto pts = points_of(lines[0]);
    ASSERT_EQ(pts.size(), x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_NEAR(pts[i].x, ax.predict(x[i]), 0.01) << "x = " << x[i];
      EXPECT_NEAR(pts[i].y, ay.predict(y[i]), 0.01) << "y = " << y[i];
    }
    // The y axis runs upwards: the last tick is above the first.
    EXPECT_LT(ay.pixels.back(), ay.pixels.front());
    EXPECT_GT(ax.pixels.back(), ax.pixels.front());
  }
}

TEST(RenderSvg, TickLabelsReadBackToTheirTicks) {
  for (const auto& [lo, hi] :
       {std::pair{0.0, 1.0}, std::pair{-2.5e-6, 7.5e-6}, std::pair{1.0, 1.0 + 1e-9},
        std::pair{-3e4, 1.2e5}, std::pair{1e15, 3e15}}) {
    Plot p;
    p.series.push_back(series("s", {lo, hi}, {hi, lo}));
    const Doc doc = parse_ok(render_svg(p));
    for (char which : {'x', 'y'}) {
      const Axis a = axis(doc, which);
      const auto labels = find_all(doc, "text", std::string(1, which));
      std::vector<std::string> texts;
      for (const auto& l : labels) {
        if (has_class(l, "tick-label")) texts.push_back(l.text);
      }
      ASSERT_EQ(texts.size(), a.values.size());
      const double step = (a.values.back() - a.values.front()) / (a.values.size() - 1);
      for (std::size_t i = 0; i < texts.size(); ++i) {
        EXPECT_NEAR(number(texts[i]), a.values[i], 1e-3 * step) << texts[i];
        EXPECT_LE(texts[i].size(), 14u) << "compact: " << texts[i];
        if (i > 0) {
          EXPECT_NE(texts[i], texts[i - 1]);
        }
      }
    }
  }
  // Compact forms: a 0..1 axis is labelled 0, 0.2, ... 1 (no trailing zeros) and tiny values
  // use an exponent.
  Plot p;
  p.series.push_back(series("s", {0, 1}, {0, 1e-6}));
  const Doc doc = parse_ok(render_svg(p));
  std::set<std::string> x_labels, y_labels;
  for (const auto& l : find_all(doc, "text", "tick-label")) {
    (has_class(l, "x") ? x_labels : y_labels).insert(l.text);
  }
  EXPECT_EQ(x_labels.count("0"), 1u);
  EXPECT_EQ(x_labels.count("1"), 1u);
  EXPECT_EQ(x_labels.count("0.4"), 1u);
  EXPECT_EQ(y_labels.count("1e-06"), 1u);
}

TEST(RenderSvg, TickLabelsDoNotCrowdSmallPictures) {
  for (const auto& [w, h] : {std::pair{10, 10}, std::pair{200, 120}, std::pair{800, 500}}) {
    Plot p;
    p.width = w;
    p.height = h;
    p.y_label = "y";
    p.series.push_back(series("s", {1.0, 1.0 + 1e-9}, {-2.5e-6, 7.5e-6}));
    const Doc doc = parse_ok(render_svg(p));
    std::vector<std::pair<double, std::size_t>> x_labels;  // (pixel x, characters)
    std::vector<double> y_labels;
    for (const auto& l : find_all(doc, "text", "tick-label")) {
      if (has_class(l, "x")) x_labels.emplace_back(attr_number(l, "x"), l.text.size());
      if (has_class(l, "y")) y_labels.push_back(attr_number(l, "y"));
    }
    ASSERT_GE(x_labels.size(), 2u);
    ASSERT_GE(y_labels.size(), 2u);
    // Centred x labels: at 6 px a character (12 px sans-serif digits are wider) they must
    // not touch; y labels at least one line (12 px) apart.
    for (std::size_t i = 1; i < x_labels.size(); ++i) {
      const double half_widths =
          3.0 * static_cast<double>(x_labels[i].second + x_labels[i - 1].second);
      EXPECT_GT(x_labels[i].first - x_labels[i - 1].first, half_widths) << w << "x" << h;
    }
    for (std::size_t i = 1; i < y_labels.size(); ++i) {
      EXPECT_GE(std::abs(y_labels[i] - y_labels[i - 1]), 12.0) << w << "x" << h;
    }
  }
}

TEST(RenderSvg, DegenerateInputsGiveFiniteWellFormedSvg) {
  std::vector<std::pair<std::string, Plot>> cases;
  cases.emplace_back("zero series", Plot{});
  {
    Plot p;
    p.series.push_back(series("empty", {}, {}));
    cases.emplace_back("empty series", p);
  }
  {
    Plot p;
    p.series.push_back(series("one", {2.0}, {3.0}));
    cases.emplace_back("one point", p);
  }
  {
    Plot p;
    p.series.push_back(series("vertical", {1, 1, 1}, {0, 1, 2}));
    cases.emplace_back("all x equal", p);
  }
  {
    Plot p;
    p.series.push_back(series("flat", {0, 1, 2}, {5, 5, 5}));
    p.series.push_back(series("zero", {0, 1, 2}, {0, 0, 0}));
    cases.emplace_back("all y equal", p);
  }
  {
    Plot p;
    p.series.push_back(series("point", {0, 0}, {0, 0}));
    cases.emplace_back("all at the origin", p);
  }
  {
    Plot p;
    p.series.push_back(series("bad", {kNaN, kInf, 1}, {0, 1, -kInf}));
    p.markers.push_back({kNaN, 1, "nowhere"});
    cases.emplace_back("all non-finite", p);
  }
  {
    Plot p;
    p.series.push_back(series("huge", {-1e308, 0, 1e308}, {1e308, 1, -1e308}));
    p.series.push_back(series("mismatched", {0, 1, 2, 3}, {1, 2}));
    cases.emplace_back("huge and mismatched", p);
  }
  {
    Plot p;
    p.markers.push_back({3, 4, "only a marker"});
    p.width = 0;
    p.height = -5;
    cases.emplace_back("marker only, no size", p);
  }
  {
    Plot p;
    p.series.push_back(series("tiny", {1e-300, 1e-300}, {-1e-300, -1e-300}));
    p.series[0].line_width = kNaN;
    cases.emplace_back("tiny values", p);
  }
  for (const auto& [what, plot] : cases) {
    SCOPED_TRACE(what);
    const std::string svg = render_svg(plot);
    expect_finite(svg, what);
    const Doc doc = parse_ok(svg);
    const Rect r = plot_area(doc);
    EXPECT_GT(r.x1 - r.x0, 10.0);
    EXPECT_GT(r.y1 - r.y0, 10.0);
    EXPECT_LE(r.x1, attr_number(doc.elements[0], "width"));
    EXPECT_LE(r.y1, attr_number(doc.elements[0], "height"));
    EXPECT_EQ(find_all(doc, "g", "legend-entry").size(), plot.series.size());
    for (const auto& e : doc.elements) {
      if (e.name != "circle" || !e.attrs.count("data-series")) continue;
      EXPECT_GE(attr_number(e, "cx"), r.x0 - 0.0051);
      EXPECT_LE(attr_number(e, "cx"), r.x1 + 0.0051);
    }
  }
  // A lone point is drawn as a circle; with no data at all the picture says so.
  EXPECT_EQ(find_all(parse_ok(render_svg(cases[2].second)), "circle", "lone").size(), 1u);
  EXPECT_EQ(find_all(parse_ok(render_svg(cases[0].second)), "text", "no-data").size(), 1u);
  EXPECT_EQ(find_all(parse_ok(render_svg(cases[6].second)), "text", "no-data").size(), 1u);
}

TEST(RenderSvg, NonFinitePointsBreakTheLine) {
  Plot p;
  p.series.push_back(series("broken", {0, 1, 2, 3, 4, 5, 6, 7}, {0, 1, kNaN, 3, 4, 5, 6, 7}));
  p.series[0].x[5] = kInf;
  p.series.push_back(series("whole", {0, 7}, {1, 2}));
  const Doc doc = parse_ok(render_svg(p));
  std::vector<std::size_t> sizes;
  for (const auto& l : find_all(doc, "polyline", "series")) {
    if (l.attrs.at("data-series") == "0") sizes.push_back(points_of(l).size());
  }
  EXPECT_EQ(sizes, (std::vector<std::size_t>{2, 2, 2})) << "runs {0,1} {3,4} {6,7}";
  EXPECT_EQ(find_all(doc, "polyline", "series").size(), 4u);
}

TEST(RenderSvg, SpecialCharactersAreEscaped) {
  Plot p;
  p.title = "a<b & c>\"d'";
  p.x_label = "x <&> (mm)";
  p.y_label = "F & G";
  p.series.push_back(series("<&>", {0, 1}, {0, 1}));
  p.series[0].colour = "red\"/><script>";
  p.markers.push_back({0.5, 0.5, "<peak> & 'so'"});
  const std::string svg = render_svg(p);
  EXPECT_NE(svg.find("a&lt;b &amp; c&gt;&quot;d&apos;"), std::string::npos);
  EXPECT_NE(svg.find("&lt;&amp;&gt;"), std::string::npos);
  EXPECT_EQ(svg.find("<&>"), std::string::npos);
  EXPECT_EQ(svg.find("<script"), std::string::npos);
  EXPECT_EQ(svg.find("<peak>"), std::string::npos);
  const Doc doc = parse_ok(svg);
  std::set<std::string> texts;
  for (const auto& e : find_all(doc, "text", "")) texts.insert(e.text);
  for (const std::string& t :
       {p.title, p.x_label, p.y_label, std::string("<&>"), p.markers[0].label}) {
    EXPECT_EQ(texts.count(t), 1u) << t;
  }
  const auto lines = find_all(doc, "polyline", "series");
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].attrs.at("stroke"), p.series[0].colour);
}

TEST(RenderSvg, ThinningKeepsThePeaksOfLongSeries) {
  constexpr int kN = 100000;
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> x(kN), y(kN);
  for (int i = 0; i < kN; ++i) {
    x[i] = 1e-3 * i;
    y[i] = std::sin(1e-3 * i) + 0.1 * unit(rng);
  }
  const int peak = 61723, dip = 12345;
  y[peak] = 40.0;
  y[dip] = -25.0;
  Plot p;
  p.series.push_back(series("long", x, y));
  const std::string svg = render_svg(p);
  const Doc doc = parse_ok(svg);
  const auto lines = find_all(doc, "polyline", "series");
  ASSERT_EQ(lines.size(), 1u);
  const auto pts = points_of(lines[0]);
  EXPECT_LE(pts.size(), 4010u);
  EXPECT_GE(pts.size(), 500u);
  const Axis ax = axis(doc, 'x'), ay = axis(doc, 'y');
  auto top = std::min_element(pts.begin(), pts.end(), [](XY a, XY b) { return a.y < b.y; });
  auto bottom = std::max_element(pts.begin(), pts.end(), [](XY a, XY b) { return a.y < b.y; });
  EXPECT_NEAR(top->y, ay.predict(40.0), 0.01) << "the global maximum survives";
  EXPECT_NEAR(top->x, ax.predict(x[peak]), 0.01);
  EXPECT_NEAR(bottom->y, ay.predict(-25.0), 0.01) << "the global minimum survives";
  EXPECT_NEAR(bottom->x, ax.predict(x[dip]), 0.01);
  // The ends of the line are kept, and the points are still in order.
  EXPECT_NEAR(pts.front().x, ax.predict(x.front()), 0.01);
  EXPECT_NEAR(pts.back().x, ax.predict(x.back()), 0.01);
  for (std::size_t i = 1; i < pts.size(); ++i) EXPECT_GE(pts[i].x, pts[i - 1].x);
  EXPECT_LT(svg.size(), 200000u) << "compact";

  // Broken into two runs by a NaN: both thinned, the peak still there.
  p.series[0].y[50000] = kNaN;
  const Doc broken = parse_ok(render_svg(p));
  const auto parts = find_all(broken, "polyline", "series");
  ASSERT_EQ(parts.size(), 2u);
  std::size_t total = 0;
  double top_y = kInf;
  for (const auto& l : parts) {
    for (XY q : points_of(l)) {
      ++total;
      top_y = std::min(top_y, q.y);
    }
  }
  EXPECT_LE(total, 4010u);
  EXPECT_NEAR(top_y, axis(broken, 'y').predict(40.0), 0.01);
}

TEST(RenderSvg, MarkersWidenTheAxesAndCarryTheirLabels) {
  Plot p;
  p.series.push_back(series("s", {0, 1, 2}, {0, 1, 0}));
  p.markers.push_back({5.0, -3.0, "far away"});
  const Doc doc = parse_ok(render_svg(p));
  const Axis ax = axis(doc, 'x'), ay = axis(doc, 'y');
  EXPECT_GE(ax.values.back(), 5.0);
  EXPECT_LE(ay.values.front(), -3.0);
  const auto markers = find_all(doc, "g", "marker");
  ASSERT_EQ(markers.size(), 1u);
  bool found = false;
  for (std::size_t i = 0; i < doc.elements.size(); ++i) {
    if (!has_class(doc.elements[i], "marker")) continue;
    ASSERT_LT(i + 2, doc.elements.size());
    const Element& c = doc.elements[i + 1];
    ASSERT_EQ(c.name, "circle");
    EXPECT_NEAR(attr_number(c, "cx"), ax.predict(5.0), 0.01);
    EXPECT_NEAR(attr_number(c, "cy"), ay.predict(-3.0), 0.01);
    EXPECT_EQ(doc.elements[i + 2].text, "far away");
    found = true;
  }
  EXPECT_TRUE(found);
}

TEST(WritePlotSvg, WritesTheRenderedPictureAtomically) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleave_test_plot_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Plot p = two_series_plot();
  const fs::path file = dir / "load_displacement.svg";
  cleave::io::write_plot_svg(file, p);
  EXPECT_EQ(cleave::io::read_file(file), render_svg(p));
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
  EXPECT_THROW(cleave::io::write_plot_svg(dir / "no" / "such" / "dir.svg", p), std::runtime_error);
  fs::remove_all(dir);
}

}  // namespace
