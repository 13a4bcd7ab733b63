#include "validation/beam_test_rig.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cleave::physics {

namespace {

constexpr unsigned kX = 1u, kY = 2u, kZ = 4u, kAll = 7u;

/// Cells of side 2r across `extent`; the extent must be a whole number of them.
int cells(double extent, double radius, const char* what) {
  const double count = extent / (2.0 * radius);
  const long n = std::lround(count);
  if (n < 1 || std::abs(count - static_cast<double>(n)) > 1e-6 * count)
    throw std::invalid_argument(std::string("beam test: the ") + what +
                                " must be a whole number of particle diameters 2r");
  return static_cast<int>(n);
}

}  // namespace

CubicLatticeDef beam_lattice(const BeamRigDef& def) {
  CubicLatticeDef ld;
  ld.radius = def.radius;
  ld.nx = cells(def.length, def.radius, "length");
  if (def.intact_length > 0.0) {
    if (def.kind != BeamTestKind::dcb)
      throw std::invalid_argument("beam test: only a DCB has an intact length beyond the weak plane");
    // The weak plane's last column is centred at x = length - r; the links across the plane
    // beyond it are bulk.
    ld.weak_end_x = def.length - def.radius;
    ld.nx += cells(def.intact_length, def.radius, "intact length");
  }
  ld.ny = cells(def.breadth, def.radius, "breadth");
  ld.nz = cells(def.height, def.radius, "height");
  if (ld.nz % 2 != 0)
    throw std::invalid_argument("beam test: the height must hold an even number of layers");
  if (def.kind != BeamTestKind::dcb && ld.nx % 2 == 0)
    throw std::invalid_argument(
        "beam test: ENF and MMB need an odd number of cells along the length (a mid-span line)");
  ld.material = def.material;
  ld.weak_layer = ld.nz / 2;
  // The load line (DCB, MMB) or support (ENF) is the first column, centred at x = r.
  ld.notch_x = def.radius + def.initial_crack;
  ld.global_damping = def.global_damping;
  ld.link_bending = def.link_bending;
  ld.tiled_areas = def.tiled_areas;
  return ld;
}

BeamTest beam_analytic(const BeamRigDef& def) {
  const CubicLatticeDef ld = beam_lattice(def);
  const double r = def.radius;
  BeamTest t;
  t.kind = def.kind;
  t.E = def.material.young;
  t.nu = def.material.poisson;
  t.B = def.breadth;
  t.h = 0.5 * def.height;
  t.a0 = def.initial_crack;
  t.r = r;
  t.g_Ic = def.g_Ic;
  t.g_IIc = def.g_IIc;
  if (def.kind == BeamTestKind::dcb) {
    // Load line to the weak plane's last column (the clamp when there is no intact part).
    t.L = 2.0 * r * (cells(def.length, r, "length") - 1);
  } else {
    t.L = 2.0 * r * ((ld.nx - 1) / 2);  // support to mid-span
    if (def.kind == BeamTestKind::mmb) t.C = mmb_lever_arm(def.mode_mix, t.L);
  }
  return t;
}

BeamTestRig::BeamTestRig(const BeamRigDef& def)
    : def_(def), lattice_(beam_lattice(def)), analytic_(beam_analytic(def)) {
  const CubicLatticeDef& ld = lattice_.def();
  dt_ = def.dt_safety * lattice_.critical_time_step();
  x_origin_ = def.radius;
  const int top = ld.nz - 1, mid = (ld.nx - 1) / 2, last = ld.nx - 1;
  switch (def.kind) {
    case BeamTestKind::dcb: {
      top_ = line(0, top);
      bottom_ = line(0, 0);
      for (int b : top_) lattice_.prescribe(b, kZ);
      for (int b : bottom_) lattice_.prescribe(b, kZ);
      for (int iz = 0; iz < ld.nz; ++iz)
        for (int b : line(last, iz)) lattice_.prescribe(b, kAll);
      break;
    }
    case BeamTestKind::enf:
    case BeamTestKind::mmb: {
      // Supports and load lines hold the beam sideways (y) as the fixture's rollers do by
      // friction: once the crack faces slide on each other without friction, nothing else
      // keeps the upper beam from walking off the lower one sideways.
      for (int b : line(0, 0)) lattice_.prescribe(b, kX | kY | kZ);
      for (int b : line(last, 0)) lattice_.prescribe(b, kY | kZ);
      if (def.kind == BeamTestKind::enf) {
        top_ = line(mid, top);
        for (int b : top_) lattice_.prescribe(b, kY | kZ);
      } else {
        end_ = line(0, top);
        mid_ = line(mid, top);
        for (int b : end_) lattice_.prescribe(b, kY | kZ);
        for (int b : mid_) lattice_.prescribe(b, kY | kZ);
        lever_span_ = analytic_.L;
        const double arm_end = analytic_.C + analytic_.L, arm_mid = analytic_.C;
        lever_inertia_ = lattice_.mass() * (static_cast<double>(end_.size()) * arm_end * arm_end +
                                            static_cast<double>(mid_.size()) * arm_mid * arm_mid);
      }
      break;
    }
  }
  top_z0_ = mean_z(top_);
  bottom_z0_ = mean_z(bottom_);
  end_z0_ = mean_z(end_);
}

std::vector<int> BeamTestRig::line(int ix, int iz) const {
  std::vector<int> out;
  for (int iy = 0; iy < lattice_.def().ny; ++iy) out.push_back(lattice_.index(ix, iy, iz));
  return out;
}

/// Eq. 56: v = v0 t / t0 for t < t0, then v0.
double BeamTestRig::ramp(double t) const {
  if (def_.ramp_time > 0.0 && t < def_.ramp_time) return def_.velocity * t / def_.ramp_time;
  return def_.velocity;
}

double BeamTestRig::sum_fz(const std::vector<int>& bodies) const {
  double s = 0.0;
  for (int b : bodies) s += lattice_.forces()[b].z();
  return s;
}

double BeamTestRig::mean_z(const std::vector<int>& bodies) const {
  if (bodies.empty()) return 0.0;
  double s = 0.0;
  for (int b : bodies) s += lattice_.positions()[b].z();
  return s / static_cast<double>(bodies.size());
}

void BeamTestRig::step() {
  const double v = ramp(time_ + 0.5 * dt_);
  switch (def_.kind) {
    case BeamTestKind::dcb:
      for (int b : top_) lattice_.set_velocity(b, 2, v);
      for (int b : bottom_) lattice_.set_velocity(b, 2, -v);
      break;
    case BeamTestKind::enf:
      for (int b : top_) lattice_.set_velocity(b, 2, -v);
      break;
    case BeamTestKind::mmb: {
      // The lever turns about its load point (which moves down at v): the generalised force
      // of the tied bodies' reactions on its rotation, with the same damping as the bodies.
      const double arm_end = analytic_.C + lever_span_, arm_mid = analytic_.C;
      const double q = -arm_end * sum_fz(end_) - arm_mid * sum_fz(mid_);
      const double c = def_.global_damping * dt_;
      lever_rate_ = ((1.0 - 0.5 * c) * lever_rate_ + dt_ * q / lever_inertia_) / (1.0 + 0.5 * c);
      for (int b : end_) lattice_.set_velocity(b, 2, -v - lever_rate_ * arm_end);
      for (int b : mid_) lattice_.set_velocity(b, 2, -v - lever_rate_ * arm_mid);
      break;
    }
  }
  lattice_.step(dt_);
  ++step_;
  time_ += dt_;
  load_impulse_ += instant_load() * dt_;
  delta_integral_ += instant_delta() * dt_;
  load_window_ += dt_;
}

double BeamTestRig::instant_delta() const {
  switch (def_.kind) {
    case BeamTestKind::dcb: return (mean_z(top_) - mean_z(bottom_)) - (top_z0_ - bottom_z0_);
    case BeamTestKind::enf: return top_z0_ - mean_z(top_);
    case BeamTestKind::mmb: return mean_z(end_) - end_z0_;
  }
  return 0.0;
}

double BeamTestRig::instant_load() const {
  switch (def_.kind) {
    case BeamTestKind::dcb: return 0.5 * (sum_fz(bottom_) - sum_fz(top_));
    case BeamTestKind::enf: return sum_fz(top_);
    case BeamTestKind::mmb: return sum_fz(end_) + sum_fz(mid_);
  }
  return 0.0;
}

BeamReading BeamTestRig::reading() const {
  BeamReading r;
  r.step = step_;
  r.time = time_;
  r.load_instant = instant_load();
  r.delta_instant = instant_delta();
  const bool window = load_window_ > 0.0;
  r.load = window ? load_impulse_ / load_window_ : r.load_instant;
  r.delta = window ? delta_integral_ / load_window_ : r.delta_instant;
  r.crack = lattice_.crack_front_x(true) - x_origin_;
  r.process_zone = lattice_.crack_front_x(false) - x_origin_;
  r.kinetic = lattice_.energy().kinetic;
  r.external_work = lattice_.external_work();
  return r;
}

StageErrors compare_with_closed_form(const BeamTest& test, const std::vector<BeamReading>& curve, int stage,
                                     double margin) {
  StageErrors e;
  e.stage = stage;
  if (stage == split_stage(test.kind)) {
    const double c = split_compliance(test), full = split_crack(test) - test.h;
    double sum = 0.0, sxx = 0.0, sxy = 0.0;
    e.from = std::numeric_limits<double>::infinity();
    e.to = 0.0;
    for (const auto& r : curve) {
      if (r.crack < full || !(r.delta > 0.0)) continue;
      const double expected = r.delta / c;
      const double err = std::abs(r.load - expected) / expected;
      sum += err;
      e.max_error = std::max(e.max_error, err);
      e.from = std::min(e.from, r.delta);
      e.to = std::max(e.to, r.delta);
      sxx += r.delta * r.delta, sxy += r.delta * r.load;
      ++e.points;
    }
    if (e.points == 0) {
      e.from = e.to = std::numeric_limits<double>::quiet_NaN();
      return e;
    }
    e.mean_error = sum / e.points;
    // The line of the stage passes through the origin (eqs 61, 65): fit it so.
    e.slope = sxy / sxx;
    e.slope_error = std::abs(e.slope * c - 1.0);
    return e;
  }
  auto [lo, hi] = stage_range(test, stage);
  const double from = lo + margin * (std::isfinite(hi) ? hi - lo : lo);
  const double to = std::isfinite(hi) ? hi - margin * (hi - lo) : hi;
  e.from = from;
  e.to = to;
  double sum = 0.0;
  for (const auto& r : curve) {
    if (r.delta < from || r.delta > to) continue;
    const auto expected = analytic_load(test, stage, r.delta);
    if (!expected || *expected <= 0.0) continue;
    const double err = std::abs(r.load - *expected) / *expected;
    sum += err;
    e.max_error = std::max(e.max_error, err);
    ++e.points;
  }
  if (e.points > 0) e.mean_error = sum / e.points;
  return e;
}

}  // namespace cleave::physics
