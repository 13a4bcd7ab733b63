#include "sim/boundary_conditions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "io/field_expression.hpp"

namespace cleave::sim {

namespace {

using io::StageDef;

/// Steps of the stage taken before the coming one.
class StageClock {
 public:
  StageClock(const physics::World& world, std::uint64_t steps_before)
      : first_(world.steps() - steps_before) {}
  [[nodiscard]] std::uint64_t done(const physics::World& world) const {
    return world.steps() - first_;
  }

 private:
  std::uint64_t first_;
};

/// The walls' velocities at the middle of each step, on the stage's linear ramp.
class WallRamp final : public physics::StepListener {
 public:
  WallRamp(const physics::World& world, const StageDef& stage, StageClock clock)
      : stage_(stage), clock_(clock) {
    for (const auto& [name, v] : stage.wall_velocity) walls_.push_back(wall_index(world, name));
  }
  void before_step(physics::World& world) override {
    const double t = (static_cast<double>(clock_.done(world)) + 0.5) * world.settings().dt;
    const double f = std::min(1.0, t / stage_.ramp_time);
    for (std::size_t k = 0; k < walls_.size(); ++k)
      world.wall(walls_[k]).velocity = f * stage_.wall_velocity[k].second;
  }

 private:
  const StageDef& stage_;
  StageClock clock_;
  std::vector<std::size_t> walls_;
};

/// The stage's uniform heating or cooling, each step's share, up to its target.
class TemperatureRamp final : public physics::StepListener {
 public:
  explicit TemperatureRamp(const StageDef& stage) : stage_(stage) {}
  void before_step(physics::World& world) override {
    world.ramp_temperature(stage_.temperature_rate * world.settings().dt,
                           stage_.temperature_target);
  }

 private:
  const StageDef& stage_;
};

/// Sets each of `ids` not held by a quench to `kelvin(id)`; a value not above 0 K stops the
/// run naming the stage, its key, the grain, its centroid and the step.
template <class F>
void prescribe_temperatures(physics::World& world, const StageDef& stage, std::uint64_t step,
                            const char* key, const std::vector<physics::BodyId>& ids, F&& kelvin) {
  for (const physics::BodyId id : ids) {
    if (world.slot_thermal()[id.index].held) continue;
    const double t = kelvin(id);
    if (!(t > 0.0)) {
      const Eigen::Vector3d& x = world.state(id).x;
      throw std::runtime_error(fmt::format(
          "stage '{}': {} gives {:.4g} K at grain {} (x = [{:.6g}, {:.6g}, {:.6g}] m) "
          "at step {} of the stage (t = {:.4g} s); keep every grain above 0 K",
          stage.name, key, t, world.info(id).grain_id, x.x(), x.y(), x.z(), step, world.time()));
    }
    world.set_temperature(id, t);
  }
}

/// The stage's growing linear field, each step's share, about the grains' mean centroid
/// then (held grains keep theirs).
class TemperatureGradient final : public physics::StepListener {
 public:
  TemperatureGradient(const StageDef& stage, StageClock clock) : stage_(stage), clock_(clock) {}
  void before_step(physics::World& world) override {
    const auto ids = world.body_ids();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const physics::BodyId id : ids)
      centre += world.state(id).x / static_cast<double>(ids.size());
    const double h = world.settings().dt;
    prescribe_temperatures(
        world, stage_, clock_.done(world) + 1, "temperature_gradient_rate", ids,
        [&](physics::BodyId id) {
          return world.temperature(id) +
                 h * stage_.temperature_gradient_rate.dot(world.state(id).x - centre);
        });
  }

 private:
  const StageDef& stage_;
  StageClock clock_;
};

/// The stage's prescribed field T(x, y, z, t) at each grain's centroid, t at the end of the
/// step (seconds since the stage began).
class TemperatureField final : public physics::StepListener {
 public:
  TemperatureField(const StageDef& stage, StageClock clock)
      : stage_(stage), clock_(clock), field_(stage.temperature_field) {}
  void before_step(physics::World& world) override {
    const std::uint64_t step = clock_.done(world) + 1;
    const double t = static_cast<double>(step) * world.settings().dt;
    prescribe_temperatures(world, stage_, step, "temperature_field", world.body_ids(),
                           [&](physics::BodyId id) {
                             const Eigen::Vector3d& x = world.state(id).x;
                             return field_(x.x(), x.y(), x.z(), t);
                           });
  }

 private:
  const StageDef& stage_;
  StageClock clock_;
  io::FieldExpression field_;
};

/// A stage's thermal shock: the grains within quench_depth of the wall's plane held at
/// quench_temperature; those a previous stage held are let go first.
void quench(physics::World& world, const StageDef& stage) {
  for (const physics::BodyId id : world.body_ids()) world.set_temperature_held(id, false);
  if (stage.quench_wall.empty()) return;
  const physics::Wall& w = world.walls()[wall_index(world, stage.quench_wall)];
  const Eigen::Vector3d n = w.normal.normalized();
  for (const physics::BodyId id : world.body_ids()) {
    if (std::abs((world.state(id).x - w.origin).dot(n)) > stage.quench_depth) continue;
    world.set_temperature(id, stage.quench_temperature);
    world.set_temperature_held(id, true);
  }
}

}  // namespace

std::size_t wall_index(const physics::World& world, const std::string& name) {
  for (std::size_t i = 0; i < world.walls().size(); ++i) {
    if (world.walls()[i].name == name) return i;
  }
  throw std::logic_error("no wall named " + name);
}

void begin_stage_conditions(physics::World& world, const io::Scenario& scenario,
                            const StageDef& stage, bool resumed) {
  if (!resumed) {
    for (std::size_t i = 0; i < world.walls().size(); ++i) world.wall(i).velocity.setZero();
    for (const auto& [name, v] : stage.wall_velocity)
      world.wall(wall_index(world, name)).velocity = v;
    if (scenario.thermal.enabled) quench(world, stage);
    // A periodic cell stretches at the stage's rates (and stands still without them).
    if (world.cell()) world.set_velocity_gradient(stage.cell_strain_rate.asDiagonal());
  }
  // A stress-free cell outside its strain tests ([periodic] stress_control_time).
  if (world.cell()) {
    const io::PeriodicDef& p = scenario.periodic;
    world.set_stress_control(p.stress_control_modulus,
                             stage.cell_strain_rate.isZero(0.0) ? p.stress_control_time : 0.0);
  }
}

StageConditions::StageConditions(physics::World& world, const StageDef& stage,
                                 std::uint64_t steps_before)
    : world_(world) {
  const StageClock clock(world, steps_before);
  if (stage.ramp_time > 0.0) listeners_.push_back(std::make_unique<WallRamp>(world, stage, clock));
  if (stage.temperature_rate != 0.0) listeners_.push_back(std::make_unique<TemperatureRamp>(stage));
  if (!stage.temperature_gradient_rate.isZero(0.0))
    listeners_.push_back(std::make_unique<TemperatureGradient>(stage, clock));
  if (!stage.temperature_field.empty())
    listeners_.push_back(std::make_unique<TemperatureField>(stage, clock));
  for (const auto& l : listeners_) world_.add_listener(l.get());
}

StageConditions::~StageConditions() {
  for (const auto& l : listeners_) world_.remove_listener(l.get());
}

}  // namespace cleave::sim
