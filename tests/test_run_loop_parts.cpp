// The run loop's parts on their own: the CSV writer every history goes through (the
// precision of each column, empty fields, the first value that is not finite, named), and a
// stage's wall ramp as a listener of the World (velocities on the closed-form ramp, gone
// with its stage).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "io/scenario.hpp"
#include "physics/dem/wall.hpp"
#include "physics/dem/world.hpp"
#include "sim/boundary_conditions.hpp"
#include "sim/run_tables.hpp"

namespace cleave::sim {
namespace {

/// printf's %.Ng, independent of the writer's formatting library.
std::string printf_g(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

TEST(RunTables, TheHeaderIsTheColumnsWithTheirUnits) {
  const CsvTable energy("energy.csv", EnergyRow::columns());
  EXPECT_EQ(energy.text(), "time_s,kinetic_J,potential_J,contacts,max_overlap_m,stage\n");
  EXPECT_FALSE(energy.has_rows());
}

TEST(RunTables, NumbersAreWrittenWithTheirColumnsSignificantDigits) {
  CsvTable energy("energy.csv", EnergyRow::columns());
  const double third = 1.0 / 3.0, tiny = 2.0 / 3.0 * 1e-7;
  energy.add(EnergyRow{third, 7.0, -third, 12, tiny, "load"}.cells());
  const std::string expected =
      printf_g(third, 9) + ",7," + printf_g(-third, 9) + ",12," + printf_g(tiny, 6) + ",load\n";
  EXPECT_EQ(energy.rows().size(), 1u);
  EXPECT_EQ(energy.text().substr(energy.text().find('\n') + 1), expected);
}

TEST(RunTables, AStageWithoutLoadWallsLeavesTheLoadFieldsEmpty) {
  std::vector<physics::Wall> walls{physics::Wall::plane("floor", {0, 0, 0}, {0, 0, 1})};
  CsvTable loads("load_displacement.csv", LoadsRow::columns(walls));
  EXPECT_EQ(loads.text(),
            "time_s,step,stage,floor_displacement_m,floor_force_N,load_N,"
            "load_point_displacement_m\n");
  loads.add(LoadsRow{0.5, 3, "drop", {{2.0, -1.0}}, std::nullopt}.cells());
  EXPECT_EQ(loads.rows().back(), (std::vector<std::string>{"0.5", "3", "drop", "-1", "2", "", ""}));
}

TEST(RunTables, TheFirstValueThatIsNotFiniteIsNamedByItsFileAndColumn) {
  const CsvTable energy("energy.csv", EnergyRow::columns());
  EXPECT_FALSE(energy.non_finite(EnergyRow{1.0, 2.0, 3.0, 4, 5.0, "s"}.cells()));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(energy.non_finite(EnergyRow{1.0, inf, nan, 4, 5.0, "s"}.cells()),
            "energy.csv kinetic_J");
  EXPECT_EQ(energy.non_finite(EnergyRow{1.0, 2.0, 3.0, 4, nan, "s"}.cells()),
            "energy.csv max_overlap_m");
}

TEST(RunTables, RowsAreReadBackByStage) {
  CsvTable cell("cell.csv", CellRow::columns());
  cell.add(CellRow{0.1, "a"}.cells());
  cell.add(CellRow{0.2, "b"}.cells());
  cell.add(CellRow{0.3, "a"}.cells());
  ASSERT_EQ(cell.rows("a").size(), 2u);
  EXPECT_EQ(cell.rows("a")[1][0], "0.3");
  EXPECT_EQ(cell.rows().size(), 3u);
}

TEST(StageConditions, AWallRampsLinearlyAtEachStepsMidpointAndStopsWithItsStage) {
  physics::WorldSettings settings;
  settings.dt = 1e-3;
  physics::World world(settings);
  world.add_wall(physics::Wall::plane("lid", {0, 0, 1.0}, {0, 0, -1}));
  io::StageDef stage;
  stage.name = "press";
  const Eigen::Vector3d v(0, 0, -2.0);
  stage.wall_velocity = {{"lid", v}};
  stage.ramp_time = 4.5e-3;  // reached in the fifth step
  {
    const StageConditions conditions(world, stage, 0);
    for (int k = 0; k < 8; ++k) {
      world.step();
      // The velocity the step used: min(1, t / ramp_time) v at t = (k + 1/2) dt.
      const double f = std::min(1.0, (k + 0.5) * settings.dt / stage.ramp_time);
      EXPECT_NEAR(world.walls()[0].velocity.z(), f * v.z(), 1e-15) << "step " << k + 1;
    }
  }
  world.wall(0).velocity.setZero();
  world.step();
  EXPECT_EQ(world.walls()[0].velocity.z(), 0.0) << "the ramp outlived its stage";
}

TEST(StageConditions, AResumedStageContinuesItsRampFromItsOwnSteps) {
  physics::WorldSettings settings;
  settings.dt = 1e-3;
  physics::World world(settings);
  world.add_wall(physics::Wall::plane("lid", {0, 0, 1.0}, {0, 0, -1}));
  for (int k = 0; k < 5; ++k) world.step();  // an earlier stage's steps
  io::StageDef stage;
  stage.wall_velocity = {{"lid", Eigen::Vector3d(0, 0, -1.0)}};
  stage.ramp_time = 10e-3;
  const StageConditions conditions(world, stage, 2);  // two steps of this stage were taken
  world.step();
  EXPECT_NEAR(world.walls()[0].velocity.z(), -(2.5e-3 / 10e-3), 1e-15);
}

}  // namespace
}  // namespace cleave::sim
