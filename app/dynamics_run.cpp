#include "dynamics_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "io/result_dir.hpp"
#include "io/vtk_output.hpp"
#include "io/world_setup.hpp"
#include "physics/grain_stress.hpp"
#include "physics/world.hpp"

namespace cleave::app {

namespace {

namespace fs = std::filesystem;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The body frame: every body's world mesh and its fields.
io::BodyFrame body_frame(const physics::World& world, const geometry::Specimen& specimen) {
  io::BodyFrame frame;
  const std::vector<Eigen::Matrix3d> stress = world.body_stresses();
  auto& ids = frame.body_fields.ids;
  auto& vec = frame.body_fields.vectors;
  auto& sca = frame.body_fields.scalars;
  for (const physics::BodyId id : world.body_ids()) {
    const physics::BodyState& s = world.state(id);
    const physics::BodyInfo& b = world.info(id);
    const auto& prim = world.shape(b.shape).primitives;
    geometry::PolygonMesh mesh;
    const Eigen::Matrix3d R = s.q.toRotationMatrix();
    for (const auto& v : prim.vertices) mesh.vertices.push_back(s.x + R * v);
    for (const auto& f : prim.faces) mesh.faces.push_back(f.vertices);
    frame.meshes.push_back(std::move(mesh));
    ids["body_id"].push_back(id.index);
    ids["grain_id"].push_back(b.grain_id);
    const auto& o = specimen.grains.at(static_cast<std::size_t>(b.grain_id)).orientation;
    ids["family_11_20"].push_back(o.family == geometry::CleavageFamily::a_11_20 ? 1 : 0);
    ids["angle_deg"].push_back(o.angle_deg);
    // The crystal's c axis (the prism axis, z of the shape frame) in the world.
    const auto& shape = world.shape(b.shape);
    vec["c_axis"].push_back(s.q * (shape.axes.transpose() * Eigen::Vector3d::UnitZ()));
    vec["velocity"].push_back(s.v);
    vec["angular_velocity"].push_back(s.w);
    sca["speed"].push_back(s.v.norm());
    // Grain stress (eq. 2.17) from the contacts: mean (hydrostatic), von Mises, principal.
    const Eigen::Matrix3d& sigma = stress[id.index];
    sca["mean_stress_Pa"].push_back(physics::mean_stress(sigma));
    sca["von_mises_Pa"].push_back(physics::von_mises(sigma));
    vec["principal_stress_Pa"].push_back(physics::principal_stresses(sigma));
  }
  return frame;
}

/// Contacts as points (zero-length links) at their contact points.
io::LinkFrame contact_frame(const physics::World& world) {
  io::LinkFrame frame;
  for (const auto& c : world.contacts()) {
    frame.a.push_back(c.point);
    frame.b.push_back(c.point);
    frame.fields.vectors["force"].push_back(c.force);
    frame.fields.vectors["normal"].push_back(c.normal);
    frame.fields.scalars["overlap"].push_back(c.overlap);
    frame.fields.ids["with_wall"].push_back(c.wall ? 1 : 0);
  }
  return frame;
}

double lowest_vertex(const physics::World& world) {
  double z = std::numeric_limits<double>::infinity();
  for (const physics::BodyId id : world.body_ids()) {
    const physics::BodyState& s = world.state(id);
    const auto& prim = world.shape(world.info(id).shape).primitives;
    for (const auto& v : prim.vertices) z = std::min(z, (s.x + s.q * v).z());
  }
  return z;
}

}  // namespace

DynamicsSummary run_dynamics(const io::Scenario& scenario, const geometry::Specimen& specimen,
                             const fs::path& out, bool quiet, std::uint64_t max_steps) {
  const auto t0 = std::chrono::steady_clock::now();
  const io::DynamicsDef& dyn = scenario.dynamics;
  physics::World world = io::make_world(scenario, specimen);

  const fs::path frames_dir = out / "frames";
  fs::create_directories(frames_dir);
  io::PvdSeries bodies_pvd(out / "bodies.pvd"), contacts_pvd(out / "contacts.pvd");
  std::string energy = "time_s,kinetic_J,potential_J,contacts,max_overlap_m\n";
  // Reaction force on every wall (the force the grains exert on it), N.
  std::string walls = "time_s";
  for (const auto& w : world.walls()) walls += fmt::format(",{0}_Fx_N,{0}_Fy_N,{0}_Fz_N", w.name);
  walls += "\n";
  const double pe0 = world.potential_energy();
  std::uint64_t total = static_cast<std::uint64_t>(std::ceil(dyn.duration / dyn.dt));
  if (max_steps > 0) total = std::min(total, max_steps);
  const std::uint64_t frame_every = dyn.frames > 0 ? std::max<std::uint64_t>(1, total / dyn.frames) : 0;
  const std::uint64_t log_every = std::max<std::uint64_t>(1, total / 200);
  DynamicsSummary sum;
  auto write_frame = [&] {
    const std::string stem = fmt::format("{:06d}", sum.frames);
    io::write_vtp(frames_dir / ("bodies_" + stem + ".vtp"), body_frame(world, specimen));
    io::write_vtp(frames_dir / ("contacts_" + stem + ".vtp"), contact_frame(world));
    bodies_pvd.add(world.time(), fs::path("frames") / ("bodies_" + stem + ".vtp"));
    contacts_pvd.add(world.time(), fs::path("frames") / ("contacts_" + stem + ".vtp"));
    ++sum.frames;
  };
  if (frame_every) write_frame();
  auto last_print = std::chrono::steady_clock::now();
  for (std::uint64_t i = 1; i <= total; ++i) {
    world.step();
    double overlap = 0.0;
    for (const auto& c : world.contacts()) overlap = std::max(overlap, c.overlap);
    sum.max_overlap = std::max(sum.max_overlap, overlap);
    const double ke = world.kinetic_energy();
    const double released = pe0 - world.potential_energy();
    if (i % log_every == 0 || i == total) {
      energy += fmt::format("{:.9g},{:.9g},{:.9g},{},{:.6g}\n", world.time(), ke,
                            world.potential_energy(), world.contacts().size(), overlap);
      walls += fmt::format("{:.9g}", world.time());
      for (const auto& w : world.walls()) {
        walls += fmt::format(",{:.9g},{:.9g},{:.9g}", w.reaction.x(), w.reaction.y(), w.reaction.z());
      }
      walls += "\n";
    }
    if (frame_every && i % frame_every == 0) write_frame();
    const bool settled = dyn.settle_ratio > 0.0 && released > 0.0 && world.contacts().size() > 0 &&
                         ke < dyn.settle_ratio * released;
    if (!quiet && (seconds_since(last_print) > 1.0 || i == total || settled)) {
      last_print = std::chrono::steady_clock::now();
      const double elapsed = seconds_since(t0);
      const double eta = elapsed / static_cast<double>(i) * static_cast<double>(total - i);
      std::fprintf(stderr,
                   "\r  dynamics   step %llu/%llu  t = %.4g s  bodies %zu  contacts %zu  KE %.3g J  "
                   "ETA %.0f s   ",
                   static_cast<unsigned long long>(i), static_cast<unsigned long long>(total),
                   world.time(), world.body_count(), world.contacts().size(), ke, eta);
    }
    if (settled) {
      sum.settled = true;
      break;
    }
  }
  if (!quiet) std::fprintf(stderr, "\n");
  if (frame_every && world.steps() % frame_every != 0) write_frame();
  io::write_file_atomically(out / "energy.csv", energy);
  io::write_file_atomically(out / "walls.csv", walls);
  sum.steps = world.steps();
  sum.time = world.time();
  sum.kinetic_energy = world.kinetic_energy();
  sum.released_energy = pe0 - world.potential_energy();
  sum.lowest_point = lowest_vertex(world);
  sum.wall_seconds = seconds_since(t0);
  return sum;
}

}  // namespace cleave::app
