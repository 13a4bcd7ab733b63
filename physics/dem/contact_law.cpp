#include "physics/dem/contact_law.hpp"

#include <algorithm>
#include <cmath>

#include "physics/bonds/tangent.hpp"

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
  ContactForce out;
  const ContactKinematics* const ks[1] = {&k};
  const ContactDamping* const ds[1] = {&d};
  ContactHistory* const hs[1] = {&h};
  ContactForce* const outs[1] = {&out};
  contact_forces<1>(p, ks, ds, hs, outs, dt);
  return out;
}

template <int W>
void contact_forces(const ContactParams& p, const ContactKinematics* const k[],
                    const ContactDamping* const d[], ContactHistory* const h[],
                    ContactForce* const out[], double dt) {
  using T = simd::Real<W>;
  using simd::load;
  using simd::max_of;
  using simd::min_of;
  // Lane i: contact i's field.
  auto in = [&](auto field) { return load<W>([&](int i) { return (*k[i]).*field; }); };
  auto coefficient = [&](double ContactDamping::*field) {
    return load<W>([&](int i) { return (*d[i]).*field; });
  };
  auto vector = [&](const auto& get) { return load3<W>(get); };
  const Vec3<T> n = vector([&](int i) -> const auto& { return k[i]->normal; });
  const Vec3<T> v = vector([&](int i) -> const auto& { return k[i]->velocity; });
  const T zero(0.0);
  const T delta = max_of(zero, in(&ContactKinematics::overlap));

  // Normal spring with the unloading multiplier (eq 2.4 and the C_res of table 2.3).
  const T max_overlap = max_of(load<W>([&](int i) { return h[i]->max_overlap; }), delta);
  const T loading = p.kn * delta;
  const T unloading =
      (p.c_res * p.kn) * (delta - max_overlap * coefficient(&ContactDamping::unload));
  const T fn_spring = max_of(zero, min_of(loading, unloading));

  // Normal damping (eq 2.6): |U_n| / dt is the normal relative speed.
  const T vn = dot(v, n);
  const T fn = max_of(zero, fn_spring - coefficient(&ContactDamping::cn) * vn);
  Vec3<T> force = fn * n;

  // Shear spring, incremental (eq 2.4): U_s = dt * v_t; Coulomb cap (eq 2.5).
  const Vec3<T> vt = v - vn * n;
  Vec3<T> shear =
      into_plane(vector([&](int i) -> const auto& { return h[i]->shear; }), n) - (p.ks * dt) * vt;
  const T cap = p.mu_s * fn;
  // Sliding when |shear| >= cap. A shear surely below the cap needs no square root (where
  // some lanes take it anyway, it is below the cap there too: the same decision).
  T fs = zero;
  if (!simd::all(surely_shorter(shear, cap))) fs = simd::root(dot(shear, shear));
  const auto sliding = fs >= cap && fs > 0.0;
  shear = select(sliding, shear * (cap / fs), shear);
  force =
      select(sliding, force + shear,
             force + (shear - coefficient(&ContactDamping::cs) * vt));  // shear damping (eq 2.6)

  // Rolling and torsional resistance (eqs 2.7, 2.8), capped by mu_r F_n lever (eq 2.5).
  const bool resists = p.kr > 0.0 || p.kt > 0.0;
  Vec3<T> rolling{zero, zero, zero}, moment{zero, zero, zero};
  T torsion = zero;
  if (resists) {
    const Vec3<T> spin = vector([&](int i) -> const auto& { return k[i]->spin; });
    const T wt = dot(spin, n);
    const Vec3<T> wr = spin - wt * n;
    const T mcap = p.mu_r * fn * in(&ContactKinematics::lever);
    rolling = into_plane(vector([&](int i) -> const auto& { return h[i]->rolling; }), n) -
              (p.kr * dt) * wr;
    if (!simd::all(surely_shorter(rolling, mcap))) {
      const T rl = simd::root(dot(rolling, rolling));
      rolling = select(rl > mcap, rolling * (mcap / rl), rolling);
    }
    torsion = load<W>([&](int i) { return h[i]->torsion; }) - (p.kt * dt) * wt;
    torsion = simd::clamp_of(torsion, T(-mcap), mcap);
    moment = (rolling - coefficient(&ContactDamping::cr) * wr) +
             (torsion - coefficient(&ContactDamping::ct) * wt) * n;
  }
  store3<W>(shear, [&](int i) -> Eigen::Vector3d& { return h[i]->shear; });
  store3<W>(force, [&](int i) -> Eigen::Vector3d& { return out[i]->force; });
  if (resists) {
    store3<W>(rolling, [&](int i) -> Eigen::Vector3d& { return h[i]->rolling; });
    store3<W>(moment, [&](int i) -> Eigen::Vector3d& { return out[i]->moment; });
  }
  for (int i = 0; i < W; ++i) {
    h[i]->max_overlap = simd::lane(max_overlap, i);
    out[i]->sliding = simd::lane(sliding, i);
    if (resists) {
      h[i]->torsion = simd::lane(torsion, i);
    } else {
      out[i]->moment.setZero();
    }
  }
}

template void contact_forces<1>(const ContactParams&, const ContactKinematics* const[],
                                const ContactDamping* const[], ContactHistory* const[],
                                ContactForce* const[], double);
template void contact_forces<2>(const ContactParams&, const ContactKinematics* const[],
                                const ContactDamping* const[], ContactHistory* const[],
                                ContactForce* const[], double);
template void contact_forces<4>(const ContactParams&, const ContactKinematics* const[],
                                const ContactDamping* const[], ContactHistory* const[],
                                ContactForce* const[], double);

double critical_time_step(double mass, double stiffness) {
  return 2.0 * std::sqrt(mass / stiffness);
}

}  // namespace cleave::physics
