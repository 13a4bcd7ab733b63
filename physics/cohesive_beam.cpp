#include "physics/cohesive_beam.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cleave::physics {

double cohesive_beam_spring(const BeamTest& t) {
  const double EI = t.E * t.B * t.h * t.h * t.h / 12.0;
  const double l = chi_I(t.E, t.nu) * t.h;  // eq. 57: the decay length of the foundation
  return 4.0 * EI / (l * l * l * l);
}

namespace {

/// The foundation under one arm, per unit length: the arm's spring k in series with the weak
/// plane's mode-I law (eqs 15, 22-25 with delta_s = 0: a rigid rise to sigma_c, then linear
/// softening to delta_c, unloading to the origin), or the spring alone where there is no plane.
struct Foundation {
  double k = 0;        ///< arm spring (N/m^2)
  double qc = 0;       ///< sigma_c B' (N/m)
  double dc = 0;       ///< opening at decohesion, 2 G_Ic / sigma_c (m)

  struct Response {
    double q;      ///< traction per unit length pulling the arm back (N/m)
    double dq_dw;  ///< its tangent
    double open;   ///< the plane's opening delta (both arms)
  };

  /// Traction at deflection w of the arm, given the largest opening so far (eq. 21).
  [[nodiscard]] Response at(double w, double open_max, bool weak) const {
    if (w <= 0.0 || !weak) return {k * w, k, 0.0};  // closed: the faces bear on each other
    if (open_max >= dc) return {0.0, 0.0, 2.0 * w};  // decohered (eq. 16)
    if (open_max > 0.0) {
      // Unloading and reloading along the secant to the origin (eqs 23-25).
      const double secant = qc * (1.0 - open_max / dc) / open_max;
      const double c = 1.0 / k + 0.5 / secant;
      const double q = w / c;
      if (q / secant <= open_max) return {q, 1.0 / c, q / secant};
    } else if (k * w <= qc) {
      return {k * w, k, 0.0};  // the connective stage: the material alone
    }
    // Softening (eq. 15): w = q/k + delta/2 with q = qc (1 - delta/dc).
    const double c = 1.0 / k - 0.5 * dc / qc;  // negative: checked at construction
    const double q = (w - 0.5 * dc) / c;
    if (q <= 0.0) return {0.0, 0.0, 2.0 * w};
    return {q, 1.0 / c, dc * (1.0 - q / qc)};
  }
};

constexpr std::array<double, 4> kGaussX = {0.0694318442029737, 0.3300094782075719,
                                           0.6699905217924281, 0.9305681557970263};
constexpr std::array<double, 4> kGaussW = {0.1739274225687269, 0.3260725774312731,
                                           0.3260725774312731, 0.1739274225687269};

/// Hermite cubic shape functions of a beam element of length e at xi in [0, 1].
std::array<double, 4> hermite(double xi, double e) {
  const double x2 = xi * xi, x3 = x2 * xi;
  return {1.0 - 3.0 * x2 + 2.0 * x3, e * (xi - 2.0 * x2 + x3), 3.0 * x2 - 2.0 * x3,
          e * (x3 - x2)};
}

/// A symmetric matrix of half bandwidth 3 (a Hermite beam's two dofs per node), factorised
/// as L D L^T without pivoting: the tangent of a stable equilibrium under displacement control
/// is positive definite, and a zero or negative pivot is reported (the caller then takes a
/// smaller increment).
class BandMatrix {
 public:
  static constexpr int kBand = 3;

  void reset(int n) {
    n_ = n;
    a_.assign(static_cast<size_t>(n) * (kBand + 1), 0.0);
  }
  /// Adds v to A(i, j) for j >= i, j - i <= kBand.
  void add(int i, int j, double v) { a_[static_cast<size_t>(i) * (kBand + 1) + (j - i)] += v; }
  /// Makes row and column d the identity's.
  void fix(int d) {
    for (int k = 0; k <= kBand; ++k) {
      if (d + k < n_) a_[static_cast<size_t>(d) * (kBand + 1) + k] = 0.0;
      if (d - k >= 0 && k > 0) a_[static_cast<size_t>(d - k) * (kBand + 1) + k] = 0.0;
    }
    a_[static_cast<size_t>(d) * (kBand + 1)] = 1.0;
  }

  /// Solves A x = b in place; false if a pivot is not positive.
  bool solve(std::vector<double>& b) {
    std::vector<double> d(n_), l(static_cast<size_t>(n_) * (kBand + 1), 0.0);
    auto A = [&](int i, int j) { return a_[static_cast<size_t>(i) * (kBand + 1) + (j - i)]; };
    auto Lm = [&](int j, int m) -> double& { return l[static_cast<size_t>(j) * (kBand + 1) + m]; };
    for (int i = 0; i < n_; ++i) {
      double di = A(i, i);
      for (int m = 1; m <= kBand && i - m >= 0; ++m) di -= Lm(i, m) * Lm(i, m) * d[i - m];
      if (!(di > 0.0)) return false;
      d[i] = di;
      for (int j = i + 1; j <= i + kBand && j < n_; ++j) {
        double v = A(i, j);
        // L(j, k) L(i, k) d_k over the k that both rows reach.
        for (int k = std::max(0, j - kBand); k < i; ++k) v -= Lm(j, j - k) * Lm(i, i - k) * d[k];
        Lm(j, j - i) = v / di;
      }
    }
    for (int j = 0; j < n_; ++j)
      for (int m = 1; m <= kBand && j - m >= 0; ++m) b[j] -= Lm(j, m) * b[j - m];
    for (int j = 0; j < n_; ++j) b[j] /= d[j];
    for (int j = n_ - 1; j >= 0; --j)
      for (int m = 1; m <= kBand && j + m < n_; ++m) b[j] -= Lm(j + m, m) * b[j + m];
    return true;
  }

 private:
  int n_ = 0;
  std::vector<double> a_;
};

struct GaussPoint {
  int element;
  std::array<double, 4> N;
  double weight;  ///< quadrature weight times element length (m)
  double x;
  bool weak;        ///< on the weak plane (else the intact beam)
  double open_max = 0;
};

class Solver {
 public:
  Solver(const BeamTest& t, double sigma_c, double intact, const CohesiveBeamOptions& o) {
    EI_ = t.E * t.B * t.h * t.h * t.h / 12.0;
    f_.k = cohesive_beam_spring(t);
    f_.qc = sigma_c * (t.B - 2.0 * t.r);
    f_.dc = 2.0 * t.g_Ic / sigma_c;
    if (!(1.0 / f_.k - 0.5 * f_.dc / f_.qc < 0.0))
      throw std::invalid_argument(
          "cohesive_dcb_curve: the softening branch is steeper than the arm's spring "
          "(sigma_c^2 > G_Ic k / B')");
    const double e = o.element > 0 ? o.element : t.h / 40.0;
    // Nodes on 0, a0, L and L + intact, evenly spaced in between.
    x_.push_back(0.0);
    const std::array<double, 3> ends = {t.a0, t.L, t.L + intact};
    for (double end : ends) {
      const double from = x_.back();
      if (end <= from) continue;
      const int n = std::max(1, static_cast<int>(std::ceil((end - from) / e - 1e-9)));
      for (int i = 1; i <= n; ++i) x_.push_back(from + (end - from) * i / n);
    }
    const int elements = static_cast<int>(x_.size()) - 1;
    for (int el = 0; el < elements; ++el) {
      const double len = x_[el + 1] - x_[el];
      const double mid = 0.5 * (x_[el] + x_[el + 1]);
      if (mid < t.a0) continue;  // the cracked arm: no foundation
      for (int g = 0; g < 4; ++g)
        gauss_.push_back({el, hermite(kGaussX[g], len), kGaussW[g] * len,
                          x_[el] + kGaussX[g] * len, mid < t.L, 0.0});
    }
    dofs_ = 2 * static_cast<int>(x_.size());
    u_.assign(dofs_, 0.0);
    trial_ = u_;
    residual_.assign(dofs_, 0.0);
    open_.assign(gauss_.size(), 0.0);
    a0_ = t.a0;
  }

  /// Moves the load line to w0 and returns whether Newton's method converged; the history is
  /// left untouched (commit() takes it).
  bool solve(double w0) {
    std::vector<double> u = u_;
    u[0] = w0;
    for (int it = 0; it < 60; ++it) {
      assemble(u);
      std::vector<double> du(dofs_);
      for (int d = 0; d < dofs_; ++d) du[d] = -residual_[d];
      for (int d : fixed()) du[d] = 0.0;
      if (!tangent_.solve(du)) return false;
      for (int d = 0; d < dofs_; ++d) u[d] += du[d];
      // Converged when the step moved no deflection by more than 1e-7 of the load line's.
      double moved = 0;
      for (int d = 0; d < dofs_; d += 2) moved = std::max(moved, std::abs(du[d]));
      if (moved <= 1e-7 * std::max(std::abs(w0), 1e-15)) {
        assemble(u);
        trial_ = u;
        return true;
      }
    }
    return false;
  }

  /// Accepts the last converged state: openings become history (eq. 21).
  void commit() {
    u_ = trial_;
    for (size_t g = 0; g < gauss_.size(); ++g)
      gauss_[g].open_max = std::max(gauss_[g].open_max, open_[g]);
  }

  [[nodiscard]] CohesiveBeamPoint point() const {
    CohesiveBeamPoint p{2.0 * u_[0], residual_[0], -u_[1], a0_, a0_};
    for (const GaussPoint& g : gauss_) {
      if (!g.weak) continue;
      if (g.open_max >= f_.dc) p.crack = std::max(p.crack, g.x);
      if (g.open_max > 0.0) p.process_zone = std::max(p.process_zone, g.x);
    }
    return p;
  }

 private:
  [[nodiscard]] std::array<int, 3> fixed() const { return {0, dofs_ - 2, dofs_ - 1}; }

  /// Residual (internal forces; at dof 0 the load line's reaction) and tangent at u, with the
  /// prescribed and clamped rows and columns made the identity's.
  void assemble(const std::vector<double>& u) {
    residual_.assign(dofs_, 0.0);
    tangent_.reset(dofs_);
    const int elements = static_cast<int>(x_.size()) - 1;
    for (int el = 0; el < elements; ++el) {
      const double e = x_[el + 1] - x_[el];
      const double c = EI_ / (e * e * e);
      const double K[4][4] = {{12 * c, 6 * e * c, -12 * c, 6 * e * c},
                              {6 * e * c, 4 * e * e * c, -6 * e * c, 2 * e * e * c},
                              {-12 * c, -6 * e * c, 12 * c, -6 * e * c},
                              {6 * e * c, 2 * e * e * c, -6 * e * c, 4 * e * e * c}};
      const int d0 = 2 * el;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          residual_[d0 + i] += K[i][j] * u[d0 + j];
          if (j >= i) tangent_.add(d0 + i, d0 + j, K[i][j]);
        }
    }
    for (size_t gi = 0; gi < gauss_.size(); ++gi) {
      const GaussPoint& g = gauss_[gi];
      const int d0 = 2 * g.element;
      double w = 0;
      for (int i = 0; i < 4; ++i) w += g.N[i] * u[d0 + i];
      const Foundation::Response r = f_.at(w, g.open_max, g.weak);
      open_[gi] = r.open;
      for (int i = 0; i < 4; ++i) {
        residual_[d0 + i] += g.weight * r.q * g.N[i];
        for (int j = i; j < 4; ++j)
          tangent_.add(d0 + i, d0 + j, g.weight * r.dq_dw * g.N[i] * g.N[j]);
      }
    }
    for (int d : fixed()) tangent_.fix(d);
  }

  double EI_ = 0, a0_ = 0;
  Foundation f_;
  std::vector<double> x_;
  std::vector<GaussPoint> gauss_;
  std::vector<double> open_;
  int dofs_ = 0;
  std::vector<double> u_, trial_, residual_;
  BandMatrix tangent_;
};

}  // namespace

double cohesive_load(const std::vector<CohesiveBeamPoint>& curve, double delta) {
  if (curve.size() < 2 || !(delta >= curve.front().delta) || !(delta <= curve.back().delta))
    return std::numeric_limits<double>::quiet_NaN();
  auto hi = std::lower_bound(curve.begin(), curve.end(), delta,
                             [](const CohesiveBeamPoint& p, double d) { return p.delta < d; });
  if (hi == curve.begin()) return hi->load;
  auto lo = hi - 1;
  const double t = (delta - lo->delta) / (hi->delta - lo->delta);
  return lo->load + t * (hi->load - lo->load);
}

std::vector<CohesiveBeamPoint> cohesive_dcb_curve(const BeamTest& test, double sigma_c,
                                                  double intact_length, double delta_max,
                                                  const CohesiveBeamOptions& options) {
  if (test.kind != BeamTestKind::dcb)
    throw std::invalid_argument("cohesive_dcb_curve: the cohesive beam is the DCB's");
  if (!(sigma_c > 0) || !(delta_max > 0) || !(intact_length >= 0) || options.steps < 1)
    throw std::invalid_argument("cohesive_dcb_curve: sigma_c, delta_max and steps must be > 0");
  Solver solver(test, sigma_c, intact_length, options);
  std::vector<CohesiveBeamPoint> curve;
  curve.push_back(solver.point());
  double w = 0;
  const double dw = 0.5 * delta_max / options.steps;
  for (int s = 1; s <= options.steps; ++s) {
    // An increment that does not converge is taken in halves, down to 1/1024 of it.
    const double target = 0.5 * delta_max * s / options.steps;
    double step = dw;
    while (w < target * (1.0 - 1e-14)) {
      const double next = std::min(target, w + step);
      if (solver.solve(next)) {
        solver.commit();
        w = next;
      } else {
        step *= 0.5;
        if (step < dw / 1024.0)
          throw std::runtime_error("cohesive_dcb_curve: Newton's method did not converge");
      }
    }
    curve.push_back(solver.point());
  }
  return curve;
}

}  // namespace cleave::physics
