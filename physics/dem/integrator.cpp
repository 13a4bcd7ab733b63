#include "physics/dem/integrator.hpp"

#include <cmath>

#include "physics/bonds/vec3.hpp"
#include "physics/simd.hpp"

namespace cleave::physics {

namespace {

/// The conjugate: the vector part negated (exactly).
template <class T>
[[gnu::always_inline]] inline Quat<T> conjugate(const Quat<T>& q) {
  return {-q.x, -q.y, -q.z, q.w};
}

/// w = R I^-1 R^T L, lane by lane: Eigen's rotated(q, inv_inertia.cwiseProduct(
/// rotated(q.conjugate(), L))), operation by operation (vec3.hpp's rotated).
template <class T>
[[gnu::always_inline]] inline Vec3<T> spin(const Quat<T>& q, const Vec3<T>& L, const Vec3<T>& inv) {
  const Vec3<T> pi = rotated(conjugate(q), L);  // body-frame angular momentum
  return rotated(q, Vec3<T>{inv.x * pi.x, inv.y * pi.y, inv.z * pi.z});
}

/// a * b with the arithmetic of Eigen's SSE quaternion product, lane by lane.
template <class T>
[[gnu::always_inline]] inline Quat<T> product(const Quat<T>& a, const Quat<T>& b) {
  return {(a.w * b.x + a.y * b.z) - (a.z * b.y - a.x * b.w),
          (a.w * b.y + a.y * b.w) + (a.z * b.x - a.x * b.z),
          (a.w * b.z - a.y * b.x) + (a.z * b.w + a.x * b.y),
          (a.w * b.w - a.y * b.y) - (a.z * b.z + a.x * b.x)};
}

/// q.normalize() with the arithmetic of Eigen's SSE code (its two-lane sum of squares);
/// unchanged where that sum is not positive.
template <class T>
[[gnu::always_inline]] inline Quat<T> normalized(const Quat<T>& q) {
  const T n2 = (q.x * q.x + q.z * q.z) + (q.y * q.y + q.w * q.w);
  const T n = simd::root(n2);
  const auto positive = n2 > 0.0;
  return {select(positive, q.x / n, q.x), select(positive, q.y / n, q.y),
          select(positive, q.z / n, q.z), select(positive, q.w / n, q.w)};
}

template <class M, class T>
[[gnu::always_inline]] inline Quat<T> select(const M& m, const Quat<T>& a, const Quat<T>& b) {
  return {simd::select(m, a.x, b.x), simd::select(m, a.y, b.y), simd::select(m, a.z, b.z),
          simd::select(m, a.w, b.w)};
}

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
/// The same lane by lane (the library's sine and cosine: the same bits at every width).
template <class T>
[[gnu::always_inline]] inline void half_angle_cos_sin(const T& half, T& ch, T& sh) {
  constexpr int W = simd::kWidth<T>;
  alignas(64) double c[W], s[W];
  for (int i = 0; i < W; ++i) half_angle_cos_sin(simd::lane(half, i), c[i], s[i]);
  ch = T(c, simd::stdx::vector_aligned);
  sh = T(s, simd::stdx::vector_aligned);
}

/// One sub-flow: rotate about principal axis k by theta = h pi_k / I_k. The orientation
/// turns by +theta about body axis k; the body-frame components of the (fixed) world
/// angular momentum turn by -theta.
template <class T>
[[gnu::always_inline]] inline void rotate_about(int k, double h, Quat<T>& q, T pi[3],
                                                const T inv[3]) {
  const T theta = h * pi[k] * inv[k];
  // One sine and cosine, of the half angle (the quaternion's), give the whole angle's.
  T ch, sh;
  half_angle_cos_sin(0.5 * theta, ch, sh);
  const T c = 1.0 - 2.0 * sh * sh, s = 2.0 * sh * ch;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const T pi_i = pi[i], pi_j = pi[j];
  pi[i] = c * pi_i + s * pi_j;
  pi[j] = -s * pi_i + c * pi_j;
  const T zero(0.0);
  q = product(q, Quat<T>{k == 0 ? sh : zero, k == 1 ? sh : zero, k == 2 ? sh : zero, ch});
}

/// Free rigid-body rotation over h, lane by lane: the splitting X(h/2) Y(h/2) Z(h) Y(h/2)
/// X(h/2), then the normalisation.
template <class T>
[[gnu::always_inline]] inline Quat<T> rotated_freely(Quat<T> q, const Vec3<T>& L,
                                                     const Vec3<T>& inv, double h) {
  const Vec3<T> p = rotated(conjugate(q), L);
  T pi[3] = {p.x, p.y, p.z};
  const T iv[3] = {inv.x, inv.y, inv.z};
  rotate_about(0, 0.5 * h, q, pi, iv);
  rotate_about(1, 0.5 * h, q, pi, iv);
  rotate_about(2, h, q, pi, iv);
  rotate_about(1, 0.5 * h, q, pi, iv);
  rotate_about(0, 0.5 * h, q, pi, iv);
  return normalized(q);
}

/// The bodies' orientations, angular momenta and inverse principal moments, body i in lane i.
template <int W>
struct Bodies {
  using T = simd::Real<W>;
  Quat<T> q;
  Vec3<T> L, inv;
  Bodies(BodyState* const s[], const BodyInfo* const b[])
      : q(load_quat<W>([&](int i) -> const auto& { return s[i]->q; })),
        L(load3<W>([&](int i) -> const auto& { return s[i]->L; })),
        inv(load3<W>([&](int i) -> const auto& { return b[i]->inv_inertia; })) {}
};

/// kick()'s second half for W bodies: their angular velocities.
template <int W>
void spin_lanes(BodyState* const s[], const BodyInfo* const b[]) {
  const Bodies<W> f(s, b);
  const auto w = spin(f.q, f.L, f.inv);
  for (int i = 0; i < W; ++i) s[i]->w = eigen(lane(w, i));
}

/// drift()'s rotation and angular velocity for W bodies; those with no angular momentum keep
/// their orientation.
template <int W>
void turn_lanes(BodyState* const s[], const BodyInfo* const b[], double h) {
  const Bodies<W> f(s, b);
  const auto turning = dot(f.L, f.L) > 0.0;
  auto q = f.q;
  if (simd::any(turning)) q = select(turning, rotated_freely(f.q, f.L, f.inv, h), f.q);
  const auto w = spin(q, f.L, f.inv);
  for (int i = 0; i < W; ++i) {
    if (simd::lane(turning, i))
      s[i]->q = Eigen::Quaterniond(simd::lane(q.w, i), simd::lane(q.x, i), simd::lane(q.y, i),
                                   simd::lane(q.z, i));
    s[i]->w = eigen(lane(w, i));
  }
}

/// f<W>(s + m, b + m) over n bodies, four at a time, then two, then one.
template <class F>
void in_lanes(BodyState* const s[], const BodyInfo* const b[], int n, F&& f) {
  int m = 0;
  for (; m + 4 <= n; m += 4) f(std::integral_constant<int, 4>{}, s + m, b + m);
  for (; m + 2 <= n; m += 2) f(std::integral_constant<int, 2>{}, s + m, b + m);
  for (; m < n; ++m) f(std::integral_constant<int, 1>{}, s + m, b + m);
}

}  // namespace

Eigen::Vector3d angular_velocity(const Eigen::Quaterniond& q, const Eigen::Vector3d& L,
                                 const Eigen::Vector3d& inv_inertia) {
  return eigen(spin(Quat<double>{q.x(), q.y(), q.z(), q.w()}, v3(L), v3(inv_inertia)));
}

void kick_momenta(BodyState& s, const BodyInfo& b, double h) {
  s.v += (h * b.inv_mass) * s.f;
  s.L += h * s.tau;
}

void kick(BodyState& s, const BodyInfo& b, double h) {
  kick_momenta(s, b, h);
  s.w = angular_velocity(s.q, s.L, b.inv_inertia);
}

void kick(BodyState* const s[], const BodyInfo* const b[], int n, double h) {
  for (int m = 0; m < n; ++m) kick_momenta(*s[m], *b[m], h);
  in_lanes(s, b, n, [](auto w, BodyState* const* sw, const BodyInfo* const* bw) {
    spin_lanes<decltype(w)::value>(sw, bw);
  });
}

void rotate_free(Eigen::Quaterniond& q, const Eigen::Vector3d& L, const Eigen::Vector3d& inv_inertia,
                 double h) {
  const Quat<double> r =
      rotated_freely(Quat<double>{q.x(), q.y(), q.z(), q.w()}, v3(L), v3(inv_inertia), h);
  q = Eigen::Quaterniond(r.w, r.x, r.y, r.z);
}

void drift(BodyState& s, const BodyInfo& b, double h) {
  BodyState* const ss[1] = {&s};
  const BodyInfo* const bs[1] = {&b};
  drift(ss, bs, 1, h);
}

void drift(BodyState* const s[], const BodyInfo* const b[], int n, double h) {
  for (int m = 0; m < n; ++m) s[m]->x += h * s[m]->v;
  in_lanes(s, b, n, [h](auto w, BodyState* const* sw, const BodyInfo* const* bw) {
    turn_lanes<decltype(w)::value>(sw, bw, h);
  });
}

}  // namespace cleave::physics
