#pragma once
/// \file
/// 2D line plots (load-displacement curves of platen tests and the like) rendered as
/// standalone SVG images, written by hand with fmt (no plotting library). The output is
/// deterministic: the same Plot always gives the same bytes.
///
/// What the SVG contains, for readers and tests (classes and data attributes are stable):
///  * `<rect class="plot-area" x= y= width= height=>`: the data rectangle. Its edges are the
///    first and last ticks of each axis, and every data point lies inside it.
///  * `<line class="tick x" data-value="V" x1= ...>` (x1 == x2 is the pixel of value V) and
///    `<line class="tick y" data-value="V" ... y1= ...>` (y1 == y2), one per tick, and
///    `<text class="tick-label x|y">` with the label shown.
///  * `<polyline class="series" data-series="i" points="...">`: one per unbroken run of two or
///    more finite points of series i; a run of a single point is drawn as
///    `<circle class="point lone" data-series="i">`, and `markers = true` adds
///    `<circle class="point" data-series="i">` at every (drawn) point.
///  * `<g class="legend-entry" data-series="i">`: one per series, inside `<g class="legend">`.
///  * `<g class="marker">` with a circle and a label for each finite PlotMarker.

#include <filesystem>
#include <string>
#include <vector>

namespace cleave::io {

/// One curve. Point k is (x[k], y[k]); only the first min(x.size(), y.size()) points are used.
/// A point with a non-finite coordinate (or one of magnitude above 1e300) is skipped and
/// breaks the line there.
struct PlotSeries {
  std::string label;         ///< Legend text; empty shows "series N" (N counted from 1).
  std::vector<double> x, y;  ///< Data, same length.
  std::string colour;        ///< CSS colour; empty takes the next one from a fixed
                             ///< colour-blind-safe palette (Okabe-Ito).
  bool markers = false;      ///< Also draw a small circle at every point.
  bool dashed = false;       ///< Dashed line.
  double line_width = 1.5;   ///< Stroke width in pixels (non-finite or <= 0 gives 1.5).
};

/// An annotated point, e.g. {2.1, 12.3, "peak 12.3 N"}: a small circle and its label.
/// Markers count towards the axis ranges; a marker with a non-finite coordinate is not drawn.
struct PlotMarker {
  double x = 0, y = 0;
  std::string label;
};

/// A whole picture. Axis labels carry units, e.g. "platen displacement (mm)". All texts are
/// XML-escaped when rendered.
struct Plot {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  std::vector<PlotMarker> markers;
  int width = 800, height = 500;  ///< Pixels; raised to a minimum that fits the axes.
};

/// Renders `plot` as a standalone SVG document (UTF-8, with an XML declaration). Pure and
/// deterministic. Axis ranges span all finite points and markers and are widened to the
/// ticks of nice_ticks (a zero-width range is padded); with no finite data at all the axes
/// span [0, 1] and "no data" is shown. Small pictures get fewer ticks (down to target 2), so
/// that labels do not overlap, and the picture is widened where even that does not fit. Series of
/// more than 4000 finite points are thinned to about 4000 points: the points of each run are split
/// into consecutive buckets and each bucket keeps its lowest and highest y (in their original
/// order), so peaks survive. No NaN or infinity is ever written.
std::string render_svg(const Plot& plot);

/// Writes render_svg(plot) to `path` atomically (through `path.tmp` and a rename; see
/// write_file_atomically). The folder must exist. Throws std::runtime_error naming the file.
void write_plot_svg(const std::filesystem::path& path, const Plot& plot);

/// "Nice" axis ticks: ascending values k * step for consecutive integers k, with step one of
/// 1, 2 or 5 x 10^e, about `target` of them (target is clamped to [2, 100]), such that the
/// first tick <= min(lo, hi) and the last tick >= max(lo, hi) with no spare tick at either
/// end. Reversed arguments are swapped. A zero-width range is padded (by 10% of |lo|, or to
/// [-1, 1] around 0) and one narrower than 1e-10 of its magnitude is widened to that, so the
/// result always has at least two ticks. A non-finite bound is replaced by the other (both
/// non-finite gives the range [0, 1]). When the ticks would overflow (ranges near the
/// largest double) the result is just {lo, hi}.
std::vector<double> nice_ticks(double lo, double hi, int target = 6);

}  // namespace cleave::io
