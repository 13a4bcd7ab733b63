// Fragment statistics: the Rosin-Rammler and power-law fits recover the parameters of samples
// drawn from those laws (fixed seeds); fragments are the clusters of bodies joined by intact
// bonds, counted against hand-built graphs and a hand-built bonded world; a run's fragment
// volumes sum to its specimen's (closed-form prism volumes).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <vector>

#include "cli_helpers.hpp"
#include "folder_test.hpp"
#include "io/fragment_sizes.hpp"
#include "io/result_dir.hpp"
#include "prism_row.hpp"
#include "sim/fragments.hpp"

using namespace cleave;
namespace fs = std::filesystem;

namespace {

/// Fragments whose mass is Rosin-Rammler distributed over d: for a mass ~ d^3 the number
/// density is f_N(d) ~ d^-3 f_RR(d), i.e. u = (d/d0)^n is Gamma(1 - 3/n) distributed (n > 3).
std::vector<io::FragmentRecord> rosin_rammler_fragments(double d0, double n, std::size_t count,
                                                        unsigned seed) {
  std::mt19937_64 rng(seed);
  std::gamma_distribution<double> gamma(1.0 - 3.0 / n, 1.0);
  std::vector<io::FragmentRecord> out;
  for (std::size_t i = 0; i < count; ++i) {
    const double d = d0 * std::pow(gamma(rng), 1.0 / n);
    const double v = M_PI * d * d * d / 6.0;
    out.push_back({1, v, 2500.0 * v});
  }
  return out;
}

}  // namespace

// Each draw of a Rosin-Rammler (Weibull) law is a unit of mass at its size (a sieve's
// sample). With 20,000 draws the maximum likelihood's standard errors are about 0.6 % of n
// and 1.1 % / n of d0: 4 % is over three of them.
TEST(RosinRammlerFit, RecoversD0AndNOfUnitMassesDrawnFromTheLaw) {
  for (const auto& [d0, n, seed] :
       {std::tuple{5e-4, 0.8, 11u}, std::tuple{2e-3, 1.5, 12u}, std::tuple{1e-2, 3.0, 13u}}) {
    std::mt19937_64 rng(seed);
    std::weibull_distribution<double> law(n, d0);
    std::vector<double> d, w;
    for (int i = 0; i < 20000; ++i) {
      d.push_back(law(rng));
      w.push_back(1.0);
    }
    const auto fit = io::fit_rosin_rammler(d, w);
    ASSERT_TRUE(fit.has_value()) << "n = " << n;
    EXPECT_NEAR(fit->d0 / d0, 1.0, 0.04) << "n = " << n;
    EXPECT_NEAR(fit->n / n, 1.0, 0.04) << "n = " << n;
  }
}

// Fragments, each of mass rho pi d^3 / 6, drawn so that their mass is Rosin-Rammler
// distributed: the fit of the run's table recovers the law. Mass-weighting leaves an
// effective sample of 30 % (n = 4) and 64 % (n = 6) of the 20,000 fragments.
TEST(RosinRammlerFit, RecoversTheLawOfTheMassOfFragmentsDrawnFromIt) {
  for (const auto& [d0, n, seed] : {std::tuple{2e-3, 4.0, 21u}, std::tuple{3e-4, 6.0, 22u}}) {
    const io::FragmentSizes s =
        io::analyse_fragment_sizes(rosin_rammler_fragments(d0, n, 20000, seed));
    ASSERT_TRUE(s.rosin_rammler.has_value()) << "n = " << n;
    EXPECT_NEAR(s.rosin_rammler->d0 / d0, 1.0, 0.04) << "n = " << n;
    EXPECT_NEAR(s.rosin_rammler->n / n, 1.0, 0.04) << "n = " << n;
  }
}

TEST(RosinRammlerFit, ThePassingFractionIsTheMassOfFragmentsNoLargerThanEachOne) {
  // Three fragments of 1, 8 and 8 (equal) and 27 units of volume: mass passing 1/44, 17/44,
  // 17/44 (ties share the fraction through both), 1.
  const double u = 1e-9;
  const io::FragmentSizes s = io::analyse_fragment_sizes(
      {{3, 27 * u, 27.0}, {1, 1 * u, 1.0}, {2, 8 * u, 8.0}, {2, 8 * u, 8.0}});
  ASSERT_EQ(s.passing.size(), 4u);
  EXPECT_DOUBLE_EQ(s.passing[0], 1.0 / 44);
  EXPECT_DOUBLE_EQ(s.passing[1], 17.0 / 44);
  EXPECT_DOUBLE_EQ(s.passing[2], 17.0 / 44);
  EXPECT_DOUBLE_EQ(s.passing[3], 1.0);
  EXPECT_DOUBLE_EQ(s.largest_mass_fraction, 27.0 / 44);
  EXPECT_NEAR(s.diameter[0], std::cbrt(6e-9 / M_PI), 1e-18);
  // A single size has no spread to fit.
  EXPECT_FALSE(io::analyse_fragment_sizes({{1, u, 1.0}, {1, u, 1.0}}).rosin_rammler.has_value());
}

// N(>d) = (d/d_min)^-b above d_min (Pareto), and below it a head that is no power law
// (log-uniform over a decade): the scaling range found starts near d_min, and b is the
// tail's within 6 % (the maximum likelihood's standard error b/sqrt(k) is 1.4 % for k =
// 5000).
TEST(PowerLawFit, RecoversTheExponentAndTheStartOfTheScalingRange) {
  for (const auto& [b, seed] : {std::pair{2.5, 21u}, std::pair{1.2, 22u}}) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const double d_min = 1e-3;
    std::vector<double> d;
    for (int i = 0; i < 5000; ++i) d.push_back(d_min * std::pow(1.0 - uni(rng), -1.0 / b));
    const io::PowerLawFit pure = io::fit_power_law(d).value();
    EXPECT_NEAR(pure.b / b, 1.0, 0.06);
    for (int i = 0; i < 3000; ++i) d.push_back(d_min * std::pow(10.0, -uni(rng)));
    const io::PowerLawFit fit = io::fit_power_law(d).value();
    EXPECT_NEAR(fit.b / b, 1.0, 0.06) << "b = " << b;
    EXPECT_GT(fit.d_min, 0.8 * d_min);
    EXPECT_LT(fit.d_min, 1.25 * d_min);
  }
  EXPECT_FALSE(io::fit_power_law({1.0, 1.0, 1.0}).has_value());
}

TEST(BondedFragments, ClustersAreTheConnectedComponentsOfTheLinks) {
  // 0-1-2 a chain, 3 alone, 4-5 and 5-6 and 6-4 a ring, 7-8 with the link given twice.
  const auto c =
      sim::connected_clusters(9, {{1, 2}, {0, 1}, {5, 6}, {4, 5}, {6, 4}, {8, 7}, {7, 8}});
  const std::vector<std::vector<std::uint32_t>> expected{{0, 1, 2}, {3}, {4, 5, 6}, {7, 8}};
  EXPECT_EQ(c, expected);
  EXPECT_EQ(sim::connected_clusters(3, {}).size(), 3u);
  EXPECT_THROW(sim::connected_clusters(2, {{0, 2}}), std::out_of_range);
}

TEST(BondedFragments, BodiesJoinedByIntactBondsAreOneFragmentAndABrokenBondParts) {
  using namespace cleave::test;
  physics::World world(prism_settings(1e-8));
  // A row of four touching prisms (three bonds) and, far away, a lone prism.
  const auto ids = row(world, 4);
  const physics::RigidShape shape = prism();
  world.add_body(0, kRho, {0, 0.05, 0}, shape.orientation_for());
  ASSERT_EQ(world.initialise_bonds(strong_bonds(), 1e-6), 3u);
  const geometry::ExactScalar one =
      geometry::ExactPolyhedron::hexagonal_prism(kSide, kThick).volume();
  auto volume = [&](std::uint32_t) { return one; };
  const double prism_volume = 1.5 * std::sqrt(3.0) * kSide * kSide * kThick;
  auto bodies = [](const std::vector<sim::BondedFragment>& f) {
    std::multiset<std::size_t> n;
    for (const auto& x : f) n.insert(x.slots.size());
    return n;
  };
  auto fragments = sim::bonded_fragments(world, volume);
  EXPECT_EQ(bodies(fragments), (std::multiset<std::size_t>{1, 4}));
  for (const auto& f : fragments) {
    EXPECT_NEAR(f.mass, kRho * prism_volume * f.slots.size(), 1e-9 * kRho * prism_volume);
    geometry::ExactScalar sum;
    for (std::size_t k = 0; k < f.slots.size(); ++k) sum = sum + one;
    EXPECT_TRUE(f.volume == sum);
  }
  // Break the middle bond: pull the last two prisms away from the first two, on a bond of
  // next to no strength.
  for (std::size_t k = 0; k < world.bonds().size(); ++k) {
    const auto& b = world.bonds()[k];
    if (b.a == ids[1].index || b.b == ids[1].index) {
      if ((b.a == ids[1].index ? b.b : b.a) == ids[2].index) world.set_bond_strength(k, 1e-12);
    }
  }
  world.state(ids[2]).v = {1.0, 0, 0};
  world.state(ids[3]).v = {1.0, 0, 0};
  world.step();
  ASSERT_EQ(world.bond_counts().broken(), 1u);
  fragments = sim::bonded_fragments(world, volume);
  EXPECT_EQ(bodies(fragments), (std::multiset<std::size_t>{1, 2, 2}));
}

// A bonded disc hit by a plate, with transgranular fracture: the fragments' volumes in
// fragment_sizes.csv sum to the grains' (closed form 3 sqrt(3)/2 r^2 t each), and the run
// checks the same sum exactly.
class FragmentOutputs : public cleave::testing::FolderTest {};

TEST_F(FragmentOutputs, TheFragmentsOfARunSumToTheSpecimensVolume) {
  const auto r = cleave::testing::run_cleave(
      fmt::format("run {}/scenarios/impact.toml --out {} --quiet --set specimen.diameter=6 --set dynamics.dt=1.2e-5 "
                  "--set 'stage[2].rate_scale=8' --set 'stage[2].time=0.2'",
                  CLEAVE_SOURCE_DIR, (dir_ / "run").string()));
  ASSERT_EQ(r.code, 0) << r.output;
  const io::Manifest m = io::read_manifest((dir_ / "run"));
  const auto cells = cleave::testing::read_csv_cells((dir_ / "run") / "fragment_sizes.csv");
  ASSERT_GE(cells.size(), 2u);
  EXPECT_EQ(cells[0][1], "volume_m3");
  EXPECT_EQ(std::to_string(cells.size() - 1), m.facts.at("fragments.count"));
  double volume = 0;
  std::size_t bodies = 0;
  for (std::size_t i = 1; i < cells.size(); ++i) {
    bodies += std::stoul(cells[i][0]);
    volume += std::stod(cells[i][1]);
  }
  const double r_bar = 0.5e-3, t_bar = 5e-3;
  const double grains = std::stod(m.facts.at("grains"));
  EXPECT_NEAR(volume / (grains * 1.5 * std::sqrt(3.0) * r_bar * r_bar * t_bar), 1.0, 1e-12);
  EXPECT_GE(bodies, static_cast<std::size_t>(grains));
  EXPECT_EQ(m.facts.at("fragments.volume_equals_specimen"), "true");
  EXPECT_TRUE(fs::exists((dir_ / "run") / "fragment_sizes.svg"));
}

// A sweep over two impact speeds and two seeds: each speed is a group whose two seeds are
// pooled; the pooled table holds exactly the fragments of its runs' tables.
TEST_F(FragmentOutputs, ASweepPoolsEachCombinationsSeedsAsReplicates) {
  const fs::path out = dir_ / "sweep";
  const auto r = cleave::testing::run_cleave(fmt::format(
      "sweep {}/scenarios/impact.toml -o {} --quiet --jobs 2 --set specimen.diameter=6 "
      "--set dynamics.dt=1.2e-5 --set 'stage[2].time=0.2' --set 'stage[2].rate_scale=4,8' "
      "--set orientation.seed=1,2",
      CLEAVE_SOURCE_DIR, out.string()));
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rows = cleave::testing::read_csv_cells(out / "fragments_pooled.csv");
  ASSERT_EQ(rows.size(), 3u);  // header, two speeds
  EXPECT_EQ(rows[0][0], "group");
  EXPECT_EQ(rows[0][2], "fragments");
  const auto pooled = cleave::testing::read_csv_cells(out / "fragment_sizes_pooled.csv");
  // Runs 1-2 are rate_scale 4 (seeds 1, 2), runs 3-4 rate_scale 8.
  for (int g = 0; g < 2; ++g) {
    EXPECT_EQ(rows[g + 1][0], fmt::format("stage[2].rate_scale={}", g == 0 ? 4 : 8));
    EXPECT_EQ(rows[g + 1][1], "2");
    std::size_t count = 0;
    for (int k = 1; k <= 2; ++k)
      count += std::stoul(
          io::read_manifest(out / fmt::format("run_{:03}", 2 * g + k)).facts.at("fragments.count"));
    EXPECT_EQ(rows[g + 1][2], std::to_string(count));
    const auto in_group = std::count_if(pooled.begin(), pooled.end(),
                                        [&](const auto& row) { return row[0] == rows[g + 1][0]; });
    EXPECT_EQ(static_cast<std::size_t>(in_group), count);
  }
  EXPECT_TRUE(fs::exists(out / "fragments_pooled.svg"));
}
