// Cracks as surfaces: a transgranular crack's area is its exact cleavage section, an
// intergranular crack's the grain-boundary face its bond stood for. Each is checked against
// the closed form of the hexagonal prism (table 2.2 / App. A of seed 000: side a, thickness
// t): a cut along a <10-10> plane runs through the axis and two opposite corners (t x 2a),
// a <11-20> plane along a short diagonal (t x sqrt(3) a), a basal cut is the hexagon
// (3 sqrt(3) / 2 a^2) and a cut tilted by theta from the basal plane the hexagon over
// cos(theta); two prisms bonded side face to side face share a face of t x a.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/lattice.hpp"
#include "physics/dem/world.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "prism_row.hpp"
#include "sim/crack_tally.hpp"

using namespace cleave;
using namespace cleave::physics;
using geometry::CleavageFamily;
using geometry::CrystalOrientation;
using geometry::ExactPlane;
using geometry::ExactPolyhedron;
using test::kDilation;
using test::kSide;
using test::kThick;

namespace {

/// The prism's corners are rounded doubles (cos and sin of multiples of 60 degrees), so the
/// exact sections match the closed forms of the ideal prism to a few ulps.
constexpr double kRel = 1e-14;

const double kHexagon = 1.5 * std::sqrt(3.0) * kSide * kSide;

/// The closed-form section of a prism plane of `family` through the prism's corners.
double cleavage_section(CleavageFamily family) {
  return family == CleavageFamily::m_10_10 ? kThick * 2.0 * kSide : kThick * std::sqrt(3.0) * kSide;
}

struct Orientations : ::testing::TestWithParam<CrystalOrientation> {};

}  // namespace

TEST_P(Orientations, CrackAreaOfEachCleavagePlaneCutIsTheClosedFormSection) {
  const CrystalOrientation o = GetParam();
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(kSide, kThick);
  const auto planes = prism.cleavage_planes(o);
  ASSERT_EQ(planes.size(), o.family == CleavageFamily::m_10_10 ? 1u : 2u);
  for (const ExactPlane& plane : planes) {
    const geometry::SplitResult cut = prism.split(plane);
    ASSERT_TRUE(cut.ok()) << cut.reason;
    const double want = cleavage_section(o.family);
    // The piece below has the section with its outward normal along the plane's; the
    // piece above along the opposite plane's; neither on the other orientation.
    EXPECT_NEAR(cut.below->area_on(plane), want, kRel * want);
    EXPECT_NEAR(cut.above->area_on(plane.opposite()), want, kRel * want);
    EXPECT_EQ(cut.above->area_on(plane), 0.0);
    EXPECT_EQ(cut.below->area_on(plane.opposite()), 0.0);
    // The intact prism has no face on a cleavage plane.
    EXPECT_EQ(prism.area_on(plane), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(CrackArea, Orientations,
                         ::testing::Values(CrystalOrientation{CleavageFamily::m_10_10, 0},
                                           CrystalOrientation{CleavageFamily::m_10_10, 60},
                                           CrystalOrientation{CleavageFamily::m_10_10, 120},
                                           CrystalOrientation{CleavageFamily::a_11_20, 0},
                                           CrystalOrientation{CleavageFamily::a_11_20, 60},
                                           CrystalOrientation{CleavageFamily::a_11_20, 120}));

TEST(CrackArea, BasalCutIsTheHexagonAndATiltedCutTheHexagonOverTheCosine) {
  const ExactPolyhedron prism = ExactPolyhedron::hexagonal_prism(kSide, kThick);
  const ExactPlane basal = ExactPlane::from_normal_offset({0.0, 0.0, 1.0}, 0.0);
  const geometry::SplitResult flat = prism.split(basal);
  ASSERT_TRUE(flat.ok());
  EXPECT_NEAR(flat.below->area_on(basal), kHexagon, kRel * kHexagon);
  // The prism's own top face lies on z = t/2 with its outward normal +z.
  EXPECT_NEAR(prism.area_on(ExactPlane::from_normal_offset({0.0, 0.0, 1.0}, kThick / 2.0)),
              kHexagon, kRel * kHexagon);
  // Normal (1, 0, 2): cos(theta) = 2 / sqrt(5); the plane z = -x/2 stays within
  // +-sqrt(3)/4 a < t/2, so it crosses the six side faces and its section projects onto the
  // hexagon. Its
  // dominant axis is z but |n| / n_z is not 1: the square root of the exact path.
  const ExactPlane tilted = ExactPlane::from_normal_offset({1.0, 0.0, 2.0}, 0.0);
  const geometry::SplitResult cut = prism.split(tilted);
  ASSERT_TRUE(cut.ok());
  const double want = kHexagon * std::sqrt(5.0) / 2.0;
  EXPECT_NEAR(cut.below->area_on(tilted), want, kRel * want);
  // A plane tilted the other way, steeper than 45 degrees (dominant axis y): normal
  // (0, 2, 1) through the centre, y = -z/2, within +-t/4 = +-a/2 of the axis. The hexagon's
  // corners point along y (corner 0 at (0, a)), so for |y| <= a/2 it is sqrt(3) a wide in x,
  // and the section is sqrt(3) a by the line's length over |z| <= t/2, t sqrt(5) / 2.
  const ExactPlane steep = ExactPlane::from_normal_offset({0.0, 2.0, 1.0}, 0.0);
  const geometry::SplitResult across = prism.split(steep);
  ASSERT_TRUE(across.ok());
  ASSERT_NEAR(geometry::hexagon_corner(kSide, 0).x(), 0.0, 1e-20);
  ASSERT_NEAR(geometry::hexagon_corner(kSide, 0).y(), kSide, 1e-20);
  const double steep_want = std::sqrt(3.0) * kSide * kThick * std::sqrt(5.0) / 2.0;
  EXPECT_NEAR(across.below->area_on(steep), steep_want, kRel * steep_want);
}

namespace {

struct Rig {
  World world{settings()};
  FractureBook book{kDilation, 0.01};
  std::shared_ptr<const ExactPolyhedron> prism =
      std::make_shared<const ExactPolyhedron>(ExactPolyhedron::hexagonal_prism(kSide, kThick));
  std::uint32_t shape = world.add_shape(make_rigid_shape(*prism, kDilation));
  Rig() { book.add_shape(shape, prism); }
  static WorldSettings settings() {
    WorldSettings ws;
    ws.gravity.setZero();
    ws.threads = 1;
    return ws;
  }
  BodyId grain(int id, const Eigen::Vector3d& x, CrystalOrientation o) {
    const BodyId b = world.add_body(shape, test::kRho, x, world.shape(shape).orientation_for(),
                                    Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), id);
    book.add_grain(world, b, id, o);
    return b;
  }
};

}  // namespace

TEST(CrackArea, AGrainSplitTwiceCarriesTheSumOfItsTwoSectionsAndWhenEachOpened) {
  // A <11-20> grain: its two short-diagonal planes each cut once (the second cuts only one
  // of the first's pieces), t sqrt(3) a each.
  Rig s;
  const BodyId g = s.grain(7, {0, 0, 0}, {CleavageFamily::a_11_20, 60});
  const BodyId other = s.grain(8, {5e-3, 0, 0}, {CleavageFamily::m_10_10, 0});
  const double section = cleavage_section(CleavageFamily::a_11_20);
  EXPECT_EQ(s.book.grain_section_area(s.world, 7), 0.0);
  s.world.step();
  const SplitEvent first = s.book.split(s.world, g, 0);
  ASSERT_EQ(first.ids.size(), 2u);
  EXPECT_NEAR(first.section_area, section, kRel * section);
  EXPECT_NEAR(s.book.grain_section_area(s.world, 7), section, kRel * section);
  const double t1 = first.time;
  s.world.step();
  s.world.step();
  double t2 = -1.0;
  for (const BodyId piece : first.ids) {
    const SplitEvent second = s.book.split(s.world, piece, 1);
    if (second.ids.empty()) continue;
    EXPECT_NEAR(second.section_area, section, kRel * section);
    t2 = second.time;
    // Each of its pieces opened along plane 0 at the first split, along plane 1 at this one
    // (NaN for a plane no cut of its lineage ran along).
    for (const BodyId id : second.ids) {
      EXPECT_EQ(s.book.opened_at(id, 0), t1);
      EXPECT_EQ(s.book.opened_at(id, 1), t2);
    }
  }
  ASSERT_GT(t2, t1);
  EXPECT_NEAR(s.book.grain_section_area(s.world, 7), 2.0 * section, kRel * section);
  // Drawn once each: summed over the live pieces, the faces below each plane are the sections.
  double drawn = 0.0;
  for (const auto& e : s.book.entries(s.world)) {
    if (e.lineage.grain_id != 7) continue;
    for (int k = 0; k < 2; ++k) drawn += s.book.section_area(e.id, k);
  }
  EXPECT_NEAR(drawn, 2.0 * section, kRel * section);
  EXPECT_EQ(s.book.grain_section_area(s.world, 8), 0.0);
  EXPECT_TRUE(std::isnan(s.book.opened_at(other, 0)));
}

TEST(CrackArea, ABrokenBondCarriesItsGrainBoundaryFaceEdgeTimesHeight) {
  // Two prisms side face to side face share a rectangle of the side a by the thickness t;
  // the bond's face area is that rectangle's, and so is its break's.
  WorldSettings ws = test::prism_settings(1e-7);
  World world(ws);
  const auto ids = test::row(world, 2, 2e-6);
  const double area = M_PI * kDilation * kDilation;
  ASSERT_EQ(world.initialise_bonds({5000.0 / area, 2000.0 / area, 1000.0, 1000.0}, 0.0), 1u);
  world.set_fixed(ids[0], true);
  world.set_fixed(ids[1], true);
  world.state(ids[1]).v = {1.0, 0.0, 0.0};  // opens the bond far past its tensile limit
  for (int i = 0; i < 400 && world.bond_breaks().empty(); ++i) world.step();
  ASSERT_EQ(world.bond_breaks().size(), 1u);
  const double face = kSide * kThick;
  EXPECT_NEAR(world.bond_breaks().front().face_area, face, 1e-9 * face);
  sim::CrackTally tally;
  tally.add_breaks(world);
  const sim::CrackTotals c = tally.totals();
  EXPECT_EQ(c.intergranular, 1u);
  EXPECT_NEAR(c.intergranular_area, face, 1e-9 * face);
  EXPECT_EQ(c.transgranular_area_fraction(), 0.0);
  EXPECT_EQ(c.intergranular_area_fraction(), 1.0);
}

TEST(CrackArea, FractionsOfBothKindsSumToOneAndAreNoneBeforeTheFirstCrack) {
  sim::CrackTotals none;
  EXPECT_FALSE(none.transgranular_area_fraction());
  EXPECT_FALSE(none.intergranular_area_fraction());
  EXPECT_FALSE(none.transgranular_count_fraction());
  // Areas over many decades: each fraction is its kind's share of the whole to an ulp, and
  // the two sum to one, exactly.
  constexpr double kUlp = 2.3e-16;
  for (double inter : {0.0, 1e-12, 3.7e-9, 1e-6, 0.25, 0.3}) {
    for (double trans : {0.0, 2.2e-10, 5e-7, 0.1, 1.0}) {
      if (inter + trans == 0.0) continue;
      const sim::CrackTotals c{inter, trans, 3, 1};
      EXPECT_NEAR(*c.transgranular_area_fraction(), trans / (inter + trans), kUlp);
      EXPECT_NEAR(*c.intergranular_area_fraction(), inter / (inter + trans), kUlp);
      EXPECT_EQ(*c.transgranular_area_fraction() + *c.intergranular_area_fraction(), 1.0);
      EXPECT_EQ(*c.transgranular_count_fraction(), 0.25);
      EXPECT_EQ(*c.intergranular_count_fraction(), 0.75);
    }
  }
  // Counts whose fractions do not round exactly: still one.
  for (std::size_t n = 1; n < 200; ++n) {
    const sim::CrackTotals c{0.0, 0.0, n, 7};
    EXPECT_EQ(*c.transgranular_count_fraction() + *c.intergranular_count_fraction(), 1.0) << n;
  }
}
