// Coarse contact detection (App. B.1 of the dissertation, seed 000) against an all-pairs
// O(N^2) reference: the basic and the bounding-box grids must both return exactly the pairs
// i < j with |c_i - c_j| <= r_i + r_j + margin, sorted by (i, j), each once.
//   - random scenes (fixed seeds): equal, mixed (1x..20x, log-uniform, a few huge, one
//     1000x giant) radii; dense, sparse and clustered; flat; negative coordinates; far
//     outliers, including touching clusters 10^6..10^11 m away, and a core with tendrils;
//   - an exact lattice of touching spheres, whose pair count is known in closed form;
//   - edge cases: no body, one body, exact touching, identical centres, zero radii;
//   - one searcher reused over moving, growing and shrinking scenes, and no allocation in
//     a repeated call (global operator new is counted in this test binary).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/rng.hpp"
#include "physics/dem/neighbour_search.hpp"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

// Counting replacements of the global allocation functions (noinline: GCC would otherwise
// see the inlined free() against a new-expression and warn).
[[gnu::noinline]] void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
[[gnu::noinline]] void operator delete(void* p) noexcept {
  std::free(p);
}
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

using cleave::geometry::SplitMix64;
using namespace cleave::physics;
using Eigen::Vector3d;

namespace {

constexpr SearchMethod kMethods[] = {SearchMethod::basic, SearchMethod::bounding_box};

const char* name_of(SearchMethod m) {
  return m == SearchMethod::basic ? "basic" : "bbox";
}

/// The contract's test over all pairs, written out on its own.
std::vector<BodyPair> all_pairs(const std::vector<BoundingSphere>& s, double margin) {
  std::vector<BodyPair> out;
  for (std::uint32_t i = 0; i < s.size(); ++i) {
    for (std::uint32_t j = i + 1; j < s.size(); ++j) {
      const double dx = s[i].centre.x() - s[j].centre.x();
      const double dy = s[i].centre.y() - s[j].centre.y();
      const double dz = s[i].centre.z() - s[j].centre.z();
      const double reach = s[i].radius + s[j].radius + margin;
      if (dx * dx + dy * dy + dz * dz <= reach * reach) out.emplace_back(i, j);
    }
  }
  return out;
}

/// Equal to the reference, or a message naming the first missing and surplus pairs.
testing::AssertionResult same_pairs(const std::vector<BodyPair>& got,
                                    const std::vector<BodyPair>& want) {
  if (got == want) return testing::AssertionSuccess();
  std::ostringstream msg;
  msg << "got " << got.size() << " pairs, want " << want.size();
  for (std::size_t k = 1; k < got.size(); ++k) {
    if (!(got[k - 1] < got[k])) {
      msg << "; not strictly ascending at " << k;
      break;
    }
  }
  int shown = 0;
  for (const BodyPair& p : want) {
    if (!std::binary_search(got.begin(), got.end(), p) && shown++ < 5) {
      msg << "; missing (" << p.first << "," << p.second << ")";
    }
  }
  shown = 0;
  for (const BodyPair& p : got) {
    if (!std::binary_search(want.begin(), want.end(), p) && shown++ < 5) {
      msg << "; surplus (" << p.first << "," << p.second << ")";
    }
  }
  return testing::AssertionFailure() << msg.str();
}

std::vector<BodyPair> search(SearchMethod method, const std::vector<BoundingSphere>& s,
                             double margin) {
  NeighbourSearch grid(method);
  std::vector<BodyPair> pairs{{7, 3}};  // stale content must be dropped
  grid.find_pairs(s, margin, pairs);
  return pairs;
}

// --- scene builders -----------------------------------------------------------------------

double uniform(SplitMix64& rng, double lo, double hi) {
  return lo + (hi - lo) * rng.uniform();
}

Vector3d in_box(SplitMix64& rng, const Vector3d& lo, double side) {
  return lo + side * Vector3d(rng.uniform(), rng.uniform(), rng.uniform());
}

Vector3d in_ball(SplitMix64& rng, const Vector3d& centre, double radius) {
  Vector3d v;
  do {
    v = Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
  } while (v.squaredNorm() > 1.0);
  return centre + radius * v;
}

/// Side of the cube in which these radii fill `fraction` of the volume.
double side_for(const std::vector<double>& radii, double fraction) {
  double volume = 0.0;
  for (double r : radii) volume += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return std::cbrt(volume / fraction);
}

/// Radius of the ball in which these radii fill `fraction` of the volume.
double ball_for(const std::vector<double>& radii, double fraction) {
  return side_for(radii, fraction) / std::cbrt(4.0 / 3.0 * std::numbers::pi);
}

std::vector<double> radii_between(SplitMix64& rng, int n, double lo, double hi) {
  std::vector<double> r(n);
  for (double& x : r) x = uniform(rng, lo, hi);
  return r;
}

std::vector<double> radii_log_between(SplitMix64& rng, int n, double lo, double hi) {
  std::vector<double> r(n);
  for (double& x : r) x = lo * std::pow(hi / lo, rng.uniform());
  return r;
}

void add_box(std::vector<BoundingSphere>& s, SplitMix64& rng, const std::vector<double>& radii,
             const Vector3d& lo, double fraction) {
  const double side = side_for(radii, fraction);
  for (double r : radii) s.push_back({in_box(rng, lo, side), r});
}

void add_ball(std::vector<BoundingSphere>& s, SplitMix64& rng, const std::vector<double>& radii,
              const Vector3d& centre, double fraction) {
  const double radius = ball_for(radii, fraction);
  for (double r : radii) s.push_back({in_ball(rng, centre, radius), r});
}

/// Interleaves the bodies so that index order says nothing about position.
void shuffle(std::vector<BoundingSphere>& s, SplitMix64& rng) {
  for (auto k = static_cast<std::uint32_t>(s.size()); k > 1; --k)
    std::swap(s[k - 1], s[rng.below(k)]);
}

struct Scene {
  std::vector<BoundingSphere> bodies;
  double scale = 0.0;  ///< a typical small radius: margins are multiples of it
};

Scene make_scene(const std::string& name) {
  std::uint64_t seed = 0xCBF29CE484222325ull;  // FNV-1a of the name: the same on every platform
  for (const char ch : name) seed = (seed ^ static_cast<unsigned char>(ch)) * 0x100000001B3ull;
  SplitMix64 rng(seed);
  Scene sc;
  auto& s = sc.bodies;
  const double r = 1e-3;
  sc.scale = r;
  if (name == "equal_dense") {
    add_box(s, rng, std::vector<double>(2000, r), {-0.01, -0.02, 0.005}, 0.6);
  } else if (name == "equal_sparse") {
    add_box(s, rng, std::vector<double>(1000, r), {-0.2, 0.1, -0.3}, 0.02);
  } else if (name == "equal_clustered") {
    const Vector3d centres[] = {{-1.0, -1.0, -1.0},
                                {0.3, -2.0, 0.7},
                                {0.31, -2.0, 0.7},
                                {5.0, 4.0, -3.0},
                                {-0.02, 0.0, 0.01}};
    for (const Vector3d& c : centres) add_ball(s, rng, std::vector<double>(300, r), c, 0.5);
    shuffle(s, rng);
  } else if (name == "mixed_1_to_20") {
    std::vector<double> radii = radii_between(rng, 1500, r, 20 * r);
    for (int k = 0; k < 10; ++k) radii[rng.below(1500)] = 0.0;
    add_box(s, rng, radii, {-0.3, -0.1, -0.2}, 0.4);
  } else if (name == "mixed_log_clustered") {
    add_ball(s, rng, radii_log_between(rng, 700, r, 20 * r), {-0.5, 0.5, -0.5}, 0.5);
    add_ball(s, rng, radii_log_between(rng, 700, r, 20 * r), {-0.45, 0.5, -0.5}, 0.3);
    add_ball(s, rng, radii_log_between(rng, 300, r, 20 * r), {2.0, -3.0, 1.0}, 0.05);
    shuffle(s, rng);
  } else if (name == "few_huge") {
    add_box(s, rng, radii_between(rng, 2000, 0.9 * r, 1.1 * r), {-0.02, -0.02, -0.02}, 0.5);
    const double side = side_for(radii_between(rng, 2000, r, r), 0.5);
    for (int k = 0; k < 6; ++k) s.push_back({in_box(rng, {-0.02, -0.02, -0.02}, side), 20 * r});
    shuffle(s, rng);
  } else if (name == "one_giant") {
    add_box(s, rng, std::vector<double>(1500, r), {0.0, 0.0, 0.0}, 0.4);
    const double side = side_for(std::vector<double>(1500, r), 0.4);
    s.insert(s.begin() + 700, {{-1000 * r + 0.5 * side, 0.5 * side, 0.4 * side}, 1000 * r});
  } else if (name == "flat_layer") {
    for (int k = 0; k < 1500; ++k) {
      s.push_back({{uniform(rng, -0.08, 0.0), uniform(rng, -0.02, 0.05), -0.5}, r});
    }
  } else if (name == "far_offset") {
    add_box(s, rng, radii_between(rng, 1500, 0.5 * r, 2 * r), {-2000.0, 1000.0, -3000.0}, 0.5);
  } else if (name == "outliers") {
    add_box(s, rng, radii_between(rng, 1000, 0.8 * r, 1.2 * r), {-0.05, -0.05, -0.05}, 0.5);
    for (int k = 0; k < 40; ++k) {
      Vector3d dir = in_ball(rng, Vector3d::Zero(), 1.0);
      dir /= dir.norm() + 1e-300;
      s.push_back({std::pow(10.0, uniform(rng, 1.0, 12.0)) * dir, r});
    }
    // Touching clusters far away: their pairs must be found too.
    add_ball(s, rng, std::vector<double>(30, r), {-1e6, 3e5, 1e7}, 0.5);
    add_ball(s, rng, std::vector<double>(30, r), {1e11, -1e11, 1e11}, 0.5);
    add_ball(s, rng, std::vector<double>(30, r), {-2e3, -2e3, 0.0}, 0.5);
    shuffle(s, rng);
  } else if (name == "core_and_tendrils") {
    // A dense core, chains of overlapping bodies reaching out to 4 core widths along
    // +-x, y, z, and a few far bodies: the grid's dense window then covers the core only
    // (fitted to the bulk of the bodies), and the chains touch across its edge.
    const double side = side_for(std::vector<double>(2000, r), 0.5);
    add_box(s, rng, std::vector<double>(2000, r), Vector3d::Constant(-0.5 * side), 0.5);
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {-1.0, 1.0}) {
        for (double d = 0.3 * side; d < 4.0 * side; d += 1.6 * r) {
          Vector3d c = in_ball(rng, Vector3d::Zero(), 0.2 * r);
          c[axis] += sign * d;
          s.push_back({c, r});
        }
      }
    }
    for (int k = 0; k < 5; ++k) s.push_back({in_box(rng, {-1e4, -1e4, -1e4}, 2e4), r});
    shuffle(s, rng);
  } else {
    ADD_FAILURE() << "no scene " << name;
  }
  return sc;
}

class RandomScene : public testing::TestWithParam<std::string> {};

TEST_P(RandomScene, BothMethodsMatchAllPairs) {
  const Scene sc = make_scene(GetParam());
  ASSERT_GT(sc.bodies.size(), 500u);
  std::size_t total = 0;
  for (const double factor : {0.0, 0.1, 1.0, 5.0}) {
    const double margin = factor * sc.scale;
    const std::vector<BodyPair> want = all_pairs(sc.bodies, margin);
    total += want.size();
    for (const SearchMethod m : kMethods) {
      SCOPED_TRACE(std::string(name_of(m)) + " margin " + std::to_string(factor) + " r");
      EXPECT_TRUE(same_pairs(search(m, sc.bodies, margin), want));
    }
  }
  // Every scene has contacts to find: an empty answer could not pass.
  EXPECT_GT(total, sc.bodies.size() / 2);
}

INSTANTIATE_TEST_SUITE_P(NeighbourSearch, RandomScene,
                         testing::Values("equal_dense", "equal_sparse", "equal_clustered",
                                         "mixed_1_to_20", "mixed_log_clustered", "few_huge",
                                         "one_giant", "flat_layer", "far_offset", "outliers",
                                         "core_and_tendrils"),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

TEST(NeighbourSearch, TouchingLatticeHasOnlyItsAxisNeighbours) {
  // Spheres of radius 1/8 on a lattice of spacing 1/4 (all exact in binary), straddling 0:
  // each touches its axis neighbours exactly; diagonals are sqrt2/4 apart. With margin 0
  // there are 3 n^2 (n - 1) pairs; a margin of 0.11 adds the 6 n (n - 1)^2 face diagonals
  // (0.3536 <= 0.36) but not the body diagonals (0.433).
  const int n = 10;
  std::vector<BoundingSphere> s;
  for (int x = 0; x < n; ++x) {
    for (int y = 0; y < n; ++y) {
      for (int z = 0; z < n; ++z) s.push_back({{0.25 * x - 1.0, 0.25 * y - 1.25, 0.25 * z}, 0.125});
    }
  }
  const std::size_t axis = 3 * n * n * (n - 1);
  const std::size_t face = 6 * n * (n - 1) * (n - 1);
  for (const SearchMethod m : kMethods) {
    SCOPED_TRACE(name_of(m));
    const auto touching = search(m, s, 0.0);
    EXPECT_EQ(touching.size(), axis);
    EXPECT_TRUE(same_pairs(touching, all_pairs(s, 0.0)));
    EXPECT_EQ(search(m, s, 0.11).size(), axis + face);
  }
}

// --- edge cases ----------------------------------------------------------------------------

TEST(NeighbourSearch, NoBodyOrOneBodyGivesNoPairs) {
  for (const SearchMethod m : kMethods) {
    EXPECT_TRUE(search(m, {}, 0.0).empty());
    EXPECT_TRUE(search(m, {{{1.0, -2.0, 3.0}, 0.5}}, 1.0).empty());
  }
}

TEST(NeighbourSearch, ExactlyTouchingIsIncludedAndTheNextDoubleApartIsNot) {
  // A 3-4-5 triangle scaled by 1/8: the centres are 0.625 apart and r1 + r2 = 0.625, all
  // exact in binary, also after the shift into negative coordinates.
  for (const double shift : {0.0, -1024.5}) {
    const Vector3d a(shift, shift, shift);
    const Vector3d b = a + Vector3d(0.375, 0.5, 0.0);
    const std::vector<BoundingSphere> touching{{a, 0.25}, {b, 0.375}};
    const std::vector<BoundingSphere> apart{{a, 0.25},
                                            {{std::nextafter(b.x(), 1e9), b.y(), b.z()}, 0.375}};
    // Distance 1.25 = 0.25 + 0.375 + margin 0.625.
    const std::vector<BoundingSphere> by_margin{{a, 0.25}, {a + Vector3d(0.0, 0.75, 1.0), 0.375}};
    for (const SearchMethod m : kMethods) {
      SCOPED_TRACE(name_of(m));
      EXPECT_EQ(search(m, touching, 0.0), (std::vector<BodyPair>{{0, 1}}));
      EXPECT_TRUE(search(m, apart, 0.0).empty());
      EXPECT_EQ(search(m, by_margin, 0.625), (std::vector<BodyPair>{{0, 1}}));
      EXPECT_TRUE(search(m, by_margin, 0.5).empty());
    }
  }
}

TEST(NeighbourSearch, IdenticalCentresPairEveryone) {
  const Vector3d c(-3.0, 0.5, 7.0);
  std::vector<BoundingSphere> s{{c, 0.0}, {c, 1.0}, {{9.0, 9.0, 9.0}, 0.1}, {c, 0.0}, {c, 5.0}};
  const std::vector<BodyPair> want{{0, 1}, {0, 3}, {0, 4}, {1, 3}, {1, 4}, {3, 4}};
  for (const SearchMethod m : kMethods) {
    SCOPED_TRACE(name_of(m));
    EXPECT_EQ(search(m, s, 0.0), want);
  }
}

TEST(NeighbourSearch, ZeroRadiusBodies) {
  // Points only: with margin 0 only coincident points pair; a margin is a reach.
  const std::vector<BoundingSphere> points{{{0.0, 0.0, 0.0}, 0.0},
                                           {{0.25, 0.0, 0.0}, 0.0},
                                           {{0.0, 0.0, 0.0}, 0.0},
                                           {{-2.0, 1.0, 0.0}, 0.0}};
  // A point on a sphere's surface, one just outside, one inside.
  const std::vector<BoundingSphere> on_sphere{{{1.0, 1.0, 1.0}, 0.5},
                                              {{1.0, 1.5, 1.0}, 0.0},
                                              {{1.0, 1.0, std::nextafter(1.5, 2.0)}, 0.0},
                                              {{1.25, 1.0, 1.0}, 0.0}};
  for (const SearchMethod m : kMethods) {
    SCOPED_TRACE(name_of(m));
    EXPECT_EQ(search(m, points, 0.0), (std::vector<BodyPair>{{0, 2}}));
    EXPECT_EQ(search(m, points, 0.25), (std::vector<BodyPair>{{0, 1}, {0, 2}, {1, 2}}));
    EXPECT_EQ(search(m, on_sphere, 0.0), (std::vector<BodyPair>{{0, 1}, {0, 3}}));
  }
}

TEST(NeighbourSearch, ExtremeSizeRatio) {
  // Pebbles (1e-3) scattered around the surface of a boulder 10^6 times larger.
  SplitMix64 rng(17);
  std::vector<BoundingSphere> s;
  const double big = 1000.0;
  for (int k = 0; k < 800; ++k) {
    Vector3d dir = in_ball(rng, Vector3d::Zero(), 1.0);
    dir.z() = std::abs(dir.z()) + 1.0;  // a cap of the boulder
    dir.normalize();
    s.push_back({dir * (big + uniform(rng, -0.01, 0.01)), 1e-3});
  }
  s.insert(s.begin() + 300, {{0.0, 0.0, 0.0}, big});
  for (const double margin : {0.0, 2e-3}) {
    const auto want = all_pairs(s, margin);
    ASSERT_GT(want.size(), 300u);
    for (const SearchMethod m : kMethods) {
      SCOPED_TRACE(name_of(m));
      EXPECT_TRUE(same_pairs(search(m, s, margin), want));
    }
  }
}

TEST(NeighbourSearch, TouchingChainsAtAnyDistance) {
  // Chains of 6 touching unit-diameter spheres (integer centres, exact) along each axis,
  // on both sides, from 10^3 to 10^15 diameters out, including across 2^30, 2^31 and 2^32
  // diameters, where cell indices run out of 32 bits; a random cluster at the origin.
  SplitMix64 rng(5);
  std::vector<BoundingSphere> s;
  for (int k = 0; k < 400; ++k) s.push_back({in_ball(rng, Vector3d::Zero(), 8.0), 0.5});
  for (const double d : {1e3, 0x1p30, 0x1p31, 0x1p32, 1e12, 1e15}) {
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {-1.0, 1.0}) {
        for (int k = -3; k < 3; ++k) {
          Vector3d c = Vector3d::Zero();
          c[axis] = sign * d + k;
          s.push_back({c, 0.5});
        }
      }
    }
  }
  const auto want = all_pairs(s, 0.0);
  for (const SearchMethod m : kMethods) {
    SCOPED_TRACE(name_of(m));
    EXPECT_TRUE(same_pairs(search(m, s, 0.0), want));
  }
}

TEST(NeighbourSearch, RejectsNegativeMarginAndNonFiniteInput) {
  NeighbourSearch grid;
  std::vector<BodyPair> pairs;
  const std::vector<BoundingSphere> ok{{{0.0, 0.0, 0.0}, 1.0}, {{1.0, 0.0, 0.0}, 1.0}};
  EXPECT_THROW(grid.find_pairs(ok, -1e-9, pairs), std::invalid_argument);
  EXPECT_THROW(grid.find_pairs(ok, std::nan(""), pairs), std::invalid_argument);
  const std::vector<BoundingSphere> bad_radius{{{0.0, 0.0, 0.0}, -1.0}, {{1.0, 0.0, 0.0}, 1.0}};
  EXPECT_THROW(grid.find_pairs(bad_radius, 0.0, pairs), std::invalid_argument);
  const std::vector<BoundingSphere> bad_centre{{{0.0, std::nan(""), 0.0}, 1.0}};
  EXPECT_THROW(grid.find_pairs(bad_centre, 0.0, pairs), std::invalid_argument);
}

// --- reuse -----------------------------------------------------------------------------------

TEST(NeighbourSearch, ReusedSearcherFollowsMovingBodies) {
  // One searcher per method over 40 steps: bodies drift and jitter, the count grows and
  // shrinks, and for a while one body flies 10^8 m away (dense grid -> hash table -> dense).
  SplitMix64 rng(99);
  const double r = 1e-3;
  std::vector<BoundingSphere> s;
  add_box(s, rng, radii_between(rng, 900, 0.5 * r, 3 * r), {-0.01, -0.01, -0.01}, 0.5);
  NeighbourSearch basic(SearchMethod::basic);
  NeighbourSearch bbox(SearchMethod::bounding_box);
  std::vector<BodyPair> got_basic, got_bbox;
  for (int step = 0; step < 40; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    for (BoundingSphere& b : s) b.centre += Vector3d(1e-3, -5e-4, 0.0) + in_ball(rng, {0, 0, 0}, r);
    if (step == 10) {
      const Vector3d corner = s[0].centre;  // a copy: add_box grows s
      add_box(s, rng, radii_between(rng, 600, 0.5 * r, 3 * r), corner, 0.5);
    }
    if (step == 20) s.resize(300);
    if (step == 25) s.resize(1200, BoundingSphere{s[5].centre, 2 * r});  // 900 coincident
    if (step == 30) s.resize(800);
    if (step >= 15 && step < 20) s[7].centre = Vector3d(1e8, -1e8, 3e7) * (step - 14);
    if (step == 20) s[7].centre = s[8].centre;
    const double margin = (step % 3) * 0.5 * r;
    const auto want = all_pairs(s, margin);
    ASSERT_FALSE(want.empty());
    basic.find_pairs(s, margin, got_basic);
    bbox.find_pairs(s, margin, got_bbox);
    EXPECT_TRUE(same_pairs(got_basic, want));
    EXPECT_TRUE(same_pairs(got_bbox, want));
  }
}

TEST(NeighbourSearch, RepeatedCallDoesNotAllocate) {
  for (const std::string name : {"equal_dense", "mixed_1_to_20", "outliers"}) {
    const Scene sc = make_scene(name);
    for (const SearchMethod m : kMethods) {
      SCOPED_TRACE(name + " " + name_of(m));
      NeighbourSearch grid(m);
      std::vector<BodyPair> pairs;
      grid.find_pairs(sc.bodies, sc.scale, pairs);
      const auto first = pairs;
      const long before = g_allocations.load();
      grid.find_pairs(sc.bodies, sc.scale, pairs);
      EXPECT_EQ(g_allocations.load() - before, 0);
      EXPECT_EQ(pairs, first);
    }
  }
}

}  // namespace
