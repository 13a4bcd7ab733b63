#include "io/validation_scenario.hpp"

#include <fstream>
#include <sstream>

#include "io/budget.hpp"
#include "io/result_dir.hpp"
#include "io/toml_reader.hpp"

namespace cleave::io {

namespace {

using namespace toml_reader;

constexpr std::string_view kTables[] = {"scenario", "specimen", "material",
                                        "loading",  "dynamics", "validation"};
constexpr std::string_view kRequired[] = {"specimen", "material", "loading", "validation"};

constexpr std::string_view kScenarioKeys[] = {"name", "description", "length_unit"};
constexpr std::string_view kSpecimenKeys[] = {"test",          "length",          "breadth",
                                              "height",        "initial_crack",   "particle_radius",
                                              "mode_mix",      "bending_springs", "effective_areas",
                                              "intact_length"};
constexpr std::string_view kMaterialKeys[] = {
    "young", "poisson", "density", "cohesive_strength", "fracture_energy",
    "g_Ic",  "g_IIc",   "contact_penalty", "friction", "initiation", "compression"};
constexpr std::string_view kLoadingKeys[] = {"velocity", "ramp_time", "deflection"};
constexpr std::string_view kDynamicsKeys[] = {"dt_safety", "global_damping", "threads",
                                              "records"};
constexpr std::string_view kValidationKeys[] = {
    "reference", "stage1", "stage2", "stage3", "stage4", "stages",
    "tolerance", "measure", "peak_tolerance", "margin"};
constexpr std::string_view kStageCheckKeys[] = {"mean", "max", "slope"};

void read_specimen(const TableReader& t, double unit, ValidationScenario& v) {
  t.reject_unknown(kSpecimenKeys);
  physics::BeamRigDef& rig = v.rig;
  rig.kind = t.choose<physics::BeamTestKind>("test", {{"dcb", physics::BeamTestKind::dcb},
                                                      {"enf", physics::BeamTestKind::enf},
                                                      {"mmb", physics::BeamTestKind::mmb}});
  rig.length = t.number("length", Range::positive()).value;
  rig.breadth = t.number("breadth", Range::positive()).value;
  rig.height = t.number("height", Range::positive()).value;
  const Number a0 = t.number("initial_crack", Range::positive());
  rig.initial_crack = a0.value;
  rig.radius = t.number("particle_radius", Range::positive()).value;
  // Each extent must hold a whole number of cubes of side 2r, and the lattice must fit in
  // memory (a body and its links take about 1 kB).
  constexpr double kMaxCells = 1e5, kMaxBodies = 5e7;
  double bodies = 1.0;
  for (std::string_view key : {"length", "breadth", "height"}) {
    const double extent = t.number(key, Range::positive()).value;
    const double count = extent / (2.0 * rig.radius);
    if (!(count <= kMaxCells))
      t.fail(*t.find(key), key,
             fmt::format("holds {:.3g} particle diameters 2r; at most {:g} are supported", count,
                         kMaxCells));
    if (std::abs(count - std::round(count)) > 1e-6 * count || std::round(count) < 1.0) {
      t.fail(*t.find(key), key,
             fmt::format("must be a whole number of particle diameters 2r = {} {}", 2.0 * rig.radius / unit,
                         unit == 1e-3 ? "mm" : "length units"));
    }
    bodies *= std::round(count);
    if (bodies > kMaxBodies)
      t.fail(*t.find(key), key,
             fmt::format("the lattice would hold {:.3g} bodies; at most {:g} are supported", bodies,
                         kMaxBodies));
  }
  const double layers = std::round(rig.height / (2.0 * rig.radius));
  if (static_cast<long>(layers) % 2 != 0)
    t.fail(*t.find("height"), "height",
           "must hold an even number of particle layers (the weak plane lies between the halves)");
  if (rig.kind != physics::BeamTestKind::dcb &&
      static_cast<long>(std::round(rig.length / (2.0 * rig.radius))) % 2 == 0)
    t.fail(*t.find("length"), "length",
           "ENF and MMB need an odd number of particles along the length (one at mid-span)");
  const double reach = rig.kind == physics::BeamTestKind::dcb ? rig.length : 0.5 * rig.length;
  if (rig.initial_crack >= reach - 2.0 * rig.radius)
    t.fail(*a0.node, "initial_crack",
           rig.kind == physics::BeamTestKind::dcb ? "must be shorter than the beam"
                                                  : "must end before mid-span");
  if (const toml::node* node = t.find("intact_length")) {
    if (rig.kind != physics::BeamTestKind::dcb)
      t.fail(*node, "intact_length", "only a DCB has an intact length beyond the weak plane");
    rig.intact_length = t.number("intact_length", Range::non_negative()).value;
    const double count = rig.intact_length / (2.0 * rig.radius);
    if (!(count <= kMaxCells) || std::abs(count - std::round(count)) > 1e-6 * std::max(count, 1.0))
      t.fail(*node, "intact_length",
             fmt::format("must be a whole number of particle diameters 2r = {} {} (at most {:g})",
                         2.0 * rig.radius / unit, unit == 1e-3 ? "mm" : "length units", kMaxCells));
    if (bodies / std::round(rig.length / (2.0 * rig.radius)) *
            std::round((rig.length + rig.intact_length) / (2.0 * rig.radius)) > kMaxBodies)
      t.fail(*node, "intact_length",
             fmt::format("the lattice would hold more than {:g} bodies", kMaxBodies));
  }
  // The memory the lattice takes, checked before it is built (io/budget.hpp).
  const double total = bodies / std::round(rig.length / (2.0 * rig.radius)) *
                       std::round((rig.length + rig.intact_length) / (2.0 * rig.radius));
  if (const MemoryLimit limit = memory_limit();
      limit.bytes > 0 && cubic_lattice_bytes(total) > static_cast<double>(limit.bytes))
    t.fail(
        *t.find("particle_radius"), "particle_radius",
        fmt::format(
            "specimen.length, breadth and height (and intact_length) in cubes of 2 particle_radius "
            "make {:.3g} bodies, which need about {} with their links, more than the limit of {} "
            "({}); use larger particles or a smaller specimen",
            total, format_bytes(cubic_lattice_bytes(total)),
            format_bytes(static_cast<double>(limit.bytes)), limit.what));
  rig.link_bending = t.number("bending_springs", Range::non_negative(), 1.0).value;
  rig.tiled_areas = t.choose<bool>("effective_areas", {{"tiled", true}, {"paper", false}}, true);
  if (rig.kind == physics::BeamTestKind::mmb) {
    rig.mode_mix = t.number("mode_mix", Range{0.0, 1.0, true, true}).value;
  } else if (const toml::node* node = t.find("mode_mix")) {
    t.fail(*node, "mode_mix", "only an MMB test has a mode mix");
  }
}

void read_material(const TableReader& t, ValidationScenario& v) {
  t.reject_unknown(kMaterialKeys);
  physics::LatticeMaterial& m = v.rig.material;
  m.young = t.number("young", Range::positive()).value;
  m.poisson = t.number("poisson", Range{0.0, 0.25, false, true}).value;
  m.density = t.number("density", Range::positive()).value;
  m.sigma_c = t.number("cohesive_strength", Range::positive()).value;
  m.g_c = t.number("fracture_energy", Range::positive()).value;
  v.rig.g_Ic = t.number("g_Ic", Range::positive(), m.g_c).value;
  v.rig.g_IIc = t.number("g_IIc", Range::positive(), m.g_c).value;
  m.kappa = t.number("contact_penalty", Range::positive(), 1.0).value;
  m.friction = t.number("friction", Range::non_negative(), 0.0).value;
  m.initiation = t.choose<physics::Initiation>(
      "initiation",
      {{"displacement", physics::Initiation::displacement},
       {"traction", physics::Initiation::traction}},
      physics::Initiation::displacement);
  m.compression = t.choose<physics::Compression>(
      "compression",
      {{"plane", physics::Compression::plane}, {"link", physics::Compression::link}},
      physics::Compression::plane);
}

void read_loading(const TableReader& t, double unit, ValidationScenario& v) {
  t.reject_unknown(kLoadingKeys);
  v.rig.velocity = t.number("velocity", Range::positive()).value;
  v.rig.ramp_time = t.number("ramp_time", Range::non_negative()).value;
  v.deflection = t.number("deflection", Range::positive()).value;
}

void read_dynamics(const TableReader& t, ValidationScenario& v) {
  t.reject_unknown(kDynamicsKeys);
  v.rig.dt_safety = t.number("dt_safety", Range{0.0, 1.0, true, false}, 0.9).value;
  v.rig.global_damping = t.number("global_damping", Range::non_negative(), 0.0).value;
  v.threads = t.int_integer("threads", 0, 0);
  v.records = t.int_integer("records", 2, 400);
}

void read_validation(const TableReader& t, ValidationScenario& v) {
  t.reject_unknown(kValidationKeys);
  v.reference = t.choose<Reference>(
      "reference", {{"lefm", Reference::lefm}, {"cohesive_beam", Reference::cohesive_beam}},
      Reference::lefm);
  const int last = v.rig.kind == physics::BeamTestKind::enf ? 4 : 3;
  const int split = physics::split_stage(v.rig.kind);
  const toml::node* short_form = t.find("stages");
  for (int stage = 1; stage <= 4; ++stage) {
    const std::string key = fmt::format("stage{}", stage);
    const toml::node* node = t.find(key);
    if (node == nullptr) continue;
    if (short_form != nullptr)
      t.fail(*node, key, "give the stages either as stage1 ... stage4 tables or as stages = [...], not both");
    if (stage > last) t.fail(*node, key, fmt::format("this test has stages 1-{}", last));
    const auto* table = node->as_table();
    if (table == nullptr)
      t.fail(*node, key,
             fmt::format("expected a table of bounds, e.g. {} = {{ mean = 0.05, max = 0.08 }}", key));
    const TableReader c(t.source(), t.name() + "." + key, table);
    c.reject_unknown(kStageCheckKeys);
    StageCheck check;
    check.stage = stage;
    check.mean = c.number("mean", Range::positive(), 0.0).value;
    check.max = c.number("max", Range::positive(), 0.0).value;
    if (const toml::node* slope = c.find("slope")) {
      if (stage != split)
        c.fail(*slope, "slope",
               split > 0 ? fmt::format("only the split beam's stage ({}) has a slope to check", split)
                         : std::string("this test has no split beam's stage with a slope"));
      check.slope = c.number("slope", Range::positive()).value;
    }
    if (check.mean == 0.0 && check.max == 0.0 && check.slope == 0.0)
      t.fail(*node, key, "bounds nothing: give mean, max or slope");
    v.checks.push_back(check);
  }
  if (short_form != nullptr) {
    const auto* array = short_form->as_array();
    if (array == nullptr || array->empty())
      t.fail(*short_form, "stages", "expected a non-empty array of stage numbers (1-4)");
    const double tolerance = t.number("tolerance", Range::positive()).value;
    bool mean = false;
    if (t.find("measure") != nullptr) mean = t.choose<bool>("measure", {{"max", false}, {"mean", true}});
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::node& e = *array->get(i);
      const auto* n = e.as_integer();
      if (n == nullptr || n->get() < 1 || n->get() > last)
        t.fail(e, "stages", fmt::format("element {}: expected a stage number 1-{}", i + 1, last));
      StageCheck check;
      check.stage = static_cast<int>(n->get());
      // The split beam's stage is judged by its slope, the others by their loads.
      if (check.stage == split) check.slope = tolerance;
      else if (mean) check.mean = tolerance;
      else check.max = tolerance;
      v.checks.push_back(check);
    }
  } else {
    for (std::string_view key : {"tolerance", "measure"})
      if (const toml::node* node = t.find(key))
        t.fail(*node, key, "belongs to the short form stages = [...]; with stage1 ... stage4 "
                           "tables give each stage's bounds there");
    if (v.checks.empty())
      t.fail_absent("stage1", "missing: the stages to check (stage1 = { max = 0.05 }, ... or stages = [...])");
  }
  v.peak_tolerance = t.number("peak_tolerance", Range::positive(), 0.0).value;
  v.margin = t.number("margin", Range{0.0, 0.5, false, true}, 0.1).value;
}

}  // namespace

ValidationScenario parse_validation_scenario(const std::string& text, const std::string& source) {
  const toml::table root = parse_root(text, source, kTables, "a validation scenario");
  for (std::string_view name : kTables) {
    const toml::node* node = root.get(name);
    if (node != nullptr && !node->is_table())
      throw ScenarioError(source, line_of(node->source()), column_of(node->source()),
                          std::string(name),
                          fmt::format("expected a table, found {}", type_name(*node)));
    if (node == nullptr && contains(kRequired, name))
      throw ScenarioError(source, 1, 1, std::string(name),
                          fmt::format("missing required table [{}]", name));
  }
  // Numbers in SI (validation_key_dimensions): bare lengths in the length unit.
  UnitContext units{validation_key_dimensions(), 1e-3};
  const auto reader = [&](std::string_view name) {
    return TableReader(source, std::string(name), root.get_as<toml::table>(name), &units);
  };
  ValidationScenario v;
  v.source = source;
  double unit = 1e-3;
  {
    const TableReader t = reader("scenario");
    t.reject_unknown(kScenarioKeys);
    v.name = t.string("name", std::filesystem::path(source).stem().string());
    if (t.find("name") != nullptr && !is_plain_folder_name(v.name)) {
      t.fail(*t.find("name"), "name",
             "'" + v.name + "' must be a plain folder name (no '/', '\\' or leading '.'): it names results/NAME");
    }
    v.description = t.string("description", "");
    unit = t.choose<double>("length_unit", {{"m", 1.0}, {"mm", 1e-3}, {"um", 1e-6}}, 1e-3);
  }
  units.length_unit = unit;
  read_specimen(reader("specimen"), unit, v);
  read_material(reader("material"), v);
  read_loading(reader("loading"), unit, v);
  read_dynamics(reader("dynamics"), v);
  read_validation(reader("validation"), v);
  return v;
}

ValidationScenario load_validation_scenario(const std::filesystem::path& file) {
  return parse_validation_scenario(read_scenario_text(file), file.string());
}

namespace {

/// A double as TOML that reads back exactly (shortest round-trip form, always a float).
std::string toml_number(double x) {
  std::string s = fmt::format("{}", x);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::string validation_scenario_as_run(const ValidationScenario& v) {
  const physics::BeamRigDef& r = v.rig;
  const physics::LatticeMaterial& m = r.material;
  const char* test = r.kind == physics::BeamTestKind::dcb   ? "dcb"
                     : r.kind == physics::BeamTestKind::enf ? "enf"
                                                            : "mmb";
  std::string out = "# The validation scenario as cleave ran it: every key, defaults filled in, SI.\n";
  out += fmt::format("[scenario]\nname = {}\ndescription = {}\nlength_unit = \"m\"\n\n",
                     toml_string(v.name), toml_string(v.description));
  out += fmt::format(
      "[specimen]\ntest = \"{}\"\nlength = {}\nbreadth = {}\nheight = {}\ninitial_crack = {}\n"
      "particle_radius = {}\nbending_springs = {}\neffective_areas = \"{}\"\n",
      test, toml_number(r.length), toml_number(r.breadth), toml_number(r.height),
      toml_number(r.initial_crack), toml_number(r.radius), toml_number(r.link_bending),
      r.tiled_areas ? "tiled" : "paper");
  if (r.kind == physics::BeamTestKind::mmb) out += fmt::format("mode_mix = {}\n", toml_number(r.mode_mix));
  if (r.kind == physics::BeamTestKind::dcb)
    out += fmt::format("intact_length = {}\n", toml_number(r.intact_length));
  out += fmt::format(
      "\n[material]\nyoung = {}\npoisson = {}\ndensity = {}\ncohesive_strength = {}\n"
      "fracture_energy = {}\ng_Ic = {}\ng_IIc = {}\ncontact_penalty = {}\nfriction = {}\n"
      "initiation = \"{}\"\ncompression = \"{}\"\n",
      toml_number(m.young), toml_number(m.poisson), toml_number(m.density), toml_number(m.sigma_c),
      toml_number(m.g_c), toml_number(r.g_Ic), toml_number(r.g_IIc), toml_number(m.kappa),
      toml_number(m.friction),
      m.initiation == physics::Initiation::traction ? "traction" : "displacement",
      m.compression == physics::Compression::plane ? "plane" : "link");
  out += fmt::format("\n[loading]\nvelocity = {}\nramp_time = {}\ndeflection = {}\n",
                     toml_number(r.velocity), toml_number(r.ramp_time), toml_number(v.deflection));
  out += fmt::format(
      "\n[dynamics]\ndt_safety = {}\nglobal_damping = {}\nthreads = {}\nrecords = {}\n",
      toml_number(r.dt_safety), toml_number(r.global_damping), v.threads, v.records);
  out += fmt::format("\n[validation]\nreference = \"{}\"\nmargin = {}\n",
                     v.reference == Reference::lefm ? "lefm" : "cohesive_beam", toml_number(v.margin));
  if (v.peak_tolerance > 0.0) out += fmt::format("peak_tolerance = {}\n", toml_number(v.peak_tolerance));
  for (const StageCheck& c : v.checks) {
    std::string bounds;
    for (auto [key, value] : {std::pair{"mean", c.mean}, {"max", c.max}, {"slope", c.slope}})
      if (value > 0.0) bounds += fmt::format("{}{} = {}", bounds.empty() ? "" : ", ", key, toml_number(value));
    out += fmt::format("stage{} = {{ {} }}\n", c.stage, bounds);
  }
  return out;
}

}  // namespace cleave::io
