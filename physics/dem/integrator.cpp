#include "physics/dem/integrator.hpp"

#include <cmath>

namespace cleave::physics {

Eigen::Vector3d angular_velocity(const Eigen::Quaterniond& q, const Eigen::Vector3d& L,
                                 const Eigen::Vector3d& inv_inertia) {
  const Eigen::Vector3d pi = rotated(q.conjugate(), L);  // body-frame angular momentum
  return rotated(q, inv_inertia.cwiseProduct(pi));
}

void kick_momenta(BodyState& s, const BodyInfo& b, double h) {
  s.v += (h * b.inv_mass) * s.f;
  s.L += h * s.tau;
}

void kick(BodyState& s, const BodyInfo& b, double h) {
  kick_momenta(s, b, h);
  s.w = angular_velocity(s.q, s.L, b.inv_inertia);
}

namespace {

/// One sub-flow: rotate the body about its principal axis k by theta = h pi_k / I_k.
/// The orientation turns by +theta about body axis k; the body-frame components of the
/// (fixed) world angular momentum turn by -theta.
void rotate_about(int k, double h, Eigen::Quaterniond& q, Eigen::Vector3d& pi,
                  const Eigen::Vector3d& inv_inertia) {
  const double theta = h * pi[k] * inv_inertia[k];
  // One sine and cosine, of the half angle (the quaternion's), give the whole angle's.
  const double ch = std::cos(0.5 * theta), sh = std::sin(0.5 * theta);
  const double c = 1.0 - 2.0 * sh * sh, s = 2.0 * sh * ch;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const double pi_i = pi[i], pi_j = pi[j];
  pi[i] = c * pi_i + s * pi_j;
  pi[j] = -s * pi_i + c * pi_j;
  Eigen::Quaterniond r(ch, 0.0, 0.0, 0.0);
  r.vec()[k] = sh;
  q = q * r;
}

}  // namespace

void rotate_free(Eigen::Quaterniond& q, const Eigen::Vector3d& L, const Eigen::Vector3d& inv_inertia,
                 double h) {
  Eigen::Vector3d pi = rotated(q.conjugate(), L);
  rotate_about(0, 0.5 * h, q, pi, inv_inertia);
  rotate_about(1, 0.5 * h, q, pi, inv_inertia);
  rotate_about(2, h, q, pi, inv_inertia);
  rotate_about(1, 0.5 * h, q, pi, inv_inertia);
  rotate_about(0, 0.5 * h, q, pi, inv_inertia);
  q.normalize();
}

void drift(BodyState& s, const BodyInfo& b, double h) {
  s.x += h * s.v;
  if (s.L.squaredNorm() > 0.0) rotate_free(s.q, s.L, b.inv_inertia, h);
  s.w = angular_velocity(s.q, s.L, b.inv_inertia);
}

}  // namespace cleave::physics
