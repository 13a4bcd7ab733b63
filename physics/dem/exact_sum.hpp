#pragma once

#include <array>
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

  /// The sum, rounded to a double (from its top 128 bits: a function of the exact sum
  /// alone, so the same for every order of the terms).
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
    double r = 0.0;
    for (int k = top; k >= 0 && k > top - 4; --k) r += std::ldexp(static_cast<double>(d[k]), 32 * k - 1074);
    return negative ? -r : r;
  }

  [[nodiscard]] std::array<std::int64_t, kDigits>& digits() { return digits_; }
  [[nodiscard]] double& special() { return special_; }

 private:
  std::array<std::int64_t, kDigits> digits_{};
  double special_ = 0.0;
};

}  // namespace cleave::physics
