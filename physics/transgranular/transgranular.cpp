#include "physics/transgranular/transgranular.hpp"

#include <algorithm>
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

PosedFaces pose_faces(const World& world, BodyId id) {
  PosedFaces out;
  const BodyState& s = world.state(id);
  const auto& p = world.shape(world.info(id).shape).primitives;
  out.primitives = &p;
  for (const auto& v : p.vertices) out.vertices.push_back(s.x + s.q * v);
  for (const auto& f : p.faces) {
    std::vector<Eigen::Vector3d> polygon;
    for (int v : f.vertices) polygon.push_back(out.vertices[static_cast<std::size_t>(v)]);
    const Eigen::Vector3d n = s.q * f.normal;
    out.normals.push_back(n);
    out.offsets.push_back(n.dot(polygon.front()));
    out.polygons.push_back(std::move(polygon));
  }
  out.forces.resize(p.faces.size());
  return out;
}

/// The face a point acts on: the one it lies farthest out from (see the header).
std::size_t face_of(const PosedFaces& faces, const Eigen::Vector3d& point) {
  std::size_t best = 0;
  double out = -std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < faces.normals.size(); ++f) {
    const double d = faces.normals[f].dot(point) - faces.offsets[f];
    if (d > out) {
      out = d;
      best = f;
    }
  }
  return best;
}

/// The section of the body by the plane: where its edges cross it, in order around the
/// section. Empty when the plane misses the body.
std::vector<Eigen::Vector3d> section(const PosedFaces& faces, const CrackPlane& plane) {
  std::vector<Eigen::Vector3d> points;
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
  if (points.size() < 3) return {};
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : points) c += p / static_cast<double>(points.size());
  const Eigen::Vector3d u = (points.front() - c).normalized();
  const Eigen::Vector3d v = plane.normal.cross(u);
  std::sort(points.begin(), points.end(), [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    return std::atan2((p - c).dot(v), (p - c).dot(u)) < std::atan2((q - c).dot(v), (q - c).dot(u));
  });
  return points;
}

}  // namespace

namespace {

/// Every contact and bond force of the last force evaluation, by body slot.
std::vector<std::vector<PointForce>> forces_by_body(const World& world) {
  std::vector<std::vector<PointForce>> out;
  auto add = [&](std::uint32_t slot, const Eigen::Vector3d& point, const Eigen::Vector3d& force) {
    if (out.size() <= slot) out.resize(slot + 1);
    out[slot].push_back({point, force});
  };
  for (const ContactRecord& c : world.contacts()) {
    add(c.b, c.point, c.force);
    if (!c.wall) add(c.a, c.point, -c.force);
  }
  for (const Bond& b : world.bonds()) {
    if (!b.intact()) continue;
    add(b.b, b.point, b.force);
    add(b.a, b.point, -b.force);
  }
  return out;
}

std::vector<CrackAssessment> assess_with(const World& world, const FractureBook& book, BodyId id,
                                         const FractureParams& params, const Eigen::Matrix3d& sigma,
                                         const std::vector<PointForce>& acting) {
  std::vector<CrackAssessment> out;
  if (!book.knows(id)) return out;
  // Eq. 3.22 first: below the hydrostatic gate no plane is worth the work.
  if (!(sigma.trace() / 3.0 >= params.sigma_f_hyd)) return out;
  const std::vector<int>& candidates = book.candidates(id);
  if (candidates.empty()) return out;

  PosedFaces faces = pose_faces(world, id);
  for (const PointForce& f : acting) faces.forces[face_of(faces, f.point)].push_back(f);
  // Eq. 3.15 on every face.
  std::vector<FaceGeometry> geometry;
  std::vector<FaceTractions> tractions;
  for (std::size_t f = 0; f < faces.polygons.size(); ++f) {
    const auto& poly = faces.polygons[f];
    geometry.push_back(face_geometry(poly, faces.normals[f], poly[1] - poly[0]));
    tractions.push_back(face_tractions(geometry.back(), faces.forces[f]));
  }
  const Eigen::Vector3d centroid = world.state(id).x;
  for (const int k : candidates) {
    const auto [normal, point] = book.world_plane(world, id, k);
    const CrackPlane plane{point, normal};
    const std::vector<Eigen::Vector3d> cut = section(faces, plane);
    if (cut.empty()) continue;
    // Eq. 3.20 for the faces (or parts of faces) behind the plane, then eq. 3.21.
    std::vector<FaceLoad> loads;
    for (std::size_t f = 0; f < faces.polygons.size(); ++f) {
      loads.push_back(face_part_load(geometry[f], tractions[f], faces.polygons[f], plane));
    }
    const CrackPlaneLoad load = crack_plane_load(loads, centroid, cut, plane, cut[1] - cut[0]);
    CrackAssessment a;
    a.id = id;
    a.plane = k;
    a.stresses = beam_stresses(load);
    a.result = fracture_check(params, sigma, a.stresses);
    out.push_back(a);
  }
  return out;
}

}  // namespace

std::vector<CrackAssessment> assess(const World& world, const FractureBook& book, BodyId id,
                                    const FractureParams& params,
                                    const std::vector<Eigen::Matrix3d>& stresses) {
  const auto forces = forces_by_body(world);
  static const std::vector<PointForce> none;
  return assess_with(world, book, id, params, stresses.at(id.index),
                     id.index < forces.size() ? forces[id.index] : none);
}

std::vector<TransgranularEvent> transgranular_step(World& world, FractureBook& book,
                                                   const FractureParams& params) {
  std::vector<TransgranularEvent> events;
  if (world.body_count() == 0) return events;
  const std::vector<Eigen::Matrix3d> stresses = world.body_stresses();
  const auto forces = forces_by_body(world);
  static const std::vector<PointForce> none;
  // Decide on the state of this step for every body, then cut.
  std::vector<CrackAssessment> failing;
  for (const BodyId id : world.body_ids()) {
    const std::vector<CrackAssessment> found = assess_with(
        world, book, id, params, stresses[id.index], id.index < forces.size() ? forces[id.index] : none);
    const CrackAssessment* worst = nullptr;
    for (const auto& a : found) {
      if (a.result.fails && (worst == nullptr || a.result.criterion > worst->result.criterion)) worst = &a;
    }
    if (worst != nullptr) failing.push_back(*worst);
  }
  for (const CrackAssessment& a : failing) {
    SplitEvent split = book.split(world, a.id, a.plane);
    if (!split.ids.empty()) events.push_back({std::move(split), a});
  }
  return events;
}

}  // namespace cleave::physics
