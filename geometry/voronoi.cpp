#include "geometry/voronoi.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "geometry/rng.hpp"

namespace cleave::geometry {

namespace {
constexpr double kPi = 3.14159265358979323846;

void check_domain(const VoronoiDef& def) {
  for (int d = 0; d < 3; ++d) {
    if (!(def.size[d] > 0.0)) throw std::invalid_argument("Voronoi box sizes must be positive");
  }
  if (def.domain != VoronoiDomain::disc) return;
  if (def.size.x() != def.size.y()) {
    throw std::invalid_argument(
        "a Voronoi disc's bounding box is square: its diameter along x and y");
  }
  if (def.periodic[0] || def.periodic[1] || def.periodic[2]) {
    throw std::invalid_argument("a Voronoi disc has no periodic axes: a periodic cell is a box");
  }
}

/// Whether p lies strictly inside the convex polygon (corners counter-clockwise).
bool inside_polygon(const std::vector<Eigen::Vector2d>& polygon, double x, double y) {
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    if (!((b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x()) > 0.0)) return false;
  }
  return true;
}
}  // namespace

std::vector<Eigen::Vector2d> disc_polygon(double diameter, int sides) {
  if (!(diameter > 0.0) || !std::isfinite(diameter))
    throw std::invalid_argument("a disc's diameter must be positive");
  if (sides < 8 || sides % 4 != 0) {
    throw std::invalid_argument("a disc's polygon needs a multiple of 4 sides, at least 8; found " +
                                std::to_string(sides));
  }
  // Side k faces the angle 2 pi k / N; corner k lies between sides k and k + 1, at the angle
  // (2k + 1) pi / N and the distance r / cos(pi / N). The first quadrant's corners are worked
  // out (its first on x = r exactly, the rest mirrored about the diagonal), the others mirrored.
  const double r = 0.5 * diameter;
  const int q = sides / 4;
  std::vector<Eigen::Vector2d> quadrant(static_cast<std::size_t>(q));
  for (int k = 0; k <= (q - 1) / 2; ++k) {
    const double angle = (2.0 * k + 1.0) * kPi / sides;
    Eigen::Vector2d c =
        r / std::cos(kPi / sides) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    if (k == 0) c = Eigen::Vector2d(r, r * std::tan(kPi / sides));
    if (2 * k + 1 == q) c.y() = c.x();  // the corner on the diagonal
    quadrant[static_cast<std::size_t>(k)] = c;
    quadrant[static_cast<std::size_t>(q - 1 - k)] = Eigen::Vector2d(c.y(), c.x());
  }
  std::vector<Eigen::Vector2d> corners;
  const auto at = [&](int k) { return quadrant[static_cast<std::size_t>(k)]; };
  for (int k = 0; k < q; ++k) corners.push_back(at(k));
  for (int k = 0; k < q; ++k) corners.emplace_back(-at(q - 1 - k).x(), at(q - 1 - k).y());
  for (int k = 0; k < q; ++k) corners.emplace_back(-at(k).x(), -at(k).y());
  for (int k = 0; k < q; ++k) corners.emplace_back(at(q - 1 - k).x(), -at(q - 1 - k).y());
  for (auto& c : corners) c += Eigen::Vector2d(r, r);
  return corners;
}

ExactPolyhedron exact_disc_prism(double diameter, double thickness, int sides) {
  if (!(thickness > 0.0) || !std::isfinite(thickness))
    throw std::invalid_argument("a disc's thickness must be positive");
  const std::vector<Eigen::Vector2d> polygon = disc_polygon(diameter, sides);
  const int n = static_cast<int>(polygon.size());
  PolygonMesh m;
  m.name = "disc";
  for (const double z : {0.0, thickness}) {
    for (const auto& c : polygon) m.vertices.emplace_back(c.x(), c.y(), z);
  }
  // Corners 0..n-1 below, n..2n-1 above; faces CCW seen from outside.
  std::vector<int> bottom, top;
  for (int i = 0; i < n; ++i) {
    bottom.push_back(n - 1 - i);
    top.push_back(n + i);
  }
  m.faces = {bottom, top};
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.faces.push_back({i, j, n + j, n + i});
  }
  return ExactPolyhedron::from_mesh(m);
}

ExactPolyhedron voronoi_domain(const VoronoiDef& def) {
  check_domain(def);
  if (def.domain == VoronoiDomain::disc)
    return exact_disc_prism(def.size.x(), def.size.z(), def.sides);
  return exact_box(Eigen::Vector3d::Zero(), def.size);
}

std::vector<Eigen::Vector3d> voronoi_points(const VoronoiDef& def) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<std::size_t>(std::max(def.cells, 0)));
  const bool disc = def.domain == VoronoiDomain::disc;
  const std::vector<Eigen::Vector2d> polygon = disc && def.cells > 0
                                                   ? disc_polygon(def.size.x(), def.sides)
                                                   : std::vector<Eigen::Vector2d>{};
  for (int i = 0; i < def.cells; ++i) {
    SplitMix64 rng = stream_for(def.seed, static_cast<std::uint64_t>(i));
    Eigen::Vector3d p;
    do {
      for (int d = 0; d < 3; ++d) p[d] = rng.uniform() * def.size[d];
    } while (disc && !inside_polygon(polygon, p.x(), p.y()));
    points.push_back(p);
  }
  return points;
}

ExactPolyhedron exact_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  PolygonMesh m;
  m.name = "box";
  for (int k = 0; k < 8; ++k) {
    m.vertices.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(),
                            (k & 4) ? hi.z() : lo.z());
  }
  // Vertex k has bit 0 = x, bit 1 = y, bit 2 = z; faces CCW seen from outside.
  m.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return ExactPolyhedron::from_mesh(m);
}

std::vector<ExactPolyhedron> voronoi_cells(const VoronoiDef& def) {
  check_domain(def);
  if (def.cells < 1) throw std::invalid_argument("a Voronoi specimen needs at least one cell");
  if (!(def.gap >= 0.0)) throw std::invalid_argument("the Voronoi gap must not be negative");
  const std::vector<Eigen::Vector3d> points = voronoi_points(def);
  const std::size_t n = points.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const double d = (points[i] - points[j]).norm();
      if (d == 0.0 || d <= def.gap) {
        throw std::invalid_argument(
            "Voronoi points " + std::to_string(j) + " and " + std::to_string(i) + " are " +
            std::to_string(d) + " m apart, not more than the gap " + std::to_string(def.gap) +
            " m: their cells would vanish; use a smaller gap, fewer cells or another seed");
      }
    }
  }
  // Along periodic axes the neighbours are the points and their images one box over, and a
  // cell starts from the box widened by a box each way (it cannot reach farther).
  std::vector<Eigen::Vector3d> others = points;
  std::vector<std::size_t> owner(n);
  std::vector<Eigen::Vector3d> shift(n, Eigen::Vector3d::Zero());  // others[k] = points[owner[k]] + shift[k]
  std::iota(owner.begin(), owner.end(), 0);
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = def.size;
  const bool periodic = def.periodic[0] || def.periodic[1] || def.periodic[2];
  if (periodic) {
    for (int d = 0; d < 3; ++d) {
      if (!def.periodic[static_cast<std::size_t>(d)]) continue;
      lo[d] = -def.size[d];
      hi[d] = 2.0 * def.size[d];
      if (!(def.size[d] > def.gap)) throw std::invalid_argument("a periodic Voronoi box must be wider than the gap");
    }
    for (int x = -1; x <= 1; ++x) {
      for (int y = -1; y <= 1; ++y) {
        for (int z = -1; z <= 1; ++z) {
          const Eigen::Vector3i k(x, y, z);
          bool skip = k.isZero();
          for (int d = 0; d < 3; ++d) skip = skip || (k[d] != 0 && !def.periodic[static_cast<std::size_t>(d)]);
          if (skip) continue;
          for (std::size_t i = 0; i < n; ++i) {
            const Eigen::Vector3d t = def.size.cwiseProduct(k.cast<double>());
            others.push_back(points[i] + t);
            owner.push_back(i);
            shift.push_back(t);
          }
        }
      }
    }
  }
  const ExactPolyhedron start = periodic ? exact_box(lo, hi) : voronoi_domain(def);
  std::vector<ExactPolyhedron> cells;
  cells.reserve(n);
  std::vector<std::size_t> order(others.size());
  for (std::size_t i = 0; i < n; ++i) {
    // The other points nearest first; once a bisector lies beyond the cell's farthest
    // corner, so do all later ones, and they cannot cut it.
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      const double da = (others[a] - points[i]).squaredNorm(), db = (others[b] - points[i]).squaredNorm();
      return da != db ? da < db : a < b;
    });
    ExactPolyhedron cell = start;
    for (std::size_t j : order) {
      if (j == i) continue;  // (its images are other points: they bound it)
      const Eigen::Vector3d& p = points[i];
      const Eigen::Vector3d& q = others[j];
      const double distance = (q - p).norm();
      double reach = 0.0;
      for (const auto& v : cell.vertices_approx()) reach = std::max(reach, (v - p).norm());
      if (0.5 * (distance - def.gap) > reach * (1.0 + 1e-9)) break;
      // Keep the side nearer to p: the bisector's positive side, exactly, or with a gap the
      // bisector moved gap/2 towards p (its offset rounded, then taken exactly).
      const ExactPlane plane =
          def.gap == 0.0
              ? (shift[j].isZero() ? ExactPlane::bisector(p, q)
                                   : ExactPlane::bisector(p, points[owner[j]], shift[j]))  // the image's sum exact
              : ExactPlane::from_normal_offset(p - q, (p - q).dot(0.5 * (p + q)) +
                                                          0.5 * def.gap * distance);
      // p lies strictly on the kept side and inside the cell, so a plane that misses the
      // cell leaves all of it on the kept side.
      SplitResult r = cell.split(plane);
      if (r.ok()) cell = std::move(*r.above);
    }
    cells.push_back(std::move(cell));
  }
  return cells;
}

}  // namespace cleave::geometry
