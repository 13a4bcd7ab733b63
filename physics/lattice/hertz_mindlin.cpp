#include "physics/lattice/hertz_mindlin.hpp"

#include <cmath>

#include "physics/bonds/tangent.hpp"

namespace cleave::physics {

HertzMindlinParams hertz_mindlin_params(double E_i, double nu_i, double r_i, double E_j,
                                        double nu_j, double r_j, double kappa, double friction) {
  const double G_i = E_i / (2.0 * (1.0 + nu_i));
  const double G_j = E_j / (2.0 * (1.0 + nu_j));
  HertzMindlinParams p{};
  p.e_star = 1.0 / ((1.0 - nu_i * nu_i) / E_i + (1.0 - nu_j * nu_j) / E_j);  // eq. 35
  p.r_star = 1.0 / (1.0 / r_i + 1.0 / r_j);                                  // eq. 36
  p.g_star = 1.0 / ((2.0 - nu_i) / G_i + (2.0 - nu_j) / G_j);                // eq. 41
  p.kappa = kappa;
  p.friction = friction;
  return p;
}

HertzMindlinForce hertz_mindlin_force(const HertzMindlinParams& p, double overlap,
                                      const Eigen::Vector3d& n, const Eigen::Vector3d& velocity,
                                      HertzMindlinState& s, double dt) {
  HertzMindlinForce out;
  if (!(overlap > 0.0)) {  // apart: the persistent-contact period of eq. 42 ends
    s = HertzMindlinState{};
    return out;
  }
  if (!s.touching) s.shear.setZero();
  s.touching = true;
  // Eq. 34: Hertz normal force, pushing B away from A.
  const double fn =
      4.0 / 3.0 * p.kappa * p.e_star * std::sqrt(p.r_star) * overlap * std::sqrt(overlap);
  // Eqs 42-43: accumulate the tangential relative displacement in the current tangent plane.
  const Eigen::Vector3d vs = velocity - velocity.dot(n) * n;
  s.shear = into_plane(s.shear, n) + vs * dt;
  // Eq. 40: Mindlin tangential spring.
  const double kt = 16.0 / 3.0 * p.g_star * std::sqrt(p.r_star * overlap);
  Eigen::Vector3d fs = -kt * s.shear;
  // Our Coulomb cap (see the header).
  const double cap = p.friction * fn;
  const double fs_len = fs.norm();
  if (fs_len > cap) {
    fs *= fs_len > 0.0 ? cap / fs_len : 0.0;
    s.shear = -fs / kt;
  }
  out.force = fn * n + fs;
  return out;
}

}  // namespace cleave::physics
