// The material library (materials/*.toml, io/material_library.hpp): every preset reads back
// in SI with the unit it was written in and a cited source; a missing, negative or unitless
// property is an error naming the file, line and key; a scenario's preset gives its density.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "io/material_library.hpp"
#include "io/scenario.hpp"

namespace fs = std::filesystem;
using cleave::io::MaterialPreset;
using cleave::io::ScenarioError;

namespace {

const fs::path kLibrary = fs::path(CLEAVE_SOURCE_DIR) / "materials";

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The size of each unit in SI, written out here apart from the library's own table.
const std::map<std::string, double> kUnitSize = {
    {"kg/m^3", 1.0}, {"g/cm^3", 1000.0}, {"Pa", 1.0},       {"kPa", 1e3},
    {"MPa", 1e6},    {"GPa", 1e9},       {"Pa m^0.5", 1.0}, {"MPa m^0.5", 1e6},
    {"m", 1.0},      {"mm", 1e-3},       {"um", 1e-6},      {"1", 1.0}};

/// The SI range a real ceramic or glass lies in: a unit slip (GPa written as MPa, um as mm)
/// lands outside by a factor of 1000.
const std::map<std::string, std::pair<double, double>> kPlausible = {
    {"density", {1.5e3, 8e3}},          {"young", {30e9, 800e9}},
    {"poisson", {0.05, 0.35}},          {"tensile_strength", {10e6, 2e9}},
    {"flexural_strength", {20e6, 3e9}}, {"k_ic", {0.3e6, 15e6}},
    {"grain_size", {0.1e-6, 200e-6}},   {"cleavage_k_ic", {0.3e6, 10e6}},
    {"weibull_modulus", {3.0, 40.0}}};

const std::string kGood = R"([material]
name = "test_ceramic"
description = "a made-up ceramic"

[properties]
density = { value = 3.0, unit = "g/cm^3", source = "a" }
young = { value = 300, unit = "GPa", source = "a" }
poisson = { value = 0.2, unit = "1", source = "a" }
tensile_strength = { value = 200, unit = "MPa", source = "b" }
flexural_strength = { value = 300, unit = "MPa", source = "b", note = "four-point" }
k_ic = { value = 3.5, unit = "MPa m^0.5", source = "b" }
grain_size = { value = 5, unit = "um", source = "a" }

[sources]
a = "Handbook A"
b = "Paper B"
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

std::string error_of(const std::string& text) {
  try {
    cleave::io::parse_material(text, "m.toml");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(MaterialLibrary, EveryPresetReadsBackInSiWithTheUnitItWasWrittenInAndASource) {
  int presets = 0;
  for (const auto& entry : fs::directory_iterator(kLibrary)) {
    if (entry.path().extension() != ".toml") continue;
    ++presets;
    SCOPED_TRACE(entry.path().string());
    const MaterialPreset m = cleave::io::load_material(entry.path());
    EXPECT_EQ(m.name, entry.path().stem().string()) << "the name a scenario's preset gives";
    std::istringstream lines(read_text(entry.path()));
    std::vector<std::string> line_text;
    for (std::string l; std::getline(lines, l);) line_text.push_back(l);
    for (const char* key : {"density", "young", "poisson", "tensile_strength",
                            "flexural_strength", "k_ic"}) {
      EXPECT_NE(m.find(key), nullptr) << key;
    }
    if (!m.amorphous) {
      EXPECT_NE(m.find("grain_size"), nullptr);
    }
    for (const auto& p : m.properties) {
      SCOPED_TRACE(p.key);
      ASSERT_TRUE(kUnitSize.count(p.unit)) << p.unit;
      EXPECT_DOUBLE_EQ(p.value, p.written * kUnitSize.at(p.unit));
      const auto [lo, hi] = kPlausible.at(p.key);
      EXPECT_GE(p.value, lo);
      EXPECT_LE(p.value, hi);
      EXPECT_FALSE(p.citation.empty());
      // The line it names holds the key, its number and its unit.
      ASSERT_GE(p.line, 1);
      ASSERT_LE(p.line, static_cast<int>(line_text.size()));
      const std::string& l = line_text[static_cast<std::size_t>(p.line - 1)];
      EXPECT_EQ(l.rfind(p.key + " ", 0), 0u) << l;
      EXPECT_NE(l.find("unit = \"" + p.unit + "\""), std::string::npos) << l;
      const std::regex number(R"(value = ([-+0-9.eE]+))");
      std::smatch match;
      ASSERT_TRUE(std::regex_search(l, match, number)) << l;
      EXPECT_DOUBLE_EQ(std::stod(match[1]), p.written);
    }
  }
  EXPECT_GE(presets, 3) << "alpha-SiC, alumina and a soda-lime glass at least";
  for (const char* name : {"sic_alpha", "alumina", "soda_lime_glass"}) {
    EXPECT_TRUE(fs::exists(kLibrary / (std::string(name) + ".toml"))) << name;
  }
}

TEST(MaterialLibrary, AGoodFileReadsInSi) {
  const MaterialPreset m = cleave::io::parse_material(kGood, "m.toml");
  EXPECT_DOUBLE_EQ(m.si("density"), 3000.0);
  EXPECT_DOUBLE_EQ(m.si("young"), 300e9);
  EXPECT_DOUBLE_EQ(m.si("k_ic"), 3.5e6);
  EXPECT_DOUBLE_EQ(m.si("grain_size"), 5e-6);
  EXPECT_EQ(m.find("flexural_strength")->note, "four-point");
  EXPECT_EQ(m.find("tensile_strength")->citation, "Paper B");
  EXPECT_EQ(m.find("weibull_modulus"), nullptr);
  EXPECT_THROW((void)m.si("weibull_modulus"), std::out_of_range);
}

TEST(MaterialLibrary, AMissingPropertyIsAnErrorAtItsTableNamingTheKey) {
  const std::string text = replaced(kGood, "young = { value = 300, unit = \"GPa\", source = \"a\" }\n", "");
  EXPECT_EQ(error_of(text),
            "m.toml:5:1: key 'properties.young': missing required property (Young's modulus E)");
}

TEST(MaterialLibrary, ANegativeOrZeroPropertyIsAnErrorAtItsLine) {
  EXPECT_EQ(error_of(replaced(kGood, "value = 300, unit = \"GPa\"", "value = -300, unit = \"GPa\"")),
            "m.toml:7:19: key 'properties.young.value': must be > 0, found -300");
  EXPECT_EQ(error_of(replaced(kGood, "value = 3.5,", "value = 0,")),
            "m.toml:11:18: key 'properties.k_ic.value': must be > 0, found 0");
  EXPECT_EQ(error_of(replaced(kGood, "value = 0.2,", "value = 0.5,")),
            "m.toml:8:21: key 'properties.poisson.value': must be in [0, 0.5), found 0.5");
}

TEST(MaterialLibrary, AnUnknownOrMissingUnitIsAnErrorListingTheAcceptedOnes) {
  EXPECT_EQ(error_of(replaced(kGood, "unit = \"GPa\"", "unit = \"psi\"")),
            "m.toml:7:31: key 'properties.young.unit': unknown unit 'psi' for Young's modulus E; "
            "accepted: 'Pa', 'kPa', 'MPa', 'GPa', 'N/m^2', 'N/mm^2'");
  EXPECT_EQ(error_of(replaced(kGood, "value = 5, unit = \"um\",", "value = 5,")),
            "m.toml:12:14: key 'properties.grain_size.unit': missing required key");
}

TEST(MaterialLibrary, ASourceMustBeCitedAndEveryCitationUsed) {
  EXPECT_EQ(error_of(replaced(kGood, "source = \"b\" }\nflexural", "source = \"c\" }\nflexural")),
            "m.toml:9:58: key 'properties.tensile_strength.source': source 'c' is not in "
            "[sources]; give its citation there as c = \"Author, title, journal, year\"");
  EXPECT_EQ(error_of(kGood + "c = \"Unused\"\n"),
            "m.toml:17:1: key 'sources.c': no property names this source");
}

TEST(MaterialLibrary, AnAmorphousMaterialHasNoGrainSize) {
  const std::string glass = replaced(kGood, "description = \"a made-up ceramic\"",
                                     "description = \"a glass\"\nstructure = \"amorphous\"");
  EXPECT_EQ(error_of(glass),
            "m.toml:13:14: key 'properties.grain_size': an amorphous material has no grains; "
            "leave it out or set [material] structure = \"polycrystal\"");
  const std::string no_grain =
      replaced(glass, "grain_size = { value = 5, unit = \"um\", source = \"a\" }\n", "");
  EXPECT_TRUE(cleave::io::parse_material(no_grain, "m.toml").amorphous);
}

TEST(MaterialLibrary, AScenarioPresetGivesItsDensityUnlessTheScenarioGivesOne) {
  const std::string base = R"([specimen]
shape = "box"
size = [2.0, 2.0, 1.0]
[grain]
r = 0.5
t = 1.0
)";
  const fs::path at = kLibrary / "scenario.toml";  // a bare name looks in the library
  const auto sic = cleave::io::parse_scenario(base + "[material]\npreset = \"sic_alpha\"\n",
                                              at.string());
  const MaterialPreset m = cleave::io::load_material(kLibrary / "sic_alpha.toml");
  EXPECT_DOUBLE_EQ(sic.material.density, m.si("density"));
  EXPECT_EQ(fs::path(sic.material.preset_file), kLibrary / "sic_alpha.toml");
  const auto lighter = cleave::io::parse_scenario(
      base + "[material]\npreset = \"sic_alpha\"\ndensity = 3000.0\n", at.string());
  EXPECT_DOUBLE_EQ(lighter.material.density, 3000.0);
  try {
    (void)cleave::io::parse_scenario(base + "[material]\npreset = \"unobtainium\"\n", "s.toml");
    FAIL() << "an unknown preset was accepted";
  } catch (const ScenarioError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("s.toml:8:10: key 'material.preset': no material 'unobtainium'", 0), 0u)
        << what;
    EXPECT_NE(what.find("'sic_alpha'"), std::string::npos) << what;
  }
}
