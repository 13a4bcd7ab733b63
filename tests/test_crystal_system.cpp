// A grain's crystal in 3D: plane families against crystallography's closed forms, exact
// cleavage planes against the rotated crystal normals, and exact volume through every cut.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/crystal_system.hpp"
#include "geometry/orientation.hpp"
#include "geometry/specimen.hpp"
#include "geometry/voronoi.hpp"

using namespace cleave::geometry;

namespace {

constexpr double kDeg = M_PI / 180.0;

CrystalLattice lattice(CrystalSystem s, double c_over_a = 1.0, double b_over_a = 1.0) {
  return {s, b_over_a, c_over_a};
}

std::size_t count(CrystalSystem s, const std::string& family, double c_over_a = 1.6) {
  const double c = s == CrystalSystem::cubic ? 1.0 : c_over_a;
  const double b = s == CrystalSystem::orthorhombic ? 1.3 : 1.0;
  return family_normals(lattice(s, c, b), parse_miller_family(family, s)).size();
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// The Bunge rotation written out (crystal -> specimen is g^T with g = Rz(phi2) Rx(Phi) Rz(phi1)).
Eigen::Matrix3d bunge_crystal_to_specimen(double phi1, double Phi, double phi2) {
  const double c1 = std::cos(phi1), s1 = std::sin(phi1), c = std::cos(Phi), s = std::sin(Phi);
  const double c2 = std::cos(phi2), s2 = std::sin(phi2);
  Eigen::Matrix3d g;
  g << c1 * c2 - s1 * s2 * c, s1 * c2 + c1 * s2 * c, s2 * s,  //
      -c1 * s2 - s1 * c2 * c, -s1 * s2 + c1 * c2 * c, c2 * s,  //
      s1 * s, -c1 * s, c;
  return g.transpose();
}

/// A cubic crystal with these families, each `per_variant` planes a variant.
CrystalDef cubic_crystal(std::initializer_list<const char*> families, int per_variant = 1) {
  CrystalDef crystal;
  crystal.enabled = true;
  crystal.lattice = lattice(CrystalSystem::cubic);
  for (const char* f : families)
    crystal.families.push_back({parse_miller_family(f, CrystalSystem::cubic), 1.0, per_variant});
  return crystal;
}

ExactPolyhedron a_voronoi_cell() {
  VoronoiDef v;
  v.size = {2e-3, 2e-3, 2e-3};
  v.cells = 6;
  v.seed = 5;
  return voronoi_cells(v).at(2);
}

}  // namespace

TEST(CrystalFamilies, EachFamilyHasTheDistinctPlanesOfItsSymmetry) {
  // Textbook multiplicities halved (a plane and its opposite are one cleavage plane).
  EXPECT_EQ(count(CrystalSystem::cubic, "{100}"), 3u);
  EXPECT_EQ(count(CrystalSystem::cubic, "{110}"), 6u);
  EXPECT_EQ(count(CrystalSystem::cubic, "{111}"), 4u);
  EXPECT_EQ(count(CrystalSystem::hexagonal, "{0001}"), 1u);
  EXPECT_EQ(count(CrystalSystem::hexagonal, "{10-10}"), 3u);
  EXPECT_EQ(count(CrystalSystem::hexagonal, "{11-20}"), 3u);
  EXPECT_EQ(count(CrystalSystem::hexagonal, "{10-11}"), 6u);
  // Corundum: the rhombohedron r {10-12} has six faces, three planes; basal one.
  EXPECT_EQ(count(CrystalSystem::trigonal, "{10-12}", 2.730), 3u);
  EXPECT_EQ(count(CrystalSystem::trigonal, "{0001}", 2.730), 1u);
  EXPECT_EQ(count(CrystalSystem::trigonal, "{11-20}", 2.730), 3u);
  EXPECT_EQ(count(CrystalSystem::orthorhombic, "{100}"), 1u);
  EXPECT_EQ(count(CrystalSystem::orthorhombic, "{110}"), 2u);
  EXPECT_EQ(count(CrystalSystem::orthorhombic, "{111}"), 4u);
}

TEST(CrystalFamilies, NormalsMatchCrystallographysClosedForms) {
  const auto cubic = lattice(CrystalSystem::cubic);
  const auto n100 = plane_normal(cubic, parse_miller_family("{100}", CrystalSystem::cubic));
  const auto n111 = plane_normal(cubic, parse_miller_family("{111}", CrystalSystem::cubic));
  EXPECT_NEAR(angle_between(n100, n111), std::acos(1.0 / std::sqrt(3.0)), 1e-14);
  // Hexagonal with a1 along x: {11-20} normals along the a axes (0, 60, 120 deg), {10-10}
  // normals between them (30, 90, 150 deg), both in the basal plane.
  const auto hex = lattice(CrystalSystem::hexagonal, 1.633);
  for (const auto& [family, first] : {std::pair{"{11-20}", 0.0}, std::pair{"{10-10}", 30.0}}) {
    const auto normals = family_normals(hex, parse_miller_family(family, CrystalSystem::hexagonal));
    ASSERT_EQ(normals.size(), 3u);
    for (const auto& n : normals) {
      EXPECT_NEAR(n.z(), 0.0, 1e-15);
      const double azimuth = std::fmod(std::atan2(n.y(), n.x()) / kDeg + 360.0, 60.0);
      EXPECT_NEAR(std::min(std::abs(azimuth - first), 60.0 - std::abs(azimuth - first)), 0.0, 1e-9) << family;
    }
  }
  // (hkil) against the c axis: tan(phi) = (2 / sqrt 3) (c/a) sqrt(h^2 + hk + k^2) / l. For
  // corundum's r plane (c/a = 2.730) that is the 57.6 deg between the r and c planes of sapphire.
  const auto corundum = lattice(CrystalSystem::trigonal, 2.730);
  const auto r = plane_normal(corundum, parse_miller_family("{10-12}", CrystalSystem::trigonal));
  const double phi = angle_between(r, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(std::tan(phi), 2.0 / std::sqrt(3.0) * 2.730 * 1.0 / 2.0, 1e-12);
  EXPECT_NEAR(phi / kDeg, 57.6, 0.05);
  // Orthorhombic (110) lies at atan(a/b) from (100) (a = 1, b = 1.3: the normal (1/a, 1/b, 0)).
  const auto ortho = lattice(CrystalSystem::orthorhombic, 0.9, 1.3);
  const auto n110 = plane_normal(ortho, parse_miller_family("{110}", CrystalSystem::orthorhombic));
  EXPECT_NEAR(angle_between(n110, Eigen::Vector3d::UnitX()), std::atan(1.0 / 1.3), 1e-14);
}

TEST(CrystalFamilies, MalformedIndicesAreRefusedSayingWhy) {
  EXPECT_THROW(parse_miller_family("{1-10}", CrystalSystem::hexagonal), std::invalid_argument);  // 3 for hkil
  EXPECT_THROW(parse_miller_family("{1100}", CrystalSystem::hexagonal), std::invalid_argument);  // i != -(h+k)
  EXPECT_THROW(parse_miller_family("{000}", CrystalSystem::cubic), std::invalid_argument);
  EXPECT_THROW(parse_miller_family("110", CrystalSystem::cubic), std::invalid_argument);
  EXPECT_THROW(parse_miller_family("{1a0}", CrystalSystem::cubic), std::invalid_argument);
  try {
    parse_miller_family("{1100}", CrystalSystem::trigonal);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("-(h + k)"), std::string::npos) << e.what();
  }
}

TEST(CrystalCleavagePlanes, ExactNormalsAgreeWithTheRotatedCrystalNormalsWithin1e9Rad) {
  const ExactPolyhedron cell = a_voronoi_cell();
  CrystalDef crystal;
  crystal.enabled = true;
  crystal.lattice = lattice(CrystalSystem::trigonal, 2.730);
  for (const char* f : {"{0001}", "{10-12}", "{11-20}", "{10-10}"})
    crystal.families.push_back({parse_miller_family(f, CrystalSystem::trigonal), 1.0, 1});
  const double phi1 = 37.0 * kDeg, Phi = 71.0 * kDeg, phi2 = 203.0 * kDeg;
  const CleavagePlanes planes = crystal_cleavage_planes(cell, crystal, from_bunge(phi1, Phi, phi2));
  ASSERT_EQ(planes.planes.size(), 1u + 3u + 3u + 3u);
  // The crystal normals written out: basal z; r planes at 57.6 deg from it every 120 deg of
  // azimuth from 30 deg; a planes along the a axes; m planes between them.
  const double rho = std::atan(2.0 / std::sqrt(3.0) * 2.730 / 2.0);
  std::vector<std::vector<Eigen::Vector3d>> expected(4);
  expected[0] = {Eigen::Vector3d::UnitZ()};
  for (int k = 0; k < 3; ++k) {
    const double az = (30.0 + 120.0 * k) * kDeg;
    expected[1].push_back({std::sin(rho) * std::cos(az), std::sin(rho) * std::sin(az), std::cos(rho)});
    expected[2].push_back({std::cos(60.0 * k * kDeg), std::sin(60.0 * k * kDeg), 0.0});
    expected[3].push_back({std::cos((30.0 + 60.0 * k) * kDeg), std::sin((30.0 + 60.0 * k) * kDeg), 0.0});
  }
  const Eigen::Matrix3d r = bunge_crystal_to_specimen(phi1, Phi, phi2);
  for (std::size_t i = 0; i < planes.planes.size(); ++i) {
    const Eigen::Vector3d n = planes.planes[i].normal_approx();
    double best = M_PI;
    for (const auto& e : expected.at(static_cast<std::size_t>(planes.family[i]))) {
      const Eigen::Vector3d want = r * e;
      best = std::min({best, angle_between(n, want), angle_between(n, -want)});
    }
    EXPECT_LT(best, 1e-9) << "plane " << i << " family " << planes.family[i];
  }
}

TEST(CrystalCleavagePlanes, PlanesSitAtTheirFractionOfTheGrainsExtent) {
  const ExactPolyhedron cell = a_voronoi_cell();
  const CrystalDef crystal = cubic_crystal({"{111}"}, 2);
  const Eigen::Quaterniond q = from_bunge(10 * kDeg, 20 * kDeg, 30 * kDeg);
  const CleavagePlanes planes = crystal_cleavage_planes(cell, crystal, q);
  ASSERT_EQ(planes.planes.size(), 8u);
  for (std::size_t i = 0; i < planes.planes.size(); ++i) {
    const Eigen::Vector3d n = planes.planes[i].normal_approx();
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& v : cell.vertices_approx()) {
      lo = std::min(lo, v.dot(n));
      hi = std::max(hi, v.dot(n));
    }
    const double at = (planes.planes[i].offset_approx() - lo) / (hi - lo);
    EXPECT_NEAR(at, i % 2 == 0 ? 1.0 / 3.0 : 2.0 / 3.0, 1e-9);
  }
}

TEST(CrystalCleavagePlanes, CuttingAGrainOnEveryPlaneInTurnKeepsItsExactVolume) {
  // Each plane cuts every piece it reaches (pieces split again on the remaining planes); the
  // pieces' exact volumes sum to the grain's exactly and each piece is a valid convex solid.
  const ExactPolyhedron cell = a_voronoi_cell();
  const CrystalDef crystal = cubic_crystal({"{100}", "{111}"});
  const CleavagePlanes planes =
      crystal_cleavage_planes(cell, crystal, from_bunge(123 * kDeg, 45 * kDeg, 67 * kDeg));
  std::vector<ExactPolyhedron> pieces{cell};
  for (const ExactPlane& plane : planes.planes) {
    std::vector<ExactPolyhedron> next;
    for (const ExactPolyhedron& p : pieces) {
      SplitResult r = p.split(plane);
      if (!r.ok()) {
        next.push_back(p);
        continue;
      }
      next.push_back(std::move(*r.below));
      next.push_back(std::move(*r.above));
    }
    pieces = std::move(next);
  }
  EXPECT_GT(pieces.size(), 8u);
  EXPECT_TRUE(total_volume(pieces) == cell.volume());
  for (const auto& p : pieces) EXPECT_TRUE(p.is_valid_convex());
}

TEST(SpecimenCrystals, TheHoneycombCrystalTurnsAboutZByItsDrawnAngle) {
  SpecimenDef def;
  def.outline = Outline::box(8e-3, 8e-3, 1e-3);
  const Specimen s = build_specimen(def);
  ASSERT_FALSE(s.grains.empty());
  for (const Grain& g : s.grains) {
    const Eigen::Vector3d c = g.crystal * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(c.z(), 1.0, 1e-15);
    const Eigen::Vector3d a = g.crystal * Eigen::Vector3d::UnitX();
    EXPECT_NEAR(std::atan2(a.y(), a.x()), g.orientation.angle_deg * kDeg, 1e-12);
  }
}

TEST(SpecimenCrystals, A3DCrystalGivesEveryGrainItsPlanesAndKeepsTheGrainsWhole) {
  SpecimenDef def;
  def.kind = SpecimenKind::voronoi;
  def.voronoi.size = {2e-3, 2e-3, 2e-3};
  def.voronoi.cells = 5;
  def.outline = Outline::box(2e-3, 2e-3, 2e-3);
  def.crystal.enabled = true;
  def.crystal.lattice = lattice(CrystalSystem::hexagonal, 1.6);
  def.crystal.families.push_back({parse_miller_family("{0001}", CrystalSystem::hexagonal), 1.0, 1});
  def.crystal.families.push_back({parse_miller_family("{10-10}", CrystalSystem::hexagonal), 2.0, 1});
  def.orientation.law = OrientationLaw::uniform;
  const Specimen s = build_specimen(def);
  ASSERT_EQ(s.grains.size(), 5u);
  for (const Grain& g : s.grains) {
    EXPECT_TRUE(g.crystal.isApprox(uniform_orientation(def.seed, static_cast<std::uint64_t>(g.id)), 1e-15));
    const CleavagePlanes p = grain_cleavage_planes(s, g);
    EXPECT_EQ(p.planes.size(), 4u);
    EXPECT_EQ(p.family, (std::vector<int>{0, 1, 1, 1}));
    EXPECT_EQ(plane_families(def.crystal), p.family);
    // The basal plane is normal to the grain's c axis.
    EXPECT_LT(angle_between(p.planes[0].normal_approx(), g.crystal * Eigen::Vector3d::UnitZ()), 1e-9);
  }
  EXPECT_EQ(split_into_slabs(s).size(), 5u);
}
