#include "physics/dem/integrator.hpp"

#include <cmath>

namespace cleave::physics {

Eigen::Vector3d angular_velocity(const Eigen::Quaterniond& q, const Eigen::Vector3d& L,
                                 const Eigen::Vector3d& inv_inertia) {
  // R I^-1 R^T L in scalars, each operation Eigen's (conjugate: the vector part negated;
  // cwiseProduct: each component's product), so the bits of
  // rotated(q, inv_inertia.cwiseProduct(rotated(q.conjugate(), L))). Eigen's forms read q
  // and L as 16-byte pairs, which wait on the 8-byte stores that the kick and the drift
  // have just made of them (perf: 44 % of this function on one such load).
  const Eigen::Quaterniond conjugate(q.w(), -q.x(), -q.y(), -q.z());
  const V3 pi = rotated(conjugate, V3{L.x(), L.y(), L.z()});  // body-frame angular momentum
  return eigen(rotated(q, V3{inv_inertia.x() * pi.x, inv_inertia.y() * pi.y, inv_inertia.z() * pi.z}));
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

/// cos and sin of a half angle. Below 2^-27 in magnitude they are 1 and the angle itself,
/// which is what a correctly rounded sine and cosine give there (sin x = x (1 - x^2/6 ...)
/// and cos x = 1 - x^2/2 ... round to x and 1 when x^2/2 is under half an ulp of 1), and
/// what glibc's sincos returns there without computing them
/// (`Integrator.TinyHalfAnglesSkipTheSineAndCosineWithTheSameBits`). A body at rest or
/// nearly so (a bonded specimen's grains turn by 1e-12 rad a step) skips the call.
[[gnu::always_inline]] inline void half_angle_cos_sin(double half, double& ch, double& sh) {
  if (std::abs(half) < 0x1p-27) {
    ch = 1.0;
    sh = half;
  } else {
    ch = std::cos(half);
    sh = std::sin(half);
  }
}

/// One sub-flow for n bodies side by side: rotate each about its principal axis k by
/// theta = h pi_k / I_k. The orientation turns by +theta about body axis k; the body-frame
/// components of the (fixed) world angular momentum turn by -theta. The bodies are
/// independent; taking them together lets one body's sine and cosine overlap another's
/// instead of each waiting for the sub-flow before it.
template <int N>
[[gnu::always_inline]] inline void rotate_about(int k, double h, Eigen::Quaterniond* const q[N],
                                                Eigen::Vector3d pi[N], const Eigen::Vector3d* const inv_inertia[N],
                                                int n) {
  double ch[N], sh[N];
  for (int m = 0; m < n; ++m) {
    const double theta = h * pi[m][k] * (*inv_inertia[m])[k];
    // One sine and cosine, of the half angle (the quaternion's), give the whole angle's.
    half_angle_cos_sin(0.5 * theta, ch[m], sh[m]);
  }
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  for (int m = 0; m < n; ++m) {
    const double c = 1.0 - 2.0 * sh[m] * sh[m], s = 2.0 * sh[m] * ch[m];
    const double pi_i = pi[m][i], pi_j = pi[m][j];
    pi[m][i] = c * pi_i + s * pi_j;
    pi[m][j] = -s * pi_i + c * pi_j;
    Eigen::Quaterniond r(ch[m], 0.0, 0.0, 0.0);
    r.vec()[k] = sh[m];
    *q[m] = quaternion_product(*q[m], r);
  }
}

/// rotate_free of n <= N bodies side by side, each with its own bits.
template <int N>
void rotate_free_n(Eigen::Quaterniond* const q[N], const Eigen::Vector3d* const L[N],
                   const Eigen::Vector3d* const inv_inertia[N], int n, double h) {
  Eigen::Vector3d pi[N];
  for (int m = 0; m < n; ++m) pi[m] = rotated(q[m]->conjugate(), *L[m]);
  rotate_about<N>(0, 0.5 * h, q, pi, inv_inertia, n);
  rotate_about<N>(1, 0.5 * h, q, pi, inv_inertia, n);
  rotate_about<N>(2, h, q, pi, inv_inertia, n);
  rotate_about<N>(1, 0.5 * h, q, pi, inv_inertia, n);
  rotate_about<N>(0, 0.5 * h, q, pi, inv_inertia, n);
  for (int m = 0; m < n; ++m) normalize_quaternion(*q[m]);
}

}  // namespace

void rotate_free(Eigen::Quaterniond& q, const Eigen::Vector3d& L, const Eigen::Vector3d& inv_inertia,
                 double h) {
  Eigen::Quaterniond* const qs[1] = {&q};
  const Eigen::Vector3d* const ls[1] = {&L};
  const Eigen::Vector3d* const is[1] = {&inv_inertia};
  rotate_free_n<1>(qs, ls, is, 1, h);
}

void drift(BodyState& s, const BodyInfo& b, double h) {
  s.x += h * s.v;
  if (s.L.squaredNorm() > 0.0) rotate_free(s.q, s.L, b.inv_inertia, h);
  s.w = angular_velocity(s.q, s.L, b.inv_inertia);
}

void drift(BodyState* const s[], const BodyInfo* const b[], int n, double h) {
  constexpr int N = kDriftBatch;
  Eigen::Quaterniond* q[N];
  const Eigen::Vector3d* L[N];
  const Eigen::Vector3d* inv[N];
  int turning = 0;
  for (int m = 0; m < n; ++m) {
    s[m]->x += h * s[m]->v;
    if (s[m]->L.squaredNorm() > 0.0) {
      q[turning] = &s[m]->q;
      L[turning] = &s[m]->L;
      inv[turning] = &b[m]->inv_inertia;
      ++turning;
    }
  }
  rotate_free_n<N>(q, L, inv, turning, h);
  for (int m = 0; m < n; ++m) s[m]->w = angular_velocity(s[m]->q, s[m]->L, b[m]->inv_inertia);
}

}  // namespace cleave::physics
