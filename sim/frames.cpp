#include "sim/frames.hpp"

#include <fmt/format.h>

#include <cmath>

#include "io/mesh_io.hpp"
#include "io/paraview_frames.hpp"
#include "physics/bonds/grain_stress.hpp"

namespace cleave::sim {

namespace fs = std::filesystem;

/// A body's shape in its world pose.
geometry::PolygonMesh world_mesh(const physics::World& world, physics::BodyId id) {
  const physics::BodyState& s = world.state(id);
  const auto& prim = world.shape(world.info(id).shape).primitives;
  geometry::PolygonMesh mesh;
  const Eigen::Matrix3d R = s.q.toRotationMatrix();
  for (const auto& v : prim.vertices) mesh.vertices.push_back(s.x + R * v);
  for (const auto& f : prim.faces) mesh.faces.push_back(f.vertices);
  return mesh;
}

namespace {

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
    frame.meshes.push_back(world_mesh(world, id));
    ids["body_id"].push_back(id.index);
    ids["grain_id"].push_back(b.grain_id);
    const geometry::Grain& grain = specimen.grains.at(static_cast<std::size_t>(b.grain_id));
    const auto& o = grain.orientation;
    ids["family_11_20"].push_back(o.family == geometry::CleavageFamily::a_11_20 ? 1 : 0);
    ids["angle_deg"].push_back(o.angle_deg);
    // A several-phase specimen's grains by phase (the [[phase]] table's index from 0).
    if (!specimen.def.phase_fractions.empty()) ids["phase"].push_back(grain.phase);
    // The crystal's c axis in the world: the grain frame's (specimen axes at the start) turned
    // as the body turned; the honeycomb crystal's is the prism axis, z.
    const auto& shape = world.shape(b.shape);
    vec["c_axis"].push_back(s.q * (shape.axes.transpose() * (grain.crystal * Eigen::Vector3d::UnitZ())));
    vec["velocity_m_per_s"].push_back(s.v);
    vec["angular_velocity_rad_per_s"].push_back(s.w);
    sca["speed_m_per_s"].push_back(s.v.norm());
    // Grain stress (eq. 2.17) from the contacts: mean (hydrostatic), von Mises, principal.
    const Eigen::Matrix3d& sigma = stress[id.index];
    sca["mean_stress_Pa"].push_back(physics::mean_stress(sigma));
    sca["von_mises_Pa"].push_back(physics::von_mises(sigma));
    vec["principal_stress_Pa"].push_back(physics::principal_stresses(sigma));
    // Eq. 2.18: the in-plane (xy) invariants the seed plots for its one-plane specimens.
    const physics::PlaneInvariants pq = physics::plane_invariants(sigma);
    sca["p_xy_Pa"].push_back(pq.p);
    sca["q_xy_Pa"].push_back(pq.q);
    sca["theta_xy_deg"].push_back(pq.theta * 180.0 / M_PI);
  }
  return frame;
}

/// A periodic cell's twelve edges as lines, `axis` the cell vector each runs along (0, 1, 2)
/// and `periodic` whether the cell is periodic along it.
io::LinkFrame cell_frame(const physics::PeriodicCell& cell) {
  io::LinkFrame frame;
  auto corner = [&](int bits) {
    return Eigen::Vector3d(cell.origin() + cell.vectors() * Eigen::Vector3d(bits & 1,
                                                                            (bits >> 1) & 1,
                                                                            (bits >> 2) & 1));
  };
  for (int bits = 0; bits < 8; ++bits) {
    for (int k = 0; k < 3; ++k) {
      if (bits & (1 << k)) continue;
      frame.a.push_back(corner(bits));
      frame.b.push_back(corner(bits | (1 << k)));
      frame.fields.ids["axis"].push_back(k);
      frame.fields.ids["periodic"].push_back(cell.periodic(k) ? 1 : 0);
    }
  }
  return frame;
}

/// Contacts as points (zero-length links) at their contact points.
io::LinkFrame contact_frame(const physics::World& world) {
  io::LinkFrame frame;
  for (const auto& c : world.contacts()) {
    frame.a.push_back(c.point);
    frame.b.push_back(c.point);
    frame.fields.vectors["force_N"].push_back(c.force);
    frame.fields.vectors["normal"].push_back(c.normal);
    frame.fields.scalars["overlap_m"].push_back(c.overlap);
    frame.fields.ids["with_wall"].push_back(c.wall ? 1 : 0);
  }
  return frame;
}

/// The bond network as lines between the two grains' centroids (the beams of figs 2.18 and
/// 2.22): intact (1) or broken (0), the failure mode, and the bond's loads.
io::LinkFrame bond_frame(const physics::World& world) {
  io::LinkFrame frame;
  auto& f = frame.fields;
  for (const physics::Bond& b : world.bonds()) {
    frame.a.push_back(world.state(world.id_at(b.a)).x);
    frame.b.push_back(world.state(world.id_at(b.b)).x);
    f.ids["intact"].push_back(b.intact() ? 1 : 0);
    f.ids["failure_mode"].push_back(static_cast<long long>(b.failure));
    f.scalars["normal_force_N"].push_back(b.state.normal);
    f.scalars["shear_force_N"].push_back(b.state.shear.norm());
    f.scalars["bending_moment_Nm"].push_back(b.state.bending.norm());
    f.scalars["torsion_moment_Nm"].push_back(std::abs(b.state.torsion));
    f.vectors["force_N"].push_back(b.force);
  }
  return frame;
}

/// The first value of a frame that is not finite, as "<item>: its <field> (<file>)".
template <class Name>
std::optional<std::string> non_finite_in(const io::FieldSet& fields, const char* file,
                                         Name&& item) {
  for (const auto& [field, values] : fields.scalars) {
    for (std::size_t k = 0; k < values.size(); ++k)
      if (!std::isfinite(values[k]))
        return fmt::format("{}: its {} ({} frame)", item(k), field, file);
  }
  for (const auto& [field, values] : fields.vectors) {
    for (std::size_t k = 0; k < values.size(); ++k)
      if (!values[k].allFinite()) return fmt::format("{}: its {} ({} frame)", item(k), field, file);
  }
  return std::nullopt;
}
template <class Name>
std::optional<std::string> non_finite_in(const std::vector<geometry::PolygonMesh>& meshes,
                                         const char* file, Name&& item) {
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    for (const Eigen::Vector3d& v : meshes[k].vertices)
      if (!v.allFinite())
        return fmt::format("{}: its place (a vertex of its mesh, {} frame)", item(k), file);
  }
  return std::nullopt;
}
template <class Name>
std::optional<std::string> non_finite_in(const io::BodyFrame& frame, const char* file,
                                         Name&& item) {
  if (auto bad = non_finite_in(frame.meshes, file, item)) return bad;
  return non_finite_in(frame.body_fields, file, item);
}
template <class Name>
std::optional<std::string> non_finite_in(const io::LinkFrame& frame, const char* file,
                                         Name&& item) {
  for (std::size_t k = 0; k < frame.a.size(); ++k) {
    if (!frame.a[k].allFinite() || (k < frame.b.size() && !frame.b[k].allFinite()))
      return fmt::format("{}: its end points ({} frame)", item(k), file);
  }
  return non_finite_in(frame.fields, file, item);
}

}  // namespace

FrameWriter::FrameWriter(fs::path out, const io::Scenario& scenario,
                         const geometry::Specimen& specimen)
    : out_(std::move(out)),
      scenario_(scenario),
      specimen_(specimen),
      bodies_(out_ / "bodies.pvd"),
      contacts_(out_ / "contacts.pvd"),
      bonds_(out_ / "bonds.pvd"),
      cell_(out_ / "cell.pvd"),
      walls_(out_ / "walls.pvd"),
      cracks_(out_ / "cracks.pvd") {}

bool FrameWriter::writes_cracks(const physics::FractureBook* book) const {
  return scenario_.bond.enabled || book != nullptr;
}

std::optional<std::string> FrameWriter::write(physics::World& world,
                                              const physics::FractureBook* book, bool root,
                                              bool gathered) {
  physics::Domain* domain = world.domain();
  if (domain && !gathered) domain->gather_all(world, true);  // the whole world, its contacts too
  // A second frame at the step of the last one (the bond stage right after the first
  // frame) replaces it: every series lists each time once.
  const bool again = frames_ > 0 && world.steps() == last_step_;
  // Built first, then checked, then written: a frame is written whole or not at all.
  std::optional<io::BodyFrame> bodies, walls, cracks;
  std::optional<io::LinkFrame> contacts, bonds, cell_edges;
  std::optional<std::string> bad;
  if (root) {  // several processes: the first writes the frames
    bodies = body_frame(world, specimen_);
    contacts = contact_frame(world);
    if (scenario_.bond.enabled) bonds = bond_frame(world);
    if (const physics::PeriodicCell* cell = world.cell()) cell_edges = cell_frame(*cell);
    if (writes_walls(world)) walls = io::wall_frame(world);
    if (writes_cracks(book)) cracks = io::crack_frame(world, book);
    const std::vector<physics::BodyId> ids = world.body_ids();
    auto body_name = [&](std::size_t row) {
      return row < ids.size()
                 ? fmt::format("body {} (grain {})", ids[row].index, world.info(ids[row]).grain_id)
                 : fmt::format("body row {}", row);
    };
    auto wall_name = [&](std::size_t row) {
      return row < world.walls().size()
                 ? fmt::format("wall {} ('{}')", row, world.walls()[row].name)
                 : fmt::format("wall row {}", row);
    };
    auto numbered = [](const char* what) {
      return [what](std::size_t row) { return fmt::format("{} {}", what, row); };
    };
    if (!bad && bodies) bad = non_finite_in(*bodies, "bodies", body_name);
    if (!bad && contacts) bad = non_finite_in(*contacts, "contacts", numbered("contact"));
    if (!bad && bonds) bad = non_finite_in(*bonds, "bonds", numbered("bond"));
    if (!bad && cell_edges) bad = non_finite_in(*cell_edges, "cell", numbered("cell edge"));
    if (!bad && walls) bad = non_finite_in(*walls, "walls", wall_name);
    // A crack face's broken_at_s is NaN on purpose for split sections (no bond broke): only
    // its place is checked.
    if (!bad && cracks) bad = non_finite_in(cracks->meshes, "cracks", numbered("crack face"));
  }
  if (domain && domain->any(bad.has_value())) bad = domain->first(bad);
  if (bad)
    return *bad +
           " is not finite (NaN or infinite) in the frame of this step, which is not written";
  if (root) {
    const std::string stem = fmt::format("{:06d}", again ? frames_ - 1 : frames_);
    const fs::path dir = "frames";
    auto put = [&](io::PvdSeries& pvd, const std::string& kind, const auto& frame) {
      const fs::path file = dir / (kind + "_" + stem + ".vtp");
      io::write_vtp(out_ / file, frame);
      pvd.add(world.time(), file);
    };
    put(bodies_, "bodies", *bodies);
    put(contacts_, "contacts", *contacts);
    if (bonds) put(bonds_, "bonds", *bonds);
    if (cell_edges) put(cell_, "cell", *cell_edges);
    if (walls) put(walls_, "walls", *walls);
    if (cracks) put(cracks_, "cracks", *cracks);
    if (scenario_.output.frame_meshes) write_meshes(world, book, stem);
  }
  if (!again) ++frames_;
  last_step_ = world.steps();
  return std::nullopt;
}

/// Every body as a mesh in its world pose, named by its lineage (grain_0017.1.0), in a
/// folder of the frame's own (frame_meshes/frame_NNNNNN/): per-fragment files of
/// different frames never meet.
void FrameWriter::write_meshes(const physics::World& world, const physics::FractureBook* book,
                               const std::string& stem) const {
  std::vector<geometry::PolygonMesh> meshes;
  for (const physics::BodyId id : world.body_ids()) {
    geometry::PolygonMesh mesh = world_mesh(world, id);
    mesh.name = book && book->knows(id) ? book->lineage(id).name()
                                        : geometry::Lineage{world.info(id).grain_id, {}}.name();
    meshes.push_back(std::move(mesh));
  }
  const fs::path folder = out_ / "frame_meshes" / ("frame_" + stem);
  fs::remove_all(folder);  // a frame rewritten at the same step, or after a restart
  io::write_meshes(meshes, folder, "frame_" + stem, scenario_.output.mesh_format,
                   scenario_.output.mesh_layout);
}

void FrameWriter::put_series(physics::StateWriter& w) const {
  for (const io::PvdSeries* pvd : {&bodies_, &contacts_, &bonds_, &cell_}) {
    w.count(pvd->entries().size());
    for (const auto& e : pvd->entries()) {
      w.put(e.time);
      w.put(e.file);
      w.put<std::int32_t>(e.part);
    }
  }
}

void FrameWriter::get_series(physics::StateReader& r, bool walls, bool cracks) {
  for (io::PvdSeries* pvd : {&bodies_, &contacts_, &bonds_, &cell_}) {
    std::vector<io::PvdSeries::Entry> entries(r.count(16));
    for (auto& e : entries) {
      e.time = r.get<double>();
      e.file = r.string();
      e.part = r.get<std::int32_t>();
    }
    pvd->restore(std::move(entries));
  }
  // The walls and cracks are written with every bodies frame (write): their lists are the
  // bodies' under their own names.
  for (auto [pvd, name, on] :
       {std::tuple{&walls_, "walls_", walls}, std::tuple{&cracks_, "cracks_", cracks}}) {
    if (!on) continue;
    std::vector<io::PvdSeries::Entry> entries = bodies_.entries();
    for (auto& e : entries) e.file.replace(e.file.find("bodies_"), 7, name);
    pvd->restore(std::move(entries));
  }
}

}  // namespace cleave::sim
