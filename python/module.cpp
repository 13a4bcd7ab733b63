// _cleave: the compiled half of the Python module `cleave` (python/cleave/__init__.py
// re-exports it). A thin layer over sim::Simulation and geometry::ExactPolyhedron: runs
// are stepped with the GIL released, body state is read as read-only numpy copies (a view
// would outlive the World's array when a grain split moves it), exact volumes come back as
// fractions.Fraction, and a scenario error becomes cleave.ScenarioError with the CLI's
// file:line:col: key message (an override's error names the override).

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "geometry/exact_polyhedron.hpp"
#include "geometry/specimen.hpp"
#include "io/checkpoint.hpp"
#include "io/mesh_io.hpp"
#include "io/scenario.hpp"
#include "io/sweep.hpp"
#include "physics/bonds/grain_stress.hpp"
#include "physics/dem/world.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "sim/simulation.hpp"

namespace py = pybind11;
using namespace pybind11::literals;
using cleave::geometry::ExactPolyhedron;
using cleave::sim::Simulation;

namespace {

/// The state hash as run.toml's final_state_hash writes it.
std::string fmt_hash(std::uint64_t h) { return fmt::format("{:016x}", h); }

PyObject* g_scenario_error = nullptr;    // cleave.ScenarioError (ValueError)
PyObject* g_checkpoint_error = nullptr;  // cleave.CheckpointError (RuntimeError)

py::object fraction(const cleave::geometry::ExactScalar& x) {
  return py::module_::import("fractions").attr("Fraction")(x.to_string());
}

/// A dict of overrides {"table.key": value} as the "table.key=value" strings of --set.
std::vector<std::string> override_strings(const py::object& overrides) {
  std::vector<std::string> out;
  if (overrides.is_none()) return out;
  for (auto item : overrides.cast<py::dict>()) {
    const std::string key = py::str(item.first);
    const py::handle v = item.second;
    std::string value;
    if (py::isinstance<py::bool_>(v)) {
      value = v.cast<bool>() ? "true" : "false";
    } else if (py::isinstance<py::str>(v)) {
      value = v.cast<std::string>();
    } else {
      value = py::repr(v).cast<std::string>();  // ints, and floats that read back exactly
    }
    out.push_back(key + "=" + value);
  }
  return out;
}

cleave::sim::SimulationOptions options(const py::object& out, bool quiet, std::uint64_t max_steps,
                                       std::optional<std::uint64_t> checkpoint_every, bool replace = false) {
  cleave::sim::SimulationOptions o;
  o.replace = replace;
  if (!out.is_none()) o.out = py::str(out).cast<std::string>();
  o.quiet = quiet;
  o.max_steps = max_steps;
  o.checkpoint_every = checkpoint_every;
  o.override_label = "override";  // an error reads "override dynamics.dt=abc: key ..."
  return o;
}

cleave::physics::World& world_of(Simulation& s) {
  if (!s.started()) {
    py::gil_scoped_release release;
    s.start();
  }
  if (!s.dynamics()) throw std::runtime_error("the scenario has no [dynamics]: there is no world to read");
  return s.dynamics()->world();
}

/// The world to change (a wall, temperatures) or step: refused once the run has ended
/// (finish() was called, or a step failed), whose result folder is written and closed.
cleave::physics::World& live_world(Simulation& s, const char* what) {
  if (s.finished())
    throw std::runtime_error(fmt::format("{}: the run has ended (finish() was called, or it failed) and its "
                                         "result folder {} is closed; start a new Simulation to run again",
                                         what, s.out().string()));
  return world_of(s);
}

/// A read-only (slots, width) copy of one Eigen member of every BodyState. A copy, not a
/// view on the World's array: that array moves when a grain splits (new slots), and a view
/// kept across a split would read freed memory. 10^4 bodies x 3 doubles copy in tens of us.
py::array state_copy(Simulation& s, std::size_t offset, py::ssize_t width) {
  const auto& states = world_of(s).slot_states();
  const auto n = static_cast<py::ssize_t>(states.size());
  py::array_t<double> a({n, width});
  auto r = a.mutable_unchecked<2>();
  const char* base = reinterpret_cast<const char*>(states.data());
  for (py::ssize_t i = 0; i < n; ++i) {
    const char* row = base + static_cast<std::size_t>(i) * sizeof(cleave::physics::BodyState) + offset;
    for (py::ssize_t k = 0; k < width; ++k) {
      double v;
      std::memcpy(&v, row + static_cast<std::size_t>(k) * sizeof(double), sizeof v);
      r(i, k) = v;
    }
  }
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// A wall's new velocity, place or move: finite, or ValueError naming the wall.
const Eigen::Vector3d& finite_for(const cleave::physics::Wall& w, const char* what, const Eigen::Vector3d& v) {
  if (!v.allFinite())
    throw py::value_error(fmt::format("wall '{}': {} must be finite (no NaN or infinity), got ({}, {}, {})", w.name,
                                      what, v.x(), v.y(), v.z()));
  return v;
}

/// One value per body slot, read off its BodyInfo (a copy: the records are not contiguous).
template <class T, class F>
py::array_t<T> per_slot(Simulation& s, F&& field) {
  const auto& infos = world_of(s).slot_infos();
  py::array_t<T> a(static_cast<py::ssize_t>(infos.size()));
  auto r = a.template mutable_unchecked<1>();
  for (std::size_t i = 0; i < infos.size(); ++i) r(static_cast<py::ssize_t>(i)) = field(infos[i]);
  return a;
}

py::dict stage_dict(const cleave::sim::StageSummary& st) {
  return py::dict("name"_a = st.name, "steps"_a = st.steps, "start"_a = st.start, "end"_a = st.end,
                  "ended_by"_a = st.ended_by, "event_missed"_a = st.event_missed,
                  "peak_load"_a = st.peak_load, "peak_displacement"_a = st.peak_displacement,
                  "bonds_broken"_a = st.bonds_broken, "splits"_a = st.splits, "plot"_a = st.plot);
}

py::dict report_dict(const cleave::sim::RunReport& r) {
  static const char* names[] = {"finished", "interrupted", "failed", "stopped"};  // RunReport::Status
  static_assert(static_cast<int>(cleave::sim::RunReport::Status::stopped) == 3);
  py::dict d("status"_a = names[static_cast<int>(r.status)], "message"_a = r.message,
             "out"_a = r.out.string());
  if (r.dynamics) {
    const auto& x = *r.dynamics;
    py::list stages;
    for (const auto& st : x.stages) stages.append(stage_dict(st));
    d["steps"] = x.steps;
    d["time"] = x.time;
    d["state_hash"] = fmt_hash(x.state_hash);
    d["peak_load"] = x.peak_load;
    d["splits"] = x.splits;
    d["bonds"] = x.bonds;
    d["bonds_broken"] = x.bond_counts.broken();
    d["settled"] = x.settled;
    d["stages"] = stages;
    d["brazilian_strength"] = x.brazilian_strength ? py::cast(*x.brazilian_strength) : py::none();
  }
  return d;
}

}  // namespace

PYBIND11_MODULE(_cleave, m) {
  m.doc() = "cleave: exact-polyhedron DEM of brittle polycrystals (the compiled part)";
  m.attr("__version__") = cleave::sim::version();

  g_scenario_error = PyErr_NewException("cleave.ScenarioError", PyExc_ValueError, nullptr);
  g_checkpoint_error = PyErr_NewException("cleave.CheckpointError", PyExc_RuntimeError, nullptr);
  m.attr("ScenarioError") = py::handle(g_scenario_error);
  m.attr("CheckpointError") = py::handle(g_checkpoint_error);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const cleave::io::ScenarioError& e) {
      py::object err = py::handle(g_scenario_error)(e.what());
      err.attr("file") = e.file();
      err.attr("line") = e.line();
      err.attr("column") = e.column();
      err.attr("key") = e.key();
      PyErr_SetObject(g_scenario_error, err.ptr());
    } catch (const cleave::io::CheckpointError& e) {
      PyErr_SetString(g_checkpoint_error, e.what());
    } catch (const cleave::io::SweepError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  // --- exact geometry ---
  py::class_<ExactPolyhedron>(m, "Polyhedron",
                              "An exact convex polyhedron (CGAL Epeck underneath); volumes are exact.")
      .def_property_readonly("volume", [](const ExactPolyhedron& p) { return fraction(p.volume()); },
                             "The exact volume, a fractions.Fraction (m^3).")
      .def_property_readonly("volume_approx", &ExactPolyhedron::volume_approx)
      .def_property_readonly("num_vertices", &ExactPolyhedron::num_vertices)
      .def_property_readonly("num_faces", &ExactPolyhedron::num_faces)
      .def_property_readonly("vertices",
                             [](const ExactPolyhedron& p) {
                               const auto v = p.vertices_approx();
                               py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
                               auto r = a.mutable_unchecked<2>();
                               for (std::size_t i = 0; i < v.size(); ++i)
                                 for (int k = 0; k < 3; ++k) r(i, k) = v[i][k];
                               return a;
                             })
      .def_property_readonly("faces", &ExactPolyhedron::faces)
      .def(
          "split",
          [](const ExactPolyhedron& p, const Eigen::Vector3d& normal, double offset, double min_fraction) {
            const auto plane = cleave::geometry::ExactPlane::from_normal_offset(normal, offset);
            cleave::geometry::SplitResult r;
            {
              py::gil_scoped_release release;
              r = p.split(plane, min_fraction);
            }
            if (!r.ok()) throw py::value_error("the plane does not split the polyhedron: " + r.reason);
            return py::make_tuple(*r.below, *r.above);
          },
          "normal"_a, "offset"_a, "min_fraction"_a = 0.0,
          "Cuts on the plane normal . x = offset (taken exactly); returns (below, above).")
      .def(
          "cleavage_slabs",
          [](const ExactPolyhedron& p, const std::string& family, int angle_deg) {
            cleave::geometry::CrystalOrientation o;
            o.family = family == "10-10" ? cleave::geometry::CleavageFamily::m_10_10
                                         : cleave::geometry::CleavageFamily::a_11_20;
            o.angle_deg = angle_deg;
            return p.cleavage_slabs(o);
          },
          "family"_a = "11-20", "angle_deg"_a = 0,
          "The slabs its cleavage planes cut it into (family '11-20': 3 slabs, '10-10': 2).")
      .def("translated", &ExactPolyhedron::translated)
      .def("__repr__", [](const ExactPolyhedron& p) {
        return "<cleave.Polyhedron " + std::to_string(p.num_vertices()) + " vertices, " +
               std::to_string(p.num_faces()) + " faces>";
      });
  m.def("hexagonal_prism", &ExactPolyhedron::hexagonal_prism, "side"_a, "thickness"_a,
        "A grain: the hexagonal prism of side `side` and height `thickness` (m), centred on the origin.");
  m.def(
      "total_volume",
      [](const std::vector<ExactPolyhedron>& parts) { return fraction(cleave::geometry::total_volume(parts)); },
      "The exact sum of the volumes, a fractions.Fraction.");
  m.def(
      "export_meshes",
      [](const std::vector<ExactPolyhedron>& parts, const std::filesystem::path& dir, const std::string& stem,
         const std::string& format, const std::string& layout) {
        std::vector<cleave::geometry::PolygonMesh> meshes;
        for (std::size_t i = 0; i < parts.size(); ++i) meshes.push_back(parts[i].to_mesh(stem + "_" + std::to_string(i)));
        const auto files = cleave::io::write_meshes(meshes, dir, stem, cleave::io::parse_mesh_format(format),
                                                    cleave::io::parse_mesh_layout(layout));
        std::vector<std::string> names;
        for (const auto& f : files) names.push_back(f.string());
        return names;
      },
      "polyhedra"_a, "dir"_a, "stem"_a = "mesh", "format"_a = "obj", "layout"_a = "scene",
      "Writes the polyhedra as meshes (format 'obj', 'stl' or 'stl_ascii'; layout 'scene' or "
      "'per_fragment'); returns the files.");

  // --- walls ---
  struct WallRef {
    py::object sim;
    std::size_t index;
    cleave::physics::Wall& wall() const { return world_of(sim.cast<Simulation&>()).wall(index); }
    /// The wall to change: refused once the run has ended.
    cleave::physics::Wall& live(const char* what) const {
      return live_world(sim.cast<Simulation&>(), what).wall(index);
    }
  };
  py::class_<WallRef>(m, "Wall", "A wall of a running simulation (a plane, platen or cylinder).")
      .def_property_readonly("name", [](const WallRef& w) { return w.wall().name; })
      .def_property(
          "origin", [](const WallRef& w) { return Eigen::Vector3d(w.wall().origin); },
          [](const WallRef& w, const Eigen::Vector3d& x) {
            cleave::physics::Wall& wall = w.live("Wall.origin");
            wall.origin = finite_for(wall, "origin", x);
          },
          "Its reference point, m (finite: ValueError otherwise).")
      .def_property(
          "velocity", [](const WallRef& w) { return Eigen::Vector3d(w.wall().velocity); },
          [](const WallRef& w, const Eigen::Vector3d& v) {
            cleave::physics::Wall& wall = w.live("Wall.velocity");
            wall.velocity = finite_for(wall, "velocity", v);
          },
          "Its prescribed velocity, m/s (a new stage sets it from its table; finite: ValueError otherwise).")
      .def_property_readonly("reaction", [](const WallRef& w) { return Eigen::Vector3d(w.wall().reaction); },
                             "The force of the bodies on it in the last step, N.")
      .def_property_readonly("normal", [](const WallRef& w) { return Eigen::Vector3d(w.wall().normal); })
      .def(
          "move",
          [](const WallRef& w, const Eigen::Vector3d& d) {
            cleave::physics::Wall& wall = w.live("Wall.move");
            const Eigen::Vector3d to = wall.origin + finite_for(wall, "move", d);
            wall.origin = finite_for(wall, "origin after the move", to);
          },
          "delta"_a, "Moves it by `delta` (m) at once.");

  // --- the run ---
  using cleave::physics::BodyState;
  py::class_<Simulation>(m, "Simulation", "One cleave run: scenario -> specimen -> slabs -> dynamics -> results.")
      .def(py::init([](const std::filesystem::path& scenario, py::object out, py::object overrides, bool quiet,
                       std::uint64_t max_steps, std::optional<std::uint64_t> checkpoint_every, bool replace) {
             return Simulation::open(scenario, options(out, quiet, max_steps, checkpoint_every, replace),
                                     override_strings(overrides));
           }),
           "scenario"_a, "out"_a = py::none(), "overrides"_a = py::none(), "quiet"_a = true,
           "max_steps"_a = 0, "checkpoint_every"_a = py::none(), "replace"_a = false,
           "Loads a scenario file; overrides: {'table.key': value} as `cleave sweep --set` takes them.")
      .def_static(
          "from_toml",
          [](std::string text, py::object out, py::object overrides, bool quiet, std::uint64_t max_steps,
             std::string source, const std::filesystem::path& base_dir, bool replace) {
            return Simulation::from_text(std::move(text), source,
                                         options(out, quiet, max_steps, std::nullopt, replace),
                                         override_strings(overrides), base_dir);
          },
          "text"_a, "out"_a = py::none(), "overrides"_a = py::none(), "quiet"_a = true, "max_steps"_a = 0,
          "source"_a = "<string>", "base_dir"_a = ".", "replace"_a = false, "A scenario given as TOML text.")
      .def_static(
          "restart",
          [](const std::filesystem::path& checkpoint, py::object out, bool quiet, bool replace) {
            return Simulation::restart(checkpoint, options(out, quiet, 0, std::nullopt, replace));
          },
          "checkpoint"_a, "out"_a = py::none(), "quiet"_a = true, "replace"_a = false, "Continues a run from its checkpoint.")
      .def("start", &Simulation::start, py::call_guard<py::gil_scoped_release>(),
           "Builds the specimen, cuts the slabs, writes the static outputs.")
      .def(
          "advance",
          [](py::object self, std::uint64_t steps, py::object callback, std::uint64_t every) {
            Simulation& s = self.cast<Simulation&>();
            if (s.finished()) live_world(s, "advance");
            if (callback.is_none()) {
              // In chunks, so that Ctrl-C (KeyboardInterrupt) is seen within a chunk's time;
              // the run can go on afterwards. The steps are the same as in one call.
              constexpr std::uint64_t kChunk = 1000;
              std::uint64_t taken = 0;
              while (taken < steps) {
                const std::uint64_t n = std::min(kChunk, steps - taken);
                std::uint64_t k = 0;
                {
                  py::gil_scoped_release release;
                  k = s.advance(n);
                }
                taken += k;
                if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                if (k < n) break;
              }
              return taken;
            }
            if (every == 0) throw py::value_error("every must be at least 1");
            std::uint64_t taken = 0;
            while (taken < steps) {
              const std::uint64_t n = std::min(every, steps - taken);
              std::uint64_t k = 0;
              {
                py::gil_scoped_release release;
                k = s.advance(n);
              }
              taken += k;
              if (PyErr_CheckSignals() != 0) throw py::error_already_set();
              if (k == 0) break;
              const py::object r = callback(self);
              if (!r.is_none() && !r.cast<bool>()) break;
              if (k < n) break;
            }
            return taken;
          },
          "steps"_a = 1, "callback"_a = py::none(), "every"_a = 1,
          "Takes up to `steps` steps with the GIL released; calls callback(sim) every `every` steps "
          "(returning False stops). Ctrl-C raises KeyboardInterrupt between chunks of steps; the run "
          "can go on. Returns the steps taken.")
      .def(
          "advance_stage",
          [](Simulation& s) -> py::object {
            if (s.finished()) live_world(s, "advance_stage");
            std::optional<cleave::sim::StageSummary> st;
            {
              py::gil_scoped_release release;
              st = s.advance_stage();
            }
            return st ? py::object(stage_dict(*st)) : py::none();
          },
          "Runs the stage under way to its end (its event or limit); returns its summary.")
      .def("finish", [](Simulation& s) {
             cleave::sim::RunReport r;
             {
               py::gil_scoped_release release;
               r = s.finish();
             }
             return report_dict(r);
           }, "Runs what is left, writes the result folder; returns the report.")
      .def_property_readonly("done", &Simulation::done)
      .def_property_readonly("finished", &Simulation::finished)
      .def_property_readonly("started", &Simulation::started)
      .def_property_readonly("out", [](const Simulation& s) { return s.out().string(); })
      .def_property_readonly("name", [](const Simulation& s) { return s.scenario().name; })
      .def_property_readonly("time", [](Simulation& s) { return world_of(s).time(); })
      .def_property_readonly("steps", [](Simulation& s) { return world_of(s).steps(); })
      .def_property_readonly("stage", [](Simulation& s) {
        world_of(s);
        return s.dynamics()->stage();
      })
      .def_property_readonly("state_hash", [](Simulation& s) { return fmt_hash(world_of(s).state_hash()); },
                             "The World's state hash, as run.toml's final_state_hash writes it.")
      .def_property_readonly("kinetic_energy", [](Simulation& s) { return world_of(s).kinetic_energy(); })
      .def_property_readonly("positions", [](Simulation& s) { return state_copy(s, offsetof(BodyState, x), 3); },
                             "(slots, 3) centroids, m: a read-only copy of the state now (see alive).")
      .def_property_readonly("orientations",
                             [](Simulation& s) { return state_copy(s, offsetof(BodyState, q), 4); },
                             "(slots, 4) unit quaternions (x, y, z, w), principal frame to world.")
      .def_property_readonly("velocities", [](Simulation& s) { return state_copy(s, offsetof(BodyState, v), 3); })
      .def_property_readonly("angular_velocities",
                             [](Simulation& s) { return state_copy(s, offsetof(BodyState, w), 3); })
      .def_property_readonly("angular_momenta",
                             [](Simulation& s) { return state_copy(s, offsetof(BodyState, L), 3); })
      .def_property_readonly("forces", [](Simulation& s) { return state_copy(s, offsetof(BodyState, f), 3); })
      .def_property_readonly("torques", [](Simulation& s) { return state_copy(s, offsetof(BodyState, tau), 3); })
      .def_property_readonly("alive",
                             [](Simulation& s) { return per_slot<bool>(s, [](const auto& b) { return b.alive; }); },
                             "(slots,) which slots hold a live body.")
      .def_property_readonly("grain_ids",
                             [](Simulation& s) { return per_slot<int>(s, [](const auto& b) { return b.grain_id; }); })
      .def_property_readonly("temperatures",
                             [](Simulation& s) {
                               const auto& thermal = world_of(s).slot_thermal();
                               py::array_t<double> a(static_cast<py::ssize_t>(thermal.size()));
                               auto r = a.mutable_unchecked<1>();
                               for (std::size_t i = 0; i < thermal.size(); ++i)
                                 r(static_cast<py::ssize_t>(i)) = thermal[i].temperature;
                               return a;
                             },
                             "(slots,) each body's temperature, K (a copy).")
      .def(
          "set_temperatures",
          [](Simulation& s, const py::array_t<double, py::array::c_style | py::array::forcecast>& kelvin) {
            cleave::physics::World& w = live_world(s, "set_temperatures");
            if (!s.scenario().thermal.enabled)
              throw std::runtime_error(fmt::format(
                  "set_temperatures: {} has no [thermal] section: without it a temperature moves nothing (no "
                  "thermal expansion, no conduction); add [thermal] with the grains' expansion coefficients "
                  "(scenarios/reference.toml) to prescribe temperatures",
                  s.scenario().source));
            const auto n = static_cast<py::ssize_t>(w.slot_thermal().size());
            if (kelvin.ndim() != 1 || kelvin.shape(0) != n)
              throw py::value_error(fmt::format("set_temperatures: expected a 1-D array of {} temperatures (one per "
                                                "slot), got {} dimension(s) of first length {}",
                                                n, kelvin.ndim(), kelvin.ndim() > 0 ? kelvin.shape(0) : 0));
            const auto r = kelvin.unchecked<1>();
            for (const auto id : w.body_ids()) {
              const double t = r(static_cast<py::ssize_t>(id.index));
              if (std::isnan(t)) continue;
              if (!(t > 0.0) || !std::isfinite(t))
                throw py::value_error(fmt::format("set_temperatures: slot {} (grain {}): {} K; temperatures must be "
                                                  "finite and above 0 K (NaN leaves a body as it is)",
                                                  id.index, w.info(id).grain_id, t));
            }
            for (const auto id : w.body_ids()) {
              const double t = r(static_cast<py::ssize_t>(id.index));
              if (!std::isnan(t)) w.set_temperature(id, t);
            }
          },
          "kelvin"_a,
          "Sets each live body's temperature (K; an array of one value per slot, NaN leaves a body as it "
          "is): a field of any shape, prescribed from Python between advance() calls. Bonds follow it "
          "from the next step on.")
      .def_property_readonly("grain_stresses",
                             [](Simulation& s) {
                               const auto stress = world_of(s).body_stresses();
                               py::array_t<double> a({static_cast<py::ssize_t>(stress.size()), py::ssize_t{3}, py::ssize_t{3}});
                               auto r = a.mutable_unchecked<3>();
                               for (std::size_t i = 0; i < stress.size(); ++i)
                                 for (int j = 0; j < 3; ++j)
                                   for (int k = 0; k < 3; ++k) r(i, j, k) = stress[i](j, k);
                               return a;
                             },
                             "(slots, 3, 3) grain stress tensors from the contacts (eq. 2.17), Pa (a copy).")
      .def_property_readonly("bonds",
                             [](Simulation& s) {
                               const auto& bonds = world_of(s).bonds();
                               const auto n = static_cast<py::ssize_t>(bonds.size());
                               py::array_t<std::uint32_t> pairs({n, py::ssize_t{2}});
                               py::array_t<bool> intact(n);
                               py::array_t<int> mode(n);
                               py::array_t<double> normal_force(n), shear_force(n);
                               auto p = pairs.mutable_unchecked<2>();
                               auto in = intact.mutable_unchecked<1>();
                               auto mo = mode.mutable_unchecked<1>();
                               auto nf = normal_force.mutable_unchecked<1>();
                               auto sf = shear_force.mutable_unchecked<1>();
                               for (py::ssize_t i = 0; i < n; ++i) {
                                 const auto& b = bonds[static_cast<std::size_t>(i)];
                                 p(i, 0) = b.a;
                                 p(i, 1) = b.b;
                                 in(i) = b.intact();
                                 mo(i) = static_cast<int>(b.failure);
                                 nf(i) = b.state.normal;
                                 sf(i) = b.state.shear.norm();
                               }
                               py::list names;
                               for (int k = 0; k <= 4; ++k)
                                 names.append(cleave::physics::to_string(static_cast<cleave::physics::BondFailure>(k)));
                               return py::dict("pairs"_a = pairs, "intact"_a = intact, "failure_mode"_a = mode,
                                               "failure_mode_names"_a = names, "normal_force"_a = normal_force,
                                               "shear_force"_a = shear_force);
                             },
                             "Bonds: pairs (body slots), intact, failure_mode (codes; failure_mode_names).")
      .def_property_readonly("contacts",
                             [](Simulation& s) {
                               const auto& cs = world_of(s).contacts();
                               const auto n = static_cast<py::ssize_t>(cs.size());
                               py::array_t<std::uint32_t> pairs({n, py::ssize_t{2}});
                               py::array_t<bool> wall(n);
                               py::array_t<double> point({n, py::ssize_t{3}}), force({n, py::ssize_t{3}}), overlap(n);
                               auto p = pairs.mutable_unchecked<2>();
                               auto w = wall.mutable_unchecked<1>();
                               auto pt = point.mutable_unchecked<2>();
                               auto f = force.mutable_unchecked<2>();
                               auto o = overlap.mutable_unchecked<1>();
                               for (py::ssize_t i = 0; i < n; ++i) {
                                 const auto& c = cs[static_cast<std::size_t>(i)];
                                 p(i, 0) = c.a;
                                 p(i, 1) = c.b;
                                 w(i) = c.wall;
                                 o(i) = c.overlap;
                                 for (int k = 0; k < 3; ++k) {
                                   pt(i, k) = c.point[k];
                                   f(i, k) = c.force[k];
                                 }
                               }
                               return py::dict("pairs"_a = pairs, "with_wall"_a = wall, "point"_a = point,
                                               "force"_a = force, "overlap"_a = overlap);
                             },
                             "Contacts of the last step: pairs (a is a wall index when with_wall), point, force on b, overlap.")
      .def_property_readonly("fragments",
                             [](Simulation& s) {
                               py::list out;
                               auto& world = world_of(s);
                               const auto* book = s.dynamics()->book();
                               for (const auto id : world.body_ids()) {
                                 py::dict d("slot"_a = id.index, "grain_id"_a = world.info(id).grain_id);
                                 if (book && book->knows(id)) {
                                   const auto& l = book->lineage(id);
                                   d["lineage"] = l.path_string();
                                   d["name"] = l.name();
                                   d["shape"] = book->exact_shape(id);
                                 }
                                 out.append(d);
                               }
                               return out;
                             },
                             "Every live body: slot, grain_id, and with [fracture] its lineage, name and exact shape.")
      .def_property_readonly("walls",
                             [](py::object self) {
                               Simulation& s = self.cast<Simulation&>();
                               py::list out;
                               for (std::size_t i = 0; i < world_of(s).walls().size(); ++i) out.append(WallRef{self, i});
                               return out;
                             })
      .def(
          "wall",
          [](py::object self, const std::string& name) {
            Simulation& s = self.cast<Simulation&>();
            std::string names;
            const auto& walls = world_of(s).walls();
            for (std::size_t i = 0; i < walls.size(); ++i) {
              if (walls[i].name == name) return WallRef{self, i};
              names += (names.empty() ? "" : ", ") + walls[i].name;
            }
            throw py::key_error(fmt::format("no wall named '{}' in {} (its walls: {})", name, s.scenario().source,
                                            names.empty() ? "none" : names));
          },
          "name"_a, "The wall of that name ([[wall]] name in the scenario); KeyError naming the others.")
      .def_property_readonly("slabs",
                             [](Simulation& s) {
                               py::list out;
                               for (const auto& p : s.slabs()) {
                                 out.append(py::dict("name"_a = p.lineage.name(), "grain_id"_a = p.lineage.grain_id,
                                                     "shape"_a = *p.shape, "position"_a = Eigen::Vector3d(p.position)));
                               }
                               return out;
                             },
                             "The exact cleavage slabs cut at the start (after start()).");
}
