// The orientation file (one Bunge triple per grain, degrees): both layouts read back to the
// rotations the angles define, and every malformed line refused with its file, line and column.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "geometry/orientation.hpp"
#include "io/orientation_file.hpp"
#include "io/scenario.hpp"

using namespace cleave;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

constexpr double deg = std::numbers::pi / 180.0;

class OrientationFile : public ::testing::Test {
 protected:
  std::filesystem::path dir_ =
      std::filesystem::temp_directory_path() /
      ("cleave_orientation_file_" +
       std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
       ::testing::UnitTest::GetInstance()->current_test_info()->name());
  void SetUp() override { std::filesystem::create_directories(dir_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path write(const std::string& text) {
    const auto path = dir_ / "grains.ori";
    std::ofstream(path) << text;
    return path;
  }
  /// The error for `text`; fails the test if there is none.
  io::ScenarioError error_for(const std::string& text,
                              std::optional<std::size_t> grains = std::nullopt) {
    const auto path = write(text);
    try {
      io::read_orientation_file(path, grains);
    } catch (const io::ScenarioError& e) {
      EXPECT_EQ(e.file(), path.string());
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos);
      return e;
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return io::ScenarioError("", 0, 0, "", "");
  }
};

/// The crystal axes in specimen coordinates are the rows of g = Rz(phi2) Rx(Phi) Rz(phi1)
/// (matrices written out here, not taken from the library).
Matrix3d passive(double phi1, double Phi, double phi2) {
  const auto rz = [](double a) {
    Matrix3d m;
    m << std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a), 0, 0, 0, 1;
    return m;
  };
  Matrix3d rx;
  rx << 1, 0, 0, 0, std::cos(Phi), std::sin(Phi), 0, -std::sin(Phi), std::cos(Phi);
  return rz(phi2 * deg) * rx * rz(phi1 * deg);
}

}  // namespace

TEST_F(OrientationFile, RowsInGrainOrderGiveTheRotationsOfTheirAngles) {
  const auto q =
      io::read_orientation_file(write("# phi1 Phi phi2\n"
                                      "10 35.5 45   # grain 0\n"
                                      "\n"
                                      "   \t\n"
                                      "200\t90 0\r\n"
                                      "-30 180 400\n"));
  ASSERT_EQ(q.size(), 3u);
  EXPECT_LT((q[0].toRotationMatrix() - passive(10, 35.5 * deg, 45).transpose()).norm(), 1e-14);
  EXPECT_LT((q[1].toRotationMatrix() - passive(200, 90 * deg, 0).transpose()).norm(), 1e-14);
  EXPECT_LT((q[2].toRotationMatrix() - passive(-30, 180 * deg, 400).transpose()).norm(), 1e-14);
}

TEST_F(OrientationFile, AnIndexColumnPlacesEachRowAtItsGrain) {
  const auto q = io::read_orientation_file(write("2 0 90 0\n0 90 0 0\n1 0 0 0\n"), 3);
  ASSERT_EQ(q.size(), 3u);
  // Grain 0: phi1 = 90 turns crystal x onto specimen y; grain 1 the identity; grain 2: Phi = 90
  // turns crystal z onto specimen -y.
  EXPECT_LT((q[0] * Vector3d::UnitX() - Vector3d::UnitY()).norm(), 1e-15);
  EXPECT_LT(std::abs(std::abs(q[1].w()) - 1.0), 1e-15);
  EXPECT_LT((q[2] * Vector3d::UnitZ() + Vector3d::UnitY()).norm(), 1e-15);
}

TEST_F(OrientationFile, WrittenFilesReadBackToTheSameRotations) {
  std::vector<Quaterniond> q;
  for (int g = 0; g < 50; ++g) q.push_back(geometry::uniform_orientation(5, g));
  q.push_back(Quaterniond::Identity());
  q.push_back(geometry::from_bunge(0.3, std::numbers::pi, 1.1));
  const auto path = dir_ / "written.ori";
  io::write_orientation_file(path, q);
  const auto back = io::read_orientation_file(path, q.size());
  ASSERT_EQ(back.size(), q.size());
  for (std::size_t i = 0; i < q.size(); ++i)
    EXPECT_NEAR(std::abs(back[i].dot(q[i])), 1.0, 1e-14) << i;
}

TEST_F(OrientationFile, ANonNumberNamesItsLineColumnAndKey) {
  const auto e = error_for("10 20 30\n# comment\n10 2O 30\n");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.column(), 4);
  EXPECT_EQ(e.key(), "Phi");
  EXPECT_NE(e.message().find("'2O'"), std::string::npos) << e.what();
  EXPECT_EQ(error_for("1 2 nan\n").key(), "phi2");
  EXPECT_EQ(error_for("1.5 1 2 3\n").key(), "grain");
  EXPECT_EQ(error_for("0 1 2 3\n-1 1 2 3\n").line(), 2);
}

TEST_F(OrientationFile, AWrongColumnCountNamesItsLine) {
  auto e = error_for("10 20 30\n10 20\n");
  EXPECT_EQ(e.line(), 2);
  EXPECT_NE(e.message().find("found 2"), std::string::npos) << e.what();
  e = error_for("10 20 30\n\n0 10 20 30\n");
  EXPECT_EQ(e.line(), 3);
  EXPECT_NE(e.message().find("line 1 has 3"), std::string::npos) << e.what();
}

TEST_F(OrientationFile, PhiOutsideZeroTo180IsRefused) {
  auto e = error_for("10 20 30\n10 180.5 30\n");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.key(), "Phi");
  EXPECT_NE(e.message().find("[0, 180]"), std::string::npos) << e.what();
  e = error_for("0 10 -1 30\n");
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.column(), 6);
}

TEST_F(OrientationFile, EveryGrainExactlyOnce) {
  auto e = error_for("0 1 2 3\n1 1 2 3\n0 4 5 6\n");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.key(), "grain");
  EXPECT_NE(e.message().find("first on line 1"), std::string::npos) << e.what();
  e = error_for("0 1 2 3\n1 1 2 3\n3 4 5 6\n");
  EXPECT_EQ(e.line(), 3);
  EXPECT_NE(e.message().find("grain 2 has no line"), std::string::npos) << e.what();
  e = error_for("1 2 3\n4 5 6\n", 3);
  EXPECT_EQ(e.line(), 0);
  EXPECT_NE(e.message().find("2 orientations for 3 grains"), std::string::npos) << e.what();
  e = error_for("# nothing\n\n");
  EXPECT_NE(e.message().find("no orientations"), std::string::npos) << e.what();
}

TEST_F(OrientationFile, AMissingFileNamesTheFile) {
  const auto path = dir_ / "absent.ori";
  try {
    io::read_orientation_file(path);
    FAIL() << "no error";
  } catch (const io::ScenarioError& e) {
    EXPECT_EQ(e.file(), path.string());
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}
