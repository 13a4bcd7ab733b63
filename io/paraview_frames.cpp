#include "io/paraview_frames.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/dem/world.hpp"
#include "physics/transgranular/fracture_book.hpp"

namespace cleave::io {

namespace {

using Eigen::Vector3d;

/// A unit vector perpendicular to unit `n`.
Vector3d perpendicular(const Vector3d& n) {
  const Vector3d other = std::abs(n.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  return n.cross(other).normalized();
}

/// A rectangle centred on `c` with half sides `a` along `e1` and `b` along `e2`, its one
/// face counter-clockwise seen from e1 x e2.
geometry::PolygonMesh rectangle(const Vector3d& c, const Vector3d& e1, const Vector3d& e2, double a,
                                double b) {
  geometry::PolygonMesh m;
  m.vertices = {c - a * e1 - b * e2, c + a * e1 - b * e2, c + a * e1 + b * e2, c - a * e1 + b * e2};
  m.faces = {{0, 1, 2, 3}};
  return m;
}

/// A closed cylinder from `end` along unit `axis`: `n` side quads and two end caps, outward.
geometry::PolygonMesh tube(const Vector3d& end, const Vector3d& axis, double length, double radius,
                           int n) {
  const Vector3d e1 = perpendicular(axis);
  const Vector3d e2 = axis.cross(e1);
  geometry::PolygonMesh m;
  for (int ring = 0; ring < 2; ++ring) {
    for (int i = 0; i < n; ++i) {
      const double t = 2.0 * M_PI * i / n;
      m.vertices.push_back(end + ring * length * axis +
                           radius * (std::cos(t) * e1 + std::sin(t) * e2));
    }
  }
  std::vector<int> bottom, top;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.faces.push_back({i, j, n + j, n + i});
    bottom.push_back(n - 1 - i);
    top.push_back(n + i);
  }
  m.faces.push_back(bottom);
  m.faces.push_back(top);
  return m;
}

/// A regular octagon of area `area` centred on `c`, normal to unit `n` (counter-clockwise
/// seen from n).
geometry::PolygonMesh octagon(const Vector3d& c, const Vector3d& n, double area) {
  // A regular k-gon of circumradius R has area k/2 R^2 sin(2 pi / k).
  const double r = std::sqrt(area / (4.0 * std::sin(M_PI / 4.0)));
  const Vector3d e1 = perpendicular(n);
  const Vector3d e2 = n.cross(e1);
  geometry::PolygonMesh m;
  m.faces.emplace_back();
  for (int i = 0; i < 8; ++i) {
    const double t = M_PI / 4.0 * i;
    m.vertices.push_back(c + r * (std::cos(t) * e1 + std::sin(t) * e2));
    m.faces.back().push_back(i);
  }
  return m;
}

/// The area of the planar polygon `corners` (in order): half the norm of its vector area.
double polygon_area(const std::vector<Vector3d>& corners) {
  Vector3d twice = Vector3d::Zero();
  for (std::size_t i = 0; i < corners.size(); ++i)
    twice += corners[i].cross(corners[(i + 1) % corners.size()]);
  return 0.5 * twice.norm();
}

}  // namespace

BodyFrame wall_frame(const physics::World& world, int segments) {
  BodyFrame frame;
  frame.index_name = "wall_index";
  frame.active_scalars = "kind";
  if (world.walls().empty()) return frame;
  // The bodies' bounding box, which an infinite plane is drawn over.
  Eigen::AlignedBox3d box;
  for (const physics::BodyId id : world.body_ids()) {
    const physics::BodyState& s = world.state(id);
    for (const auto& v : world.shape(world.info(id).shape).primitives.vertices)
      box.extend(s.x + s.q * v);
  }
  if (box.isEmpty()) box.extend(Vector3d::Zero());
  const double diagonal = box.diagonal().norm();
  const double margin = diagonal > 0.0 ? 0.25 * diagonal : 1.0;
  auto& f = frame.body_fields;
  for (const physics::Wall& w : world.walls()) {
    geometry::PolygonMesh m;
    switch (w.kind) {
      case physics::Wall::Kind::plane: {
        const Vector3d n = w.normal.normalized();
        const Vector3d e1 = perpendicular(n);
        const Vector3d e2 = n.cross(e1);
        const Vector3d c = box.center() - (box.center() - w.origin).dot(n) * n;
        double a = 0.0, b = 0.0;
        for (int k = 0; k < 8; ++k) {
          const Vector3d d = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)) - c;
          a = std::max(a, std::abs(d.dot(e1)));
          b = std::max(b, std::abs(d.dot(e2)));
        }
        m = rectangle(c, e1, e2, a + margin, b + margin);
        break;
      }
      case physics::Wall::Kind::platen:
        m = rectangle(w.origin, w.u, w.normal.cross(w.u), w.half_u, w.half_v);
        break;
      case physics::Wall::Kind::cylinder:
        m = tube(w.origin, w.normal.normalized(), w.length, w.radius, segments);
        break;
    }
    m.name = w.name;
    frame.meshes.push_back(std::move(m));
    f.strings["name"].push_back(w.name);
    f.ids["kind"].push_back(static_cast<long long>(w.kind));
    f.vectors["origin_m"].push_back(w.origin);
    f.vectors["normal"].push_back(w.normal);
    f.vectors["velocity_m_per_s"].push_back(w.velocity);
    f.vectors["reaction_force_N"].push_back(w.reaction);
  }
  return frame;
}

BodyFrame crack_frame(const physics::World& world, const physics::FractureBook* book) {
  BodyFrame frame;
  frame.index_name = "crack_index";
  frame.active_scalars = "mode";
  auto& f = frame.body_fields;
  // Declared up front, so an empty frame still has every field.
  for (const char* name : {"kind", "mode", "grain_a", "grain_b"}) f.ids[name];
  for (const char* name : {"broken_at_s", "opened_at_s", "area_m2"}) f.scalars[name];
  f.vectors["normal"];
  auto add = [&](geometry::PolygonMesh m, int kind, int mode, double broken_at, double opened_at,
                 double area, int grain_a, int grain_b, const Vector3d& normal) {
    frame.meshes.push_back(std::move(m));
    f.ids["kind"].push_back(kind);
    f.ids["mode"].push_back(mode);
    f.ids["grain_a"].push_back(grain_a);
    f.ids["grain_b"].push_back(grain_b);
    f.scalars["broken_at_s"].push_back(broken_at);
    f.scalars["opened_at_s"].push_back(opened_at);
    f.scalars["area_m2"].push_back(area);
    f.vectors["normal"].push_back(normal);
  };
  // Broken bonds, at their material point and normal as A carries them now; the octagon's
  // area is the bond's face area, the crack area reported for it (BondBreak::face_area).
  for (const physics::Bond& bd : world.bonds()) {
    if (bd.intact()) continue;
    const physics::BodyState& a = world.state(world.id_at(bd.a));
    const Vector3d point = a.x + a.q * bd.arm_a;
    const Vector3d normal = (a.q * bd.normal_a).normalized();
    add(octagon(point, normal, bd.transmission), 1, static_cast<int>(bd.failure), bd.broken_at,
        bd.broken_at, bd.transmission, world.slot_infos()[bd.a].grain_id,
        world.slot_infos()[bd.b].grain_id, normal);
  }
  if (book == nullptr) return frame;
  // Split sections: the faces of fragments that lie on one of their grain's cleavage planes.
  std::vector<geometry::PolygonMesh> faces;
  for (const physics::BodyId id : world.body_ids()) {
    if (!book->knows(id) || book->lineage(id).path.empty()) continue;
    const physics::BodyState& s = world.state(id);
    const physics::RigidShape& shape = world.shape(world.info(id).shape);
    const auto& prim = shape.primitives;
    // The faces' corners are the exact shape's, rounded: on the plane to rounding.
    const double tolerance = 1e-7 * shape.bounding_radius();
    const int grain = book->lineage(id).grain_id;
    for (std::size_t k = 0; k < book->planes(id).size(); ++k) {
      const auto [n, on] = book->world_plane(world, id, static_cast<int>(k));
      faces.clear();
      double drawn = 0.0;  // the faces' areas as drawn (rounded corners)
      for (const auto& face : prim.faces) {
        if ((s.q * face.normal).dot(n) < 1.0 - 1e-9) continue;
        geometry::PolygonMesh m;
        bool on_plane = true;
        for (const int v : face.vertices) {
          m.vertices.push_back(s.x + s.q * prim.vertices[static_cast<std::size_t>(v)]);
          on_plane = on_plane && std::abs((m.vertices.back() - on).dot(n)) <= tolerance;
        }
        if (!on_plane) continue;
        m.faces.emplace_back();
        for (std::size_t i = 0; i < face.vertices.size(); ++i)
          m.faces.back().push_back(static_cast<int>(i));
        drawn += polygon_area(m.vertices);
        faces.push_back(std::move(m));
      }
      if (faces.empty()) continue;
      // The exact area of the piece's faces on the plane (one face: a piece is convex),
      // shared among the faces drawn by their drawn areas should there be several.
      const double exact = book->section_area(id, static_cast<int>(k));
      const double opened = book->opened_at(id, static_cast<int>(k));
      for (auto& m : faces) {
        const double share = faces.size() == 1 || !(drawn > 0.0)
                                 ? 1.0 / static_cast<double>(faces.size())
                                 : polygon_area(m.vertices) / drawn;
        add(std::move(m), 2, 5, std::numeric_limits<double>::quiet_NaN(), opened, exact * share,
            grain, grain, n);
      }
    }
  }
  return frame;
}

}  // namespace cleave::io
