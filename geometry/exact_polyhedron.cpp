// Exact convex polyhedra on CGAL's Epeck kernel: construction, validation, plane splits,
// exact volumes and mass properties, exact text serialisation.

#include "geometry/exact_polyhedron.hpp"

#include <CGAL/intersections.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <unordered_map>

#include "geometry/exact_internal.hpp"
#include "geometry/lattice.hpp"

namespace cleave::geometry {

// ---------------------------------------------------------------------------------------
// ExactScalar

ExactScalar::ExactScalar() : ExactScalar(0.0) {}
ExactScalar::ExactScalar(double value)
    : impl_(std::make_shared<const Impl>(Impl{FT(value)})) {}
ExactScalar::ExactScalar(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

ExactScalar ExactScalar::operator+(const ExactScalar& o) const {
  return ExactAccess::make_scalar(impl_->value + o.impl_->value);
}
ExactScalar ExactScalar::operator-(const ExactScalar& o) const {
  return ExactAccess::make_scalar(impl_->value - o.impl_->value);
}
ExactScalar ExactScalar::operator*(const ExactScalar& o) const {
  return ExactAccess::make_scalar(impl_->value * o.impl_->value);
}
bool ExactScalar::operator==(const ExactScalar& o) const { return impl_->value == o.impl_->value; }
bool ExactScalar::operator<(const ExactScalar& o) const { return impl_->value < o.impl_->value; }
double ExactScalar::to_double() const { return CGAL::to_double(impl_->value); }

namespace {

std::string exact_to_string(const ExactFT& x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

/// Parses "[-]digits[/digits]" into an exact rational; throws GeometryError otherwise.
ExactFT parse_exact(const std::string& text) {
  std::size_t i = (!text.empty() && (text[0] == '-' || text[0] == '+')) ? 1 : 0;
  bool digits = false, slash = false, den_digits = false;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (std::isdigit(static_cast<unsigned char>(c))) {
      (slash ? den_digits : digits) = true;
    } else if (c == '/' && !slash && digits) {
      slash = true;
    } else {
      throw GeometryError("not an exact rational number: '" + text + "'");
    }
  }
  if (!digits || (slash && !den_digits)) {
    throw GeometryError("not an exact rational number: '" + text + "'");
  }
  if (slash && text.find_first_not_of('0', text.find('/') + 1) == std::string::npos) {
    throw GeometryError("zero denominator in '" + text + "'");
  }
  std::istringstream in(text[0] == '+' ? text.substr(1) : text);
  ExactFT value;
  in >> value;
  if (in.fail()) throw GeometryError("not an exact rational number: '" + text + "'");
  return value;
}

FT exact_ft(const std::string& text) { return FT(parse_exact(text)); }

}  // namespace

std::string ExactScalar::to_string() const { return exact_to_string(impl_->value.exact()); }

ExactScalar ExactScalar::parse(const std::string& text) {
  return ExactAccess::make_scalar(exact_ft(text));
}

// ---------------------------------------------------------------------------------------
// ExactPlane

ExactPlane::ExactPlane(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

namespace {
ExactPlane make_plane(const Plane3& plane);
Point3 to_point(const Eigen::Vector3d& p) { return Point3(p.x(), p.y(), p.z()); }
}  // namespace

ExactPlane ExactPlane::from_normal_offset(const Eigen::Vector3d& normal, double offset) {
  if (normal.squaredNorm() == 0.0) throw GeometryError("plane normal is zero");
  return make_plane(Plane3(FT(normal.x()), FT(normal.y()), FT(normal.z()), -FT(offset)));
}

ExactPlane ExactPlane::through_points(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                      const Eigen::Vector3d& r) {
  const Point3 a = to_point(p), b = to_point(q), c = to_point(r);
  if (CGAL::collinear(a, b, c)) throw GeometryError("plane through collinear points");
  return make_plane(Plane3(a, b, c));
}

ExactPlane ExactPlane::through_vertices(const ExactPolyhedron& body, int i, int j, int k) {
  const auto& v = ExactAccess::impl(body).vertices;
  const int n = static_cast<int>(v.size());
  if (i < 0 || j < 0 || k < 0 || i >= n || j >= n || k >= n) {
    throw GeometryError("plane through vertices: index out of range");
  }
  if (CGAL::collinear(v[i], v[j], v[k])) throw GeometryError("plane through collinear vertices");
  return make_plane(Plane3(v[i], v[j], v[k]));
}

ExactPlane ExactPlane::through_vertex(const ExactPolyhedron& body, int i,
                                      const Eigen::Vector3d& normal) {
  const auto& v = ExactAccess::impl(body).vertices;
  if (i < 0 || i >= static_cast<int>(v.size())) {
    throw GeometryError("plane through vertex: index out of range");
  }
  if (normal.squaredNorm() == 0.0) throw GeometryError("plane normal is zero");
  return make_plane(Plane3(v[i], Kernel::Vector_3(normal.x(), normal.y(), normal.z())));
}

ExactPlane ExactPlane::through_segment(const ExactPolyhedron& body, int i, int j,
                                       const Eigen::Vector3d& along) {
  const auto& v = ExactAccess::impl(body).vertices;
  const int n = static_cast<int>(v.size());
  if (i < 0 || j < 0 || i >= n || j >= n) {
    throw GeometryError("plane through segment: index out of range");
  }
  const Point3 third = v[i] + Kernel::Vector_3(along.x(), along.y(), along.z());
  if (CGAL::collinear(v[i], v[j], third)) {
    throw GeometryError("plane through segment: direction parallel to the segment");
  }
  return make_plane(Plane3(v[i], v[j], third));
}

ExactPlane ExactPlane::bisector(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const Point3 a = to_point(p), b = to_point(q);
  if (a == b) throw GeometryError("bisector of a point with itself");
  return make_plane(CGAL::bisector(a, b));
}

ExactPlane ExactPlane::bisector(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& shift) {
  const Point3 a = to_point(p), b = to_point(q) + (to_point(shift) - CGAL::ORIGIN);
  if (a == b) throw GeometryError("bisector of a point with itself");
  return make_plane(CGAL::bisector(a, b));
}

ExactPlane ExactPlane::power_bisector(const Eigen::Vector3d& p, double wp, const Eigen::Vector3d& q,
                                      double wq, const Eigen::Vector3d& shift) {
  const Point3 a = to_point(p), b = to_point(q) + (to_point(shift) - CGAL::ORIGIN);
  if (a == b) throw GeometryError("power bisector of a point with itself");
  const Kernel::Vector_3 pa = a - CGAL::ORIGIN, pb = b - CGAL::ORIGIN;
  // (a x + d) = (|x - q'|^2 - wq) - (|x - p|^2 - wp): positive where p's power is smaller.
  const Kernel::Vector_3 n = FT(2) * (pa - pb);
  return make_plane(Plane3(n.x(), n.y(), n.z(), pb.squared_length() - pa.squared_length() - FT(wq) + FT(wp)));
}

ExactPlane ExactPlane::opposite() const { return make_plane(impl_->plane.opposite()); }

Eigen::Vector3d ExactPlane::normal_approx() const {
  const auto& pl = impl_->plane;
  Eigen::Vector3d n(CGAL::to_double(pl.a()), CGAL::to_double(pl.b()), CGAL::to_double(pl.c()));
  return n.normalized();
}

double ExactPlane::offset_approx() const {
  const auto& pl = impl_->plane;
  Eigen::Vector3d n(CGAL::to_double(pl.a()), CGAL::to_double(pl.b()), CGAL::to_double(pl.c()));
  return -CGAL::to_double(pl.d()) / n.norm();
}

namespace {
/// The axis of the largest component of `plane`'s normal, exactly.
int dominant_axis(const Plane3& plane) {
  const std::array<FT, 3> n{CGAL::abs(plane.a()), CGAL::abs(plane.b()), CGAL::abs(plane.c())};
  int k = 0;
  for (int i = 1; i < 3; ++i) {
    if (n[i] > n[k]) k = i;
  }
  return k;
}

FT component(const Plane3& plane, int k) {
  return k == 0 ? plane.a() : k == 1 ? plane.b() : plane.c();
}
}  // namespace

double ExactPlane::area_of_projection(const ExactScalar& projected) const {
  const Plane3& pl = impl_->plane;
  const FT nk = component(pl, dominant_axis(pl));
  const FT& p = ExactAccess::value(projected);
  // A^2 = P^2 (a^2 + b^2 + c^2) / n_k^2, exact; one rounding, then the square root.
  const FT squared = p * p * (pl.a() * pl.a() + pl.b() * pl.b() + pl.c() * pl.c()) / (nk * nk);
  return std::sqrt(CGAL::to_double(squared.exact()));
}

std::string ExactPlane::to_string() const {
  const auto& pl = impl_->plane;
  return exact_to_string(pl.a().exact()) + " " + exact_to_string(pl.b().exact()) + " " +
         exact_to_string(pl.c().exact()) + " " + exact_to_string(pl.d().exact());
}

ExactPlane ExactPlane::parse(const std::string& text) {
  std::istringstream in(text);
  std::array<std::string, 4> w;
  if (!(in >> w[0] >> w[1] >> w[2] >> w[3])) {
    throw GeometryError("plane needs four exact coefficients: '" + text + "'");
  }
  std::string extra;
  if (in >> extra) throw GeometryError("plane has more than four coefficients: '" + text + "'");
  const FT a = exact_ft(w[0]), b = exact_ft(w[1]), c = exact_ft(w[2]), d = exact_ft(w[3]);
  if (CGAL::is_zero(a) && CGAL::is_zero(b) && CGAL::is_zero(c)) {
    throw GeometryError("plane normal is zero: '" + text + "'");
  }
  return make_plane(Plane3(a, b, c, d));
}

namespace {
ExactPlane make_plane(const Plane3& plane) { return ExactAccess::make_plane(plane); }
}  // namespace

// ---------------------------------------------------------------------------------------
// ExactPolyhedron: construction and validation

ExactPolyhedron::ExactPolyhedron(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

namespace {

using Impl = ExactPolyhedron::Impl;

/// Exact check of a convex polyhedron; returns an empty string when valid, else the reason.
std::string convexity_problem(const Impl& p) {
  const int nv = static_cast<int>(p.vertices.size());
  if (nv < 4) return "fewer than 4 vertices";
  if (p.faces.size() < 4) return "fewer than 4 faces";
  std::map<std::pair<int, int>, int> directed;
  std::vector<int> used(nv, 0);
  for (std::size_t f = 0; f < p.faces.size(); ++f) {
    const auto& face = p.faces[f];
    if (face.size() < 3) return "face " + std::to_string(f) + " has fewer than 3 vertices";
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      if (a < 0 || a >= nv) return "face " + std::to_string(f) + " uses a vertex out of range";
      if (a == b) return "face " + std::to_string(f) + " repeats a vertex";
      if (++directed[{a, b}] > 1) {
        return "edge " + std::to_string(a) + "-" + std::to_string(b) +
               " is used twice in the same direction (faces not consistently oriented)";
      }
      used[a] = 1;
    }
  }
  for (const auto& [e, n] : directed) {
    if (!directed.count({e.second, e.first})) {
      return "edge " + std::to_string(e.first) + "-" + std::to_string(e.second) +
             " has no opposite (the surface is not closed)";
    }
  }
  for (int i = 0; i < nv; ++i) {
    if (!used[i]) return "vertex " + std::to_string(i) + " belongs to no face";
  }
  const long euler = static_cast<long>(nv) - static_cast<long>(directed.size() / 2) +
                     static_cast<long>(p.faces.size());
  if (euler != 2) return "the surface is not a sphere (Euler characteristic " + std::to_string(euler) + ")";

  for (std::size_t f = 0; f < p.faces.size(); ++f) {
    const auto& face = p.faces[f];
    const std::size_t k = face.size();
    // Every consecutive triple turns left seen from outside: the face is strictly convex,
    // and its first triple defines the outward plane.
    const Point3& a0 = p.vertices[face[0]];
    const Point3& b0 = p.vertices[face[1]];
    const Point3& c0 = p.vertices[face[2]];
    if (CGAL::collinear(a0, b0, c0)) return "face " + std::to_string(f) + " has collinear corners";
    const Plane3 plane(a0, b0, c0);
    const auto normal = plane.orthogonal_vector();
    for (std::size_t i = 0; i < k; ++i) {
      const Point3& a = p.vertices[face[i]];
      const Point3& b = p.vertices[face[(i + 1) % k]];
      const Point3& c = p.vertices[face[(i + 2) % k]];
      if (plane.oriented_side(a) != CGAL::ON_ORIENTED_BOUNDARY) {
        return "face " + std::to_string(f) + " is not planar";
      }
      if (CGAL::orientation(a, b, c, a + normal) != CGAL::POSITIVE) {
        return "face " + std::to_string(f) + " is not strictly convex";
      }
    }
    std::vector<char> on_face(nv, 0);
    for (int v : face) on_face[v] = 1;
    for (int v = 0; v < nv; ++v) {
      if (on_face[v]) continue;
      const auto side = plane.oriented_side(p.vertices[v]);
      if (side == CGAL::ON_POSITIVE_SIDE) {
        return "vertex " + std::to_string(v) + " lies outside face " + std::to_string(f) +
               " (not convex, or faces oriented inward)";
      }
      if (side == CGAL::ON_ORIENTED_BOUNDARY) {
        return "vertex " + std::to_string(v) + " lies in the plane of face " + std::to_string(f) +
               " without belonging to it (coplanar faces)";
      }
    }
  }
  return {};
}

ExactPolyhedron make_checked(Impl impl, const char* what) {
  const std::string problem = convexity_problem(impl);
  if (!problem.empty()) throw GeometryError(std::string(what) + ": " + problem);
  return ExactAccess::make_polyhedron(std::move(impl));
}

}  // namespace

ExactPolyhedron ExactPolyhedron::hexagonal_prism(double side, double thickness) {
  if (!(side > 0.0) || !(thickness > 0.0)) {
    throw GeometryError("hexagonal prism needs a positive side and thickness");
  }
  Impl impl;
  impl.vertices.reserve(12);
  for (double z : {-thickness / 2.0, thickness / 2.0}) {
    for (int n = 0; n < 6; ++n) {
      const Eigen::Vector2d c = hexagon_corner(side, n);
      impl.vertices.emplace_back(c.x(), c.y(), z);
    }
  }
  // Corners run clockwise seen from +z, so the bottom face lists them in order (CCW seen
  // from below) and the top face in reverse.
  impl.faces.push_back({0, 1, 2, 3, 4, 5});
  impl.faces.push_back({11, 10, 9, 8, 7, 6});
  for (int n = 0; n < 6; ++n) {
    const int m = (n + 1) % 6;
    impl.faces.push_back({n, 6 + n, 6 + m, m});
  }
  return make_checked(std::move(impl), "hexagonal prism");
}

ExactPolyhedron ExactPolyhedron::from_mesh(const PolygonMesh& mesh) {
  Impl impl;
  impl.vertices.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) throw GeometryError("mesh '" + mesh.name + "': a vertex is not finite");
    impl.vertices.push_back(to_point(v));
  }
  impl.faces = mesh.faces;
  const std::string what = "mesh '" + mesh.name + "'";
  return make_checked(std::move(impl), what.c_str());
}

std::string ExactPolyhedron::to_exact_text() const {
  std::ostringstream out;
  out << "vertices " << impl_->vertices.size() << '\n';
  for (const auto& v : impl_->vertices) {
    const auto& e = CGAL::exact(v);
    out << exact_to_string(e.x()) << ' ' << exact_to_string(e.y()) << ' ' << exact_to_string(e.z())
        << '\n';
  }
  out << "faces " << impl_->faces.size() << '\n';
  for (const auto& f : impl_->faces) {
    out << f.size();
    for (int i : f) out << ' ' << i;
    out << '\n';
  }
  return out.str();
}

ExactPolyhedron ExactPolyhedron::from_exact_text(const std::string& text) {
  std::istringstream in(text);
  std::string word;
  std::size_t nv = 0, nf = 0;
  if (!(in >> word >> nv) || word != "vertices") {
    throw GeometryError("exact polyhedron text must start with 'vertices N'");
  }
  if (nv > 1000000) throw GeometryError("exact polyhedron text: too many vertices");
  Impl impl;
  impl.vertices.reserve(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    std::string x, y, z;
    if (!(in >> x >> y >> z)) {
      throw GeometryError("exact polyhedron text: vertex " + std::to_string(i) + " is missing");
    }
    impl.vertices.emplace_back(exact_ft(x), exact_ft(y), exact_ft(z));
  }
  if (!(in >> word >> nf) || word != "faces") {
    throw GeometryError("exact polyhedron text: expected 'faces M' after the vertices");
  }
  if (nf > 1000000) throw GeometryError("exact polyhedron text: too many faces");
  for (std::size_t f = 0; f < nf; ++f) {
    std::size_t k = 0;
    if (!(in >> k) || k < 3 || k > nv) {
      throw GeometryError("exact polyhedron text: face " + std::to_string(f) + " is malformed");
    }
    std::vector<int> face(k);
    for (auto& idx : face) {
      if (!(in >> idx)) {
        throw GeometryError("exact polyhedron text: face " + std::to_string(f) + " is truncated");
      }
    }
    impl.faces.push_back(std::move(face));
  }
  if (in >> word) throw GeometryError("exact polyhedron text: unexpected '" + word + "' at the end");
  return make_checked(std::move(impl), "exact polyhedron text");
}

int ExactPolyhedron::num_vertices() const { return static_cast<int>(impl_->vertices.size()); }
int ExactPolyhedron::num_faces() const { return static_cast<int>(impl_->faces.size()); }
int ExactPolyhedron::num_edges() const {
  // Closed 2-manifold: every edge is shared by two faces.
  std::size_t half_edges = 0;
  for (const auto& f : impl_->faces) half_edges += f.size();
  return static_cast<int>(half_edges / 2);
}
const std::vector<std::vector<int>>& ExactPolyhedron::faces() const { return impl_->faces; }

std::vector<Eigen::Vector3d> ExactPolyhedron::vertices_approx() const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(impl_->vertices.size());
  for (const auto& v : impl_->vertices) {
    out.emplace_back(CGAL::to_double(v.x()), CGAL::to_double(v.y()), CGAL::to_double(v.z()));
  }
  return out;
}

PolygonMesh ExactPolyhedron::to_mesh(const std::string& name, const Eigen::Vector3d& offset) const {
  PolygonMesh mesh;
  mesh.name = name;
  mesh.vertices = vertices_approx();
  for (auto& v : mesh.vertices) v += offset;
  mesh.faces = impl_->faces;
  return mesh;
}

bool ExactPolyhedron::is_valid_convex() const { return convexity_problem(*impl_).empty(); }

bool ExactPolyhedron::is_inside(const ExactPolyhedron& container) const {
  for (const auto& face : container.impl_->faces) {
    const auto& cv = container.impl_->vertices;
    const Plane3 plane(cv[face[0]], cv[face[1]], cv[face[2]]);
    for (const auto& v : impl_->vertices) {
      if (plane.oriented_side(v) == CGAL::ON_POSITIVE_SIDE) return false;
    }
  }
  return true;
}

ExactScalar ExactPolyhedron::projected_area_on(const ExactPlane& exact_plane) const {
  const Impl& p = *impl_;
  const Plane3& plane = ExactAccess::plane(exact_plane);
  const int k = dominant_axis(plane);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const bool positive = CGAL::is_positive(component(plane, k));
  FT sum = 0;
  for (const auto& face : p.faces) {
    bool on = true;
    for (int v : face) on = on && plane.has_on(p.vertices[static_cast<std::size_t>(v)]);
    if (!on) continue;
    // Twice the k component of the vector area (shoelace in the (i, j) plane): its sign
    // is that of the face's outward normal's k component.
    FT twice = 0;
    for (std::size_t m = 0; m < face.size(); ++m) {
      const Point3& a = p.vertices[static_cast<std::size_t>(face[m])];
      const Point3& b = p.vertices[static_cast<std::size_t>(face[(m + 1) % face.size()])];
      twice += a[i] * b[j] - a[j] * b[i];
    }
    if (CGAL::is_positive(twice) == positive) sum += (positive ? twice : -twice) / 2;
  }
  return ExactAccess::make_scalar(FT(sum.exact()));
}

double ExactPolyhedron::area_on(const ExactPlane& plane) const {
  return plane.area_of_projection(projected_area_on(plane));
}

ExactPolyhedron ExactPolyhedron::translated(const Eigen::Vector3d& offset) const {
  Impl impl;
  impl.faces = impl_->faces;
  const Kernel::Vector_3 d(offset.x(), offset.y(), offset.z());
  impl.vertices.reserve(impl_->vertices.size());
  for (const auto& v : impl_->vertices) impl.vertices.push_back(v + d);
  return ExactAccess::make_polyhedron(std::move(impl));
}

// ---------------------------------------------------------------------------------------
// Volumes and mass properties (exact rational arithmetic on the exact coordinates)

namespace {

struct ExactMoments {
  ExactFT six_volume;                 // 6 V
  std::array<ExactFT, 3> first24;     // 24 * first moment about the reference vertex
  std::array<ExactFT, 6> second120;   // 120 * second moments xx yy zz xy xz yz about it
};

/// Volume integrals of the polyhedron, fanning each face from its first corner and forming
/// tetrahedra with vertex 0 (the reference point): for a tetrahedron (0, a, b, c) with
/// D = a . (b x c), V = D/6, first moment D (a+b+c)/24, and
/// integral x_i x_j dV = D/120 (sum_k a_ki a_kj + s_i s_j), s = a+b+c (Tonon 2004).
ExactMoments exact_moments(const Impl& p, bool with_moments) {
  const auto& o = CGAL::exact(p.vertices[0]);
  std::vector<std::array<ExactFT, 3>> x(p.vertices.size());
  for (std::size_t i = 0; i < p.vertices.size(); ++i) {
    const auto& e = CGAL::exact(p.vertices[i]);
    x[i] = {e.x() - o.x(), e.y() - o.y(), e.z() - o.z()};
  }
  ExactMoments m{ExactFT(0), {ExactFT(0), ExactFT(0), ExactFT(0)},
                 {ExactFT(0), ExactFT(0), ExactFT(0), ExactFT(0), ExactFT(0), ExactFT(0)}};
  for (const auto& face : p.faces) {
    const auto& a = x[face[0]];
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      const auto& b = x[face[i]];
      const auto& c = x[face[i + 1]];
      const ExactFT det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                          a[2] * (b[0] * c[1] - b[1] * c[0]);
      m.six_volume += det;
      if (!with_moments) continue;
      const std::array<ExactFT, 3> s{a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
      for (int d = 0; d < 3; ++d) m.first24[d] += det * s[d];
      static constexpr int ij[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
      for (int q = 0; q < 6; ++q) {
        const int i0 = ij[q][0], j0 = ij[q][1];
        m.second120[q] += det * (a[i0] * a[j0] + b[i0] * b[j0] + c[i0] * c[j0] + s[i0] * s[j0]);
      }
    }
  }
  return m;
}

}  // namespace

ExactScalar ExactPolyhedron::volume() const {
  const ExactMoments m = exact_moments(*impl_, false);
  return ExactAccess::make_scalar(FT(m.six_volume / ExactFT(6)));
}

double ExactPolyhedron::volume_approx() const { return to_mesh().signed_volume(); }

namespace {
MassProperties compute_mass_properties(const Impl& p) {
  const ExactMoments m = exact_moments(p, true);
  const ExactFT volume = m.six_volume / ExactFT(6);
  // Centroid relative to the reference vertex: c = first / V = (first24 / 24) / (six / 6).
  std::array<ExactFT, 3> c;
  for (int d = 0; d < 3; ++d) c[d] = m.first24[d] / (ExactFT(4) * m.six_volume);
  // Central second moments S_ij = integral x_i x_j - V c_i c_j (exact: no cancellation loss).
  static constexpr int ij[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  Eigen::Matrix3d S;
  for (int q = 0; q < 6; ++q) {
    const int i = ij[q][0], j = ij[q][1];
    const ExactFT central = m.second120[q] / ExactFT(120) - volume * c[i] * c[j];
    S(i, j) = S(j, i) = CGAL::to_double(central);
  }
  MassProperties mp;
  mp.volume = CGAL::to_double(volume);
  const auto& o = CGAL::exact(p.vertices[0]);
  mp.centroid = {CGAL::to_double(o.x() + c[0]), CGAL::to_double(o.y() + c[1]),
                 CGAL::to_double(o.z() + c[2])};
  mp.inertia = S.trace() * Eigen::Matrix3d::Identity() - S;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(mp.inertia);
  mp.principal_moments = eig.eigenvalues();
  mp.principal_axes = eig.eigenvectors();
  if (mp.principal_axes.determinant() < 0.0) mp.principal_axes.col(2) *= -1.0;
  return mp;
}
}  // namespace

MassProperties ExactPolyhedron::mass_properties() const {
  return impl_->mass.get([this] { return compute_mass_properties(*impl_); });
}

ExactScalar total_volume(const std::vector<ExactPolyhedron>& parts) {
  ExactScalar sum;
  for (const auto& p : parts) sum = sum + p.volume();
  return sum;
}

// ---------------------------------------------------------------------------------------
// Plane split of a convex polyhedron

namespace {

/// Clips `p` to one closed side of `plane` (keep == ON_NEGATIVE_SIDE or ON_POSITIVE_SIDE).
/// Vertex ids: 0..n-1 are p's vertices, n.. are the cut points on crossing edges.
Impl clip(const Impl& p, const std::vector<CGAL::Oriented_side>& side,
          const std::vector<Point3>& cut_points,
          const std::map<std::pair<int, int>, int>& cut_of_edge, CGAL::Oriented_side keep) {
  const int n = static_cast<int>(p.vertices.size());
  auto on_plane = [&](int id) { return id >= n || side[id] == CGAL::ON_ORIENTED_BOUNDARY; };
  auto kept = [&](int id) { return id >= n || side[id] != -keep; };

  std::vector<std::vector<int>> faces;
  std::unordered_map<int, int> cap_next;  // cap loop: from -> to
  for (const auto& face : p.faces) {
    std::vector<int> poly;
    const std::size_t k = face.size();
    for (std::size_t i = 0; i < k; ++i) {
      const int a = face[i], b = face[(i + 1) % k];
      if (kept(a)) poly.push_back(a);
      if ((side[a] == CGAL::ON_POSITIVE_SIDE && side[b] == CGAL::ON_NEGATIVE_SIDE) ||
          (side[a] == CGAL::ON_NEGATIVE_SIDE && side[b] == CGAL::ON_POSITIVE_SIDE)) {
        poly.push_back(cut_of_edge.at({std::min(a, b), std::max(a, b)}));
      }
    }
    if (poly.size() < 3) continue;  // the face lies on the other side (or touches the plane)
    // The face's part in the plane is one of its edges a -> b; the cap runs b -> a there.
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const int a = poly[i], b = poly[(i + 1) % poly.size()];
      if (on_plane(a) && on_plane(b)) cap_next[b] = a;
    }
    faces.push_back(std::move(poly));
  }
  // Chain the cap edges into one loop.
  std::vector<int> cap;
  if (!cap_next.empty()) {
    const int start = cap_next.begin()->first;
    int at = start;
    do {
      cap.push_back(at);
      auto it = cap_next.find(at);
      if (it == cap_next.end() || cap.size() > cap_next.size()) {
        throw GeometryError("internal error: the cut section does not close");
      }
      at = it->second;
    } while (at != start);
    if (cap.size() != cap_next.size()) {
      throw GeometryError("internal error: the cut section is not a single loop");
    }
    faces.push_back(std::move(cap));
  }
  // Compact the vertex ids.
  Impl out;
  std::unordered_map<int, int> remap;
  for (auto& face : faces) {
    for (int& id : face) {
      auto [it, fresh] = remap.try_emplace(id, static_cast<int>(out.vertices.size()));
      if (fresh) out.vertices.push_back(id < n ? p.vertices[id] : cut_points[id - n]);
      id = it->second;
    }
  }
  out.faces = std::move(faces);
  return out;
}

}  // namespace

SplitResult ExactPolyhedron::split(const ExactPlane& exact_plane, double min_volume_fraction) const {
  const Impl& p = *impl_;
  const Plane3& plane = ExactAccess::plane(exact_plane);
  const int n = static_cast<int>(p.vertices.size());
  std::vector<CGAL::Oriented_side> side(n);
  int pos = 0, neg = 0;
  for (int i = 0; i < n; ++i) {
    side[i] = plane.oriented_side(p.vertices[i]);
    pos += side[i] == CGAL::ON_POSITIVE_SIDE;
    neg += side[i] == CGAL::ON_NEGATIVE_SIDE;
  }
  SplitResult result;
  if (pos == 0 || neg == 0) {
    result.status = SplitStatus::misses_body;
    result.reason = "the plane does not cut the interior: " + std::to_string(neg) +
                    " vertices below it, " + std::to_string(pos) + " above, " +
                    std::to_string(n - pos - neg) + " on it";
    return result;
  }
  // One exact cut point per edge that crosses the plane strictly.
  std::vector<Point3> cut_points;
  std::map<std::pair<int, int>, int> cut_of_edge;
  for (const auto& face : p.faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = std::min(face[i], face[(i + 1) % face.size()]);
      const int b = std::max(face[i], face[(i + 1) % face.size()]);
      if (side[a] * side[b] >= 0 || cut_of_edge.count({a, b})) continue;
      const auto hit = CGAL::intersection(Kernel::Segment_3(p.vertices[a], p.vertices[b]), plane);
      const Point3* q = hit ? boost::get<Point3>(&*hit) : nullptr;
      if (!q) throw GeometryError("internal error: crossing edge without a cut point");
      cut_of_edge[{a, b}] = n + static_cast<int>(cut_points.size());
      cut_points.push_back(*q);
    }
  }
  Impl below = clip(p, side, cut_points, cut_of_edge, CGAL::ON_NEGATIVE_SIDE);
  Impl above = clip(p, side, cut_points, cut_of_edge, CGAL::ON_POSITIVE_SIDE);
  ExactPolyhedron b = ExactAccess::make_polyhedron(std::move(below));
  ExactPolyhedron a = ExactAccess::make_polyhedron(std::move(above));
  const double vb = b.volume_approx(), va = a.volume_approx();
  result.below_fraction = vb / (vb + va);
  result.above_fraction = va / (vb + va);
  // A corner cut far below a double's resolution can round a part's volume to zero or
  // less; both parts are exact and non-empty here, so only a positive minimum refuses one.
  const double smaller = std::min(result.below_fraction, result.above_fraction);
  if (min_volume_fraction > 0.0 && smaller < min_volume_fraction) {
    result.status = SplitStatus::sliver;
    result.reason = "a fragment would hold " + std::to_string(smaller) +
                    " of the volume, below the minimum fraction " +
                    std::to_string(min_volume_fraction);
    return result;
  }
  result.status = SplitStatus::split;
  result.below = std::move(b);
  result.above = std::move(a);
  return result;
}

std::optional<ExactPolyhedron> ExactPolyhedron::clipped(const ExactPlane& exact_plane) const {
  const Plane3& plane = ExactAccess::plane(exact_plane);
  int pos = 0, neg = 0;
  for (const auto& v : impl_->vertices) {
    const auto side = plane.oriented_side(v);
    pos += side == CGAL::ON_POSITIVE_SIDE;
    neg += side == CGAL::ON_NEGATIVE_SIDE;
  }
  if (neg == 0) return *this;
  if (pos == 0) return std::nullopt;
  return split(exact_plane).above;
}

// ---------------------------------------------------------------------------------------
// Cleavage slabs of a prism

namespace {
/// True for the layout `hexagonal_prism` builds: 12 vertices, bottom and top hexagons, then
/// the six side quads, with exactly those indices.
bool is_honeycomb_prism(const Impl& p) {
  if (p.vertices.size() != 12 || p.faces.size() != 8) return false;
  if (p.faces[0] != std::vector<int>{0, 1, 2, 3, 4, 5}) return false;
  if (p.faces[1] != std::vector<int>{11, 10, 9, 8, 7, 6}) return false;
  for (int n = 0; n < 6; ++n) {
    const int m = (n + 1) % 6;
    if (p.faces[2 + n] != std::vector<int>{n, 6 + n, 6 + m, m}) return false;
  }
  return true;
}
}  // namespace

std::vector<ExactPlane> ExactPolyhedron::cleavage_planes(const CrystalOrientation& o) const {
  const auto normal = cleavage_normal(o);
  const Eigen::Vector3d want(normal[0], normal[1], normal[2]);
  std::vector<ExactPlane> planes;
  if (!is_honeycomb_prism(*impl_)) {
    // Any other convex grain: the prism's plane positions relative to the extent along the
    // normal (the <11-20> planes cut a hexagon's corner-to-corner width at its quarter
    // points, the <10-10> plane halves its flat-to-flat width).
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& v : vertices_approx()) {
      lo = std::min(lo, v.dot(want));
      hi = std::max(hi, v.dot(want));
    }
    const std::vector<double> at = o.family == CleavageFamily::a_11_20
                                       ? std::vector<double>{0.25, 0.75}
                                       : std::vector<double>{0.5};
    for (double f : at) planes.push_back(ExactPlane::from_normal_offset(want, lo + f * (hi - lo)));
    return planes;
  }
  for (const CornerPlane& cp : cleavage_corner_planes(o)) {
    // Bottom corners a and b, and the top corner above a: a vertical plane through the
    // grain's own exact vertices.
    ExactPlane plane = ExactPlane::through_vertices(*this, cp.corner_a, cp.corner_b, 6 + cp.corner_a);
    if (plane.normal_approx().dot(want) < 0.0) plane = plane.opposite();
    planes.push_back(std::move(plane));
  }
  return planes;
}

std::vector<ExactPolyhedron> ExactPolyhedron::cleavage_slabs(const CrystalOrientation& o,
                                                             double min_volume_fraction) const {
  std::vector<ExactPolyhedron> slabs;
  ExactPolyhedron rest = *this;
  for (const ExactPlane& plane : cleavage_planes(o)) {
    SplitResult r = rest.split(plane, min_volume_fraction);
    if (r.status == SplitStatus::sliver) continue;
    if (!r.ok()) throw GeometryError("cleavage split refused: " + r.reason);
    slabs.push_back(std::move(*r.below));
    rest = std::move(*r.above);
  }
  slabs.push_back(std::move(rest));
  return slabs;
}

}  // namespace cleave::geometry
