#include "validation/beam_theory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cleave::physics {

double chi_I(double E, double nu) {
  const double G = E / (2.0 * (1.0 + nu));
  const double gamma = 1.18 * E / G;  // eq. 58
  const double g = gamma / (1.0 + gamma);
  return std::sqrt(E / (11.0 * G) * (3.0 - 2.0 * g * g));  // eq. 57
}

double chi_II(double E, double nu) {
  return 0.42 * chi_I(E, nu);
}

double mmb_lever_arm(double beta, double L) {
  if (!(beta > 0.0 && beta < 1.0)) throw std::domain_error("mmb_lever_arm: beta outside (0, 1)");
  const double q = 2.0 / std::sqrt(3.0) * std::sqrt(beta / (1.0 - beta));
  if (!(3.0 * q - 1.0 > 0.0)) throw std::domain_error("mmb_lever_arm: beta <= 1/13");
  return L * (1.0 + q) / (3.0 * q - 1.0);  // eq. 67
}

MmbLoads mmb_loads(double P, double C, double L) {
  return {(3.0 * C - L) / (4.0 * L) * P, (C + L) / L * P};  // eq. 66
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Derived quantities of one test.
struct Beam {
  BeamTest t;
  double EI = 0;     ///< E I of one arm
  double Bp = 0;     ///< B' = B - 2r
  double hI = 0;     ///< chi_I h
  double hII = 0;    ///< chi_II h
  double alpha = 0;  ///< MMB: P_I / P
  double gamma = 0;  ///< MMB: P_II / P
  double a_end = 0;  ///< largest crack length of the growth branches

  explicit Beam(const BeamTest& test) : t(test) {
    EI = t.E * t.B * t.h * t.h * t.h / 12.0;
    Bp = t.B - 2.0 * t.r;
    hI = chi_I(t.E, t.nu) * t.h;
    hII = chi_II(t.E, t.nu) * t.h;
    if (!(t.E > 0 && t.B > 0 && t.h > 0 && t.L > 0 && t.a0 > 0 && Bp > 0))
      throw std::invalid_argument("BeamTest: non-positive size, modulus or crack front width");
    switch (t.kind) {
      case BeamTestKind::dcb:
        if (!(t.g_Ic > 0)) throw std::invalid_argument("BeamTest: DCB needs g_Ic > 0");
        a_end = t.L;
        break;
      case BeamTestKind::enf:
        if (!(t.g_IIc > 0)) throw std::invalid_argument("BeamTest: ENF needs g_IIc > 0");
        a_end = 2.0 * t.L - hII;  // approached only as the load grows without bound
        break;
      case BeamTestKind::mmb: {
        if (!(t.g_Ic > 0 && t.g_IIc > 0))
          throw std::invalid_argument("BeamTest: MMB needs g_Ic > 0 and g_IIc > 0");
        const MmbLoads unit = mmb_loads(1.0, t.C, t.L);
        alpha = unit.p_I;
        gamma = unit.p_II;
        if (!(alpha > 0)) throw std::invalid_argument("BeamTest: MMB needs C > L/3");
        a_end = 2.0 * t.L - hI;
        if (gamma / 2.0 > alpha)  // the mode-I root moment vanishes at this a_I
          a_end = std::min(a_end, gamma * t.L / 2.0 / (gamma / 2.0 - alpha) - hI);
        break;
      }
    }
    if (!(t.a0 < a_end)) throw std::invalid_argument("BeamTest: a0 past the end of crack growth");
  }

  /// ENF/MMB mode-II lever: a_II before mid-span, 2L - a_II after it.
  [[nodiscard]] double mode2_arm(double a) const {
    const double a2 = a + hII;
    return std::min(a2, 2.0 * t.L - a2);
  }

  /// Compliance Delta / P with the crack held at a.
  [[nodiscard]] double compliance(double a) const {
    const double L = t.L;
    switch (t.kind) {
      case BeamTestKind::dcb: {
        const double a1 = std::min(a, L) + hI;
        return 2.0 * a1 * a1 * a1 / (3.0 * EI);  // eqs 59, 61
      }
      case BeamTestKind::enf: {
        const double a2 = a + hII;
        if (a2 <= L) return (2.0 * L * L * L + 3.0 * a2 * a2 * a2) / (96.0 * EI);  // eq. 63
        const double b = 2.0 * L - a2;
        return (8.0 * L * L * L - 3.0 * b * b * b) / (96.0 * EI);  // eq. 64
      }
      case BeamTestKind::mmb: {
        const double a1 = a + hI;
        const double c = std::max(a1 - L, 0.0);
        return 2.0 * alpha * a1 * a1 * a1 / (3.0 * EI)         // eq. 68
               - gamma * c * c * (2.0 * a1 + L) / (6.0 * EI);  // mid-span load on the arm
      }
    }
    return kNaN;
  }

  /// The load at which a crack of length a grows (G reaches its critical value).
  [[nodiscard]] double critical_load(double a) const {
    switch (t.kind) {
      case BeamTestKind::dcb:
        return std::sqrt(Bp * EI * t.g_Ic) / (a + hI);  // eq. 60
      case BeamTestKind::enf:
        return std::sqrt(64.0 * Bp * EI * t.g_IIc / 3.0) / mode2_arm(a);  // eqs 63-64
      case BeamTestKind::mmb: {
        const double a1 = a + hI;
        const double m = alpha * a1 - 0.5 * gamma * std::max(a1 - t.L, 0.0);  // root moment / P
        const double b = mode2_arm(a);
        // Eq. 69 (and its continuation past mid-span): P^2 F = 1.
        const double F =
            (m * m / t.g_Ic + 3.0 * gamma * gamma * b * b / (64.0 * t.g_IIc)) / (Bp * EI);
        return 1.0 / std::sqrt(F);
      }
    }
    return kNaN;
  }
};

/// One stage of the path: a stationary crack loaded linearly, or a growing crack.
struct Segment {
  int stage = 0;
  bool growing = false;
  double a_lo = 0, a_hi = 0;  ///< crack range (growing) or the crack (a_lo, stationary)
  double p_lo = 0, p_hi = 0;  ///< load range of a stationary crack (p_hi may be +inf)
  bool open_end = false;      ///< growing towards a_hi with unbounded load (ENF stage III)
};

struct State {
  double delta, load, crack;
};

/// Crack length at parameter s in [0, 1] of a growing segment. An open end is approached
/// geometrically in the remaining ligament, down to 1e-12 of it.
double crack_at(const Segment& seg, double s) {
  if (!seg.open_end) return seg.a_lo + s * (seg.a_hi - seg.a_lo);
  return seg.a_hi - (seg.a_hi - seg.a_lo) * std::pow(1e-12, s);
}

State growing_state(const Beam& b, double a) {
  const double P = b.critical_load(a);
  return {P * b.compliance(a), P, a};
}

State state_at(const Beam& b, const Segment& seg, double s) {
  if (seg.growing) return growing_state(b, crack_at(seg, s));
  const double P = seg.p_lo + s * (seg.p_hi - seg.p_lo);
  return {P * b.compliance(seg.a_lo), P, seg.a_lo};
}

constexpr int kGrid = 2048;

/// The smallest s of a growing segment at which Delta reaches `target` (nullopt if it never
/// does): a scan on a fine grid, then bisection in the first cell that reaches it.
std::optional<double> first_reach(const Beam& b, const Segment& seg, double target) {
  if (state_at(b, seg, 0.0).delta >= target) return 0.0;
  double prev = 0.0;
  for (int i = 1; i <= kGrid; ++i) {
    const double s = static_cast<double>(i) / kGrid;
    if (state_at(b, seg, s).delta >= target) {
      double lo = prev, hi = s;
      for (int k = 0; k < 80; ++k) {
        const double mid = 0.5 * (lo + hi);
        (state_at(b, seg, mid).delta >= target ? hi : lo) = mid;
      }
      return hi;
    }
    prev = s;
  }
  return std::nullopt;
}

/// The largest Delta on a segment (+inf for unbounded ones).
double segment_max(const Beam& b, const Segment& seg) {
  if (!seg.growing) return seg.p_hi * b.compliance(seg.a_lo);
  if (seg.open_end) return kInf;
  int best = 0;
  double best_d = -kInf;
  for (int i = 0; i <= kGrid; ++i) {
    const double d = state_at(b, seg, static_cast<double>(i) / kGrid).delta;
    if (d > best_d) best_d = d, best = i;
  }
  if (best == 0 || best == kGrid) return best_d;
  // Interior maximum: golden-section refinement between the neighbouring grid points.
  double lo = static_cast<double>(best - 1) / kGrid, hi = static_cast<double>(best + 1) / kGrid;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int k = 0; k < 60; ++k) {
    const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    if (state_at(b, seg, x1).delta > state_at(b, seg, x2).delta)
      hi = x2;
    else
      lo = x1;
  }
  return std::max(best_d, state_at(b, seg, 0.5 * (lo + hi)).delta);
}

/// The path of a test as its stages, in order (ENF stage IV, a reference line, is not on it).
std::vector<Segment> build_path(const Beam& b) {
  const BeamTest& t = b.t;
  std::vector<Segment> path;
  Segment s1;
  s1.stage = 1;
  s1.a_lo = s1.a_hi = t.a0;
  s1.p_lo = 0.0;
  s1.p_hi = b.critical_load(t.a0);
  path.push_back(s1);
  auto grow = [&](int stage, double lo, double hi, bool open) {
    if (!(hi > lo)) return;
    Segment s;
    s.stage = stage;
    s.growing = true;
    s.a_lo = lo;
    s.a_hi = hi;
    s.open_end = open;
    path.push_back(s);
  };
  switch (t.kind) {
    case BeamTestKind::dcb: {
      grow(2, t.a0, t.L, false);
      Segment s3;
      s3.stage = 3;
      s3.a_lo = s3.a_hi = t.L;
      s3.p_lo = b.critical_load(t.L);
      s3.p_hi = kInf;
      path.push_back(s3);
      break;
    }
    case BeamTestKind::enf: {
      const double mid = t.L - b.hII;  // a_II = L
      grow(2, t.a0, std::min(mid, b.a_end), false);
      grow(3, std::max(t.a0, mid), b.a_end, true);
      break;
    }
    case BeamTestKind::mmb: {
      const double mid = t.L - b.hI;  // a_I = L
      grow(2, t.a0, std::min(mid, b.a_end), false);
      grow(3, std::max(t.a0, mid), b.a_end, false);
      break;
    }
  }
  return path;
}

const Segment* find_stage(const std::vector<Segment>& path, int stage) {
  for (const Segment& s : path)
    if (s.stage == stage) return &s;
  return nullptr;
}

}  // namespace

std::pair<double, double> stage_range(const BeamTest& test, int stage) {
  const Beam b(test);
  const std::vector<Segment> path = build_path(b);
  double running = 0.0;  // the largest Delta reached so far along the path
  for (const Segment& seg : path) {
    const double top = segment_max(b, seg);
    if (seg.stage == stage) {
      if (!(top > running * (1.0 + 1e-12))) return {kNaN, kNaN};  // jumped over
      return {std::max(running, state_at(b, seg, 0.0).delta), top};
    }
    running = std::max(running, top);
  }
  return {kNaN, kNaN};
}

int split_stage(BeamTestKind kind) {
  switch (kind) {
    case BeamTestKind::dcb: return 3;
    case BeamTestKind::enf: return 4;
    case BeamTestKind::mmb: return 0;
  }
  return 0;
}

double split_compliance(const BeamTest& test) {
  const Beam b(test);
  switch (test.kind) {
    case BeamTestKind::dcb: return b.compliance(test.L);  // eq. 61
    case BeamTestKind::enf: return test.L * test.L * test.L / (12.0 * b.EI);  // eq. 65
    case BeamTestKind::mmb: return kNaN;
  }
  return kNaN;
}

double split_crack(const BeamTest& test) {
  switch (test.kind) {
    case BeamTestKind::dcb: return test.L;
    case BeamTestKind::enf: return 2.0 * test.L;
    case BeamTestKind::mmb: return kNaN;
  }
  return kNaN;
}

std::optional<double> analytic_load(const BeamTest& test, int stage, double delta) {
  const auto [lo, hi] = stage_range(test, stage);
  // A stage's ends are computed along different formulas; forgive rounding there.
  const double tol = 1e-12 * std::abs(delta);
  if (std::isnan(lo) || delta < lo - tol || delta > hi + tol) return std::nullopt;
  delta = std::clamp(delta, lo, hi);
  const Beam b(test);
  const std::vector<Segment> path = build_path(b);
  const Segment* seg = find_stage(path, stage);
  if (seg == nullptr) return std::nullopt;
  if (!seg->growing) return delta / b.compliance(seg->a_lo);
  // The first point of the stage at which Delta reaches delta: all earlier points of the path
  // lie below it, so it is the reachable one.
  const std::optional<double> s = first_reach(b, *seg, delta);
  if (!s) return std::nullopt;
  return state_at(b, *seg, *s).load;
}

std::vector<CurvePoint> analytic_curve(const BeamTest& test, double delta_max, int n_per_stage) {
  const Beam b(test);
  const std::vector<Segment> path = build_path(b);
  const int n = std::max(n_per_stage, 2);
  std::vector<CurvePoint> out;
  if (!(delta_max > 0)) return out;
  for (const Segment& seg : path) {
    if (!seg.growing) {
      const double c = b.compliance(seg.a_lo);
      const double p_stop = std::min(seg.p_hi, delta_max / c);
      if (p_stop < seg.p_lo) break;
      for (int i = 0; i < n; ++i) {
        const double P = seg.p_lo + (p_stop - seg.p_lo) * i / (n - 1);
        out.push_back({P * c, P, seg.stage, seg.a_lo});
      }
      if (p_stop < seg.p_hi) break;
      continue;
    }
    const std::optional<double> stop = first_reach(b, seg, delta_max);
    const double a_stop = crack_at(seg, stop.value_or(1.0));
    for (int i = 0; i < n; ++i) {
      const double a = seg.a_lo + (a_stop - seg.a_lo) * i / (n - 1);
      const State st = growing_state(b, a);
      out.push_back({st.delta, st.load, seg.stage, st.crack});
    }
    if (stop) break;
  }
  if (test.kind == BeamTestKind::enf) {  // eq. 65: the split beam, as a reference line
    const double c = split_compliance(test);
    for (int i = 0; i < n; ++i) {
      const double d = delta_max * i / (n - 1);
      out.push_back({d, d / c, 4, split_crack(test)});
    }
  }
  return out;
}

}  // namespace cleave::physics
