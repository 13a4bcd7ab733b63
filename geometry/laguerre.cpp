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

/// The neighbours a cell is cut by: the points, and along periodic axes their images one box
/// over. Neighbour k is point k % n moved by shifts[k / n] (shifts[0] = 0).
struct Neighbours {
  std::size_t n = 0;
  std::vector<Eigen::Vector3d> shifts;
  std::vector<Eigen::Vector3d> at;  ///< at[k] = points[k % n] + shifts[k / n], rounded
};

Neighbours neighbours_of(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& size,
                         const std::array<bool, 3>& periodic) {
  Neighbours out;
  out.n = points.size();
  out.shifts.push_back(Eigen::Vector3d::Zero());
  for (int x = -1; x <= 1; ++x) {
    for (int y = -1; y <= 1; ++y) {
      for (int z = -1; z <= 1; ++z) {
        const Eigen::Vector3i k(x, y, z);
        bool skip = k.isZero();
        for (int d = 0; d < 3; ++d)
          skip = skip || (k[d] != 0 && !periodic[static_cast<std::size_t>(d)]);
        if (!skip) out.shifts.push_back(size.cwiseProduct(k.cast<double>()));
      }
    }
  }
  for (const auto& s : out.shifts) {
    for (const auto& p : points) out.at.push_back(p + s);
  }
  return out;
}

Neighbours plain_neighbours(const std::vector<Eigen::Vector3d>& points) {
  return neighbours_of(points, Eigen::Vector3d::Ones(), {false, false, false});
}

/// Per cell, its neighbours ordered by their bisector's offset (nearest plane first).
std::vector<int> by_offset(const Neighbours& nb, const std::vector<double>& weights,
                           std::size_t i) {
  std::vector<int> order;
  std::vector<double> t(nb.at.size());
  for (std::size_t k = 0; k < nb.at.size(); ++k) {
    if (k == i) continue;
    t[k] = bisector_offset(nb.at[i], weights[i], nb.at[k], weights[k % nb.n]);
    order.push_back(static_cast<int>(k));
  }
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return t[a] != t[b] ? t[a] < t[b] : a < b; });
  return order;
}

using Hints = std::vector<std::vector<std::pair<int, double>>>;

LaguerreApprox approx_cells(const Poly& domain, double length, const Neighbours& nb,
                            const std::vector<double>& weights, const Hints* hints) {
  const std::size_t n = nb.n, m = nb.at.size();
  LaguerreApprox out;
  out.volumes.assign(n, 0.0);
  out.faces.assign(n, {});
  std::vector<char> done(m, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = nb.at[i];
    Poly cell = domain;
    double reach = reach_of(vertices_of(cell), p);
    std::fill(done.begin(), done.end(), 0);
    done[i] = 1;
    bool alive = true;
    auto cut = [&](int k) {
      done[static_cast<std::size_t>(k)] = 1;
      const Eigen::Vector3d& q = nb.at[static_cast<std::size_t>(k)];
      const double wq = weights[static_cast<std::size_t>(k) % n];
      if (q == p)
        throw std::invalid_argument("Laguerre points " + std::to_string(i) + " and " +
                                    std::to_string(static_cast<std::size_t>(k) % n) + " coincide");
      const double t = bisector_offset(p, weights[i], q, wq);
      if (t > reach * (1.0 + 1e-9)) return false;
      const Eigen::Vector3d a = 2.0 * (p - q);
      const double d = q.squaredNorm() - p.squaredNorm() - wq + weights[i];
      alive = clip(cell, a, d, k, 1e-12 * a.norm() * length);
      if (alive) reach = reach_of(vertices_of(cell), p);
      return true;
    };
    if (hints != nullptr) {
      for (const auto& [k, area] : (*hints)[i]) {
        if (alive) cut(k);
      }
      // The rest in index order: cheap to skip once the cell is small.
      for (std::size_t k = 0; k < m && alive; ++k) {
        if (!done[k]) cut(static_cast<int>(k));
      }
    } else {
      for (int k : by_offset(nb, weights, i)) {
        if (!alive) break;
        if (!cut(k)) break;  // offsets only grow from here on: no later plane reaches the cell
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
  return approx_cells(poly_of(domain), domain_length(domain), plain_neighbours(points), weights,
                      nullptr);
}

namespace {
std::vector<ExactPolyhedron> exact_cells(const ExactPolyhedron& domain,
                                         const std::vector<Eigen::Vector3d>& points,
                                         const Neighbours& nb, const std::vector<double>& weights,
                                         const Hints* hints, double gap) {
  check_input(points, weights);
  if (!(gap >= 0.0)) throw std::invalid_argument("the Laguerre gap must not be negative");
  const std::size_t n = nb.n, m = nb.at.size();
  std::vector<ExactPolyhedron> cells;
  cells.reserve(n);
  std::vector<char> done(m, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = points[i];
    ExactPolyhedron cell = domain;
    double reach = reach_of(cell.vertices_approx(), p);
    std::fill(done.begin(), done.end(), 0);
    done[i] = 1;
    // Returns false when the plane lies beyond the cell's farthest vertex (no cut).
    auto cut = [&](std::size_t k) {
      done[k] = 1;
      const std::size_t j = k % n;
      const Eigen::Vector3d& q = nb.at[k];
      if (q == p) {
        throw std::invalid_argument("Laguerre points " + std::to_string(std::min(i, j)) + " and " +
                                    std::to_string(std::max(i, j)) + " coincide");
      }
      const double t = bisector_offset(p, weights[i], q, weights[j]) - 0.5 * gap;
      if (t > reach * (1.0 + 1e-9)) return false;
      // The image's position summed exactly: bisectors of images match their translates.
      // With a gap the bisector moves gap/2 towards p, its offset rounded, then taken
      // exactly: (p - q) . x >= (|p|^2 - |q|^2 + w_q - w_p) / 2 + gap |p - q| / 2.
      std::optional<ExactPolyhedron> kept = cell.clipped(
          gap == 0.0
              ? ExactPlane::power_bisector(p, weights[i], points[j], weights[j], nb.shifts[k / n])
              : ExactPlane::from_normal_offset(
                    p - q, 0.5 * (p.squaredNorm() - q.squaredNorm() + weights[j] - weights[i]) +
                               0.5 * gap * (p - q).norm()));
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
      for (const auto& [k, area] : (*hints)[i]) cut(static_cast<std::size_t>(k));
    }
    for (int k : by_offset(nb, weights, i)) {
      if (done[static_cast<std::size_t>(k)]) continue;
      if (!cut(static_cast<std::size_t>(k))) break;  // later offsets are larger still
    }
    cells.push_back(std::move(cell));
  }
  return cells;
}

/// The box a cell starts from: [0, size], widened by a box each way along periodic axes (a
/// periodic cell reaches across a face, no farther).
ExactPolyhedron start_box(const Eigen::Vector3d& size, const std::array<bool, 3>& periodic) {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = size;
  for (int d = 0; d < 3; ++d) {
    if (!periodic[static_cast<std::size_t>(d)]) continue;
    lo[d] = -size[d];
    hi[d] = 2.0 * size[d];
  }
  return exact_box(lo, hi);
}

LaguerreFit fit_weights(const Poly& start, double length, const Neighbours& nb,
                        const std::vector<double>& targets, double tolerance, int max_iterations);
}  // namespace

std::vector<ExactPolyhedron> laguerre_cells(const ExactPolyhedron& domain,
                                            const std::vector<Eigen::Vector3d>& points,
                                            const std::vector<double>& weights, double gap) {
  return exact_cells(domain, points, plain_neighbours(points), weights, nullptr, gap);
}

std::vector<ExactPolyhedron> laguerre_box_cells(const Eigen::Vector3d& size,
                                                const std::array<bool, 3>& periodic,
                                                const std::vector<Eigen::Vector3d>& points,
                                                const std::vector<double>& weights, double gap) {
  for (int d = 0; d < 3; ++d) {
    if (!(size[d] > 0.0)) throw std::invalid_argument("Laguerre box sizes must be positive");
  }
  return exact_cells(start_box(size, periodic), points, neighbours_of(points, size, periodic),
                     weights, nullptr, gap);
}

LaguerreFit fit_laguerre_weights(const PolygonMesh& domain,
                                 const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<double>& targets, double tolerance,
                                 int max_iterations) {
  return fit_weights(poly_of(domain), domain_length(domain), plain_neighbours(points), targets,
                     tolerance, max_iterations);
}

namespace {
LaguerreFit fit_weights(const Poly& start, double length, const Neighbours& nb,
                        const std::vector<double>& targets, double tolerance, int max_iterations) {
  const std::size_t n = nb.n;
  const std::vector<Eigen::Vector3d> points(nb.at.begin(), nb.at.begin() + static_cast<long>(n));
  if (targets.size() != n)
    throw std::invalid_argument("fit_laguerre_weights: one target volume per point");
  for (double t : targets) {
    if (!(t > 0.0))
      throw std::invalid_argument("fit_laguerre_weights: target volumes must be positive");
  }
  LaguerreFit fit;
  // Zero weights (the Voronoi cells) leave no cell empty: every point lies in its own.
  fit.weights.assign(n, 0.0);
  std::vector<double> radius(n);
  for (std::size_t i = 0; i < n; ++i) radius[i] = std::cbrt(3.0 * targets[i] / (4.0 * kPi));
  check_input(points, fit.weights);
  LaguerreApprox now = approx_cells(start, length, nb, fit.weights, nullptr);
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
      for (const auto& [k, area] : now.faces[i]) {
        const std::size_t j = static_cast<std::size_t>(k) % n;
        if (j == i) continue;  // a periodic cell against its own image: no change between them
        const double c = 0.25 * area / (points[i] - nb.at[static_cast<std::size_t>(k)]).norm();
        entries.emplace_back(static_cast<int>(i), static_cast<int>(j), -c);
        entries.emplace_back(static_cast<int>(j), static_cast<int>(i), -c);
        diagonal[i] += c;
        diagonal[j] += c;
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
      LaguerreApprox next = approx_cells(start, length, nb, trial, &now.faces);
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
}  // namespace

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

namespace {
/// Targets scaled to `volume`, weights fitted in `start`, the exact cells built once.
LaguerreTessellation fitted_in(const ExactPolyhedron& start, double volume,
                               const std::vector<Eigen::Vector3d>& points,
                               std::vector<double> targets, const Neighbours& nb, double gap) {
  if (targets.size() != points.size()) throw std::invalid_argument("one target volume per point");
  if (points.empty())
    throw std::invalid_argument("a Laguerre tessellation needs at least one point");
  double sum = 0.0;
  for (double t : targets) {
    if (!(t > 0.0)) throw std::invalid_argument("target volumes must be positive");
    sum += t;
  }
  for (double& t : targets) t *= volume / sum;
  const PolygonMesh mesh = start.to_mesh();
  const Poly poly = poly_of(mesh);
  const double length = domain_length(mesh);
  LaguerreTessellation out;
  out.points = points;
  out.targets = targets;
  out.fit = fit_weights(poly, length, nb, targets, 1e-3, 60);
  const LaguerreApprox last = approx_cells(poly, length, nb, out.fit.weights, nullptr);
  out.cells = exact_cells(start, points, nb, out.fit.weights, &last.faces, gap);
  return out;
}
}  // namespace

LaguerreTessellation fitted_laguerre(const Eigen::Vector3d& size,
                                     const std::vector<Eigen::Vector3d>& points,
                                     std::vector<double> targets,
                                     const std::array<bool, 3>& periodic, double gap) {
  for (int d = 0; d < 3; ++d) {
    if (!(size[d] > 0.0)) throw std::invalid_argument("Laguerre box sizes must be positive");
  }
  return fitted_in(start_box(size, periodic), size.x() * size.y() * size.z(), points,
                   std::move(targets), neighbours_of(points, size, periodic), gap);
}

LaguerreTessellation fitted_laguerre(const ExactPolyhedron& domain,
                                     const std::vector<Eigen::Vector3d>& points,
                                     std::vector<double> targets, double gap) {
  return fitted_in(domain, domain.volume().to_double(), points, std::move(targets),
                   plain_neighbours(points), gap);
}

LaguerreTessellation lognormal_laguerre(const Eigen::Vector3d& size, int cells, double spread,
                                        std::uint64_t seed, const std::array<bool, 3>& periodic,
                                        double gap) {
  VoronoiDef def;
  def.size = size;
  def.cells = cells;
  def.seed = seed;
  def.periodic = periodic;
  def.size_spread = spread;
  def.gap = gap;
  return lognormal_laguerre(def);
}

LaguerreTessellation lognormal_laguerre(const VoronoiDef& def) {
  const std::vector<Eigen::Vector3d> points = voronoi_points(def);
  if (def.domain == VoronoiDomain::box) {
    const double volume = def.size.x() * def.size.y() * def.size.z();
    return fitted_laguerre(def.size, points,
                           lognormal_volumes(def.cells, def.size_spread, def.seed, volume),
                           def.periodic, def.gap);
  }
  const ExactPolyhedron domain = voronoi_domain(def);
  return fitted_laguerre(
      domain, points,
      lognormal_volumes(def.cells, def.size_spread, def.seed, domain.volume().to_double()),
      def.gap);
}

}  // namespace cleave::geometry
