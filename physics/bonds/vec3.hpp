#pragma once
/// \file
/// Three values (doubles, or physics/simd.hpp's lanes of them) for the laws, their
/// kinematics and the sums onto the bodies, each operation's arithmetic in the order Eigen
/// gives it, so that a law reads the same whether it is handed Eigen vectors or these.
///
/// Why not Eigen::Vector3d there: at -O2 Eigen adds two Vector3d as one SSE pair plus one
/// scalar, and a cross product's result goes through the stack as three scalars; the pair's
/// load then waits for two scalar stores it cannot forward from. Plain values stay in
/// registers, and take the lanes of simd.hpp as they are.

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <type_traits>
#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "physics/simd.hpp"

namespace cleave::physics {

/// A vector of three T: T = double for one contact, bond or body, simd::Real<W> for W of
/// them side by side (lane i the i-th one's).
template <class T>
struct Vec3 {
  T x, y, z;
};
using V3 = Vec3<double>;

/// A quaternion's components (Eigen's x, y, z, w).
template <class T>
struct Quat {
  T x, y, z, w;
};

using simd::select;

[[gnu::always_inline]] inline V3 v3(const Eigen::Vector3d& e) { return {e.x(), e.y(), e.z()}; }
[[gnu::always_inline]] inline Eigen::Vector3d eigen(const V3& a) { return {a.x, a.y, a.z}; }
template <class T>
[[gnu::always_inline]] inline Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
[[gnu::always_inline]] inline Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
[[gnu::always_inline]] inline Vec3<T> operator*(const std::type_identity_t<T>& s,
                                                const Vec3<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
[[gnu::always_inline]] inline Vec3<T> operator*(const Vec3<T>& a,
                                                const std::type_identity_t<T>& s) {
  return {a.x * s, a.y * s, a.z * s};
}
/// `m ? a : b`, lane by lane.
template <class M, class T>
[[gnu::always_inline]] inline Vec3<T> select(const M& m, const Vec3<T>& a, const Vec3<T>& b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
/// Eigen's a.dot(b) and squaredNorm(): (a0 b0 + a1 b1) + a2 b2.
template <class T>
[[gnu::always_inline]] inline T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
template <class T>
[[gnu::always_inline]] inline T norm(const Vec3<T>& a) {
  return simd::root(dot(a, a));
}
/// True only when norm(a) < limit, strictly and to the bit, decided without the square root
/// (its latency held up the laws' caps): |a|^2 < fl(limit^2) (1 - 2^-20). With fl(limit^2)
/// and that product each at most one rounding (2^-53) high, |a| < limit (1 - 2^-22), and the
/// correctly rounded root stays below limit. Limits far from 1 (where limit^2 leaves the
/// normal range) and NaN answer false: the caller then takes the root.
template <class T>
[[gnu::always_inline]] inline auto surely_shorter(const Vec3<T>& a, const T& limit) {
  return limit > 1e-150 && limit < 1e150 && dot(a, a) < (limit * limit) * (1.0 - 0x1p-20);
}
/// Eigen's a.cross(b).
template <class T>
[[gnu::always_inline]] inline Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Eigen's normalized(): each component divided by the length (unchanged when it is zero).
template <class T>
[[gnu::always_inline]] inline Vec3<T> normalized(const Vec3<T>& a) {
  const T z = dot(a, a);
  const T s = simd::root(z);
  return select(z > 0.0, Vec3<T>{a.x / s, a.y / s, a.z / s}, a);
}
/// q * v with the arithmetic of Eigen's QuaternionBase::_transformVector (the same bits);
/// physics/dem/body.hpp's rotated() is this on Eigen vectors.
template <class T>
[[gnu::always_inline]] inline Vec3<T> rotated(const Quat<T>& q, const Vec3<T>& v) {
  T ux = q.y * v.z - q.z * v.y, uy = q.z * v.x - q.x * v.z, uz = q.x * v.y - q.y * v.x;
  ux += ux;
  uy += uy;
  uz += uz;
  const T cx = q.y * uz - q.z * uy, cy = q.z * ux - q.x * uz, cz = q.x * uy - q.y * ux;
  return {(v.x + q.w * ux) + cx, (v.y + q.w * uy) + cy, (v.z + q.w * uz) + cz};
}
[[gnu::always_inline]] inline V3 rotated(const Eigen::Quaterniond& q, const V3& v) {
  return rotated(Quat<double>{q.x(), q.y(), q.z(), q.w()}, v);
}

#if defined(__AVX__)
/// Four lanes to and from an AVX register, through one aligned store and load (the
/// compiler keeps them in the register).
[[gnu::always_inline]] inline simd::Real<4> from_avx(__m256d v) {
  alignas(32) double t[4];
  _mm256_store_pd(t, v);
  return simd::Real<4>(t, simd::stdx::vector_aligned);
}
[[gnu::always_inline]] inline __m256d to_avx(const simd::Real<4>& v) {
  alignas(32) double t[4];
  v.copy_to(t, simd::stdx::vector_aligned);
  return _mm256_load_pd(t);
}
#endif

/// The vectors get(0), get(1), ... (Eigen vectors) in lanes 0, 1, ... With AVX and W = 4
/// each vector's x, y pair moves as one 16-byte load and two shuffles make the x and y
/// lanes, where lane-by-lane loads cost one load and one insert a value.
template <int W, class Get>
[[gnu::always_inline]] inline Vec3<simd::Real<W>> load3(Get&& get) {
#if defined(__AVX__)
  if constexpr (W == 4) {
    const Eigen::Vector3d &p0 = get(0), &p1 = get(1), &p2 = get(2), &p3 = get(3);
    const __m128d a0 = _mm_loadu_pd(p0.data()), a1 = _mm_loadu_pd(p1.data());
    const __m128d a2 = _mm_loadu_pd(p2.data()), a3 = _mm_loadu_pd(p3.data());
    const __m256d xy02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(a0), a2, 1);
    const __m256d xy13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(a1), a3, 1);
    return {from_avx(_mm256_unpacklo_pd(xy02, xy13)), from_avx(_mm256_unpackhi_pd(xy02, xy13)),
            from_avx(_mm256_set_pd(p3.z(), p2.z(), p1.z(), p0.z()))};
  }
#endif
  return {simd::load<W>([&](int i) { return get(i).x(); }),
          simd::load<W>([&](int i) { return get(i).y(); }),
          simd::load<W>([&](int i) { return get(i).z(); })};
}

/// The quaternions get(0), get(1), ... in lanes 0, 1, ... (with AVX and W = 4: four 32-byte
/// loads and a 4 x 4 transpose).
template <int W, class Get>
[[gnu::always_inline]] inline Quat<simd::Real<W>> load_quat(Get&& get) {
#if defined(__AVX__)
  if constexpr (W == 4) {
    // Eigen stores x, y, z, w.
    const __m256d r0 = _mm256_loadu_pd(get(0).coeffs().data());
    const __m256d r1 = _mm256_loadu_pd(get(1).coeffs().data());
    const __m256d r2 = _mm256_loadu_pd(get(2).coeffs().data());
    const __m256d r3 = _mm256_loadu_pd(get(3).coeffs().data());
    const __m256d xz01 = _mm256_unpacklo_pd(r0, r1), yw01 = _mm256_unpackhi_pd(r0, r1);
    const __m256d xz23 = _mm256_unpacklo_pd(r2, r3), yw23 = _mm256_unpackhi_pd(r2, r3);
    return {from_avx(_mm256_permute2f128_pd(xz01, xz23, 0x20)),
            from_avx(_mm256_permute2f128_pd(yw01, yw23, 0x20)),
            from_avx(_mm256_permute2f128_pd(xz01, xz23, 0x31)),
            from_avx(_mm256_permute2f128_pd(yw01, yw23, 0x31))};
  }
#endif
  return {simd::load<W>([&](int i) { return get(i).x(); }),
          simd::load<W>([&](int i) { return get(i).y(); }),
          simd::load<W>([&](int i) { return get(i).z(); }),
          simd::load<W>([&](int i) { return get(i).w(); })};
}

/// p[idx[0]], p[idx[1]], ... in lanes 0, 1, ...: load3 over an array of Eigen vectors.
template <int W>
[[gnu::always_inline]] inline Vec3<simd::Real<W>> gather3(const Eigen::Vector3d* p,
                                                         const int* idx) {
  return load3<W>([&](int i) -> const Eigen::Vector3d& { return p[idx[i]]; });
}

/// load3's inverse: lane i of v into put(i) (an Eigen vector each, all distinct). With AVX
/// and W = 4, two shuffles make the x, y pairs and each vector takes one 16-byte and one
/// 8-byte store, where lane-by-lane stores extract every value on its own.
template <int W, class Put>
[[gnu::always_inline]] inline void store3(const Vec3<simd::Real<W>>& v, Put&& put) {
  if constexpr (W == 1) {
    put(0) = Eigen::Vector3d(v.x, v.y, v.z);
#if defined(__AVX__)
  } else if constexpr (W == 4) {
    const __m256d x = to_avx(v.x), y = to_avx(v.y), z = to_avx(v.z);
    const __m256d xy02 = _mm256_unpacklo_pd(x, y), xy13 = _mm256_unpackhi_pd(x, y);
    const __m128d z01 = _mm256_castpd256_pd128(z), z23 = _mm256_extractf128_pd(z, 1);
    Eigen::Vector3d &p0 = put(0), &p1 = put(1), &p2 = put(2), &p3 = put(3);
    _mm_storeu_pd(p0.data(), _mm256_castpd256_pd128(xy02));
    _mm_storeu_pd(p1.data(), _mm256_castpd256_pd128(xy13));
    _mm_storeu_pd(p2.data(), _mm256_extractf128_pd(xy02, 1));
    _mm_storeu_pd(p3.data(), _mm256_extractf128_pd(xy13, 1));
    _mm_storel_pd(&p0.z(), z01);
    _mm_storeh_pd(&p1.z(), z01);
    _mm_storel_pd(&p2.z(), z23);
    _mm_storeh_pd(&p3.z(), z23);
#endif
  } else {
    // Through memory once, not lane by lane out of the registers.
    alignas(64) double x[W], y[W], z[W];
    v.x.copy_to(x, simd::stdx::vector_aligned);
    v.y.copy_to(y, simd::stdx::vector_aligned);
    v.z.copy_to(z, simd::stdx::vector_aligned);
    for (int i = 0; i < W; ++i) put(i) = Eigen::Vector3d(x[i], y[i], z[i]);
  }
}

/// gather3's inverse: lane i of v into p[idx[i]] (the indices distinct).
template <int W>
[[gnu::always_inline]] inline void scatter3(Eigen::Vector3d* p, const int* idx,
                                            const Vec3<simd::Real<W>>& v) {
  store3<W>(v, [&](int i) -> Eigen::Vector3d& { return p[idx[i]]; });
}

/// Lane i of a vector.
template <class T>
[[gnu::always_inline]] inline V3 lane(const Vec3<T>& v, int i) {
  return {simd::lane(v.x, i), simd::lane(v.y, i), simd::lane(v.z, i)};
}

}  // namespace cleave::physics
