#include "io/scenario_writer.hpp"
#include "io/toml_text.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <filesystem>

namespace cleave::io {

namespace {

/// A double as a TOML float with the shortest digits that read back the same value.
std::string num(double x) {
  std::string s = fmt::format("{}", x);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // "3100" -> "3100.0"
  return s;
}

/// A TOML basic string (io/toml_text.hpp).
std::string str(const std::string& s) { return toml_basic_string(s); }

std::string vec(const Eigen::Vector3d& v) {
  return fmt::format("[{}, {}, {}]", num(v.x()), num(v.y()), num(v.z()));
}

std::string boolean(bool b) { return b ? "true" : "false"; }

const char* outline_name(geometry::Outline::Kind k) {
  switch (k) {
    case geometry::Outline::Kind::box: return "box";
    case geometry::Outline::Kind::disc: return "disc";
    case geometry::Outline::Kind::beam: return "beam";
  }
  return "?";
}

const char* wall_kind(physics::Wall::Kind k) {
  switch (k) {
    case physics::Wall::Kind::plane: return "plane";
    case physics::Wall::Kind::platen: return "platen";
    case physics::Wall::Kind::cylinder: return "cylinder";
  }
  return "?";
}

/// The key/value lines of one contact parameter set.
void contact_params(std::string& out, const char* table, const physics::ContactParams& p) {
  out += fmt::format("\n[contact.{}]\nkn = {}\nks = {}\nkr = {}\nkt = {}\nc_res = {}\nmu_s = {}\n"
                     "mu_r = {}\ndamping = {}\n",
                     table, num(p.kn), num(p.ks), num(p.kr), num(p.kt), num(p.c_res), num(p.mu_s),
                     num(p.mu_r), num(p.damping_ratio));
}

}  // namespace

std::string scenario_to_toml(const Scenario& s) {
  std::string out =
      "# The scenario as run by cleave: every default filled in, lengths in metres.\n"
      "# `cleave run` reads it as it is.\n";
  out += fmt::format("\n[scenario]\nname = {}\ndescription = {}\nlength_unit = \"m\"\n",
                     str(s.name), str(s.description));

  const geometry::SpecimenDef& d = s.specimen;
  const geometry::Outline& o = d.outline;
  if (d.kind == geometry::SpecimenKind::voronoi) {
    const std::string domain =
        d.voronoi.domain == geometry::VoronoiDomain::disc
            ? fmt::format("domain = \"disc\"\ndiameter = {}\nthickness = {}\nsides = {}\n",
                          num(d.voronoi.size.x()), num(d.voronoi.size.z()), d.voronoi.sides)
            : fmt::format("size = {}\n", vec(d.voronoi.size));
    if (d.voronoi.lognormal) {
      out += fmt::format(
          "\n[specimen]\nshape = \"voronoi\"\n{}grains = {}\nseed = {}\nsizes = "
          "\"lognormal\"\nsize_spread = {}\ngap = {}\n",
          domain, d.voronoi.cells, d.voronoi.seed, num(d.voronoi.size_spread), num(d.voronoi.gap));
    } else {
      out += fmt::format("\n[specimen]\nshape = \"voronoi\"\n{}grains = {}\ngap = {}\nseed = {}\n",
                         domain, d.voronoi.cells, num(d.voronoi.gap), d.voronoi.seed);
    }
  } else if (d.kind == geometry::SpecimenKind::meshes && s.tessellation) {
    const TessellationFileSpec& t = *s.tessellation;
    out += fmt::format("\n[specimen]\nshape = {}\nfile = {}\nscale = {}\n", str(t.shape),
                       str(t.file.string()), num(t.scale));
    if (t.shape == "grain_file") out += fmt::format("size = {}\n", vec(d.outline.size));
  } else if (d.kind == geometry::SpecimenKind::meshes) {
    out += "\n[specimen]\nshape = \"mesh\"\n";
    for (const MeshGrainSpec& m : s.mesh_grains) {
      out += fmt::format("\n[[mesh_grain]]\nfile = {}\nscale = {}\nposition = {}\nconvex_hull = {}\n",
                         str(m.file.string()), num(m.scale), vec(m.offset), boolean(m.convex_hull));
    }
  } else {
    out += fmt::format("\n[specimen]\nshape = \"{}\"\n", outline_name(o.kind));
    switch (o.kind) {
      case geometry::Outline::Kind::box:
        out += fmt::format("size = {}\n", vec(o.size));
        break;
      case geometry::Outline::Kind::disc:
        out += fmt::format("diameter = {}\nthickness = {}\n", num(o.size.x()), num(o.size.z()));
        break;
      case geometry::Outline::Kind::beam:
        out += fmt::format(
            "length = {}\nheight = {}\nthickness = {}\nnotch_width = {}\nnotch_depth = {}\n",
            num(o.size.x()), num(o.size.y()), num(o.size.z()), num(o.notch_width),
            num(o.notch_depth));
        break;
    }
    out += fmt::format("keep = \"{}\"\n",
                       d.keep == geometry::KeepRule::cell_inside ? "cell_inside" : "centre_inside");
    out += fmt::format("\n[grain]\nr = {}\nr_bar = {}\nt = {}\nt_bar = {}\n", num(d.r),
                       num(d.r_bar), num(d.t), num(d.t_bar));
  }  // lattice specimens
  if (d.crystal.enabled) {
    const geometry::CrystalLattice& l = d.crystal.lattice;
    out += fmt::format("\n[crystal]\nsystem = \"{}\"\n", geometry::to_string(l.system));
    if (l.system != geometry::CrystalSystem::cubic) out += fmt::format("c_over_a = {}\n", num(l.c_over_a));
    if (l.system == geometry::CrystalSystem::orthorhombic) out += fmt::format("b_over_a = {}\n", num(l.b_over_a));
    for (const auto& f : d.crystal.families) {
      out += fmt::format("\n[[cleavage]]\nplanes = {}\nplanes_per_variant = {}\n", str(f.family.text),
                         f.planes_per_variant);
      if (s.fracture.enabled) out += fmt::format("resistance = {}\n", num(f.resistance));
    }
  }
  using geometry::OrientationLaw;
  const geometry::OrientationDef& law = d.orientation;
  out += fmt::format("\n[orientation]\nseed = {}\n", d.seed);
  switch (law.law) {
    case OrientationLaw::honeycomb:
      if (d.crystal.enabled) out += "law = \"honeycomb\"\n";
      out += fmt::format("family_mix = {}\nangles = [{}]\n", num(d.family_mix), fmt::join(d.angles, ", "));
      break;
    case OrientationLaw::uniform: out += "law = \"uniform\"\n"; break;
    case OrientationLaw::fibre:
      out += fmt::format("law = \"fibre\"\nspread = {}\ncrystal_direction = {}\nspecimen_axis = {}\n",
                         num(law.spread_deg), vec(law.crystal_direction), vec(law.specimen_axis));
      break;
    case OrientationLaw::preferred:
      out += fmt::format("law = \"preferred\"\nspread = {}\neuler = [{}, {}, {}]\n", num(law.spread_deg),
                         num(law.euler_deg[0]), num(law.euler_deg[1]), num(law.euler_deg[2]));
      break;
    case OrientationLaw::given: out += fmt::format("law = \"file\"\nfile = {}\n", str(law.file)); break;
    case OrientationLaw::imported: out += "law = \"imported\"\n"; break;
  }
  out += fmt::format("\n[split]\nmin_fragment_fraction = {}\n", num(s.split.min_fragment_fraction));
  if (s.split.min_fragment_diameter > 0.0)
    out += fmt::format("min_fragment_diameter = {}\n", num(s.split.min_fragment_diameter));
  out += fmt::format("\n[output]\nmesh_format = \"{}\"\nmesh_layout = \"{}\"\nframe_meshes = {}\n",
                     to_string(s.output.mesh_format), to_string(s.output.mesh_layout),
                     boolean(s.output.frame_meshes));
  out += fmt::format("checkpoint_every = {}\n", s.output.checkpoint_every);
  out += fmt::format("\n[material]\ndensity = {}\n", num(s.material.density));
  if (!s.material.preset.empty()) {
    // A bare name reads the same library anywhere; a path is made absolute, since this file
    // is read from another folder than the scenario's.
    const bool is_path = s.material.preset.find('/') != std::string::npos ||
                         s.material.preset.ends_with(".toml");
    out += fmt::format("preset = \"{}\"\n",
                       is_path ? std::filesystem::absolute(s.material.preset_file).string()
                               : s.material.preset);
  }
  for (const PhaseDef& p : s.phases) {
    out += fmt::format(
        "\n[[phase]]\nname = {}\nfraction = {}\ndensity = {}\nstiffness = {}\nstrength = {}\n",
        str(p.name), num(p.fraction), num(p.density), num(p.stiffness), num(p.strength));
    if (!std::isnan(p.alpha)) out += fmt::format("alpha = {}\n", num(p.alpha));
    if (!p.preset.empty()) {
      const bool is_path = p.preset.find('/') != std::string::npos || p.preset.ends_with(".toml");
      out +=
          fmt::format("preset = {}\n",
                      str(is_path ? std::filesystem::absolute(p.preset_file).string() : p.preset));
    }
  }
  for (const BoundaryDef& b : s.boundaries) {
    out += fmt::format("\n[[boundary]]\nphases = [{}, {}]\nstiffness = {}\nstrength = {}\n",
                       str(s.phases.at(static_cast<std::size_t>(b.phases[0])).name),
                       str(s.phases.at(static_cast<std::size_t>(b.phases[1])).name),
                       num(b.stiffness), num(b.strength));
  }

  // [contact] is optional without [dynamics]; when given, its dilation radius is > 0.
  if (s.contact.dilation_radius > 0.0) {
    out += fmt::format("\n[contact]\ndilation_radius = {}\n", num(s.contact.dilation_radius));
    contact_params(out, "particle_particle", s.contact.particle_particle);
    contact_params(out, "particle_wall", s.contact.particle_wall);
  }

  const DynamicsDef& dyn = s.dynamics;
  if (dyn.enabled) {
    out += fmt::format("\n[dynamics]\ndt = {}\n", num(dyn.dt));
    if (s.stages.empty()) out += fmt::format("duration = {}\n", num(dyn.duration));
    out += fmt::format(
        "gravity = {}\nlift = {}\nframes = {}\nsettle_ratio = {}\ndt_safety = {}\nsearch = \"{}\"\n"
        "threads = {}\nlocal_damping = {}\n",
        vec(dyn.gravity), num(dyn.lift), dyn.frames, num(dyn.settle_ratio), num(dyn.dt_safety),
        dyn.search == physics::SearchMethod::basic ? "basic" : "bounding_box", dyn.threads,
        num(dyn.local_damping));
    if (dyn.density_scale != 1.0) out += fmt::format("density_scale = {}\n", num(dyn.density_scale));
    if (dyn.manifold_tolerance != 0.0)
      out += fmt::format("manifold_tolerance = {}\n", num(dyn.manifold_tolerance));
    if (dyn.in_plane) out += "in_plane = true\n";
  }

  for (const physics::Wall& w : s.walls) {
    out += fmt::format("\n[[wall]]\nname = {}\nkind = \"{}\"\npoint = {}\nnormal = {}\n", str(w.name),
                       wall_kind(w.kind), vec(w.origin), vec(w.normal));
    if (w.kind == physics::Wall::Kind::platen) {
      // size is read as full lengths and halved: doubling is exact.
      out += fmt::format("u = {}\nsize = [{}, {}]\n", vec(w.u), num(2.0 * w.half_u), num(2.0 * w.half_v));
    }
    if (w.kind == physics::Wall::Kind::cylinder) {
      out += fmt::format("length = {}\nradius = {}\n", num(w.length), num(w.radius));
    }
    out += fmt::format("velocity = {}\n", vec(w.velocity));
    // Planes and platens read along their normal unless told otherwise; cylinders read
    // magnitudes (zero axis) unless told otherwise.
    const bool default_axis = w.kind == physics::Wall::Kind::cylinder ? w.load_axis.isZero(0.0)
                                                                      : w.load_axis == w.normal;
    if (!default_axis) out += fmt::format("load_axis = {}\n", vec(w.load_axis));
    const std::size_t i = static_cast<std::size_t>(&w - s.walls.data());
    if (i < s.wall_gaps.size() && !std::isnan(s.wall_gaps[i])) out += fmt::format("gap = {}\n", num(s.wall_gaps[i]));
  }

  if (s.bond.enabled) {
    const physics::BondParams& b = s.bond.params;
    if (b.law == physics::BondLaw::beam) {
      out += fmt::format("\n[bond]\nlaw = \"beam\"\nyoung = {}\npoisson = {}\nradius = {}\n", num(b.beam_young),
                         num(b.beam_poisson), num(b.beam_radius));
      if (b.criterion != physics::BondCriterion::limits)
        out += fmt::format("criterion = \"{}\"\n", b.criterion == physics::BondCriterion::rankine ? "rankine" : "hydrostatic");
      if (std::isfinite(b.sigma_f)) out += fmt::format("sigma_f = {}\n", num(b.sigma_f));
    } else {
      out += fmt::format("\n[bond]\nkbn = {}\nkbs = {}\n", num(b.kbn), num(b.kbs));
      if (b.law == physics::BondLaw::cohesive) {
        out += fmt::format("law = \"cohesive\"\nsigma_c = {}\ng_c = {}\n", num(b.sigma_c), num(b.g_c));
      } else if (b.criterion == physics::BondCriterion::limits) {
        out += fmt::format("law = \"bonded_particle\"\ntbn = {}\ntbs = {}\n", num(b.tbn), num(b.tbs));
      } else {
        out += fmt::format("law = \"bonded_particle\"\ncriterion = \"{}\"\nsigma_f = {}\n",
                           b.criterion == physics::BondCriterion::rankine ? "rankine" : "hydrostatic", num(b.sigma_f));
      }
    }
    if (s.bond.strength_modulus > 0.0)
      out += fmt::format("strength_modulus = {}\n", num(s.bond.strength_modulus));
  }

  if (s.fracture.enabled) {
    const physics::FractureParams& f = s.fracture.params;
    if (f.criterion == physics::GrainCriterion::lefm) {
      out += fmt::format(
          "\n[fracture]\nsigma_f_hyd = {}\nk_ic = {}\nc = {}\ncrack_length = {}\ncheck_every = {}\n"
          "inertia = {}\n",
          num(f.sigma_f_hyd), num(f.k_ic), num(f.c), num(f.crack_length), s.fracture.check_every,
          f.inertia);
    } else {
      out += fmt::format("\n[fracture]\ncriterion = \"{}\"\nsigma_f = {}\ncheck_every = {}\n",
                         f.criterion == physics::GrainCriterion::rankine ? "rankine" : "hydrostatic", num(f.sigma_f),
                         s.fracture.check_every);
    }
  }

  if (s.thermal.enabled) {
    const ThermalDef& t = s.thermal;
    out += fmt::format("\n[thermal]\ntemperature = {}\nalpha_a = {}\nalpha_b = {}\nalpha_c = {}\nc_axis = \"{}\"\nseed = {}\n",
                       num(t.temperature), num(t.alpha_a), num(t.alpha_b), num(t.alpha_c),
                       t.c_axis == ThermalDef::Axis::prism    ? "prism"
                       : t.c_axis == ThermalDef::Axis::random ? "random"
                                                              : "crystal",
                       t.seed);
    if (!t.gradient.isZero(0.0)) out += fmt::format("gradient = {}\n", vec(t.gradient));
    out += fmt::format("conductivity = {}\n", num(t.conductivity));
    if (t.heat_capacity > 0.0) out += fmt::format("heat_capacity = {}\n", num(t.heat_capacity));
  }

  if (s.periodic.enabled) {
    std::string axes;
    for (int k = 0; k < 3; ++k) {
      if (s.periodic.axes[static_cast<std::size_t>(k)]) axes += fmt::format("{}\"{}\"", axes.empty() ? "" : ", ", "xyz"[k]);
    }
    out += fmt::format("\n[periodic]\naxes = [{}]\n", axes);
    if (s.periodic.stress_control_time > 0.0) {
      out += fmt::format("stress_control_time = {}\nstress_control_modulus = {}\n", num(s.periodic.stress_control_time),
                         num(s.periodic.stress_control_modulus));
    }
  }

  for (const StageDef& st : s.stages) {
    out += fmt::format("\n[[stage]]\nname = {}\n", str(st.name));
    if (st.kind == StageDef::Kind::bond) {
      out += fmt::format("kind = \"bond\"\ndistance = {}\n", num(st.bond_distance));
      continue;
    }
    out += "kind = \"motion\"\n";
    std::string velocities;
    for (const auto& [name, v] : st.wall_velocity) {
      velocities += fmt::format("{}{} = {}", velocities.empty() ? "" : ", ", str(name), vec(v));
    }
    out += fmt::format("wall_velocity = {{ {} }}\n", velocities);
    if (st.steps > 0) {
      out += fmt::format("steps = {}\n", st.steps);
    } else {
      out += fmt::format("time = {}\n", num(st.time));
    }
    out += fmt::format("until = \"{}\"\n", to_string(st.until));
    if (st.until == StageDef::Until::load_drop) out += fmt::format("load_drop = {}\n", num(st.load_drop));
    std::string walls;
    for (const auto& name : st.load_walls) walls += (walls.empty() ? "" : ", ") + str(name);
    out += fmt::format("load_walls = [{}]\nframes = {}\n", walls, st.frames);
    if (st.ramp_time > 0.0) out += fmt::format("ramp_time = {}\n", num(st.ramp_time));
    if (st.temperature_rate != 0.0) {
      out += fmt::format("temperature_rate = {}\ntemperature_target = {}\n", num(st.temperature_rate),
                         num(st.temperature_target));
    }
    if (!st.quench_wall.empty()) {
      out += fmt::format("quench_wall = {}\nquench_temperature = {}\nquench_depth = {}\n", str(st.quench_wall),
                         num(st.quench_temperature), num(st.quench_depth));
    }
    if (!st.cell_strain_rate.isZero(0.0)) out += fmt::format("cell_strain_rate = {}\n", vec(st.cell_strain_rate));
    if (!st.temperature_gradient_rate.isZero(0.0))
      out += fmt::format("temperature_gradient_rate = {}\n", vec(st.temperature_gradient_rate));
    if (!st.temperature_field.empty()) out += fmt::format("temperature_field = {}\n", str(st.temperature_field));
    if (st.measure_modulus) out += "measure_modulus = true\n";
    if (st.hold_cracks) out += "hold_cracks = true\n";
  }
  return out;
}

// ---- comparison -----------------------------------------------------------------------------

namespace {

/// Collects the keys where two scenarios differ.
class Diff {
 public:
  std::vector<std::string> keys;

  template <class T>
  void same(const std::string& key, const T& a, const T& b) {
    if (!(a == b)) keys.push_back(key);
  }
  /// Numbers: bit-for-bit the same value (NaN never occurs in a parsed scenario).
  void same(const std::string& key, double a, double b) {
    if (!(a == b)) keys.push_back(key);
  }
  void same(const std::string& key, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    if (a != b) keys.push_back(key);
  }
  /// Unit vectors normalised on reading: within a few ulp.
  void direction(const std::string& key, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    if (!((a - b).lpNorm<Eigen::Infinity>() <= 4e-16)) keys.push_back(key);
  }
  void contact(const std::string& key, const physics::ContactParams& a, const physics::ContactParams& b) {
    same(key + ".kn", a.kn, b.kn);
    same(key + ".ks", a.ks, b.ks);
    same(key + ".kr", a.kr, b.kr);
    same(key + ".kt", a.kt, b.kt);
    same(key + ".c_res", a.c_res, b.c_res);
    same(key + ".mu_s", a.mu_s, b.mu_s);
    same(key + ".mu_r", a.mu_r, b.mu_r);
    same(key + ".damping", a.damping_ratio, b.damping_ratio);
  }
};

}  // namespace

std::vector<std::string> scenario_differences(const Scenario& a, const Scenario& b) {
  Diff d;
  d.same("scenario.name", a.name, b.name);
  d.same("scenario.description", a.description, b.description);

  const geometry::SpecimenDef &sa = a.specimen, &sb = b.specimen;
  d.same("specimen.shape", sa.outline.kind, sb.outline.kind);
  d.same("specimen.shape", sa.kind, sb.kind);
  d.same("specimen.size", sa.voronoi.size, sb.voronoi.size);
  d.same("specimen.domain", sa.voronoi.domain, sb.voronoi.domain);
  d.same("specimen.sides", sa.voronoi.sides, sb.voronoi.sides);
  d.same("specimen.grains", sa.voronoi.cells, sb.voronoi.cells);
  d.same("specimen.gap", sa.voronoi.gap, sb.voronoi.gap);
  d.same("specimen.seed", sa.voronoi.seed, sb.voronoi.seed);
  d.same("specimen.sizes", sa.voronoi.lognormal, sb.voronoi.lognormal);
  d.same("specimen.size_spread", sa.voronoi.size_spread, sb.voronoi.size_spread);
  d.same("specimen.file", a.tessellation ? a.tessellation->file : std::filesystem::path(),
         b.tessellation ? b.tessellation->file : std::filesystem::path());
  d.same("specimen.scale", a.tessellation ? a.tessellation->scale : 0.0,
         b.tessellation ? b.tessellation->scale : 0.0);
  d.same("mesh_grain", a.mesh_grains.size(), b.mesh_grains.size());
  for (std::size_t i = 0; i < std::min(a.mesh_grains.size(), b.mesh_grains.size()); ++i) {
    const std::string key = fmt::format("mesh_grain[{}]", i + 1);
    d.same(key + ".file", a.mesh_grains[i].file, b.mesh_grains[i].file);
    d.same(key + ".scale", a.mesh_grains[i].scale, b.mesh_grains[i].scale);
    d.same(key + ".position", a.mesh_grains[i].offset, b.mesh_grains[i].offset);
    d.same(key + ".convex_hull", a.mesh_grains[i].convex_hull, b.mesh_grains[i].convex_hull);
  }
  d.same("mesh_grain (grains)", sa.custom_grains.size(), sb.custom_grains.size());
  for (std::size_t i = 0; i < std::min(sa.custom_grains.size(), sb.custom_grains.size()); ++i) {
    d.same(fmt::format("mesh_grain (grain {})", i), sa.custom_grains[i].shape.to_exact_text(),
           sb.custom_grains[i].shape.to_exact_text());
  }
  d.same("specimen.size", sa.outline.size, sb.outline.size);
  d.same("specimen.notch_width", sa.outline.notch_width, sb.outline.notch_width);
  d.same("specimen.notch_depth", sa.outline.notch_depth, sb.outline.notch_depth);
  d.same("specimen.keep", sa.keep, sb.keep);
  d.same("grain.r", sa.r, sb.r);
  d.same("grain.r_bar", sa.r_bar, sb.r_bar);
  d.same("grain.t", sa.t, sb.t);
  d.same("grain.t_bar", sa.t_bar, sb.t_bar);
  d.same("orientation.seed", sa.seed, sb.seed);
  d.same("orientation.family_mix", sa.family_mix, sb.family_mix);
  d.same("orientation.angles", sa.angles, sb.angles);
  d.same("crystal", sa.crystal, sb.crystal);
  d.same("orientation.law", sa.orientation.law, sb.orientation.law);
  d.same("orientation.euler", sa.orientation.euler_deg, sb.orientation.euler_deg);
  d.same("orientation.spread", sa.orientation.spread_deg, sb.orientation.spread_deg);
  d.same("orientation.crystal_direction", sa.orientation.crystal_direction, sb.orientation.crystal_direction);
  d.same("orientation.specimen_axis", sa.orientation.specimen_axis, sb.orientation.specimen_axis);
  d.same("orientation.file", sa.orientation.file, sb.orientation.file);
  d.same("orientation.given", sa.orientation.given.size(), sb.orientation.given.size());
  d.same("split.min_fragment_fraction", a.split.min_fragment_fraction, b.split.min_fragment_fraction);
  d.same("split.min_fragment_diameter", a.split.min_fragment_diameter, b.split.min_fragment_diameter);
  d.same("output.mesh_format", a.output.mesh_format, b.output.mesh_format);
  d.same("output.mesh_layout", a.output.mesh_layout, b.output.mesh_layout);
  d.same("output.frame_meshes", a.output.frame_meshes, b.output.frame_meshes);
  d.same("output.checkpoint_every", a.output.checkpoint_every, b.output.checkpoint_every);
  d.same("material.density", a.material.density, b.material.density);
  d.same("material.preset_file",
         a.material.preset_file.empty() ? std::string() : std::filesystem::weakly_canonical(a.material.preset_file).string(),
         b.material.preset_file.empty() ? std::string() : std::filesystem::weakly_canonical(b.material.preset_file).string());
  d.same("phase (count)", a.phases.size(), b.phases.size());
  for (std::size_t i = 0; i < std::min(a.phases.size(), b.phases.size()); ++i) {
    const PhaseDef &pa = a.phases[i], &pb = b.phases[i];
    const std::string k = fmt::format("phase[{}].", i + 1);
    d.same(k + "name", pa.name, pb.name);
    d.same(k + "fraction", pa.fraction, pb.fraction);
    d.same(k + "density", pa.density, pb.density);
    if (std::isnan(pa.alpha) != std::isnan(pb.alpha) ||
        (!std::isnan(pa.alpha) && pa.alpha != pb.alpha))
      d.keys.push_back(k + "alpha");
    d.same(k + "stiffness", pa.stiffness, pb.stiffness);
    d.same(k + "strength", pa.strength, pb.strength);
  }
  d.same("boundary (count)", a.boundaries.size(), b.boundaries.size());
  for (std::size_t i = 0; i < std::min(a.boundaries.size(), b.boundaries.size()); ++i) {
    const std::string k = fmt::format("boundary[{}].", i + 1);
    d.same(k + "phases", a.boundaries[i].phases, b.boundaries[i].phases);
    d.same(k + "stiffness", a.boundaries[i].stiffness, b.boundaries[i].stiffness);
    d.same(k + "strength", a.boundaries[i].strength, b.boundaries[i].strength);
  }
  d.same("contact.dilation_radius", a.contact.dilation_radius, b.contact.dilation_radius);
  d.contact("contact.particle_particle", a.contact.particle_particle, b.contact.particle_particle);
  d.contact("contact.particle_wall", a.contact.particle_wall, b.contact.particle_wall);

  const DynamicsDef &da = a.dynamics, &db = b.dynamics;
  d.same("dynamics", da.enabled, db.enabled);
  d.same("dynamics.dt", da.dt, db.dt);
  d.same("dynamics.duration", da.duration, db.duration);
  d.same("dynamics.gravity", da.gravity, db.gravity);
  d.same("dynamics.lift", da.lift, db.lift);
  d.same("dynamics.frames", da.frames, db.frames);
  d.same("dynamics.settle_ratio", da.settle_ratio, db.settle_ratio);
  d.same("dynamics.dt_safety", da.dt_safety, db.dt_safety);
  d.same("dynamics.search", da.search, db.search);
  d.same("dynamics.threads", da.threads, db.threads);
  d.same("dynamics.local_damping", da.local_damping, db.local_damping);
  d.same("dynamics.density_scale", da.density_scale, db.density_scale);
  d.same("dynamics.manifold_tolerance", da.manifold_tolerance, db.manifold_tolerance);
  d.same("dynamics.in_plane", da.in_plane, db.in_plane);

  d.same("bond", a.bond.enabled, b.bond.enabled);
  d.same("bond.kbn", a.bond.params.kbn, b.bond.params.kbn);
  d.same("bond.strength_modulus", a.bond.strength_modulus, b.bond.strength_modulus);
  d.same("bond.kbs", a.bond.params.kbs, b.bond.params.kbs);
  d.same("bond.tbn", a.bond.params.tbn, b.bond.params.tbn);
  d.same("bond.tbs", a.bond.params.tbs, b.bond.params.tbs);
  d.same("bond.law", a.bond.params.law, b.bond.params.law);
  d.same("bond.sigma_c", a.bond.params.sigma_c, b.bond.params.sigma_c);
  d.same("bond.g_c", a.bond.params.g_c, b.bond.params.g_c);
  d.same("bond.criterion", a.bond.params.criterion, b.bond.params.criterion);
  d.same("bond.sigma_f", a.bond.params.sigma_f, b.bond.params.sigma_f);
  d.same("bond.young", a.bond.params.beam_young, b.bond.params.beam_young);
  d.same("bond.poisson", a.bond.params.beam_poisson, b.bond.params.beam_poisson);
  d.same("bond.radius", a.bond.params.beam_radius, b.bond.params.beam_radius);

  d.same("fracture", a.fracture.enabled, b.fracture.enabled);
  d.same("fracture.sigma_f_hyd", a.fracture.params.sigma_f_hyd, b.fracture.params.sigma_f_hyd);
  d.same("fracture.k_ic", a.fracture.params.k_ic, b.fracture.params.k_ic);
  d.same("fracture.c", a.fracture.params.c, b.fracture.params.c);
  d.same("fracture.crack_length", a.fracture.params.crack_length, b.fracture.params.crack_length);
  d.same("fracture.check_every", a.fracture.check_every, b.fracture.check_every);
  d.same("fracture.criterion", a.fracture.params.criterion, b.fracture.params.criterion);
  d.same("fracture.sigma_f", a.fracture.params.sigma_f, b.fracture.params.sigma_f);
  d.same("fracture.inertia", a.fracture.params.inertia, b.fracture.params.inertia);

  d.same("thermal", a.thermal.enabled, b.thermal.enabled);
  d.same("thermal.temperature", a.thermal.temperature, b.thermal.temperature);
  d.same("thermal.gradient", a.thermal.gradient, b.thermal.gradient);
  d.same("thermal.alpha_a", a.thermal.alpha_a, b.thermal.alpha_a);
  d.same("thermal.alpha_c", a.thermal.alpha_c, b.thermal.alpha_c);
  d.same("thermal.alpha_b", a.thermal.alpha_b, b.thermal.alpha_b);
  d.same("thermal.c_axis", a.thermal.c_axis, b.thermal.c_axis);
  d.same("thermal.seed", a.thermal.seed, b.thermal.seed);
  d.same("thermal.conductivity", a.thermal.conductivity, b.thermal.conductivity);
  d.same("thermal.heat_capacity", a.thermal.heat_capacity, b.thermal.heat_capacity);
  d.same("periodic", a.periodic.enabled, b.periodic.enabled);
  for (std::size_t k = 0; k < 3; ++k) d.same(fmt::format("periodic.axes[{}]", k), a.periodic.axes[k], b.periodic.axes[k]);
  d.same("periodic.stress_control_time", a.periodic.stress_control_time, b.periodic.stress_control_time);
  d.same("periodic.stress_control_modulus", a.periodic.stress_control_modulus, b.periodic.stress_control_modulus);

  d.same("wall (count)", a.walls.size(), b.walls.size());
  for (std::size_t i = 0; i < std::min(a.walls.size(), b.walls.size()); ++i) {
    const physics::Wall &wa = a.walls[i], &wb = b.walls[i];
    const std::string k = fmt::format("wall[{}].", i + 1);
    d.same(k + "name", wa.name, wb.name);
    d.same(k + "kind", wa.kind, wb.kind);
    d.same(k + "point", wa.origin, wb.origin);
    d.direction(k + "normal", wa.normal, wb.normal);
    d.direction(k + "u", wa.u, wb.u);
    d.same(k + "size", std::pair(wa.half_u, wa.half_v), std::pair(wb.half_u, wb.half_v));
    d.same(k + "length", wa.length, wb.length);
    d.same(k + "radius", wa.radius, wb.radius);
    d.same(k + "velocity", wa.velocity, wb.velocity);
    const double ga = i < a.wall_gaps.size() ? a.wall_gaps[i] : NAN, gb = i < b.wall_gaps.size() ? b.wall_gaps[i] : NAN;
    if (std::isnan(ga) != std::isnan(gb) || (!std::isnan(ga) && ga != gb)) d.keys.push_back(k + "gap");
    d.direction(k + "load_axis", wa.load_axis, wb.load_axis);
  }

  d.same("stage (count)", a.stages.size(), b.stages.size());
  for (std::size_t i = 0; i < std::min(a.stages.size(), b.stages.size()); ++i) {
    const StageDef &ta = a.stages[i], &tb = b.stages[i];
    const std::string k = fmt::format("stage[{}].", i + 1);
    d.same(k + "name", ta.name, tb.name);
    d.same(k + "kind", ta.kind, tb.kind);
    d.same(k + "wall_velocity (count)", ta.wall_velocity.size(), tb.wall_velocity.size());
    for (std::size_t j = 0; j < std::min(ta.wall_velocity.size(), tb.wall_velocity.size()); ++j) {
      d.same(k + "wall_velocity." + ta.wall_velocity[j].first, ta.wall_velocity[j].first,
             tb.wall_velocity[j].first);
      d.same(k + "wall_velocity." + ta.wall_velocity[j].first, ta.wall_velocity[j].second,
             tb.wall_velocity[j].second);
    }
    d.same(k + "steps", ta.steps, tb.steps);
    d.same(k + "time", ta.time, tb.time);
    d.same(k + "until", ta.until, tb.until);
    d.same(k + "load_drop", ta.load_drop, tb.load_drop);
    d.same(k + "load_walls", ta.load_walls, tb.load_walls);
    d.same(k + "frames", ta.frames, tb.frames);
    d.same(k + "ramp_time", ta.ramp_time, tb.ramp_time);
    d.same(k + "temperature_rate", ta.temperature_rate, tb.temperature_rate);
    d.same(k + "temperature_target", ta.temperature_target, tb.temperature_target);
    d.same(k + "quench_wall", ta.quench_wall, tb.quench_wall);
    d.same(k + "quench_temperature", ta.quench_temperature, tb.quench_temperature);
    d.same(k + "quench_depth", ta.quench_depth, tb.quench_depth);
    for (int c = 0; c < 3; ++c) d.same(k + fmt::format("cell_strain_rate[{}]", c), ta.cell_strain_rate[c], tb.cell_strain_rate[c]);
    d.same(k + "measure_modulus", ta.measure_modulus, tb.measure_modulus);
    for (int c = 0; c < 3; ++c)
      d.same(k + fmt::format("temperature_gradient_rate[{}]", c), ta.temperature_gradient_rate[c],
             tb.temperature_gradient_rate[c]);
    d.same(k + "temperature_field", ta.temperature_field, tb.temperature_field);
    d.same(k + "hold_cracks", ta.hold_cracks, tb.hold_cracks);
    d.same(k + "distance", ta.bond_distance, tb.bond_distance);
  }
  return d.keys;
}

}  // namespace cleave::io
