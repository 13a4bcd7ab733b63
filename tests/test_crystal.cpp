// Crystallographic orientation: families, angles, corner planes and the seeded generator.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/crystal.hpp"
#include "geometry/lattice.hpp"
#include "geometry/rng.hpp"

using namespace cleave::geometry;

TEST(SplitMix64, MatchesThePublishedReferenceSequence) {
  // Reference outputs of splitmix64.c (Vigna) for seed 1234567.
  SplitMix64 rng(1234567);
  EXPECT_EQ(rng.next(), 6457827717110365317ull);
  EXPECT_EQ(rng.next(), 3203168211198807973ull);
  EXPECT_EQ(rng.next(), 9817491932198370423ull);
  EXPECT_EQ(rng.next(), 4593380528125082431ull);
  EXPECT_EQ(rng.next(), 16408922859458223821ull);
}

TEST(SplitMix64, BoundedDrawsStayInRangeAndCoverIt) {
  SplitMix64 rng(99);
  int seen[3] = {0, 0, 0};
  for (int i = 0; i < 3000; ++i) {
    const auto k = rng.below(3);
    ASSERT_LT(k, 3u);
    ++seen[k];
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
  }
  for (int k : seen) EXPECT_GT(k, 800);
}

TEST(CleavagePlanes, CornersLieOnLinesNormalToTheCleavageDirection) {
  for (auto family : {CleavageFamily::a_11_20, CleavageFamily::m_10_10}) {
    for (int angle : {0, 60, 120}) {
      const CrystalOrientation o{family, angle};
      const auto n = cleavage_normal(o);
      const Eigen::Vector2d normal(n[0], n[1]);
      const auto planes = cleavage_corner_planes(o);
      ASSERT_EQ(static_cast<int>(planes.size()), slab_count(family) - 1);
      // Expected offsets along the normal: <11-20> at -r/2 then +r/2; <10-10> at 0.
      const std::vector<double> want =
          family == CleavageFamily::a_11_20 ? std::vector<double>{-0.5, 0.5} : std::vector{0.0};
      for (std::size_t p = 0; p < planes.size(); ++p) {
        const Eigen::Vector2d a = hexagon_corner(1.0, planes[p].corner_a);
        const Eigen::Vector2d b = hexagon_corner(1.0, planes[p].corner_b);
        EXPECT_NEAR(normal.dot(a), want[p], 1e-15) << to_string(family) << " " << angle;
        EXPECT_NEAR(normal.dot(b), want[p], 1e-15) << to_string(family) << " " << angle;
      }
      // The normal points along 30 + angle (<11-20>) or angle (<10-10>) degrees.
      const double deg = (family == CleavageFamily::a_11_20 ? 30.0 : 0.0) + angle;
      EXPECT_NEAR(std::atan2(n[1], n[0]) * 180 / M_PI, deg, 1e-12);
    }
  }
}

TEST(CleavageFamilies, NamesRoundTripAndBadInputThrows) {
  EXPECT_EQ(parse_cleavage_family(to_string(CleavageFamily::a_11_20)), CleavageFamily::a_11_20);
  EXPECT_EQ(parse_cleavage_family(to_string(CleavageFamily::m_10_10)), CleavageFamily::m_10_10);
  EXPECT_THROW(parse_cleavage_family("0001"), std::invalid_argument);
  EXPECT_THROW(cleavage_corner_planes({CleavageFamily::a_11_20, 45}), std::invalid_argument);
}

TEST(DrawOrientation, IndependentOfDrawOrder) {
  const int angles[] = {0, 60, 120};
  const auto late_first = draw_orientation(5, 1000, 0.5, angles);
  for (int g = 0; g < 1000; ++g) draw_orientation(5, g, 0.5, angles);
  EXPECT_EQ(draw_orientation(5, 1000, 0.5, angles), late_first);
  // Mix 0 and 1 give one family only; a single allowed angle is always drawn.
  const int sixty[] = {60};
  for (int g = 0; g < 50; ++g) {
    EXPECT_EQ(draw_orientation(3, g, 0.0, angles).family, CleavageFamily::m_10_10);
    EXPECT_EQ(draw_orientation(3, g, 1.0, angles).family, CleavageFamily::a_11_20);
    EXPECT_EQ(draw_orientation(3, g, 0.5, sixty).angle_deg, 60);
  }
}
