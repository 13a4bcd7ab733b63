#pragma once
/// \file
/// A portable, seeded random source. std::uniform_*_distribution differ between standard
/// libraries, so cleave maps raw 64-bit words to numbers itself: the same seed gives the
/// same specimen on every machine and compiler.

#include <cstdint>

namespace cleave::geometry {

/// SplitMix64 (Steele, Lea & Flood 2014): a 64-bit state, one multiply-xorshift finaliser.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform double in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform integer in [0, n) by the multiply-high method (Lemire); n > 0.
  std::uint32_t below(std::uint32_t n) {
    return static_cast<std::uint32_t>(((next() >> 32) * static_cast<std::uint64_t>(n)) >> 32);
  }

 private:
  std::uint64_t state_;
};

/// A stream for one item of a seeded ensemble: independent of how many items exist or the
/// order they are drawn in (grain 17 gets the same orientation in any specimen size).
inline SplitMix64 stream_for(std::uint64_t seed, std::uint64_t item) {
  SplitMix64 mix(seed ^ (item * 0xD1B54A32D192ED03ull));
  mix.next();
  return SplitMix64(mix.next());
}

}  // namespace cleave::geometry
