// Dilated-polyhedron contacts between two prisms: face-to-face patches, edge-on-face,
// independence from how faces are listed, and no touching point counted twice.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <cstring>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/rng.hpp"
#include "physics/dem/narrow_phase.hpp"

using namespace cleave;
using namespace cleave::physics;

namespace {

const double kR = 0.5e-3, kT = 1e-3, kRho = 0.05e-3;  // side, thickness, dilation radius

RigidShape prism() { return make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(kR, kT), kRho); }

PosedShape pose(const RigidShape& shape, const Eigen::Vector3d& x, const Eigen::Quaterniond& turn) {
  BodyState s;
  s.x = x;
  s.q = shape.orientation_for(turn);
  PosedShape p;
  p.update(shape, s);
  return p;
}

Eigen::Quaterniond about_z(double deg) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitZ()));
}

std::vector<FeatureContact> contacts(const PosedShape& a, const PosedShape& b) {
  std::vector<FeatureContact> out;
  polyhedron_contacts(a, b, 0.0, out);
  return out;
}

}  // namespace

TEST(FaceToFace, CoaxialPrismsTouchAtTheCornersOfTheirOverlap) {
  const RigidShape s = prism();
  const double delta = 1e-6;
  const double z = kT + 2 * kRho - delta;  // B's basal face pressed delta into A's top face
  // Aligned: the overlap is the hexagon itself, six corners (each counted once).
  auto c = contacts(pose(s, {0, 0, 0}, about_z(0)), pose(s, {0, 0, z}, about_z(0)));
  EXPECT_EQ(c.size(), 6u);
  // Turned 30 degrees: the overlap of two hexagons is a 12-gon whose corners are the rim
  // crossings (no corner of either hexagon lies inside the other).
  c = contacts(pose(s, {0, 0, 0}, about_z(0)), pose(s, {0, 0, z}, about_z(30)));
  EXPECT_EQ(c.size(), 12u);
  for (const auto& fc : c) {
    EXPECT_NEAR(fc.contact.penetration, delta, 1e-12);
    EXPECT_NEAR(fc.contact.normal.z(), 1.0, 1e-12);  // from A (below) towards B
    EXPECT_NEAR(fc.contact.point.z(), kT / 2 + kRho - delta / 2, 1e-12);
  }
  // The 12 points are symmetric about the axis: they sum to the centre (no net torque).
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& fc : c) sum += fc.contact.point;
  EXPECT_NEAR(sum.head<2>().norm(), 0.0, 1e-15);
}

// Two equal prisms stacked face to face, B's axis offset from A's: the overlap of two equal
// hexagons offset by d is symmetric about the midpoint of their centres, so its corners,
// the patch's contacts, must be too (no torque from the patch's shape). Offsets along the
// sides (0, 60, 120 degrees) put sides on one line and corners on the other's rim; the
// bodies are nudged by 1e-12 m and 1e-12 rad, as a run leaves grains of a lattice, so
// nothing there is exactly aligned. A corner lost on a rim, a crossing of two sides on one
// line, or a point counted twice moves the centroid off the midpoint.
TEST(FaceToFace, AlignedFacesUnderRoundingNoiseTouchAtTheCornersOfTheirOverlap) {
  const RigidShape s = prism();
  const double delta = 1e-6;
  const double z = kT + 2 * kRho - delta;
  geometry::SplitMix64 rng(11);
  auto nudge = [&]() -> Eigen::Vector3d { return 1e-12 * Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5); };
  int trials = 0;
  for (double deg : {0.0, 60.0, 120.0, 30.0, 90.0, 17.0}) {
    for (double d : {0.0, 0.1 * kR, 0.37 * kR, 0.8 * kR}) {
      for (int k = 0; k < 8; ++k, ++trials) {
        const Eigen::Vector3d offset(d * std::cos(deg * M_PI / 180), d * std::sin(deg * M_PI / 180), z);
        const Eigen::Vector3d xa = nudge(), xb = offset + nudge();
        const Eigen::Quaterniond qa(Eigen::AngleAxisd(1e-12 * (rng.uniform() - 0.5), Eigen::Vector3d::UnitX()));
        const Eigen::Quaterniond qb(Eigen::AngleAxisd(1e-12 * (rng.uniform() - 0.5), Eigen::Vector3d::UnitY()));
        const auto c = contacts(pose(s, xa, qa), pose(s, xb, qb));
        ASSERT_GE(c.size(), 3u) << deg << " deg, d " << d;
        Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
        for (const auto& fc : c) {
          EXPECT_NEAR(fc.contact.penetration, delta, 1e-9) << deg << " deg, d " << d;
          centroid += fc.contact.point.head<2>() / static_cast<double>(c.size());
        }
        // Corners that the nudges put within the rim tolerance of each other are one point,
        // A's: the centroid may be off by the nudges (about 1e-12 m), while a corner lost or
        // a crossing gained moves it by a good fraction of a side.
        const Eigen::Vector2d mid = 0.5 * (xa + xb).head<2>();
        EXPECT_LT((centroid - mid).norm(), 1e-5 * kR)
            << deg << " deg, d " << d << ": " << c.size() << " contacts, centroid off by " << (centroid - mid).norm();
      }
    }
  }
  EXPECT_EQ(trials, 192);
}

TEST(FaceToFace, NoContactWhileTheDilatedFacesAreApart) {
  const RigidShape s = prism();
  EXPECT_TRUE(contacts(pose(s, {0, 0, 0}, about_z(0)), pose(s, {0, 0, kT + 2 * kRho + 1e-7}, about_z(17))).empty());
}

TEST(EdgeOnFace, APrismOnItsSideEdgeTouchesAtTheEdgesEnds) {
  const RigidShape s = prism();
  // A lies on its side (axis along x) with a side edge down: turned about x so that edge
  // is lowest. B is a large flat prism below (its top face at z = 0).
  const RigidShape big = make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(3e-3, kT), kRho);
  const PosedShape b = pose(big, {0, 0, -kT / 2}, about_z(0));
  // Turned -30 degrees about its axis a corner of the hexagon points along +x; laid on its
  // side (+90 degrees about y, which takes +x to -z) that corner's long edge is lowest, r
  // below the axis.
  const Eigen::Quaterniond side =
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY())) * about_z(-30);
  const double delta = 2e-7;
  const PosedShape a = pose(s, {0, 0, kR + 2 * kRho - delta}, side);
  const auto c = contacts(b, a);  // B first: the flat face, then the edge
  ASSERT_EQ(c.size(), 2u);  // the edge's two end corners over the face; nothing counted twice
  for (const auto& fc : c) {
    EXPECT_NEAR(fc.contact.penetration, delta, 1e-12);
    EXPECT_NEAR(fc.contact.normal.z(), 1.0, 1e-12);
  }
  EXPECT_NEAR(std::abs(c[0].contact.point.x() - c[1].contact.point.x()), kT, 1e-12);
}

TEST(FaceListing, ContactsDoNotDependOnWhereAFaceLoopStarts) {
  // The same prism with every face loop rotated: the contact set is the same.
  geometry::PolygonMesh m = geometry::ExactPolyhedron::hexagonal_prism(kR, kT).to_mesh();
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    std::rotate(m.faces[f].begin(), m.faces[f].begin() + (f % m.faces[f].size()), m.faces[f].end());
  }
  const RigidShape plain = prism();
  const RigidShape rotated = make_rigid_shape(geometry::ExactPolyhedron::from_mesh(m), kRho);
  geometry::SplitMix64 rng(7);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d x(0.6e-3 * (rng.uniform() - 0.5), 0.6e-3 * (rng.uniform() - 0.5),
                            kT + 2 * kRho - 2e-6 * rng.uniform());
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.2 * (rng.uniform() - 0.5),
                                                 Eigen::Vector3d(rng.uniform(), rng.uniform(), 1).normalized()) *
                               about_z(360 * rng.uniform()));
    auto p1 = contacts(pose(plain, {0, 0, 0}, about_z(0)), pose(plain, x, q));
    auto p2 = contacts(pose(rotated, {0, 0, 0}, about_z(0)), pose(rotated, x, q));
    ASSERT_EQ(p1.size(), p2.size());
    auto key = [](const FeatureContact& a, const FeatureContact& b) {
      return std::tie(a.contact.point.x(), a.contact.point.y()) < std::tie(b.contact.point.x(), b.contact.point.y());
    };
    std::sort(p1.begin(), p1.end(), key);
    std::sort(p2.begin(), p2.end(), key);
    for (std::size_t i = 0; i < p1.size(); ++i) {
      EXPECT_NEAR((p1[i].contact.point - p2[i].contact.point).norm(), 0.0, 1e-15);
      EXPECT_NEAR(p1[i].contact.penetration, p2[i].contact.penetration, 1e-18);
    }
    compared += static_cast<int>(p1.size());
  }
  EXPECT_GT(compared, 200);
}

TEST(NoDoubleCounting, RandomTouchingPosesNeverReportOnePointTwice) {
  const RigidShape s = prism();
  geometry::SplitMix64 rng(11);
  int total = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // B somewhere around A, turned at random, moved in along the line of centres until
    // the first contacts appear.
    Eigen::Vector3d dir(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
    dir.normalize();
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(Eigen::AngleAxisd(2 * M_PI * rng.uniform(),
                                             Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5,
                                                             rng.uniform() - 0.5).normalized()));
    const PosedShape a = pose(s, {0, 0, 0}, about_z(0));
    double d = 3e-3;
    std::vector<FeatureContact> c;
    while (d > 0 && (c = contacts(a, pose(s, d * dir, q))).empty()) d -= 2e-6;
    ASSERT_FALSE(c.empty());
    total += static_cast<int>(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
      EXPECT_NEAR(c[i].contact.normal.norm(), 1.0, 1e-12);
      EXPECT_GT(c[i].contact.penetration, 0.0);
      EXPECT_LT(c[i].contact.penetration, 2.5e-6);  // caught within one approach step
      for (std::size_t j = i + 1; j < c.size(); ++j) {
        EXPECT_GT((c[i].contact.point - c[j].contact.point).norm(), 1e-9)
            << "features " << std::hex << c[i].feature_a << "/" << c[i].feature_b << " and "
            << c[j].feature_a << "/" << c[j].feature_b;
      }
    }
    if (HasFailure()) break;
  }
  EXPECT_GT(total, 3000);
}

namespace {
Eigen::Quaterniond random_turn(geometry::SplitMix64& rng, double angle) {
  const Eigen::Vector3d axis(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

bool same_contacts(const std::vector<FeatureContact>& x, const std::vector<FeatureContact>& y) {
  if (x.size() != y.size()) return false;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto &p = x[i], &q = y[i];
    if (p.feature_a != q.feature_a || p.feature_b != q.feature_b || p.contact.point != q.contact.point ||
        p.contact.normal != q.contact.normal || p.contact.penetration != q.contact.penetration) {
      return false;
    }
  }
  return true;
}
// A prism, a thin slab and a large prism: the pairs the random trials below draw from.
std::vector<RigidShape> trial_shapes() {
  return {prism(), make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(kR, 0.2 * kT), kRho),
          make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(3 * kR, kT), kRho)};
}

PosedShape posed(const RigidShape& s, const BodyState& st) {
  PosedShape p;
  p.update(s, st);
  return p;
}

/// Trial `trial`'s pair drawn at random: A and B turned at random, or on odd trials B's
/// faces within `face_lo` + [0, `face_span`] degrees of opposite A's, coming in along one
/// of A's principal axes; moved in along the line of centres to the first contact, then up
/// to 40 um further.
void touching_pair(geometry::SplitMix64& rng, int trial, const RigidShape& sa, const RigidShape& sb,
                   double face_lo, double face_span, BodyState& a, BodyState& b) {
  Eigen::Vector3d dir(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
  dir.normalize();
  a = BodyState{};
  b = BodyState{};
  a.q = random_turn(rng, 2 * M_PI * rng.uniform());
  b.q = random_turn(rng, 2 * M_PI * rng.uniform());
  if (trial % 2 == 1) {
    b.q = random_turn(rng, (face_lo + face_span * rng.uniform()) * M_PI / 180) * a.q;
    dir = a.q * (Eigen::Vector3d::Unit(static_cast<int>(rng.below(3))) * (rng.below(2) != 0 ? 1.0 : -1.0) +
                 0.2 * dir);
    dir.normalize();
  }
  double d = sa.bounding_radius() + sb.bounding_radius();
  for (b.x = d * dir; d > 0 && contacts(posed(sa, a), posed(sb, b)).empty(); b.x = d * dir) d -= 2e-6;
  b.x = (d - 40e-6 * rng.uniform()) * dir;
}
}  // namespace

// The near-feature cache against the full search as its brute-force reference: pairs of a
// prism, a thin slab and a large prism brought into touch at random, then moved for 40
// steps by random relative and common motions from a nanometre to past the skin. Every
// step the cached search must give the full search's contacts bit for bit, and it must
// have been the cached features that were searched in most steps.
TEST(NearFeatureCache, GivesTheFullSearchsContactsBitForBit) {
  const std::vector<RigidShape> shapes = trial_shapes();
  geometry::SplitMix64 rng(2026);
  int steps = 0, cached = 0, touching = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    const RigidShape& sa = shapes[trial % 3];
    const RigidShape& sb = shapes[(trial / 3) % 3];
    // Faces nearly opposite on odd trials: about the face-to-face threshold of 6 degrees.
    BodyState a, b;
    touching_pair(rng, trial, sa, sb, 5.0, 2.0, a, b);
    NearFeatures near;
    PosedShape pa, pb;  // kept, so that their motion bounds add up step by step
    const double skin = 0.5 * 2 * kRho;
    for (int step = 0; step < 40; ++step) {
      // Log-uniform sizes: most moves far below the skin, some beyond it.
      const double move = std::pow(10.0, -9 + 5 * rng.uniform());
      const double turn = std::pow(10.0, -8 + 7 * rng.uniform());
      switch (rng.below(3)) {
        case 0:  // B alone
          b.x += move * Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
          b.q = random_turn(rng, turn) * b.q;
          break;
        case 1:  // A alone
          a.x += move * Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
          a.q = random_turn(rng, turn) * a.q;
          break;
        default: {  // both as one rigid body, turned about a far point: world boxes change
          const Eigen::Quaterniond r = random_turn(rng, 100 * turn);
          const Eigen::Vector3d pivot(0.01, -0.02, 0.005);
          a.x = pivot + r * (a.x - pivot);
          b.x = pivot + r * (b.x - pivot);
          a.q = r * a.q;
          b.q = r * b.q;
        }
      }
      a.q.normalize();
      b.q.normalize();
      pa.update(sa, a);
      pb.update(sb, b);
      std::vector<FeatureContact> with_cache;
      cached += polyhedron_contacts(pa, pb, skin, near, with_cache) ? 1 : 0;
      const std::vector<FeatureContact> full = contacts(pa, pb);
      touching += full.empty() ? 0 : 1;
      ++steps;
      ASSERT_TRUE(same_contacts(with_cache, full))
          << "trial " << trial << " step " << step << ": " << with_cache.size() << " vs " << full.size();
    }
  }
  EXPECT_GT(touching, steps / 2);
  EXPECT_GT(cached, steps / 2);
}

// The culls (edge pairs ruled out by plane distances, a corner's candidate edges that are
// clearly out of reach) against the search without them, as its brute-force reference:
// pairs of a prism, a thin slab and a wedge cut from a prism at 60 degrees (whose obtuse
// edges open the edge normal cones past the face planes) brought into touch at random and
// pushed up to 60 um further in. The contacts must be the same bit for bit, and there must
// be many edge-edge contacts among them.
TEST(NarrowPhaseCulls, ChangeNoContactBitForBit) {
  const auto split = geometry::ExactPolyhedron::hexagonal_prism(kR, kT).split(
      geometry::ExactPlane::from_normal_offset(Eigen::Vector3d(1.0, 0.3, std::sqrt(3.0)).normalized(), 0.0));
  ASSERT_TRUE(split.ok());
  const std::vector<RigidShape> shapes = {
      prism(), make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(kR, 0.2 * kT), kRho),
      make_rigid_shape(*split.below, kRho)};
  ASSERT_GT(shapes[2].primitives.edge_cone_spread, 0.4);  // an edge of more than 113 degrees
  geometry::SplitMix64 rng(7);
  int touching = 0, edge_edge = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const RigidShape& sa = shapes[trial % 3];
    const RigidShape& sb = shapes[(trial / 3) % 3];
    const Eigen::Vector3d dir =
        Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalized();
    BodyState a, b;
    a.q = random_turn(rng, 2 * M_PI * rng.uniform());
    b.q = random_turn(rng, 2 * M_PI * rng.uniform());
    auto search = [&](bool culls) {
      PosedShape pa, pb;
      pa.update(sa, a);
      pb.update(sb, b);
      std::vector<FeatureContact> out;
      polyhedron_contacts(pa, pb, 0.0, out, culls);
      return out;
    };
    double d = sa.bounding_radius() + sb.bounding_radius();
    for (b.x = d * dir; d > 0 && search(false).empty(); b.x = d * dir) d -= 2e-6;
    b.x = (d - 60e-6 * rng.uniform()) * dir;
    const std::vector<FeatureContact> with = search(true), without = search(false);
    ASSERT_TRUE(same_contacts(with, without))
        << "trial " << trial << ": " << with.size() << " vs " << without.size() << " contacts";
    touching += without.empty() ? 0 : 1;
    for (const auto& c : without) {
      edge_edge += (c.feature_a >> 16) == static_cast<std::uint32_t>(FeatureKind::edge) &&
                   (c.feature_b >> 16) == static_cast<std::uint32_t>(FeatureKind::edge);
    }
  }
  EXPECT_GT(touching, 3900);
  EXPECT_GT(edge_edge, 1000);
}

// Persistent contact manifolds (an approximation) against the full search as the reference:
// pairs of a prism, a thin slab and a large prism brought into touch at random (half of them
// nearly face to face) and pushed up to 40 um in (the dilation is 50 um); a manifold is
// captured with a margin of `tolerance` times the radii, then B is moved and turned at
// random relative to A, as far as the manifold still holds (half the margin, the motion
// bound). With k = 1 the spring force is sum(pen n), and its moment is taken about A's centre.
// - Where the full search finds the same feature pairs before and after the motion, the
//   carried force must be within half of (number of contacts) x (motion bound) of the full
//   search's, the moment within that times the lever, and summed over the trials its error
//   must be under a fifth of what contacts left as they were found would give.
// - Where the full search's own feature pairs change (a vertex handed from an edge to a
//   face, a patch that gains a corner), the full search jumps; the carried force must then
//   be within that jump plus the same bound.
// The manifold must have held in most trials.
TEST(ContactManifold, CarriedContactsStayWithinTheMotionOfTheFullSearchsForce) {
  const std::vector<RigidShape> shapes = trial_shapes();
  auto force = [](const std::vector<FeatureContact>& c, const Eigen::Vector3d& centre) {
    Eigen::Matrix<double, 6, 1> fm = Eigen::Matrix<double, 6, 1>::Zero();
    for (const FeatureContact& f : c) {
      const Eigen::Vector3d F = f.contact.penetration * f.contact.normal;
      fm.head<3>() += F;
      fm.tail<3>() += (f.contact.point - centre).cross(F);
    }
    return fm;
  };
  auto keys = [](const std::vector<FeatureContact>& c) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> k;
    for (const FeatureContact& f : c) k.emplace_back(f.feature_a, f.feature_b);
    std::sort(k.begin(), k.end());
    return k;
  };
  for (const double tolerance : {0.02, 0.2}) {
    geometry::SplitMix64 rng(77);
    int held = 0, trials = 0, same_features = 0;
    double worst_force = 0.0, worst_moment = 0.0, worst_jumped = 0.0;
    double carried_error = 0.0, frozen_error = 0.0;  // summed |dF|: carried, and left as found
    for (int trial = 0; trial < 1500; ++trial) {
      const RigidShape& sa = shapes[trial % 3];
      const RigidShape& sb = shapes[(trial / 3) % 3];
      BodyState a, b;
      touching_pair(rng, trial, sa, sb, 0.0, 8.0, a, b);
      const PosedShape pa = posed(sa, a);
      const PosedShape pb0 = posed(sb, b);
      ContactManifold m;
      const double margin = tolerance * 2 * kRho;
      const std::vector<FeatureContact> before = contacts(pa, pb0);
      capture_manifold(pa, pb0, before, margin, m);
      // B moved relative to A by up to half the margin: a translation and a turn about its
      // own centre, sharing it at random.
      const BodyState b0 = b;
      const double share = rng.uniform();
      const double lever = sb.bounding_radius();
      b.x += share * 0.5 * margin * rng.uniform() *
             Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalized();
      b.q = random_turn(rng, (1 - share) * 0.5 * margin * rng.uniform() / lever) * b.q;
      b.q.normalize();
      const PosedShape pb = posed(sb, b);
      std::vector<FeatureContact> carried;
      ++trials;
      {  // Moved past half the margin, the manifold refuses (and appends nothing).
        BodyState far = b0;
        far.x += 0.6 * margin * Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalized();
        EXPECT_FALSE(manifold_contacts(pa, posed(sb, far), m, carried));
        EXPECT_TRUE(carried.empty());
      }
      if (!manifold_contacts(pa, pb, m, carried)) continue;
      ++held;
      const std::vector<FeatureContact> full = contacts(pa, pb);
      const double moved = 0.5 * margin;
      const double n = static_cast<double>(std::max(full.size(), carried.size()));
      const double arm = sa.bounding_radius() + lever;
      const Eigen::Matrix<double, 6, 1> diff = force(carried, a.x) - force(full, a.x);
      if (keys(full) == keys(before)) {
        ++same_features;
        carried_error += diff.head<3>().norm();
        frozen_error += (force(before, a.x) - force(full, a.x)).head<3>().norm();
        worst_force = std::max(worst_force, diff.head<3>().norm() / (n * moved));
        worst_moment = std::max(worst_moment, diff.tail<3>().norm() / (n * moved * arm));
      } else {
        const double jump = (force(full, a.x) - force(before, a.x)).head<3>().norm();
        // Rounding: the carried force is the force before the jump to about 1e-12 of it.
        worst_jumped = std::max(worst_jumped, diff.head<3>().norm() / (jump * (1 + 1e-9) + n * moved));
      }
    }
    EXPECT_GT(held, trials * 3 / 4) << "tolerance " << tolerance;
    EXPECT_GT(same_features, held / 2) << "tolerance " << tolerance;
    EXPECT_LT(worst_force, 0.5) << "tolerance " << tolerance;
    EXPECT_LT(worst_moment, 0.5) << "tolerance " << tolerance;
    // Carrying the points is what makes it right: contacts left as they were found (the
    // penetrations not carried) would be off by several times more.
    EXPECT_LT(carried_error, 0.2 * frozen_error) << "tolerance " << tolerance;
    EXPECT_LT(worst_jumped, 1.0) << "tolerance " << tolerance;
    std::printf("tolerance %g: held %d of %d, %d with the same features; worst |dF| / (n moved) %.3g, "
                "|dM| / (n moved lever) %.3g, carried / frozen %.3g; where the search jumped, |dF| / (jump + n moved) %.6f\n",
                tolerance, held, trials, same_features, worst_force, worst_moment, carried_error / frozen_error,
                worst_jumped);
  }
}

// The posed vertices and their box, written in scalars, against Eigen's centre + R v and
// cwiseMin/cwiseMax, to the bit, over random poses.
TEST(PosedShape, VerticesAndTheirBoxGiveTheBitsOfEigensForm) {
  const RigidShape s = prism();
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int differ_from_one_order = 0;
  for (int t = 0; t < 20000; ++t) {
    BodyState st;
    st.x = 1e-2 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    st.q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    if (t % 10 == 0) st.q = Eigen::Quaterniond::Identity();
    PosedShape p;
    p.update(s, st);
    const Eigen::Matrix3d R = st.q.toRotationMatrix();
    ASSERT_EQ(p.vertices.size(), s.primitives.vertices.size());
    Eigen::Vector3d lo = st.x, hi = st.x;
    for (std::size_t i = 0; i < p.vertices.size(); ++i) {
      const Eigen::Vector3d want = st.x + R * s.primitives.vertices[i];
      ASSERT_EQ(std::memcmp(p.vertices[i].data(), want.data(), 3 * sizeof(double)), 0) << t << " vertex " << i;
      lo = lo.cwiseMin(want);
      hi = hi.cwiseMax(want);
      const Eigen::Vector3d& v = s.primitives.vertices[i];
      differ_from_one_order += st.x.z() + ((R(2, 0) * v.x() + R(2, 1) * v.y()) + R(2, 2) * v.z()) != want.z();
    }
    ASSERT_EQ(std::memcmp(p.lo.data(), lo.data(), 3 * sizeof(double)), 0) << t;
    ASSERT_EQ(std::memcmp(p.hi.data(), hi.data(), 3 * sizeof(double)), 0) << t;
  }
  EXPECT_GT(differ_from_one_order, 100);  // the orders differ: the test tells them apart
}
