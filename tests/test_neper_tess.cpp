// Imported tessellations: a Neper .tess written by hand from the format's specification
// (Neper's doc/fileformat.rst, format 3.x as Neper 4 writes it) and a plain grain file, read
// back; orientations against rotation matrices written out here.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/orientation.hpp"
#include "geometry/voronoi.hpp"
#include "io/neper_tess.hpp"

namespace io = cleave::io;
namespace g = cleave::geometry;

namespace {

// The unit cube cut by the plane x = 0.5 into two cells: seeds (0.25, 0.5, 0.5) and
// (0.75, 0.5, 0.5) with equal weights. 12 vertices, 20 edges, 11 faces (face 3 the shared one,
// its normal +x pointing out of cell 1), 2 polyhedra; a cube domain. Cell 1 is Bunge
// (90, 0, 0), cell 2 Bunge (0, 90, 0), passive.
const char* const kTwoCells = R"(***tess
 **format
   3.4
 **general
   3 standard
 **cell
  2
  *id
   1 2
  *crysym
   cubic
  *seed
   1 0.250000000000 0.500000000000 0.500000000000 0.200000000000
   2 0.750000000000 0.500000000000 0.500000000000 0.200000000000
  *ori
   euler-bunge:passive
   90.000000000000 0.000000000000 0.000000000000
   0.000000000000 90.000000000000 0.000000000000
  *mode
   1 1
 **vertex
 12
   1 0.000000000000 0.000000000000 0.000000000000 0
   2 0.500000000000 0.000000000000 0.000000000000 0
   3 1.000000000000 0.000000000000 0.000000000000 0
   4 0.000000000000 1.000000000000 0.000000000000 0
   5 0.500000000000 1.000000000000 0.000000000000 0
   6 1.000000000000 1.000000000000 0.000000000000 0
   7 0.000000000000 0.000000000000 1.000000000000 0
   8 0.500000000000 0.000000000000 1.000000000000 0
   9 1.000000000000 0.000000000000 1.000000000000 0
  10 0.000000000000 1.000000000000 1.000000000000 0
  11 0.500000000000 1.000000000000 1.000000000000 0
  12 1.000000000000 1.000000000000 1.000000000000 0
 **edge
 20
   1 1 2 0
   2 2 3 0
   3 4 5 0
   4 5 6 0
   5 7 8 0
   6 8 9 0
   7 10 11 0
   8 11 12 0
   9 1 4 0
  10 2 5 0
  11 3 6 0
  12 7 10 0
  13 8 11 0
  14 9 12 0
  15 1 7 0
  16 2 8 0
  17 3 9 0
  18 4 10 0
  19 5 11 0
  20 6 12 0
 **face
 11
   1 4 1 7 10 4
     4 15 12 -18 -9
    0.000000000000 -1.000000000000 0.000000000000 0.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
   2 4 3 6 12 9
     4 11 20 -14 -17
    1.000000000000 1.000000000000 0.000000000000 0.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
   3 4 2 5 11 8
     4 10 19 -13 -16
    0.500000000000 1.000000000000 0.000000000000 0.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
   4 4 1 2 8 7
     4 1 16 -5 -15
    0.000000000000 0.000000000000 -1.000000000000 0.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
   5 4 2 3 9 8
     4 2 17 -6 -16
    0.000000000000 0.000000000000 -1.000000000000 0.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
   6 4 4 10 11 5
     4 18 7 -19 -3
    1.000000000000 0.000000000000 1.000000000000 0.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
   7 4 5 11 12 6
     4 19 8 -20 -4
    1.000000000000 0.000000000000 1.000000000000 0.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
   8 4 1 4 5 2
     4 9 3 -10 -1
    0.000000000000 0.000000000000 0.000000000000 -1.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
   9 4 2 5 6 3
     4 10 4 -11 -2
    0.000000000000 0.000000000000 0.000000000000 -1.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
  10 4 7 8 11 10
     4 5 13 -7 -12
    1.000000000000 0.000000000000 0.000000000000 1.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
  11 4 8 9 12 11
     4 6 14 -8 -13
    1.000000000000 0.000000000000 0.000000000000 1.000000000000
     0 0 0.000000000000 0.000000000000 0.000000000000
 **polyhedron
 2
   1 6 1 3 4 6 8 10
   2 6 2 -3 5 7 9 11
 **domain
  *general
   cube
  *vertex
   8
   1 0.000000000000 0.000000000000 0.000000000000 x0y0z0
      1 1
   2 1.000000000000 0.000000000000 0.000000000000 x1y0z0
      1 3
   3 1.000000000000 1.000000000000 0.000000000000 x1y1z0
      1 6
   4 0.000000000000 1.000000000000 0.000000000000 x0y1z0
      1 4
   5 0.000000000000 0.000000000000 1.000000000000 x0y0z1
      1 7
   6 0.000000000000 1.000000000000 1.000000000000 x0y1z1
      1 10
   7 1.000000000000 1.000000000000 1.000000000000 x1y1z1
      1 12
   8 1.000000000000 0.000000000000 1.000000000000 x1y0z1
      1 9
  *edge
   12
   1 2 4 6
     x0y1
     1 18
   2 2 6 5
     x0z1
     1 12
   3 2 5 1
     x0y0
     1 15
   4 2 1 4
     x0z0
     1 9
   5 2 2 8
     x1y0
     1 17
   6 2 8 7
     x1z1
     1 14
   7 2 7 3
     x1y1
     1 20
   8 2 3 2
     x1z0
     1 11
   9 2 5 8
     y0z1
     2 5 6
  10 2 2 1
     y0z0
     2 1 2
  11 2 4 3
     y1z0
     2 3 4
  12 2 7 6
     y1z1
     2 7 8
  *face
   6
   1 4 4 6 5 1
     4 1 2 3 4
     plane
     4 0.000000000000 1.000000000000 0.000000000000 0.000000000000
     x0
     1 1
   2 4 2 8 7 3
     4 5 6 7 8
     plane
     4 -1.000000000000 -1.000000000000 -0.000000000000 -0.000000000000
     x1
     1 2
   3 4 1 5 8 2
     4 3 9 5 10
     plane
     4 0.000000000000 0.000000000000 1.000000000000 0.000000000000
     y0
     2 4 5
   4 4 4 3 7 6
     4 11 7 12 1
     plane
     4 -1.000000000000 -0.000000000000 -1.000000000000 -0.000000000000
     y1
     2 6 7
   5 4 1 2 3 4
     4 10 8 11 4
     plane
     4 0.000000000000 0.000000000000 0.000000000000 1.000000000000
     z0
     2 8 9
   6 4 5 6 7 8
     4 2 12 6 9
     plane
     4 -1.000000000000 -0.000000000000 -0.000000000000 -1.000000000000
     z1
     2 10 11
***end
)";

/// The 1-based line of the first occurrence of `needle` in `text`.
int line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

void expect_matrix(const Eigen::Quaterniond& q, const Eigen::Matrix3d& m) {
  EXPECT_LT((q.toRotationMatrix() - m).norm(), 1e-12) << q.toRotationMatrix() << "\nexpected\n"
                                                      << m;
}

Eigen::Matrix3d rows(double a, double b, double c, double d, double e, double f, double g_,
                     double h, double i) {
  Eigen::Matrix3d m;
  m << a, b, c, d, e, f, g_, h, i;
  return m;
}

std::string error_of(const std::string& text) {
  try {
    (void)io::parse_neper_tess(text, "hand.tess");
  } catch (const io::TessellationFileError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(NeperTess, HandWrittenTwoCellFileReadsBackAsTwoExactHalves) {
  const io::ImportedTessellation t = io::parse_neper_tess(kTwoCells, "hand.tess");
  ASSERT_EQ(t.cells.size(), 2u);
  EXPECT_EQ(t.ids, (std::vector<int>{1, 2}));
  EXPECT_EQ(t.crystal_symmetry, "cubic");
  EXPECT_EQ(t.cells[0].volume(), g::ExactScalar(0.5));
  EXPECT_EQ(t.cells[1].volume(), g::ExactScalar(0.5));
  EXPECT_EQ(g::total_volume(t.cells), g::ExactScalar(1.0));
  EXPECT_EQ(t.domain_volume, g::ExactScalar(1.0));
  // Weights are Neper's radii: power |x - s|^2 - w^2.
  EXPECT_DOUBLE_EQ(t.weights[0], 0.2 * 0.2);
  ASSERT_EQ(t.orientations.size(), 2u);
  // Passive Bunge: g = Rz(phi2) Rx(Phi) Rz(phi1) maps specimen to crystal; crystal -> specimen
  // is g^T. (90, 0, 0): g = [[0, 1, 0], [-1, 0, 0], [0, 0, 1]].
  expect_matrix(t.orientations[0], rows(0, -1, 0, 1, 0, 0, 0, 0, 1));
  // (0, 90, 0): g = [[1, 0, 0], [0, 0, 1], [0, -1, 0]].
  expect_matrix(t.orientations[1], rows(1, 0, 0, 0, 0, -1, 0, 1, 0));
}

TEST(NeperTess, ScaleMultipliesEveryLength) {
  const io::ImportedTessellation t = io::parse_neper_tess(kTwoCells, "hand.tess", 1e-3);
  EXPECT_EQ(g::total_volume(t.cells), t.domain_volume);
  EXPECT_NEAR(t.cells[0].volume().to_double(), 0.5e-9, 1e-24);
  EXPECT_NEAR(t.seeds[1].x(), 0.75e-3, 1e-18);
}

TEST(NeperTess, SeedsThatDoNotMakeTheFilesCellsAreRefusedNamingThePolyhedron) {
  // Unequal weights move the shared face off x = 0.5: the rebuilt cells disagree.
  const std::string text = replaced(kTwoCells, "0.500000000000 0.500000000000 0.200000000000",
                                    "0.500000000000 0.500000000000 0.400000000000");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("hand.tess:" + std::to_string(line_of(text, "   1 6 1 3 4 6 8 10")) + ":"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("cell 1"), std::string::npos) << e;
}

TEST(NeperTess, MalformedFilesAreRefusedNamingTheLine) {
  {
    const std::string text =
        replaced(kTwoCells, "  11 0.500000000000 1.000000000000 1.000000000000 0",
                 "  11 0.5x00000000000 1.000000000000 1.000000000000 0");
    const std::string e = error_of(text);
    EXPECT_NE(
        e.find("hand.tess:" + std::to_string(line_of(text, "0.5x0")) + ": a vertex coordinate"),
        std::string::npos)
        << e;
  }
  {
    const std::string text = replaced(kTwoCells, "   euler-bunge:passive", "   euler-kocks");
    const std::string e = error_of(text);
    EXPECT_NE(e.find("hand.tess:" + std::to_string(line_of(text, "euler-kocks")) + ":"),
              std::string::npos)
        << e;
    EXPECT_NE(e.find("euler-kocks"), std::string::npos) << e;
  }
  {
    const std::string text = replaced(kTwoCells, "   3.4\n", "   2.0\n");
    EXPECT_NE(error_of(text).find("hand.tess:3: format version 2.0"), std::string::npos)
        << error_of(text);
  }
  {
    const std::string text = replaced(kTwoCells, "***end\n", "");
    EXPECT_NE(error_of(text).find("ends without ***end"), std::string::npos) << error_of(text);
  }
  {
    const std::string text = replaced(kTwoCells, "   2 6 2 -3 5 7 9 11", "   2 6 2 -3 5 7 9 12");
    const std::string e = error_of(text);
    EXPECT_NE(e.find("hand.tess:" + std::to_string(line_of(text, "   2 6 2 -3 5 7 9 12")) +
                     ": polyhedron 2 names face 12"),
              std::string::npos)
        << e;
  }
  {
    // A regularised face (state 1) is not planar.
    const std::string text = replaced(
        kTwoCells, "    0.500000000000 1.000000000000 0.000000000000 0.000000000000\n     0 0",
        "    0.500000000000 1.000000000000 0.000000000000 0.000000000000\n     1 0");
    EXPECT_NE(error_of(text).find("regularised"), std::string::npos) << error_of(text);
  }
}

TEST(NeperOrientation, DescriptorsAndConventionsMatchMatricesWrittenOut) {
  const double s = std::sqrt(0.5);
  // Neper's matrix for a 90-degree rotation about z: g = [[0, 1, 0], [-1, 0, 0], [0, 0, 1]].
  const Eigen::Matrix3d gz = rows(0, 1, 0, -1, 0, 0, 0, 0, 1);
  // Passive: crystal -> specimen is g^T; active (Neper's default): g itself.
  expect_matrix(io::neper_orientation("rodrigues:passive", {0, 0, 1}), gz.transpose());
  expect_matrix(io::neper_orientation("rodrigues", {0, 0, 1}), gz);
  expect_matrix(io::neper_orientation("rodrigues:active", {0, 0, 1}), gz);
  expect_matrix(io::neper_orientation("quaternion:passive", {s, 0, 0, s}), gz.transpose());
  expect_matrix(io::neper_orientation("axis-angle:passive", {0, 0, 1, 90}), gz.transpose());
  expect_matrix(io::neper_orientation("rotmat:passive", {0, 1, 0, -1, 0, 0, 0, 0, 1}),
                gz.transpose());
  expect_matrix(io::neper_orientation("euler-bunge:passive", {90, 0, 0}), gz.transpose());
  expect_matrix(io::neper_orientation("euler-bunge", {90, 0, 0}), gz);
  // 90 degrees about x: g = [[1, 0, 0], [0, 0, 1], [0, -1, 0]].
  const Eigen::Matrix3d gx = rows(1, 0, 0, 0, 0, 1, 0, -1, 0);
  expect_matrix(io::neper_orientation("axis-angle:passive", {2, 0, 0, 90}), gx.transpose());
  expect_matrix(io::neper_orientation("euler-bunge:passive", {0, 90, 0}), gx.transpose());
  // A general passive Bunge triple, g = Rz(phi2) Rx(Phi) Rz(phi1) multiplied out.
  const double p1 = 30 * M_PI / 180, P = 40 * M_PI / 180, p2 = 50 * M_PI / 180;
  const double c1 = std::cos(p1), s1 = std::sin(p1), c = std::cos(P), sP = std::sin(P),
               c2 = std::cos(p2), s2 = std::sin(p2);
  const Eigen::Matrix3d g = rows(c1 * c2 - s1 * s2 * c, s1 * c2 + c1 * s2 * c, s2 * sP,    //
                                 -c1 * s2 - s1 * c2 * c, -s1 * s2 + c1 * c2 * c, c2 * sP,  //
                                 s1 * sP, -c1 * sP, c);
  expect_matrix(io::quaternion_from_bunge_degrees(30, 40, 50), g.transpose());
  EXPECT_THROW((void)io::neper_orientation("rodrigues:sideways", {0, 0, 1}), std::invalid_argument);
  EXPECT_THROW((void)io::neper_orientation("rodrigues", {0, 0}), std::invalid_argument);
  EXPECT_THROW((void)io::neper_orientation("euler-roe", {0, 0, 0}), std::invalid_argument);
}

TEST(GrainFile, HandWrittenGrainsTileTheBoxExactlyWithTheirVolumes) {
  // Four grains in a 2 x 1 x 1 mm box (file lengths in mm, scale 1e-3), volumes 0.2, 0.3,
  // 0.6, 0.9 mm^3 (sum 2), Bunge angles in degrees.
  const std::string text =
      "# x y z volume phi1 Phi phi2\n"
      "0.3 0.3 0.5 0.2  0 0 0\n"
      "\n"
      "0.4 0.7 0.5 0.3  90 0 0   # rotated about z\n"
      "1.2 0.3 0.4 0.6  0 90 0\n"
      "1.5 0.7 0.6 0.9  10 20 30\n";
  const Eigen::Vector3d size(2e-3, 1e-3, 1e-3);
  const io::ImportedTessellation t = io::parse_grain_file(text, "grains.txt", 1e-3, size);
  ASSERT_EQ(t.cells.size(), 4u);
  EXPECT_EQ(g::total_volume(t.cells), g::exact_box(Eigen::Vector3d::Zero(), size).volume());
  const double want[] = {0.2e-9, 0.3e-9, 0.6e-9, 0.9e-9};
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(t.cells[static_cast<std::size_t>(i)].volume().to_double(), want[i], 2e-3 * want[i])
        << i;
  expect_matrix(t.orientations[0], Eigen::Matrix3d::Identity());
  expect_matrix(t.orientations[1], rows(0, -1, 0, 1, 0, 0, 0, 0, 1));
  expect_matrix(t.orientations[2], rows(1, 0, 0, 0, 0, -1, 0, 1, 0));
}

TEST(GrainFile, BadLinesAreRefusedNamingTheLine) {
  const Eigen::Vector3d size(1e-3, 1e-3, 1e-3);
  auto error = [&](const std::string& text) {
    try {
      (void)io::parse_grain_file(text, "grains.txt", 1e-3, size);
    } catch (const io::TessellationFileError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("0.5 0.5 0.5 1 0 0 0\n0.2 0.2\n").find("grains.txt:2: expected 7 values"),
            std::string::npos);
  EXPECT_NE(error("# c\n0.5 0.5 0.5 1 zero 0 0\n").find("grains.txt:2: phi1: expected a number"),
            std::string::npos);
  EXPECT_NE(error("0.5 0.5 1.5 1 0 0 0\n").find("grains.txt:1: centroid z"), std::string::npos);
  EXPECT_NE(error("0.5 0.5 0.5 -1 0 0 0\n").find("grains.txt:1: volume must be positive"),
            std::string::npos);
  EXPECT_NE(error("0.5 0.5 0.5 0.5 0 0 0\n").find("sum to"), std::string::npos);
}

TEST(NeperOrientation, BungeConversionAgreesWithTheOrientationLibrary) {
  // Both follow the binding convention (crystal -> specimen = g^T); they must agree.
  const double d = M_PI / 180.0;
  for (const auto& e :
       {Eigen::Vector3d(30, 40, 50), Eigen::Vector3d(200, 10, 300), Eigen::Vector3d(0, 90, 0)}) {
    const Eigen::Quaterniond a = io::quaternion_from_bunge_degrees(e[0], e[1], e[2]);
    const Eigen::Quaterniond b = g::from_bunge(e[0] * d, e[1] * d, e[2] * d);
    EXPECT_LT((a.toRotationMatrix() - b.toRotationMatrix()).norm(), 1e-12) << e.transpose();
  }
}
