// Scenario files: valid files of each shape, and one test per class of bad input, each checking
// the exception type, the line and the key the error names.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "io/key_catalogue.hpp"
#include "io/scenario.hpp"
#include "io/scenario_writer.hpp"
#include "io/units.hpp"
#include "io/validation_scenario.hpp"
#include "scenario_error_test.hpp"
#include "sim/world_assembly.hpp"

namespace cleave::io {
namespace {

namespace fs = std::filesystem;
using geometry::KeepRule;
using geometry::Outline;

constexpr double kTol = 1e-15;
/// A valid [grain] table, appended to texts whose error lies before it.
const std::string kGrain = "[grain]\nr = 1\nt = 1\n";
/// A valid file of 6 lines; errors in tables appended to it are on line 7 or later.
const std::string kBase = "[specimen]\nshape = \"box\"\nsize = [1, 1, 1]\n" + kGrain;

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// A scratch folder under the system temp directory, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("cleave_test_scenario_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// ---- valid files ------------------------------------------------------------------------

TEST(Scenario, BoxWithDefaults) {
  const Scenario s = parse_scenario(R"([specimen]
shape = "box"
size = [12, 10.5, 4]

[grain]
r = 1
t = 1.3
)",
                                    "scenarios/mem.toml");
  EXPECT_EQ(s.source, "scenarios/mem.toml");
  EXPECT_EQ(s.name, "mem");
  EXPECT_EQ(s.description, "");
  EXPECT_EQ(s.length_unit, "mm");
  const auto& d = s.specimen;
  EXPECT_EQ(d.outline.kind, Outline::Kind::box);
  EXPECT_NEAR(d.outline.size.x(), 12e-3, kTol);
  EXPECT_NEAR(d.outline.size.y(), 10.5e-3, kTol);
  EXPECT_NEAR(d.outline.size.z(), 4e-3, kTol);
  EXPECT_EQ(d.outline.notch_width, 0.0);
  EXPECT_EQ(d.outline.notch_depth, 0.0);
  EXPECT_EQ(d.keep, KeepRule::cell_inside);
  EXPECT_NEAR(d.r, 1e-3, kTol);
  EXPECT_EQ(d.r_bar, d.r);
  EXPECT_NEAR(d.t, 1.3e-3, kTol);
  EXPECT_EQ(d.t_bar, d.t);
  EXPECT_EQ(d.seed, 1u);
  EXPECT_EQ(d.family_mix, 0.5);
  EXPECT_EQ(d.angles, (std::vector<int>{0, 60, 120}));
  EXPECT_EQ(s.split.min_fragment_fraction, 0.01);
  EXPECT_EQ(s.output.mesh_format, MeshFormat::obj);
  EXPECT_EQ(s.output.mesh_layout, MeshLayout::scene);
}

TEST(Scenario, DiscInMicrometresWithEveryOption) {
  const Scenario s = parse_scenario(R"([scenario]
name = "disc run"
description = "a disc"
length_unit = "um"

[specimen]
shape = "disc"
diameter = 15000
thickness = 5000.0
keep = "centre_inside"

[grain]
r = 1000
r_bar = 900
t = 1300
t_bar = 1000

[orientation]
seed = 42
family_mix = 0.25
angles = [120, 0]

[split]
min_fragment_fraction = 0.1

[output]
mesh_format = "obj"
mesh_layout = "per_fragment"
)",
                                    "inline");
  EXPECT_EQ(s.name, "disc run");
  EXPECT_EQ(s.description, "a disc");
  EXPECT_EQ(s.length_unit, "um");
  const auto& d = s.specimen;
  EXPECT_EQ(d.outline.kind, Outline::Kind::disc);
  EXPECT_NEAR(d.outline.size.x(), 15e-3, kTol);
  EXPECT_NEAR(d.outline.size.y(), 15e-3, kTol);
  EXPECT_NEAR(d.outline.size.z(), 5e-3, kTol);
  EXPECT_EQ(d.keep, KeepRule::centre_inside);
  EXPECT_NEAR(d.r, 1e-3, kTol);
  EXPECT_NEAR(d.r_bar, 0.9e-3, kTol);
  EXPECT_NEAR(d.t, 1.3e-3, kTol);
  EXPECT_NEAR(d.t_bar, 1e-3, kTol);
  EXPECT_EQ(d.seed, 42u);
  EXPECT_EQ(d.family_mix, 0.25);
  EXPECT_EQ(d.angles, (std::vector<int>{120, 0}));
  EXPECT_EQ(s.split.min_fragment_fraction, 0.1);
  EXPECT_EQ(s.output.mesh_format, MeshFormat::obj);
  EXPECT_EQ(s.output.mesh_layout, MeshLayout::per_fragment);
}

TEST(Scenario, NotchedBeamInMetres) {
  const Scenario s = parse_scenario(R"([scenario]
length_unit = "m"
[specimen]
shape = "beam"
length = 0.02
height = 0.005
thickness = 4e-3
notch_width = 0.001
notch_depth = 0.002
[grain]
r = 0.001
t = 0.001
[output]
mesh_format = "stl_ascii"
)",
                                    "beam.toml");
  EXPECT_EQ(s.name, "beam");
  EXPECT_EQ(s.length_unit, "m");
  const auto& o = s.specimen.outline;
  EXPECT_EQ(o.kind, Outline::Kind::beam);
  EXPECT_EQ(o.size.x(), 0.02);
  EXPECT_EQ(o.size.y(), 0.005);
  EXPECT_EQ(o.size.z(), 4e-3);
  EXPECT_EQ(o.notch_width, 0.001);
  EXPECT_EQ(o.notch_depth, 0.002);
  EXPECT_EQ(s.specimen.r, 0.001);
  EXPECT_EQ(s.output.mesh_format, MeshFormat::stl_ascii);
  EXPECT_EQ(s.output.mesh_layout, MeshLayout::scene);
}

TEST(Scenario, UnnotchedBeamAndInlineTables) {
  const Scenario s = parse_scenario(
      "specimen = { shape = \"beam\", length = 20, height = 5, thickness = 4 }\n"
      "grain = { r = 1, t = 1 }\n",
      "inline");
  EXPECT_EQ(s.specimen.outline.kind, Outline::Kind::beam);
  EXPECT_NEAR(s.specimen.outline.size.x(), 20e-3, kTol);
  EXPECT_EQ(s.specimen.outline.notch_width, 0.0);
  EXPECT_EQ(s.specimen.outline.notch_depth, 0.0);
}

TEST(Scenario, LoadsAFileAndNamesItAfterItsStem) {
  TempDir dir;
  const fs::path file = dir.path() / "drop_test.toml";
  std::ofstream(file) << "[specimen]\nshape = \"box\"\nsize = [6, 6, 2]\n[grain]\nr = 1\nt = 1\n";
  const Scenario s = load_scenario(file);
  EXPECT_EQ(s.source, file.string());
  EXPECT_EQ(s.name, "drop_test");
  EXPECT_NEAR(s.specimen.outline.size.x(), 6e-3, kTol);
  EXPECT_NEAR(s.specimen.outline.size.z(), 2e-3, kTol);
}

TEST(Scenario, ErrorsFromALoadedFileNameIt) {
  TempDir dir;
  const fs::path file = dir.path() / "bad.toml";
  std::ofstream(file) << "[specimen]\nshape = \"box\"\nsize = [6, 6, 2]\n[grain]\nr = -1\nt = 1\n";
  try {
    (void)load_scenario(file);
    ADD_FAILURE() << "no ScenarioError";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_EQ(e.line(), 5);
    EXPECT_EQ(std::string(e.what()), file.string() + ":5:5: key 'grain.r': must be > 0, found -1");
  }
}

TEST(Scenario, ReferenceFileLoads) {
  const Scenario s = load_scenario(CLEAVE_SOURCE_DIR "/scenarios/reference.toml");
  EXPECT_EQ(s.name, "reference");
  EXPECT_EQ(s.specimen.outline.kind, Outline::Kind::box);
  EXPECT_NEAR(s.specimen.outline.size.x(), 12e-3, kTol);
  EXPECT_NEAR(s.specimen.outline.size.z(), 4e-3, kTol);
  EXPECT_NEAR(s.specimen.r, 1e-3, kTol);
  EXPECT_NEAR(s.specimen.t, 1e-3, kTol);
  // It documents the dynamics tables too, and they parse.
  EXPECT_TRUE(s.dynamics.enabled);
  EXPECT_EQ(s.walls.size(), 1u);
  EXPECT_EQ(s.contact.particle_particle.kn, 5000.0);
}

/// The keys scenarios/reference.toml writes under each table header, as `key = ...` or
/// commented out as `# key = ...` (alternatives); headers count commented out too, and a
/// sub-table's header [a.b] counts as the key b of [a].
std::map<std::string, std::set<std::string>> reference_keys(const fs::path& file) {
  static const std::regex header(R"(^\s*(?:#\s*)?\[\[?\s*([A-Za-z0-9_.]+)\s*\]\]?)");
  static const std::regex key(R"(^\s*(?:#\s*)?([A-Za-z_][A-Za-z0-9_]*)\s*=)");
  std::map<std::string, std::set<std::string>> keys;
  std::ifstream in(file);
  std::string table;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_search(line, m, header)) {
      table = m[1];
      keys[table];
      if (const auto dot = table.rfind('.'); dot != std::string::npos)
        keys[table.substr(0, dot)].insert(table.substr(dot + 1));
    } else if (!table.empty() && std::regex_search(line, m, key)) {
      keys[table].insert(m[1]);
    }
  }
  return keys;
}

/// "wall[2]" -> "wall": the array tables' entries share one header.
std::string table_header(const std::string& name) {
  return std::regex_replace(name, std::regex(R"(\[[0-9]+\])"), "");
}

TEST(ScenarioReference, ListsEveryKeyTheReaderAccepts) {
  const fs::path reference = CLEAVE_SOURCE_DIR "/scenarios/reference.toml";
  const auto documented = reference_keys(reference);
  // The reference itself, and every committed scenario (they reach the tables the reference
  // can show only commented out: [[mesh_grain]], each kind of [[stage]]). The validation
  // specimens and the calibration file have formats of their own.
  std::vector<fs::path> files = {reference};
  for (const auto& entry : fs::recursive_directory_iterator(CLEAVE_SOURCE_DIR "/scenarios")) {
    if (entry.path().extension() != ".toml" || entry.path() == reference) continue;
    if (entry.path().parent_path().filename() == "validation") continue;
    std::ifstream in(entry.path());
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    if (text.find("\n[specimen]") != std::string::npos) files.push_back(entry.path());
  }
  ASSERT_GT(files.size(), 10u);
  std::set<std::pair<std::string, std::string>> missing;
  std::map<std::string, std::set<std::string>> accepted;
  for (const fs::path& file : files) {
    KeyCatalogue catalogue;
    EXPECT_NO_THROW((void)load_scenario(file)) << file;
    for (const AcceptedKeys& t : catalogue.tables()) {
      if (t.source != file.string()) continue;  // a material preset's own file
      const std::string name = table_header(t.table);
      const auto it = documented.find(name);
      for (const std::string& k : t.keys) {
        accepted[name].insert(k);
        if (it == documented.end() || it->second.count(k) == 0) missing.insert({name, k});
      }
    }
  }
  for (const auto& [table, k] : missing) {
    ADD_FAILURE() << "scenarios/reference.toml does not list [" << table << "] " << k;
  }
  // Nor does it list a key the reader would refuse (a stale or misspelt one).
  for (const auto& [table, ks] : documented) {
    for (const std::string& k : ks) {
      EXPECT_TRUE(accepted.count(table) && accepted[table].count(k))
          << "scenarios/reference.toml lists [" << table << "] " << k
          << ", which no reader accepts";
    }
  }
  // Each table of the format was reached at least once, so none escaped the check.
  for (std::string_view t :
       {"scenario", "specimen", "grain", "mesh_grain", "orientation", "split", "output", "material",
        "contact", "contact.particle_particle", "contact.particle_wall", "dynamics", "wall", "bond",
        "fracture", "thermal", "periodic", "stage", "crystal", "cleavage"}) {
    EXPECT_TRUE(accepted.count(std::string(t))) << "no scenario reaches [" << t << "]";
  }
}

TEST(ScenarioReference, TheFormatPageListsEveryValidationKey) {
  // The validation files have a format of their own, listed in SCENARIO_FORMAT.md's last
  // section: every table and key the validation reader accepts is written there in backticks.
  std::ifstream in(CLEAVE_SOURCE_DIR "/docs/SCENARIO_FORMAT.md");
  const std::string page((std::istreambuf_iterator<char>(in)), {});
  const auto start = page.find("## Validation scenarios");
  ASSERT_NE(start, std::string::npos);
  const std::string section = page.substr(start, page.find("\n## ", start + 1) - start);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(CLEAVE_SOURCE_DIR "/scenarios/validation")) {
    if (entry.path().extension() != ".toml") continue;
    ++files;
    KeyCatalogue catalogue;
    EXPECT_NO_THROW((void)load_validation_scenario(entry.path())) << entry.path();
    for (const AcceptedKeys& t : catalogue.tables()) {
      if (t.source != entry.path().string()) continue;
      const std::string table = t.table.substr(0, t.table.find('.'));
      if (table == t.table) {
        EXPECT_TRUE(has(section, "`[" + table + "]`")) << "no [" << table << "]";
      }
      for (const std::string& k : t.keys) {
        EXPECT_TRUE(has(section, "`" + k + "`")) << "[" << t.table << "] " << k << " is not listed";
      }
    }
  }
  EXPECT_GT(files, 5u);
}

// ---- errors -------------------------------------------------------------------------------

TEST(ScenarioErrors, MissingFile) {
  const fs::path missing = fs::temp_directory_path() / "cleave_no_such_dir" / "none.toml";
  try {
    (void)load_scenario(missing);
    ADD_FAILURE() << "no ScenarioError";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.file(), missing.string());
    EXPECT_EQ(e.line(), 0);
    EXPECT_EQ(e.key(), "");
    EXPECT_EQ(std::string(e.what()), missing.string() + ": file does not exist");
  }
}

TEST(ScenarioErrors, DirectoryCannotBeRead) {
  TempDir dir;
  try {
    (void)load_scenario(dir.path());
    ADD_FAILURE() << "no ScenarioError";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.line(), 0);
    EXPECT_EQ(e.key(), "");
    EXPECT_TRUE(has(e.what(), "cannot be read")) << e.what();
  }
}

TEST(ScenarioErrors, TomlSyntax) {
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [1, 2,, 3]\n", 3, "",
                        "TOML syntax error");
  EXPECT_SCENARIO_ERROR("[grain]\nr = 1\nr = 2\n", 3, "", "TOML syntax error");
  EXPECT_SCENARIO_ERROR("[grain]\nr = 1\nt = \"unterminated\n", 3, "", "TOML syntax error");
}

TEST(ScenarioErrors, UnknownTable) {
  EXPECT_SCENARIO_ERROR(R"([specimen]
shape = "box"
size = [12, 12, 4]
[grain]
r = 1
t = 1
[materials]
density = 3.9
)",
                        7, "materials", "'scenario', 'specimen', 'grain', 'orientation'");
  EXPECT_SCENARIO_ERROR("seed = 3\n[specimen]\nshape = \"box\"\n", 1, "seed", "unknown table");
}

TEST(ScenarioErrors, UnknownKeyListsTheAcceptedKeys) {
  EXPECT_SCENARIO_ERROR(R"([specimen]
shape = "box"
size = [12, 12, 4]
[grain]
r = 1
radius = 1
t = 1
)",
                        6, "grain.radius", "accepted keys: 'r', 'r_bar', 't', 't_bar'");
  // The first unknown key in the file is named, whatever the alphabet says.
  EXPECT_SCENARIO_ERROR(R"([specimen]
shape = "box"
zeta = 1
size = [12, 12, 4]
alpha = 2
)" + kGrain,
                        3, "specimen.zeta", "'notch_depth', 'keep'");
  EXPECT_SCENARIO_ERROR(kBase + "[output]\nformat = \"stl\"\n", 8, "output.format",
                        "'mesh_format', 'mesh_layout'");
  // An unknown key is pointed at by its name, not its value.
  try {
    (void)parse_scenario(kBase + "[split]\n  fraction = 0.1\n", "mem.toml");
    ADD_FAILURE() << "no ScenarioError";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()),
              "mem.toml:8:3: key 'split.fraction': unknown key in [split]; accepted keys: "
              "'min_fragment_fraction', 'min_fragment_diameter'");
  }
}

TEST(ScenarioErrors, KeyOfAnotherShape) {
  EXPECT_SCENARIO_ERROR(R"([specimen]
shape = "box"
size = [12, 12, 4]
diameter = 15
)" + kGrain,
                        4, "specimen.diameter",
                        "does not apply to shape 'box' (only to 'disc', 'voronoi')");
  EXPECT_SCENARIO_ERROR(R"([specimen]
shape = "disc"
diameter = 15
thickness = 5
notch_depth = 1
)" + kGrain,
                        5, "specimen.notch_depth", "only to 'beam'");
}

TEST(ScenarioErrors, WrongType) {
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [12, 12, 4]\n[grain]\nr = \"1\"\n", 5,
                        "grain.r",
                        "expected a number, or a number with its unit as a string (e.g. \"1 m\" "
                        "for a length (m)); \"1\" has no unit");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = 3\n" + kGrain, 2, "specimen.shape",
                        "expected a string, found an integer");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = 12\n" + kGrain, 3, "specimen.size",
                        "expected an array of 3 numbers, found an integer");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [12,\n  true,\n  4]\n" + kGrain, 4,
                        "specimen.size", "element 2: expected a number");
  EXPECT_SCENARIO_ERROR(kBase + "[orientation]\nseed = 1.5\n", 8, "orientation.seed",
                        "expected an integer, found a float");
  EXPECT_SCENARIO_ERROR(kBase + "[scenario]\nname = 7\n", 8, "scenario.name",
                        "expected a string, found an integer");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [12, 12, 4]\ngrain = 3\n" + kGrain, 4,
                        "specimen.grain", "unknown key");
  EXPECT_SCENARIO_ERROR("grain = 3\n[specimen]\nshape = \"box\"\n", 1, "grain",
                        "expected a table, found an integer");
}

TEST(ScenarioErrors, NonPositiveSizes) {
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [12, 0, 4]\n" + kGrain, 3,
                        "specimen.size", "element 2: must be > 0, found 0");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [12, 12]\n" + kGrain, 3,
                        "specimen.size", "found 2 elements");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"disc\"\ndiameter = -15\nthickness = 5\n" + kGrain, 3,
                        "specimen.diameter", "must be > 0, found -15");
  EXPECT_SCENARIO_ERROR(
      "[specimen]\nshape = \"beam\"\nlength = 20\nheight = 5\nthickness = 0.0\n" + kGrain, 5,
      "specimen.thickness", "must be > 0");
  EXPECT_SCENARIO_ERROR(
      "[specimen]\nshape = \"box\"\nsize = [1, 1, 1]\n[grain]\nr = 1\nt = 1\nt_bar = -0.5\n", 7,
      "grain.t_bar", "must be > 0, found -0.5");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [1, 1, 1]\n[grain]\nr = 0\nt = 1\n", 5,
                        "grain.r", "must be > 0, found 0");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [1, 1, 1]\n[grain]\nr = inf\nt = 1\n",
                        5, "grain.r", "expected a finite number");
}

TEST(ScenarioErrors, RBarExceedsR) {
  const std::string text = R"([specimen]
shape = "box"
size = [12, 12, 4]
[grain]
r = 1
t = 1
r_bar = 1.5
)";
  EXPECT_SCENARIO_ERROR(text, 7, "grain.r_bar", "must not exceed grain.r = 1, found 1.5");
  try {
    (void)parse_scenario(text, "mem.toml");
    ADD_FAILURE() << "no ScenarioError";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.column(), 9);
    EXPECT_EQ(std::string(e.what()),
              "mem.toml:7:9: key 'grain.r_bar': must not exceed grain.r = 1, found 1.5");
  }
}

TEST(ScenarioErrors, TBarExceedsT) {
  EXPECT_SCENARIO_ERROR(R"([specimen]
shape = "box"
size = [12, 12, 4]
[grain]
r = 1
t = 1
t_bar = 1.3
)",
                        7, "grain.t_bar", "must not exceed grain.t = 1, found 1.3");
}

TEST(ScenarioErrors, ValuesOutOfRange) {
  EXPECT_SCENARIO_ERROR(kBase + "[orientation]\nfamily_mix = 1.5\n", 8, "orientation.family_mix",
                        "must be in [0, 1], found 1.5");
  EXPECT_SCENARIO_ERROR(kBase + "[orientation]\nseed = -1\n", 8, "orientation.seed",
                        "must be >= 0, found -1");
  EXPECT_SCENARIO_ERROR(kBase + "[split]\nmin_fragment_fraction = 0.5\n", 8,
                        "split.min_fragment_fraction", "must be in [0, 0.5), found 0.5");
  EXPECT_SCENARIO_ERROR(kBase + "[split]\nmin_fragment_fraction = -0.1\n", 8,
                        "split.min_fragment_fraction", "must be in [0, 0.5)");
  EXPECT_SCENARIO_ERROR(kBase + "[scenario]\nname = \"\"\n", 8, "scenario.name",
                        "must not be empty");
}

TEST(ScenarioErrors, BeamNotch) {
  const std::string beam = "[specimen]\nshape = \"beam\"\nlength = 20\nheight = 5\nthickness = 4\n";
  // Each case appends its notch keys (lines 6 and 7), then the grain table.
  EXPECT_SCENARIO_ERROR(beam + "notch_width = 1\nnotch_depth = 5\n" + kGrain, 7,
                        "specimen.notch_depth", "must be < specimen.height = 5, found 5");
  EXPECT_SCENARIO_ERROR(beam + "notch_width = 20\nnotch_depth = 1\n" + kGrain, 6,
                        "specimen.notch_width", "must be < specimen.length = 20");
  EXPECT_SCENARIO_ERROR(beam + "notch_width = -1\n" + kGrain, 6, "specimen.notch_width",
                        "must be >= 0");
  EXPECT_SCENARIO_ERROR(beam + "notch_width = 1\nnotch_depth = 0\n" + kGrain, 7,
                        "specimen.notch_depth", "must be > 0 when specimen.notch_width > 0");
  // An absent partner is blamed at the table's header.
  EXPECT_SCENARIO_ERROR(beam + "notch_depth = 2\n" + kGrain, 1, "specimen.notch_width",
                        "must be > 0 when specimen.notch_depth > 0");
}

TEST(ScenarioErrors, BadEnumListsTheAcceptedValues) {
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"sphere\"\n" + kGrain, 2, "specimen.shape",
                        "unknown value 'sphere'; accepted: 'box', 'disc', 'beam'");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [1, 1, 1]\nkeep = \"all\"\n" + kGrain,
                        4, "specimen.keep", "accepted: 'cell_inside', 'centre_inside'");
  EXPECT_SCENARIO_ERROR("[scenario]\nlength_unit = \"cm\"\n" + kBase, 2, "scenario.length_unit",
                        "unknown value 'cm'; accepted: 'm', 'mm', 'um'");
  EXPECT_SCENARIO_ERROR(kBase + "[output]\nmesh_format = \"ply\"\n", 8, "output.mesh_format",
                        "accepted: 'stl', 'stl_ascii', 'obj'");
  EXPECT_SCENARIO_ERROR(kBase + "[output]\nmesh_layout = \"split\"\n", 8, "output.mesh_layout",
                        "accepted: 'scene', 'per_fragment'");
}

TEST(ScenarioErrors, EmptyOrBadAngles) {
  const std::string head = kBase + "[orientation]\n";
  EXPECT_SCENARIO_ERROR(head + "angles = []\n", 8, "orientation.angles", "must not be empty");
  EXPECT_SCENARIO_ERROR(head + "angles = [0,\n  45]\n", 9, "orientation.angles",
                        "element 2: angle 45 is not one of 0, 60, 120");
  EXPECT_SCENARIO_ERROR(head + "angles = [60, 0, 60]\n", 8, "orientation.angles",
                        "element 3: angle 60 is repeated");
  EXPECT_SCENARIO_ERROR(head + "angles = [60.0]\n", 8, "orientation.angles",
                        "element 1: expected an integer angle, found a float");
  EXPECT_SCENARIO_ERROR(head + "angles = 60\n", 8, "orientation.angles",
                        "expected an array of angles");
}

TEST(ScenarioErrors, MissingRequiredKeyPointsAtItsTable) {
  EXPECT_SCENARIO_ERROR(R"([specimen]
shape = "box"
size = [12, 12, 4]

[grain]
r = 1
)",
                        5, "grain.t", "missing required key");
  EXPECT_SCENARIO_ERROR("[scenario]\nname = \"x\"\n[specimen]\nsize = [1, 1, 1]\n" + kGrain, 3,
                        "specimen.shape", "missing required key");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\n" + kGrain, 1, "specimen.size",
                        "missing required key");
  EXPECT_SCENARIO_ERROR("\n[specimen]\nshape = \"disc\"\ndiameter = 3\n" + kGrain, 2,
                        "specimen.thickness", "missing required key");
}

TEST(ScenarioErrors, MissingRequiredTable) {
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"box\"\nsize = [1, 1, 1]\n", 1, "grain",
                        "missing required table [grain]");
  EXPECT_SCENARIO_ERROR("", 1, "specimen", "missing required table [specimen]");
}

}  // namespace
// ---- dynamics tables ----------------------------------------------------------------------

namespace {
const char* kDropTest = R"([specimen]
shape = "box"
size = [12, 12, 4]
[grain]
r = 1
r_bar = 0.9
t = 1
[material]
density = 3100
[contact]
dilation_radius = 0.05
[contact.particle_particle]
kn = 5.0
ks = 2.0
c_res = 2.0
mu_r = 0.5
[contact.particle_wall]
kn = 10.0
c_res = 10.0
[dynamics]
dt = 1e-4
duration = 0.5
lift = 50
frames = 10
[[wall]]
kind = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]
[[wall]]
name = "top"
kind = "platen"
point = [6, 6, 60]
normal = [0, 0, -1]
u = [1, 0, 0]
size = [20, 20]
velocity = [0, 0, -0.001]
[[wall]]
kind = "cylinder"
point = [0, 0, 0]
normal = [0, 1, 0]
length = 10
radius = 2
)";
}  // namespace

TEST(Scenario, DynamicsContactAndWalls) {
  const Scenario s = parse_scenario(kDropTest, "drop.toml");
  EXPECT_TRUE(s.dynamics.enabled);
  EXPECT_EQ(s.dynamics.dt, 1e-4);
  EXPECT_EQ(s.dynamics.dt_position.line, 21);
  EXPECT_NEAR(s.dynamics.lift, 0.05, 1e-15);
  EXPECT_EQ(s.dynamics.frames, 10);
  EXPECT_NEAR(s.contact.dilation_radius, 0.05e-3, 1e-18);
  EXPECT_EQ(s.contact.particle_particle.kn, 5.0);
  EXPECT_EQ(s.contact.particle_particle.mu_r, 0.5);
  EXPECT_EQ(s.contact.particle_particle.damping_ratio, 0.1);  // default of eq 2.6
  EXPECT_EQ(s.contact.particle_wall.c_res, 10.0);
  EXPECT_EQ(s.material.density, 3100.0);
  ASSERT_EQ(s.walls.size(), 3u);
  EXPECT_EQ(s.walls[0].kind, cleave::physics::Wall::Kind::plane);
  EXPECT_EQ(s.walls[0].name, "wall_1");
  EXPECT_EQ(s.walls[1].kind, cleave::physics::Wall::Kind::platen);
  EXPECT_NEAR(s.walls[1].half_u, 0.01, 1e-15);  // 20 mm wide
  EXPECT_NEAR(s.walls[1].origin.z(), 0.06, 1e-15);
  EXPECT_NEAR(s.walls[1].velocity.z(), -1e-6, 1e-21);  // mm/s, like every length
  EXPECT_EQ(s.walls[2].kind, cleave::physics::Wall::Kind::cylinder);
  EXPECT_NEAR(s.walls[2].radius, 2e-3, 1e-15);
}

TEST(ScenarioErrors, DynamicsNeedsContactAndValidWalls) {
  std::string no_contact = kDropTest;
  const auto from = no_contact.find("[contact]"), to = no_contact.find("[dynamics]");
  no_contact.erase(from, to - from);
  EXPECT_SCENARIO_ERROR(no_contact, 1, "contact.dilation_radius", "needs a [contact] table");

  std::string bad_kind = kDropTest;
  bad_kind.replace(bad_kind.find("kind = \"cylinder\""), 17, "kind = \"sphere\"");
  EXPECT_SCENARIO_ERROR(bad_kind, 38, "wall[3].kind", "'plane', 'platen', 'cylinder'");

  std::string foreign = kDropTest;
  foreign.replace(foreign.find("normal = [0, 0, 1]"), 18, "normal = [0, 0, 1]\nradius = 3");
  EXPECT_SCENARIO_ERROR(foreign, 29, "wall[1].radius", "another kind of wall");

  std::string zero = kDropTest;
  zero.replace(zero.find("normal = [0, 0, 1]"), 18, "normal = [0, 0, 0]");
  EXPECT_SCENARIO_ERROR(zero, 28, "wall[1].normal", "zero vector");

  std::string cres = kDropTest;
  cres.replace(cres.find("c_res = 10.0"), 12, "c_res = 0.5");
  EXPECT_SCENARIO_ERROR(cres, 19, "contact.particle_wall.c_res", ">= 1");
}

// ---- staged runs: [bond] and [[stage]] ----------------------------------------------------

/// kDropTest without its duration, plus a bond table and stages (appended at line 41 on).
std::string staged(const std::string& stages, bool bond = true) {
  std::string text = kDropTest;
  text.replace(text.find("duration = 0.5\n"), 15, "# no duration\n");
  if (bond) text += "[bond]\nkbn = 6.366e8\nkbs = 2.546e8\ntbn = 1000\ntbn_unused = 0\n";
  return text + stages;
}

TEST(Scenario, StagesAndBonds) {
  std::string text = kDropTest;
  text.replace(text.find("duration = 0.5\n"), 15, "local_damping = 0.7\n");
  text += R"([bond]
kbn = 6.366e8
kbs = 2.546e8
tbn = 1000
tbs = 500
[[stage]]
name = "compaction"
wall_velocity = { wall_1 = [0, 0, 50], top = [0, 0, -50] }
until = "all_in_contact"
time = 0.05
[[stage]]
name = "bonding"
kind = "bond"
distance = 0.08
[[stage]]
name = "loading"
wall_velocity = { top = [0, 0, -0.001] }
until = "load_drop"
load_drop = 0.4
steps = 1000
frames = 3
)";
  const Scenario s = parse_scenario(text, "staged.toml");
  EXPECT_EQ(s.dynamics.local_damping, 0.7);
  ASSERT_TRUE(s.bond.enabled);
  EXPECT_EQ(s.bond.params.kbn, 6.366e8);
  EXPECT_EQ(s.bond.params.tbs, 500.0);
  ASSERT_EQ(s.stages.size(), 3u);
  const StageDef& c = s.stages[0];
  EXPECT_EQ(c.kind, StageDef::Kind::motion);
  EXPECT_EQ(c.until, StageDef::Until::all_in_contact);
  EXPECT_EQ(c.time, 0.05);
  ASSERT_EQ(c.wall_velocity.size(), 2u);
  EXPECT_NEAR(c.wall_velocity[0].second.z() + c.wall_velocity[1].second.z(), 0.0, 1e-15);
  EXPECT_EQ(c.load_walls.size(), 2u);  // default: the walls that move
  EXPECT_EQ(s.stages[1].kind, StageDef::Kind::bond);
  EXPECT_NEAR(s.stages[1].bond_distance, 0.08e-3, 1e-18);
  const StageDef& l = s.stages[2];
  EXPECT_EQ(l.steps, 1000u);
  EXPECT_EQ(l.load_drop, 0.4);
  EXPECT_EQ(l.frames, 3);
  ASSERT_EQ(l.load_walls, std::vector<std::string>{"top"});
  EXPECT_NEAR(l.wall_velocity[0].second.z(), -1e-6, 1e-21);  // mm/s -> m/s
}

/// The 1-based line of the last occurrence of `needle` in `text`.
int line_of_last(const std::string& text, const std::string& needle) {
  const auto at = text.rfind(needle);
  return at == std::string::npos ? -1 : 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

TEST(ScenarioErrors, StagesAndBonds) {
  const std::string loading = "[[stage]]\nname = \"loading\"\nwall_velocity = { top = [0, 0, -1] }\n";
  const std::string bonding = "[[stage]]\nname = \"bonding\"\nkind = \"bond\"\n";
  // Each case: the text, the text on the offending line, the key, part of the message.
  auto expect = [](const std::string& t, const std::string& at, const std::string& key, const std::string& part) {
    EXPECT_SCENARIO_ERROR(t, line_of_last(t, at), key, part);
  };
  expect(staged(bonding + loading + "steps = 10\n"), "tbn_unused", "bond.tbn_unused", "unknown key in [bond]");
  auto text = [&](const std::string& stages) {
    std::string t = staged(stages);
    t.replace(t.find("tbn_unused = 0\n"), 15, "tbs = 1000\n");
    return t;
  };
  expect(text(bonding + loading), "[[stage]]", "stage[2].steps", "steps (integer > 0) or time");
  expect(text(bonding + loading + "steps = 10\ntime = 1\n"), "time = 1", "stage[2].time", "not both");
  expect(text(bonding + loading + "steps = 0\n"), "steps = 0", "stage[2].steps", ">= 1");
  expect(text(bonding + "[[stage]]\nname = \"x\"\nwall_velocity = { lid = [0, 0, 1] }\nsteps = 5\n"), "lid",
         "stage[2].wall_velocity.lid", "no [[wall]] is named 'lid'");
  expect(text(bonding + "[[stage]]\nname = \"x\"\nsteps = 5\nuntil = \"load_drop\"\n"), "until",
         "stage[2].until", "needs walls to watch");
  expect(text(bonding + loading + "steps = 5\nuntil = \"broken\"\n"), "until", "stage[2].until",
         "'limit', 'all_in_contact', 'walls_touch', 'load_drop'");
  expect(text(bonding + loading + "steps = 5\nload_drop = 0.5\n"), "load_drop", "stage[2].load_drop",
         "only with until = \"load_drop\"");
  expect(text(bonding + loading + "steps = 5\ndistance = 1\n"), "distance", "stage[2].distance",
         "unknown key in [stage[2]]");
  expect(text(bonding + bonding), "name = \"bonding\"", "stage[2].name", "another [[stage]] is named 'bonding'");
  expect(text(bonding + "[[stage]]\nname = \"again\"\nkind = \"bond\"\n"), "kind = \"bond\"", "stage[2].kind",
         "bonds are initialised once");
  expect(text(loading + "steps = 5\n"), "[bond]", "bond", "no [[stage]] of kind \"bond\" initialises the bonds");
  // Without [bond], a bond stage has no parameters.
  expect(staged(bonding, false), "kind = \"bond\"", "stage[1].kind", "needs a [bond] table");
  // A staged run takes its length from its stages.
  expect(kDropTest + std::string(bonding), "duration", "dynamics.duration", "remove duration");
  std::string no_dynamics = kDropTest;
  no_dynamics.erase(no_dynamics.find("[dynamics]"), no_dynamics.find("[[wall]]") - no_dynamics.find("[dynamics]"));
  expect(no_dynamics + loading + "steps = 5\n", "[[stage]]", "stage", "[[stage]] tables need a [dynamics] table");
  std::string twin = kDropTest;
  twin += "[[wall]]\nname = \"top\"\nkind = \"plane\"\npoint = [0, 0, 9]\nnormal = [0, 0, -1]\n";
  expect(twin, "name = \"top\"", "wall[4].name", "another [[wall]] is named 'top'");
}
}  // namespace cleave::io

namespace cleave::io {

TEST(Scenario, RateScaleRunsTheSameStageAtAnotherLoadingRate) {
  // rate_scale folds into the stage: velocities times it, its length and ramp over it, so
  // the walls travel as far at any rate. Steps round up (a stage never ends short).
  std::string text = kDropTest;
  text.replace(text.find("duration = 0.5\n"), 15, "density_scale = 4\n");
  text += R"([bond]
kbn = 6.366e8
kbs = 2.546e8
tbn = 1000
tbs = 500
strength_modulus = 8
[[stage]]
name = "bonding"
kind = "bond"
[[stage]]
name = "slow"
wall_velocity = { top = [0, 0, -2] }
time = 0.01
ramp_time = 0.002
rate_scale = 0.25
[[stage]]
name = "fast"
wall_velocity = { top = [0, 0, -2] }
steps = 1001
rate_scale = 2
)";
  const Scenario s = parse_scenario(text, "rate.toml");
  EXPECT_EQ(s.dynamics.density_scale, 4.0);
  EXPECT_EQ(s.bond.strength_modulus, 8.0);
  ASSERT_EQ(s.stages.size(), 3u);
  const StageDef& slow = s.stages[1];
  EXPECT_NEAR(slow.wall_velocity[0].second.z(), -0.5e-3, 1e-18);  // 2 mm/s x 0.25
  EXPECT_NEAR(slow.time, 0.04, 1e-15);
  EXPECT_NEAR(slow.ramp_time, 0.008, 1e-15);
  EXPECT_NEAR(slow.time * slow.wall_velocity[0].second.z(), 0.01 * -2e-3, 1e-18);  // same travel
  const StageDef& fast = s.stages[2];
  EXPECT_NEAR(fast.wall_velocity[0].second.z(), -4e-3, 1e-18);
  EXPECT_EQ(fast.steps, 501u);  // 1001 / 2, rounded up
  EXPECT_EQ(fast.ramp_time, 0.0);
  // The as-run copy holds what runs: it reads back the same, with no rate_scale left to apply twice.
  const Scenario again = parse_scenario(scenario_to_toml(s), "again.toml");
  EXPECT_TRUE(scenario_differences(s, again).empty());
}

TEST(ScenarioErrors, RampRateAndDensityScale) {
  std::string text = kDropTest;
  text.replace(text.find("duration = 0.5\n"), 15, "# staged\n");
  text += "[bond]\nkbn = 1\nkbs = 1\ntbn = 1\ntbs = 1\n[[stage]]\nname = \"b\"\nkind = \"bond\"\n"
          "[[stage]]\nname = \"l\"\nwall_velocity = { top = [0, 0, -1] }\nsteps = 5\n";
  EXPECT_SCENARIO_ERROR(text + "rate_scale = 0\n", line_of_last(text + "rate_scale = 0\n", "rate_scale"),
                        "stage[2].rate_scale", "> 0");
  EXPECT_SCENARIO_ERROR(text + "ramp_time = -1\n", line_of_last(text + "ramp_time = -1\n", "ramp_time"),
                        "stage[2].ramp_time", ">= 0");
  const std::string scatter = std::string(text).replace(text.find("tbs = 1\n"), 8, "tbs = 1\nstrength_modulus = 0\n");
  EXPECT_SCENARIO_ERROR(scatter, line_of_last(scatter, "strength_modulus"), "bond.strength_modulus", "> 0");
  std::string dense = text;
  dense.replace(dense.find("# staged\n"), 9, "density_scale = 0.5\n");
  EXPECT_SCENARIO_ERROR(dense, line_of_last(dense, "density_scale"), "dynamics.density_scale", ">= 1");
}

TEST(Scenario, ManifoldToleranceReadsBackAndIsRefusedOutsideItsRange) {
  std::string text = kDropTest;
  text.replace(text.find("duration = 0.5\n"), 15, "duration = 0.5\nmanifold_tolerance = 0.02\n");
  const Scenario s = parse_scenario(text, "manifold.toml");
  EXPECT_EQ(s.dynamics.manifold_tolerance, 0.02);
  const Scenario again = parse_scenario(scenario_to_toml(s), "again.toml");
  EXPECT_TRUE(scenario_differences(s, again).empty());
  EXPECT_EQ(again.dynamics.manifold_tolerance, 0.02);
  EXPECT_EQ(parse_scenario(kDropTest, "plain.toml").dynamics.manifold_tolerance, 0.0);  // exact by default
  for (const char* bad : {"-0.1", "1"}) {
    std::string t = kDropTest;
    t.replace(t.find("duration = 0.5\n"), 15, std::string("duration = 0.5\nmanifold_tolerance = ") + bad + "\n");
    EXPECT_SCENARIO_ERROR(t, line_of_last(t, "manifold_tolerance"), "dynamics.manifold_tolerance",
                          std::string("must be in [0, 1), found ") + bad);
  }
}

TEST(Scenario, InPlaneReadsBackAndANonBooleanNamesItsKey) {
  std::string text = kDropTest;
  text.replace(text.find("duration = 0.5\n"), 15, "duration = 0.5\nin_plane = true\n");
  const Scenario s = parse_scenario(text, "plane.toml");
  EXPECT_TRUE(s.dynamics.in_plane);
  EXPECT_EQ(s.dynamics.in_plane_position.line, line_of_last(text, "in_plane"));
  const Scenario again = parse_scenario(scenario_to_toml(s), "again.toml");
  EXPECT_TRUE(scenario_differences(s, again).empty());
  EXPECT_TRUE(again.dynamics.in_plane);
  EXPECT_FALSE(parse_scenario(kDropTest, "plain.toml").dynamics.in_plane);  // off by default
  std::string bad = kDropTest;
  bad.replace(bad.find("duration = 0.5\n"), 15, "duration = 0.5\nin_plane = 1\n");
  EXPECT_SCENARIO_ERROR(bad, line_of_last(bad, "in_plane"), "dynamics.in_plane", "expected true or false");
}

TEST(Scenario, ThermalTableAndTemperatureStagesReadBackAndBadValuesNameTheirKey) {
  const std::string thermal = std::string(kDropTest) +
                              "[thermal]\ntemperature = 1773\nalpha_a = -2e-6\nalpha_c = 2e-5\nc_axis = \"random\"\n"
                              "seed = 3\nconductivity = 20\nheat_capacity = 800\n";
  auto with_stage = [](std::string text, const std::string& keys) {
    text.replace(text.find("duration = 0.5\n"), 15, "");
    return text + "[[stage]]\nname = \"cool\"\nwall_velocity = {}\ntime = 0.1\n" + keys;
  };
  const Scenario s = parse_scenario(with_stage(thermal, "temperature_rate = -100\ntemperature_target = 293\n"), "t.toml");
  EXPECT_TRUE(s.thermal.enabled);
  EXPECT_EQ(s.thermal.temperature, 1773.0);
  EXPECT_EQ(s.thermal.alpha_a, -2e-6);
  EXPECT_EQ(s.thermal.alpha_c, 2e-5);
  EXPECT_EQ(s.thermal.c_axis, ThermalDef::Axis::random);
  EXPECT_EQ(s.thermal.seed, 3u);
  EXPECT_EQ(s.thermal.heat_capacity, 800.0);
  EXPECT_EQ(s.stages.at(0).temperature_rate, -100.0);
  EXPECT_EQ(s.stages.at(0).temperature_target, 293.0);
  const Scenario again = parse_scenario(scenario_to_toml(s), "again.toml");
  EXPECT_TRUE(scenario_differences(s, again).empty());
  EXPECT_EQ(again.stages.at(0).temperature_rate, -100.0);
  // A field growing over a stage: K per length unit per second in the file (mm here).
  const Scenario grows = parse_scenario(with_stage(thermal, "temperature_gradient_rate = [0, 0, 5]\n"), "f.toml");
  EXPECT_EQ(grows.stages.at(0).temperature_gradient_rate, Eigen::Vector3d(0, 0, 5e3));
  EXPECT_TRUE(scenario_differences(grows, parse_scenario(scenario_to_toml(grows), "f2.toml")).empty());
  const std::string unheated = with_stage(std::string(kDropTest), "temperature_gradient_rate = [0, 0, 5]\n");
  EXPECT_SCENARIO_ERROR(unheated, line_of_last(unheated, "temperature_gradient_rate"), "stage[1].temperature_gradient_rate",
                        "[thermal]");
  // A linear field: K per length unit in the file, K/m read.
  const Scenario field = parse_scenario(std::string(kDropTest) + "[thermal]\ngradient = [0, 10, 0]\n", "g.toml");
  EXPECT_EQ(field.thermal.gradient, Eigen::Vector3d(0, 1e4, 0));
  EXPECT_TRUE(scenario_differences(field, parse_scenario(scenario_to_toml(field), "g2.toml")).empty());
  // Isotropic: alpha sets both.
  const Scenario iso = parse_scenario(std::string(kDropTest) + "[thermal]\nalpha = 8e-6\n", "iso.toml");
  EXPECT_EQ(iso.thermal.alpha_a, 8e-6);
  EXPECT_EQ(iso.thermal.alpha_c, 8e-6);
  EXPECT_EQ(iso.thermal.temperature, 293.15);
  EXPECT_FALSE(parse_scenario(kDropTest, "plain.toml").thermal.enabled);

  std::string both = std::string(kDropTest) + "[thermal]\nalpha = 8e-6\nalpha_c = 1e-5\n";
  EXPECT_SCENARIO_ERROR(both, line_of_last(both, "alpha_c"), "thermal.alpha_c", "not both");
  std::string half = std::string(kDropTest) + "[thermal]\nalpha_a = 8e-6\n";
  EXPECT_SCENARIO_ERROR(half, line_of_last(half, "[thermal]"), "thermal.alpha_c", "go together");
  std::string cold = std::string(kDropTest) + "[thermal]\ntemperature = -5\n";
  EXPECT_SCENARIO_ERROR(cold, line_of_last(cold, "temperature"), "thermal.temperature", "must be > 0");
  std::string no_capacity = std::string(kDropTest) + "[thermal]\nconductivity = 20\n";
  EXPECT_SCENARIO_ERROR(no_capacity, line_of_last(no_capacity, "[thermal]"), "thermal.heat_capacity", "missing");
  std::string axis = std::string(kDropTest) + "[thermal]\nc_axis = \"x\"\n";
  EXPECT_SCENARIO_ERROR(axis, line_of_last(axis, "c_axis"), "thermal.c_axis", "prism");
  const std::string no_thermal = with_stage(kDropTest, "temperature_rate = -100\ntemperature_target = 293\n");
  EXPECT_SCENARIO_ERROR(no_thermal, line_of_last(no_thermal, "temperature_rate"), "stage[1].temperature_rate",
                        "needs a [thermal] table");
  const Scenario shock = parse_scenario(
      with_stage(thermal, "quench_wall = \"top\"\nquench_temperature = 293\nquench_depth = 2\n"), "q.toml");
  EXPECT_EQ(shock.stages.at(0).quench_wall, "top");
  EXPECT_EQ(shock.stages.at(0).quench_depth, 2e-3);  // mm
  EXPECT_TRUE(scenario_differences(shock, parse_scenario(scenario_to_toml(shock), "q2.toml")).empty());
  const std::string nowall = with_stage(thermal, "quench_wall = \"side\"\nquench_temperature = 293\nquench_depth = 2\n");
  EXPECT_SCENARIO_ERROR(nowall, line_of_last(nowall, "quench_wall"), "stage[1].quench_wall", "no [[wall]] is named 'side'");
  const std::string stray = with_stage(thermal, "quench_depth = 2\n");
  EXPECT_SCENARIO_ERROR(stray, line_of_last(stray, "quench_depth"), "stage[1].quench_depth", "only with a quench_wall");
  const std::string no_target = with_stage(thermal, "temperature_rate = -100\n");
  EXPECT_SCENARIO_ERROR(no_target, line_of_last(no_target, "[[stage]]"), "stage[1].temperature_target", "missing");
}

TEST(Scenario, BondStressCriteriaReadBackAndReplaceTheBondStrengths) {
  auto bonded = [](const std::string& keys) {
    std::string text = kDropTest;
    text.replace(text.find("duration = 0.5\n"), 15, "");
    return text + "[bond]\nkbn = 1e9\nkbs = 4e8\n" + keys + "[[stage]]\nname = \"bond\"\nkind = \"bond\"\n";
  };
  const Scenario s = parse_scenario(bonded("criterion = \"rankine\"\nsigma_f = 2e6\n"), "r.toml");
  EXPECT_EQ(s.bond.params.criterion, physics::BondCriterion::rankine);
  EXPECT_EQ(s.bond.params.sigma_f, 2e6);
  const Scenario again = parse_scenario(scenario_to_toml(s), "again.toml");
  EXPECT_TRUE(scenario_differences(s, again).empty());
  EXPECT_EQ(again.bond.params.criterion, physics::BondCriterion::rankine);
  EXPECT_EQ(parse_scenario(bonded("criterion = \"hydrostatic\"\nsigma_f = 1e6\n"), "h.toml").bond.params.criterion,
            physics::BondCriterion::hydrostatic);
  EXPECT_EQ(parse_scenario(bonded("tbn = 1\ntbs = 1\n"), "l.toml").bond.params.criterion,
            physics::BondCriterion::limits);
  const std::string both = bonded("criterion = \"rankine\"\nsigma_f = 2e6\ntbn = 5\n");
  EXPECT_SCENARIO_ERROR(both, line_of_last(both, "tbn"), "bond.tbn", "replaces the bond strengths");
  const std::string lone = bonded("tbn = 1\ntbs = 1\nsigma_f = 2e6\n");
  EXPECT_SCENARIO_ERROR(lone, line_of_last(lone, "sigma_f"), "bond.sigma_f", "applies only with criterion");
  const std::string none = bonded("criterion = \"rankine\"\n");
  EXPECT_SCENARIO_ERROR(none, line_of_last(none, "[bond]"), "bond.sigma_f", "missing");
  const std::string odd = bonded("criterion = \"tresca\"\nsigma_f = 1\n");
  EXPECT_SCENARIO_ERROR(odd, line_of_last(odd, "criterion"), "bond.criterion", "rankine");
  const std::string cohesive = bonded("law = \"cohesive\"\nsigma_c = 1e6\ng_c = 10\ncriterion = \"rankine\"\n");
  EXPECT_SCENARIO_ERROR(cohesive, line_of_last(cohesive, "criterion"), "bond.criterion", "bonded_particle");
}

TEST(Scenario, BeamBondsReadBackInMetresAndRefuseTheSpringKeys) {
  auto bonded = [](const std::string& keys) {
    std::string text = kDropTest;
    text.replace(text.find("duration = 0.5\n"), 15, "");
    return text + "[bond]\nlaw = \"beam\"\n" + keys + "[[stage]]\nname = \"bond\"\nkind = \"bond\"\n";
  };
  // The drop test's lengths are in mm: radius 0.08 mm is 8e-5 m.
  const Scenario s = parse_scenario(bonded("young = 2e10\npoisson = 0.2\nradius = 0.08\nsigma_f = 5e7\n"), "b.toml");
  EXPECT_EQ(s.bond.params.law, physics::BondLaw::beam);
  EXPECT_EQ(s.bond.params.beam_young, 2e10);
  EXPECT_EQ(s.bond.params.beam_poisson, 0.2);
  EXPECT_DOUBLE_EQ(s.bond.params.beam_radius, 8e-5);
  EXPECT_EQ(s.bond.params.sigma_f, 5e7);
  EXPECT_EQ(s.bond.params.criterion, physics::BondCriterion::limits);
  const Scenario again = parse_scenario(scenario_to_toml(s), "again.toml");
  EXPECT_TRUE(scenario_differences(s, again).empty());
  // Without sigma_f a beam does not break; with a stress criterion sigma_f is required.
  const Scenario strong = parse_scenario(bonded("young = 2e10\npoisson = 0.2\nradius = 0.08\n"), "u.toml");
  EXPECT_TRUE(std::isinf(strong.bond.params.sigma_f));
  EXPECT_TRUE(scenario_differences(strong, parse_scenario(scenario_to_toml(strong), "u2.toml")).empty());
  const Scenario rankine =
      parse_scenario(bonded("young = 2e10\npoisson = 0.2\nradius = 0.08\ncriterion = \"rankine\"\nsigma_f = 1e6\n"), "k.toml");
  EXPECT_EQ(rankine.bond.params.criterion, physics::BondCriterion::rankine);
  EXPECT_TRUE(scenario_differences(rankine, parse_scenario(scenario_to_toml(rankine), "k2.toml")).empty());
  const std::string springs = bonded("young = 2e10\npoisson = 0.2\nradius = 0.08\nkbn = 1e9\n");
  EXPECT_SCENARIO_ERROR(springs, line_of_last(springs, "kbn"), "bond.kbn", "the beam law takes young");
  const std::string no_radius = bonded("young = 2e10\npoisson = 0.2\n");
  EXPECT_SCENARIO_ERROR(no_radius, line_of_last(no_radius, "[bond]"), "bond.radius", "missing");
  const std::string odd_nu = bonded("young = 2e10\npoisson = 0.7\nradius = 0.08\n");
  EXPECT_SCENARIO_ERROR(odd_nu, line_of_last(odd_nu, "poisson"), "bond.poisson", "0.5");
  const std::string stray = "[bond]\nkbn = 1e9\nkbs = 4e8\ntbn = 1\ntbs = 1\nyoung = 2e10\n";
  std::string plain = kDropTest;
  plain.replace(plain.find("duration = 0.5\n"), 15, "");
  plain += stray + "[[stage]]\nname = \"bond\"\nkind = \"bond\"\n";
  EXPECT_SCENARIO_ERROR(plain, line_of_last(plain, "young"), "bond.young", "belongs to law = \"beam\"");
}

TEST(Scenario, GrainStressCriteriaReadBackAndLeaveOutTheToughness) {
  const std::string base = kDropTest;
  const Scenario s = parse_scenario(base + "[fracture]\ncriterion = \"hydrostatic\"\nsigma_f = 3e6\n", "f.toml");
  EXPECT_EQ(s.fracture.params.criterion, physics::GrainCriterion::hydrostatic);
  EXPECT_EQ(s.fracture.params.sigma_f, 3e6);
  const Scenario again = parse_scenario(scenario_to_toml(s), "again.toml");
  EXPECT_TRUE(scenario_differences(s, again).empty());
  const std::string mixed = base + "[fracture]\ncriterion = \"rankine\"\nsigma_f = 3e6\nk_ic = 1e6\n";
  EXPECT_SCENARIO_ERROR(mixed, line_of_last(mixed, "k_ic"), "fracture.k_ic", "belongs to criterion = \"lefm\"");
  const std::string lefm = base + "[fracture]\nsigma_f_hyd = 0\nk_ic = 1e6\ncrack_length = 0.1\nsigma_f = 3e6\n";
  EXPECT_SCENARIO_ERROR(lefm, line_of_last(lefm, "sigma_f ="), "fracture.sigma_f", "applies only with criterion");
  const std::string none = base + "[fracture]\ncriterion = \"rankine\"\n";
  EXPECT_SCENARIO_ERROR(none, line_of_last(none, "[fracture]"), "fracture.sigma_f", "missing");
}

TEST(Scenario, FractureInertiaIsOnByDefaultReadsBackAndBelongsToTheLefmCriterion) {
  // The d'Alembert terms of eqs 3.8-3.19 are on unless the file says otherwise; the
  // manifest carries the choice, and a stress criterion (no crack section) refuses it.
  const std::string base =
      std::string(kDropTest) + "[fracture]\nsigma_f_hyd = 0\nk_ic = 1e6\ncrack_length = 0.1\n";
  EXPECT_TRUE(parse_scenario(base, "on.toml").fracture.params.inertia);
  const Scenario off = parse_scenario(base + "inertia = false\n", "off.toml");
  EXPECT_FALSE(off.fracture.params.inertia);
  const Scenario again = parse_scenario(scenario_to_toml(off), "again.toml");
  EXPECT_FALSE(again.fracture.params.inertia);
  EXPECT_TRUE(scenario_differences(off, again).empty());
  EXPECT_FALSE(scenario_differences(off, parse_scenario(base, "on.toml")).empty());
  const std::string stress = std::string(kDropTest) +
                             "[fracture]\ncriterion = \"rankine\"\nsigma_f = 3e6\ninertia = true\n";
  EXPECT_SCENARIO_ERROR(stress, line_of_last(stress, "inertia"), "fracture.inertia",
                        "belongs to criterion = \"lefm\"");
}

TEST(Scenario, PeriodicCellsAndCellStrainStagesReadBackAndBadValuesNameTheirKey) {
  const std::string voronoi = R"([specimen]
shape = "voronoi"
size = [1, 1, 0.5]
grains = 20
seed = 3
[material]
density = 3000
[contact]
dilation_radius = 0.01
[contact.particle_particle]
kn = 5.0
ks = 2.0
[contact.particle_wall]
kn = 5.0
[dynamics]
dt = 1e-6
gravity = [0, 0, 0]
)";
  auto with = [&](const std::string& periodic, const std::string& stage) {
    return voronoi + periodic + "[[stage]]\nname = \"pull\"\nsteps = 10\n" + stage;
  };
  const Scenario s = parse_scenario(with("[periodic]\naxes = [\"x\", \"z\"]\n",
                                         "cell_strain_rate = [2.5, 0, 0]\nmeasure_modulus = true\n"),
                                    "p.toml");
  EXPECT_TRUE(s.periodic.enabled);
  EXPECT_EQ(s.periodic.axes, (std::array<bool, 3>{true, false, true}));
  EXPECT_EQ(s.specimen.voronoi.periodic, s.periodic.axes);  // the cells tile the cell
  EXPECT_EQ(s.stages.at(0).cell_strain_rate, Eigen::Vector3d(2.5, 0, 0));
  EXPECT_TRUE(s.stages.at(0).measure_modulus);
  const Scenario again = parse_scenario(scenario_to_toml(s), "again.toml");
  EXPECT_TRUE(scenario_differences(s, again).empty());
  const Scenario controlled =
      parse_scenario(with("[periodic]\naxes = [\"x\"]\nstress_control_time = 1e-7\nstress_control_modulus = 4e11\n", ""),
                     "c.toml");
  EXPECT_EQ(controlled.periodic.stress_control_time, 1e-7);
  EXPECT_EQ(controlled.periodic.stress_control_modulus, 4e11);
  EXPECT_TRUE(scenario_differences(controlled, parse_scenario(scenario_to_toml(controlled), "c2.toml")).empty());
  // Errors, each at its key.
  const std::string half = with("[periodic]\naxes = [\"x\"]\nstress_control_time = 1e-7\n", "");
  EXPECT_SCENARIO_ERROR(half, line_of_last(half, "stress_control_time"), "periodic.stress_control_time",
                        "both stress_control_time (s) and stress_control_modulus (Pa)");
  const std::string negative =
      with("[periodic]\naxes = [\"x\"]\nstress_control_time = 1e-7\nstress_control_modulus = -4e11\n", "");
  EXPECT_SCENARIO_ERROR(negative, line_of_last(negative, "stress_control_modulus"), "periodic.stress_control_modulus", "");
  const std::string bad_axis = with("[periodic]\naxes = [\"x\", \"w\"]\n", "");
  EXPECT_SCENARIO_ERROR(bad_axis, line_of_last(bad_axis, "axes"), "periodic.axes", "element 2");
  const std::string twice = with("[periodic]\naxes = [\"y\", \"y\"]\n", "");
  EXPECT_SCENARIO_ERROR(twice, line_of_last(twice, "axes"), "periodic.axes", "named twice");
  const std::string empty = with("[periodic]\naxes = []\n", "");
  EXPECT_SCENARIO_ERROR(empty, line_of_last(empty, "axes"), "periodic.axes", "non-empty");
  const std::string not_periodic = with("[periodic]\naxes = [\"x\"]\n", "cell_strain_rate = [0, 1.0, 0]\n");
  EXPECT_SCENARIO_ERROR(not_periodic, line_of_last(not_periodic, "cell_strain_rate"), "stage[1].cell_strain_rate",
                        "not periodic along y");
  const std::string no_cell = with("", "cell_strain_rate = [1.0, 0, 0]\n");
  EXPECT_SCENARIO_ERROR(no_cell, line_of_last(no_cell, "cell_strain_rate"), "stage[1].cell_strain_rate", "[periodic]");
  const std::string two = with("[periodic]\naxes = [\"x\", \"z\"]\n", "cell_strain_rate = [1, 0, 1]\nmeasure_modulus = true\n");
  EXPECT_SCENARIO_ERROR(two, line_of_last(two, "measure_modulus"), "stage[1].measure_modulus", "exactly one axis");
  std::string lattice = kDropTest;
  lattice += "[periodic]\naxes = [\"x\"]\n";
  EXPECT_SCENARIO_ERROR(lattice, line_of_last(lattice, "axes"), "periodic.axes", "shape = \"voronoi\"");
}

}  // namespace cleave::io

// ---- values with their units ------------------------------------------------------------

namespace cleave::io {
namespace {

/// A bonded, staged scenario in metres whose every dimensional key is written with a unit.
const std::string kWithUnits = R"([scenario]
length_unit = "m"
[specimen]
shape = "box"
size = { value = [6.0, 6.0, 2.0], unit = "mm" }
[grain]
r = "0.6 mm"
t = "1 mm"
[material]
density = "3.1 g/cm^3"
[contact]
dilation_radius = "0.05 mm"
[contact.particle_particle]
kn = "5 N/m"
ks = "2 kN/m"
[contact.particle_wall]
kn = "10 N/m"
[dynamics]
dt = "15 us"
gravity = [0, 0, "-9.81 m/s^2"]
[[wall]]
kind = "plane"
name = "top"
point = ["0 mm", "6 mm", "0 mm"]
normal = [0, -1, 0]
velocity = ["0 mm/s", "-1 mm/s", "0 mm/s"]
[bond]
kbn = "6.4e8 N/m^3"
kbs = "2.5 GN/m^3"
tbn = "250 MPa"
tbs = "0.1 GPa"
[fracture]
k_ic = "3.1 MPa m^0.5"
sigma_f_hyd = "0 Pa"
crack_length = "100 um"
[thermal]
temperature = "1773 K"
alpha_a = "8.3e-6 1/K"
alpha_c = "9e-6 K^-1"
gradient = { value = [0, 2, 0], unit = "K/mm" }
[[stage]]
name = "bonding"
kind = "bond"
distance = "0.08 mm"
[[stage]]
name = "load"
wall_velocity = { top = { value = [0, -2, 0], unit = "mm/s" } }
time = "0.5 ms"
ramp_time = "100 us"
temperature_rate = "-60 K/min"
temperature_target = "293 K"
)";

TEST(ScenarioUnits, AValueWithItsUnitIsItsNumberTimesTheUnitInSI) {
  const Scenario s = parse_scenario(kWithUnits, "units.toml");
  // Exact where the product is: powers of ten on integers, and 0.6 x 1e-3 = 6e-4.
  EXPECT_EQ(s.specimen.r, 6e-4);
  EXPECT_EQ(s.specimen.t, 1e-3);
  EXPECT_EQ(s.specimen.outline.size, Eigen::Vector3d(6e-3, 6e-3, 2e-3));
  EXPECT_EQ(s.material.density, 3100.0);
  EXPECT_EQ(s.contact.dilation_radius, 5e-5);
  EXPECT_EQ(s.contact.particle_particle.kn, 5.0);
  EXPECT_EQ(s.contact.particle_particle.ks, 2000.0);
  EXPECT_EQ(s.contact.particle_wall.kn, 10.0);
  EXPECT_DOUBLE_EQ(s.dynamics.dt, 1.5e-5);  // 15 x 1e-6: within an ulp of 1.5e-5
  EXPECT_EQ(s.dynamics.gravity, Eigen::Vector3d(0, 0, -9.81));
  EXPECT_EQ(s.walls[0].origin, Eigen::Vector3d(0, 6e-3, 0));
  EXPECT_EQ(s.walls[0].velocity, Eigen::Vector3d(0, -1e-3, 0));
  EXPECT_EQ(s.bond.params.kbn, 6.4e8);
  EXPECT_EQ(s.bond.params.kbs, 2.5e9);
  EXPECT_EQ(s.bond.params.tbn, 2.5e8);
  EXPECT_EQ(s.bond.params.tbs, 1e8);
  EXPECT_EQ(s.fracture.params.k_ic, 3.1e6);
  EXPECT_DOUBLE_EQ(s.fracture.params.crack_length, 1e-4);
  EXPECT_EQ(s.thermal.temperature, 1773.0);
  EXPECT_EQ(s.thermal.alpha_a, 8.3e-6);
  EXPECT_DOUBLE_EQ(s.thermal.alpha_c, 9e-6);
  EXPECT_EQ(s.thermal.gradient, Eigen::Vector3d(0, 2000.0, 0));  // 2 K/mm = 2000 K/m
  ASSERT_EQ(s.stages.size(), 2u);
  EXPECT_DOUBLE_EQ(s.stages[0].bond_distance, 8e-5);
  EXPECT_EQ(s.stages[1].wall_velocity.at(0).second, Eigen::Vector3d(0, -2e-3, 0));
  EXPECT_DOUBLE_EQ(s.stages[1].time, 5e-4);
  EXPECT_DOUBLE_EQ(s.stages[1].ramp_time, 1e-4);
  EXPECT_DOUBLE_EQ(s.stages[1].temperature_rate, -1.0);  // -60 K/min
  EXPECT_EQ(s.stages[1].temperature_target, 293.0);
}

TEST(ScenarioUnits, AUnitDoesNotDependOnTheFilesLengthUnit) {
  // "0.6 mm" is 6e-4 m in a file of metres and in one of millimetres; a bare 0.6 is not.
  for (const char* unit : {"m", "mm", "um"}) {
    SCOPED_TRACE(unit);
    const std::string text =
        std::string("[scenario]\nlength_unit = \"") + unit +
        "\"\n[specimen]\nshape = \"box\"\nsize = [\"6 mm\", \"6 mm\", \"2 mm\"]\n"
        "[grain]\nr = \"0.6 mm\"\nt = \"1 mm\"\n";
    const Scenario s = parse_scenario(text, "u.toml");
    EXPECT_EQ(s.specimen.r, 6e-4);
    EXPECT_EQ(s.specimen.outline.size.x(), 6e-3);
  }
}

TEST(ScenarioUnits, AUnitOfAnotherDimensionIsAnErrorNamingFileLineAndKey) {
  const std::string bond = kBase + "[bond]\nkbn = 1\nkbs = 1\n";
  EXPECT_SCENARIO_ERROR(
      bond + "tbn = \"5 mm\"\ntbs = 1\n", 10, "bond.tbn",
      "'mm' is the unit of a length (m), but this key is a stress (Pa); accepted units: 'Pa'");
  EXPECT_SCENARIO_ERROR(bond + "tbn = \"5 psi\"\ntbs = 1\n", 10, "bond.tbn",
                        "unknown unit 'psi' for a stress (Pa); accepted units: 'Pa', 'kPa', 'MPa'");
  EXPECT_SCENARIO_ERROR(bond + "tbn = \"MPa\"\ntbs = 1\n", 10, "bond.tbn",
                        "expected a number and its unit, e.g. \"2.5 Pa\", found \"MPa\"");
  EXPECT_SCENARIO_ERROR(kBase + "[orientation]\nfamily_mix = \"0.5 mm\"\n", 8,
                        "orientation.family_mix", "is a plain number, without a unit");
  EXPECT_SCENARIO_ERROR(
      "[specimen]\nshape = \"box\"\nsize = [\"1 mm\", \"1 s\", \"1 mm\"]\n" + kGrain, 3,
      "specimen.size", "element 2: 's' is the unit of a time (s), but this key is a length (m)");
  EXPECT_SCENARIO_ERROR(
      "[specimen]\nshape = \"box\"\nsize = { value = [1, 1, 1], unit = \"Pa\" }\n" + kGrain, 3,
      "specimen.size", "element 1: 'Pa' is the unit of a stress (Pa), but this key is a length");
  EXPECT_SCENARIO_ERROR("[specimen]\nshape = \"disc\"\ndiameter = { value = \"5 mm\", unit = \"mm\" }\n"
                        "thickness = 5\n" + kGrain, 3, "specimen.diameter", "the unit is given once, as unit = \"mm\"");
  // The range is checked on the converted value and reported as written.
  EXPECT_SCENARIO_ERROR(
      "[specimen]\nshape = \"disc\"\ndiameter = \"-15 mm\"\nthickness = 5\n" + kGrain, 3,
      "specimen.diameter", "must be > 0, found \"-15 mm\"");
  EXPECT_SCENARIO_ERROR(
      kBase.substr(0, kBase.find("[grain]")) + "[grain]\nr = \"1 mm\"\nr_bar = \"1.5 mm\"\nt = 1\n",
      6, "grain.r_bar", "must not exceed grain.r = \"1 mm\", found \"1.5 mm\"");
}

TEST(ScenarioUnits, TheSameWorldFromMetresWithUnitsAndFromBareMillimetres) {
  // One drop test written twice: bare numbers in mm (the seeds' way) and in metres with a
  // unit on every length. Both build the same bodies and step the same, bit for bit; a
  // density off by 1 kg/m^3 does not, so the comparison sees the conversions.
  const std::string mm = R"([scenario]
length_unit = "mm"
[specimen]
shape = "box"
size = [6.0, 6.0, 2.0]
[grain]
r = 1.0
r_bar = 0.9
t = 1.0
t_bar = 0.85
[material]
density = 3100.0
[contact]
dilation_radius = 0.05
[contact.particle_particle]
kn = 5000.0
ks = 2000.0
mu_s = 0.3
[contact.particle_wall]
kn = 10000.0
ks = 2000.0
[dynamics]
dt = 1.2e-6
duration = 0.1
gravity = [0.0, 0.0, -9.81]
lift = 0.02
[[wall]]
name = "floor"
kind = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
velocity = [0.0, 0.0, 30.0]
)";
  std::string si = mm;
  const auto set = [&](const std::string& from, const std::string& to) {
    ASSERT_NE(si.find(from), std::string::npos) << from;
    si.replace(si.find(from), from.size(), to);
  };
  set("length_unit = \"mm\"", "length_unit = \"m\"");
  set("size = [6.0, 6.0, 2.0]", "size = { value = [6.0, 6.0, 2.0], unit = \"mm\" }");
  set("r = 1.0", "r = \"1 mm\"");
  set("r_bar = 0.9", "r_bar = \"0.9 mm\"");
  set("t = 1.0", "t = \"1.0 mm\"");
  set("t_bar = 0.85", "t_bar = \"0.85 mm\"");
  set("density = 3100.0", "density = \"3.1 g/cm^3\"");
  set("dilation_radius = 0.05", "dilation_radius = \"0.05 mm\"");
  set("kn = 5000.0", "kn = \"5 kN/m\"");
  set("dt = 1.2e-6", "dt = \"1.2e-6 s\"");
  set("lift = 0.02", "lift = \"20 um\"");
  set("velocity = [0.0, 0.0, 30.0]", "velocity = [\"0 mm/s\", \"0 mm/s\", \"30 mm/s\"]");
  const auto hash_after = [](const std::string& text, int steps) {
    const Scenario s = parse_scenario(text, "w.toml");
    physics::World world = sim::make_world(s, geometry::build_specimen(s.specimen));
    for (int i = 0; i < steps; ++i) world.step();
    return std::pair(world.body_count(), world.state_hash());
  };
  const auto a = hash_after(mm, 300), b = hash_after(si, 300);
  EXPECT_GT(a.first, 10u);
  EXPECT_EQ(a, b);
  std::string heavier = si;
  heavier.replace(heavier.find("\"3.1 g/cm^3\""), 12, "\"3101 kg/m^3\"");
  EXPECT_NE(hash_after(heavier, 300), a);
}

}  // namespace
}  // namespace cleave::io

namespace cleave::io {
namespace {

TEST(ScenarioUnits, TheFormatReferenceNamesEveryDimensionalKeysUnits) {
  // docs/SCENARIO_FORMAT.md#units lists each key in the row of its dimension, whose units
  // are the reader's, the SI one first.
  std::ifstream in(std::string(CLEAVE_SOURCE_DIR) + "/docs/SCENARIO_FORMAT.md");
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("| ", 0) == 0) rows.push_back(line);
  for (const KeyDimension& k : scenario_key_dimensions()) {
    SCOPED_TRACE(std::string(k.key));
    const auto row = std::find_if(rows.begin(), rows.end(), [&](const std::string& r) {
      return r.find("`" + std::string(k.key) + "`") != std::string::npos &&
             r.find(" | ") != std::string::npos &&
             r.find("`" + std::string(units_of(k.dimension).front().name) + "`") !=
                 std::string::npos;
    });
    ASSERT_NE(row, rows.end()) << "no row names the key with its SI unit";
    std::string units;
    for (const UnitSpec& u : units_of(k.dimension))
      units += (units.empty() ? "`" : ", `") + std::string(u.name) + "`";
    EXPECT_NE(row->find(units), std::string::npos) << *row << "\n  lacks: " << units;
  }
}

}  // namespace
}  // namespace cleave::io
