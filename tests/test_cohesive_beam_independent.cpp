// An independent check of the cohesive DCB of validation/cohesive_beam.hpp (cohesive_dcb_curve):
// the same physical model solved a second time, here, by a different method that shares no code
// with validation/cohesive_beam.cpp. That file discretises the arm with Hermite cubic finite
// elements and integrates the foundation at Gauss points; this one writes the arm's equation
// EI w'''' + q(w) = 0 in central finite differences on a uniform grid and lumps the foundation
// at the grid's nodes (each node carries the plane's law over its own tributary length, with
// its own damage history). Both are followed quasi-statically under displacement control with
// Newton's method. The two discretisations converge to the same continuum from different
// directions, so their agreement over the whole load-deflection curve checks the code under
// test, and the finite differences are themselves checked against closed forms (Hetenyi's
// beam on an elastic foundation before the zone opens, Rice's J-integral and eq. 60 while the
// crack grows), so that a wrong finite-difference solver fails on its own.
//
// The model (validation/cohesive_beam.hpp): one arm of the DCB of Chen et al. 2020 (seed 002,
// sec. 7.1), an Euler-Bernoulli beam of EI = E B h^3 / 12, from the load line x = 0 (its
// end pulled to w(0) = Delta / 2, moment free) to a clamp at x = L + intact_length. It has no
// support on the notch 0 <= x < a0; on the weak plane a0 <= x <= L it rests on a Winkler spring
// k = 4 EI / (chi_I h)^4 per unit length in series with the mode-I linear-softening cohesive
// law of strength q_c = sigma_c B' per unit length (B' = B - 2r); past L on the spring alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "validation/beam_theory.hpp"
#include "validation/cohesive_beam.hpp"

using namespace cleave::physics;

namespace {

// --- Inputs: the DCB of scenarios/validation/dcb.toml and tests/test_cohesive_beam.cpp -------

constexpr double kGIc = 260.0;            ///< G_Ic (N/m): 0.26 N/mm (sec. 7)
constexpr double kIntactLength = 3e-3;    ///< dcb.toml: 3 mm of intact beam before the clamp
constexpr double kDeltaMax = 4e-3;        ///< dcb.toml: 4 mm of opening, past the crack's run
constexpr int kSteps = 800;               ///< load steps of 5 micrometres of opening
constexpr int kCellsPerH = 80;            ///< finite-difference grid: dx = h / 80 = 12.5 um

/// The paper's DCB (sec. 7.1): E = 120 GPa, nu = 0.2, B = 2 mm, h = 1 mm (2h = 2 mm),
/// L = 30 mm, a0 = 9 mm, r = 0.125 mm, G_Ic = 0.26 N/mm (G_IIc unused by the DCB).
BeamTest dcb(double g_Ic = kGIc) {
  return {BeamTestKind::dcb, 120e9, 0.2, 2e-3, 1e-3, 30e-3, 9e-3, 0.125e-3, g_Ic, 1002.0};
}

/// EI of one arm: E times I = B h^3 / 12 (sec. 7.1, text under eq. 56).
double bending_stiffness(const BeamTest& t) { return t.E * t.B * t.h * t.h * t.h / 12.0; }

/// The decay length of the arm's foundation, lambda = chi_I h (eq. 57, with eq. 58's Gamma;
/// chi_I from beam_theory.hpp): the model's spring is k = 4 EI / lambda^4, so that Winkler's
/// decay length (4 EI / k)^(1/4) (Hetenyi 1946, ch. 2) is this effective-length correction.
double decay_length(const BeamTest& t) { return chi_I(t.E, t.nu) * t.h; }

// --- The foundation: the arm's spring in series with the weak plane's law --------------------

/// What one unit length of foundation does to the arm: the arm's spring k in series with the
/// plane's mode-I cohesive law (eqs 15-16 and 21-25 of Chen et al. with delta_s = 0 and
/// lambda_cr = 0, i.e. no compliance before the strength: rigid up to the strength, then linear softening to zero at
/// delta_c, unloading and reloading along the secant to the origin with the damage of the
/// largest opening so far). The plane opens by delta and each arm sees half of it, so at
/// traction q (N/m) the arm's deflection is w = q / k + delta / 2.
struct ArmFoundation {
  double k = 0;    ///< the arm's spring per unit length (N/m^2)
  double q_c = 0;  ///< the plane's strength per unit length, sigma_c B' (N/m)
  double d_c = 0;  ///< the opening at decohesion (m)

  /// Which linear piece of the law a point is on (the law is piecewise linear in w, so Newton's
  /// method is exact once no point changes piece).
  enum class Piece { spring, rigid, secant, softening, decohered };

  struct Reaction {
    double q;        ///< traction pulling the arm back (N/m)
    double dq_dw;    ///< its slope
    double opening;  ///< the plane's opening delta (m)
    Piece piece;
  };

  /// The traction at deflection w given the largest opening the point has had (eq. 21's history).
  [[nodiscard]] Reaction on_plane(double w, double largest) const {
    /// Faces pushed together (w <= 0 on this arm, the other arm mirrors it): no opening, they bear
    /// on each other and only the arm's spring deforms (the law acts on the opening's positive
    /// part, eq. 14's Macaulay bracket, with a stiff penalty in compression: here rigid).
    if (w <= 0.0) return {k * w, k, 0.0, Piece::spring};
    /// Decohered (eq. 16, lambda = 1): no traction; the arm's end of the plane moves freely.
    if (largest >= d_c) return {0.0, 0.0, 2.0 * w, Piece::decohered};
    if (largest > 0.0) {
      /// Damaged: below the largest opening the plane is a linear spring along the secant to the
      /// origin (eqs 22-25: T = sigma_c (1 - d) r, d the damage of the largest opening, eq. 22,
      /// r = lambda / lambda_max the loading ratio, eq. 23; with lambda_cr = 0, d = lambda_max).
      /// Its stiffness per unit length is the softening traction at the largest opening over it.
      const double secant = q_c * (1.0 - largest / d_c) / largest;
      /// Spring k and secant plane in series: w = q / k + (q / secant) / 2.
      const double compliance = 1.0 / k + 0.5 / secant;
      const double q = w / compliance;
      if (q / secant <= largest) return {q, 1.0 / compliance, q / secant, Piece::secant};
    } else if (k * w <= q_c) {
      /// Undamaged and below the strength: the plane is rigid, only the spring deforms.
      return {k * w, k, 0.0, Piece::rigid};
    }
    /// On the softening line q = q_c (1 - delta / d_c) (eq. 15 with lambda_cr = 0): with
    /// w = q / k + delta / 2, delta = (w - q_c / k) / (1/2 - q_c / (k d_c)).
    const double denominator = 0.5 - q_c / (k * d_c);  // > 0: checked by the caller
    const double opening = (w - q_c / k) / denominator;
    if (opening >= d_c) return {0.0, 0.0, 2.0 * w, Piece::decohered};
    return {q_c * (1.0 - opening / d_c), -q_c / (d_c * denominator), opening, Piece::softening};
  }
};

// --- A banded linear solver with partial pivoting --------------------------------------------

/// Gaussian elimination with partial pivoting for a matrix with at most two nonzeros on either
/// side of its diagonal (banded LU with row interchanges: Golub & Van Loan, Matrix
/// Computations, 4th ed., sec. 4.3.5; the interchanges widen the upper band to four). The
/// finite-difference tangent need not be positive definite on the way to a solution (Newton's
/// trial states cross the softening branch), so no Cholesky here. Row i keeps columns
/// i-2 .. i+4.
class BandedSystem {
 public:
  void reset(int n) {
    n_ = n;
    a_.assign(static_cast<size_t>(n) * kWidth, 0.0);
  }
  /// Adds v to A(i, j), |i - j| <= 2.
  void add(int i, int j, double v) { a_[slot(i, j)] += v; }

  /// Solves A x = b in place (b becomes x); false if A is singular. Overwrites A.
  bool solve(std::vector<double>& b) {
    for (int k = 0; k < n_; ++k) {
      const int last = std::min(n_ - 1, k + 2);
      const int right = std::min(n_ - 1, k + 4);
      int p = k;
      for (int i = k + 1; i <= last; ++i)
        if (std::abs(get(i, k)) > std::abs(get(p, k))) p = i;
      if (get(p, k) == 0.0) return false;
      if (p != k) {
        // Rows k and p (<= k + 2) are both zero left of column k and end by column k + 4.
        for (int j = k; j <= right; ++j) std::swap(a_[slot(k, j)], a_[slot(p, j)]);
        std::swap(b[k], b[p]);
      }
      for (int i = k + 1; i <= last; ++i) {
        const double f = get(i, k) / get(k, k);
        if (f == 0.0) continue;
        for (int j = k; j <= right; ++j) a_[slot(i, j)] -= f * get(k, j);
        b[i] -= f * b[k];
      }
    }
    for (int k = n_ - 1; k >= 0; --k) {
      double v = b[k];
      for (int j = k + 1; j <= std::min(n_ - 1, k + 4); ++j) v -= get(k, j) * b[j];
      b[k] = v / get(k, k);
    }
    return true;
  }

 private:
  static constexpr int kWidth = 7;
  [[nodiscard]] size_t slot(int i, int j) const {
    return static_cast<size_t>(i) * kWidth + static_cast<size_t>(j - i + 2);
  }
  [[nodiscard]] double get(int i, int j) const {
    return (j < i - 2 || j > i + 4) ? 0.0 : a_[slot(i, j)];
  }
  int n_ = 0;
  std::vector<double> a_;
};

// --- The finite-difference arm ----------------------------------------------------------------

/// One converged state of the finite-difference arm.
struct FdPoint {
  double delta;     ///< opening at the load line, 2 w(0) (m)
  double load;      ///< end load P on the arm (N)
  double rotation;  ///< -w'(0) (rad)
  double crack;     ///< the end of the decohered plane, contiguous from a0 (m)
  double zone_tip;  ///< the farthest node of the plane that has opened at all (m)
};

/// One DCB arm in central finite differences on a uniform grid x_i = i dx, i = 0 .. N (x_N the
/// clamp), written as two second-order equations so that round-off grows as N^2 rather than N^4
/// (the four-point biharmonic stencil's condition number): with m = dx^2 w'' = dx^2 M / EI,
///   curvature:   w_{i-1} - 2 w_i + w_{i+1} - m_i = 0,                      i = 1 .. N,
///   equilibrium: m_{i-1} - 2 m_i + m_{i+1} + (dx^3 / EI) F_i(w_i) = 0,     i = 1 .. N-1,
/// from M = EI w'' and M'' = -q (EI w'''' + q = 0; eliminating m gives the usual
/// w_{i-2} - 4 w_{i-1} + 6 w_i - 4 w_{i+1} + w_{i+2} = -dx^3 F_i / EI). F_i is the foundation
/// force on node i: the trapezoidal rule over its tributary length (half a cell where the
/// plane or the spring begins or ends). Boundary conditions: w_0 = Delta / 2 prescribed and
/// m_0 = 0 (no moment at the load line); w_N = 0 and w'_N = 0 (the clamp: the ghost node
/// w_{N+1} = w_{N-1} in the curvature at N). The load is the shear at the load line,
/// P = M'(0) = EI m_1 / dx^3 (the notch carries no foundation, so M = P x there exactly).
class FiniteDifferenceArm {
 public:
  FiniteDifferenceArm(const BeamTest& t, double sigma_c, double intact_length, int cells_per_h)
      : dx_(t.h / cells_per_h), EI_(bending_stiffness(t)), a0_(t.a0) {
    const double lambda = decay_length(t);
    /// The model's spring k = 4 EI / (chi_I h)^4 (validation/cohesive_beam.hpp, after
    /// Kanninen's augmented DCB, Int. J. Fract. 9, 1973, with eq. 57's decay length).
    law_.k = 4.0 * EI_ / (lambda * lambda * lambda * lambda);
    /// Strength over the crack front width B' = B - 2r (sec. 7, text after eq. 49).
    law_.q_c = sigma_c * (t.B - 2.0 * t.r);
    /// Eq. 18 for the linear softening triangle: G_Ic = sigma_c delta_c / 2.
    law_.d_c = 2.0 * t.g_Ic / sigma_c;
    /// The softening line must be less steep than the spring (1/2 - q_c / (k d_c) > 0, i.e.
    /// sigma_c^2 < G_Ic k / B'), else a point would snap back on its own.
    if (!(0.5 - law_.q_c / (law_.k * law_.d_c) > 0.0))
      throw std::invalid_argument("softening steeper than the arm's spring");
    auto node = [&](double x) {
      const double n = x / dx_;
      if (std::abs(n - std::round(n)) > 1e-6) throw std::invalid_argument("x off the grid");
      return static_cast<int>(std::lround(n));
    };
    i_a0_ = node(t.a0);
    i_L_ = node(t.L);
    n_ = node(t.L + intact_length);
    plane_.assign(n_ + 1, 0.0);
    spring_.assign(n_ + 1, 0.0);
    for (int i = i_a0_; i <= i_L_; ++i) plane_[i] = (i == i_a0_ || i == i_L_) ? 0.5 * dx_ : dx_;
    for (int i = i_L_; i < n_; ++i) spring_[i] = (i == i_L_) ? 0.5 * dx_ : dx_;
    w_.assign(n_ + 1, 0.0);
    m_.assign(n_ + 1, 0.0);
    largest_.assign(n_ + 1, 0.0);
  }

  /// Newton's method for the state with w_0 = w0 from the last accepted one (the history
  /// held fixed). The foundation is piecewise linear in w, so a Newton step that leaves every
  /// node on the piece it was linearised on has solved the equations exactly: that is the
  /// convergence test. False if it has not settled after 100 iterations.
  bool pull_to(double w0) {
    std::vector<double> w = w_, m = m_;
    if (w_[0] > 0.0) {  // the last state scaled: exact while nothing changes piece
      const double scale = w0 / w_[0];
      for (int i = 0; i <= n_; ++i) {
        w[i] *= scale;
        m[i] *= scale;
      }
    }
    w[0] = w0;
    std::vector<ArmFoundation::Piece> used, now;
    std::vector<double> step;
    for (int it = 0; it < 100; ++it) {
      assemble(w, m, step, now);
      if (it > 0 && now == used) {
        trial_w_ = w;
        trial_m_ = m;
        return true;
      }
      used = now;
      if (!system_.solve(step)) return false;
      for (int i = 1; i < n_; ++i) {
        w[i] += step[w_dof(i)];
        m[i] += step[m_dof(i)];
      }
      m[n_] += step[m_dof(n_)];
      if (!std::isfinite(w[1]) || !std::isfinite(m[1])) return false;
    }
    return false;
  }

  /// Accepts the last solved state: the openings become history (eq. 21: the largest so far).
  void accept() {
    w_ = trial_w_;
    m_ = trial_m_;
    for (int i = i_a0_; i <= i_L_; ++i)
      largest_[i] = std::max(largest_[i], law_.on_plane(w_[i], largest_[i]).opening);
  }

  [[nodiscard]] FdPoint point() const {
    FdPoint p{2.0 * w_[0], EI_ * m_[1] / (dx_ * dx_ * dx_), 0.0, a0_, a0_};
    /// In the notch w is the cubic w_0 + w'(0) x + P x^3 / (6 EI) (w''(0) = 0, EI w''' = P),
    /// and central differences are exact for cubics, so w'(0) follows from w_0 and w_1.
    p.rotation = -((w_[1] - w_[0]) / dx_ - p.load * dx_ * dx_ / (6.0 * EI_));
    for (int i = i_a0_; i <= i_L_ && largest_[i] >= law_.d_c; ++i) p.crack = i * dx_;
    for (int i = i_a0_; i <= i_L_; ++i)
      if (largest_[i] > 0.0) p.zone_tip = i * dx_;
    return p;
  }

 private:
  // Unknowns and equations interleaved node by node (w_i, m_i), i = 1 .. N-1, then m_N; the
  // curvature at i has w_i's row, the equilibrium at i m_i's: a band of two either side.
  [[nodiscard]] int w_dof(int i) const { return 2 * (i - 1); }
  [[nodiscard]] int m_dof(int i) const { return i < n_ ? 2 * (i - 1) + 1 : 2 * n_ - 2; }

  /// The tangent into system_, minus the residual into rhs, each node's piece into pieces.
  void assemble(const std::vector<double>& w, const std::vector<double>& m,
                std::vector<double>& rhs, std::vector<ArmFoundation::Piece>& pieces) {
    const int dofs = 2 * n_ - 1;
    system_.reset(dofs);
    rhs.assign(dofs, 0.0);
    pieces.assign(n_ + 1, ArmFoundation::Piece::spring);
    const double s = dx_ * dx_ * dx_ / EI_;
    for (int i = 1; i < n_; ++i) {
      /// Curvature at i, w_{i-1} - 2 w_i + w_{i+1} = m_i (w_N = 0 at the clamp).
      const int c = w_dof(i);
      rhs[c] = -(w[i - 1] - 2.0 * w[i] + w[i + 1] - m[i]);
      if (i > 1) system_.add(c, w_dof(i - 1), 1.0);
      system_.add(c, w_dof(i), -2.0);
      if (i + 1 < n_) system_.add(c, w_dof(i + 1), 1.0);
      system_.add(c, m_dof(i), -1.0);
      /// Equilibrium at i, m_{i-1} - 2 m_i + m_{i+1} = -dx^3 F_i / EI (m_0 = 0 at the load line).
      double force = spring_[i] * law_.k * w[i], slope = spring_[i] * law_.k;
      if (plane_[i] > 0.0) {
        const ArmFoundation::Reaction r = law_.on_plane(w[i], largest_[i]);
        force += plane_[i] * r.q;
        slope += plane_[i] * r.dq_dw;
        pieces[i] = r.piece;
      }
      const int e = m_dof(i);
      rhs[e] = -(m[i - 1] - 2.0 * m[i] + m[i + 1] + s * force);
      if (i > 1) system_.add(e, m_dof(i - 1), 1.0);
      system_.add(e, m_dof(i), -2.0);
      system_.add(e, m_dof(i + 1), 1.0);
      system_.add(e, w_dof(i), s * slope);
    }
    /// Curvature at the clamp with the ghost node: 2 w_{N-1} - m_N = 0.
    const int c = m_dof(n_);
    rhs[c] = -(2.0 * w[n_ - 1] - m[n_]);
    system_.add(c, w_dof(n_ - 1), 2.0);
    system_.add(c, m_dof(n_), -1.0);
  }

  double dx_, EI_, a0_;
  ArmFoundation law_;
  int i_a0_ = 0, i_L_ = 0, n_ = 0;
  std::vector<double> plane_, spring_;  ///< tributary lengths of plane and spring (m)
  std::vector<double> w_, m_, trial_w_, trial_m_;
  std::vector<double> largest_;  ///< the plane's largest opening so far at each node (m)
  BandedSystem system_;
};

/// The finite-difference arm pulled through the given openings Delta (increasing), one point
/// each. An increment whose Newton iteration does not settle is taken in halves, down to
/// 1/1024 of it; throws std::runtime_error below that.
std::vector<FdPoint> fd_dcb_curve(const BeamTest& t, double sigma_c,
                                  const std::vector<double>& deltas,
                                  int cells_per_h = kCellsPerH) {
  FiniteDifferenceArm arm(t, sigma_c, kIntactLength, cells_per_h);
  std::vector<FdPoint> curve;
  double w = 0.0;
  for (double delta : deltas) {
    const double target = 0.5 * delta;
    const double increment = target - w;
    double step = increment;
    while (w < target) {
      const double next = std::min(target, w + step);
      if (arm.pull_to(next)) {
        arm.accept();
        w = next;
      } else if ((step *= 0.5) < increment / 1024.0) {
        throw std::runtime_error("finite-difference arm: Newton's method did not settle");
      }
    }
    curve.push_back(arm.point());
  }
  return curve;
}

std::vector<double> openings_of(const std::vector<CohesiveBeamPoint>& curve) {
  std::vector<double> d;
  for (const CohesiveBeamPoint& p : curve) d.push_back(p.delta);
  return d;
}

/// Both solutions of one case at the same openings: the finite differences are pulled through
/// exactly the openings of the finite-element curve's points, so loads compare without
/// interpolation (cohesive_load at a curve's own point is that point's load).
struct Comparison {
  std::vector<CohesiveBeamPoint> fe;
  std::vector<FdPoint> fd;
};

Comparison compare(const BeamTest& fe_test, const BeamTest& fd_test, double sigma_c, int steps,
                   int cells_per_h) {
  Comparison c;
  c.fe = cohesive_dcb_curve(fe_test, sigma_c, kIntactLength, kDeltaMax, {0, steps});
  c.fd = fd_dcb_curve(fd_test, sigma_c, openings_of(c.fe), cells_per_h);
  return c;
}

/// The plane (sigma_c = 70 MPa, dcb.toml): Hillerborg's length E G_Ic / sigma_c^2 =
/// 6.4 mm, a long cohesive zone. dx = h / 80: the largest difference from the finite elements
/// is 2.7e-4 at h / 40, 9e-5 at h / 80, 5e-5 at h / 160, 4e-5 at h / 320, and halving the
/// increments leaves it unchanged.
const Comparison& weak_plane() {
  static const Comparison c = compare(dcb(), dcb(), 70e6, kSteps, kCellsPerH);
  return c;
}

/// A strong plane, sigma_c = 180 MPa (E G_Ic / sigma_c^2 = 0.96 mm, about h: near LEFM). Not
/// 200 MPa: cohesive_dcb_curve throws there (its Newton iteration stops converging during crack
/// growth, near Delta = 1.56 mm; from 190 MPa on). 350 MPa is past the law's limit
/// sigma_c^2 < G_Ic k / B' (262 MPa). The zone is 0.2 mm long, so the lumped foundation needs
/// a fine grid: at h / 80 and h / 160 the crack's advance from node to node nearly snaps (the
/// Newton iteration needs many halved increments), at h / 320 it runs smoothly. 400 steps of
/// 10 um keep the run short (halving them leaves the largest difference unchanged; at h / 80
/// and h / 160 it is 3e-4 and 2e-4).
const Comparison& strong_plane() {
  static const Comparison c = compare(dcb(), dcb(), 180e6, 400, 320);
  return c;
}

/// The largest |P_fd / P_fe - 1| over every point but the origin (0 / 0 there: both loads
/// are exactly zero), with an EXPECT for each point against `bound`.
double largest_difference(const Comparison& c, double bound, const char* label, double* where) {
  EXPECT_EQ(c.fe.size(), c.fd.size());
  double worst = 0.0;
  for (size_t i = 1; i < std::min(c.fe.size(), c.fd.size()); ++i) {
    EXPECT_EQ(c.fd[i].delta, c.fe[i].delta);
    const double fe_load = cohesive_load(c.fe, c.fd[i].delta);
    const double d = std::abs(c.fd[i].load / fe_load - 1.0);
    EXPECT_LT(d, bound) << label << ": Delta = " << c.fd[i].delta << " m, P_fd = " << c.fd[i].load
                        << " N, P_fe = " << fe_load << " N";
    if (!(d <= worst)) {  // NaN counts as the worst
      worst = d;
      *where = c.fd[i].delta;
    }
  }
  return worst;
}

/// The whole curve is in the comparison: stage I (the plane not yet open), the peak, crack
/// growth along the plane, and the tail where the zone has reached the plane's end at L and
/// the load is back on eq. 61's line (the last ligament keeps some traction: the arm past L is
/// clamped on its spring, so the plane's last point opens only slowly).
void expect_whole_curve(const Comparison& c, const BeamTest& t) {
  const auto& fe = c.fe;
  size_t peak = 0;
  int stage_one = 0, growing = 0, tail = 0;
  for (size_t i = 1; i < fe.size(); ++i) {
    if (fe[i].load > fe[peak].load) peak = i;
    if (fe[i].process_zone == t.a0) ++stage_one;
    if (c.fd[i].crack > t.a0 + 1e-3 && c.fd[i].zone_tip < t.L - 1e-3) ++growing;
    if (c.fd[i].zone_tip > t.L - 1e-9) ++tail;  // the plane's last node has opened
  }
  EXPECT_GE(stage_one, 10);
  EXPECT_GT(peak, 10u);
  EXPECT_LT(fe.back().load, 0.5 * fe[peak].load);
  EXPECT_GT(growing, 100);
  EXPECT_GT(tail, 20);
  EXPECT_GT(c.fd.back().crack, t.L - 1e-3);
  /// Eq. 61, Delta = 2 P (L + chi_I h)^3 / (3 EI) (the split arms): the tail's load within 1 %
  /// (measured: 0.65 % above at 70 MPa, where the last ligament still holds, 0.01 % at 180 MPa).
  const double a = t.L + decay_length(t);
  const double eq61 = fe.back().delta * 3.0 * bending_stiffness(t) / (2.0 * a * a * a);
  EXPECT_NEAR(c.fd.back().load / eq61, 1.0, 0.01);
}

/// Decohered length from the two discretisations (nodes 12.5 or 3.1 um apart here, Gauss
/// points of 25 um elements there): within 0.025 mm at every point (measured: 0.011 mm).
void expect_same_crack(const Comparison& c) {
  for (size_t i = 0; i < std::min(c.fe.size(), c.fd.size()); ++i)
    EXPECT_NEAR(c.fd[i].crack, c.fe[i].crack, 2.5e-5) << "Delta = " << c.fe[i].delta;
}

/// Openings 0, Delta_max / steps, ..., Delta_max.
std::vector<double> uniform_openings(int steps) {
  std::vector<double> d;
  for (int s = 0; s <= steps; ++s) d.push_back(kDeltaMax * s / steps);
  return d;
}

}  // namespace

namespace {

/// The two solutions within 1 % at every point, over every part of the curve, with the crack
/// in the same place; prints and returns the largest difference.
double agreement(const Comparison& c, const char* label) {
  double where = 0.0;
  const double worst = largest_difference(c, 0.01, label, &where);
  expect_whole_curve(c, dcb());
  expect_same_crack(c);
  std::printf("[ measured ] %s: largest |P_fd / P_fe - 1| = %.3g at Delta = %.4g mm\n", label,
              worst, where * 1e3);
  return worst;
}

}  // namespace

TEST(IndependentFiniteDifferenceBeam, AgreesWithTheCohesiveDcbWithin1PercentOverTheWholeCurve) {
  EXPECT_LT(agreement(weak_plane(), "sigma_c = 70 MPa"), 0.01);
}

TEST(IndependentFiniteDifferenceBeam, AgreesWithTheCohesiveDcbWithin1PercentForAStrongPlane) {
  EXPECT_LT(agreement(strong_plane(), "sigma_c = 180 MPa"), 0.01);
}

TEST(IndependentFiniteDifferenceBeam, BeforeTheZoneOpensItIsHetenyisCantileverOnAnElasticFoundation) {
  /// The finite differences on their own against a closed form. Until the plane's first point
  /// reaches sigma_c the arm is a cantilever of length a0 whose root rests on an elastic
  /// foundation k = 4 EI / lambda^4 (lambda = chi_I h). Hetenyi (Beams on Elastic Foundation,
  /// 1946, sec. 2, the semi-infinite beam loaded at its end by a force P and a moment M):
  ///   w(a0) = (2 / (k lambda)) (P + M / lambda),  w'(a0) = -(2 / (k lambda^2)) (P + 2 M / lambda)
  /// with M = P a0, plus the free arm's own bending P a0^3 / (3 EI) and the root's turn times
  /// a0, so that with k lambda^4 = 4 EI
  ///   w(0) = P / (3 EI) (a0^3 + 3 a0^2 lambda + 3 a0 lambda^2 + 3 lambda^3 / 2),
  ///   -w'(0) = P (a0 + lambda)^2 / (2 EI).
  /// The foundation runs 24 mm = 37 lambda to the clamp: semi-infinite to e^-37.
  const BeamTest t = dcb();
  const double EI = bending_stiffness(t), a = t.a0, l = decay_length(t);
  const double compliance = 2.0 / (3.0 * EI) * (a * a * a + 3 * a * a * l + 3 * a * l * l + 1.5 * l * l * l);
  std::vector<double> deltas;
  for (int s = 1; s <= 10; ++s) deltas.push_back(0.005e-3 * s);  // to 0.05 mm: the plane
                                                                  // opens near 0.1 mm
  const auto curve = fd_dcb_curve(t, 70e6, deltas);
  for (const FdPoint& p : curve) {
    EXPECT_EQ(p.zone_tip, t.a0);
    EXPECT_NEAR(p.delta / p.load / compliance, 1.0, 1e-4) << "Delta = " << p.delta;
    EXPECT_NEAR(p.rotation / (p.load * (a + l) * (a + l) / (2.0 * EI)), 1.0, 1e-4);
  }
  // A cantilever clamped at a0 (no foundation) would be far off.
  EXPECT_GT(std::abs(2.0 * a * a * a / (3.0 * EI) / compliance - 1.0), 0.1);
}

TEST(IndependentFiniteDifferenceBeam, WhileTheCrackGrowsTheJIntegralIsTheFractureEnergyAndTheLoadIsEq60s) {
  /// The finite differences on their own. Rice's J-integral (J. Appl. Mech. 35, 1968) on the arm:
  /// for EI w'''' + q(w) = 0 with every point loaded monotonically, EI w' w''' - EI w''^2 / 2 +
  /// Phi(w) is constant along the arm (Phi: the work done on the foundation per unit length),
  /// except that Phi steps from 0 to G_Ic B' / 2 where the decohered plane begins (each arm
  /// does half of the plane's G_Ic B' of work; the spring gives its energy back). At the load
  /// line it is -P theta0, far ahead of the zone 0, so 2 P theta0 = G_Ic B' while the crack
  /// runs with its zone well inside the plane. And with the crack there, LEFM's eq. 60 holds:
  /// P a_I = sqrt(B' E I G_Ic) with a_I from the compliance of eq. 59, Delta = 2 P a_I^3 / (3 EI),
  /// up to the zone's length against the arm (measured: 3e-4 at 70 MPa, 6e-5 at 180 MPa;
  /// checked to 0.5 %; the J-integral, 1e-4 and 3e-5, to 0.1 %).
  const BeamTest t = dcb();
  const double EI = bending_stiffness(t), Bp = t.B - 2.0 * t.r;
  // The two cases' grids and steps (their comments above), without the finite elements.
  for (const auto& [sigma_c, steps, cells_per_h] : {std::tuple{70e6, kSteps, kCellsPerH},
                                                     std::tuple{180e6, 400, 320}}) {
    int growing = 0;
    for (const FdPoint& p : fd_dcb_curve(t, sigma_c, uniform_openings(steps), cells_per_h)) {
      if (p.crack < t.a0 + 2e-3 || p.zone_tip > t.L - 2e-3) continue;
      ++growing;
      EXPECT_NEAR(2.0 * p.load * p.rotation / (kGIc * Bp), 1.0, 1e-3)
          << "sigma_c = " << sigma_c << ", Delta = " << p.delta;
      const double a_I = std::cbrt(3.0 * EI * p.delta / (2.0 * p.load));
      EXPECT_NEAR(p.load * a_I / std::sqrt(Bp * EI * kGIc), 1.0, 5e-3)
          << "sigma_c = " << sigma_c << ", Delta = " << p.delta;
    }
    EXPECT_GT(growing, 100) << "sigma_c = " << sigma_c;
  }
}

TEST(IndependentFiniteDifferenceBeam, WouldSeeAThreePercentErrorInTheFractureEnergy) {
  /// The comparison can fail: the finite differences with G_Ic 3 % high (stage II's load goes
  /// as sqrt(G_Ic), +1.5 %) against the code under test with the right G_Ic differ by more than
  /// the 1 % bound somewhere (measured: 2.3 %, at Delta = 1.1 mm).
  const std::vector<CohesiveBeamPoint>& fe = weak_plane().fe;
  const auto fd = fd_dcb_curve(dcb(1.03 * kGIc), 70e6, openings_of(fe));
  double worst = 0.0;
  for (size_t i = 1; i < fe.size(); ++i) worst = std::max(worst, std::abs(fd[i].load / fe[i].load - 1.0));
  EXPECT_GT(worst, 0.01);
}
