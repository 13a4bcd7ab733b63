#include "physics/dem/contact_law.hpp"
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

double critical_time_step(double mass, double stiffness) {
  return 2.0 * std::sqrt(mass / stiffness);
}

}  // namespace cleave::physics
