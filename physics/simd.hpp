#pragma once
/// \file
/// The one SIMD abstraction of the laws: W contacts, bonds, bodies or links side by side,
/// W = 1, 2 or 4. Real<1> is double; Real<2> and Real<4> are GCC's portable
/// std::experimental::fixed_size_simd<double, W> (AVX, SSE2, NEON or plain loops, whichever
/// the build's flags allow). A law is written once as a template over its value type T and
/// called with W = 4 on full batches and W = 1 for the rest.
///
/// Every lane rounds exactly as the scalar code: packed add, multiply, divide and square
/// root are IEEE operations lane by lane, the build turns multiply-add fusion off
/// (-ffp-contract=off), the laws' branches are selects, and max/min/clamp below are
/// std::max/min/clamp's comparisons. So a law's bits do not depend on W
/// (`SimdWidths.*GiveTheSameBitsAtWidthsOneAndFour`).
///
/// Here, not in a physics folder: bonds, dem and lattice all use it and it uses nothing of
/// cleave's.

#include <cmath>
#include <experimental/simd>
#include <type_traits>

namespace cleave::physics::simd {

namespace stdx = std::experimental;

/// W doubles side by side; plain double for W = 1.
template <int W>
using Real = std::conditional_t<W == 1, double, stdx::fixed_size_simd<double, W>>;

/// The lane count of a value type.
template <class T>
inline constexpr int kWidth = static_cast<int>(stdx::simd_size_v<double, typename T::abi_type>);
template <>
inline constexpr int kWidth<double> = 1;

/// Lanes from get(0), get(1), ...: a gather from arrays of structs.
template <int W, class Get>
[[gnu::always_inline]] inline Real<W> load(Get&& get) {
  if constexpr (W == 1) {
    return get(0);
  } else {
    return Real<W>([&](auto i) { return static_cast<double>(get(static_cast<int>(i))); });
  }
}

/// The mask of get(0), get(1), ... (bools); a bool for W = 1.
template <int W, class Get>
[[gnu::always_inline]] inline auto load_mask(Get&& get) {
  if constexpr (W == 1) {
    return static_cast<bool>(get(0));
  } else {
    return load<W>([&](int i) { return get(i) ? 1.0 : 0.0; }) != 0.0;
  }
}

/// Lane i of a value or a mask.
[[gnu::always_inline]] inline double lane(double v, int) {
  return v;
}
[[gnu::always_inline]] inline bool lane(bool m, int) {
  return m;
}
template <class V>
[[gnu::always_inline]] inline auto lane(const V& v, int i) {
  return static_cast<typename V::value_type>(v[i]);
}

/// `m ? a : b`, lane by lane.
[[gnu::always_inline]] inline double select(bool m, double a, double b) {
  return m ? a : b;
}
template <class T>
[[gnu::always_inline]] inline T select(const typename T::mask_type& m, const T& a, const T& b) {
  T r = b;
  stdx::where(m, r) = a;
  return r;
}

/// Whether any / every lane of a mask is set.
[[gnu::always_inline]] inline bool any(bool m) {
  return m;
}
[[gnu::always_inline]] inline bool all(bool m) {
  return m;
}
template <class M>
[[gnu::always_inline]] inline bool any(const M& m) {
  return stdx::any_of(m);
}
template <class M>
[[gnu::always_inline]] inline bool all(const M& m) {
  return stdx::all_of(m);
}

/// std::max(a, b), std::min(a, b) and std::clamp(v, lo, hi) lane by lane, with their
/// comparisons (so their choices for NaNs and signed zeros).
template <class T>
[[gnu::always_inline]] inline T max_of(const T& a, const T& b) {
  return select(a < b, b, a);
}
template <class T>
[[gnu::always_inline]] inline T min_of(const T& a, const T& b) {
  return select(b < a, b, a);
}
template <class T>
[[gnu::always_inline]] inline T clamp_of(const T& v, const T& lo, const T& hi) {
  return select(v < lo, lo, select(hi < v, hi, v));
}

/// The correctly rounded square root, lane by lane.
[[gnu::always_inline]] inline double root(double a) {
  return std::sqrt(a);
}
template <class T>
[[gnu::always_inline]] inline T root(const T& a) {
  return stdx::sqrt(a);
}

/// f applied to each lane of a (a scalar library function: the same bits at every width).
template <class T, class F>
[[gnu::always_inline]] inline T each_lane(const T& a, F&& f) {
  if constexpr (std::is_same_v<T, double>) {
    return f(a);
  } else {
    return T([&](auto i) { return static_cast<double>(f(static_cast<double>(a[i]))); });
  }
}

}  // namespace cleave::physics::simd
