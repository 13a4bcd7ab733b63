// Round trips of hand-built closed meshes through assimp (STL binary, STL ASCII, OBJ; one
// scene file or one file per body) and the error paths of read_meshes.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "geometry/polygon_mesh.hpp"
#include "io/mesh_io.hpp"

namespace {

namespace fs = std::filesystem;
using cleave::geometry::PolygonMesh;
using cleave::io::MeshFormat;
using cleave::io::MeshIoError;
using cleave::io::MeshLayout;

// ---------------------------------------------------------------------------------------
// Hand-built bodies. Coordinates are small dyadic numbers, exact in float, so a round trip
// through assimp's single-precision storage loses nothing and volumes compare to 1e-9.

PolygonMesh unit_cube(const std::string& name, const Eigen::Vector3d& origin) {
  PolygonMesh m;
  m.name = name;
  for (int z = 0; z < 2; ++z) {
    m.vertices.push_back(origin + Eigen::Vector3d(0, 0, z));
    m.vertices.push_back(origin + Eigen::Vector3d(1, 0, z));
    m.vertices.push_back(origin + Eigen::Vector3d(1, 1, z));
    m.vertices.push_back(origin + Eigen::Vector3d(0, 1, z));
  }
  m.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  return m;
}

/// Right prism over a counter-clockwise polygon in the xy plane, from z0 to z0 + t.
PolygonMesh prism(const std::string& name, const std::vector<Eigen::Vector2d>& polygon, double z0,
                  double t, const Eigen::Vector3d& shift) {
  PolygonMesh m;
  m.name = name;
  const int n = static_cast<int>(polygon.size());
  for (double z : {z0, z0 + t}) {
    for (const auto& p : polygon) m.vertices.push_back(shift + Eigen::Vector3d(p.x(), p.y(), z));
  }
  std::vector<int> bottom, top;
  for (int i = n - 1; i >= 0; --i) bottom.push_back(i);
  for (int i = 0; i < n; ++i) top.push_back(n + i);
  m.faces = {bottom, top};
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.faces.push_back({i, j, n + j, n + i});
  }
  return m;
}

/// Hexagon (2,0) (1,2) (-1,2) (-2,0) (-1,-2) (1,-2): a 2x4 rectangle plus two triangles of
/// base 4 and height 1, area 8 + 2 + 2 = 12. With thickness 0.5 the prism holds 6.
PolygonMesh hex_prism(const std::string& name, const Eigen::Vector3d& shift) {
  return prism(name, {{2, 0}, {1, 2}, {-1, 2}, {-2, 0}, {-1, -2}, {1, -2}}, 0.0, 0.5, shift);
}
constexpr double kHexPrismVolume = 6.0;

PolygonMesh tetrahedron(const std::string& name, const Eigen::Vector3d& shift) {
  PolygonMesh m;
  m.name = name;
  m.vertices = {shift, shift + Eigen::Vector3d(1, 0, 0), shift + Eigen::Vector3d(0, 1, 0),
                shift + Eigen::Vector3d(0, 0, 1)};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}
constexpr double kTetrahedronVolume = 1.0 / 6.0;

struct Body {
  PolygonMesh mesh;
  double volume;  ///< analytic
};

/// Three disjoint bodies; names with dots like the lineage names of real fragments.
std::vector<Body> three_bodies() {
  return {{unit_cube("cube_0001.0", {0, 0, 0}), 1.0},
          {hex_prism("hexprism_0002.1.0", {6, 0, 0}), kHexPrismVolume},
          {tetrahedron("tet_0003", {0, 6, 0}), kTetrahedronVolume}};
}

std::size_t triangle_count(const PolygonMesh& m) {
  std::size_t n = 0;
  for (const auto& f : m.faces) n += f.size() - 2;
  return n;
}

std::multiset<std::size_t> face_sizes(const PolygonMesh& m) {
  std::multiset<std::size_t> s;
  for (const auto& f : m.faces) s.insert(f.size());
  return s;
}

std::vector<std::array<double, 3>> sorted_points(const PolygonMesh& m) {
  std::vector<std::array<double, 3>> pts;
  for (const auto& v : m.vertices) pts.push_back({v.x(), v.y(), v.z()});
  std::sort(pts.begin(), pts.end());
  return pts;
}

/// All bodies as one mesh (what a single STL solid holds).
PolygonMesh merged(const std::vector<Body>& bodies) {
  PolygonMesh all;
  for (const Body& b : bodies) {
    const int offset = static_cast<int>(all.vertices.size());
    all.vertices.insert(all.vertices.end(), b.mesh.vertices.begin(), b.mesh.vertices.end());
    for (auto f : b.mesh.faces) {
      for (int& v : f) v += offset;
      all.faces.push_back(f);
    }
  }
  return all;
}

bool is_stl(MeshFormat f) {
  return f != MeshFormat::obj;
}

/// Read-back `got` must be `expected` with faces triangulated for STL, polygons kept for OBJ.
void expect_same_body(const PolygonMesh& got, const PolygonMesh& expected, double volume,
                      MeshFormat format) {
  SCOPED_TRACE("body '" + expected.name + "' read back as '" + got.name + "'");
  EXPECT_EQ(got.vertices.size(), expected.vertices.size());
  if (is_stl(format)) {
    EXPECT_EQ(got.faces.size(), triangle_count(expected));
    EXPECT_EQ(face_sizes(got), face_sizes(expected.triangulated()));  // all triangles
  } else {
    EXPECT_EQ(got.faces.size(), expected.faces.size());
    EXPECT_EQ(face_sizes(got), face_sizes(expected));
  }
  EXPECT_TRUE(got.is_closed_and_consistently_oriented());
  EXPECT_NEAR(got.signed_volume(), volume, 1e-9 * volume);
  EXPECT_EQ(sorted_points(got), sorted_points(expected));
}

// ---------------------------------------------------------------------------------------

class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device rd;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string tag = std::string(info->test_suite_name()) + "_" + info->name();
    std::replace_if(
        tag.begin(), tag.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); },
        '_');
    dir_ = fs::temp_directory_path() /
           ("cleave_test_mesh_io_" + tag + "_" + std::to_string(rd()) + std::to_string(rd()));
    ASSERT_TRUE(fs::create_directories(dir_)) << dir_;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  [[nodiscard]] std::set<fs::path> files_in_dir() const {
    std::set<fs::path> s;
    for (const auto& e : fs::directory_iterator(dir_)) s.insert(e.path());
    return s;
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------------------

TEST(MeshIoFixtures, HandBuiltBodiesAreClosedOutwardWithTheirAnalyticVolume) {
  for (const Body& b : three_bodies()) {
    SCOPED_TRACE(b.mesh.name);
    EXPECT_TRUE(b.mesh.is_closed_and_consistently_oriented());
    EXPECT_NEAR(b.mesh.signed_volume(), b.volume, 1e-12 * b.volume);
  }
}

TEST(MeshIoNames, FormatAndLayoutStringsRoundTrip) {
  for (MeshFormat f : {MeshFormat::stl_binary, MeshFormat::stl_ascii, MeshFormat::obj}) {
    EXPECT_EQ(cleave::io::parse_mesh_format(cleave::io::to_string(f)), f);
  }
  for (MeshLayout l : {MeshLayout::scene, MeshLayout::per_fragment}) {
    EXPECT_EQ(cleave::io::parse_mesh_layout(cleave::io::to_string(l)), l);
  }
  EXPECT_EQ(cleave::io::parse_mesh_format("stl"), MeshFormat::stl_binary);
  EXPECT_EQ(cleave::io::parse_mesh_format("stl_ascii"), MeshFormat::stl_ascii);
  EXPECT_EQ(cleave::io::parse_mesh_format("obj"), MeshFormat::obj);
  EXPECT_EQ(cleave::io::parse_mesh_layout("scene"), MeshLayout::scene);
  EXPECT_EQ(cleave::io::parse_mesh_layout("per_fragment"), MeshLayout::per_fragment);
  EXPECT_EQ(cleave::io::extension(MeshFormat::stl_binary), ".stl");
  EXPECT_EQ(cleave::io::extension(MeshFormat::stl_ascii), ".stl");
  EXPECT_EQ(cleave::io::extension(MeshFormat::obj), ".obj");
}

TEST(MeshIoNames, UnknownNamesThrowInvalidArgumentListingTheAcceptedOnes) {
  EXPECT_THROW(cleave::io::parse_mesh_format("ply"), std::invalid_argument);
  EXPECT_THROW(cleave::io::parse_mesh_format("STL"), std::invalid_argument);
  EXPECT_THROW(cleave::io::parse_mesh_format(""), std::invalid_argument);
  EXPECT_THROW(cleave::io::parse_mesh_layout("scenes"), std::invalid_argument);
  try {
    cleave::io::parse_mesh_format("ply");
    FAIL() << "parse_mesh_format(\"ply\") did not throw";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("ply"), std::string::npos) << what;
    EXPECT_NE(what.find("stl_ascii"), std::string::npos) << what;
    EXPECT_NE(what.find("obj"), std::string::npos) << what;
  }
}

// ---------------------------------------------------------------------------------------

class RoundTrip : public TempDir,
                  public ::testing::WithParamInterface<std::tuple<MeshFormat, MeshLayout>> {};

TEST_P(RoundTrip, KeepsBodiesTopologyAndVolume) {
  const auto [format, layout] = GetParam();
  const std::vector<Body> bodies = three_bodies();
  std::vector<PolygonMesh> meshes;
  for (const Body& b : bodies) meshes.push_back(b.mesh);
  const std::string ext = cleave::io::extension(format);
  const bool obj = format == MeshFormat::obj;

  const std::vector<fs::path> written =
      cleave::io::write_meshes(meshes, dir_, "fragments", format, layout);

  // Exactly the announced files exist: no temporary left behind, no material file.
  std::set<fs::path> expected_files;
  if (layout == MeshLayout::scene) {
    expected_files.insert(dir_ / ("fragments" + ext));
  } else {
    for (const Body& b : bodies) expected_files.insert(dir_ / (b.mesh.name + ext));
  }
  EXPECT_EQ(std::set<fs::path>(written.begin(), written.end()), expected_files);
  EXPECT_EQ(written.size(), expected_files.size());
  EXPECT_EQ(files_in_dir(), expected_files);

  if (layout == MeshLayout::per_fragment) {
    for (const Body& b : bodies) {
      const std::vector<PolygonMesh> back = cleave::io::read_meshes(dir_ / (b.mesh.name + ext));
      ASSERT_EQ(back.size(), 1u) << b.mesh.name;
      EXPECT_EQ(back[0].name, b.mesh.name);
      expect_same_body(back[0], b.mesh, b.volume, format);
    }
  } else if (obj) {
    // OBJ keeps one named group per body.
    const std::vector<PolygonMesh> back = cleave::io::read_meshes(dir_ / "fragments.obj");
    ASSERT_EQ(back.size(), bodies.size());
    for (const Body& b : bodies) {
      const auto it = std::find_if(back.begin(), back.end(),
                                   [&](const PolygonMesh& m) { return m.name == b.mesh.name; });
      ASSERT_NE(it, back.end()) << "no mesh named " << b.mesh.name;
      expect_same_body(*it, b.mesh, b.volume, format);
    }
  } else {
    // assimp's STL exporters write every mesh into one solid: the bodies come back as one
    // mesh (disjoint here, so still closed) whose volume is the sum.
    const std::vector<PolygonMesh> back = cleave::io::read_meshes(dir_ / "fragments.stl");
    ASSERT_EQ(back.size(), 1u);
    double total = 0.0;
    for (const Body& b : bodies) total += b.volume;
    PolygonMesh all = merged(bodies);
    all.name = "all bodies";
    expect_same_body(back[0], all, total, format);
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllFormatsAndLayouts, RoundTrip,
    ::testing::Combine(::testing::Values(MeshFormat::stl_binary, MeshFormat::stl_ascii,
                                         MeshFormat::obj),
                       ::testing::Values(MeshLayout::scene, MeshLayout::per_fragment)),
    [](const auto& info) {
      return cleave::io::to_string(std::get<0>(info.param)) + "_" +
             cleave::io::to_string(std::get<1>(info.param));
    });

// ---------------------------------------------------------------------------------------

class MeshIoFiles : public TempDir {};

/// A regular hexagonal prism at grain scale in metres, away from the origin: coordinates
/// are not exact in float, so the round trip is exact only to single precision.
TEST_F(MeshIoFiles, GrainScaleCoordinatesSurviveToSinglePrecision) {
  const double r = 1.7e-3, t = 0.9e-3;
  std::vector<Eigen::Vector2d> hexagon;
  for (int i = 0; i < 6; ++i) {
    const double a = M_PI / 3.0 * i + 0.1;
    hexagon.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  const PolygonMesh grain = prism("grain_0042", hexagon, 3e-3, t, {0.01, -0.02, 0.0});
  const double exact = 3.0 * std::sqrt(3.0) / 2.0 * r * r * t;
  for (MeshFormat f : {MeshFormat::stl_binary, MeshFormat::stl_ascii, MeshFormat::obj}) {
    SCOPED_TRACE(cleave::io::to_string(f));
    const fs::path sub = dir_ / cleave::io::to_string(f);
    cleave::io::write_meshes({grain}, sub, "unused", f, MeshLayout::per_fragment);
    const auto back = cleave::io::read_meshes(sub / ("grain_0042" + cleave::io::extension(f)));
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(back[0].vertices.size(), 12u);
    EXPECT_TRUE(back[0].is_closed_and_consistently_oriented());
    EXPECT_NEAR(back[0].signed_volume(), exact, 1e-5 * exact);
    double max_dev = 0.0;
    for (const auto& p : back[0].vertices) {
      double best = 1.0;
      for (const auto& q : grain.vertices) best = std::min(best, (p - q).norm());
      max_dev = std::max(max_dev, best);
    }
    EXPECT_LT(max_dev, 1e-8);  // float spacing near 0.02 m is 1.9e-9 m
  }
}

/// Distinct vertices stay distinct however close they are, as long as float tells them apart:
/// 1 mm plates of 1 um down to 0.1 nm thickness keep their 8 corners. (assimp 5.2.5's
/// aiProcess_JoinIdenticalVertices welds some of these.)
TEST_F(MeshIoFiles, ThinBodiesKeepTheirVertices) {
  for (const double t : {1e-6, 1e-7, 1e-8, 1e-9, 1e-10}) {
    const PolygonMesh plate =
        prism("plate", {{0, 0}, {1e-3, 0}, {1e-3, 1e-3}, {0, 1e-3}}, 0.0, t, {0, 0, 0});
    for (MeshFormat f : {MeshFormat::stl_binary, MeshFormat::stl_ascii, MeshFormat::obj}) {
      SCOPED_TRACE(cleave::io::to_string(f) + " thickness " + std::to_string(t));
      const fs::path sub = dir_ / cleave::io::to_string(f);
      cleave::io::write_meshes({plate}, sub, "plate", f, MeshLayout::scene);
      const auto back = cleave::io::read_meshes(sub / ("plate" + cleave::io::extension(f)));
      ASSERT_EQ(back.size(), 1u);
      EXPECT_EQ(back[0].vertices.size(), 8u);
      EXPECT_TRUE(back[0].is_closed_and_consistently_oriented());
      const double exact = 1e-3 * 1e-3 * t;
      EXPECT_NEAR(back[0].signed_volume(), exact, 1e-6 * exact);
    }
  }
}

TEST_F(MeshIoFiles, TruncatedBinaryStlThrows) {
  const auto written = cleave::io::write_meshes({unit_cube("cube", {0, 0, 0})}, dir_, "cube",
                                                MeshFormat::stl_binary, MeshLayout::scene);
  ASSERT_EQ(written.size(), 1u);
  const fs::path file = written[0];
  const auto size = fs::file_size(file);
  ASSERT_EQ(size, 84u + 50u * 12u);  // header, count, 12 facets of 50 bytes
  ASSERT_NO_THROW(cleave::io::read_meshes(file));
  fs::resize_file(file, size / 2);
  EXPECT_THROW(cleave::io::read_meshes(file), MeshIoError);
}

TEST_F(MeshIoFiles, GarbageFilesThrow) {
  std::mt19937 rng(12345);
  std::string bytes(4096, '\0');
  for (char& c : bytes) c = static_cast<char>(rng() & 0xff);
  const std::string text = "this is not a mesh\nv 1 2\nf 1 2 3 4\nendsolid nothing\n";
  for (const std::string ext : {".obj", ".stl"}) {
    for (const auto& [what, content] : {std::pair{"random", bytes}, std::pair{"text", text}}) {
      const fs::path file = dir_ / (std::string(what) + ext);
      std::ofstream(file, std::ios::binary) << content;
      SCOPED_TRACE(file.string());
      EXPECT_THROW(cleave::io::read_meshes(file), MeshIoError);
    }
  }
  const fs::path empty = dir_ / "empty.stl";
  std::ofstream(empty, std::ios::binary).flush();
  EXPECT_THROW(cleave::io::read_meshes(empty), MeshIoError);
}

/// Corrupted copies of valid files (bytes overwritten, cut short, junk inserted) either read
/// or throw MeshIoError; nothing else escapes and nothing crashes.
TEST_F(MeshIoFiles, CorruptedFilesReadOrThrowMeshIoError) {
  std::mt19937 rng(20240607);
  for (MeshFormat f : {MeshFormat::stl_binary, MeshFormat::stl_ascii, MeshFormat::obj}) {
    SCOPED_TRACE(cleave::io::to_string(f));
    const fs::path sub = dir_ / cleave::io::to_string(f);
    const fs::path file = cleave::io::write_meshes({hex_prism("hex", {0, 0, 0})}, sub, "hex", f,
                                                   MeshLayout::scene)[0];
    std::string original;
    {
      std::ifstream in(file, std::ios::binary);
      original.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    ASSERT_GT(original.size(), 100u);
    int thrown = 0;
    for (int i = 0; i < 100; ++i) {
      std::string s = original;
      switch (rng() % 3) {
        case 0:
          for (int k = 1 + static_cast<int>(rng() % 8); k > 0; --k) {
            s[rng() % s.size()] = static_cast<char>(rng());
          }
          break;
        case 1:
          s.resize(rng() % s.size());
          break;
        default:
          s.insert(rng() % s.size(), std::string(1 + rng() % 20, static_cast<char>(rng())));
      }
      std::ofstream(file, std::ios::binary | std::ios::trunc) << s;
      try {
        cleave::io::read_meshes(file);
      } catch (const MeshIoError& e) {
        EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
        ++thrown;
      }
    }
    EXPECT_GT(thrown, 0);
  }
}

TEST_F(MeshIoFiles, MissingFileThrowsNamingIt) {
  const fs::path file = dir_ / "no_such_fragment.stl";
  try {
    cleave::io::read_meshes(file);
    FAIL() << "read_meshes on a missing file did not throw";
  } catch (const MeshIoError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

TEST_F(MeshIoFiles, WriteRejectsBadInputNamingTheFile) {
  PolygonMesh bad = unit_cube("bad", {0, 0, 0});
  bad.faces[2][1] = 8;  // one past the last vertex
  try {
    cleave::io::write_meshes({bad}, dir_, "s", MeshFormat::obj, MeshLayout::scene);
    FAIL() << "write_meshes accepted an out-of-range vertex index";
  } catch (const MeshIoError& e) {
    EXPECT_NE(std::string(e.what()).find((dir_ / "s.obj").string()), std::string::npos) << e.what();
  }
  const PolygonMesh a = unit_cube("same", {0, 0, 0});
  const PolygonMesh b = unit_cube("same", {3, 0, 0});
  EXPECT_THROW(
      cleave::io::write_meshes({a, b}, dir_, "s", MeshFormat::stl_binary, MeshLayout::per_fragment),
      MeshIoError);
  EXPECT_THROW(cleave::io::write_meshes({unit_cube("../escape", {0, 0, 0})}, dir_, "s",
                                        MeshFormat::stl_binary, MeshLayout::per_fragment),
               MeshIoError);
  EXPECT_TRUE(files_in_dir().empty());
}

TEST_F(MeshIoFiles, RewriteReplacesTheFile) {
  const PolygonMesh small = unit_cube("body", {0, 0, 0});
  const PolygonMesh big = hex_prism("body", {0, 0, 0});
  cleave::io::write_meshes({small}, dir_, "s", MeshFormat::stl_ascii, MeshLayout::per_fragment);
  cleave::io::write_meshes({big}, dir_, "s", MeshFormat::stl_ascii, MeshLayout::per_fragment);
  const auto back = cleave::io::read_meshes(dir_ / "body.stl");
  ASSERT_EQ(back.size(), 1u);
  EXPECT_NEAR(back[0].signed_volume(), kHexPrismVolume, 1e-9 * kHexPrismVolume);
  EXPECT_EQ(files_in_dir(), std::set<fs::path>{dir_ / "body.stl"});
}

}  // namespace
