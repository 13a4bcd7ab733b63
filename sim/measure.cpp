/// \file
/// Macroscopic measurements on a bonded specimen (see measure.hpp).

#include "sim/measure.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "physics/dem/world.hpp"

namespace cleave::sim {

namespace {

/// Least-squares slope of y against x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  return sxy / sxx;
}

/// The walls the last stage moves (its load walls, when it names them).
std::vector<std::size_t> moving_walls(const io::Scenario& s, const physics::World& world) {
  const io::StageDef& last = s.stages.back();
  std::vector<std::string> names = last.load_walls;
  if (names.empty()) {
    for (const auto& [name, v] : last.wall_velocity) {
      if (v.squaredNorm() > 0.0) names.push_back(name);
    }
  }
  std::vector<std::size_t> out;
  for (std::size_t w = 0; w < world.walls().size(); ++w) {
    if (std::find(names.begin(), names.end(), world.walls()[w].name) != names.end()) out.push_back(w);
  }
  return out;
}

std::vector<std::size_t> walls_of_kind(const physics::World& world, physics::Wall::Kind kind) {
  std::vector<std::size_t> out;
  for (std::size_t w = 0; w < world.walls().size(); ++w) {
    if (world.walls()[w].kind == kind) out.push_back(w);
  }
  return out;
}

[[noreturn]] void refuse(const io::Scenario& s, Test t, const std::string& why) {
  throw std::runtime_error(
      fmt::format("{}: not a {} test: {}", s.source, to_string(t), why));
}

/// Runs every stage before the last (bonding, approach) to its end.
void run_to_last_stage(Simulation& sim) {
  const auto stages = sim.scenario().stages.size();
  while (sim.dynamics()->summary().stages.size() + 1 < stages && !sim.done()) sim.advance_stage();
}

/// The loading stage's length in steps, as its limit gives it.
std::uint64_t stage_steps(const io::Scenario& s, const io::StageDef& loading) {
  return loading.steps > 0 ? loading.steps
                           : static_cast<std::uint64_t>(std::llround(loading.time / s.dynamics.dt));
}

Measurement measure_elastic(Simulation& sim, Measurement m, int samples) {
  const io::Scenario& s = sim.scenario();
  Dynamics& dyn = *sim.dynamics();
  run_to_last_stage(sim);
  const physics::World& world = dyn.world();
  const auto platens = moving_walls(s, world);
  if (platens.size() != 2 || world.walls()[platens[0]].kind != physics::Wall::Kind::platen ||
      world.walls()[platens[1]].kind != physics::Wall::Kind::platen) {
    refuse(s, m.test, "the last stage must move two platens against each other");
  }
  const io::StageDef& loading = s.stages.back();
  const std::uint64_t chunk =
      std::max<std::uint64_t>(1, stage_steps(s, loading) / static_cast<std::uint64_t>(samples));

  // The grains in the middle half of the height, and where they are at the loading's start.
  double ylo = INFINITY, yhi = -INFINITY;
  const auto ids = world.body_ids();
  for (const auto id : ids) {
    ylo = std::min(ylo, world.state(id).x.y());
    yhi = std::max(yhi, world.state(id).x.y());
  }
  std::vector<physics::BodyId> middle;
  std::vector<Eigen::Vector2d> x0;
  for (const auto id : ids) {
    const Eigen::Vector3d& x = world.state(id).x;
    if (std::abs(x.y() - 0.5 * (ylo + yhi)) <= 0.25 * (yhi - ylo)) {
      middle.push_back(id);
      x0.emplace_back(x.x(), x.y());
    }
  }
  if (middle.size() < 3) refuse(s, m.test, "fewer than three grains in the middle half");
  std::vector<Eigen::Vector3d> origin0;
  for (std::size_t w : platens) origin0.push_back(world.walls()[w].origin);
  const double area = m.section.width * m.section.thickness;
  const double t0 = world.time();
  double work = 0.0, last_load = 0.0, last_closure = 0.0;

  while (!sim.done()) {
    if (sim.advance(chunk) == 0) break;
    if (sim.dynamics()->stage() != loading.name) break;
    double load = 0.0, closure = 0.0;
    for (std::size_t k = 0; k < platens.size(); ++k) {
      const physics::Wall& w = world.walls()[platens[k]];
      load += -w.reaction.dot(w.load_axis) / static_cast<double>(platens.size());
      closure += (w.origin - origin0[k]).dot(w.load_axis);
    }
    std::vector<Eigen::Vector2d> u;
    for (std::size_t i = 0; i < middle.size(); ++i) {
      const Eigen::Vector3d& x = world.state(middle[i]).x;
      u.push_back(Eigen::Vector2d(x.x(), x.y()) - x0[i]);
    }
    const physics::AffineFit fit = physics::fit_affine(x0, u);
    ElasticSample e;
    e.time = world.time() - t0;
    e.stress = load / area;
    e.strain_platens = closure / m.section.depth;
    e.strain_axial = -fit.strain()(1, 1);
    e.strain_lateral = fit.strain()(0, 0);
    m.samples.push_back(e);
    work += 0.5 * (load + last_load) * (closure - last_closure);
    last_load = load;
    last_closure = closure;
    if (m.samples.size() * 2 > static_cast<std::size_t>(samples) && work > 0.0) {
      m.kinetic_ratio = std::isnan(m.kinetic_ratio)
                            ? world.kinetic_energy() / work
                            : std::max(m.kinetic_ratio, world.kinetic_energy() / work);
    }
  }
  if (m.samples.size() < 4) refuse(s, m.test, "its loading stage gave fewer than four readings");
  std::vector<double> stress, axial, lateral, platen;
  for (std::size_t i = m.samples.size() * 3 / 10; i < m.samples.size(); ++i) {
    stress.push_back(m.samples[i].stress);
    axial.push_back(m.samples[i].strain_axial);
    lateral.push_back(m.samples[i].strain_lateral);
    platen.push_back(m.samples[i].strain_platens);
  }
  m.value = slope(axial, stress);
  m.poisson = slope(axial, lateral);
  m.young_platens = slope(platen, stress);
  m.formula = fmt::format(
      "E = d sigma / d eps_axial, sigma = P / (w t) with w = {:.4g} mm, t = {:.4g} mm; nu = "
      "d eps_lateral / d eps_axial; strains from the affine fit of {} grains' displacements "
      "(middle half); least squares over the last 70 % of the loading",
      m.section.width * 1e3, m.section.thickness * 1e3, middle.size());
  if (s.bond.enabled && s.bond.params.law == physics::BondLaw::bonded_particle &&
      s.specimen.kind == geometry::SpecimenKind::lattice) {
    const double ab = M_PI * s.contact.dilation_radius * s.contact.dilation_radius;
    m.closed_form = physics::honeycomb_elasticity(s.bond.params.kbn * ab, s.bond.params.kbs * ab,
                                                  m.section.thickness);
  }
  return m;
}

/// Where a bending test's section forces are taken (mid_span_forces), and what they read.
struct SectionProbe {
  std::vector<std::size_t> walls;  ///< the rollers
  double x_mid = 0.0;              ///< the mid-span section
  double y_ref = 0.0;              ///< its centre (the bar's mean grain centroid)
  /// The test's value from the section's moment (N m, sagging positive) and axial force
  /// (N, tension positive).
  std::function<double(double moment, double axial)> value;
};

struct SectionForces {
  double moment = 0.0;  ///< N m, sagging positive
  double axial = 0.0;   ///< N, tension positive
};

/// The bending moment about (x_mid, y_ref) and the axial force at the section x = x_mid,
/// from the probe's walls' contact forces on the specimen left of it, each where it acts:
/// the statics of the left part, so it holds whatever the rollers push with (friction
/// along the faces, a corner off a roller's apex), where the formulas take vertical forces
/// at the rollers' axes and no axial force.
SectionForces mid_span_forces(const physics::World& world, const SectionProbe& probe) {
  SectionForces f;
  for (const physics::ContactRecord& c : world.contacts()) {
    if (!c.wall || std::find(probe.walls.begin(), probe.walls.end(), c.a) == probe.walls.end()) continue;
    if (!(c.point.x() < probe.x_mid)) continue;
    // c.force is on the grain (B). The right part holds the left one with N along +x (N > 0
    // pulls: tension) and the sagging moment M: both balance the walls' forces on the left.
    f.moment -= (c.point.x() - probe.x_mid) * c.force.y() - (c.point.y() - probe.y_ref) * c.force.x();
    f.axial -= c.force.x();
  }
  return f;
}

/// The loading stage to its end; its peak, refused unless the load dropped. The run is
/// finished first, so that its folder holds the curve whatever is refused. On the way, the
/// kinetic energy against the work the loading walls have done (each wall pushes with
/// minus its reaction), sampled 4,000 times over the stage's length (the first crack's
/// reading is the sample before it: 1/4,000 of the stage, a few tenths of a per cent of
/// the load in the SiC tests, where 1/400 was 1-2 %), and with a
/// `probe` its reading of the mid-span section's forces at each sample (the largest, and
/// the first crack's).
void run_strength_test(Simulation& sim, Measurement& m, const SectionProbe* probe = nullptr) {
  const io::Scenario& s = sim.scenario();
  run_to_last_stage(sim);
  if (!sim.done()) {
    const io::StageDef& loading = s.stages.back();
    const physics::World& world = sim.dynamics()->world();
    const auto loaders = moving_walls(s, world);
    const std::uint64_t chunk = std::max<std::uint64_t>(1, stage_steps(s, loading) / 4000);
    std::vector<Eigen::Vector3d> last_origin, last_reaction;
    for (std::size_t w : loaders) {
      last_origin.push_back(world.walls()[w].origin);
      last_reaction.push_back(world.walls()[w].reaction);
    }
    struct Sample {
      double time, load, ratio;
    };
    SectionForces last_forces;  // the probe's, on the last sample (zero without a probe)
    std::vector<Sample> samples;
    const double t0 = world.time();
    std::vector<Eigen::Vector3d> origins;  // the walls at the loading's start
    for (const physics::Wall& w : world.walls()) origins.push_back(w.origin);
    // A split adds bodies (nothing else does during a test); a break, a broken bond.
    const std::size_t bodies0 = world.body_count(), broken0 = world.bond_counts().broken();
    double work = 0.0;
    while (!sim.done()) {
      if (sim.advance(chunk) == 0) break;
      if (sim.dynamics()->stage() != loading.name) break;
      for (std::size_t k = 0; k < loaders.size(); ++k) {
        const physics::Wall& w = world.walls()[loaders[k]];
        work -= 0.5 * (w.reaction + last_reaction[k]).dot(w.origin - last_origin[k]);
        last_origin[k] = w.origin;
        last_reaction[k] = w.reaction;
      }
      // The load as the run's table and peak read it (two platens each carry P, not 2P).
      const double load = machine_reading(world, loaders, origins).load;
      if (m.first_crack.empty()) {
        if (world.body_count() != bodies0) m.first_crack = "grain";
        else if (world.bond_counts().broken() != broken0) m.first_crack = "bond";
        if (!m.first_crack.empty()) {
          m.first_crack_load = samples.empty() ? 0.0 : samples.back().load;
          if (probe != nullptr) {
            m.moment_at_first_crack = last_forces.moment;
            m.axial_at_first_crack = last_forces.axial;
            m.value_from_statics_at_first_crack = probe->value(last_forces.moment, last_forces.axial);
          }
        }
      }
      if (probe != nullptr) {
        last_forces = mid_span_forces(world, *probe);
        const double value = probe->value(last_forces.moment, last_forces.axial);
        if (!(m.value_from_statics >= value)) m.value_from_statics = value;  // NaN until the first
      }
      samples.push_back({world.time() - t0, load, work > 0.0 ? world.kinetic_energy() / work : NAN});
    }
    const auto peak = std::max_element(samples.begin(), samples.end(),
                                       [](const Sample& a, const Sample& b) { return a.load < b.load; });
    if (peak != samples.end()) {
      for (auto it = samples.begin(); it <= peak; ++it) {
        if (it->time < 0.5 * peak->time || !std::isfinite(it->ratio)) continue;
        m.kinetic_ratio = std::isnan(m.kinetic_ratio) ? it->ratio : std::max(m.kinetic_ratio, it->ratio);
      }
    }
  }
  m.report = sim.finish();
  if (m.report.status != RunReport::Status::finished || !m.report.dynamics) return;
  const auto& stages = m.report.dynamics->stages;
  if (stages.size() != s.stages.size()) refuse(s, m.test, "the run stopped before its last stage ended");
  const StageSummary& last = stages.back();
  if (last.ended_by != "load_drop") {
    refuse(s, m.test,
           fmt::format("its last stage ended by '{}', not by the load dropping after its peak "
                       "(until = \"load_drop\"): a peak at the stage's end is no strength; "
                       "give it more time",
                       last.ended_by));
  }
  m.peak_load = last.peak_load;
  m.peak_displacement = last.peak_displacement;
}

/// The x of the cylinder walls in `which`, sorted.
std::vector<double> roller_x(const physics::World& world, const std::vector<std::size_t>& which) {
  std::vector<double> x;
  for (std::size_t w : which) x.push_back(world.walls()[w].origin.x());
  std::sort(x.begin(), x.end());
  return x;
}

}  // namespace

const char* to_string(Test t) {
  switch (t) {
    case Test::elastic: return "elastic";
    case Test::brazilian: return "brazilian";
    case Test::flexural: return "flexural";
    case Test::senb: return "senb";
  }
  return "?";
}

std::optional<Test> parse_test(std::string_view name) {
  for (Test t : {Test::elastic, Test::brazilian, Test::flexural, Test::senb}) {
    if (name == to_string(t)) return t;
  }
  return std::nullopt;
}

Section specimen_section(const geometry::Specimen& specimen) {
  const geometry::SpecimenDef& d = specimen.def;
  Section s{d.outline.size.x(), d.outline.size.y(), d.outline.size.z(), d.outline.notch_depth};
  if (d.kind != geometry::SpecimenKind::lattice || specimen.grains.empty()) return s;
  // Rows 1.5 r apart in y, layers t apart in z: count the distinct ones (to a tenth of r).
  std::map<std::pair<long long, long long>, int> per_row;
  std::set<long long> rows, layers;
  for (const auto& g : specimen.grains) {
    const long long row = std::llround(g.site.centre.y() / (0.1 * d.r));
    const long long layer = std::llround(g.site.centre.z() / (0.1 * d.t));
    rows.insert(row);
    layers.insert(layer);
    ++per_row[{layer, row}];
  }
  s.depth = static_cast<double>(rows.size()) * 1.5 * d.r;
  s.thickness = static_cast<double>(layers.size()) * d.t;
  // The width that carries a load along y: the rows of a honeycomb strip alternate n and
  // n - 1 grains, and each layer of bonds between two rows holds two diagonal bonds per
  // grain of the shorter row, as an unbounded honeycomb does over that many cells of
  // sqrt(3) r; the longer row's end grains hang on by one diagonal bond and pass no axial
  // load on. So the width is the shortest row's cells.
  int shortest = std::numeric_limits<int>::max();
  for (const auto& [key, count] : per_row) shortest = std::min(shortest, count);
  s.width = static_cast<double>(shortest) * std::sqrt(3.0) * d.r;
  // The notch: rows from the bottom with no grain within 3/4 of a cell of its centre line.
  if (d.outline.notch_depth > 0.0) {
    const double centre = 0.5 * d.outline.size.x();
    int cut = 0;
    for (long long row : rows) {
      const bool whole = std::any_of(specimen.grains.begin(), specimen.grains.end(), [&](const auto& g) {
        return std::llround(g.site.centre.y() / (0.1 * d.r)) == row &&
               std::abs(g.site.centre.x() - centre) < 0.75 * std::sqrt(3.0) * d.r;
      });
      if (whole) break;
      ++cut;
    }
    s.notch = cut * 1.5 * d.r;
  }
  return s;
}

Measurement measure(Test test, const std::filesystem::path& scenario, SimulationOptions options,
                    const std::vector<std::string>& overrides, int samples) {
  auto sim = Simulation::open(scenario, std::move(options), overrides);
  const io::Scenario& s = sim->scenario();
  if (!s.dynamics.enabled || s.stages.empty()) {
    refuse(s, test, "it needs [dynamics] and [[stage]] tables, the last one loading the specimen");
  }
  if (!s.bond.enabled) refuse(s, test, "it has no [bond]: the measurements are of a bonded specimen");
  sim->start();
  Measurement m;
  m.test = test;
  m.section = specimen_section(sim->specimen());
  const physics::World& world = sim->dynamics()->world();
  const auto& outline = s.specimen.outline;
  switch (test) {
    case Test::elastic:
      m = measure_elastic(*sim, std::move(m), samples);
      break;
    case Test::brazilian: {
      if (outline.kind != geometry::Outline::Kind::disc) refuse(s, test, "its specimen is not a disc");
      run_strength_test(*sim, m);
      const double D = outline.size.x(), t = m.section.thickness;
      m.value = physics::brazilian_tensile_strength(m.peak_load, D, t);
      m.formula = fmt::format("sigma_t = 2P / (pi D t) = 2 x {:.5g} N / (pi x {:.4g} mm x {:.4g} mm)",
                              m.peak_load, D * 1e3, t * 1e3);
      break;
    }
    case Test::flexural:
    case Test::senb: {
      if (outline.kind != geometry::Outline::Kind::beam) refuse(s, test, "its specimen is not a beam");
      const auto cylinders = walls_of_kind(world, physics::Wall::Kind::cylinder);
      const auto loaders = moving_walls(s, world);
      std::vector<std::size_t> supports;
      for (std::size_t w : cylinders) {
        if (std::find(loaders.begin(), loaders.end(), w) == loaders.end()) supports.push_back(w);
      }
      const std::size_t want = test == Test::flexural ? 2 : 1;
      if (loaders.size() != want || supports.size() != 2) {
        refuse(s, test, fmt::format("it needs two support rollers and {} loading roller{} (cylinder "
                                    "walls; the last stage moves the loading ones), found {} and {}",
                                    want, want == 1 ? "" : "s", supports.size(), loaders.size()));
      }
      const auto sx = roller_x(world, supports), lx = roller_x(world, loaders);
      // The section the forces are taken at: mid-span (the notch's, under the loading roller).
      auto section_probe = [&](double x_mid, std::function<double(double, double)> value) {
        SectionProbe probe;
        probe.walls = cylinders;
        probe.x_mid = x_mid;
        probe.value = std::move(value);
        for (const physics::BodyId id : world.body_ids()) probe.y_ref += world.state(id).x.y();
        probe.y_ref /= static_cast<double>(world.body_count());
        return probe;
      };
      const double span = sx[1] - sx[0];
      const double b = m.section.thickness, d = m.section.depth;
      if (test == Test::flexural) {
        const double inner = lx[1] - lx[0];
        // The tension face's stress: 6 M / (b d^2) (the formula's, with M = P (L - L_i) / 4)
        // and N / (b d) of the axial force the rollers' friction puts on the section.
        const SectionProbe probe = section_probe(0.5 * (lx[0] + lx[1]), [b, d](double moment, double axial) {
          return 6.0 * moment / (b * d * d) + axial / (b * d);
        });
        run_strength_test(*sim, m, &probe);
        m.value = physics::four_point_flexural_strength(m.peak_load, span, inner, b, d);
        m.formula = fmt::format(
            "sigma_f = 3P (L - L_i) / (2 b d^2) = 3 x {:.5g} N x ({:.4g} - {:.4g}) mm / (2 x {:.4g} mm "
            "x ({:.4g} mm)^2)",
            m.peak_load, span * 1e3, inner * 1e3, b * 1e3, d * 1e3);
      } else {
        if (std::abs(span / d - 4.0) > 0.08) {
          refuse(s, test, fmt::format("ASTM C1421's three-point formula holds for S/W = 4; this "
                                      "rig has S = {:.4g} mm over W = {:.4g} mm = {:.3g}",
                                      span * 1e3, d * 1e3, span / d));
        }
        const double a = m.section.notch;
        if (!(a > 0.0)) refuse(s, test, "its beam has no notch (notch_depth)");
        // K_I of the notched section's moment (the formula's P S is 4 M of a three-point
        // moment) and of its axial force (an edge-notched strip in tension), superposed.
        const SectionProbe probe = section_probe(lx[0], [span, b, d, a](double moment, double axial) {
          return physics::senb_stress_intensity(4.0 * moment / span, span, b, d, a) +
                 physics::edge_notch_tension_stress_intensity(axial, b, d, a);
        });
        run_strength_test(*sim, m, &probe);
        m.value = physics::senb_stress_intensity(m.peak_load, span, b, d, a);
        m.formula = fmt::format(
            "K_Ic = P S / (B W^1.5) Y(a/W) = {:.5g} N x {:.4g} mm / ({:.4g} mm x ({:.4g} mm)^1.5) x "
            "Y({:.3f}), Y = {:.4f} (ASTM C1421, S/W = 4)",
            m.peak_load, span * 1e3, b * 1e3, d * 1e3, a / d, physics::senb_geometry_factor(a / d));
      }
      break;
    }
  }
  if (!sim->finished()) m.report = sim->finish();
  // Every strength formula above is linear in the load.
  if (std::isfinite(m.first_crack_load) && m.peak_load > 0.0 && std::isfinite(m.value)) {
    m.value_at_first_crack = m.value * m.first_crack_load / m.peak_load;
  }
  return m;
}

RateStudy converge_loading_rate(Test test, const std::filesystem::path& scenario,
                                const SimulationOptions& options,
                                const std::vector<std::string>& overrides, double tolerance,
                                int max_runs, const std::function<void(const RatePoint&)>& on_point) {
  if (!(tolerance > 0.0)) throw std::invalid_argument("the convergence tolerance must be > 0");
  if (max_runs < 2) throw std::invalid_argument("a loading-rate study needs at least 2 runs");
  // The scenario as given (with the overrides): its stages and its loading walls' speed.
  const auto probe = Simulation::open(scenario, options, overrides);
  const io::Scenario& s = probe->scenario();
  if (s.stages.empty()) refuse(s, test, "it has no [[stage]] tables: no loading stage to slow down");
  double speed = 0.0;
  for (const auto& [name, v] : s.stages.back().wall_velocity) speed = std::max(speed, v.norm());
  const std::string key = fmt::format("stage[{}].rate_scale", s.stages.size());
  const std::filesystem::path root = probe->out();
  RateStudy study;
  study.tolerance = tolerance;
  double scale = 1.0;
  for (int k = 0; k < max_runs; ++k, scale *= 0.5) {
    SimulationOptions o = options;
    RatePoint p;
    p.rate_scale = scale;
    p.wall_speed = speed * scale;
    p.out = root / fmt::format("rate_{:g}", scale);
    o.out = p.out;
    std::vector<std::string> with = overrides;
    with.push_back(fmt::format("{}={:.17g}", key, scale));
    const auto start = std::chrono::steady_clock::now();
    const Measurement m = measure(test, scenario, o, with);
    p.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (m.report.status != RunReport::Status::finished) {
      throw std::runtime_error(fmt::format("the run at rate_scale {:g} did not finish: {}", scale,
                                           m.report.message));
    }
    p.value = judged_value(m);
    p.kinetic_ratio = m.kinetic_ratio;
    if (!study.points.empty()) p.change = p.value / study.points.back().value - 1.0;
    study.points.push_back(p);
    if (on_point) on_point(p);
    if (std::abs(p.change) < tolerance) {
      study.converged = true;
      break;
    }
  }
  return study;
}

bool judged_at_first_crack(Test t) { return t == Test::flexural || t == Test::senb; }

double judged_value(const Measurement& m) {
  return judged_at_first_crack(m.test) ? m.value_from_statics_at_first_crack : m.value;
}

std::string judged_key(Test t) {
  return judged_at_first_crack(t) ? std::string(value_key(t)) + "_from_statics_at_first_crack" : value_key(t);
}

const char* value_key(Test t) {
  switch (t) {
    case Test::elastic: return "young_Pa";
    case Test::brazilian: return "tensile_strength_Pa";
    case Test::flexural: return "flexural_strength_Pa";
    case Test::senb: return "k_ic_Pa_sqrt_m";
  }
  return "?";
}

std::string measurement_toml(const Measurement& m) {
  const auto num = [](double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string("nan"); };
  std::string out = fmt::format("test = \"{}\"\n{} = {}\n", to_string(m.test), value_key(m.test), num(m.value));
  if (m.test == Test::elastic) {
    out += fmt::format("poisson = {}\nyoung_platens_Pa = {}\n", num(m.poisson), num(m.young_platens));
    if (m.closed_form) {
      out += fmt::format("closed_form_young_Pa = {}\nclosed_form_poisson = {}\n",
                         num(m.closed_form->young), num(m.closed_form->poisson));
    }
  }
  if (std::isfinite(m.peak_load)) {
    out += fmt::format("peak_load_N = {}\npeak_displacement_m = {}\nfirst_crack = \"{}\"\n",
                       num(m.peak_load), num(m.peak_displacement), m.first_crack);
    if (std::isfinite(m.first_crack_load)) {
      out += fmt::format("first_crack_load_N = {}\n{}_at_first_crack = {}\n", num(m.first_crack_load),
                         value_key(m.test), num(m.value_at_first_crack));
    }
  }
  if (std::isfinite(m.value_from_statics)) {
    out += fmt::format("{0}_from_statics = {1}\n{0}_from_statics_at_first_crack = {2}\n", value_key(m.test),
                       num(m.value_from_statics), num(m.value_from_statics_at_first_crack));
  }
  out += fmt::format("section_width_m = {}\nsection_depth_m = {}\nsection_thickness_m = {}\n",
                     num(m.section.width), num(m.section.depth), num(m.section.thickness));
  if (std::isfinite(m.kinetic_ratio)) out += fmt::format("kinetic_ratio = {}\n", num(m.kinetic_ratio));
  out += fmt::format("formula = \"{}\"\n", m.formula);
  return out;
}

}  // namespace cleave::sim
