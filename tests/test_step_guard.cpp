// The step guard (physics/dem/step_guard.hpp): a run that blows up is caught at the step it
// happens, with the body and a time step that would have kept the motion in bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "geometry/exact_polyhedron.hpp"
#include "physics/dem/rigid_shape.hpp"
#include "physics/dem/step_guard.hpp"
#include "physics/dem/world.hpp"

using namespace cleave::physics;

namespace {

constexpr double kRho = 3100.0;
constexpr double kDt = 1e-6;

/// Free bodies (no gravity, far apart, nothing to touch).
struct FreeWorld {
  World world;
  std::uint32_t shape;
  double radius;
  FreeWorld() : world(settings()) {
    shape = world.add_shape(
        make_rigid_shape(cleave::geometry::ExactPolyhedron::hexagonal_prism(0.9e-3, 0.85e-3), 0.05e-3));
    radius = world.shape(shape).bounding_radius();
  }
  static WorldSettings settings() {
    WorldSettings ws;
    ws.gravity.setZero();
    ws.dt = kDt;
    ws.particle_particle.kn = ws.particle_wall.kn = 1e4;
    return ws;
  }
  BodyId add(const Eigen::Vector3d& x, const Eigen::Vector3d& v, const Eigen::Vector3d& w = Eigen::Vector3d::Zero(),
             int grain = -1) {
    return world.add_body(shape, kRho, x, Eigen::Quaterniond::Identity(), v, w, grain);
  }
  /// Steps with the guard until it fires or `steps` have passed.
  std::optional<BlowUp> run(StepGuard& guard, int steps) {
    for (int i = 0; i < steps; ++i) {
      guard.before_step(world);
      world.step();
      if (auto b = guard.check(world)) return b;
    }
    return std::nullopt;
  }
};

}  // namespace

TEST(StepGuard, OrdinaryMotionPasses) {
  FreeWorld f;
  // 10 m/s: 1e-5 m per step, a hundredth of the ~1 mm body.
  f.add({0, 0, 0}, {10, 0, 0});
  f.add({0.1, 0, 0}, {0, -10, 0}, {0, 0, 100});
  StepGuard guard;
  EXPECT_FALSE(f.run(guard, 50));
}

TEST(StepGuard, AFastBodyIsNamedWithItsStepAndASafeTimeStep) {
  FreeWorld f;
  f.add({0, 0, 0}, {1, 0, 0}, Eigen::Vector3d::Zero(), 4);
  const double speed = 1000.0;  // 1 mm per step: about the body's own size
  const BodyId fast = f.add({0.1, 0, 0}, {0, 0, speed}, Eigen::Vector3d::Zero(), 7);
  f.add({0.2, 0, 0}, {0, 0, 2 * speed}, Eigen::Vector3d::Zero(), 9);  // later slot: not named
  StepGuard guard;
  const auto b = f.run(guard, 5);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->step, 1u);
  EXPECT_EQ(b->body, fast);
  EXPECT_EQ(b->grain_id, 7);
  EXPECT_TRUE(b->non_finite.empty());
  // A free body moves v dt per step; the limit is a tenth of its bounding radius.
  EXPECT_NEAR(b->displacement, speed * kDt, 1e-12);
  EXPECT_NEAR(b->limit, 0.1 * f.radius, 1e-15);
  EXPECT_DOUBLE_EQ(b->dt, kDt);
  EXPECT_NEAR(b->suggested_dt, 0.1 * f.radius / speed, 1e-15);
  EXPECT_LT(b->suggested_dt, kDt);
}

TEST(StepGuard, TheSuggestedTimeStepKeepsTheSameMotionInBounds) {
  // Run the fast body again with the suggested step: the guard stays quiet.
  FreeWorld f;
  f.add({0, 0, 0}, {0, 0, 1000.0});
  StepGuard guard;
  const auto b = f.run(guard, 1);
  ASSERT_TRUE(b);
  WorldSettings ws = FreeWorld::settings();
  ws.dt = 0.99 * b->suggested_dt;
  World slower(ws);
  const auto sh = slower.add_shape(f.world.shape(0));
  slower.add_body(sh, kRho, {0, 0, 0}, Eigen::Quaterniond::Identity(), {0, 0, 1000.0});
  StepGuard again;
  for (int i = 0; i < 20; ++i) {
    again.before_step(slower);
    slower.step();
    ASSERT_FALSE(again.check(slower)) << "step " << i + 1;
  }
}

TEST(StepGuard, SpinCountsAsMovementOfTheBodysPoints) {
  FreeWorld f;
  // No translation; spinning at 2e5 rad/s about its axis it turns 0.2 rad per 1e-6 s step:
  // its outermost points move 0.2 bounding radii, twice the limit of 0.1.
  f.add({0, 0, 0}, Eigen::Vector3d::Zero(), {0, 0, 2e5});
  StepGuard guard;
  const auto b = f.run(guard, 1);
  ASSERT_TRUE(b);
  EXPECT_GT(b->displacement, b->limit);
  EXPECT_NEAR(b->displacement / f.radius, 0.2, 0.02);  // angle per step, rotation about an axis
}

TEST(StepGuard, NonFiniteStateIsCaughtAtOnce) {
  FreeWorld f;
  f.add({0, 0, 0}, {1, 0, 0});
  const BodyId bad = f.add({0.1, 0, 0}, {std::numeric_limits<double>::quiet_NaN(), 0, 0});
  StepGuard guard;
  guard.before_step(f.world);
  // The NaN position stops the step part-way (the neighbour search refuses it); the guard
  // then names the step that was under way.
  std::optional<BlowUp> b;
  try {
    f.world.step();
    b = guard.check(f.world);
  } catch (const std::exception&) {
    b = guard.check(f.world, false);
  }
  ASSERT_TRUE(b);
  EXPECT_EQ(b->step, 1u);
  EXPECT_EQ(b->body, bad);
  EXPECT_EQ(b->non_finite, "position");  // x += dt v made the position NaN
  EXPECT_DOUBLE_EQ(b->suggested_dt, kDt / 10);
}

TEST(StepGuard, TheFractionIsTheCallers) {
  FreeWorld f;
  f.add({0, 0, 0}, {0, 0, 10.0});  // 1e-5 m per step, about 1% of the radius
  StepGuard strict(0.001);
  const auto b = f.run(strict, 1);
  ASSERT_TRUE(b);
  EXPECT_NEAR(b->limit, 0.001 * f.radius, 1e-18);
  StepGuard usual;
  EXPECT_FALSE(f.run(usual, 1));
}

TEST(StepGuard, TheMessageNamesStepBodyAndTimeSteps) {
  BlowUp b;
  b.step = 1234;
  b.time = 1.234e-3;
  b.body.index = 17;
  b.grain_id = 17;
  b.displacement = 3e-4;
  b.fraction = 0.1;
  b.limit = 1e-4;
  b.dt = 1e-6;
  b.suggested_dt = 1e-6 / 3;
  const std::string above = describe(b, 2e-7);
  EXPECT_NE(above.find("step 1234"), std::string::npos) << above;
  EXPECT_NE(above.find("body 17"), std::string::npos) << above;
  EXPECT_NE(above.find("suggested dt <= 3.33e-07 s"), std::string::npos) << above;
  EXPECT_NE(above.find("use dt <= 2e-07 s"), std::string::npos) << above;  // the smaller
  const std::string within = describe(b, 5e-6);
  EXPECT_NE(within.find("within the stable step"), std::string::npos) << within;
}

TEST(StepGuard, ANonFiniteWallIsNamedBeforeTheBodiesItWouldSpoil) {
  // A wall far from every body, given a NaN velocity: its place is NaN after the step while
  // every body is still finite. The guard names the wall and its velocity (the cause).
  FreeWorld f;
  f.add({0, 0, 0}, {1, 0, 0});
  f.world.add_wall(Wall::plane("floor", {0, 0, -1.0}, {0, 0, 1}));
  f.world.add_wall(Wall::plane("lid", {0, 0, 1.0}, {0, 0, -1}));
  StepGuard guard;
  EXPECT_FALSE(f.run(guard, 2));
  f.world.wall(1).velocity = {0, 0, std::numeric_limits<double>::quiet_NaN()};
  const auto b = f.run(guard, 1);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->step, 3u);
  ASSERT_TRUE(b->wall);
  EXPECT_EQ(*b->wall, 1u);
  EXPECT_EQ(b->wall_name, "lid");
  EXPECT_EQ(b->non_finite, "velocity");
  const std::string text = describe(*b);
  EXPECT_NE(text.find("step 3 "), std::string::npos) << text;
  EXPECT_NE(text.find("wall 1 ('lid'): its velocity is not finite"), std::string::npos) << text;
}

TEST(StepGuard, AsAListenerItMeasuresEachStepFromThatStepsStart) {
  // Registered with the world, the guard remembers the poses before every step: a body
  // moving 0.6 of the limit a step is never flagged, though three steps take it 1.8 limits
  // from where it was before the first; a body moving 2 limits a step is, with one step's
  // displacement, v dt.
  FreeWorld f;
  const double limit = 0.1 * f.radius;
  f.add({0, 0, 0}, {0.6 * limit / kDt, 0, 0});
  StepGuard guard;
  f.world.add_listener(&guard);
  for (int i = 0; i < 3; ++i) {
    f.world.step();
    EXPECT_FALSE(guard.check(f.world)) << "step " << i + 1;
  }
  const double speed = 2.0 * limit / kDt;
  const BodyId fast = f.add({0.1, 0, 0}, {0, speed, 0});
  f.world.step();
  f.world.step();
  const auto b = guard.check(f.world);
  f.world.remove_listener(&guard);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->body, fast);
  EXPECT_NEAR(b->displacement, speed * kDt, 1e-12);
  EXPECT_EQ(b->step, f.world.steps());
}
