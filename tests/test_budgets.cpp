// Budgets before allocation (io/budget.hpp): a specimen's grain count estimated from its
// outline is checked against the grains actually built; a specimen too large for the memory
// limit, or holding no grain, is refused naming its keys before anything is allocated; mesh
// headers are bounded by the file's size; inputs that are not regular files are refused
// rather than waited on. Every CLI run here is under a memory and time limit of its own, so
// that a regression fails instead of exhausting the machine.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_helpers.hpp"
#include "folder_test.hpp"
#include "geometry/specimen.hpp"
#include "io/budget.hpp"
#include "io/mesh_io.hpp"
#include "io/result_dir.hpp"


#if defined(__SANITIZE_ADDRESS__)
#define CLEAVE_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CLEAVE_TEST_UNDER_ASAN 1
#endif
#endif
#ifndef CLEAVE_TEST_UNDER_ASAN
#define CLEAVE_TEST_UNDER_ASAN 0
#endif

namespace fs = std::filesystem;

namespace {

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class Budgets : public cleave::testing::FolderTest {
 protected:
  fs::path fifo(const std::string& name) {
    const fs::path p = dir_ / name;
    EXPECT_EQ(::mkfifo(p.c_str(), 0644), 0);
    return p;
  }
  /// `cleave ARGS` run in this test's folder with at most 2 GiB of address space and 30 s.
  /// Under AddressSanitizer only the 30 s: its shadow memory reserves terabytes of address
  /// space at start, which any such limit refuses.
  cleave::testing::CliOutcome cleave(const std::string& args) { return run_cleave_in(dir_, args); }
  static cleave::testing::CliOutcome run_cleave_in(const fs::path& dir, const std::string& args) {
#if CLEAVE_TEST_UNDER_ASAN
    const std::string limit;
#else
    const std::string limit = "ulimit -v 2097152 && ";
#endif
    return cleave::testing::run_shell("cd " + dir.string() + " && " + limit + "timeout -s KILL 30 " +
                                      std::string(CLEAVE_BINARY) + " " + args + " 2>&1");
  }
};

std::string lattice_box(const std::string& size, const std::string& r) {
  return "[specimen]\nshape = \"box\"\nsize = " + size + "\n[grain]\nr = " + r + "\nt = 1.0\n";
}

// ---- the estimate against the grains built ------------------------------------------------

TEST(SpecimenEstimate, LatticeGrainCountMatchesTheGrainsBuilt) {
  using cleave::geometry::KeepRule;
  using cleave::geometry::Outline;
  struct Case {
    Outline outline;
    double r, t;
    KeepRule keep;
    double tolerance;  // relative
  };
  const std::vector<Case> cases = {
      {Outline::box(12e-3, 12e-3, 4e-3), 1e-3, 1e-3, KeepRule::cell_inside,
       0.02},  // the 168 grains of sec. 2.5.1
      {Outline::box(40e-3, 25e-3, 3e-3), 1e-3, 1e-3, KeepRule::cell_inside, 0.02},
      {Outline::box(40e-3, 25e-3, 3.5e-3), 0.7e-3, 1.3e-3, KeepRule::centre_inside, 0.02},
      {Outline::beam(60e-3, 12e-3, 2e-3, 4e-3, 5e-3), 0.6e-3, 1e-3, KeepRule::cell_inside, 0.05},
      {Outline::disc(15e-3, 5e-3), 0.6e-3, 5e-3, KeepRule::centre_inside,
       0.05},  // the Brazilian disc
      {Outline::disc(40e-3, 2e-3), 0.5e-3, 1e-3, KeepRule::cell_inside, 0.05},
  };
  for (const Case& c : cases) {
    cleave::geometry::SpecimenDef def;
    def.outline = c.outline;
    def.r = def.r_bar = c.r;
    def.t = def.t_bar = c.t;
    def.keep = c.keep;
    const double built = static_cast<double>(cleave::geometry::build_specimen(def).grains.size());
    const double estimate = cleave::io::lattice_grain_estimate(def);
    ASSERT_GT(built, 100.0);
    EXPECT_NEAR(estimate / built, 1.0, c.tolerance)
        << "outline " << c.outline.size.transpose() << ", r " << c.r << ": " << estimate
        << " estimated, " << built << " built";
  }
}

TEST(SpecimenEstimate, MemorySizesReadAsPowersOf1024) {
  using cleave::io::parse_memory_size;
  EXPECT_EQ(parse_memory_size("4G"), 4ull << 30);
  EXPECT_EQ(parse_memory_size("512M"), 512ull << 20);
  EXPECT_EQ(parse_memory_size("1.5GiB"), 3ull << 29);
  EXPECT_EQ(parse_memory_size("300kb"), 300ull << 10);
  EXPECT_EQ(parse_memory_size("1000"), 1000ull);
  for (const char* bad : {"", "0", "-1G", "4X", "G", "1e30", "4 GG"})
    EXPECT_THROW((void)parse_memory_size(bad), std::invalid_argument) << bad;
}

// ---- specimens refused before they are built ---------------------------------------------

TEST_F(Budgets, AHugeLatticeIsRefusedBeforeAGrainIsAllocated) {
  // A 10^6 mm box of 1 mm grains, and 1 um grains across 2000 mm: 10^12 and more grains.
  for (const auto& [size, r] :
       {std::pair{"[1e6, 1e6, 4.0]", "1"}, {"[2000.0, 2000.0, 2000.0]", "0.001"}}) {
    write("huge.toml", lattice_box(size, r));
    const auto t0 = std::chrono::steady_clock::now();
    const auto o = cleave("run huge.toml --out out");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(o.code, 2) << o.output;
    EXPECT_TRUE(has(o.output, "huge.toml:3:") && has(o.output, "key 'specimen.size'")) << o.output;
    EXPECT_TRUE(has(o.output, "grain.r = " + std::string(r)) && has(o.output, "at most 1e+08"))
        << o.output;
    EXPECT_LT(seconds, 5.0);
    EXPECT_FALSE(fs::exists(dir_ / "out")) << "a refused specimen leaves no result folder";
  }
}

TEST_F(Budgets, MaxMemoryRefusesTheEstimateNamingTheKeysAndTheLimit) {
  // 200 x 200 x 4 mm of 1 mm prisms: about 6e4 grains, far above 32 MiB in any run.
  write("big.toml", lattice_box("[200.0, 200.0, 4.0]", "1.0"));
  const auto o = cleave("run big.toml --out out --max-memory 32M");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_TRUE(has(o.output, "big.toml:3:") && has(o.output, "key 'specimen.size'")) << o.output;
  EXPECT_TRUE(has(o.output, "grain.r = 1") && has(o.output, "grains, which need about"))
      << o.output;
  EXPECT_TRUE(has(o.output, "the limit of 32 MiB (--max-memory 32M)")) << o.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  // The same specimen runs under a limit above its estimate; a malformed limit is a usage error.
  write("small.toml", lattice_box("[12.0, 12.0, 2.0]", "1.0"));
  EXPECT_EQ(cleave("run small.toml --out small --max-memory 1G -q").code, 0);
  EXPECT_EQ(cleave("run small.toml --out bad --max-memory 4X").code, 2);
  EXPECT_EQ(cleave("validate small.toml --max-memory 0").code, 2);
}

TEST_F(Budgets, AnOutlineHoldingNoGrainIsAUsageErrorNamingItsKeys) {
  // A Brazilian disc 1 mm across of 0.6 mm prisms: no lattice cell fits (or point lies) in it.
  for (const char* keep : {"cell_inside", "centre_inside"}) {
    write("disc.toml",
          std::string("[specimen]\nshape = \"disc\"\ndiameter = 1.0\nthickness = 5.0\nkeep = \"") +
              keep + "\"\n[grain]\nr = 0.6\nt = 5.0\n");
    const auto o = cleave("run disc.toml --out out");
    EXPECT_EQ(o.code, 2) << o.output;
    EXPECT_TRUE(has(o.output, "disc.toml:3:12: key 'specimen.diameter'")) << o.output;
    EXPECT_TRUE(has(o.output, "grain.r = 0.6") && has(o.output, "no grain")) << o.output;
    EXPECT_TRUE(has(o.output, keep)) << o.output;
  }
  // Vast but thinner than a layer: no grain, found without searching 10^18 lattice points.
  write("thin.toml", lattice_box("[1e9, 1e9, 0.5]", "1.0"));
  const auto o = cleave("run thin.toml --out out");
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_TRUE(has(o.output, "key 'specimen.size'") && has(o.output, "no grain")) << o.output;
}

// ---- mesh headers bounded by the file ----------------------------------------------------

TEST_F(Budgets, APlyHeaderClaimingMoreElementsThanTheFileHoldsIsRefused) {
  // Binary: 10^8 vertices of three floats need 1.2 GB; ASCII: 10^8 faces need 2 characters a
  // number at least. Each file is under 200 bytes.
  write("vertices.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 100000000\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n");
  write("faces.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
        "float z\n"
        "element face 100000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 "
        "0\n0 1 0\n3 0 1 2\n");
  for (const auto& [file, element] :
       {std::pair{"vertices.ply", "'vertex'"}, {"faces.ply", "'face'"}}) {
    write("mesh.toml",
          std::string("[specimen]\nshape = \"mesh\"\n[[mesh_grain]]\nfile = \"") + file + "\"\n");
    const auto o = cleave("run mesh.toml --out out");
    EXPECT_EQ(o.code, 2) << o.output;
    EXPECT_TRUE(has(o.output, "key 'mesh_grain[1].file'") && has(o.output, file)) << o.output;
    EXPECT_TRUE(has(o.output, "claims 100000000 " + std::string(element) + " elements"))
        << o.output;
  }
}

TEST_F(Budgets, APlyHoldingWhatItsHeaderClaimsStillReads) {
  // A binary tetrahedron: 4 vertices of 3 floats (48 bytes), 4 faces of a uchar and 3 ints
  // (52 bytes): exactly the size the header needs; one byte less is refused.
  std::string body;
  const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  body.append(reinterpret_cast<const char*>(v), sizeof v);
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : faces) {
    body += static_cast<char>(3);
    body.append(reinterpret_cast<const char*>(f), sizeof f);
  }
  ASSERT_EQ(body.size(), 100u);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  const auto meshes = cleave::io::read_meshes(write("tet.ply", header + body));
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].vertices.size(), 4u);
  EXPECT_EQ(meshes[0].faces.size(), 4u);
  EXPECT_THROW((void)cleave::io::read_meshes(write("short.ply", header + body.substr(0, 99))),
               cleave::io::MeshIoError);
}

TEST_F(Budgets, OnlyObjStlAndPlyMeshesAreRead) {
  // assimp picks its reader by the extension; the formats cleave does not bound are refused.
  const fs::path off = write("cube.off", "OFF\n8 6 0\n");
  try {
    (void)cleave::io::read_meshes(off);
    FAIL() << "an .off file was read";
  } catch (const cleave::io::MeshIoError& e) {
    EXPECT_TRUE(has(e.what(), "cube.off") && has(e.what(), ".obj, .stl or .ply")) << e.what();
  }
}

// ---- inputs that are not regular files ---------------------------------------------------

TEST_F(Budgets, AFifoGivenAsAnyInputIsRefusedNotWaitedOn) {
  fifo("pipe.toml");
  fifo("pipe.obj");
  fs::create_directories(dir_ / "result");
  fifo("result/run.toml");
  write("mesh.toml", "[specimen]\nshape = \"mesh\"\n[[mesh_grain]]\nfile = \"pipe.obj\"\n");
  write("preset.toml",
        "[specimen]\nshape = \"box\"\nsize = [6.0, 6.0, 2.0]\n[grain]\nr = 1.0\nt = 1.0\n"
        "[material]\npreset = \"./pipe.toml\"\n");
  const std::vector<std::pair<std::string, std::string>> runs = {
      {"run pipe.toml --out a", "pipe.toml"},
      {"run pipe.toml --out a --set grain.r=1", "pipe.toml"},
      {"run mesh.toml --out b", "pipe.obj"},
      {"run preset.toml --out c", "pipe.toml"},
      {"restart pipe.toml --out d", "pipe.toml"},
      {"validate pipe.toml --out e", "pipe.toml"},
      {"sweep pipe.toml --set grain.r=1,2 --out f", "pipe.toml"},
      {"calibrate pipe.toml --out g", "pipe.toml"},
      {"check volume result", "run.toml"},
  };
  for (const auto& [args, named] : runs) {
    const auto o = cleave(args);
    EXPECT_EQ(o.code, 2) << args << "\n" << o.output;
    EXPECT_TRUE(has(o.output, named)) << args << "\n" << o.output;
    // A preset path that is no regular file is no material (resolve_material looks for files).
    EXPECT_TRUE(has(o.output, "FIFO") || has(o.output, "not a file") ||
                has(o.output, "no material"))
        << args << "\n"
        << o.output;
  }
  EXPECT_THROW((void)cleave::io::read_file(dir_ / "pipe.toml"), std::runtime_error);
  EXPECT_EQ(cleave::io::input_file_problem(dir_ / "pipe.toml"), "is a FIFO (named pipe)");
  EXPECT_EQ(cleave::io::input_file_problem(dir_), "is a directory");
  EXPECT_EQ(cleave::io::input_file_problem(dir_ / "mesh.toml"), "");
}

}  // namespace
