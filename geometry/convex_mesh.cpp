// Imported meshes as exact convex grains: topology checks with messages that say where,
// an exact convexity test per face, and CGAL's exact convex hull with its planar facets
// merged into convex polygons. The second of geometry's CGAL translation units that build
// shapes (with exact_polyhedron.cpp); the header is CGAL-free.

#include "geometry/convex_mesh.hpp"

#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "geometry/exact_internal.hpp"

namespace cleave::geometry {

namespace {

using Impl = ExactPolyhedron::Impl;
using Vector3 = Kernel::Vector_3;
using SurfaceMesh = CGAL::Surface_mesh<Point3>;

/// A vertex this far outside a face's plane, relative to the mesh's bounding-box diagonal,
/// still counts as convex: float storage bends planar polygons by about 1e-7.
constexpr double kConvexityTolerance = 1e-6;
/// A convex surface encloses its hull's volume (to rounding); one that does not folds.
constexpr double kVolumeTolerance = 1e-5;

std::string describe_vertex(const PolygonMesh& m, int i) {
  std::ostringstream out;
  out.precision(6);
  const Eigen::Vector3d& v = m.vertices[static_cast<std::size_t>(i)];
  out << "vertex " << i << " (" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

std::string describe_edge(const PolygonMesh& m, int a, int b) {
  return "the edge between " + describe_vertex(m, a) + " and " + describe_vertex(m, b);
}

/// Union-find over face indices.
struct Groups {
  explicit Groups(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
  std::vector<std::size_t> parent;
};

/// The exact convex hull of `points` (not all coplanar) as a convex polyhedron with one
/// polygon per planar facet and no vertex inside a facet or on an edge.
Impl hull_polyhedron(const std::vector<Point3>& points) {
  SurfaceMesh sm;
  CGAL::convex_hull_3(points.begin(), points.end(), sm);
  // Triangles of one facet: neighbours across an edge whose four corners are coplanar.
  Groups groups(sm.num_faces());
  for (const auto e : sm.edges()) {
    const auto h = sm.halfedge(e);
    const auto o = sm.opposite(h);
    if (sm.is_border(h) || sm.is_border(o)) continue;
    const Point3& a = sm.point(sm.source(h));
    const Point3& b = sm.point(sm.target(h));
    const Point3& c = sm.point(sm.target(sm.next(h)));
    const Point3& d = sm.point(sm.target(sm.next(o)));
    if (CGAL::coplanar(a, b, c, d)) groups.join(sm.face(h).idx(), sm.face(o).idx());
  }
  // Each facet's boundary: the half-edges whose opposite lies in another facet, chained.
  std::map<std::size_t, std::unordered_map<std::size_t, std::size_t>> boundary;
  for (const auto h : sm.halfedges()) {
    if (sm.is_border(h) || sm.is_border(sm.opposite(h))) continue;
    const std::size_t g = groups.find(sm.face(h).idx());
    if (g == groups.find(sm.face(sm.opposite(h)).idx())) continue;
    boundary[g][sm.source(h).idx()] = sm.target(h).idx();
  }
  std::vector<std::vector<std::size_t>> loops;
  for (const auto& [g, next] : boundary) {
    std::vector<std::size_t> loop;
    const std::size_t start = next.begin()->first;
    std::size_t at = start;
    do {
      loop.push_back(at);
      const auto it = next.find(at);
      if (it == next.end() || loop.size() > next.size()) {
        throw GeometryError("internal error: a convex hull facet's boundary does not close");
      }
      at = it->second;
    } while (at != start);
    if (loop.size() != next.size()) {
      throw GeometryError("internal error: a convex hull facet has more than one boundary");
    }
    loops.push_back(std::move(loop));
  }
  // Corners where the boundary runs straight on are not vertices of the polyhedron.
  auto point_of = [&](std::size_t v) -> const Point3& {
    return sm.point(SurfaceMesh::Vertex_index(static_cast<SurfaceMesh::size_type>(v)));
  };
  for (auto& loop : loops) {
    bool removed = true;
    while (removed && loop.size() > 3) {
      removed = false;
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const std::size_t n = loop.size();
        if (CGAL::collinear(point_of(loop[(i + n - 1) % n]), point_of(loop[i]),
                            point_of(loop[(i + 1) % n]))) {
          loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
          removed = true;
          break;
        }
      }
    }
  }
  Impl out;
  std::unordered_map<std::size_t, int> remap;
  for (const auto& loop : loops) {
    std::vector<int> face;
    for (std::size_t v : loop) {
      auto [it, fresh] = remap.try_emplace(v, static_cast<int>(out.vertices.size()));
      if (fresh) out.vertices.push_back(point_of(v));
      face.push_back(it->second);
    }
    out.faces.push_back(std::move(face));
  }
  return out;
}

}  // namespace

ConvexMeshResult convex_shape_from_mesh(const PolygonMesh& mesh, bool convex_hull) {
  const std::string who = "mesh '" + mesh.name + "': ";
  auto fail = [&](const std::string& what) -> void { throw GeometryError(who + what); };
  const int nv = static_cast<int>(mesh.vertices.size());
  if (mesh.faces.empty() || nv == 0) fail("has no faces");
  for (int i = 0; i < nv; ++i) {
    if (!mesh.vertices[static_cast<std::size_t>(i)].allFinite()) {
      fail("vertex " + std::to_string(i) + " is not finite");
    }
  }

  // Topology: every undirected edge with the faces using it and their direction.
  struct Use {
    int face;
    bool forward;  // runs from the smaller vertex index to the larger
  };
  std::map<std::pair<int, int>, std::vector<Use>> edges;
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    const std::string name = "face " + std::to_string(f);
    if (face.size() < 3) fail(name + " has " + std::to_string(face.size()) + " corners (need 3)");
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i];
      const int b = face[(i + 1) % face.size()];
      if (a < 0 || a >= nv) fail(name + " refers to vertex " + std::to_string(a) + " of " + std::to_string(nv));
      if (std::count(face.begin(), face.end(), a) > 1) {
        fail(name + " uses " + describe_vertex(mesh, a) + " twice (a degenerate face)");
      }
      used[static_cast<std::size_t>(a)] = 1;
      edges[{std::min(a, b), std::max(a, b)}].push_back({static_cast<int>(f), a < b});
    }
  }
  std::size_t over = 0, border = 0;
  const std::pair<const std::pair<int, int>, std::vector<Use>>* first_over = nullptr;
  const std::pair<const std::pair<int, int>, std::vector<Use>>* first_border = nullptr;
  for (const auto& entry : edges) {
    if (entry.second.size() > 2 && over++ == 0) first_over = &entry;
    if (entry.second.size() == 1 && border++ == 0) first_border = &entry;
  }
  if (first_over != nullptr) {
    const auto& [e, uses] = *first_over;
    std::string faces;
    for (const Use& u : uses) faces += (faces.empty() ? "" : ", ") + std::to_string(u.face);
    fail("not manifold: " + describe_edge(mesh, e.first, e.second) + " is shared by " +
         std::to_string(uses.size()) + " faces (" + faces + "); " + std::to_string(over) +
         " edge(s) in all are shared by more than two faces");
  }
  if (first_border != nullptr) {
    const auto& [e, uses] = *first_border;
    fail("not closed: " + std::to_string(border) +
         " boundary edge(s) (used by one face only), e.g. " + describe_edge(mesh, e.first, e.second) +
         " of face " + std::to_string(uses.front().face));
  }
  for (const auto& [e, uses] : edges) {
    if (uses[0].forward == uses[1].forward) {
      const int a = uses[0].forward ? e.first : e.second;
      const int b = uses[0].forward ? e.second : e.first;
      fail("faces " + std::to_string(uses[0].face) + " and " + std::to_string(uses[1].face) +
           " are not consistently oriented: both run from " + describe_vertex(mesh, a) + " to " +
           describe_vertex(mesh, b));
    }
  }
  const long used_count = std::count(used.begin(), used.end(), 1);
  const long euler = used_count - static_cast<long>(edges.size()) + static_cast<long>(mesh.faces.size());
  if (euler != 2) {
    fail("not one closed surface: Euler characteristic V - E + F = " + std::to_string(euler) +
         " (a closed surface without handles has 2; several pieces or holes through it differ)");
  }

  // Exact points; degenerate when all lie in one plane.
  std::vector<Point3> p(static_cast<std::size_t>(nv));
  std::vector<int> ids;
  for (int i = 0; i < nv; ++i) {
    if (!used[static_cast<std::size_t>(i)]) continue;
    const Eigen::Vector3d& v = mesh.vertices[static_cast<std::size_t>(i)];
    p[static_cast<std::size_t>(i)] = Point3(v.x(), v.y(), v.z());
    ids.push_back(i);
  }
  {
    std::vector<Point3> distinct;
    for (int i : ids) {
      const Point3& q = p[static_cast<std::size_t>(i)];
      if (distinct.size() == 0 || (distinct.size() == 1 && q != distinct[0]) ||
          (distinct.size() == 2 && !CGAL::collinear(distinct[0], distinct[1], q)) ||
          (distinct.size() == 3 && !CGAL::coplanar(distinct[0], distinct[1], distinct[2], q))) {
        distinct.push_back(q);
      }
    }
    if (distinct.size() < 4) {
      fail(std::string("degenerate: all ") + std::to_string(ids.size()) + " vertices lie " +
           (distinct.size() < 3 ? "on one line" : "in one plane") + " (zero volume)");
    }
  }

  // Enclosed volume, exactly (fan triangles against the first vertex).
  const Point3& o = p[static_cast<std::size_t>(ids.front())];
  FT six_volume(0);
  for (const auto& face : mesh.faces) {
    const Vector3 a = p[static_cast<std::size_t>(face[0])] - o;
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      const Vector3 b = p[static_cast<std::size_t>(face[i])] - o;
      const Vector3 c = p[static_cast<std::size_t>(face[i + 1])] - o;
      six_volume += a * CGAL::cross_product(b, c);
    }
  }
  if (CGAL::is_zero(six_volume)) fail("degenerate: the enclosed volume is zero");
  const bool inward = six_volume < 0;
  if (inward) six_volume = -six_volume;

  ConvexMeshResult result{ExactAccess::make_polyhedron(hull_polyhedron([&] {
                            std::vector<Point3> pts;
                            for (int i : ids) pts.push_back(p[static_cast<std::size_t>(i)]);
                            return pts;
                          }())),
                          true, CGAL::to_double(six_volume) / 6.0, 0.0};

  // Convexity: every vertex on the inner side of (or on) every face triangle's plane, up to
  // a rounding tolerance (planar faces stored in float are seldom exactly planar).
  Eigen::Vector3d lo = mesh.vertices[static_cast<std::size_t>(ids.front())], hi = lo;
  for (int i : ids) {
    lo = lo.cwiseMin(mesh.vertices[static_cast<std::size_t>(i)]);
    hi = hi.cwiseMax(mesh.vertices[static_cast<std::size_t>(i)]);
  }
  const double tolerance = kConvexityTolerance * (hi - lo).norm();
  std::size_t violations = 0;
  double worst = -1.0;
  int worst_vertex = -1, worst_face = -1;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      const Point3& a = p[static_cast<std::size_t>(face[0])];
      const Point3& b = p[static_cast<std::size_t>(face[i])];
      const Point3& c = p[static_cast<std::size_t>(face[i + 1])];
      if (CGAL::collinear(a, b, c)) continue;
      const Plane3 plane = inward ? Plane3(a, c, b) : Plane3(a, b, c);
      for (int v : ids) {
        if (plane.oriented_side(p[static_cast<std::size_t>(v)]) != CGAL::ON_POSITIVE_SIDE) continue;
        const double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(p[static_cast<std::size_t>(v)], plane)));
        if (d <= tolerance) continue;
        ++violations;
        if (d > worst) {
          worst = d;
          worst_vertex = v;
          worst_face = static_cast<int>(f);
        }
      }
    }
  }
  result.was_convex = violations == 0;
  if (!result.was_convex && !convex_hull) {
    std::ostringstream d;
    d.precision(4);
    d << worst << " (mesh units) outside the plane of face " << worst_face << " (tolerance "
      << tolerance << ")";
    fail("not convex: " + describe_vertex(mesh, worst_vertex) + " lies " + d.str() +
         ", the largest of " + std::to_string(violations) +
         " vertex-face violation(s); convex_hull = true would use the mesh's convex hull");
  }
  const ExactScalar hull_volume = result.shape.volume();
  if (result.was_convex &&
      std::abs(hull_volume.to_double() - result.mesh_volume) > kVolumeTolerance * hull_volume.to_double()) {
    fail("not convex: the surface folds over itself (its enclosed volume differs from its "
         "convex hull's)");
  }
  if (!result.shape.is_valid_convex()) {
    fail("internal error: the convex hull is not a valid convex polyhedron");
  }
  result.shape_volume = hull_volume.to_double();
  return result;
}

}  // namespace cleave::geometry
