// physics::ExactSum: the exact, order-free sum that makes a reading of several MPI processes
// the same on any number of them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "physics/dem/exact_sum.hpp"

using cleave::physics::ExactSum;

namespace {
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

double exact_of(const std::vector<double>& terms) {
  ExactSum s;
  for (double t : terms) s.add(t);
  return s.value();
}
}  // namespace

TEST(ExactSum, CancellationThatAPlainSumLosesIsExact) {
  // 1e308 + 1 - 1e308: a left-to-right double sum gives 0.
  EXPECT_EQ(exact_of({1e308, 1.0, -1e308}), 1.0);
  EXPECT_EQ(exact_of({1e-300, 1e300, -1e300}), 1e-300);
  // Subnormals and the largest doubles.
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(exact_of({tiny, tiny, tiny}), 3.0 * tiny);
  const double big = std::numeric_limits<double>::max();
  EXPECT_EQ(exact_of({big, -big, big}), big);
  EXPECT_EQ(exact_of({}), 0.0);
  EXPECT_EQ(exact_of({0.1, -0.1}), 0.0);
}

TEST(ExactSum, DyadicTermsGiveTheirIntegerSumCorrectlyRounded) {
  // Terms n 2^e with |n| <= 10^6 and e in [-20, 20]: their exact sum, in units of 2^-20, is an
  // integer of up to 68 bits, held by a 128-bit integer; the conversion of that integer to
  // double rounds once, to nearest, which is what the exact sum must give, whatever the order.
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> n(-1000000, 1000000), e(-20, 20);
  int rounded = 0;  // trials whose sum a double cannot hold (else the rounding goes untested)
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> terms;
    __int128 reference = 0;
    for (int k = 0; k < 200; ++k) {
      const int mantissa = n(rng);  // drawn in sequence: an argument list's order is unspecified
      const int exponent = e(rng);
      terms.push_back(std::ldexp(static_cast<double>(mantissa), exponent));
      reference += static_cast<__int128>(mantissa) << (exponent + 20);
    }
    const double expected = std::ldexp(static_cast<double>(reference), -20);
    if (static_cast<__int128>(std::ldexp(expected, 20)) != reference) ++rounded;
    EXPECT_TRUE(same_bits(exact_of(terms), expected)) << trial << ": " << exact_of(terms) << " vs " << expected;
    std::reverse(terms.begin(), terms.end());
    EXPECT_TRUE(same_bits(exact_of(terms), expected)) << trial;
  }
  EXPECT_GT(rounded, 50);
}

TEST(ExactSum, HalfwayCasesRoundToEvenAndAnythingPastHalfwayRoundsUp) {
  const double two53 = std::ldexp(1.0, 53);
  // 2^53 + 1 lies halfway between 2^53 and 2^53 + 2: to even, 2^53.
  EXPECT_TRUE(same_bits(exact_of({two53, 1.0}), two53));
  // 2^53 + 3 lies halfway between 2^53 + 2 and 2^53 + 4: to even, 2^53 + 4.
  EXPECT_TRUE(same_bits(exact_of({two53, 3.0}), two53 + 4.0));
  // A bit far below the halfway point breaks the tie: up, then down for the negative sum.
  EXPECT_TRUE(same_bits(exact_of({two53, 1.0, std::ldexp(1.0, -900)}), two53 + 2.0));
  EXPECT_TRUE(same_bits(exact_of({two53, 1.0, -std::ldexp(1.0, -900)}), two53));
  EXPECT_TRUE(same_bits(exact_of({-two53, -1.0, -std::ldexp(1.0, -900)}), -two53 - 2.0));
  // Rounding that carries into a new top bit: (2^53 - 1) 2 + 1 + tiny rounds to 2^54.
  EXPECT_TRUE(same_bits(exact_of({two53 - 1.0, two53 - 1.0, 1.0, std::ldexp(1.0, -1074)}), 2.0 * two53));
  // A subnormal result is exact.
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_TRUE(same_bits(exact_of({std::ldexp(1.0, -1022), -tiny}), std::ldexp(1.0, -1022) - tiny));
}

TEST(ExactSum, AnyOrderAndAnySplitIntoPartsGiveTheSameBits) {
  // What several processes do: each sums its share, the shares' digits are added.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-60, 60);
  std::vector<double> terms;
  for (int k = 0; k < 5000; ++k) terms.push_back(std::ldexp(mantissa(rng), exponent(rng)));
  const double whole = exact_of(terms);
  double plain_min = std::numeric_limits<double>::infinity(), plain_max = -plain_min;
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(terms.begin(), terms.end(), rng);
    const int parts = 1 + trial % 7;
    std::vector<ExactSum> part(static_cast<std::size_t>(parts));
    for (std::size_t k = 0; k < terms.size(); ++k) part[k % part.size()].add(terms[k]);
    ExactSum all;
    for (const ExactSum& p : part) all.add(p);
    EXPECT_TRUE(same_bits(all.value(), whole)) << trial;
    double plain = 0.0;
    for (double t : terms) plain += t;
    plain_min = std::min(plain_min, plain);
    plain_max = std::max(plain_max, plain);
  }
  // The plain sum does depend on the order (else this test shows nothing).
  EXPECT_LT(plain_min, plain_max);
  EXPECT_NEAR(whole, plain_min, 1e-9 * std::abs(whole) + 1e-12);
}

TEST(ExactSum, InfinityAndNanPassThrough) {
  EXPECT_TRUE(std::isinf(exact_of({1.0, std::numeric_limits<double>::infinity()})));
  EXPECT_TRUE(std::isnan(exact_of({1.0, std::numeric_limits<double>::quiet_NaN()})));
}
