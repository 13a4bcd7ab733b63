#include "geometry/laguerre.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>

#include "geometry/rng.hpp"
#include "geometry/voronoi.hpp"

namespace cleave::geometry {

namespace {

constexpr double kPi = 3.14159265358979323846;

void check_input(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights) {
  if (points.empty())
    throw std::invalid_argument("a Laguerre tessellation needs at least one point");
  if (weights.size() != points.size()) {
    throw std::invalid_argument("Laguerre tessellation: " + std::to_string(points.size()) +
                                " points but " + std::to_string(weights.size()) + " weights");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite() || !std::isfinite(weights[i])) {
      throw std::invalid_argument("Laguerre point " + std::to_string(i) +
                                  " or its weight is not finite");
    }
  }
}

/// Where the power bisector of p_i and p_j lies along the unit direction from p_i to p_j:
/// cell i keeps (x - p_i) . u <= t.
double bisector_offset(const Eigen::Vector3d& pi, double wi, const Eigen::Vector3d& pj, double wj) {
  const double d = (pj - pi).norm();
  return (d * d + wi - wj) / (2.0 * d);
}

double reach_of(const std::vector<Eigen::Vector3d>& vertices, const Eigen::Vector3d& p) {
  double r = 0.0;
  for (const auto& v : vertices) r = std::max(r, (v - p).norm());
  return r;
}

// ---- a double-precision convex clipper (fitting only) -------------------------------------

struct Face {
  int tag = -1;                    ///< the neighbour whose bisector made it; -1 for the domain
  std::vector<Eigen::Vector3d> v;  ///< CCW seen from outside
};
using Poly = std::vector<Face>;

Poly poly_of(const PolygonMesh& m) {
  Poly p;
  for (const auto& f : m.faces) {
    Face face;
    for (int k : f) face.v.push_back(m.vertices[static_cast<std::size_t>(k)]);
    p.push_back(std::move(face));
  }
  return p;
}

std::vector<Eigen::Vector3d> vertices_of(const Poly& p) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& f : p) out.insert(out.end(), f.v.begin(), f.v.end());
  return out;
}

/// Keeps a . x + d >= 0 (within eps). Returns false when nothing is left.
bool clip(Poly& poly, const Eigen::Vector3d& a, double d, int tag, double eps) {
  bool out = false, in = false;
  for (const auto& f : poly) {
    for (const auto& v : f.v) {
      const double s = a.dot(v) + d;
      out = out || s < -eps;
      in = in || s > eps;
    }
  }
  if (!out) return true;
  if (!in) {
    poly.clear();
    return false;
  }
  Poly result;
  std::vector<Eigen::Vector3d> cap;
  for (const auto& f : poly) {
    Face kept{f.tag, {}};
    const std::size_t n = f.v.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& c = f.v[i];
      const Eigen::Vector3d& x = f.v[(i + 1) % n];
      const double sc = a.dot(c) + d, sx = a.dot(x) + d;
      if (sc >= -eps) {
        kept.v.push_back(c);
        if (sc <= eps) cap.push_back(c);
      }
      if ((sc > eps && sx < -eps) || (sc < -eps && sx > eps)) {
        const Eigen::Vector3d hit = c + (x - c) * (sc / (sc - sx));
        kept.v.push_back(hit);
        cap.push_back(hit);
      }
    }
    if (kept.v.size() >= 3) result.push_back(std::move(kept));
  }
  if (cap.size() >= 3) {
    // The cap's outward normal is -a; order its points CCW seen from outside.
    const Eigen::Vector3d n = -a.normalized();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& c : cap) centre += c;
    centre /= static_cast<double>(cap.size());
    const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
    std::vector<std::pair<double, Eigen::Vector3d>> around;
    for (const auto& c : cap)
      around.emplace_back(std::atan2((c - centre).dot(w), (c - centre).dot(u)), c);
    std::sort(around.begin(), around.end(),
              [](const auto& l, const auto& r) { return l.first < r.first; });
    Face face{tag, {}};
    const double close = 10.0 * eps / a.norm();
    for (const auto& [angle, c] : around) {
      if (!face.v.empty() && (face.v.back() - c).norm() <= close) continue;
      face.v.push_back(c);
    }
    while (face.v.size() > 1 && (face.v.back() - face.v.front()).norm() <= close) face.v.pop_back();
    if (face.v.size() >= 3) result.push_back(std::move(face));
  }
  poly = std::move(result);
  return !poly.empty();
}

double volume_of(const Poly& p) {
  if (p.empty()) return 0.0;
  const Eigen::Vector3d o = p.front().v.front();
  double six = 0.0;
  for (const auto& f : p) {
    for (std::size_t i = 1; i + 1 < f.v.size(); ++i) {
      six += (f.v[0] - o).dot((f.v[i] - o).cross(f.v[i + 1] - o));
    }
  }
  return six / 6.0;
}

double area_of(const Face& f) {
  Eigen::Vector3d twice = Eigen::Vector3d::Zero();
  for (std::size_t i = 1; i + 1 < f.v.size(); ++i)
    twice += (f.v[i] - f.v[0]).cross(f.v[i + 1] - f.v[0]);
  return 0.5 * twice.norm();
}

/// Per cell, the other points ordered by their bisector's offset (nearest plane first).
std::vector<int> by_offset(const std::vector<Eigen::Vector3d>& points,
                           const std::vector<double>& weights, std::size_t i) {
  std::vector<int> order;
  std::vector<double> t(points.size());
  for (std::size_t j = 0; j < points.size(); ++j) {
    if (j == i) continue;
    t[j] = bisector_offset(points[i], weights[i], points[j], weights[j]);
    order.push_back(static_cast<int>(j));
  }
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return t[a] != t[b] ? t[a] < t[b] : a < b; });
  return order;
}

LaguerreApprox approx_cells(const Poly& domain, double length,
                            const std::vector<Eigen::Vector3d>& points,
                            const std::vector<double>& weights,
                            const std::vector<std::vector<std::pair<int, double>>>* hints) {
  const std::size_t n = points.size();
  LaguerreApprox out;
  out.volumes.assign(n, 0.0);
  out.faces.assign(n, {});
  std::vector<char> done(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = points[i];
    Poly cell = domain;
    double reach = reach_of(vertices_of(cell), p);
    std::fill(done.begin(), done.end(), 0);
    done[i] = 1;
    bool alive = true;
    auto cut = [&](int j) {
      done[static_cast<std::size_t>(j)] = 1;
      const Eigen::Vector3d& q = points[static_cast<std::size_t>(j)];
      if (q == p)
        throw std::invalid_argument("Laguerre points " + std::to_string(i) + " and " +
                                    std::to_string(j) + " coincide");
      const double t = bisector_offset(p, weights[i], q, weights[static_cast<std::size_t>(j)]);
      if (t > reach * (1.0 + 1e-9)) return false;
      const Eigen::Vector3d a = 2.0 * (p - q);
      const double d =
          q.squaredNorm() - p.squaredNorm() - weights[static_cast<std::size_t>(j)] + weights[i];
      alive = clip(cell, a, d, j, 1e-12 * a.norm() * length);
      if (alive) reach = reach_of(vertices_of(cell), p);
      return true;
    };
    if (hints != nullptr) {
      for (const auto& [j, area] : (*hints)[i]) {
        if (alive) cut(j);
      }
      // The rest in index order: cheap to skip once the cell is small.
      for (std::size_t j = 0; j < n && alive; ++j) {
        if (!done[j]) cut(static_cast<int>(j));
      }
    } else {
      for (int j : by_offset(points, weights, i)) {
        if (!alive) break;
        if (!cut(j)) {
          // Offsets only grow from here on: no later plane reaches the cell.
          break;
        }
      }
    }
    if (!alive) continue;
    out.volumes[i] = volume_of(cell);
    for (const auto& f : cell) {
      if (f.tag >= 0) out.faces[i].emplace_back(f.tag, area_of(f));
    }
  }
  return out;
}

double domain_length(const PolygonMesh& m) {
  Eigen::AlignedBox3d box;
  for (const auto& v : m.vertices) box.extend(v);
  return box.diagonal().norm();
}

double max_error(const std::vector<double>& v, const std::vector<double>& t) {
  double e = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) e = std::max(e, std::abs(v[i] - t[i]) / t[i]);
  return e;
}

}  // namespace

LaguerreApprox laguerre_cells_approx(const PolygonMesh& domain,
                                     const std::vector<Eigen::Vector3d>& points,
                                     const std::vector<double>& weights) {
  check_input(points, weights);
  return approx_cells(poly_of(domain), domain_length(domain), points, weights, nullptr);
}

namespace {
std::vector<ExactPolyhedron> exact_cells(
    const ExactPolyhedron& domain, const std::vector<Eigen::Vector3d>& points,
    const std::vector<double>& weights,
    const std::vector<std::vector<std::pair<int, double>>>* hints) {
  check_input(points, weights);
  const std::size_t n = points.size();
  std::vector<ExactPolyhedron> cells;
  cells.reserve(n);
  std::vector<char> done(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = points[i];
    ExactPolyhedron cell = domain;
    double reach = reach_of(cell.vertices_approx(), p);
    std::fill(done.begin(), done.end(), 0);
    done[i] = 1;
    // Returns false when the plane lies beyond the cell's farthest vertex (no cut).
    auto cut = [&](std::size_t j) {
      done[j] = 1;
      const Eigen::Vector3d& q = points[j];
      if (q == p) {
        throw std::invalid_argument("Laguerre points " + std::to_string(std::min(i, j)) + " and " +
                                    std::to_string(std::max(i, j)) + " coincide");
      }
      const double t = bisector_offset(p, weights[i], q, weights[j]);
      if (t > reach * (1.0 + 1e-9)) return false;
      std::optional<ExactPolyhedron> kept =
          cell.clipped(ExactPlane::power_bisector(p, weights[i], q, weights[j]));
      if (!kept) {
        throw std::invalid_argument(
            "Laguerre point " + std::to_string(i) + " (weight " + std::to_string(weights[i]) +
            " m^2) has an empty cell: point " + std::to_string(j) +
            "'s power covers all of it; lower that weight or raise this one");
      }
      const bool changed =
          kept->num_vertices() != cell.num_vertices() || kept->num_faces() != cell.num_faces();
      cell = std::move(*kept);
      if (changed) reach = reach_of(cell.vertices_approx(), p);
      return true;
    };
    if (hints != nullptr) {
      for (const auto& [j, area] : (*hints)[i]) cut(static_cast<std::size_t>(j));
    }
    for (int j : by_offset(points, weights, i)) {
      if (done[static_cast<std::size_t>(j)]) continue;
      if (!cut(static_cast<std::size_t>(j))) break;  // later offsets are larger still
    }
    cells.push_back(std::move(cell));
  }
  return cells;
}
}  // namespace

std::vector<ExactPolyhedron> laguerre_cells(const ExactPolyhedron& domain,
                                            const std::vector<Eigen::Vector3d>& points,
                                            const std::vector<double>& weights) {
  return exact_cells(domain, points, weights, nullptr);
}

LaguerreFit fit_laguerre_weights(const PolygonMesh& domain,
                                 const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<double>& targets, double tolerance,
                                 int max_iterations) {
  const std::size_t n = points.size();
  if (targets.size() != n)
    throw std::invalid_argument("fit_laguerre_weights: one target volume per point");
  for (double t : targets) {
    if (!(t > 0.0))
      throw std::invalid_argument("fit_laguerre_weights: target volumes must be positive");
  }
  const Poly start = poly_of(domain);
  const double length = domain_length(domain);
  LaguerreFit fit;
  // Zero weights (the Voronoi cells) leave no cell empty: every point lies in its own.
  fit.weights.assign(n, 0.0);
  std::vector<double> radius(n);
  for (std::size_t i = 0; i < n; ++i) radius[i] = std::cbrt(3.0 * targets[i] / (4.0 * kPi));
  check_input(points, fit.weights);
  LaguerreApprox now = approx_cells(start, length, points, fit.weights, nullptr);
  double error = max_error(now.volumes, targets);
  auto norm_of = [&](const std::vector<double>& v) {
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) s += (v[i] - targets[i]) * (v[i] - targets[i]);
    return std::sqrt(s);
  };
  double residual_norm = norm_of(now.volumes);
  // No cell may fall below half the least of the targets and the start's volumes (KMT).
  const double floor = 0.5 * std::min(*std::min_element(targets.begin(), targets.end()),
                                      *std::min_element(now.volumes.begin(), now.volumes.end()));
  while (error > tolerance && fit.iterations < max_iterations) {
    ++fit.iterations;
    // The Jacobian of the volumes in the weights (a graph Laplacian), symmetrised.
    std::vector<Eigen::Triplet<double>> entries;
    std::vector<double> diagonal(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      for (const auto& [j, area] : now.faces[i]) {
        const double c = 0.25 * area / (points[i] - points[static_cast<std::size_t>(j)]).norm();
        entries.emplace_back(static_cast<int>(i), j, -c);
        entries.emplace_back(j, static_cast<int>(i), -c);
        diagonal[i] += c;
        diagonal[static_cast<std::size_t>(j)] += c;
      }
    }
    double mean = 0.0;
    for (double d : diagonal) mean += d / static_cast<double>(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double d = diagonal[i] > 0.0 ? diagonal[i] : kPi * radius[i];
      entries.emplace_back(static_cast<int>(i), static_cast<int>(i), d + 1e-9 * mean);
    }
    Eigen::SparseMatrix<double> jacobian(static_cast<int>(n), static_cast<int>(n));
    jacobian.setFromTriplets(entries.begin(), entries.end());
    Eigen::VectorXd residual(static_cast<int>(n));
    for (std::size_t i = 0; i < n; ++i) residual[static_cast<int>(i)] = targets[i] - now.volumes[i];
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> solver;
    solver.setTolerance(1e-10);
    solver.compute(jacobian);
    Eigen::VectorXd step = solver.solve(residual);
    if (!step.allFinite()) break;
    // Damped: halve the step until no cell falls below the floor and the residual shrinks.
    double tau = 1.0;
    bool accepted = false;
    for (int halving = 0; halving < 16 && !accepted; ++halving, tau *= 0.5) {
      std::vector<double> trial = fit.weights;
      for (std::size_t i = 0; i < n; ++i) trial[i] += tau * step[static_cast<int>(i)];
      LaguerreApprox next = approx_cells(start, length, points, trial, &now.faces);
      const double r = norm_of(next.volumes);
      const bool above = std::all_of(next.volumes.begin(), next.volumes.end(),
                                     [&](double v) { return v >= floor; });
      if (above && r <= (1.0 - 0.5 * tau) * residual_norm) {
        fit.weights = std::move(trial);
        now = std::move(next);
        residual_norm = r;
        error = max_error(now.volumes, targets);
        accepted = true;
      }
    }
    if (!accepted) break;
  }
  fit.max_relative_error = error;
  return fit;
}

std::vector<double> lognormal_volumes(int n, double spread, std::uint64_t seed, double total) {
  if (n < 1) throw std::invalid_argument("a grain-size distribution needs at least one grain");
  if (!(spread >= 0.0) || !std::isfinite(spread))
    throw std::invalid_argument("the size spread must be >= 0");
  if (!(total > 0.0)) throw std::invalid_argument("the total volume must be positive");
  const double sigma = std::sqrt(std::log1p(spread * spread));
  std::vector<double> volumes;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    // Sizes draw from streams of their own, apart from the points' (stream_for(seed, i)).
    SplitMix64 rng = stream_for(seed ^ 0x6C6F676E6F726D61ull, static_cast<std::uint64_t>(i));
    const double u1 = 1.0 - rng.uniform(), u2 = rng.uniform();  // u1 in (0, 1]
    const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
    const double d = std::exp(sigma * z);  // the mean is set by the scale below
    volumes.push_back(kPi / 6.0 * d * d * d);
    sum += volumes.back();
  }
  for (double& v : volumes) v *= total / sum;
  return volumes;
}

int lognormal_grain_count(double volume, double mean_diameter, double spread) {
  if (!(mean_diameter > 0.0))
    throw std::invalid_argument("the mean grain diameter must be positive");
  const double s2 = std::log1p(spread * spread);
  const double mu = std::log(mean_diameter) - 0.5 * s2;
  const double mean_volume = kPi / 6.0 * std::exp(3.0 * mu + 4.5 * s2);
  const double count = std::round(volume / mean_volume);
  if (!(count < 1e9)) throw std::invalid_argument("the mean grain diameter makes too many grains");
  return std::max(1, static_cast<int>(count));
}

LaguerreTessellation fitted_laguerre(const Eigen::Vector3d& size,
                                     const std::vector<Eigen::Vector3d>& points,
                                     std::vector<double> targets) {
  for (int d = 0; d < 3; ++d) {
    if (!(size[d] > 0.0)) throw std::invalid_argument("Laguerre box sizes must be positive");
  }
  if (targets.size() != points.size()) throw std::invalid_argument("one target volume per point");
  double sum = 0.0;
  for (double t : targets) {
    if (!(t > 0.0)) throw std::invalid_argument("target volumes must be positive");
    sum += t;
  }
  const double box_volume = size.x() * size.y() * size.z();
  for (double& t : targets) t *= box_volume / sum;
  const ExactPolyhedron box = exact_box(Eigen::Vector3d::Zero(), size);
  const PolygonMesh mesh = box.to_mesh();
  LaguerreTessellation out;
  out.points = points;
  out.targets = targets;
  out.fit = fit_laguerre_weights(mesh, points, targets);
  const LaguerreApprox last = laguerre_cells_approx(mesh, points, out.fit.weights);
  out.cells = exact_cells(box, points, out.fit.weights, &last.faces);
  return out;
}

LaguerreTessellation lognormal_laguerre(const Eigen::Vector3d& size, int cells, double spread,
                                        std::uint64_t seed) {
  VoronoiDef def;
  def.size = size;
  def.cells = cells;
  def.seed = seed;
  const double volume = size.x() * size.y() * size.z();
  return fitted_laguerre(size, voronoi_points(def), lognormal_volumes(cells, spread, seed, volume));
}

}  // namespace cleave::geometry
