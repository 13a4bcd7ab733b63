/// \file
/// Inputs that once got through the readers wrongly (found by the fuzz targets in fuzz/ or
/// while writing them). Each must now be refused with the reader's documented error:
/// io::ScenarioError, io::MeshGrainError, io::CheckpointError.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "io/mesh_grains.hpp"
#include "io/mesh_io.hpp"
#include "io/scenario.hpp"
#include "io/validation_scenario.hpp"
#include "physics/dem/state_codec.hpp"

namespace {

using namespace cleave;

std::string read_text(const std::string& path) {
  std::ifstream in(std::string(CLEAVE_SOURCE_DIR) + "/" + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// `text` with `line` inserted after the first line that is `after`.
std::string with_line_after(std::string text, const std::string& after, const std::string& line) {
  const auto at = text.find(after + "\n");
  EXPECT_NE(at, std::string::npos) << after;
  text.insert(at + after.size() + 1, line + "\n");
  return text;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// An integer setting held in an `int` (frames, threads, check_every, records) took values
// beyond INT_MAX modulo 2^32: threads = 4294967296 became 0 ("all cores"), records =
// 4294967297 became 1, below its own minimum of 2. They are errors now.
TEST(IntegerSettings, BeyondIntRangeIsAnErrorNotAWrapAround) {
  const std::string base = read_text("scenarios/drop_test.toml");
  try {
    (void)io::parse_scenario(with_line_after(base, "[dynamics]", "threads = 4294967296"), "drop.toml");
    ADD_FAILURE() << "threads = 4294967296 was accepted";
  } catch (const io::ScenarioError& e) {
    EXPECT_EQ(e.key(), "dynamics.threads") << e.what();
    EXPECT_TRUE(has(e.what(), "must be <= 2147483647")) << e.what();
  }
  // The largest int is still fine.
  EXPECT_EQ(io::parse_scenario(with_line_after(base, "[dynamics]", "threads = 2147483647"), "drop.toml")
                .dynamics.threads,
            2147483647);

  const std::string dcb = read_text("scenarios/validation/dcb_coarse.toml");
  try {
    (void)io::parse_validation_scenario(with_line_after(dcb, "[dynamics]", "records = 4294967297"),
                                        "dcb.toml");
    ADD_FAILURE() << "records = 4294967297 was accepted";
  } catch (const io::ScenarioError& e) {
    EXPECT_EQ(e.key(), "dynamics.records") << e.what();
  }
}

// fuzz_mesh: a PLY file whose header lacks its "end_header" line (here "end_heade" and
// binary bytes) made assimp 5.2's PLY reader spin forever. read_meshes refuses it first.
TEST(MeshImport, PlyWithoutEndHeaderIsRefusedNotAHang) {
  const std::string file = std::string(CLEAVE_SOURCE_DIR) + "/tests/data/fuzz/ply_without_end_header.ply";
  try {
    (void)io::read_meshes(file);
    ADD_FAILURE() << "no MeshIoError";
  } catch (const io::MeshIoError& e) {
    EXPECT_TRUE(has(e.what(), "ply_without_end_header.ply")) << e.what();
    EXPECT_TRUE(has(e.what(), "end_header")) << e.what();
  }
  io::MeshGrainSpec spec;
  spec.file = file;
  EXPECT_THROW((void)io::load_mesh_grains(spec), io::MeshGrainError);
  // The same file with its header line restored is read (and is the seed's quad cube).
  EXPECT_NO_THROW((void)io::read_meshes(std::string(CLEAVE_SOURCE_DIR) + "/tests/data/meshes/cube_quads.ply"));
}

// fuzz_mesh: a PLY whose "end_header" is followed by a vertical tab, not a line end (and
// a mangled property line) made assimp 5.2's PLY reader spin forever; SIGTERM did not stop
// cleave there. read_meshes refuses a header that is not text before assimp reads it.
TEST(MeshImport, PlyHeaderWithAControlCharacterIsRefusedNotAHang) {
  const std::string file =
      std::string(CLEAVE_SOURCE_DIR) + "/tests/data/fuzz/ply_end_header_then_vertical_tab.ply";
  EXPECT_THROW((void)io::read_meshes(file), io::MeshIoError);
  // Its property line mended, the vertical tab alone is refused, naming the byte.
  std::string text = read_text("tests/data/fuzz/ply_end_header_then_vertical_tab.ply");
  text.replace(text.find("properNSt6locale5ty"), 19, "property");
  const std::filesystem::path copy = std::filesystem::temp_directory_path() / "cleave_ply_header_as_text.ply";
  { std::ofstream(copy, std::ios::binary) << text; }
  try {
    (void)io::read_meshes(copy);
    ADD_FAILURE() << "no MeshIoError";
  } catch (const io::MeshIoError& e) {
    EXPECT_TRUE(has(e.what(), "cleave_ply_header_as_text.ply")) << e.what();
    EXPECT_TRUE(has(e.what(), "0x0b")) << e.what();
  }
  // The same header as text, tabs and CR-LF line ends included, is read.
  text.replace(text.find("end_header\v"), 11, "end_header \t\r\n");
  for (std::size_t at = text.find("\nproperty"); at != std::string::npos; at = text.find("\nproperty", at + 3))
    text.replace(at, 1, "\r\n");
  { std::ofstream(copy, std::ios::binary) << text; }
  EXPECT_NO_THROW((void)io::read_meshes(copy));
  std::filesystem::remove(copy);
}

// fuzz_mesh (UBSan build, glibc's heap checks): a PLY header declaring 'vertex' and 'face'
// twice, with run-together property lines, corrupted assimp 5.2's heap ("malloc(): invalid
// size"); the same header with clean lines crashed it. read_meshes refuses both first.
TEST(MeshImport, PlyHeaderDeclaringAnElementTwiceIsRefusedNotACrash) {
  const std::string fuzzed =
      std::string(CLEAVE_SOURCE_DIR) + "/tests/data/fuzz/ply_elements_declared_twice.ply";
  EXPECT_THROW((void)io::read_meshes(fuzzed), io::MeshIoError);
  const std::filesystem::path twice =
      std::filesystem::temp_directory_path() / "cleave_ply_vertex_twice.ply";
  {
    std::ofstream(twice, std::ios::binary)
        << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
           "property float z\nelement face 6\nelement vertex 8\nproperty float x\n"
           "property float y\nproperty float z\nelement face 6\nproperty list uchar int "
           "vertex_indices\nend_header\n0 0 0\n2 0 0\n0 2 0\n2 2 0\n0 0 2\n2 0 2\n0 2 2\n"
           "2 2 2\n4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
  }
  try {
    (void)io::read_meshes(twice);
    ADD_FAILURE() << "no MeshIoError";
  } catch (const io::MeshIoError& e) {
    EXPECT_TRUE(has(e.what(), "declares the element 'vertex' a second time")) << e.what();
  }
  std::filesystem::remove(twice);
}

// fuzz_checkpoint (UBSan): an empty vector of numbers was read with memcpy into its null
// data(). Every checkpoint holds some; they read back empty now without undefined behaviour.
TEST(StateCodec, EmptyNumberVectorsReadBack) {
  physics::StateWriter w;
  w.put(std::vector<double>{});
  w.put(std::vector<std::uint32_t>{7, 8});
  physics::StateReader r(w.bytes());
  EXPECT_TRUE(r.numbers<double>().empty());
  EXPECT_EQ(r.numbers<std::uint32_t>(), (std::vector<std::uint32_t>{7, 8}));
  EXPECT_TRUE(r.done());
}

// A beam length of 1e44 mm (fuzz_validation_scenario, on a fresh clone's CI run) made the
// particle count overflow a long (undefined behaviour) before any check; the lattice size is
// now bounded per axis and in all, with the key named.
TEST(ValidationSpecimen, AnAstronomicalLatticeIsRefusedByKey) {
  const std::string mmb = read_text("scenarios/validation/mmb_50_coarse.toml");
  const auto at = mmb.find("length = 30.25");
  ASSERT_NE(at, std::string::npos);
  for (const auto& [value, key] :
       std::vector<std::pair<std::string, std::string>>{{"1" + std::string(44, '1') + "5.25", "specimen.length"},
                                                        {"25000.25", "specimen.length"}}) {
    std::string text = mmb;
    text.replace(at, 14, "length = " + value);
    try {
      (void)io::parse_validation_scenario(text, "mmb.toml");
      ADD_FAILURE() << "length = " << value << " was accepted";
    } catch (const io::ScenarioError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
      EXPECT_TRUE(has(e.what(), "at most")) << e.what();
    }
  }
  // A long beam of a few million bodies is still fine.
  std::string text = mmb;
  text.replace(at, 14, "length = 300.25");
  EXPECT_NO_THROW((void)io::parse_validation_scenario(text, "mmb.toml"));
}

}  // namespace
