#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace cleave::physics {

/// An exact sum of doubles: a fixed-point accumulator over the whole double range (32-bit
/// digits from 2^-1074, the smallest subnormal, past 2^1024), so the sum does not depend on
/// the order of its terms, nor on how they are shared among processes (the digits of
/// several accumulators add as integers). A run on any number of processes reads the same
/// kinetic energy, the same bits, from it. Each digit is an int64 holding 32 bits plus
/// carries: 2^31 terms can be added before value() or a carry pass is needed.
class ExactSum {
 public:
  static constexpr int kDigits = 67;  // bit 0 is 2^-1074; a double's top bit is at most bit 2098

  void add(double x) {
    if (x == 0.0) return;
    if (!std::isfinite(x)) {
      special_ += x;  // inf and nan: their sums do not depend on the order either
      return;
    }
    int exp = 0;
    const double fraction = std::frexp(std::abs(x), &exp);  // |x| = fraction 2^exp, fraction in [0.5, 1)
    auto m = static_cast<std::uint64_t>(std::ldexp(fraction, 53));  // exact: 53 bits
    int at = exp - 53 + 1074;                                        // bit position of m's lowest bit
    if (at < 0) {  // a subnormal: its low bits are zero
      m >>= -at;
      at = 0;
    }
    const unsigned __int128 v = static_cast<unsigned __int128>(m) << (at % 32);
    const int k = at / 32;
    const std::int64_t sign = x < 0.0 ? -1 : 1;
    digits_[k] += sign * static_cast<std::int64_t>(v & 0xFFFFFFFFu);
    digits_[k + 1] += sign * static_cast<std::int64_t>((v >> 32) & 0xFFFFFFFFu);
    digits_[k + 2] += sign * static_cast<std::int64_t>(v >> 64);
  }

  void add(const ExactSum& other) {
    for (int k = 0; k < kDigits; ++k) digits_[k] += other.digits_[k];
    special_ += other.special_;
  }

  /// The sum, correctly rounded to the nearest double (ties to even): a function of the
  /// exact sum alone, so the same for every order of the terms.
  [[nodiscard]] double value() const {
    if (special_ != 0.0 || std::isnan(special_)) return special_;
    std::array<std::int64_t, kDigits> d = digits_;
    auto carry_up = [&d] {  // every digit but the top into [0, 2^32); the top keeps the sign
      for (int k = 0; k + 1 < kDigits; ++k) {
        const std::int64_t carry = d[k] >> 32;  // floor division by 2^32
        d[k] -= carry * (std::int64_t{1} << 32);
        d[k + 1] += carry;
      }
    };
    carry_up();
    const bool negative = d[kDigits - 1] < 0;
    if (negative) {  // the magnitude, every digit non-negative
      for (auto& x : d) x = -x;
      carry_up();
    }
    int top = kDigits - 1;
    while (top > 0 && d[top] == 0) --top;
    if (d[top] == 0) return 0.0;
    const int length = 32 * top + std::bit_width(static_cast<std::uint64_t>(d[top]));  // bits of the magnitude
    // The 64 bits below the top one's end, and whether any bit under them is set (sticky):
    // converting those 64 bits, sticky or-ed into the lowest, rounds once, to nearest, as the
    // exact magnitude would (11 bits below a double's 53 decide the rounding).
    const int shift = std::max(0, length - 64);
    auto digit = [&d](int k) -> unsigned __int128 {
      return k < kDigits ? static_cast<unsigned __int128>(static_cast<std::uint64_t>(d[k])) : 0;
    };
    const int k = shift / 32, offset = shift % 32;
    const unsigned __int128 window = digit(k) | digit(k + 1) << 32 | digit(k + 2) << 64;
    auto bits = static_cast<std::uint64_t>(window >> offset);
    bool sticky = (static_cast<std::uint64_t>(d[k]) & ((std::uint64_t{1} << offset) - 1)) != 0;
    for (int j = 0; j < k && !sticky; ++j) sticky = d[j] != 0;
    if (sticky) bits |= 1u;
    // With shift > 0 the result is at least 2^(63 + shift - 1074), a normal double, so the
    // scaling is exact; with shift = 0 a subnormal result is the integer itself, exact too.
    const double r = std::ldexp(static_cast<double>(bits), shift - 1074);
    return negative ? -r : r;
  }

  [[nodiscard]] std::array<std::int64_t, kDigits>& digits() { return digits_; }
  [[nodiscard]] double& special() { return special_; }

 private:
  std::array<std::int64_t, kDigits> digits_{};
  double special_ = 0.0;
};

}  // namespace cleave::physics
