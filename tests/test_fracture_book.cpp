// The exact side of transgranular fracture: grains cut along their cleavage planes during
// a run keep their exact volume (summed over the live pieces, compared as rationals), carry
// their lineage, share the pieces' shapes, and drop planes that no longer cut them.
#include <gtest/gtest.h>

#include <set>

#include "geometry/polygon_mesh.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "physics/transgranular/transgranular.hpp"

using namespace cleave;
using namespace cleave::physics;

namespace {

constexpr double kSide = 0.5e-3, kThick = 1.0e-3, kDilation = 0.05e-3, kRho = 3100.0;

struct Rig {
  World world;
  FractureBook book{kDilation, 0.01};
  std::shared_ptr<const geometry::ExactPolyhedron> prism =
      std::make_shared<const geometry::ExactPolyhedron>(geometry::ExactPolyhedron::hexagonal_prism(kSide, kThick));
  std::uint32_t shape = 0;
  Rig() : world(settings()) {
    shape = world.add_shape(make_rigid_shape(*prism, kDilation));
    book.add_shape(shape, prism);
  }
  static WorldSettings settings() {
    WorldSettings ws;
    ws.gravity.setZero();
    ws.particle_particle.kn = 5000.0;
    ws.particle_wall.kn = 5000.0;
    ws.threads = 1;
    return ws;
  }
  BodyId grain(int id, const Eigen::Vector3d& x, geometry::CrystalOrientation o) {
    const BodyId b = world.add_body(shape, kRho, x, world.shape(shape).orientation_for(), {0.1, 0, 0},
                                    {0, 0, 50}, id);
    book.add_grain(world, b, id, o);
    return b;
  }
};

/// The exact volume of every live piece of grain `grain`, summed.
geometry::ExactScalar grain_volume(const Rig& s, int grain) {
  geometry::ExactScalar sum;
  for (const auto& e : s.book.entries(s.world)) {
    if (e.lineage.grain_id == grain) sum = sum + e.shape->volume();
  }
  return sum;
}

}  // namespace

TEST(FractureBook, ThreeSlabGrainBreaksTwiceAndKeepsItsExactVolume) {
  Rig s;
  const geometry::CrystalOrientation o{geometry::CleavageFamily::a_11_20, 60};
  const BodyId g = s.grain(5, {0, 0, 0}, o);
  ASSERT_EQ(s.book.candidates(g).size(), 2u);  // <11-20>: two planes, three slabs
  const geometry::ExactScalar whole = s.prism->volume();

  const SplitEvent first = s.book.split(s.world, g, 0);
  ASSERT_EQ(first.ids.size(), 2u);
  EXPECT_EQ(first.parent.path_string(), "5");
  EXPECT_EQ(first.pieces[0].path_string(), "5.0");
  EXPECT_EQ(first.pieces[1].path_string(), "5.1");
  EXPECT_TRUE(grain_volume(s, 5) == whole);
  EXPECT_EQ(s.world.body_count(), 2u);

  // Each piece keeps plane 1 as a candidate; it cuts exactly one of them (the other lies
  // wholly on one side), which the book finds and drops.
  int cut = 0;
  for (const BodyId piece : first.ids) {
    ASSERT_EQ(s.book.candidates(piece), std::vector<int>{1});
    const SplitEvent second = s.book.split(s.world, piece, 1);
    if (second.ids.empty()) {
      EXPECT_TRUE(s.book.candidates(piece).empty());
      continue;
    }
    ++cut;
    for (const auto& l : second.pieces) EXPECT_EQ(l.path.size(), 2u);
  }
  EXPECT_EQ(cut, 1);
  EXPECT_EQ(s.world.body_count(), 3u);
  EXPECT_TRUE(grain_volume(s, 5) == whole);
  // The three live pieces are the prism's three cleavage slabs, exactly.
  const auto slabs = s.prism->cleavage_slabs(o);
  ASSERT_EQ(slabs.size(), 3u);
  for (const auto& e : s.book.entries(s.world)) {
    bool same = false;
    for (const auto& slab : slabs) same = same || (slab.volume() == e.shape->volume());
    EXPECT_TRUE(same) << e.lineage.path_string();
  }
}

TEST(FractureBook, GrainsCutAlongTheSamePlaneShareTheirPieces) {
  Rig s;
  const geometry::CrystalOrientation o{geometry::CleavageFamily::m_10_10, 120};
  const BodyId a = s.grain(1, {0, 0, 0}, o);
  const BodyId b = s.grain(2, {5e-3, 0, 0}, o);
  s.book.split(s.world, a, 0);
  const std::size_t shapes_after_one = s.book.entries(s.world).size();
  EXPECT_EQ(shapes_after_one, 3u);  // two pieces of grain 1, grain 2 whole
  const SplitEvent e = s.book.split(s.world, b, 0);
  ASSERT_EQ(e.ids.size(), 2u);
  // The second grain's pieces use the first grain's shapes: no new shape was made.
  std::set<std::uint32_t> used;
  for (const auto& entry : s.book.entries(s.world)) used.insert(s.world.info(entry.id).shape);
  EXPECT_EQ(used.size(), 2u);
  EXPECT_TRUE(grain_volume(s, 1) == s.prism->volume());
  EXPECT_TRUE(grain_volume(s, 2) == s.prism->volume());
}

TEST(FractureBook, CrackPlaneInTheWorldFollowsTheGrain) {
  // A <10-10> grain cut at 0 deg: the plane passes through the grain's centre; turned by
  // 90 deg about z, its world normal turns with it.
  Rig s;
  const geometry::CrystalOrientation o{geometry::CleavageFamily::m_10_10, 0};
  const BodyId g = s.grain(3, {1e-3, 2e-3, 0}, o);
  const auto [n0, p0] = s.book.world_plane(s.world, g, 0);
  EXPECT_NEAR(n0.norm(), 1.0, 1e-12);
  // The centre lies on the plane (two equal slabs).
  EXPECT_NEAR(n0.dot(s.world.state(g).x - p0), 0.0, 1e-12);
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  s.world.state(g).q = turn * s.world.state(g).q;
  const auto [n1, p1] = s.book.world_plane(s.world, g, 0);
  EXPECT_LT((n1 - turn * n0).norm(), 1e-12);
}

TEST(Transgranular, GrainPulledAcrossItsCleavagePlaneSplitsThereWhenKIReachesKIc) {
  // A <10-10> grain whose cleavage plane is x = 0 (through corners 0 and 3), bonded on its
  // two x faces to neighbours that are pulled apart. Each bond pulls with F at its face
  // centre, so the section x = 0 (area A_c = 2 a t) carries sigma = F / A_c and no shear:
  // K_I = F / A_c sqrt(pi a_crack) (eqs 3.23-3.24). With the gate of eq. 3.22 open (mean
  // stress > 0), the grain must not split while K_I < K_Ic and must split on that plane at
  // the step F passes F* = K_Ic A_c / sqrt(pi a_crack).
  Rig s;
  geometry::CrystalOrientation o{geometry::CleavageFamily::m_10_10, 0};
  int angle = -1;
  for (const int a : {0, 60, 120}) {
    Rig probe;
    const BodyId g = probe.grain(0, {0, 0, 0}, {geometry::CleavageFamily::m_10_10, a});
    if (std::abs(probe.book.world_plane(probe.world, g, 0).first.x()) > 1.0 - 1e-12) angle = a;
  }
  ASSERT_GE(angle, 0) << "no <10-10> plane along x";
  o.angle_deg = angle;
  const double pitch = std::sqrt(3.0) * kSide + 2 * kDilation - 1e-6;
  const BodyId g = s.world.add_body(s.shape, kRho, {0, 0, 0}, s.world.shape(s.shape).orientation_for(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0);
  s.book.add_grain(s.world, g, 0, o);
  const BodyId left = s.world.add_body(s.shape, kRho, {-pitch, 0, 0}, s.world.shape(s.shape).orientation_for());
  const BodyId right = s.world.add_body(s.shape, kRho, {pitch, 0, 0}, s.world.shape(s.shape).orientation_for());
  const double area = M_PI * kDilation * kDilation;
  const BondParams bond{5000.0 / area, 2000.0 / area, 1e9, 1e9};  // strong: the grain breaks first
  ASSERT_EQ(s.world.initialise_bonds(bond, 0.0), 2u);
  s.world.set_fixed(left, true);
  s.world.set_fixed(right, true);
  s.world.state(left).v = {-1e-3, 0, 0};
  s.world.state(right).v = {1e-3, 0, 0};

  FractureParams p;
  p.sigma_f_hyd = 0.0;
  p.crack_length = 0.1e-3;
  const double a_c = 2 * kSide * kThick;
  const double f_star = 2e-4;  // N: reached after 40 nm of opening per bond
  p.k_ic = f_star / a_c * std::sqrt(M_PI * p.crack_length);

  double previous = 0.0;
  for (int step = 0; step < 20000; ++step) {
    s.world.step();
    const double f = s.world.bonds().front().state.normal;  // bond tension, N
    const auto events = transgranular_step(s.world, s.book, p);
    if (events.empty()) {
      ASSERT_LT(f, f_star * (1 + 1e-6)) << "no split at F = " << f << " N, step " << step;
      previous = f;
      continue;
    }
    ASSERT_EQ(events.size(), 1u);
    const auto& e = events.front();
    EXPECT_GE(f, f_star * (1 - 1e-6));
    EXPECT_LT(previous, f_star);
    EXPECT_EQ(e.cause.plane, 0);
    EXPECT_NEAR(e.cause.stresses.sigma, f / a_c, 1e-6 * f / a_c);
    EXPECT_NEAR(e.cause.stresses.tau, 0.0, 1e-6 * f / a_c);
    EXPECT_NEAR(std::abs(e.split.normal.x()), 1.0, 1e-12);
    EXPECT_EQ(e.split.pieces.size(), 2u);
    EXPECT_TRUE(grain_volume(s, 0) == s.prism->volume());
    // Each piece took the bond on its side: the bond point lies on the surface of both its
    // bodies, within the dilation radius (outside the face, by at most the radius).
    s.world.step();
    for (const Bond& b : s.world.bonds()) {
      const bool has_piece = b.a == e.split.ids[0].index || b.b == e.split.ids[0].index ||
                             b.a == e.split.ids[1].index || b.b == e.split.ids[1].index;
      EXPECT_TRUE(has_piece);
      for (const std::uint32_t slot : {b.a, b.b}) {
        const BodyId body = s.world.id_at(slot);
        const BodyState& st = s.world.state(body);
        const Eigen::Vector3d local = st.q.conjugate() * (b.point - st.x);
        double out = -1.0;
        for (const auto& face : s.world.shape(s.world.info(body).shape).primitives.faces) {
          out = std::max(out, face.normal.dot(local) - face.offset);
        }
        EXPECT_GE(out, -1e-9) << "bond point inside body " << slot;
        EXPECT_LE(out, kDilation + 1e-9) << "bond point off body " << slot;
      }
    }
    return;
  }
  FAIL() << "the grain never split; last bond force " << previous << " N, F* = " << f_star;
}

TEST(Transgranular, AFamilysResistanceScalesTheLoadItsPlaneSplitsAt) {
  // The same pull as above with the plane's family 1.7 times as tough (a 3D crystal's
  // family, FractureBook::set_plane_resistance): eq. 3.25 with K_Ic x 1.7, so the split comes when
  // F passes 1.7 F*, not before.
  const double resistance = 1.7;
  int angle = -1;
  for (const int a : {0, 60, 120}) {
    Rig probe;
    const BodyId g = probe.grain(0, {0, 0, 0}, {geometry::CleavageFamily::m_10_10, a});
    if (std::abs(probe.book.world_plane(probe.world, g, 0).first.x()) > 1.0 - 1e-12) angle = a;
  }
  ASSERT_GE(angle, 0);
  Rig s;
  const double pitch = std::sqrt(3.0) * kSide + 2 * kDilation - 1e-6;
  const BodyId g = s.world.add_body(s.shape, kRho, {0, 0, 0}, s.world.shape(s.shape).orientation_for(),
                                    Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0);
  s.book.add_grain(s.world, g, 0, s.prism->cleavage_planes({geometry::CleavageFamily::m_10_10, angle}));
  s.book.set_plane_resistance({resistance});
  EXPECT_EQ(s.book.resistance(0), resistance);
  const BodyId left = s.world.add_body(s.shape, kRho, {-pitch, 0, 0}, s.world.shape(s.shape).orientation_for());
  const BodyId right = s.world.add_body(s.shape, kRho, {pitch, 0, 0}, s.world.shape(s.shape).orientation_for());
  const double area = M_PI * kDilation * kDilation;
  ASSERT_EQ(s.world.initialise_bonds(BondParams{5000.0 / area, 2000.0 / area, 1e9, 1e9}, 0.0), 2u);
  s.world.set_fixed(left, true);
  s.world.set_fixed(right, true);
  s.world.state(left).v = {-1e-3, 0, 0};
  s.world.state(right).v = {1e-3, 0, 0};
  FractureParams p;
  p.crack_length = 0.1e-3;
  const double a_c = 2 * kSide * kThick, f_star = 2e-4;
  p.k_ic = f_star / a_c * std::sqrt(M_PI * p.crack_length);
  for (int step = 0; step < 40000; ++step) {
    s.world.step();
    const double f = s.world.bonds().front().state.normal;
    const auto events = transgranular_step(s.world, s.book, p);
    if (events.empty()) {
      ASSERT_LT(f, resistance * f_star * (1 + 1e-6)) << "no split at F = " << f << " N";
      continue;
    }
    EXPECT_GE(f, resistance * f_star * (1 - 1e-6));
    EXPECT_NEAR(events.front().cause.result.criterion, std::pow(f / (resistance * f_star), 2), 1e-6);
    return;
  }
  FAIL() << "the grain never split";
}

TEST(Transgranular, GrainSqueezedBetweenPlatensSplitsOnThePredictedPlaneNotBefore) {
  // A <11-20> grain (two cleavage planes) lying flat, squeezed between two platens closing
  // along y. Every step the criterion is evaluated for its planes (assess, eqs 3.22-3.25);
  // the grain must split at the first step where some plane fails, on the plane with the
  // largest left side of eq. 3.25, and never before. (Squeezed on its corners at y = +-a,
  // the grain at 60 deg has no plane the criterion fails on within the run: it must then
  // not split at all; the other two orientations split.)
  int splits = 0;
  for (const int angle : {0, 60, 120}) {
    Rig s;
    const geometry::CrystalOrientation o{geometry::CleavageFamily::a_11_20, angle};
    const BodyId g = s.world.add_body(s.shape, kRho, {0, 0, 0}, s.world.shape(s.shape).orientation_for(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0);
    s.book.add_grain(s.world, g, 0, o);
    // Corners at y = +-0.5 mm; the platens start touching the dilated corners.
    const double reach = kSide + kDilation;
    s.world.add_wall(Wall::platen("bottom", {0, -reach, 0}, {0, 1, 0}, {1, 0, 0}, 2e-3, 2e-3));
    s.world.add_wall(Wall::platen("top", {0, reach, 0}, {0, -1, 0}, {1, 0, 0}, 2e-3, 2e-3));
    s.world.wall(0).velocity = {0, 1e-3, 0};
    s.world.wall(1).velocity = {0, -1e-3, 0};
    FractureParams p;
    p.sigma_f_hyd = -1e12;  // gate open: the test is about eq. 3.25
    p.crack_length = 0.1e-3;
    p.k_ic = 30.0;
    bool split = false;
    for (int step = 0; step < 20000 && !split; ++step) {
      s.world.step();
      const BodyId id = s.world.body_ids().front();
      const auto found = assess(s.world, s.book, id, p, s.world.body_stresses());
      const CrackAssessment* worst = nullptr;
      for (const auto& a : found) {
        if (a.result.fails && (worst == nullptr || a.result.criterion > worst->result.criterion)) worst = &a;
      }
      const auto events = transgranular_step(s.world, s.book, p);
      if (worst == nullptr) {
        ASSERT_TRUE(events.empty()) << "angle " << angle << ": split before the criterion held";
        continue;
      }
      ASSERT_EQ(events.size(), 1u) << "angle " << angle << ": no split once the criterion held";
      EXPECT_EQ(events.front().cause.plane, worst->plane) << angle;
      EXPECT_EQ(events.front().split.plane, worst->plane) << angle;
      EXPECT_GE(events.front().cause.result.criterion, 1.0);
      EXPECT_TRUE(grain_volume(s, 0) == s.prism->volume());
      split = true;
    }
    splits += split;
  }
  EXPECT_EQ(splits, 2);
}

class GrainStressCriterion : public ::testing::TestWithParam<GrainCriterion> {};

TEST_P(GrainStressCriterion, AChainPulledApartSplitsAnInnerGrainWhenItsStressReachesSigmaF) {
  // Four bonded prisms in a row along x, unbreakable bonds, the first held and the last
  // pulled slowly: an inner grain's Love-Weber stress is sigma_xx = pitch F / V (F the
  // chain's force). With the Rankine criterion an inner grain splits when that reaches
  // sigma_f, with the hydrostatic one when sigma_xx / 3 does; it cleaves on the candidate
  // plane whose normal is nearest x (<10-10> at angle 0: its plane's normal is x itself).
  const GrainCriterion criterion = GetParam();
  WorldSettings ws = Rig::settings();
  ws.dt = 5e-7;
  ws.local_damping = 0.7;
  Rig s;
  s.world = World(ws);
  s.shape = s.world.add_shape(make_rigid_shape(*s.prism, kDilation));
  const double pitch = std::sqrt(3.0) * kSide + 2.0 * kDilation;
  std::vector<BodyId> ids;
  for (int i = 0; i < 4; ++i) {
    ids.push_back(s.world.add_body(s.shape, kRho, {i * pitch, 0, 0}, s.world.shape(s.shape).orientation_for(),
                                   Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), i));
    s.book.add_grain(s.world, ids.back(), i, {geometry::CleavageFamily::m_10_10, 0});
  }
  const double area = M_PI * kDilation * kDilation;
  ASSERT_EQ(s.world.initialise_bonds({5000.0 / area, 2000.0 / area, 1e12, 1e12}, 1e-6), 3u);
  s.world.set_fixed(ids[0], true);
  s.world.set_fixed(ids[3], true);
  s.world.state(ids[3]).v = Eigen::Vector3d(1e-3, 0, 0);
  FractureParams p;
  p.criterion = criterion;
  p.sigma_f = 1e4;
  const double volume = s.world.shape(s.shape).volume;
  double force = 0.0;
  std::vector<TransgranularEvent> events;
  for (int step = 0; step < 40000 && events.empty(); ++step) {
    force = s.world.bonds()[1].state.normal;
    s.world.step();
    events = transgranular_step(s.world, s.book, p);
  }
  ASSERT_FALSE(events.empty());
  const BodyId split = events.front().cause.id;
  EXPECT_TRUE(split == ids[1] || split == ids[2]) << split.index;
  const double factor = criterion == GrainCriterion::rankine ? 1.0 : 3.0;
  const double expected = factor * p.sigma_f * volume / pitch;
  EXPECT_NEAR(force, expected, 0.01 * expected);
  // The plane chosen is the one across the pull.
  const Eigen::Vector3d n = events.front().split.normal;
  EXPECT_GT(std::abs(n.x()), 0.99) << n.transpose();
}

INSTANTIATE_TEST_SUITE_P(RankineAndHydrostatic, GrainStressCriterion,
                         ::testing::Values(GrainCriterion::rankine, GrainCriterion::hydrostatic));

// --- The d'Alembert terms of eqs 3.8-3.19 in the check -------------------------------------

namespace {

/// The <10-10> orientation whose cleavage plane is x = 0 through the grain's centre (through
/// two opposite corners of the hexagon, whose flats face +-x).
int angle_with_plane_along_x() {
  for (const int a : {0, 60, 120}) {
    Rig probe;
    const BodyId g = probe.grain(0, {0, 0, 0}, {geometry::CleavageFamily::m_10_10, a});
    if (std::abs(probe.book.world_plane(probe.world, g, 0).first.x()) > 1.0 - 1e-12) return a;
  }
  return -1;
}

/// Only the section load matters here: the gate is open and nothing can fail.
FractureParams section_probe() {
  FractureParams p;
  p.sigma_f_hyd = -1e30;
  p.k_ic = 1e30;
  p.crack_length = 0.1e-3;
  return p;
}

}  // namespace

TEST(DAlembert, ASpinningGrainsSectionCarriesTheCentripetalForceOfItsHalf) {
  // A free grain spinning about its prism axis at omega, no contact, no gravity: each half
  // (a trapezoidal prism cut through two opposite corners, centroid d = 2 sqrt(3) s / 9 from
  // the axis) turns on a circle, and the other half must pull it in with m/2 omega^2 d
  // through the section, a uniform tension over A_c = 2 s t. Without the d'Alembert term
  // the section carries nothing.
  const int angle = angle_with_plane_along_x();
  ASSERT_GE(angle, 0);
  Rig s;
  const double omega = 2000.0;
  const BodyId g =
      s.world.add_body(s.shape, kRho, {0, 0, 0}, s.world.shape(s.shape).orientation_for(),
                       Eigen::Vector3d::Zero(), {0, 0, omega}, 0);
  s.book.add_grain(s.world, g, 0, {geometry::CleavageFamily::m_10_10, angle});
  s.world.step();
  const auto found = assess(s.world, s.book, g, section_probe(), s.world.body_stresses());
  ASSERT_EQ(found.size(), 1u);
  const CrackAssessment& a = found.front();
  const Eigen::Vector3d n = s.book.world_plane(s.world, g, a.plane).first;
  const double mass = kRho * 1.5 * std::sqrt(3.0) * kSide * kSide * kThick;
  const double d = 2.0 * std::sqrt(3.0) * kSide / 9.0;
  const double centripetal = 0.5 * mass * omega * omega * d;
  EXPECT_LT((a.section_force - centripetal * n).norm(), 1e-9 * centripetal)
      << a.section_force.transpose() << " vs " << centripetal;
  // It pulls through the section's centroid: no bending, so sigma = F / A_c.
  EXPECT_LT(a.section_moment.norm(), 1e-9 * centripetal * kSide);
  EXPECT_NEAR(a.stresses.sigma, centripetal / (2 * kSide * kThick),
              1e-9 * centripetal / (2 * kSide * kThick));
  // Switched off, the quasi-static balance of sec. 3.3 sees no load at all.
  FractureParams off = section_probe();
  off.inertia = false;
  EXPECT_EQ(assess(s.world, s.book, g, off, s.world.body_stresses()).front().section_force.norm(),
            0.0);
}

TEST(DAlembert, APushedGrainsSectionDrivesTheFarHalfWithItsMassTimesTheAcceleration) {
  // A free grain pushed on its -x face by a platen (force F along x, through the face's
  // centre): it accelerates at a = F / m without turning, and the section x = 0 must give
  // the far half m/2 a = F / 2, a compression of F / 2 on either side's section (the near
  // half passes F on and keeps F / 2). Quasi-statically the near half would carry all of F
  // and the far half none.
  const int angle = angle_with_plane_along_x();
  ASSERT_GE(angle, 0);
  Rig s;
  const BodyId g =
      s.world.add_body(s.shape, kRho, {0, 0, 0}, s.world.shape(s.shape).orientation_for(),
                       Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0);
  s.book.add_grain(s.world, g, 0, {geometry::CleavageFamily::m_10_10, angle});
  const double reach = std::sqrt(3.0) / 2.0 * kSide + kDilation;
  s.world.add_wall(Wall::platen("pusher", {-reach + 2e-6, 0, 0}, {1, 0, 0}, {0, 1, 0}, 2e-3, 2e-3));
  s.world.step();
  const double push = s.world.state(g).f.x();
  ASSERT_GT(push, 0.0);
  ASSERT_LT(s.world.state(g).f.tail<2>().norm(), 1e-9 * push);
  const auto found = assess(s.world, s.book, g, section_probe(), s.world.body_stresses());
  ASSERT_EQ(found.size(), 1u);
  const CrackAssessment& a = found.front();
  const Eigen::Vector3d n = s.book.world_plane(s.world, g, a.plane).first;
  EXPECT_LT((a.section_force + 0.5 * push * n).norm(), 1e-6 * push)
      << a.section_force.transpose() << " vs " << (-0.5 * push * n).transpose();
}

namespace {
/// A right prism on a regular n-gon of circumradius r, height h, centred on the origin.
geometry::ExactPolyhedron polygon_prism(int n, double r, double h) {
  geometry::PolygonMesh m;
  for (int z = 0; z < 2; ++z)
    for (int k = 0; k < n; ++k)
      m.vertices.emplace_back(r * std::cos(2 * M_PI * k / n), r * std::sin(2 * M_PI * k / n), z ? h / 2 : -h / 2);
  std::vector<int> bottom, top;
  for (int k = 0; k < n; ++k) {
    bottom.push_back(n - 1 - k);
    top.push_back(n + k);
    m.faces.push_back({k, (k + 1) % n, n + (k + 1) % n, n + k});
  }
  m.faces.push_back(bottom);
  m.faces.push_back(top);
  return geometry::ExactPolyhedron::from_mesh(m);
}
}  // namespace

TEST(ContactLimits, AShapeBeyondTheContactSearchIsRefusedNotLeftWithoutContacts) {
  // The narrow phase's buffers take 64 vertices: a 33-gon prism (66) would meet nothing.
  World world(Rig::settings());
  const auto big = polygon_prism(33, 1e-3, 1e-3);
  try {
    (void)world.add_shape(make_rigid_shape(big, kDilation));
    FAIL() << "a 66-vertex shape was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("66 vertices"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW((void)world.add_shape(make_rigid_shape(polygon_prism(32, 1e-3, 1e-3), kDilation)));
}

TEST(ContactLimits, ACutThatWouldMakeAPieceTooBigForTheContactSearchIsRefused) {
  // A 32-gon prism has 64 vertices, the most the contact search takes. Cutting a corner off
  // turns one vertex into three: the large piece would have 66, so the cut is refused and
  // the plane dropped, as a sliver's is; a plane across the middle still cuts.
  World world(Rig::settings());
  FractureBook book(kDilation, 0.0);
  const auto prism = std::make_shared<const geometry::ExactPolyhedron>(polygon_prism(32, 1e-3, 1e-3));
  const std::uint32_t shape = world.add_shape(make_rigid_shape(*prism, kDilation));
  book.add_shape(shape, prism);
  const BodyId g = world.add_body(shape, kRho, Eigen::Vector3d::Zero(), world.shape(shape).orientation_for());
  // Corner 0 sits at (r, 0, -h/2): a plane cutting just that corner off, and one through the middle.
  const Eigen::Vector3d corner(1e-3, 0.0, -0.5e-3), n = Eigen::Vector3d(1.0, 0.0, -1.0).normalized();
  std::vector<geometry::ExactPlane> planes{geometry::ExactPlane::from_normal_offset(n, n.dot(corner) - 1e-5),
                                           geometry::ExactPlane::from_normal_offset(Eigen::Vector3d::UnitX(), 0.0)};
  book.add_grain(world, g, 0, planes);
  const SplitEvent refused = book.split(world, g, 0);
  EXPECT_TRUE(refused.ids.empty());
  EXPECT_EQ(book.candidates(g), (std::vector<int>{1}));
  const SplitEvent cut = book.split(world, g, 1);
  EXPECT_EQ(cut.ids.size(), 2u);
}

TEST(SmallestPiece, ACutLeavingAPieceBelowTheSmallestVolumeIsRefused) {
  // A 24-gon prism of circumradius r and height h: a plane x = 0.8 r cuts off a cap far
  // below a fifth of the prism; with the smallest piece set between the cap's volume and
  // the half's, that cut is refused and the plane dropped, while x = 0 still halves it.
  World world(Rig::settings());
  FractureBook book(kDilation, 0.0);
  const double r = 1e-3, h = 1e-3;
  const auto prism = std::make_shared<const geometry::ExactPolyhedron>(polygon_prism(24, r, h));
  const std::uint32_t shape = world.add_shape(make_rigid_shape(*prism, kDilation));
  book.add_shape(shape, prism);
  const BodyId g = world.add_body(shape, kRho, Eigen::Vector3d::Zero(), world.shape(shape).orientation_for());
  std::vector<geometry::ExactPlane> planes{
      geometry::ExactPlane::from_normal_offset(Eigen::Vector3d::UnitX(), 0.8 * r),
      geometry::ExactPlane::from_normal_offset(Eigen::Vector3d::UnitX(), 0.0)};
  book.add_grain(world, g, 0, planes);
  // The cap beyond x = 0.8 r of a disc of radius r: r^2 (acos(0.8) - 0.8 sqrt(1 - 0.64)),
  // about 0.052 of the disc; the prism's polygon has less. A quarter of the prism's volume
  // sits between it and the half.
  const double prism_volume = prism->volume().to_double();
  book.set_min_piece_volume(0.25 * prism_volume);
  const SplitEvent refused = book.split(world, g, 0);
  EXPECT_TRUE(refused.ids.empty());
  EXPECT_EQ(book.candidates(g), (std::vector<int>{1}));
  const SplitEvent cut = book.split(world, g, 1);
  ASSERT_EQ(cut.ids.size(), 2u);
  for (const BodyId piece : cut.ids)
    EXPECT_NEAR(world.shape(world.info(piece).shape).volume, 0.5 * prism_volume, 1e-9 * prism_volume);
}
