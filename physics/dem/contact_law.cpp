#include "physics/dem/contact_law.hpp"
#include "physics/bonds/lanes.hpp"
#include "physics/bonds/tangent.hpp"

#include <algorithm>
#include <cmath>

namespace cleave::physics {

ContactDamping contact_damping(const ContactParams& p, double m_crit, double i_crit) {
  ContactDamping d;
  d.cn = p.damping_ratio * std::sqrt(p.c_res * p.kn * m_crit);
  d.cs = p.damping_ratio * std::sqrt(p.ks * m_crit);
  d.cr = p.damping_ratio * std::sqrt(p.kr * i_crit);
  d.ct = p.damping_ratio * std::sqrt(p.kt * i_crit);
  d.unload = 1.0 - 1.0 / p.c_res;
  return d;
}

ContactForce contact_force(const ContactParams& p, const ContactKinematics& k,
                           ContactHistory& h, double dt) {
  return contact_force(p, k, contact_damping(p, k.m_crit, k.i_crit), h, dt);
}

ContactForce contact_force(const ContactParams& p, const ContactKinematics& k, const ContactDamping& d,
                           ContactHistory& h, double dt) {
  // Plain doubles (vec3.hpp): Eigen's bits, without its stalls on three-element vectors.
  const V3 n = v3(k.normal), v = v3(k.velocity);
  const double delta = std::max(0.0, k.overlap);

  // Normal spring with the unloading multiplier (eq 2.4 and the C_res of table 2.3).
  h.max_overlap = std::max(h.max_overlap, delta);
  const double loading = p.kn * delta;
  const double unloading = p.c_res * p.kn * (delta - h.max_overlap * d.unload);
  const double fn_spring = std::max(0.0, std::min(loading, unloading));

  // Normal damping (eq 2.6): |U_n| / dt is the normal relative speed.
  const double vn = dot(v, n);
  const double fn = std::max(0.0, fn_spring - d.cn * vn);
  V3 force = fn * n;

  // Shear spring, incremental (eq 2.4): U_s = dt * v_t; Coulomb cap (eq 2.5).
  const V3 vt = v - vn * n;
  V3 shear = into_plane(v3(h.shear), n) - p.ks * dt * vt;
  const double cap = p.mu_s * fn;
  ContactForce out;
  // Sliding when |shear| >= cap; a shear surely below it needs no square root.
  double fs = 0.0;
  if (!surely_shorter(shear, cap)) fs = norm(shear);
  if (fs >= cap && fs > 0.0) {
    shear = shear * (cap / fs);
    out.sliding = true;
    force = force + shear;
  } else {
    force = force + (shear - d.cs * vt);  // shear damping (eq 2.6)
  }
  h.shear = eigen(shear);
  out.force = eigen(force);

  // Rolling and torsional resistance (eqs 2.7, 2.8), capped by mu_r F_n lever (eq 2.5).
  if (p.kr > 0.0 || p.kt > 0.0) {
    const V3 spin = v3(k.spin);
    const double wt = dot(spin, n);
    const V3 wr = spin - wt * n;
    const double mcap = p.mu_r * fn * k.lever;
    V3 rolling = into_plane(v3(h.rolling), n) - p.kr * dt * wr;
    if (!surely_shorter(rolling, mcap)) {
      const double rl = norm(rolling);
      if (rl > mcap) rolling = rolling * (mcap / rl);
    }
    h.rolling = eigen(rolling);
    h.torsion -= p.kt * dt * wt;
    h.torsion = std::clamp(h.torsion, -mcap, mcap);
    out.moment = eigen((rolling - d.cr * wr) + (h.torsion - d.ct * wt) * n);
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// contact_force_quad: the law above for four contacts in AVX's lanes.

namespace {

using namespace wide;

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"

/// The vectors (*in[i]).*field in lanes i.
template <class T>
CLEAVE_LANES Wide<D4> gather(const T* const in[4], Eigen::Vector3d T::*field) {
  return {lanes<D4>([&](int i) { return ((*in[i]).*field).x(); }),
          lanes<D4>([&](int i) { return ((*in[i]).*field).y(); }),
          lanes<D4>([&](int i) { return ((*in[i]).*field).z(); })};
}
/// The scalars (*in[i]).*field in lanes i.
template <class T>
CLEAVE_LANES D4 gather(const T* const in[4], double T::*field) {
  return lanes<D4>([&](int i) { return (*in[i]).*field; });
}
CLEAVE_LANES void put(const Wide<D4>& v, Eigen::Vector3d* const out[4]) {
  alignas(32) double x[4], y[4], z[4];
  _mm256_store_pd(x, v.x);
  _mm256_store_pd(y, v.y);
  _mm256_store_pd(z, v.z);
  for (int i = 0; i < 4; ++i) *out[i] = {x[i], y[i], z[i]};
}
CLEAVE_LANES void put(D4 v, double* const out[4]) {
  alignas(32) double x[4];
  _mm256_store_pd(x, v);
  for (int i = 0; i < 4; ++i) *out[i] = x[i];
}

}  // namespace

[[gnu::target("avx")]] void contact_force_quad(const ContactParams& p, const ContactKinematics* const k[4],
                                               const ContactDamping* const d[4],
                                               ContactHistory* const h[4], ContactForce* const out[4],
                                               double dt) {
  const D4 zero = _mm256_setzero_pd();
  const Wide<D4> n = gather(k, &ContactKinematics::normal), v = gather(k, &ContactKinematics::velocity);
  const D4 delta = max_of(gather(k, &ContactKinematics::overlap), zero);

  // Eq 2.4 with C_res, as contact_force.
  const ContactHistory* const* hc = h;
  const D4 max_overlap = max_of(delta, gather(hc, &ContactHistory::max_overlap));
  const D4 loading = mul(_mm256_set1_pd(p.kn), delta);
  const D4 unloading = mul(_mm256_set1_pd(p.c_res * p.kn),
                           sub(delta, mul(max_overlap, gather(d, &ContactDamping::unload))));
  const D4 fn_spring = max_of(min_of(unloading, loading), zero);

  // Eq 2.6's normal damping.
  const D4 vn = dot(v, n);
  const D4 fn = max_of(sub(fn_spring, mul(gather(d, &ContactDamping::cn), vn)), zero);
  Wide<D4> force = scale(fn, n);

  // The shear spring and its Coulomb cap (eqs 2.4, 2.5). contact_force skips the root where
  // the shear is surely shorter than the cap; there the root is below the cap too, so taking
  // it in every lane decides each branch as contact_force does.
  const Wide<D4> vt = sub(v, scale(vn, n));
  Wide<D4> shear = sub(into_plane(gather(hc, &ContactHistory::shear), n),
                       scale(_mm256_set1_pd(p.ks * dt), vt));
  const D4 cap = mul(_mm256_set1_pd(p.mu_s), fn);
  const D4 fs = root(dot(shear, shear));
  const D4 sliding = _mm256_and_pd(at_least(fs, cap), greater(fs, zero));
  shear = pick(sliding, scale(div(cap, fs), shear), shear);
  force = pick(sliding, add(force, shear),
               add(force, sub(shear, scale(gather(d, &ContactDamping::cs), vt))));
  Eigen::Vector3d* shear_out[4];
  Eigen::Vector3d* force_out[4];
  double* overlap_out[4];
  const int slides = _mm256_movemask_pd(sliding);
  for (int i = 0; i < 4; ++i) {
    shear_out[i] = &h[i]->shear;
    force_out[i] = &out[i]->force;
    overlap_out[i] = &h[i]->max_overlap;
    out[i]->sliding = (slides >> i & 1) != 0;
  }

  if (p.kr > 0.0 || p.kt > 0.0) {
    // Eqs 2.7 and 2.8, capped by mu_r F_n lever (eq 2.5), as contact_force.
    const Wide<D4> spin = gather(k, &ContactKinematics::spin);
    const D4 wt = dot(spin, n);
    const Wide<D4> wr = sub(spin, scale(wt, n));
    const D4 mcap = mul(mul(_mm256_set1_pd(p.mu_r), fn), gather(k, &ContactKinematics::lever));
    Wide<D4> rolling = sub(into_plane(gather(hc, &ContactHistory::rolling), n),
                           scale(_mm256_set1_pd(p.kr * dt), wr));
    const D4 rl = root(dot(rolling, rolling));
    rolling = pick(greater(rl, mcap), scale(div(mcap, rl), rolling), rolling);
    // std::clamp(t, -mcap, mcap): t < -mcap ? -mcap : (mcap < t ? mcap : t).
    D4 torsion = sub(gather(hc, &ContactHistory::torsion), mul(_mm256_set1_pd(p.kt * dt), wt));
    const D4 low = flip(mcap);
    torsion = pick(less(torsion, low), low, pick(less(mcap, torsion), mcap, torsion));
    const Wide<D4> moment = add(sub(rolling, scale(gather(d, &ContactDamping::cr), wr)),
                                scale(sub(torsion, mul(gather(d, &ContactDamping::ct), wt)), n));
    Eigen::Vector3d* rolling_out[4];
    Eigen::Vector3d* moment_out[4];
    double* torsion_out[4];
    for (int i = 0; i < 4; ++i) {
      rolling_out[i] = &h[i]->rolling;
      moment_out[i] = &out[i]->moment;
      torsion_out[i] = &h[i]->torsion;
    }
    put(rolling, rolling_out);
    put(torsion, torsion_out);
    put(moment, moment_out);
  } else {
    for (int i = 0; i < 4; ++i) out[i]->moment.setZero();
  }
  put(shear, shear_out);
  put(force, force_out);
  put(max_overlap, overlap_out);
}

#pragma GCC diagnostic pop

double critical_time_step(double mass, double stiffness) {
  return 2.0 * std::sqrt(mass / stiffness);
}

}  // namespace cleave::physics
