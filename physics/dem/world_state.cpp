// World checkpoints: save_state / load_state (bit-exact) and the state hash.

#include <cmath>
#include <cstring>
#include <string>

#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"

namespace cleave::physics {

namespace {

/// The layout of this file's records; a change in what is saved changes it, and the
/// checkpoint reader refuses other layouts.
// 2: contact manifolds; 3: orientations at the search; 4: temperatures; 5: beam bonds;
// 6: periodic cells; 7: expansion centres; 8: a bond break's face area; 9: each bond's
// stiffness factor.
constexpr std::uint32_t kWorldLayout = 9;

void put_params(StateWriter& w, const ContactParams& p) {
  for (double v : {p.kn, p.ks, p.kr, p.kt, p.c_res, p.mu_s, p.mu_r, p.damping_ratio}) w.put(v);
}
ContactParams get_params(StateReader& r) {
  ContactParams p;
  for (double* v : {&p.kn, &p.ks, &p.kr, &p.kt, &p.c_res, &p.mu_s, &p.mu_r, &p.damping_ratio}) {
    *v = r.get<double>();
  }
  return p;
}

void put_shape(StateWriter& w, const RigidShape& s) {
  w.put(s.volume);
  w.put(s.principal_moments);
  w.put(s.centroid);
  w.put(s.axes);
  const geometry::ContactPrimitives& p = s.primitives;
  w.put(p.origin);
  w.put(p.vertices);
  w.count(p.edges.size());
  for (const auto& e : p.edges) {
    for (int v : {e.a, e.b, e.left_face, e.right_face}) w.put<std::int32_t>(v);
  }
  w.count(p.faces.size());
  for (const auto& f : p.faces) {
    w.count(f.vertices.size());
    for (int v : f.vertices) w.put<std::int32_t>(v);
    w.put(f.normal);
    w.put(f.offset);
    w.put(f.centroid);
    w.put(f.area);
  }
  w.count(p.triangles.size());
  for (const auto& t : p.triangles) {
    for (int v : {t.v[0], t.v[1], t.v[2], t.face}) w.put<std::int32_t>(v);
  }
  w.put(p.dilation_radius);
  w.put(p.bounding_radius);
}

RigidShape get_shape(StateReader& r) {
  RigidShape s;
  s.volume = r.get<double>();
  s.principal_moments = r.vec3();
  s.centroid = r.vec3();
  s.axes = r.mat3();
  geometry::ContactPrimitives& p = s.primitives;
  p.origin = r.vec3();
  p.vertices = r.vec3s();
  const auto nv = static_cast<std::int32_t>(p.vertices.size());
  auto vertex = [&](std::int32_t v) {
    if (v < 0 || v >= nv) r.fail("a shape's vertex index is out of range");
    return static_cast<int>(v);
  };
  p.edges.resize(r.count(16));
  for (auto& e : p.edges) {
    e.a = vertex(r.get<std::int32_t>());
    e.b = vertex(r.get<std::int32_t>());
    e.left_face = r.get<std::int32_t>();
    e.right_face = r.get<std::int32_t>();
  }
  p.faces.resize(r.count(8));
  for (auto& f : p.faces) {
    f.vertices.resize(r.count(4));
    for (int& v : f.vertices) v = vertex(r.get<std::int32_t>());
    f.normal = r.vec3();
    f.offset = r.get<double>();
    f.centroid = r.vec3();
    f.area = r.get<double>();
  }
  p.triangles.resize(r.count(16));
  for (auto& t : p.triangles) {
    for (int& v : t.v) v = vertex(r.get<std::int32_t>());
    t.face = r.get<std::int32_t>();
  }
  p.dilation_radius = r.get<double>();
  p.bounding_radius = r.get<double>();
  if (!geometry::finish_primitives(p)) r.fail("a side of a shape's face is not one of its edges");
  return s;
}

void put_bond_state(StateWriter& w, const BondState& s) {
  w.put(s.normal);
  w.put(s.shear);
  w.put(s.bending);
  w.put(s.torsion);
  w.put(s.cohesive.phase);
  w.put(s.cohesive.psi_max);
  w.put(s.cohesive.lambda_max);
  // cohesive.dc and lambda_cr are not kept: bonds use the paper's initiation rule, under
  // which they stay 0 (BondParams has no other; the traction rule is the lattice's).
  w.put(s.broken);
}
BondState get_bond_state(StateReader& r) {
  BondState s;
  s.normal = r.get<double>();
  s.shear = r.vec3();
  s.bending = r.vec3();
  s.torsion = r.get<double>();
  s.cohesive.phase = r.get_enum(LinkPhase::contact);
  s.cohesive.psi_max = r.get<double>();
  s.cohesive.lambda_max = r.get<double>();
  s.broken = r.get_bool();
  return s;
}

/// FNV-1a over the bytes of values.
struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) {
      h ^= c[i];
      h *= 1099511628211ull;
    }
  }
  template <class T>
  void add(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof(T));
  }
  void add(const Eigen::Vector3d& v) { bytes(v.data(), 3 * sizeof(double)); }
  void add(const Eigen::Quaterniond& q) { bytes(q.coeffs().data(), 4 * sizeof(double)); }
};

void put_settings(StateWriter& w, const WorldSettings& settings) {
  // Settings (threads and the feature skin stay the loader's: results do not depend on them).
  w.put(settings.gravity);
  w.put(settings.dt);
  put_params(w, settings.particle_particle);
  put_params(w, settings.particle_wall);
  w.put(settings.search);
  w.put(settings.search_skin);
  w.put(settings.local_damping);
}

/// Shapes, bodies and their thermal records.
void put_bodies(StateWriter& w, const Bodies& bodies, const ThermalField& thermal) {
  w.count(bodies.shapes().size());
  for (const RigidShape& s : bodies.shapes()) put_shape(w, s);

  const std::vector<BodyState>& states = bodies.states();
  const std::vector<BodyInfo>& infos = bodies.infos();
  w.count(states.size());
  for (std::size_t i = 0; i < states.size(); ++i) {
    const BodyInfo& b = infos[i];
    w.put(b.shape);
    w.put(b.mass);
    w.put(b.inv_mass);
    w.put(b.inertia);
    w.put(b.inv_inertia);
    w.put<std::int32_t>(b.grain_id);
    w.put(b.generation);
    w.put(b.alive);
    w.put(b.fixed);
    const BodyState& s = states[i];
    for (const Eigen::Vector3d* v : {&s.x, &s.v, &s.L, &s.w, &s.f, &s.tau}) w.put(*v);
    w.put(s.q);
  }
  w.put(bodies.free_slots());
  w.put<std::uint64_t>(bodies.count());
  w.put(thermal.on());
  w.put(thermal.conductivity());
  w.put(thermal.heat_capacity());
  for (const BodyThermal& t : thermal.slots()) {
    w.put(t.temperature);
    w.put(t.bonded_at);
    w.put(t.alpha);
    w.put(t.held);
    w.put(t.shaped_at);
    w.put(t.centre);
  }
}

void put_walls(StateWriter& w, const std::vector<Wall>& walls) {
  w.count(walls.size());
  for (const Wall& wall : walls) {
    w.put(wall.kind);
    w.put(wall.name);
    for (const Eigen::Vector3d* v : {&wall.origin, &wall.normal, &wall.u, &wall.velocity, &wall.reaction,
                                     &wall.load_axis}) {
      w.put(*v);
    }
    for (double v : {wall.half_u, wall.half_v, wall.length, wall.radius}) w.put(v);
  }
}

/// The neighbour search's state, the periodic cell and the contact manifolds.
void put_search(StateWriter& w, const Contacts& contacts, const CellControl& cell, bool whole) {
  // The neighbour search's Verlet list: reused until a body moves half the skin.
  // One process of several (a domain) lists its own region's pairs only: its checkpoint,
  // read on any number of processes, searches afresh.
  w.put(whole && contacts.pairs_current());
  w.put(contacts.skin());
  w.put(whole ? contacts.searched_at() : std::vector<Eigen::Vector3d>{});
  w.count(whole ? contacts.searched_q().size() : 0);
  if (whole) {
    for (const Eigen::Quaterniond& q : contacts.searched_q()) w.put(q);
  }
  w.count(whole ? contacts.pairs().size() : 0);
  for (const auto& [i, j] : whole ? contacts.pairs() : std::vector<BodyPair>{}) {
    w.put(i);
    w.put(j);
  }
  // The periodic cell: its vectors, origin, axes, velocity gradient, the vectors at the last
  // search and each searched pair's image.
  w.put(cell.on());
  if (cell.on()) {
    for (const Eigen::Matrix3d* m :
         {&cell.cell().vectors(), &cell.cell().velocity_gradient(), &cell.at_search()}) {
      for (int c = 0; c < 3; ++c) w.put(Eigen::Vector3d(m->col(c)));
    }
    w.put(cell.cell().origin());
    for (bool periodic : cell.cell().periodic()) w.put(periodic);
    w.count(contacts.pair_images().size());
    for (const Eigen::Vector3i& n : contacts.pair_images()) {
      for (int c = 0; c < 3; ++c) w.put<std::int32_t>(n[c]);
    }
  }
  // The pairs' contact manifolds (manifold_tolerance > 0), so that a restart carries the
  // same contacts as the run it continues.
  w.put(contacts.manifold_slots());
  w.count(contacts.manifolds().size());
  for (const ContactManifold& m : contacts.manifolds()) {
    w.put(m.margin);
    w.put(m.lever);
    w.put(m.offset);
    w.put(m.turn);
    w.count(m.entries.size());
    for (const ContactManifold::Entry& e : m.entries) {
      w.put(e.feature_a);
      w.put(e.feature_b);
      w.put(e.point_a);
      w.put(e.point_b);
      w.put(e.normal_a);
      w.put(e.penetration);
    }
  }
}

void put_contacts(StateWriter& w, const std::vector<HistoryEntry>& history,
                  const std::vector<ContactRecord>& records, bool cell) {
  w.count(history.size());
  for (const HistoryEntry& e : history) {
    for (std::uint32_t k : {e.key.a, e.key.b, e.key.fa, e.key.fb}) w.put(k);
    w.put(e.history.shear);
    w.put(e.history.rolling);
    w.put(e.history.torsion);
    w.put(e.history.max_overlap);
  }
  w.count(records.size());
  for (const ContactRecord& c : records) {
    w.put(c.a);
    w.put(c.b);
    w.put(c.wall);
    w.put(c.point);
    w.put(c.normal);
    w.put(c.overlap);
    w.put(c.force);
    if (cell) w.put(c.shift);
  }
}

/// The bonds, the pairs' offsets, the bond parameters and the breaks.
void put_bonds(StateWriter& w, const Bonds& bonds, bool cell) {
  const bool beams = bonds.params().law == BondLaw::beam;
  w.put(beams);
  w.count(bonds.list().size());
  for (const Bond& bd : bonds.list()) {
    if (beams) {
      for (const Eigen::Vector3d* v : {&bd.beam.end_a, &bd.beam.end_b, &bd.beam.axis_a, &bd.beam.axis_b,
                                       &bd.beam.across_a, &bd.beam.across_b})
        w.put(*v);
      w.put(bd.beam.rest_length);
    }
    w.put(bd.a);
    w.put(bd.b);
    if (cell) {
      for (int c = 0; c < 3; ++c) w.put<std::int32_t>(bd.image[c]);
    }
    for (const Eigen::Vector3d* v : {&bd.arm_a, &bd.arm_b, &bd.normal_a, &bd.normal_b, &bd.point, &bd.normal,
                                     &bd.force, &bd.moment}) {
      w.put(*v);
    }
    w.put(bd.section.radius);
    w.put(bd.strength);
    w.put(bd.stiffness);
    w.put(bd.thermal_gap);
    w.put(bd.transmission);
    put_bond_state(w, bd.state);
    w.put(bd.failure);
    w.put(bd.broken_at);
    w.count(bd.initial.size());
    for (const Bond::Overlap& o : bd.initial) {
      w.put(o.fa);
      w.put(o.fb);
      w.put(o.overlap);
    }
  }
  w.count(bonds.offsets().size());
  for (const Bonds::PairOffset& o : bonds.offsets()) {
    w.put(o.a);
    w.put(o.b);
    w.put(o.overlap);
  }
  for (double v : {bonds.params().kbn, bonds.params().kbs, bonds.params().tbn, bonds.params().tbs,
                   bonds.params().sigma_c, bonds.params().g_c}) {
    w.put(v);
  }
  w.put(bonds.params().law);
  w.put(bonds.params().criterion);
  w.put(bonds.params().sigma_f);
  for (double v :
       {bonds.params().beam_young, bonds.params().beam_poisson, bonds.params().beam_radius})
    w.put(v);
  w.count(bonds.breaks().size());
  for (const BondBreak& b : bonds.breaks()) {
    w.put(b.time);
    w.put(b.step);
    w.put<std::uint64_t>(b.bond);
    w.put(b.a);
    w.put(b.b);
    w.put<std::int32_t>(b.grain_a);
    w.put<std::int32_t>(b.grain_b);
    w.put(b.point);
    w.put(b.normal);
    w.put(b.mode);
    put_bond_state(w, b.loads);
    w.put(b.face_area);
  }
}

WorldSettings get_settings(StateReader& r, const WorldSettings& mine) {
  WorldSettings ws;
  ws.threads = mine.threads;
  ws.feature_skin = mine.feature_skin;
  ws.manifold_tolerance = mine.manifold_tolerance;  // a choice of this run, as the skin
  ws.in_plane = mine.in_plane;                      // and the same
  ws.gravity = r.vec3();
  ws.dt = r.get<double>();
  ws.particle_particle = get_params(r);
  ws.particle_wall = get_params(r);
  ws.search = r.get_enum(SearchMethod::bounding_box);
  ws.search_skin = r.get<double>();
  ws.local_damping = r.get<double>();
  if (!(ws.dt > 0.0)) r.fail("the time step is not positive");
  return ws;
}

struct LoadedBodies {
  std::vector<RigidShape> shapes;
  std::vector<BodyState> states;
  std::vector<BodyInfo> infos;
  std::vector<std::uint32_t> free_slots;
  std::uint64_t live;
  bool thermal_on;
  double conductivity, heat_capacity;
  std::vector<BodyThermal> thermal;
};
LoadedBodies get_bodies(StateReader& r) {
  std::vector<RigidShape> shapes(r.count(8));
  for (RigidShape& s : shapes) s = get_shape(r);

  const std::size_t slots = r.count(8);
  std::vector<BodyState> states(slots);
  std::vector<BodyInfo> infos(slots);
  for (std::size_t i = 0; i < slots; ++i) {
    BodyInfo& b = infos[i];
    b.shape = r.get<std::uint32_t>();
    if (b.shape >= shapes.size()) r.fail("a body's shape index is out of range");
    b.mass = r.get<double>();
    b.inv_mass = r.get<double>();
    b.inertia = r.vec3();
    b.inv_inertia = r.vec3();
    b.grain_id = r.get<std::int32_t>();
    b.generation = r.get<std::uint32_t>();
    b.alive = r.get_bool();
    b.fixed = r.get_bool();
    BodyState& s = states[i];
    for (Eigen::Vector3d* v : {&s.x, &s.v, &s.L, &s.w, &s.f, &s.tau}) *v = r.vec3();
    s.q = r.quat();
  }
  std::vector<std::uint32_t> free_slots = r.numbers<std::uint32_t>();
  const auto live = r.get<std::uint64_t>();
  const bool thermal_on = r.get_bool();
  const double conductivity = r.get<double>(), heat_capacity = r.get<double>();
  if (!(conductivity >= 0.0) || !std::isfinite(conductivity) || !std::isfinite(heat_capacity) ||
      (conductivity > 0.0 && !(heat_capacity > 0.0)))
    r.fail("the conductivity or heat capacity is out of range");
  std::vector<BodyThermal> thermal(slots);
  for (BodyThermal& t : thermal) {
    t.temperature = r.get<double>();
    t.bonded_at = r.get<double>();
    t.alpha = r.mat3();
    t.held = r.get_bool();
    t.shaped_at = r.get<double>();
    t.centre = r.vec3();
    if (!std::isfinite(t.temperature) || !std::isfinite(t.bonded_at) || !t.alpha.allFinite() ||
        !std::isfinite(t.shaped_at) || !t.centre.allFinite())
      r.fail("a body's temperature or expansion is not finite");
  }
  std::size_t alive = 0;
  for (const BodyInfo& b : infos) alive += b.alive ? 1 : 0;
  if (alive != live) r.fail("the live body count does not match the bodies");
  for (std::uint32_t f : free_slots) {
    if (f >= slots || infos[f].alive) r.fail("a free slot holds a live body");
  }
  return {std::move(shapes), std::move(states), std::move(infos), std::move(free_slots), live,
          thermal_on,        conductivity,      heat_capacity,    std::move(thermal)};
}

std::vector<Wall> get_walls(StateReader& r) {
  std::vector<Wall> walls(r.count(8));
  for (Wall& wall : walls) {
    wall.kind = r.get_enum(Wall::Kind::cylinder);
    wall.name = r.string();
    for (Eigen::Vector3d* v : {&wall.origin, &wall.normal, &wall.u, &wall.velocity, &wall.reaction,
                               &wall.load_axis}) {
      *v = r.vec3();
    }
    for (double* v : {&wall.half_u, &wall.half_v, &wall.length, &wall.radius}) *v = r.get<double>();
  }
  return walls;
}

struct LoadedSearch {
  Contacts::SearchState search;
  bool cell_on;
  PeriodicCell cell;
  Eigen::Matrix3d cell_at_search;
};
LoadedSearch get_search(StateReader& r) {
  const bool pairs_current = r.get_bool();
  const double skin = r.get<double>();
  std::vector<Eigen::Vector3d> searched_at = r.vec3s();
  std::vector<Eigen::Quaterniond> searched_q(r.count(4 * sizeof(double)));
  for (Eigen::Quaterniond& q : searched_q) q = r.quat();
  if (searched_q.size() != searched_at.size()) r.fail("the search's orientations are not one per centre");
  std::vector<BodyPair> pairs(r.count(8));
  for (auto& [i, j] : pairs) {
    i = r.get<std::uint32_t>();
    j = r.get<std::uint32_t>();
    if (i >= searched_at.size() || j >= searched_at.size()) r.fail("a searched pair is out of range");
  }
  const bool cell_on = r.get_bool();
  PeriodicCell cell;
  Eigen::Matrix3d cell_at_search = Eigen::Matrix3d::Zero();
  std::vector<Eigen::Vector3i> pair_image;
  if (cell_on) {
    Eigen::Matrix3d h, l;
    for (Eigen::Matrix3d* m : {&h, &l, &cell_at_search}) {
      for (int c = 0; c < 3; ++c) m->col(c) = r.vec3();
    }
    const Eigen::Vector3d origin = r.vec3();
    std::array<bool, 3> periodic{};
    for (bool& p : periodic) p = r.get_bool();
    if (!h.allFinite() || !(std::abs(h.determinant()) > 0.0) || !l.allFinite() || !origin.allFinite())
      r.fail("the periodic cell is not a finite cell with a volume");
    cell = PeriodicCell(h, origin, periodic);
    cell.set_velocity_gradient(l);
    pair_image.resize(r.count(12));
    if (pair_image.size() != pairs.size()) r.fail("the pairs' images are not one per pair");
    for (Eigen::Vector3i& n : pair_image) {
      for (int c = 0; c < 3; ++c) n[c] = r.get<std::int32_t>();
    }
  }
  std::vector<std::uint32_t> manifold_slots = r.numbers<std::uint32_t>();
  std::vector<ContactManifold> manifolds(r.count(8));
  if (!manifolds.empty() && manifolds.size() != pairs.size()) r.fail("the contact manifolds are not one per pair");
  for (ContactManifold& m : manifolds) {
    m.margin = r.get<double>();
    m.lever = r.get<double>();
    m.offset = r.vec3();
    m.turn = r.quat();
    m.entries.resize(r.count(8));
    for (ContactManifold::Entry& e : m.entries) {
      e.feature_a = r.get<std::uint32_t>();
      e.feature_b = r.get<std::uint32_t>();
      e.point_a = r.vec3();
      e.point_b = r.vec3();
      e.normal_a = r.vec3();
      e.penetration = r.get<double>();
    }
  }
  return {{pairs_current, skin, std::move(searched_at), std::move(searched_q), std::move(pairs),
           std::move(pair_image), std::move(manifold_slots), std::move(manifolds)},
          cell_on,
          cell,
          cell_at_search};
}

struct LoadedContacts {
  std::vector<HistoryEntry> history;
  std::vector<ContactRecord> records;
};
LoadedContacts get_contacts(StateReader& r, std::size_t slots, std::size_t walls, bool cell_on) {
  auto slot = [&](std::uint32_t s) {
    if (s >= slots) r.fail("a body slot is out of range");
    return s;
  };
  std::vector<HistoryEntry> history(r.count(16));
  for (HistoryEntry& e : history) {
    e.key.a = r.get<std::uint32_t>();
    e.key.b = slot(r.get<std::uint32_t>());
    e.key.fa = r.get<std::uint32_t>();
    e.key.fb = r.get<std::uint32_t>();
    e.history.shear = r.vec3();
    e.history.rolling = r.vec3();
    e.history.torsion = r.get<double>();
    e.history.max_overlap = r.get<double>();
  }
  std::vector<ContactRecord> records(r.count(8));
  for (ContactRecord& c : records) {
    c.a = r.get<std::uint32_t>();
    c.b = slot(r.get<std::uint32_t>());
    c.wall = r.get_bool();
    if (c.wall ? c.a >= walls : c.a >= slots) r.fail("a contact's body or wall is out of range");
    c.point = r.vec3();
    c.normal = r.vec3();
    c.overlap = r.get<double>();
    c.force = r.vec3();
    if (cell_on) c.shift = r.vec3();
  }
  return {std::move(history), std::move(records)};
}

struct LoadedBonds {
  std::vector<Bond> bonds;
  std::vector<Bonds::PairOffset> offsets;
  BondParams params;
  std::vector<BondBreak> breaks;
};
LoadedBonds get_bonds(StateReader& r, std::size_t slots, bool cell_on, const PeriodicCell& cell) {
  auto slot = [&](std::uint32_t s) {
    if (s >= slots) r.fail("a body slot is out of range");
    return s;
  };
  const bool beams = r.get_bool();
  std::vector<Bond> bonds(r.count(8));
  for (Bond& bd : bonds) {
    if (beams) {
      for (Eigen::Vector3d* v : {&bd.beam.end_a, &bd.beam.end_b, &bd.beam.axis_a, &bd.beam.axis_b,
                                 &bd.beam.across_a, &bd.beam.across_b})
        *v = r.vec3();
      bd.beam.rest_length = r.get<double>();
      if (!(bd.beam.rest_length > 0.0)) r.fail("a beam's rest length is not positive");
    }
    bd.a = slot(r.get<std::uint32_t>());
    bd.b = slot(r.get<std::uint32_t>());
    if (cell_on) {
      for (int c = 0; c < 3; ++c) bd.image[c] = r.get<std::int32_t>();
      bd.shift = cell.shift(bd.image);
    }
    for (Eigen::Vector3d* v : {&bd.arm_a, &bd.arm_b, &bd.normal_a, &bd.normal_b, &bd.point, &bd.normal,
                               &bd.force, &bd.moment}) {
      *v = r.vec3();
    }
    bd.section.radius = r.get<double>();
    bd.strength = r.get<double>();
    bd.stiffness = r.get<double>();
    bd.thermal_gap = r.get<double>();
    bd.transmission = r.get<double>();
    if (!(bd.strength > 0.0)) r.fail("a bond's strength factor is not positive");
    if (!(bd.stiffness > 0.0) || !std::isfinite(bd.stiffness))
      r.fail("a bond's stiffness factor is not positive and finite");
    bd.state = get_bond_state(r);
    bd.failure = r.get_enum(BondFailure::torsion);
    bd.broken_at = r.get<double>();
    bd.initial.resize(r.count(16));
    for (Bond::Overlap& o : bd.initial) {
      o.fa = r.get<std::uint32_t>();
      o.fb = r.get<std::uint32_t>();
      o.overlap = r.get<double>();
    }
  }
  std::vector<Bonds::PairOffset> offsets(r.count(16));
  for (Bonds::PairOffset& o : offsets) {
    o.a = slot(r.get<std::uint32_t>());
    o.b = slot(r.get<std::uint32_t>());
    o.overlap = r.get<double>();
  }
  BondParams bp;
  for (double* v : {&bp.kbn, &bp.kbs, &bp.tbn, &bp.tbs, &bp.sigma_c, &bp.g_c}) *v = r.get<double>();
  bp.law = r.get_enum(BondLaw::beam);
  bp.criterion = r.get_enum(BondCriterion::hydrostatic);
  bp.sigma_f = r.get<double>();
  for (double* v : {&bp.beam_young, &bp.beam_poisson, &bp.beam_radius}) *v = r.get<double>();
  if (beams != (bp.law == BondLaw::beam)) r.fail("the bonds' beams and the bond law disagree");
  std::vector<BondBreak> breaks(r.count(8));
  for (BondBreak& b : breaks) {
    b.time = r.get<double>();
    b.step = r.get<std::uint64_t>();
    b.bond = r.get<std::uint64_t>();
    b.a = r.get<std::uint32_t>();
    b.b = r.get<std::uint32_t>();
    b.grain_a = r.get<std::int32_t>();
    b.grain_b = r.get<std::int32_t>();
    b.point = r.vec3();
    b.normal = r.vec3();
    b.mode = r.get_enum(BondFailure::torsion);
    b.loads = get_bond_state(r);
    b.face_area = r.get<double>();
  }
  return {std::move(bonds), std::move(offsets), bp, std::move(breaks)};
}

}  // namespace

void World::save_state(StateWriter& w) const {
  w.put(kWorldLayout);
  put_settings(w, settings_);
  put_bodies(w, bodies_, thermal_);
  put_walls(w, walls_);
  // One process of several (a domain) lists its own region's pairs only: its checkpoint,
  // read on any number of processes, searches afresh.
  put_search(w, contacts_, cell_, bodies_.roles().empty());
  put_contacts(w, contacts_.histories(), contacts(), cell_.on());
  put_bonds(w, bonds_, cell_.on());
  w.put(time_);
  w.put(steps_);
  w.put(forces_current_);
}

void World::load_state(StateReader& r) {
  if (const auto layout = r.get<std::uint32_t>(); layout != kWorldLayout) {
    r.fail("world layout " + std::to_string(layout) + " is not supported (this build reads " +
           std::to_string(kWorldLayout) + ")");
  }
  const WorldSettings ws = get_settings(r, settings_);
  LoadedBodies b = get_bodies(r);
  const std::size_t slots = b.states.size();
  std::vector<Wall> walls = get_walls(r);
  LoadedSearch s = get_search(r);
  LoadedContacts c = get_contacts(r, slots, walls.size(), s.cell_on);
  LoadedBonds bd = get_bonds(r, slots, s.cell_on, s.cell);
  const double time = r.get<double>();
  const auto steps = r.get<std::uint64_t>();
  const bool forces_current = r.get_bool();

  // All read: replace the state.
  settings_ = ws;
  bodies_.restore(std::move(b.shapes), std::move(b.states), std::move(b.infos),
                  std::move(b.free_slots), b.live);
  thermal_.restore(std::move(b.thermal), b.thermal_on, b.conductivity, b.heat_capacity);
  walls_ = std::move(walls);
  cell_.restore(s.cell_on, s.cell, s.cell_at_search);
  bonds_.restore(std::move(bd.bonds), std::move(bd.offsets), bd.params, std::move(bd.breaks));
  contacts_.restore(settings_.search, std::move(s.search), std::move(c.history),
                    std::move(c.records), bodies_);
  time_ = time;
  steps_ = steps;
  forces_current_ = forces_current;
}

std::uint64_t World::state_hash() const {
  Fnv h;
  const std::vector<BodyState>& states = bodies_.states();
  const std::vector<BodyInfo>& infos = bodies_.infos();
  const std::vector<BodyThermal>& thermal = thermal_.slots();
  h.add(time_);
  h.add(steps_);
  for (std::uint32_t i = 0; i < states.size(); ++i) {
    if (!infos[i].alive) continue;
    const BodyState& s = states[i];
    h.add(i);
    h.add(infos[i].generation);
    h.add(infos[i].shape);
    for (const Eigen::Vector3d* v : {&s.x, &s.v, &s.L, &s.w, &s.f, &s.tau}) h.add(*v);
    h.add(s.q);
  }
  for (const Wall& w : walls_) {
    h.add(w.origin);
    h.add(w.velocity);
    h.add(w.reaction);
  }
  for (const Bond& bd : bonds_.list()) {
    h.add(bd.a);
    h.add(bd.b);
    h.add(bd.state.normal);
    h.add(bd.state.shear);
    h.add(bd.state.bending);
    h.add(bd.state.torsion);
    h.add(bd.state.broken);
    h.add(bd.failure);
  }
  for (const HistoryEntry& e : contacts_.histories()) {
    h.add(e.key.a);
    h.add(e.key.b);
    h.add(e.key.fa);
    h.add(e.key.fb);
    h.add(e.history.shear);
    h.add(e.history.rolling);
    h.add(e.history.torsion);
    h.add(e.history.max_overlap);
  }
  for (const Bonds::PairOffset& o : bonds_.offsets()) {
    h.add(o.a);
    h.add(o.b);
    h.add(o.overlap);
  }
  if (thermal_.on() || thermal_.conductivity() > 0.0) {  // (left out otherwise: hashes as before)
    for (std::uint32_t i = 0; i < thermal.size(); ++i) {
      if (!infos[i].alive) continue;
      h.add(thermal[i].temperature);
      h.add(thermal[i].bonded_at);
    }
    for (const Bond& bd : bonds_.list()) h.add(bd.thermal_gap);
  }
  if (bonds_.params().law == BondLaw::beam) {
    for (const Bond& bd : bonds_.list()) h.add(bd.beam.rest_length);
  }
  if (cell_.on()) {
    for (int c = 0; c < 3; ++c) h.add(Eigen::Vector3d(cell_.cell().vectors().col(c)));
    for (const Bond& bd : bonds_.list()) h.add(bd.shift);
  }
  return h.h;
}

}  // namespace cleave::physics
