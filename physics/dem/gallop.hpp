#pragma once
/// \file
/// A forward walk through a sorted array that reads few of the elements it passes.

#include <algorithm>
#include <cstddef>
#include <iterator>

namespace cleave::physics {

/// The first index i >= from with !before(v[i]) (v.size() if none), where `before` holds on
/// a prefix of v[from..] and not after it: what `while (i < size && before(v[i])) ++i` finds
/// from `from`, by strides that double and then halving back, reading about 2 log2 of the
/// distance elements instead of every one between. (World's bonds are 576 bytes each: a
/// walk across a loaded disc's 30,000 bonds to its few hundred contacts read a cache line
/// of each.)
template <class V, class Before>
std::size_t gallop(const V& v, std::size_t from, Before before) {
  const std::size_t size = std::size(v);
  if (from >= size || !before(v[from])) return from;
  std::size_t lo = from, stride = 1;  // before(v[lo]) holds
  while (lo + stride < size && before(v[lo + stride])) {
    lo += stride;
    stride *= 2;
  }
  const auto first = std::begin(v) + static_cast<std::ptrdiff_t>(lo + 1);
  const auto last = std::begin(v) + static_cast<std::ptrdiff_t>(std::min(size, lo + stride));
  return static_cast<std::size_t>(std::partition_point(first, last, before) - std::begin(v));
}

}  // namespace cleave::physics
