#include "physics/transgranular/transgranular.hpp"
#include "physics/bonds/grain_stress.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <exception>
#include <omp.h>
#include <limits>
#include <optional>
#include <span>
#include <cmath>

namespace cleave::physics {

namespace {

/// A body's faces in the world, with the contact and bond forces acting on each.
struct PosedFaces {
  std::vector<std::vector<Eigen::Vector3d>> polygons;
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> offsets;
  std::vector<std::vector<PointForce>> forces;
  std::vector<Eigen::Vector3d> vertices;
  const geometry::ContactPrimitives* primitives = nullptr;
};

/// The body's faces posed into `out`, whose storage is kept from call to call (the check
/// poses every body past its gate: a few dozen allocations each, otherwise).
void pose_faces(const World& world, BodyId id, PosedFaces& out) {
  const BodyState& s = world.state(id);
  const auto& p = world.shape(world.info(id).shape).primitives;
  out.primitives = &p;
  out.vertices.clear();
  for (const auto& v : p.vertices) out.vertices.push_back(s.x + s.q * v);
  out.polygons.resize(p.faces.size());
  out.normals.clear();
  out.offsets.clear();
  for (std::size_t k = 0; k < p.faces.size(); ++k) {
    const auto& f = p.faces[k];
    std::vector<Eigen::Vector3d>& polygon = out.polygons[k];
    polygon.clear();
    for (int v : f.vertices) polygon.push_back(out.vertices[static_cast<std::size_t>(v)]);
    const Eigen::Vector3d n = s.q * f.normal;
    out.normals.push_back(n);
    out.offsets.push_back(n.dot(polygon.front()));
  }
  out.forces.resize(p.faces.size());
  for (auto& list : out.forces) list.clear();
}

/// The face a point acts on: the one it lies farthest out from (see the header), of the
/// faces that have an area in doubles (`flat[f]` marks those that have none).
std::size_t face_of(const PosedFaces& faces, const Eigen::Vector3d& point, const std::vector<char>& flat) {
  std::size_t best = 0;
  double out = -std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < faces.normals.size(); ++f) {
    if (flat[f]) continue;
    const double d = faces.normals[f].dot(point) - faces.offsets[f];
    if (d > out) {
      out = d;
      best = f;
    }
  }
  return best;
}

/// The section of the body by the plane, into `points`: where its edges cross it, in order
/// around the section. Empty when the plane misses the body.
void section(const PosedFaces& faces, const CrackPlane& plane, std::vector<Eigen::Vector3d>& points) {
  points.clear();
  auto add = [&](const Eigen::Vector3d& p) {
    for (const auto& q : points) {
      if ((p - q).squaredNorm() < 1e-24) return;
    }
    points.push_back(p);
  };
  for (const auto& e : faces.primitives->edges) {
    const Eigen::Vector3d& a = faces.vertices[static_cast<std::size_t>(e.a)];
    const Eigen::Vector3d& b = faces.vertices[static_cast<std::size_t>(e.b)];
    const double da = (a - plane.point).dot(plane.normal), db = (b - plane.point).dot(plane.normal);
    if (da == 0.0) add(a);
    if (db == 0.0) add(b);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) add(a + (b - a) * (da / (da - db)));
  }
  if (points.size() < 3) {
    points.clear();
    return;
  }
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : points) c += p / static_cast<double>(points.size());
  const Eigen::Vector3d u = (points.front() - c).normalized();
  const Eigen::Vector3d v = plane.normal.cross(u);
  std::sort(points.begin(), points.end(), [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    return std::atan2((p - c).dot(v), (p - c).dot(u)) < std::atan2((q - c).dot(v), (q - c).dot(u));
  });
}

}  // namespace

namespace {

int check_threads(const World& world) {
  const int wanted = world.settings().threads;
  return wanted > 0 ? wanted : omp_get_max_threads();
}

/// Eq. 2.17 from the body's sum of (point - centroid) (x) force (World::stress_sums).
Eigen::Matrix3d stress_from(const World& world, std::uint32_t slot, const Eigen::Matrix3d& sum) {
  return stress_from_sum(sum, world.shape(world.slot_infos()[slot].shape).volume);
}

/// The forces acting on a body (World::forces_on) as the traction code takes them.
std::span<const PointForce> forces_of(const World& world, std::uint32_t slot, std::vector<World::AppliedForce>& applied,
                                      std::vector<PointForce>& out) {
  world.forces_on(slot, applied);
  out.clear();
  for (const auto& f : applied) out.push_back({f.point, f.force});
  return out;
}

/// The body's rigid motion now, for its fragments' d'Alembert terms (see the header): a_G
/// and alpha from the forces `acting` on its faces and gravity, omega the step's.
RigidMotion rigid_motion(const World& world, BodyId id, std::span<const PointForce> acting) {
  const BodyState& s = world.state(id);
  const BodyInfo& b = world.info(id);
  RigidMotion m;
  m.centroid = s.x;
  m.omega = s.w;
  m.gravity = world.settings().gravity;
  if (b.fixed) {
    m.acceleration = Eigen::Vector3d::Zero();
    return m;  // prescribed, unaccelerated motion
  }
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  for (const PointForce& f : acting) {
    force += f.force;
    torque += (f.point - s.x).cross(f.force);
  }
  m.acceleration = force / b.mass + m.gravity;
  if (world.settings().in_plane) {
    m.acceleration.z() = 0.0;
    torque.x() = torque.y() = 0.0;
  }
  // Euler's equations in the principal frame: I alpha = tau - omega x (I omega).
  const Eigen::Vector3d w = s.q.conjugate() * s.w, t = s.q.conjugate() * torque;
  const Eigen::Vector3d iw = b.inertia.cwiseProduct(w);
  m.alpha = s.q * (t - w.cross(iw)).cwiseProduct(b.inv_inertia);
  if (world.settings().in_plane) m.alpha.x() = m.alpha.y() = 0.0;
  return m;
}

/// `acting()`: the forces on the body, asked for only past the gate.
template <class Acting>
std::vector<CrackAssessment> assess_with(const World& world, const FractureBook& book, BodyId id,
                                         const FractureParams& params, const Eigen::Matrix3d& sigma,
                                         Acting&& acting) {
  std::vector<CrackAssessment> out;
  if (!book.knows(id)) return out;
  if (params.criterion != GrainCriterion::lefm) {
    // A stress criterion: the grain's stress alone decides; it cleaves on the candidate
    // plane that carries the largest normal stress n^T sigma n.
    double value = sigma.trace() / 3.0;
    if (params.criterion == GrainCriterion::rankine) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(sigma, Eigen::EigenvaluesOnly);
      value = solver.eigenvalues().maxCoeff();
    }
    if (!(value > params.sigma_f)) return out;
    // A plane of resistance r (its family's strength over sigma_f) is open once the value
    // passes r sigma_f; of those, the one whose normal stress is the largest share of its
    // strength is cut (with every r = 1: the largest normal stress).
    CrackAssessment best;
    double most = -std::numeric_limits<double>::infinity(), most_share = most, best_r = 1.0;
    for (const int k : book.candidates(id)) {
      const double r = book.resistance(k);
      if (!(value > r * params.sigma_f)) continue;
      const Eigen::Vector3d n = book.world_plane(world, id, k).first;
      const double normal = n.dot(sigma * n);
      const double share = r == 1.0 ? normal : normal / r;
      if (share > most_share) {
        most_share = share;
        most = normal;
        best_r = r;
        best.plane = k;
      }
    }
    if (best.plane < 0) return out;
    best.id = id;
    best.result.mean_stress = sigma.trace() / 3.0;
    best.result.gate = true;
    best.result.criterion = value / (best_r * params.sigma_f);
    best.result.fails = true;
    best.stresses.sigma = most;
    out.push_back(best);
    return out;
  }
  // Eq. 3.22 first: below the hydrostatic gate no plane is worth the work.
  if (!(sigma.trace() / 3.0 >= params.sigma_f_hyd)) return out;
  const std::vector<int>& candidates = book.candidates(id);
  if (candidates.empty()) return out;

  // Scratch kept by each thread from body to body.
  thread_local PosedFaces faces;
  thread_local std::vector<FaceGeometry> geometry;
  thread_local std::vector<FaceTractions> tractions;
  thread_local std::vector<Eigen::Vector3d> cut;
  thread_local std::vector<FaceLoad> loads;
  thread_local std::vector<Eigen::Vector3d> part;
  thread_local std::vector<char> flat;
  pose_faces(world, id, faces);
  // A sliver face of an exact piece can round to no area in doubles: it carries nothing,
  // and the forces go to the faces around it.
  geometry.clear();
  flat.assign(faces.polygons.size(), 0);
  for (std::size_t f = 0; f < faces.polygons.size(); ++f) {
    const auto& poly = faces.polygons[f];
    try {
      geometry.push_back(face_geometry(poly, faces.normals[f], poly[1] - poly[0]));
    } catch (const std::invalid_argument&) {
      geometry.emplace_back();
      flat[f] = 1;
    }
  }
  const std::span<const PointForce> forces = acting();
  for (const PointForce& f : forces) faces.forces[face_of(faces, f.point, flat)].push_back(f);
  // Eq. 3.15 on every face.
  tractions.clear();
  for (std::size_t f = 0; f < faces.polygons.size(); ++f) {
    tractions.push_back(flat[f] ? FaceTractions{} : face_tractions(geometry[f], faces.forces[f]));
  }
  const Eigen::Vector3d centroid = world.state(id).x;
  RigidMotion motion;
  double rho = 0.0;
  if (params.inertia) {
    motion = rigid_motion(world, id, forces);
    rho = world.info(id).mass / world.shape(world.info(id).shape).volume;
  }
  for (const int k : candidates) {
    const auto [normal, point] = book.world_plane(world, id, k);
    const CrackPlane plane{point, normal};
    section(faces, plane, cut);
    if (cut.empty()) continue;
    // Eq. 3.20 for the faces (or parts of faces) behind the plane, then eq. 3.21.
    // Each face clipped once, for its load and (with inertia) the fragment's mass sum.
    loads.clear();
    SolidMassSum mass = params.inertia ? fragment_mass_sum(cut, plane) : SolidMassSum(plane.point);
    for (std::size_t f = 0; f < faces.polygons.size(); ++f) {
      if (flat[f]) {
        loads.emplace_back();
        continue;
      }
      clip_polygon_into(faces.polygons[f], plane, part);
      loads.push_back(part_load(geometry[f], tractions[f], part));
      if (params.inertia) mass.add_face(part, faces.normals[f]);
    }
    CrackPlaneLoad load;
    try {
      if (params.inertia) {
        /// Eq. 3.8's m a for the fragment, with its dH/dt about its own centroid (sec. 3.3).
        mass.add_face(cut, plane.normal);
        const SolidMass fragment = mass.result();
        load = crack_plane_load(loads, fragment.centroid, cut, plane, cut[1] - cut[0],
                                fragment_inertia(motion, rho, fragment));
      } else {
        load = crack_plane_load(loads, centroid, cut, plane, cut[1] - cut[0]);
      }
    } catch (const std::invalid_argument&) {
      continue;  // the plane grazes the body: a section with no area in doubles carries nothing
    }
    CrackAssessment a;
    a.id = id;
    a.plane = k;
    a.section_force = load.force;
    a.section_moment = load.moment;
    a.stresses = beam_stresses(load);
    const double r = book.resistance(k);
    if (r == 1.0) {
      a.result = fracture_check(params, sigma, a.stresses);
    } else {
      // The plane's family has its own toughness (eq. 3.25 with its K_Ic).
      FractureParams own = params;
      own.k_ic *= r;
      a.result = fracture_check(own, sigma, a.stresses);
    }
    out.push_back(a);
  }
  return out;
}

}  // namespace

double mean_stress_from_diagonal(const Eigen::Vector3d& diagonal, double volume) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  sum.diagonal() = diagonal;
  // Not evaluated: the trace asks the expression for its three diagonal coefficients
  // alone (three divisions, not nine), each the evaluated matrix's, summed as it would be.
  return ((sum + sum.transpose()) / (2.0 * volume)).trace() / 3.0;
}

std::vector<CrackAssessment> assess(const World& world, const FractureBook& book, BodyId id,
                                    const FractureParams& params,
                                    const std::vector<Eigen::Matrix3d>& stresses) {
  std::vector<World::AppliedForce> applied;
  std::vector<PointForce> acting;
  return assess_with(world, book, id, params, stresses.at(id.index),
                     [&] { return forces_of(world, id.index, applied, acting); });
}

std::vector<TransgranularEvent> transgranular_step(World& world, FractureBook& book,
                                                   const FractureParams& params) {
  std::vector<TransgranularEvent> events;
  if (world.body_count() == 0) return events;
  // The gate reads a body's mean stress, the trace of eq. 2.17's: from the diagonals of the
  // sums (summed with the forces when this check asked for them at its last call,
  // StepNeeds::stress_sums). Past it, the body's whole sum and then its forces.
  const std::vector<Eigen::Vector3d>& diagonals = world.stress_sum_diagonals();
  // Decide on the state of this step for every body (each on its own, in parallel: the
  // world and the book are only read), then cut, in body order: each thread lists the
  // failing bodies of its blocks of slots, and the lists are merged by slot.
  const auto slots = static_cast<std::ptrdiff_t>(world.slot_states().size());
  const int nt = slots >= 512 ? check_threads(world) : 1;
  std::vector<std::vector<CrackAssessment>> found_by(static_cast<std::size_t>(nt));
  // An exception may not leave a parallel region (the process would terminate): each thread
  // keeps the first it meets, with its slot, and the lowest slot's is thrown after.
  std::vector<std::pair<std::uint32_t, std::exception_ptr>> failed_by(static_cast<std::size_t>(nt));
#pragma omp parallel num_threads(nt) if (nt > 1)
  {
    std::vector<World::AppliedForce> applied;
    std::vector<PointForce> acting;
    std::vector<CrackAssessment>& mine = found_by[static_cast<std::size_t>(omp_get_thread_num())];
    auto& failed = failed_by[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t k = 0; k < slots; ++k) {
      const auto slot = static_cast<std::uint32_t>(k);
      if (failed.second || !world.slot_infos()[slot].alive) continue;
      try {
      // The gate first: it reads the step's small arrays, the book's record (a cache line
      // of its own) only past it.
      if (params.criterion != GrainCriterion::rankine) {
        // The sum's diagonal gives the trace (the bits of stress_from's, as assess_with reads it).
        const double mean =
            mean_stress_from_diagonal(diagonals[slot], world.shape(world.slot_infos()[slot].shape).volume);
        if (params.criterion == GrainCriterion::lefm ? !(mean >= params.sigma_f_hyd) : !(mean > params.sigma_f))
          continue;  // below the gate (eq. 3.22) or the hydrostatic criterion: as assess_with decides
      }
      const BodyId id{slot, world.slot_infos()[slot].generation};
      if (!book.knows(id) || !world.owns(slot)) continue;  // one process of several: its own bodies
      std::optional<CrackAssessment> worst;
      for (const auto& a : assess_with(world, book, id, params, stress_from(world, slot, world.stress_sum(slot)),
                                       [&] { return forces_of(world, slot, applied, acting); })) {
        if (a.result.fails && (!worst || a.result.criterion > worst->result.criterion)) worst = a;
      }
      if (worst) mine.push_back(*worst);
      } catch (...) {
        failed = {slot, std::current_exception()};
      }
    }
  }
  const std::pair<std::uint32_t, std::exception_ptr>* first = nullptr;
  for (const auto& f : failed_by) {
    if (f.second && (first == nullptr || f.first < first->first)) first = &f;
  }
  if (first != nullptr) std::rethrow_exception(first->second);
  std::vector<CrackAssessment> failing;
  for (const auto& list : found_by) failing.insert(failing.end(), list.begin(), list.end());
  std::sort(failing.begin(), failing.end(),
            [](const CrackAssessment& p, const CrackAssessment& q) { return p.id.index < q.id.index; });
  if (Domain* domain = world.domain()) {
    // Several processes: each decided for its own bodies; every process makes every split,
    // in body order, from the owner's state of the parent (the same slots everywhere).
    std::vector<char> mine;
    auto put = [&mine](const auto& v) {
      const auto* p = reinterpret_cast<const char*>(&v);
      mine.insert(mine.end(), p, p + sizeof v);
    };
    for (const CrackAssessment& a : failing) {
      put(a);
      put(world.state(a.id));
    }
    std::vector<std::pair<CrackAssessment, BodyState>> all;
    for (const std::vector<char>& part : domain->all_gather(mine)) {
      constexpr std::size_t kOne = sizeof(CrackAssessment) + sizeof(BodyState);
      if (part.size() % kOne != 0) throw std::logic_error("transgranular_step: a split message is cut short");
      for (std::size_t at = 0; at < part.size(); at += kOne) {
        auto& [a, s] = all.emplace_back();
        std::memcpy(static_cast<void*>(&a), part.data() + at, sizeof a);
        std::memcpy(static_cast<void*>(&s), part.data() + at + sizeof a, sizeof s);
      }
    }
    std::sort(all.begin(), all.end(), [](const auto& p, const auto& q) { return p.first.id.index < q.first.id.index; });
    failing.clear();
    for (const auto& [a, s] : all) {
      world.state(a.id) = s;
      failing.push_back(a);
    }
  }
  for (const CrackAssessment& a : failing) {
    SplitEvent split = book.split(world, a.id, a.plane);
    if (!split.ids.empty()) events.push_back({std::move(split), a});
  }
  return events;
}

StepNeeds TransgranularCheck::needs(const World& world) const {
  return {.stress_sums = !held_ && (world.steps() + 1) % every_ == 0};
}

void TransgranularCheck::after_step(World& world) {
  if (held_ || world.steps() % every_ != 0) return;
  const auto t0 = std::chrono::steady_clock::now();
  auto found = transgranular_step(world, book_, params_);
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (auto& e : found) events_.push_back(std::move(e));
}
}  // namespace cleave::physics
