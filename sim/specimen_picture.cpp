#include "sim/specimen_picture.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace cleave::sim {

namespace {

/// Convex hull of 2D points (Andrew's monotone chain), counter-clockwise.
std::vector<Eigen::Vector2d> hull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k > 1 ? k - 1 : k);
  return h;
}

const char* colour(const geometry::CrystalOrientation& o, int slab) {
  static const char* blues[3][3] = {{"#1f4e9c", "#3a6fc4", "#6f98dc"},
                                    {"#2b7a8c", "#44a0b4", "#7cc4d2"},
                                    {"#4b3f9e", "#6e61c4", "#9d93dc"}};
  static const char* oranges[3][2] = {{"#c0561b", "#e07b3a"}, {"#b8860b", "#dcae3c"},
                                      {"#a23b4c", "#cc6375"}};
  const int a = o.angle_deg / 60;
  return o.family == geometry::CleavageFamily::a_11_20 ? blues[a][slab % 3] : oranges[a][slab % 2];
}

}  // namespace

std::string specimen_picture_svg(const geometry::Specimen& specimen,
                                 const std::vector<geometry::Piece>& pieces) {
  const Eigen::Vector3d size = specimen.def.outline.size;
  const double scale = 800.0 / std::max(size.x(), size.y());  // pixels per metre
  const double w = size.x() * scale, h = size.y() * scale;
  std::string svg = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{:.0f}' height='{:.0f}' "
      "viewBox='-10 -40 {:.0f} {:.0f}' font-family='sans-serif' font-size='13'>\n"
      "<text x='0' y='-22'>cleave: bottom layer, {} grains split into cleavage slabs</text>\n"
      "<text x='0' y='-6' fill='#1f4e9c'>blue: &lt;11-20&gt; (3 slabs)</text>"
      "<text x='190' y='-6' fill='#c0561b'>orange: &lt;10-10&gt; (2 slabs)</text>"
      "<text x='390' y='-6' fill='#555'>shade: 0/60/120 degrees</text>\n"
      "<rect x='0' y='0' width='{:.1f}' height='{:.1f}' fill='none' stroke='#999'/>\n",
      w + 20, h + 50, w + 20, h + 50, specimen.grains.size(), w, h);
  if (specimen.def.outline.kind == geometry::Outline::Kind::disc) {
    svg += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='{:.1f}' fill='none' stroke='#999'/>\n",
                       w / 2, h / 2, w / 2);
  }
  for (const auto& p : pieces) {
    if (specimen.grains[p.lineage.grain_id].site.k != 1) continue;
    std::vector<Eigen::Vector2d> pts;
    for (const auto& v : p.shape->vertices_approx()) {
      const Eigen::Vector3d q = v + p.position;
      pts.emplace_back(q.x() * scale, h - q.y() * scale);  // y up
    }
    std::string points;
    for (const auto& q : hull(pts)) points += fmt::format("{:.2f},{:.2f} ", q.x(), q.y());
    svg += fmt::format("<polygon points='{}' fill='{}' stroke='white' stroke-width='0.6'>"
                       "<title>{}</title></polygon>\n",
                       points, colour(p.orientation, p.lineage.path.empty() ? 0 : p.lineage.path[0]),
                       p.lineage.name());
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace cleave::sim
