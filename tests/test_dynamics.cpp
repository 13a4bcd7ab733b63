// Whole-world dynamics: walls carry weights, rollers and platens, a small drop test that
// settles, and bit-identical repeat runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <utility>

#include "geometry/specimen.hpp"
#include "io/scenario.hpp"
#include "sim/world_assembly.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"

using namespace cleave;
using namespace cleave::physics;

namespace {

ContactParams soft(double kn, double c_res, double mu) {
  ContactParams p;
  p.kn = kn;
  p.ks = 0.4 * kn;
  p.c_res = c_res;
  p.mu_s = mu;
  return p;
}

RigidShape prism_shape() {
  return make_rigid_shape(geometry::ExactPolyhedron::hexagonal_prism(0.9e-3, 0.85e-3), 0.05e-3);
}

const double kRho = 3100.0;

/// Runs until the kinetic energy has decayed well below the weight's energy scale.
void settle(World& world, int steps) {
  for (int i = 0; i < steps; ++i) world.step();
}

/// A world under gravity with the given particle-wall law and a step of 1 us.
World gravity_world(const ContactParams& wall_law) {
  WorldSettings ws;
  ws.gravity = {0, 0, -9.81};
  ws.dt = 1e-6;
  ws.particle_wall = wall_law;
  return World(ws);
}

}  // namespace

TEST(Walls, FloorCarriesTheWeightOfARestingGrain) {
  // C_res = 1: a purely elastic spring (with C_res > 1 the rest overlap keeps the offset
  // of the unloading line); the damping of eq 2.6 settles it.
  World world = gravity_world(soft(1e4, 1.0, 0.3));
  const RigidShape shape = prism_shape();
  const auto sh = world.add_shape(shape);
  const auto floor = world.add_wall(Wall::plane("floor", {0, 0, 0}, {0, 0, 1}));
  // Lying on a basal face, its lowest corners 10 um above the floor's reach.
  const BodyId id = world.add_body(sh, kRho, {0, 0, 0.425e-3 + 0.05e-3 + 10e-6},
                                   shape.orientation_for());
  settle(world, 200000);
  const double weight = world.info(id).mass * 9.81;
  EXPECT_NEAR(world.walls()[floor].reaction.z(), -weight, 1e-3 * weight);
  EXPECT_NEAR(world.walls()[floor].reaction.x(), 0.0, 1e-6 * weight);
  EXPECT_LT(world.state(id).v.norm(), 1e-4);
  // Resting on a face: six corner contacts share the load, each pressed by weight/(6 kn).
  ASSERT_EQ(world.contacts().size(), 6u);
  for (const auto& c : world.contacts()) EXPECT_NEAR(c.overlap, weight / 6 / 1e4, 2e-3 * weight / 6 / 1e4);
}

TEST(Walls, TwoRollersShareTheLoadAndAPlatenOnlyCatchesWhatIsAboveIt) {
  World world = gravity_world(soft(1e4, 2.0, 0.3));
  const RigidShape shape = prism_shape();
  const auto sh = world.add_shape(shape);
  // Two rollers along y under the grain, symmetric about x = 0 (a bending support).
  const double R = 0.3e-3;
  const auto left = world.add_wall(Wall::cylinder("left", {-0.5e-3, -2e-3, -R}, {0, 1, 0}, 4e-3, R));
  const auto right = world.add_wall(Wall::cylinder("right", {0.5e-3, -2e-3, -R}, {0, 1, 0}, 4e-3, R));
  // A small platen far to the side catches nothing of this grain.
  const auto platen =
      world.add_wall(Wall::platen("aside", {5e-3, 0, 0}, {0, 0, 1}, {1, 0, 0}, 1e-3, 1e-3));
  // The grain lies on a side face (prism axis along x): its flat side rests on both rollers.
  const Eigen::Quaterniond on_side(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  const BodyId id = world.add_body(sh, kRho, {0, 0, 0.9e-3 * std::sqrt(3.0) / 2 + 0.05e-3 + 5e-6},
                                   shape.orientation_for(on_side));
  settle(world, 300000);
  const double weight = world.info(id).mass * 9.81;
  const Eigen::Vector3d rl = world.walls()[left].reaction, rr = world.walls()[right].reaction;
  EXPECT_NEAR(rl.z() + rr.z(), -weight, 2e-3 * weight);
  EXPECT_NEAR(rl.z(), rr.z(), 2e-2 * weight);  // symmetric supports share the load
  EXPECT_EQ(world.walls()[platen].reaction.norm(), 0.0);
  EXPECT_LT(world.state(id).v.norm(), 1e-4);
}

namespace {

/// A small drop test through the scenario path: 2 layers of a 6 x 6 mm box (15 grains)
/// from 5 mm onto a floor, with the drop test's contact parameters.
const char* kSmallDrop = R"([specimen]
shape = "box"
size = [6.0, 6.0, 2.0]
[grain]
r = 1.0
r_bar = 0.9
t = 1.0
t_bar = 0.85
[orientation]
seed = 5
[material]
density = 3100
[contact]
dilation_radius = 0.05
[contact.particle_particle]
kn = 5000.0
ks = 2000.0
c_res = 2.0
mu_s = 0.3
[contact.particle_wall]
kn = 10000.0
ks = 2000.0
c_res = 10.0
mu_s = 0.3
[dynamics]
dt = 1.2e-6
duration = 0.3
lift = 5.0
[[wall]]
kind = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]
)";

std::uint64_t state_hash(const World& world) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    h = (h ^ bits) * 1099511628211ull;
  };
  for (const BodyId id : world.body_ids()) {
    const BodyState& s = world.state(id);
    for (int k = 0; k < 3; ++k) {
      mix(s.x[k]);
      mix(s.v[k]);
      mix(s.L[k]);
    }
    mix(s.q.w());
    mix(s.q.x());
    mix(s.q.y());
    mix(s.q.z());
  }
  return h;
}

}  // namespace

// The small drop, with the exact search and with the touching pairs' contacts carried
// between searches (manifold_tolerance 0.05: an approximation, so not the same bits, but the
// same physics). The grains fall, bounce and settle above the floor, the impacts' overlaps
// stay small, and the floor carries their weight.
namespace {
class DropSettles : public ::testing::TestWithParam<double> {};
class ThreadCounts : public ::testing::TestWithParam<double> {};

/// "Exact" for manifold_tolerance 0, "Manifolds" otherwise: test names for the parameter.
std::string search_name(const ::testing::TestParamInfo<double>& info) {
  return info.param > 0.0 ? "Manifolds" : "Exact";
}
}  // namespace

TEST_P(DropSettles, GrainsFallBounceAndSettleAboveTheFloor) {
  io::Scenario scenario = io::parse_scenario(kSmallDrop, "small_drop.toml");
  scenario.dynamics.manifold_tolerance = GetParam();
  const geometry::Specimen specimen = geometry::build_specimen(scenario.specimen);
  ASSERT_GE(specimen.grains.size(), 12u);
  World world = sim::make_world(scenario, specimen);
  ASSERT_EQ(world.settings().manifold_tolerance, GetParam());
  const double pe0 = world.potential_energy();
  const double radius = scenario.contact.dilation_radius;
  double max_overlap = 0.0;
  bool settled = false;
  const int steps = static_cast<int>(scenario.dynamics.duration / scenario.dynamics.dt);
  for (int i = 0; i < steps && !settled; ++i) {
    world.step();
    for (const auto& c : world.contacts()) max_overlap = std::max(max_overlap, c.overlap);
    const double released = pe0 - world.potential_energy();
    settled = !world.contacts().empty() && world.kinetic_energy() < 1e-6 * released;
  }
  const double released = pe0 - world.potential_energy();
  EXPECT_TRUE(settled) << "kinetic " << world.kinetic_energy() << " J of " << released << " J";
  EXPECT_GT(released, 0.0);
  // No grain below the floor: every corner stays above it (the dilated surface touches it).
  for (const BodyId id : world.body_ids()) {
    const BodyState& s = world.state(id);
    for (const auto& v : world.shape(world.info(id).shape).primitives.vertices) {
      EXPECT_GT((s.x + s.q * v).z(), 0.0);
    }
  }
  // The deepest overlap during the impacts stays a small fraction of the dilation radius.
  EXPECT_LT(max_overlap, 0.5 * radius);
  EXPECT_GT(max_overlap, 0.0);
  // At rest the floor carries the whole weight.
  double weight = 0.0;
  for (const BodyId id : world.body_ids()) weight += world.info(id).mass * 9.81;
  EXPECT_NEAR(-world.walls()[0].reaction.z(), weight, 0.01 * weight);
}

INSTANTIATE_TEST_SUITE_P(SearchModes, DropSettles, ::testing::Values(0.0, 0.05), search_name);

TEST(DropTest, RepeatRunsAreBitIdentical) {
  const io::Scenario scenario = io::parse_scenario(kSmallDrop, "small_drop.toml");
  const geometry::Specimen specimen = geometry::build_specimen(scenario.specimen);
  World a = sim::make_world(scenario, specimen);
  World b = sim::make_world(scenario, specimen);
  for (int i = 0; i < 60000; ++i) {  // through the first impacts
    a.step();
    b.step();
  }
  EXPECT_FALSE(a.contacts().empty());
  EXPECT_EQ(state_hash(a), state_hash(b));
}

TEST(DropTest, TheNearFeatureCacheChangesNoBit) {
  // The same drop with every pair searched in full every step and with the pairs' near
  // features cached (narrow_phase.hpp), through the impacts and the bouncing.
  const io::Scenario scenario = io::parse_scenario(kSmallDrop, "small_drop.toml");
  const geometry::Specimen specimen = geometry::build_specimen(scenario.specimen);
  World full = sim::make_world(scenario, specimen);
  World cached = sim::make_world(scenario, specimen);
  full.set_feature_skin(0.0);
  cached.set_feature_skin(0.5);
  std::size_t touching_steps = 0;
  for (int i = 0; i < 80000; ++i) {
    full.step();
    cached.step();
    touching_steps += full.contacts().empty() ? 0 : 1;
    if (i % 1000 == 0) {
      ASSERT_EQ(state_hash(full), state_hash(cached)) << "step " << i;
    }
  }
  EXPECT_GT(touching_steps, 10000u);
  EXPECT_EQ(full.contacts().size(), cached.contacts().size());
  EXPECT_EQ(state_hash(full), state_hash(cached));
}

namespace {

/// kSmallDrop's grains packed in a box of x by y by z (m) on its floor, each pressed 5 um
/// into its neighbours' dilated surfaces and 2.5 um into the floor's, with a time step short
/// enough that the packing holds over the steps compared.
io::Scenario pressed_on_the_floor(double x, double y, double z, double manifold_tolerance) {
  io::Scenario s = io::parse_scenario(kSmallDrop, "small_drop.toml");
  s.specimen.outline = geometry::Outline::box(x, y, z);
  s.specimen.r_bar = 1e-3 - (0.1e-3 - 5e-6) / std::sqrt(3.0);
  s.specimen.t_bar = 1e-3 - (0.1e-3 - 5e-6);
  s.dynamics.lift = 0.05e-3 - 2.5e-6;
  s.dynamics.dt = 1e-8;
  s.dynamics.manifold_tolerance = manifold_tolerance;
  return s;
}

/// `scenario` stepped `steps` times on one thread and on two.
std::pair<World, World> on_one_and_two_threads(io::Scenario scenario, int steps) {
  io::Scenario two = scenario;
  scenario.dynamics.threads = 1;
  two.dynamics.threads = 2;
  const geometry::Specimen specimen = geometry::build_specimen(scenario.specimen);
  std::pair<World, World> worlds{sim::make_world(scenario, specimen), sim::make_world(two, specimen)};
  for (int i = 0; i < steps; ++i) {
    worlds.first.step();
    worlds.second.step();
  }
  return worlds;
}

}  // namespace

// A packed block of 168 grains pressed 5 um into each other on a floor (about 850 touching
// pairs and 4,500 contacts, enough for every loop to run on both threads), run on one and
// on two threads, with the exact search and with the contacts carried: each pair of runs
// must end in the same bits.

TEST_P(ThreadCounts, OneAndTwoThreadsGiveBitIdenticalStates) {
  const auto [a, b] = on_one_and_two_threads(pressed_on_the_floor(12e-3, 12e-3, 4e-3, GetParam()), 300);
  ASSERT_EQ(a.body_ids().size(), 168u);
  EXPECT_GT(a.contacts().size(), 2000u);
  EXPECT_EQ(a.contacts().size(), b.contacts().size());
  EXPECT_EQ(state_hash(a), state_hash(b));
}

INSTANTIATE_TEST_SUITE_P(SearchModes, ThreadCounts, ::testing::Values(0.0, 0.02), search_name);

TEST(ThreadCounts, AWideLayerOnAFloorGivesTheSameBitsOnOneAndTwoThreads) {
  // One layer of about 1,200 grains pressed onto a floor: its wall contacts are listed in
  // pieces of body slots, as the threads come free, and joined in order (World::
  // wall_contacts); the floor's contacts fall in every piece. One and two threads must list
  // them in the same order, so that each grain sums them alike: the same bits.
  const auto [a, b] = on_one_and_two_threads(pressed_on_the_floor(56e-3, 56e-3, 1e-3, 0.0), 30);
  ASSERT_GT(a.body_ids().size(), 1100u);
  std::size_t on_floor = 0, last_slot = 0;
  for (const auto& c : a.contacts()) {
    if (!c.wall) continue;
    ++on_floor;
    last_slot = std::max<std::size_t>(last_slot, c.b);
  }
  EXPECT_GT(on_floor, 6000u);       // every grain on its six bottom corners
  EXPECT_GT(last_slot, 1100u);      // in the pieces of the last slots too
  EXPECT_EQ(state_hash(a), state_hash(b));
}

// ---- persistent contact manifolds (WorldSettings::manifold_tolerance > 0) -----------------

TEST(ContactManifolds, AWorldReadBackFromItsStateCarriesOnBitForBit) {
  // The manifolds are part of the world's state: saved through the first impacts and read
  // into a fresh world, the run goes on exactly as the one that was never stopped.
  io::Scenario scenario = io::parse_scenario(kSmallDrop, "small_drop.toml");
  scenario.dynamics.manifold_tolerance = 0.05;
  const geometry::Specimen specimen = geometry::build_specimen(scenario.specimen);
  World a = sim::make_world(scenario, specimen);
  for (int i = 0; i < 60000; ++i) a.step();
  ASSERT_FALSE(a.contacts().empty());
  StateWriter w;
  a.save_state(w);
  World b = sim::make_world(scenario, specimen);
  StateReader r(w.bytes());
  b.load_state(r);
  for (int i = 0; i < 20000; ++i) {
    a.step();
    b.step();
  }
  EXPECT_EQ(state_hash(a), state_hash(b));
}

TEST(DropTest, ATimeStepAboveTheStableLimitIsRefusedWithTheValueNeeded) {
  std::string text = kSmallDrop;
  text.replace(text.find("dt = 1.2e-6"), 11, "dt = 0.001");
  const io::Scenario scenario = io::parse_scenario(text, "small_drop.toml");
  const geometry::Specimen specimen = geometry::build_specimen(scenario.specimen);
  const double limit = sim::stable_time_step(scenario, specimen);
  EXPECT_GT(limit, 1.2e-6);
  EXPECT_LT(limit, 1e-3);
  try {
    (void)sim::make_world(scenario, specimen);
    FAIL() << "no error for dt = 0.001";
  } catch (const io::ScenarioError& e) {
    EXPECT_EQ(e.key(), "dynamics.dt");
    EXPECT_EQ(e.line(), 26);
    EXPECT_NE(std::string(e.what()).find("use dt <="), std::string::npos) << e.what();
  }
}

TEST(GrainStressInAWorld, AGrainRestingOnTheFloorCarriesItsWeightOverItsBase) {
  // Resting on its basal face, the grain's averaged stress (eq. 2.17) is vertical
  // compression: the floor pushes up with the weight W at the contact points, a height h
  // below the centroid (half the thickness plus the dilation radius), gravity acts at the
  // centroid (no arm): sigma_zz = -W h / V.
  World world = gravity_world(soft(1e4, 1.0, 0.3));
  const RigidShape shape = prism_shape();
  const auto sh = world.add_shape(shape);
  world.add_wall(Wall::plane("floor", {0, 0, 0}, {0, 0, 1}));
  const BodyId id = world.add_body(sh, kRho, {0, 0, 0.425e-3 + 0.05e-3 + 10e-6},
                                   shape.orientation_for());
  settle(world, 200000);
  const Eigen::Matrix3d s = world.body_stresses()[id.index];
  const double weight = world.info(id).mass * 9.81;
  const double area = 1.5 * std::sqrt(3.0) * 0.9e-3 * 0.9e-3;
  const double h = 0.425e-3 + 0.05e-3;  // overlap (~1 nm) negligible
  EXPECT_NEAR(s(2, 2), -weight * h / (area * 0.85e-3), 1e-3 * weight * h / (area * 0.85e-3));
  EXPECT_NEAR(s(0, 0), 0.0, 1e-6 * weight / area);
  EXPECT_LT(s(2, 2), 0.0);
}

// ---- motion in the xy plane (WorldSettings::in_plane) ----------------------------------

namespace {
/// A prism standing along z, thrown with velocity and spin out of the plane onto a floor
/// tilted out of it, under a gravity with a z component: every push it gets has a part
/// along z and a torque about x and y.
struct Throw {
  World world;
  BodyId id;
  Eigen::Vector3d largest_reaction = Eigen::Vector3d::Zero();
};

Throw thrown_prism(bool in_plane, int steps) {
  WorldSettings ws;
  ws.gravity = {0, -9.81, -4.0};
  ws.dt = 1e-6;
  ws.particle_wall = soft(1e4, 1.0, 0.3);
  ws.in_plane = in_plane;
  Throw t{World(ws), {}, {}};
  const RigidShape shape = prism_shape();
  const auto sh = t.world.add_shape(shape);
  t.world.add_wall(Wall::plane("floor", {0, 0, 0}, Eigen::Vector3d(0, 1, 0.5).normalized()));
  t.id = t.world.add_body(sh, kRho, {0.2e-3, 1.2e-3, 0.1e-3}, shape.orientation_for(),
                          {2e-3, -20e-3, 5e-3}, {3.0, -2.0, 10.0});
  for (int i = 0; i < steps; ++i) {
    t.world.step();
    const Eigen::Vector3d r = t.world.walls()[0].reaction;
    if (r.norm() > t.largest_reaction.norm()) t.largest_reaction = r;
  }
  return t;
}

/// How far the body's z axis has turned from world z (rad).
double tilt(const World& world, BodyId id) {
  const Eigen::Matrix3d r = world.state(id).q.toRotationMatrix();
  const Eigen::Matrix3d inertia = r * world.info(id).inertia.asDiagonal() * r.transpose();
  // z stays a principal axis while the xz, yz products of inertia are zero.
  return std::hypot(inertia(0, 2), inertia(1, 2)) / inertia.trace();
}
}  // namespace

TEST(InPlane, AGrainPushedOutOfThePlaneKeepsItsHeightAndTurnsAboutZAlone) {
  const Throw held = thrown_prism(true, 20000);
  // It fell onto the floor and the floor pushed it out of the plane as well as up.
  const Eigen::Vector3d r = held.largest_reaction;
  ASSERT_GT(r.norm(), 0.0);
  EXPECT_GT(std::abs(r.z()), 0.2 * r.norm());
  const BodyState& s = held.world.state(held.id);
  EXPECT_LT(s.x.y(), 1.2e-3 - 20e-6);  // it moved in the plane: down onto the floor
  EXPECT_EQ(s.x.z(), 0.1e-3);           // and not out of it, to the bit
  EXPECT_EQ(s.v.z(), 0.0);
  EXPECT_EQ(s.L.x(), 0.0);
  EXPECT_EQ(s.L.y(), 0.0);
  EXPECT_NE(s.L.z(), 0.0);
  EXPECT_LT(tilt(held.world, held.id), 1e-12);
  // The same throw left free goes out of the plane and tips over: the test can fail.
  const Throw free = thrown_prism(false, 20000);
  EXPECT_GT(std::abs(free.world.state(free.id).x.z() - 0.1e-3), 1e-5);
  EXPECT_GT(tilt(free.world, free.id), 1e-3);
}
