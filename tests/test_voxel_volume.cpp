// Volume of hand-built meshes measured through OpenVDB level sets, against closed forms.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "geometry/polygon_mesh.hpp"
#include "io/voxel_volume.hpp"

namespace {

using cleave::geometry::PolygonMesh;
using cleave::io::voxel_volume;

PolygonMesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& size) {
  PolygonMesh m;
  m.name = "box";
  for (int z = 0; z < 2; ++z) {
    for (const auto& [x, y] :
         {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}, std::pair{0, 1}}) {
      m.vertices.push_back(lo + Eigen::Vector3d(x * size.x(), y * size.y(), z * size.z()));
    }
  }
  m.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  return m;
}

/// Regular hexagonal prism of circumradius r and thickness t, hexagon rotated by `phase`.
PolygonMesh hex_prism(double r, double t, double phase, const Eigen::Vector3d& centre) {
  PolygonMesh m;
  m.name = "hex_prism";
  for (double z : {-t / 2, t / 2}) {
    for (int i = 0; i < 6; ++i) {
      const double a = phase + M_PI / 3.0 * i;
      m.vertices.push_back(centre + Eigen::Vector3d(r * std::cos(a), r * std::sin(a), z));
    }
  }
  m.faces = {{5, 4, 3, 2, 1, 0}, {6, 7, 8, 9, 10, 11}};
  for (int i = 0; i < 6; ++i) {
    const int j = (i + 1) % 6;
    m.faces.push_back({i, j, 6 + j, 6 + i});
  }
  return m;
}

double relative_error(double got, double exact) {
  return std::abs(got - exact) / exact;
}

TEST(VoxelVolume, FixturesAreClosedWithTheirAnalyticVolume) {
  const PolygonMesh cube = box({0, 0, 0}, {1, 1, 1});
  EXPECT_TRUE(cube.is_closed_and_consistently_oriented());
  EXPECT_NEAR(cube.signed_volume(), 1.0, 1e-12);
  const PolygonMesh hex = hex_prism(2.0, 0.7, 0.3, {0.1, 0.2, 0.3});
  EXPECT_TRUE(hex.is_closed_and_consistently_oriented());
  const double exact = 3.0 * std::sqrt(3.0) / 2.0 * 4.0 * 0.7;
  EXPECT_NEAR(hex.signed_volume(), exact, 1e-12 * exact);
}

TEST(VoxelVolume, UnitCube) {
  const double v = voxel_volume(box({0, 0, 0}, {1, 1, 1}), 1.0 / 50.0);
  EXPECT_LT(relative_error(v, 1.0), 1e-2) << v;
}

TEST(VoxelVolume, ScalesWithTheMeshUnit) {
  // A 2 mm cube off the origin in metres, voxels of 40 micrometres: same answer in m^3.
  const double edge = 2e-3;
  const double v = voxel_volume(box({0.013, -0.007, 0.002}, {edge, edge, edge}), edge / 50.0);
  EXPECT_LT(relative_error(v, edge * edge * edge), 1e-2) << v;
}

TEST(VoxelVolume, HexagonalPrismMatchesClosedForm) {
  const double r = 1.0, t = 0.6;
  const double exact = 3.0 * std::sqrt(3.0) / 2.0 * r * r * t;
  const double v = voxel_volume(hex_prism(r, t, 0.2, {0.3, -0.4, 0.5}), t / 30.0);
  EXPECT_LT(relative_error(v, exact), 2e-2) << v << " vs " << exact;
}

TEST(VoxelVolume, FinerVoxelsConvergeOnTheHexagonalPrism) {
  const double r = 1.0, t = 0.6;
  const double exact = 3.0 * std::sqrt(3.0) / 2.0 * r * r * t;
  const PolygonMesh hex = hex_prism(r, t, 0.2, {0.3, -0.4, 0.5});
  const double coarse = relative_error(voxel_volume(hex, t / 8.0), exact);
  const double fine = relative_error(voxel_volume(hex, t / 40.0), exact);
  EXPECT_LT(fine, coarse);
  EXPECT_LT(fine, 1e-2);
}

TEST(VoxelVolume, TwoDisjointBodiesAddUp) {
  PolygonMesh two = box({0, 0, 0}, {1, 1, 1});
  const PolygonMesh other = box({3, 0, 0}, {1, 2, 1});
  for (auto f : other.faces) {
    for (int& v : f) v += 8;
    two.faces.push_back(f);
  }
  two.vertices.insert(two.vertices.end(), other.vertices.begin(), other.vertices.end());
  EXPECT_LT(relative_error(voxel_volume(two, 1.0 / 50.0), 3.0), 1e-2);
}

TEST(VoxelVolume, MeshWithAFaceRemovedIsFarFromTheExactVolume) {
  PolygonMesh open = box({0, 0, 0}, {1, 1, 1});
  open.faces.erase(open.faces.begin() + 1);  // the top
  ASSERT_FALSE(open.is_closed_and_consistently_oriented());
  const double v = voxel_volume(open, 1.0 / 50.0);
  EXPECT_GT(relative_error(v, 1.0), 0.05) << "open box measured " << v;
}

/// Unit cube whose top is an n x n grid of quads that shares no vertex index with the sides
/// (geometrically closed, topologically open), with the central quad left out when `hole`.
PolygonMesh cube_with_tiled_top(int n, bool hole) {
  PolygonMesh m = box({0, 0, 0}, {1, 1, 1});
  m.faces.erase(m.faces.begin() + 1);
  const int base = static_cast<int>(m.vertices.size());
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) m.vertices.emplace_back(double(i) / n, double(j) / n, 1.0);
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (hole && i == n / 2 && j == n / 2) continue;
      const int a = base + j * (n + 1) + i;
      m.faces.push_back({a, a + 1, a + n + 2, a + n + 1});
    }
  }
  return m;
}

TEST(VoxelVolume, IgnoresConnectivityOfAGeometricallyClosedSurface) {
  const PolygonMesh tiled = cube_with_tiled_top(10, false);
  ASSERT_FALSE(tiled.is_closed_and_consistently_oriented());
  EXPECT_LT(relative_error(voxel_volume(tiled, 1.0 / 50.0), 1.0), 1e-2);
}

TEST(VoxelVolume, HoleSeveralVoxelsWideIsFarFromTheExactVolume) {
  // A 0.1 x 0.1 hole is 5 voxels wide at voxel 1/50: the outside leaks in.
  const double v = voxel_volume(cube_with_tiled_top(10, true), 1.0 / 50.0);
  EXPECT_GT(relative_error(v, 1.0), 0.05) << "cube with a hole measured " << v;
}

TEST(VoxelVolume, IndependentOfFaceOrientation) {
  // Inverted faces do not change the measured volume: orientation is signed_volume's job.
  PolygonMesh inside_out = box({0, 0, 0}, {1, 1, 1});
  for (auto& f : inside_out.faces) std::reverse(f.begin(), f.end());
  ASSERT_LT(inside_out.signed_volume(), 0.0);
  EXPECT_LT(relative_error(voxel_volume(inside_out, 1.0 / 50.0), 1.0), 1e-2);
}

TEST(VoxelVolume, NonPositiveVoxelSizeThrows) {
  const PolygonMesh cube = box({0, 0, 0}, {1, 1, 1});
  EXPECT_THROW(voxel_volume(cube, 0.0), std::invalid_argument);
  EXPECT_THROW(voxel_volume(cube, -0.1), std::invalid_argument);
  EXPECT_THROW(voxel_volume(cube, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

TEST(VoxelVolume, EmptyMeshThrows) {
  PolygonMesh empty;
  empty.name = "empty";
  EXPECT_THROW(voxel_volume(empty, 0.1), std::invalid_argument);
}

}  // namespace
