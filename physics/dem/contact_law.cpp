#include "physics/dem/contact_law.hpp"
#include "physics/bonds/tangent.hpp"

#include <algorithm>
#include <cmath>

namespace cleave::physics {

ContactForce contact_force(const ContactParams& p, const ContactKinematics& k,
                           ContactHistory& h, double dt) {
  ContactForce out;
  const Eigen::Vector3d& n = k.normal;
  const double delta = std::max(0.0, k.overlap);

  // Normal spring with the unloading multiplier (eq 2.4 and the C_res of table 2.3).
  h.max_overlap = std::max(h.max_overlap, delta);
  const double loading = p.kn * delta;
  const double unloading = p.c_res * p.kn * (delta - h.max_overlap * (1.0 - 1.0 / p.c_res));
  const double fn_spring = std::max(0.0, std::min(loading, unloading));

  // Normal damping (eq 2.6): |U_n| / dt is the normal relative speed.
  const double vn = k.velocity.dot(n);
  const double cn = p.damping_ratio * std::sqrt(p.c_res * p.kn * k.m_crit);
  const double fn = std::max(0.0, fn_spring - cn * vn);
  out.force = fn * n;

  // Shear spring, incremental (eq 2.4): U_s = dt * v_t; Coulomb cap (eq 2.5).
  const Eigen::Vector3d vt = k.velocity - vn * n;
  h.shear = into_plane(h.shear, n) - p.ks * dt * vt;
  const double cap = p.mu_s * fn;
  const double fs = h.shear.norm();
  if (fs >= cap && fs > 0.0) {
    h.shear *= cap / fs;
    out.sliding = true;
    out.force += h.shear;
  } else {
    const double cs = p.damping_ratio * std::sqrt(p.ks * k.m_crit);
    out.force += h.shear - cs * vt;  // shear damping (eq 2.6)
  }

  // Rolling and torsional resistance (eqs 2.7, 2.8), capped by mu_r F_n lever (eq 2.5).
  if (p.kr > 0.0 || p.kt > 0.0) {
    const double wt = k.spin.dot(n);
    const Eigen::Vector3d wr = k.spin - wt * n;
    const double mcap = p.mu_r * fn * k.lever;
    h.rolling = into_plane(h.rolling, n) - p.kr * dt * wr;
    if (h.rolling.norm() > mcap) h.rolling *= mcap / h.rolling.norm();
    h.torsion -= p.kt * dt * wt;
    h.torsion = std::clamp(h.torsion, -mcap, mcap);
    const double cr = p.damping_ratio * std::sqrt(p.kr * k.i_crit);
    const double ct = p.damping_ratio * std::sqrt(p.kt * k.i_crit);
    out.moment = h.rolling - cr * wr + (h.torsion - ct * wt) * n;
  }
  return out;
}

double critical_time_step(double mass, double stiffness) {
  return 2.0 * std::sqrt(mass / stiffness);
}

}  // namespace cleave::physics
