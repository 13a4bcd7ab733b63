#pragma once
/// \file
/// Arithmetic on two doubles (SSE2) or four (AVX) side by side, each lane rounded exactly as
/// the scalar instruction rounds it: the helpers of bond_pair.hpp's bond law, of
/// contact_law.cpp's contact_force_quad and of the integrator's batch drift and kick, which
/// do several bodies', bonds' or contacts' scalar arithmetic at once, in its order, to the
/// bit. Every function is compiled for AVX (target attribute, not
/// FMA: no multiply-add is fused); callers check has_avx() first.

#include <immintrin.h>

#include "physics/bonds/vec3.hpp"

namespace cleave::physics {

/// Whether this processor runs AVX (the lanes need it; without, the callers do one bond or
/// body at a time, with the same bits).
[[nodiscard]] inline bool has_avx() {
  static const bool avx = __builtin_cpu_supports("avx");
  return avx;
}

namespace wide {

// (__m128d's and __m256d's attributes are not part of a template argument: no matter here.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"

/// Every lane function is compiled for AVX (the caller checks has_avx()), the SSE2 ones
/// too, so that one generic body serves both widths.
#define CLEAVE_LANES [[gnu::always_inline, gnu::target("avx")]] inline

using D2 = __m128d;
using D4 = __m256d;
template <class D>
struct Wide {
  D x, y, z;
};

CLEAVE_LANES D2 add(D2 a, D2 b) { return _mm_add_pd(a, b); }
CLEAVE_LANES D2 sub(D2 a, D2 b) { return _mm_sub_pd(a, b); }
CLEAVE_LANES D2 mul(D2 a, D2 b) { return _mm_mul_pd(a, b); }
CLEAVE_LANES D2 div(D2 a, D2 b) { return _mm_div_pd(a, b); }
CLEAVE_LANES D2 root(D2 a) { return _mm_sqrt_pd(a); }
CLEAVE_LANES D2 equal(D2 a, D2 b) { return _mm_cmpeq_pd(a, b); }
CLEAVE_LANES D2 greater(D2 a, D2 b) { return _mm_cmpgt_pd(a, b); }
CLEAVE_LANES D2 at_least(D2 a, D2 b) { return _mm_cmpge_pd(a, b); }
CLEAVE_LANES D2 less(D2 a, D2 b) { return _mm_cmplt_pd(a, b); }
/// std::max(b, a) and std::min(b, a), lane by lane: max_pd (min_pd) gives its second operand
/// unless the first is strictly greater (smaller), as std::max(b, a) gives b unless b < a
/// (NaNs and signed zeros included).
CLEAVE_LANES D2 max_of(D2 a, D2 b) { return _mm_max_pd(a, b); }
CLEAVE_LANES D2 min_of(D2 a, D2 b) { return _mm_min_pd(a, b); }
CLEAVE_LANES D2 flip(D2 a) { return _mm_xor_pd(a, _mm_set1_pd(-0.0)); }  // the sign bit
/// `mask ? a : b`, lane by lane.
CLEAVE_LANES D2 pick(D2 mask, D2 a, D2 b) {
  return _mm_or_pd(_mm_and_pd(mask, a), _mm_andnot_pd(mask, b));
}
CLEAVE_LANES D4 add(D4 a, D4 b) { return _mm256_add_pd(a, b); }
CLEAVE_LANES D4 sub(D4 a, D4 b) { return _mm256_sub_pd(a, b); }
CLEAVE_LANES D4 mul(D4 a, D4 b) { return _mm256_mul_pd(a, b); }
CLEAVE_LANES D4 div(D4 a, D4 b) { return _mm256_div_pd(a, b); }
CLEAVE_LANES D4 root(D4 a) { return _mm256_sqrt_pd(a); }
CLEAVE_LANES D4 equal(D4 a, D4 b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
CLEAVE_LANES D4 greater(D4 a, D4 b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
CLEAVE_LANES D4 at_least(D4 a, D4 b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
CLEAVE_LANES D4 less(D4 a, D4 b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
CLEAVE_LANES D4 max_of(D4 a, D4 b) { return _mm256_max_pd(a, b); }
CLEAVE_LANES D4 min_of(D4 a, D4 b) { return _mm256_min_pd(a, b); }
CLEAVE_LANES D4 flip(D4 a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
CLEAVE_LANES D4 pick(D4 mask, D4 a, D4 b) {
  return _mm256_or_pd(_mm256_and_pd(mask, a), _mm256_andnot_pd(mask, b));
}

/// The register of get(0), get(1), ... in lanes 0, 1, ...
template <class D, class Get>
CLEAVE_LANES D lanes(Get&& get) {
  if constexpr (sizeof(D) == 16) {
    return _mm_set_pd(get(1), get(0));
  } else {
    return _mm256_set_pd(get(3), get(2), get(1), get(0));
  }
}
template <class D>
CLEAVE_LANES D splat(double a) {
  return lanes<D>([a](int) { return a; });
}
/// Lane i of v.
template <class D>
CLEAVE_LANES double lane(D v, int i) {
  alignas(32) double out[sizeof(D) / 8];
  if constexpr (sizeof(D) == 16) {
    _mm_store_pd(out, v);
  } else {
    _mm256_store_pd(out, v);
  }
  return out[i];
}
template <class D>
CLEAVE_LANES V3 lane(const Wide<D>& v, int i) {
  return {lane(v.x, i), lane(v.y, i), lane(v.z, i)};
}

template <class D>
CLEAVE_LANES Wide<D> pick(D mask, const Wide<D>& a, const Wide<D>& b) {
  return {pick(mask, a.x, b.x), pick(mask, a.y, b.y), pick(mask, a.z, b.z)};
}
template <class D>
CLEAVE_LANES Wide<D> add(const Wide<D>& a, const Wide<D>& b) {
  return {add(a.x, b.x), add(a.y, b.y), add(a.z, b.z)};
}
template <class D>
CLEAVE_LANES Wide<D> sub(const Wide<D>& a, const Wide<D>& b) {
  return {sub(a.x, b.x), sub(a.y, b.y), sub(a.z, b.z)};
}
template <class D>
CLEAVE_LANES Wide<D> scale(D s, const Wide<D>& a) {
  return {mul(s, a.x), mul(s, a.y), mul(s, a.z)};
}
/// vec3.hpp's dot: (a0 b0 + a1 b1) + a2 b2.
template <class D>
CLEAVE_LANES D dot(const Wide<D>& a, const Wide<D>& b) {
  return add(add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z));
}
template <class D>
CLEAVE_LANES Wide<D> cross(const Wide<D>& a, const Wide<D>& b) {
  return {sub(mul(a.y, b.z), mul(a.z, b.y)), sub(mul(a.z, b.x), mul(a.x, b.z)),
          sub(mul(a.x, b.y), mul(a.y, b.x))};
}
/// vec3.hpp's normalized: unchanged where the squared length is not positive.
template <class D>
CLEAVE_LANES Wide<D> normalized(const Wide<D>& a) {
  const D z = dot(a, a);
  const D s = root(z);
  const Wide<D> n{div(a.x, s), div(a.y, s), div(a.z, s)};
  return pick(greater(z, splat<D>(0.0)), n, a);
}
/// vec3.hpp's rotated (Eigen's _transformVector), lane i by the quaternion (qx, qy, qz, qw)
/// of lane i.
template <class D>
CLEAVE_LANES Wide<D> rotated(D qx, D qy, D qz, D qw, const Wide<D>& v) {
  D ux = sub(mul(qy, v.z), mul(qz, v.y)), uy = sub(mul(qz, v.x), mul(qx, v.z)),
    uz = sub(mul(qx, v.y), mul(qy, v.x));
  ux = add(ux, ux);
  uy = add(uy, uy);
  uz = add(uz, uz);
  const D cx = sub(mul(qy, uz), mul(qz, uy)), cy = sub(mul(qz, ux), mul(qx, uz)),
          cz = sub(mul(qx, uy), mul(qy, ux));
  return {add(add(v.x, mul(qw, ux)), cx), add(add(v.y, mul(qw, uy)), cy),
          add(add(v.z, mul(qw, uz)), cz)};
}
/// tangent.hpp's into_plane: v where its length is zero, zero where its part across n is.
template <class D>
CLEAVE_LANES Wide<D> into_plane(const Wide<D>& v, const Wide<D>& n) {
  const D zero = splat<D>(0.0);
  const D len = root(dot(v, v));
  const Wide<D> t = sub(v, scale(dot(v, n), n));
  const D tl = root(dot(t, t));
  const Wide<D> scaled = scale(div(len, tl), t);
  // (t * (len / tl) is vec3.hpp's t * s: each component times s, the same product.)
  const Wide<D> across = pick(equal(tl, zero), Wide<D>{zero, zero, zero}, scaled);
  return pick(equal(len, zero), v, across);
}

#pragma GCC diagnostic pop

}  // namespace wide

}  // namespace cleave::physics
