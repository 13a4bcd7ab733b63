#include "physics/dem/integrator.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

#include "physics/bonds/lanes.hpp"

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

// (__m256d's attributes are not part of a template argument: no matter here.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"

/// One sub-flow of rotate_about for four bodies in AVX's lanes: pi the body-frame momentum's
/// components, q the orientation's (x, y, z, w).
[[gnu::always_inline, gnu::target("avx")]] inline void turn_four(int k, double hk, wide::D4 pi[3],
                                                                 wide::D4 q[4],
                                                                 const wide::D4 inv[3]) {
  using namespace wide;
  using D = D4;
  const D zero = splat<D>(0.0);
  const D theta = mul(mul(splat<D>(hk), pi[k]), inv[k]);
  alignas(32) double half[4], ch[4], sh[4];
  _mm256_store_pd(half, mul(splat<D>(0.5), theta));
  for (int m = 0; m < 4; ++m) half_angle_cos_sin(half[m], ch[m], sh[m]);
  const D c_h = _mm256_load_pd(ch), s_h = _mm256_load_pd(sh);
  const D twice = mul(splat<D>(2.0), s_h);
  const D c = sub(splat<D>(1.0), mul(twice, s_h)), sn = mul(twice, c_h);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const D pi_i = pi[i], pi_j = pi[j];
  pi[i] = add(mul(c, pi_i), mul(sn, pi_j));
  pi[j] = add(mul(flip(sn), pi_i), mul(c, pi_j));
  // quaternion_product(q, r), r = (ch; sh along axis k, +0 on the others).
  const D bx = k == 0 ? s_h : zero, by = k == 1 ? s_h : zero, bz = k == 2 ? s_h : zero, bw = c_h;
  const D x = q[0], y = q[1], z = q[2], w = q[3];
  q[0] = sub(add(mul(w, bx), mul(y, bz)), sub(mul(z, by), mul(x, bw)));
  q[1] = add(add(mul(w, by), mul(y, bw)), sub(mul(z, bx), mul(x, bz)));
  q[2] = add(sub(mul(w, bz), mul(y, bx)), add(mul(z, bw), mul(x, by)));
  q[3] = sub(sub(mul(w, bw), mul(y, by)), add(mul(z, bz), mul(x, bx)));
}

/// angular_velocity of lane i's body: R I^-1 R^T L (the conjugate's vector part negated).
[[gnu::always_inline, gnu::target("avx")]] inline wide::Wide<wide::D4> spin_lanes(
    wide::D4 qx, wide::D4 qy, wide::D4 qz, wide::D4 qw, const wide::Wide<wide::D4>& L,
    const wide::D4 inv[3]) {
  using namespace wide;
  const Wide<D4> body = rotated(flip(qx), flip(qy), flip(qz), qw, L);
  return rotated(qx, qy, qz, qw,
                 Wide<D4>{mul(inv[0], body.x), mul(inv[1], body.y), mul(inv[2], body.z)});
}

/// Four bodies' orientations, angular momenta and inverse principal moments, body m in
/// lane m.
struct FourBodies {
  wide::D4 qx, qy, qz, qw;
  wide::Wide<wide::D4> L;
  wide::D4 inv[3];
};
[[gnu::always_inline, gnu::target("avx")]] inline FourBodies four_bodies(
    BodyState* const s[4], const BodyInfo* const b[4]) {
  using wide::D4;
  using wide::lanes;
  return {
      lanes<D4>([&](int m) { return s[m]->q.x(); }),
      lanes<D4>([&](int m) { return s[m]->q.y(); }),
      lanes<D4>([&](int m) { return s[m]->q.z(); }),
      lanes<D4>([&](int m) { return s[m]->q.w(); }),
      {lanes<D4>([&](int m) { return s[m]->L.x(); }), lanes<D4>([&](int m) { return s[m]->L.y(); }),
       lanes<D4>([&](int m) { return s[m]->L.z(); })},
      {lanes<D4>([&](int m) { return b[m]->inv_inertia.x(); }),
       lanes<D4>([&](int m) { return b[m]->inv_inertia.y(); }),
       lanes<D4>([&](int m) { return b[m]->inv_inertia.z(); })}};
}

/// The angular velocities of four bodies in AVX's lanes (kick's second half).
[[gnu::target("avx")]] void spin_four(BodyState* const s[4], const BodyInfo* const b[4]) {
  using namespace wide;
  const FourBodies f = four_bodies(s, b);
  const Wide<D4> w = spin_lanes(f.qx, f.qy, f.qz, f.qw, f.L, f.inv);
  for (int m = 0; m < 4; ++m) s[m]->w = Eigen::Vector3d(lane(w.x, m), lane(w.y, m), lane(w.z, m));
}

/// rotate_free_n and angular_velocity of four bodies in AVX's four lanes, each lane the
/// scalar code's operations in its order (so its bits): the quaternion products, the turns
/// of the body-frame momentum and the normalisation side by side, the sines and cosines
/// one lane at a time. Bodies with `turning` false keep their orientation (rotate_free is
/// not called for them); every body gets its angular velocity.
[[gnu::target("avx")]] void rotate_and_spin_four(BodyState* const s[4], const BodyInfo* const b[4],
                                                 const bool turning[4], double h) {
  using namespace wide;
  using D = D4;
  const FourBodies f = four_bodies(s, b);
  // rotate_free_n: the body-frame momentum (the conjugate's vector part negated, exactly).
  const Wide<D> p0 = rotated(flip(f.qx), flip(f.qy), flip(f.qz), f.qw, f.L);
  D pi[3] = {p0.x, p0.y, p0.z};
  D q[4] = {f.qx, f.qy, f.qz, f.qw};  // x, y, z, w
  const D zero = splat<D>(0.0);
  turn_four(0, 0.5 * h, pi, q, f.inv);
  turn_four(1, 0.5 * h, pi, q, f.inv);
  turn_four(2, h, pi, q, f.inv);
  turn_four(1, 0.5 * h, pi, q, f.inv);
  turn_four(0, 0.5 * h, pi, q, f.inv);
  // normalize_quaternion: Eigen's two-lane sum of squares; unchanged where it is not positive.
  const D n2 = add(add(mul(q[0], q[0]), mul(q[2], q[2])), add(mul(q[1], q[1]), mul(q[3], q[3])));
  const D positive = greater(n2, zero), n = root(n2);
  // Bodies that do not turn keep their orientation.
  const D turns =
      lanes<D>([&](int m) { return turning[m] ? std::bit_cast<double>(~std::uint64_t{0}) : 0.0; });
  const D qx = pick(turns, pick(positive, div(q[0], n), q[0]), f.qx);
  const D qy = pick(turns, pick(positive, div(q[1], n), q[1]), f.qy);
  const D qz = pick(turns, pick(positive, div(q[2], n), q[2]), f.qz);
  const D qw = pick(turns, pick(positive, div(q[3], n), q[3]), f.qw);
  const Wide<D> w = spin_lanes(qx, qy, qz, qw, f.L, f.inv);
  for (int m = 0; m < 4; ++m) {
    if (turning[m])
      s[m]->q = Eigen::Quaterniond(lane(qw, m), lane(qx, m), lane(qy, m), lane(qz, m));
    s[m]->w = Eigen::Vector3d(lane(w.x, m), lane(w.y, m), lane(w.z, m));
  }
}

#pragma GCC diagnostic pop

}  // namespace

void kick(BodyState* const s[], const BodyInfo* const b[], int n, double h, bool lanes) {
  for (int m = 0; m < n; ++m) kick_momenta(*s[m], *b[m], h);
  if (lanes && n == 4 && has_avx()) {
    spin_four(s, b);
    return;
  }
  for (int m = 0; m < n; ++m) s[m]->w = angular_velocity(s[m]->q, s[m]->L, b[m]->inv_inertia);
}

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

void drift(BodyState* const s[], const BodyInfo* const b[], int n, double h, bool lanes) {
  constexpr int N = kDriftBatch;
  Eigen::Quaterniond* q[N];
  const Eigen::Vector3d* L[N];
  const Eigen::Vector3d* inv[N];
  if (lanes && n == 4 && has_avx()) {  // four at once in AVX's lanes (rotate_and_spin_four)
    bool turns[4];
    for (int m = 0; m < 4; ++m) {
      s[m]->x += h * s[m]->v;
      turns[m] = s[m]->L.squaredNorm() > 0.0;
    }
    rotate_and_spin_four(s, b, turns, h);
    return;
  }
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
