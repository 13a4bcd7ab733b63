// Grains that are not hexagonal prisms: convex grains from mesh files (closed-form volumes
// and centroids, the errors for open, non-manifold, non-convex and flat meshes, the convex
// hull option) and the Voronoi polycrystal (exact tiling of the box, convex cells that do
// not overlap, determinism), then both through scenario files, the world and `cleave run`.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/convex_mesh.hpp"
#include "geometry/rng.hpp"
#include "geometry/specimen.hpp"
#include "geometry/voronoi.hpp"
#include "io/mesh_grains.hpp"
#include "io/mesh_io.hpp"
#include "io/result_dir.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"
#include "scenario_error_test.hpp"
#include "sim/world_assembly.hpp"

namespace {

namespace fs = std::filesystem;
using cleave::geometry::ConvexMeshResult;
using cleave::geometry::ExactPolyhedron;
using cleave::geometry::ExactScalar;
using cleave::geometry::GeometryError;
using cleave::geometry::PolygonMesh;

const fs::path kData = fs::path(CLEAVE_SOURCE_DIR) / "tests" / "data" / "meshes";

PolygonMesh only_mesh(const std::string& file) {
  const auto meshes = cleave::io::read_meshes(kData / file);
  EXPECT_EQ(meshes.size(), 1u) << file;
  return meshes.at(0);
}

/// The GeometryError message of importing `file` (empty if it imports).
std::string import_error(const std::string& file, bool convex_hull = false) {
  try {
    cleave::geometry::convex_shape_from_mesh(only_mesh(file), convex_hull);
  } catch (const GeometryError& e) {
    return e.what();
  }
  return {};
}

// ---------------------------------------------------------------------------------------
// Mesh grains

TEST(MeshGrain, TriangulatedCubeHasTheExactVolumeCentroidAndInertiaOfItsBox) {
  // [1,3] x [2,4] x [-1,1]: V = 8, centroid (2, 3, 0), I = V (a^2 + b^2) / 12 = 16/3 each.
  const ConvexMeshResult r = cleave::geometry::convex_shape_from_mesh(only_mesh("cube_triangulated.obj"), false);
  EXPECT_TRUE(r.was_convex);
  EXPECT_TRUE(r.shape.volume() == ExactScalar(8.0));
  EXPECT_EQ(r.shape.num_faces(), 6);  // the 12 triangles merged into 6 squares
  EXPECT_EQ(r.shape.num_vertices(), 8);
  const auto mp = r.shape.mass_properties();
  EXPECT_EQ(mp.centroid, Eigen::Vector3d(2.0, 3.0, 0.0));
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(mp.inertia(d, d), 16.0 / 3.0, 1e-14);
  EXPECT_NEAR(mp.inertia(0, 1), 0.0, 1e-14);
  EXPECT_TRUE(cleave::geometry::validate_with_cgal(r.shape).ok());
}

TEST(MeshGrain, StlTetrahedronHasTheExactVolumeAndCentroid) {
  // Corners 0, 2x, 3y, 4z: V = 2*3*4/6 = 4; centroid = mean of the corners (0.5, 0.75, 1).
  const ConvexMeshResult r = cleave::geometry::convex_shape_from_mesh(only_mesh("tetrahedron.stl"), false);
  EXPECT_TRUE(r.shape.volume() == ExactScalar(4.0));
  EXPECT_EQ(r.shape.num_faces(), 4);
  EXPECT_EQ(r.shape.mass_properties().centroid, Eigen::Vector3d(0.5, 0.75, 1.0));
}

TEST(MeshGrain, PlyCubeOfQuadsHasTheExactVolumeAndCentroid) {
  const ConvexMeshResult r = cleave::geometry::convex_shape_from_mesh(only_mesh("cube_quads.ply"), false);
  EXPECT_TRUE(r.shape.volume() == ExactScalar(8.0));
  EXPECT_EQ(r.shape.num_faces(), 6);
  EXPECT_EQ(r.shape.mass_properties().centroid, Eigen::Vector3d(1.0, 1.0, 1.0));
}

TEST(MeshGrain, InwardOrientedMeshGivesTheSameShape) {
  PolygonMesh m = only_mesh("cube_triangulated.obj");
  for (auto& f : m.faces) std::reverse(f.begin(), f.end());
  EXPECT_TRUE(cleave::geometry::convex_shape_from_mesh(m, false).shape.volume() == ExactScalar(8.0));
}

TEST(MeshGrain, OpenMeshIsRefusedWithItsBoundaryEdges) {
  const std::string e = import_error("open_box.obj");
  EXPECT_NE(e.find("not closed"), std::string::npos) << e;
  EXPECT_NE(e.find("4 boundary edge"), std::string::npos) << e;
}

TEST(MeshGrain, NonManifoldEdgeIsRefusedNamingTheEdge) {
  const std::string e = import_error("nonmanifold_fin.obj");
  EXPECT_NE(e.find("not manifold"), std::string::npos) << e;
  EXPECT_NE(e.find("shared by 3 faces"), std::string::npos) << e;
  // The fin sits on the edge from (1, 2, -1) to (3, 2, -1).
  EXPECT_NE(e.find("(1, 2, -1)"), std::string::npos) << e;
  EXPECT_NE(e.find("(3, 2, -1)"), std::string::npos) << e;
}

TEST(MeshGrain, NonConvexMeshIsRefusedSayingByHowMuch) {
  // The L prism's inner walls x = 1 and y = 1 have the far corners (x or y = 2) 1 outside.
  const std::string e = import_error("nonconvex_l_prism.obj");
  EXPECT_NE(e.find("not convex"), std::string::npos) << e;
  EXPECT_NE(e.find("lies 1 (mesh units) outside the plane of face"), std::string::npos) << e;
  EXPECT_NE(e.find("convex_hull = true"), std::string::npos) << e;
}

TEST(MeshGrain, FlatMeshIsRefusedAsDegenerate) {
  const std::string e = import_error("degenerate_flat_tetrahedron.obj");
  EXPECT_NE(e.find("degenerate"), std::string::npos) << e;
  EXPECT_NE(e.find("one plane"), std::string::npos) << e;
}

TEST(MeshGrain, ConvexHullOptionGivesTheHullsClosedFormVolume) {
  // L = 2x2 square minus the unit square at (1..2, 1..2), 1 thick: V = 3. Its hull is the
  // pentagon (0,0) (2,0) (2,1) (1,2) (0,2) of area 4 - 1/2, 1 thick: 7/2.
  const ConvexMeshResult r =
      cleave::geometry::convex_shape_from_mesh(only_mesh("nonconvex_l_prism.obj"), true);
  EXPECT_FALSE(r.was_convex);
  EXPECT_DOUBLE_EQ(r.mesh_volume, 3.0);
  EXPECT_TRUE(r.shape.volume() == ExactScalar(3.5));
  EXPECT_EQ(r.shape.num_faces(), 7);  // pentagonal prism
  EXPECT_TRUE(r.shape.is_valid_convex());
}

TEST(MeshGrain, FileErrorsNameTheFile) {
  cleave::io::MeshGrainSpec spec;
  spec.file = kData / "no_such_mesh.obj";
  try {
    cleave::io::load_mesh_grains(spec);
    FAIL() << "a missing file was accepted";
  } catch (const cleave::io::MeshGrainError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_mesh.obj"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos) << e.what();
  }
  spec.file = kData / "open_box.obj";
  try {
    cleave::io::load_mesh_grains(spec);
    FAIL() << "an open mesh was accepted";
  } catch (const cleave::io::MeshGrainError& e) {
    EXPECT_NE(std::string(e.what()).find("open_box.obj"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
  }
}

TEST(MeshGrain, ScaleAndOffsetApplyBeforeTheShapeIsMade) {
  cleave::io::MeshGrainSpec spec;
  spec.file = kData / "tetrahedron.stl";
  spec.scale = 0.5;                              // V = 4 / 8 = 1/2
  spec.offset = Eigen::Vector3d(1.0, 0.0, -2.0); // centroid (0.25, 0.375, 0.5) + offset
  const auto grains = cleave::io::load_mesh_grains(spec);
  ASSERT_EQ(grains.size(), 1u);
  EXPECT_EQ(grains[0].name, "tetrahedron.stl");
  EXPECT_TRUE(grains[0].shape.volume() == ExactScalar(0.5));
  EXPECT_EQ(grains[0].shape.mass_properties().centroid, Eigen::Vector3d(1.25, 0.375, -1.5));
}

// ---------------------------------------------------------------------------------------
// Voronoi polycrystal

cleave::geometry::VoronoiDef small_voronoi() {
  cleave::geometry::VoronoiDef def;
  def.size = Eigen::Vector3d(3e-3, 2e-3, 1.5e-3);
  def.cells = 12;
  def.seed = 7;
  return def;
}

/// Exact vertex coordinates of a shape, read from its exact text.
std::vector<std::array<ExactScalar, 3>> exact_vertices(const ExactPolyhedron& p) {
  std::istringstream in(p.to_exact_text());
  std::string word;
  std::size_t n = 0;
  in >> word >> n;
  std::vector<std::array<ExactScalar, 3>> out;
  for (std::size_t i = 0; i < n; ++i) {
    std::string x, y, z;
    in >> x >> y >> z;
    out.push_back({ExactScalar::parse(x), ExactScalar::parse(y), ExactScalar::parse(z)});
  }
  return out;
}

TEST(Voronoi, CellVolumesSumExactlyToTheBox) {
  const auto def = small_voronoi();
  const auto cells = cleave::geometry::voronoi_cells(def);
  ASSERT_EQ(cells.size(), 12u);
  // The box volume from its three sides, exactly (the doubles' exact values multiplied).
  const ExactScalar box = ExactScalar(def.size.x()) * ExactScalar(def.size.y()) * ExactScalar(def.size.z());
  EXPECT_TRUE(cleave::geometry::total_volume(cells) == box)
      << cleave::geometry::total_volume(cells).to_string() << " vs " << box.to_string();
  // Dropping any one cell leaves a shortfall: no cell is empty.
  for (const auto& c : cells) EXPECT_TRUE(ExactScalar() < c.volume());
}

TEST(Voronoi, CellsAreConvexAndPairwiseSeparatedByTheirBisectors) {
  const auto def = small_voronoi();
  const auto cells = cleave::geometry::voronoi_cells(def);
  const auto points = cleave::geometry::voronoi_points(def);
  for (const auto& c : cells) {
    EXPECT_TRUE(c.is_valid_convex());
    EXPECT_TRUE(cleave::geometry::validate_with_cgal(c).ok());
  }
  // Interior-disjoint: for every pair (i, j) the plane of points equally far from p_i and
  // p_j separates them, i.e. every vertex x of cell i has |x - p_i|^2 <= |x - p_j|^2 and
  // every vertex of cell j the reverse. Evaluated exactly on the exact vertices.
  auto sq = [](const ExactScalar& a) { return a * a; };
  auto nearer_or_equal = [&](const std::array<ExactScalar, 3>& x, const Eigen::Vector3d& p,
                             const Eigen::Vector3d& q) {
    ExactScalar dp, dq;
    for (int d = 0; d < 3; ++d) {
      dp = dp + sq(x[d] - ExactScalar(p[d]));
      dq = dq + sq(x[d] - ExactScalar(q[d]));
    }
    return !(dq < dp);
  };
  int pairs = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const auto vi = exact_vertices(cells[i]);
    for (std::size_t j = 0; j < cells.size(); ++j) {
      if (i == j) continue;
      for (const auto& x : vi) {
        ASSERT_TRUE(nearer_or_equal(x, points[i], points[j])) << "cell " << i << " reaches past point " << j;
      }
      ++pairs;
    }
  }
  EXPECT_EQ(pairs, 12 * 11);
}

namespace {
/// How far `x` lies inside the mesh moved by `shift`: the smallest distance inside its face
/// planes (negative: outside).
double inside_margin(const cleave::geometry::PolygonMesh& mesh, const Eigen::Vector3d& x,
                     const Eigen::Vector3d& shift = Eigen::Vector3d::Zero()) {
  double margin = 1.0;
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d a = mesh.vertices[f[0]] + shift, b = mesh.vertices[f[1]] + shift,
                          cc = mesh.vertices[f[2]] + shift;
    const Eigen::Vector3d n = (b - a).cross(cc - a).normalized();
    margin = std::min(margin, -(x - a).dot(n));
  }
  return margin;
}

/// Where a point x of the box lies: in how many cells (each moved by each of `shifts`) it
/// lies strictly inside, each expected to be cell `nearest`; whether it is within 1e-12 of
/// some face (then the count says nothing).
struct Located {
  int inside = 0;
  bool near_face = false;
};
Located locate(const std::vector<ExactPolyhedron>& cells, const Eigen::Vector3d& x,
               const std::vector<Eigen::Vector3d>& shifts, std::size_t nearest) {
  Located at;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const auto mesh = cells[c].to_mesh();
    for (const auto& t : shifts) {
      const double margin = inside_margin(mesh, x, t);
      if (std::abs(margin) < 1e-12) at.near_face = true;
      if (margin > 0.0) {
        ++at.inside;
        EXPECT_EQ(c, nearest);
      }
    }
  }
  return at;
}
}  // namespace

TEST(Voronoi, RandomPointsLieInExactlyTheCellOfTheirNearestPoint) {
  // Brute force in doubles: a point of the box is strictly inside one cell, the one whose
  // seed point is nearest, and outside all others (points within 1e-12 of a face skipped).
  const auto def = small_voronoi();
  const auto cells = cleave::geometry::voronoi_cells(def);
  const auto points = cleave::geometry::voronoi_points(def);
  cleave::geometry::SplitMix64 rng(2024);
  int checked = 0;
  for (int s = 0; s < 500; ++s) {
    const Eigen::Vector3d x(rng.uniform() * def.size.x(), rng.uniform() * def.size.y(),
                            rng.uniform() * def.size.z());
    std::size_t nearest = 0;
    for (std::size_t k = 1; k < points.size(); ++k) {
      if ((x - points[k]).norm() < (x - points[nearest]).norm()) nearest = k;
    }
    const Located at = locate(cells, x, {Eigen::Vector3d::Zero()}, nearest);
    if (at.near_face) continue;
    EXPECT_EQ(at.inside, 1);
    ++checked;
  }
  EXPECT_GT(checked, 490);
}

TEST(Voronoi, PeriodicCellsTileTheBoxExactlyAndHoldThePointsNearestImage) {
  // Periodic in x and z: the cells sum exactly to the box's volume; a random point of the
  // box lies (through one image of one cell) in the cell of the point nearest to it across
  // the periodic faces, by brute force over the images; some cells reach across a face.
  auto def = small_voronoi();
  def.periodic = {true, false, true};
  const auto cells = cleave::geometry::voronoi_cells(def);
  const auto points = cleave::geometry::voronoi_points(def);
  const ExactScalar box = ExactScalar(def.size.x()) * ExactScalar(def.size.y()) * ExactScalar(def.size.z());
  EXPECT_TRUE(cleave::geometry::total_volume(cells) == box);
  int across = 0;
  for (const auto& c : cells) {
    EXPECT_TRUE(c.is_valid_convex());
    bool out = false;
    for (const auto& v : c.vertices_approx()) out = out || v.x() < -1e-12 || v.x() > def.size.x() + 1e-12 ||
                                                    v.z() < -1e-12 || v.z() > def.size.z() + 1e-12;
    across += out;
    for (const auto& v : c.vertices_approx()) {  // cut by the box along y
      EXPECT_GE(v.y(), -1e-12);
      EXPECT_LE(v.y(), def.size.y() + 1e-12);
    }
  }
  EXPECT_GT(across, 0);
  std::vector<Eigen::Vector3d> shifts;
  for (int x = -1; x <= 1; ++x)
    for (int z = -1; z <= 1; ++z) shifts.emplace_back(x * def.size.x(), 0.0, z * def.size.z());
  cleave::geometry::SplitMix64 rng(77);
  int checked = 0;
  for (int s = 0; s < 300; ++s) {
    const Eigen::Vector3d x(rng.uniform() * def.size.x(), rng.uniform() * def.size.y(), rng.uniform() * def.size.z());
    std::size_t nearest = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < points.size(); ++k) {
      for (const auto& t : shifts) {
        const double d = (x - points[k] - t).norm();
        if (d < best) {
          best = d;
          nearest = k;
        }
      }
    }
    const Located at = locate(cells, x, shifts, nearest);
    if (at.near_face) continue;
    EXPECT_EQ(at.inside, 1);
    ++checked;
  }
  EXPECT_GT(checked, 290);
}

TEST(Voronoi, SameSeedSameSpecimenOtherSeedOtherSpecimen) {
  auto def = small_voronoi();
  const auto a = cleave::geometry::voronoi_cells(def);
  const auto b = cleave::geometry::voronoi_cells(def);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].to_exact_text(), b[i].to_exact_text());
  def.seed = 8;
  const auto c = cleave::geometry::voronoi_cells(def);
  EXPECT_NE(a[0].to_exact_text(), c[0].to_exact_text());
}

TEST(Voronoi, GapSeparatesNeighbours) {
  auto def = small_voronoi();
  def.gap = 0.05e-3;
  const auto cells = cleave::geometry::voronoi_cells(def);
  const ExactScalar box = ExactScalar(def.size.x()) * ExactScalar(def.size.y()) * ExactScalar(def.size.z());
  EXPECT_TRUE(cleave::geometry::total_volume(cells) < box);
  // Every vertex of cell i is at least gap/2 nearer (along the bisector normal) to p_i.
  const auto points = cleave::geometry::voronoi_points(def);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    for (const auto& v : cells[i].vertices_approx()) {
      for (std::size_t j = 0; j < cells.size(); ++j) {
        if (j == i) continue;
        const Eigen::Vector3d n = (points[i] - points[j]).normalized();
        EXPECT_GE((v - 0.5 * (points[i] + points[j])).dot(n), 0.5 * def.gap * (1 - 1e-9) - 1e-15);
      }
    }
  }
  def.gap = 10e-3;  // wider than the box: cells would vanish
  EXPECT_THROW(cleave::geometry::voronoi_cells(def), std::invalid_argument);
}

TEST(Voronoi, SpecimenGrainsSplitIntoSlabsThatSumToThemExactly) {
  cleave::geometry::SpecimenDef def;
  def.kind = cleave::geometry::SpecimenKind::voronoi;
  def.voronoi = small_voronoi();
  def.seed = 3;
  const auto s = cleave::geometry::build_specimen(def);
  ASSERT_EQ(s.grains.size(), 12u);
  const auto points = cleave::geometry::voronoi_points(def.voronoi);
  const auto cells = cleave::geometry::voronoi_cells(def.voronoi);
  for (const auto& g : s.grains) {
    EXPECT_EQ(g.site.centre, points[static_cast<std::size_t>(g.id)]);
    // The grain's shape is its cell moved exactly by its point.
    EXPECT_EQ(s.shape_of(g).translated(g.site.centre).to_exact_text(),
              cells[static_cast<std::size_t>(g.id)].to_exact_text());
  }
  const auto pieces = cleave::geometry::split_into_slabs(s, 0.0);
  std::vector<ExactScalar> sums(s.grains.size());
  for (const auto& p : pieces) {
    EXPECT_TRUE(p.shape->is_valid_convex());
    sums[static_cast<std::size_t>(p.lineage.grain_id)] = sums[static_cast<std::size_t>(p.lineage.grain_id)] + p.shape->volume();
  }
  for (const auto& g : s.grains) EXPECT_TRUE(sums[static_cast<std::size_t>(g.id)] == s.shape_of(g).volume());
  EXPECT_GT(pieces.size(), s.grains.size());
}

// ---------------------------------------------------------------------------------------
// Scenario files

/// Scenarios read here as if from the meshes' folder, so mesh files resolve.
const std::string kInline = (kData / "inline.toml").string();

const std::string kContact = R"(
[contact]
dilation_radius = 0.01
[contact.particle_particle]
kn = 5000.0
[contact.particle_wall]
kn = 5000.0
[dynamics]
dt = 1e-7
duration = 1e-5
gravity = [0, 0, -9.81]
)";

TEST(CustomGrainScenario, MeshGrainsLoadRelativeToTheScenarioAndMakeABodyEach) {
  const auto s = cleave::io::parse_scenario(R"([scenario]
length_unit = "m"
[specimen]
shape = "mesh"
[[mesh_grain]]
file = "cube_triangulated.obj"
[[mesh_grain]]
file = "tetrahedron.stl"
position = [10, 0, 0]
[material]
density = 2.0
)" + kContact,
                                            (kData / "inline.toml").string());
  ASSERT_EQ(s.specimen.kind, cleave::geometry::SpecimenKind::meshes);
  ASSERT_EQ(s.specimen.custom_grains.size(), 2u);
  const auto specimen = cleave::geometry::build_specimen(s.specimen);
  ASSERT_EQ(specimen.grains.size(), 2u);
  EXPECT_EQ(specimen.grains[0].site.centre, Eigen::Vector3d(2, 3, 0));
  EXPECT_EQ(specimen.grains[1].site.centre, Eigen::Vector3d(10.5, 0.75, 1));
  const auto world = cleave::sim::make_world(s, specimen);
  const auto ids = world.body_ids();
  ASSERT_EQ(ids.size(), 2u);
  // Masses from the closed-form volumes: 2 kg/m^3 x 8 m^3 and x 4 m^3.
  std::vector<double> masses;
  for (auto id : ids) masses.push_back(world.shape(world.info(id).shape).volume * 2.0);
  std::sort(masses.begin(), masses.end());
  EXPECT_DOUBLE_EQ(masses[0], 8.0);
  EXPECT_DOUBLE_EQ(masses[1], 16.0);
}

TEST(CustomGrainScenario, BadMeshIsAnErrorAtItsFileKey) {
  const std::string e =
      cleave::testing::expect_scenario_error(R"([specimen]
shape = "mesh"
[[mesh_grain]]
file = "cube_triangulated.obj"
[[mesh_grain]]
file = "nonconvex_l_prism.obj"
)",
                                             kInline, 6, "mesh_grain[2].file", "not convex", 8);
  EXPECT_NE(e.find("nonconvex_l_prism.obj"), std::string::npos) << e;
  // The same mesh with convex_hull = true is accepted.
  EXPECT_NO_THROW((void)cleave::io::parse_scenario(R"([specimen]
shape = "mesh"
[[mesh_grain]]
file = "nonconvex_l_prism.obj"
convex_hull = true
)",
                                                   kInline));
  EXPECT_SCENARIO_ERROR_IN(
      kInline, "[specimen]\nshape = \"mesh\"\n[[mesh_grain]]\nfile = \"open_box.obj\"\n", 4,
      "mesh_grain[1].file", "key 'mesh_grain[1].file': mesh file", 8);
}

TEST(CustomGrainScenario, KeysThatDoNotFitAreErrors) {
  EXPECT_SCENARIO_ERROR_IN(kInline, "[specimen]\nshape = \"mesh\"\n", 2, "specimen.shape",
                           "[[mesh_grain]]");
  EXPECT_SCENARIO_ERROR_IN(kInline, "[specimen]\nshape = \"voronoi\"\nsize = [1, 1, 1]\n", 1,
                           "specimen.grains", "key 'specimen.grains': missing required key");
  EXPECT_SCENARIO_ERROR_IN(
      kInline,
      "[specimen]\nshape = \"voronoi\"\nsize = [1, 1, 1]\ngrains = 3\n[grain]\nr = 1\nt = 1\n", 5,
      "grain", "key 'grain': [grain] sets the honeycomb lattice", 1);
  EXPECT_SCENARIO_ERROR_IN(
      kInline,
      "[specimen]\nshape = \"voronoi\"\nsize = [1, 1, 1]\ngrains = 3\nkeep = \"cell_inside\"\n", 5,
      "specimen.keep", "applies to the lattice shapes");
  EXPECT_SCENARIO_ERROR_IN(
      kInline, "[specimen]\nshape = \"box\"\nsize = [1, 1, 1]\ngrains = 3\n[grain]\nr = 1\nt = 1\n",
      4, "specimen.grains",
      "key 'specimen.grains': does not apply to shape 'box' (only to 'voronoi')");
  EXPECT_SCENARIO_ERROR_IN(
      kInline,
      "[specimen]\nshape = \"box\"\nsize = [1, 1, 1]\n[grain]\nr = 1\nt = 1\n"
      "[[mesh_grain]]\nfile = \"cube_triangulated.obj\"\n",
      7, "mesh_grain", "key 'mesh_grain': [[mesh_grain]] tables need [specimen] shape = \"mesh\"");
  EXPECT_SCENARIO_ERROR_IN(
      kInline, "[specimen]\nshape = \"voronoi\"\nsize = [1, 1, 1]\ngrains = 50\ngap = 0.9\n", 5,
      "specimen.gap", "not more than the gap", 7);
  EXPECT_SCENARIO_ERROR_IN(
      kInline,
      "[specimen]\nshape = \"mesh\"\n[[mesh_grain]]\nfile = \"cube_triangulated.obj\"\nsize = 2\n",
      5, "mesh_grain[1].size", "key 'mesh_grain[1].size': unknown key");
}

TEST(CustomGrainScenario, VoronoiScenarioIsTheVoronoiDefinitionInMetres) {
  const auto s = cleave::io::parse_scenario(R"([specimen]
shape = "voronoi"
size = [3, 2, 1.5]
grains = 12
seed = 7
)",
                                            "voronoi.toml");
  EXPECT_EQ(s.specimen.kind, cleave::geometry::SpecimenKind::voronoi);
  EXPECT_EQ(s.specimen.voronoi.cells, 12);
  EXPECT_EQ(s.specimen.voronoi.seed, 7u);
  EXPECT_EQ(s.specimen.voronoi.size, Eigen::Vector3d(3e-3, 2e-3, 1.5e-3));
  EXPECT_EQ(s.specimen.voronoi.gap, 0.0);
}

TEST(CustomGrainScenario, ScenarioAsRunReadsBackEqual) {
  for (const char* name : {"mesh_grains", "voronoi"}) {
    SCOPED_TRACE(name);
    const auto s = cleave::io::load_scenario(fs::path(CLEAVE_SOURCE_DIR) / "scenarios" / (std::string(name) + ".toml"));
    const std::string text = cleave::io::scenario_to_toml(s);
    const auto back = cleave::io::parse_scenario(text, "as_run.toml");
    EXPECT_TRUE(cleave::io::scenario_differences(s, back).empty()) << text;
    EXPECT_EQ(back.specimen.kind, s.specimen.kind);
  }
}

// ---------------------------------------------------------------------------------------
// `cleave run` on the two shipped scenarios

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The provenance of a run: `key` in run.toml's [provenance] table.
std::string provenance_of(const fs::path& out, const std::string& key) {
  return cleave::io::read_manifest(out).provenance.at(key);
}

/// Runs the scenario and checks it as a user would; returns its manifest.
cleave::io::Manifest expect_run_finishes(
    const std::string& scenario, const std::vector<std::pair<std::string, std::string>>& provenance = {}) {
  const fs::path out = fs::temp_directory_path() / ("cleave_test_custom_" + scenario);
  fs::remove_all(out);
  const std::string cmd = std::string(CLEAVE_BINARY) + " run --quiet " + CLEAVE_SOURCE_DIR +
                          "/scenarios/" + scenario + ".toml --out " + out.string();
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << cmd;
  if (rc != 0) return {};
  const std::string manifest = read_text(out / "run.toml");
  EXPECT_TRUE(manifest.find("\nstatus = \"finished\"") != std::string::npos ||
              manifest.find("\nstatus = 'finished'") != std::string::npos)
      << manifest;
  for (const auto& [key, value] : provenance) EXPECT_EQ(provenance_of(out, key), value) << key;
  const std::string check = std::string(CLEAVE_BINARY) + " check volume " + out.string() + " > /dev/null";
  EXPECT_EQ(std::system(check.c_str()), 0) << check;
  cleave::io::Manifest m = cleave::io::read_manifest(out);
  fs::remove_all(out);
  return m;
}

TEST(CustomGrainRun, MeshGrainsScenarioRunsAndChecks) {
  const cleave::io::Manifest m = expect_run_finishes("mesh_grains");
  EXPECT_EQ(m.status, "finished");
  EXPECT_EQ(m.facts.at("grains"), "3");  // two octahedra and a brick
}
TEST(CustomGrainRun, VoronoiScenarioRunsAndChecks) {
  // Both seeds that made the specimen (scenarios/voronoi.toml: points 11, orientations 12).
  const cleave::io::Manifest m = expect_run_finishes("voronoi", {{"voronoi_seed", "11"}, {"seed", "12"}});
  EXPECT_EQ(m.status, "finished");
  EXPECT_EQ(m.facts.at("grains"), "9");
}

}  // namespace
