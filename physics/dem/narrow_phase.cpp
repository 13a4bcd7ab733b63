#include "physics/dem/narrow_phase.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <bit>
#include <limits>
#include <tuple>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace cleave::physics {

namespace {

constexpr std::size_t kMaxVertices = kContactLimits.vertices;
constexpr std::size_t kMaxFaces = kContactLimits.faces;

/// Signed distances of every vertex of `from` to every face plane of `to`. Left
/// uninitialised: only the entries plane_distances writes are read.
struct PlaneDistances {
  std::size_t faces = 0;
  std::size_t stride = 0;  ///< a row's length: faces, made even
  std::array<double, kMaxVertices * kMaxFaces> d;
  /// Bit f of vertex v: the vertex is `reach` or more beyond face f's plane.
  std::array<std::uint64_t, kMaxVertices> beyond;
  double deep = 0.0;  ///< minus reach times `to`'s edge cone spread (see edge_pair_culled)
  double at(std::size_t v, std::size_t f) const { return d[v * stride + f]; }
};

std::uint64_t all_bits(std::size_t n) { return n >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1; }

/// The rows of the vertices in `rows` (bit v: vertex v) only.
void plane_distances(const PosedShape& from, const PosedShape& to, std::uint64_t rows, double reach,
                     PlaneDistances& out) {
  out.faces = to.faces;
  out.stride = to.plane_stride();
  out.deep = -reach * to.primitives->edge_cone_spread;
  const std::size_t stride = out.stride;
  const double* __restrict nx = to.planes.data();
  const double* __restrict ny = nx + stride;
  const double* __restrict nz = ny + stride;
  const double* __restrict offset = nz + stride;
  // The rows left out have no `beyond` bits: what reads them unmasked (the near-edge test
  // of contacts_over) then drops them on their own mask.
  std::fill_n(out.beyond.begin(), from.vertices.size(), std::uint64_t{0});
  for (; rows != 0; rows &= rows - 1) {
    const auto v = static_cast<std::size_t>(std::countr_zero(rows));
    const double x = from.vertices[v].x(), y = from.vertices[v].y(), z = from.vertices[v].z();
    double* __restrict d = out.d.data() + v * stride;
    std::uint64_t beyond = 0;
#ifdef __SSE2__
    // Two faces at a time, rounded as the scalar loop below would be.
    const __m128d px = _mm_set1_pd(x), py = _mm_set1_pd(y), pz = _mm_set1_pd(z), pr = _mm_set1_pd(reach);
    for (std::size_t f = 0; f < stride; f += 2) {
      const __m128d xy = _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(nx + f), px), _mm_mul_pd(_mm_loadu_pd(ny + f), py));
      const __m128d dist = _mm_sub_pd(_mm_add_pd(xy, _mm_mul_pd(_mm_loadu_pd(nz + f), pz)), _mm_loadu_pd(offset + f));
      _mm_storeu_pd(d + f, dist);
      beyond |= static_cast<std::uint64_t>(_mm_movemask_pd(_mm_cmpge_pd(dist, pr))) << f;
    }
    beyond &= all_bits(out.faces);  // not the padding
#else
    for (std::size_t f = 0; f < stride; ++f) d[f] = nx[f] * x + ny[f] * y + nz[f] * z - offset[f];
    for (std::size_t f = 0; f < out.faces; ++f) beyond |= static_cast<std::uint64_t>(d[f] >= reach) << f;
#endif
    out.beyond[v] = beyond;
  }
}

/// Polygon of face f of `s` as a small array of world points.
struct FacePolygon {
  std::array<Eigen::Vector3d, kMaxVertices> pts;  // Eigen leaves these uninitialised
  std::size_t n = 0;
};
void face_polygon(const PosedShape& s, std::size_t f, FacePolygon& out) {
  const auto& idx = s.primitives->faces[f].vertices;
  out.n = idx.size();
  for (std::size_t i = 0; i < out.n; ++i) out.pts[i] = s.vertices[idx[i]];
}

/// A plane distance this far beyond `reach` is beyond it whatever the rounding of the
/// distances compared with it (about 1e-16 of the coordinates, against 1e-6 of the reach).
double clearly_beyond(double reach) { return reach * (1.0 + 1e-6); }

/// Contact of vertex v of `p` (the sphere side) against `q`. Returns the contact with the
/// normal from p's vertex towards q, and q's feature code.
bool vertex_against(const PosedShape& p, std::size_t v, const PosedShape& q,
                    const PlaneDistances& dist, double margin, bool corner_pairs, bool culls,
                    std::uint32_t& q_feature, PrimitiveContact& c) {
  const double reach = p.radius + q.radius + margin;
  const Eigen::Vector3d& x = p.vertices[v];
  double dmax = -std::numeric_limits<double>::infinity();
  std::size_t fmax = 0;
  for (std::size_t f = 0; f < dist.faces; ++f) {
    const double d = dist.at(v, f);
    if (d > dmax) {
      dmax = d;
      fmax = f;
    }
  }
  if (dmax >= reach) return false;  // separated by that face's plane
  FacePolygon poly;
  if (dmax < 0.0) {  // inside q: push out through the face it is least deep under
    c.normal = -q.face_normal(fmax);
    c.penetration = p.radius + q.radius - dmax;
    c.point = x - (p.radius - 0.5 * c.penetration) * c.normal;
    q_feature = feature_code(FeatureKind::face, static_cast<std::uint32_t>(fmax));
    return true;
  }
  // A face whose plane the point is above and whose polygon it projects into holds the
  // closest point of q.
  for (std::size_t f = 0; f < dist.faces; ++f) {
    const double d = dist.at(v, f);
    if (d < 0.0 || d >= reach) continue;
    face_polygon(q, f, poly);
    if (auto hit = sphere_facet(x, p.radius, {poly.pts.data(), poly.n}, q.face_normal(f),
                                q.radius, margin)) {
      c = *hit;
      q_feature = feature_code(FeatureKind::face, static_cast<std::uint32_t>(f));
      return true;
    }
  }
  // Otherwise the closest point is on an edge or a corner of a face the point is above.
  // An edge lies in both its faces' planes, so it is at least as far from x as either plane:
  // one with a plane x is clearly beyond reach of cannot be the closest within reach, and is
  // passed over (a cull: without it such an edge could be the closest, but out of reach).
  const auto& edges = q.primitives->edges;
  const double far = culls ? clearly_beyond(reach) : std::numeric_limits<double>::infinity();
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_edge = 0;
  double best_t = 0.0;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto& E = edges[e];
    const double d_left = dist.at(v, E.left_face), d_right = dist.at(v, E.right_face);
    if ((d_left < 0.0 && d_right < 0.0) || d_left > far || d_right > far) continue;
    const Eigen::Vector3d& a = q.vertices[E.a];
    const Eigen::Vector3d ab = q.vertices[E.b] - a;
    const double t = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    const double d2 = (a + t * ab - x).squaredNorm();
    if (d2 < best) {
      best = d2;
      best_edge = e;
      best_t = t;
    }
  }
  if (!(best < reach * reach)) return false;
  const auto& E = edges[best_edge];
  if (best_t > 0.0 && best_t < 1.0) {
    if (auto hit = sphere_cylinder(x, p.radius, q.vertices[E.a], q.vertices[E.b], q.radius, margin)) {
      c = *hit;
      q_feature = feature_code(FeatureKind::edge, static_cast<std::uint32_t>(best_edge));
      return true;
    }
    return false;
  }
  if (!corner_pairs) return false;
  const int corner = best_t <= 0.0 ? E.a : E.b;
  if (auto hit = sphere_sphere(x, p.radius, q.vertices[corner], q.radius, margin)) {
    c = *hit;
    q_feature = feature_code(FeatureKind::vertex, static_cast<std::uint32_t>(corner));
    return true;
  }
  return false;
}

/// True when direction u lies in the normal cone of edge E of s (between the outward normals
/// of its two faces, in the plane across the edge), its boundary included: a face-to-face
/// touch shows up as the crossings of the two faces' rims, with the face normal as u.
bool in_normal_cone(const PosedShape& s, const geometry::ContactEdge& E, const Eigen::Vector3d& u) {
  const Eigen::Vector3d e = s.edge_direction(static_cast<std::size_t>(&E - s.primitives->edges.data()));
  const Eigen::Vector3d n1 = s.face_normal(E.left_face);
  const Eigen::Vector3d n2 = s.face_normal(E.right_face);
  Eigen::Vector3d m1 = e.cross(n1);
  if (m1.dot(n2) < 0.0) m1 = -m1;
  Eigen::Vector3d m2 = e.cross(n2);
  if (m2.dot(n1) < 0.0) m2 = -m2;
  constexpr double eps = 1e-9;
  return u.dot(m1) > -eps && u.dot(m2) > -eps;
}

/// Whether an edge of `s` can reach `other` at all: no face plane of `other` has both
/// endpoints `reach` or more beyond it.
bool edge_near(const PlaneDistances& dist, const geometry::ContactEdge& E, double reach) {
  for (std::size_t f = 0; f < dist.faces; ++f) {
    if (dist.at(E.a, f) >= reach && dist.at(E.b, f) >= reach) return false;
  }
  return true;
}
/// The same for the reach the distances were computed with, from their `beyond` masks.
bool edge_near(const PlaneDistances& dist, const geometry::ContactEdge& E) {
  return (dist.beyond[E.a] & dist.beyond[E.b]) == 0;
}

/// Whether edge E of A and edge F of B cannot make an edge-edge contact that passes the
/// normal cone tests. Such a contact joins p on E and q on F, |p - q| = dist < reach, with
/// p - q in F's normal cone: for either face f of F, whose plane holds q, the distance of p
/// from f's plane is n_f . (p - q) >= -spread dist > -spread reach (spread: B's
/// edge_cone_spread). That distance is affine along E, so one of E's ends is as far out: a
/// pair whose edge E lies wholly more than spread reach behind a face plane of F's cannot
/// touch, and the same with A and B swapped. The spread's 1e-6 is far above the rounding of
/// the distances (about 1e-16 of the coordinates).
bool edge_pair_culled(const geometry::ContactEdge& E, const PlaneDistances& a_to_b,
                      const geometry::ContactEdge& F, const PlaneDistances& b_to_a) {
  auto behind = [](const PlaneDistances& dist, const geometry::ContactEdge& edge, int face) {
    return std::max(dist.at(edge.a, face), dist.at(edge.b, face)) < dist.deep;
  };
  return behind(a_to_b, E, F.left_face) | behind(a_to_b, E, F.right_face) |
         behind(b_to_a, F, E.left_face) | behind(b_to_a, F, E.right_face);
}

/// The face pair of a face-to-face touch: nearly opposite outward normals (within about 6
/// degrees) and planes within reach of each other's corners.
constexpr double kFaceToFaceCos = 0.9945;  // cos 6 degrees

/// A point this close to a face's side line, relative to the side's length, is on it: a
/// nanometre for a millimetre side, far above the rounding of world coordinates and far
/// below any overlap that carries load.
constexpr double kRimTolerance = 1e-6;

struct Patch {
  std::size_t fa, fb;
};

/// Contacts of a face-to-face touch between face fa of A and face fb of B: the corners of
/// the overlap of the two polygons seen along the common normal n. They are A's corners
/// over B's face, B's corners over A's face (but for those on one of A's counted corners),
/// and the crossings of the two rims. Unlike single vertex or edge contacts, these points
/// move continuously when the faces tilt a little, so the patch does not flicker as bodies
/// rock on each other. `covered_a` and `covered_b` collect (as bits) the corners the patch
/// already holds, whose own vertex contacts then need not be looked for.
///
/// Everything is decided in the plane across n, in coordinates (u, v) with u x v = n, where
/// the 2-D cross product of two projected vectors is their triple product with n. There A's
/// rim runs counter-clockwise (its face looks along n) and B's clockwise. One table holds
/// how far inside each side of one rim each corner of the other lies (times the side's
/// length): side_b(i, j) for A's corner i and B's side j, side_a(i, j) for B's corner j and
/// A's side i. A point within kRimTolerance of a side's length of a side's line is on it:
/// such a corner is inside (its polygon closed), and two sides cross only where each has
/// its ends clearly on both sides of the other's line. So sides on one line (as grains of a
/// lattice leave them, to rounding) make no crossing, and a crossing at a corner is that
/// corner's contact: every corner of the overlap is found once, whatever the rounding.
void face_patch(const PosedShape& a, std::size_t fa, const PosedShape& b, std::size_t fb,
                const PlaneDistances& a_to_b, const PlaneDistances& b_to_a, double margin,
                std::vector<FeatureContact>& out, std::uint64_t& covered_a,
                std::uint64_t& covered_b) {
  const double radii = a.radius + b.radius;
  const Eigen::Vector3d na = a.face_normal(fa);
  const Eigen::Vector3d nb = b.face_normal(fb);
  const Eigen::Vector3d n = (na - nb).normalized();  // from A towards B
  FacePolygon pa, pb;
  face_polygon(a, fa, pa);
  face_polygon(b, fb, pb);
  const std::size_t na_n = pa.n, nb_n = pb.n;
  const auto& ia = a.primitives->faces[fa].vertices;
  const auto& ib = b.primitives->faces[fb].vertices;
  const auto& rim_ia = a.primitives->faces[fa].rim;
  const auto& rim_ib = b.primitives->faces[fb].rim;
  const Eigen::Vector3d u = n.unitOrthogonal();
  const Eigen::Vector3d v = n.cross(u);
  std::array<Eigen::Vector2d, kMaxVertices> qa2, qb2, da2, db2;
  // A side value is the side's length times a distance: the tolerance for a distance of
  // kRimTolerance lengths is kRimTolerance times the length squared.
  std::array<double, kMaxVertices> tol_a, tol_b;
  for (std::size_t i = 0; i < na_n; ++i) {
    const Eigen::Vector3d d = pa.pts[(i + 1) % na_n] - pa.pts[i];
    qa2[i] = {u.dot(pa.pts[i]), v.dot(pa.pts[i])};
    da2[i] = {u.dot(d), v.dot(d)};
    const double len = a.primitives->edge_lengths[rim_ia[i]];
    tol_a[i] = kRimTolerance * len * len;
  }
  for (std::size_t j = 0; j < nb_n; ++j) {
    const Eigen::Vector3d d = pb.pts[(j + 1) % nb_n] - pb.pts[j];
    qb2[j] = {u.dot(pb.pts[j]), v.dot(pb.pts[j])};
    db2[j] = {u.dot(d), v.dot(d)};
    const double len = b.primitives->edge_lengths[rim_ib[j]];
    tol_b[j] = kRimTolerance * len * len;
  }
  auto cross2 = [](const Eigen::Vector2d& x, const Eigen::Vector2d& y) { return x.x() * y.y() - x.y() * y.x(); };
  // The table, and which corners are inside: which tests pass is as good as random to a
  // branch predictor, so they are gathered as bits, without branching, and acted on after.
  constexpr std::size_t kCells = kMaxVertices * kMaxVertices;
  std::array<double, kCells> side_a, side_b;  // cell i * nb_n + j
  std::uint64_t a_inside = all_bits(na_n), b_inside = all_bits(nb_n);
  for (std::size_t i = 0; i < na_n; ++i) {
    bool a_in = true;
    for (std::size_t j = 0; j < nb_n; ++j) {
      const std::size_t k = i * nb_n + j;
      const Eigen::Vector2d w = qb2[j] - qa2[i];
      side_a[k] = cross2(da2[i], w);  // B's corner j inside A's side i (left of it)
      side_b[k] = cross2(db2[j], w);  // A's corner i inside B's side j (right of it)
      a_in &= side_b[k] >= -tol_b[j];
      b_inside &= ~(static_cast<std::uint64_t>(side_a[k] < -tol_a[i]) << j);
    }
    a_inside &= ~(static_cast<std::uint64_t>(!a_in) << i);
  }
  // A's corners over B's face.
  std::uint64_t a_counted = 0;
  for (std::uint64_t m = a_inside; m != 0; m &= m - 1) {
    const auto i = static_cast<std::size_t>(std::countr_zero(m));
    const double pen = radii - a_to_b.at(ia[i], fb);
    if (pen <= -margin) continue;
    PrimitiveContact c{pa.pts[i] - (a.radius - 0.5 * pen) * nb, -nb, pen};
    out.push_back({feature_code(FeatureKind::vertex, ia[i]), feature_code(FeatureKind::face, fb), c});
    covered_a |= std::uint64_t{1} << ia[i];
    a_counted |= std::uint64_t{1} << i;
  }
  // B's corners over A's face, but for one on a corner of A's counted above: that point
  // is counted once. B's corners so passed over are covered all the same.
  for (std::uint64_t m = b_inside; m != 0; m &= m - 1) {
    const auto j = static_cast<std::size_t>(std::countr_zero(m));
    const double pen = radii - b_to_a.at(ib[j], fa);
    if (pen <= -margin) continue;
    covered_b |= std::uint64_t{1} << ib[j];
    bool shared = false;
    for (std::uint64_t mi = a_counted; mi != 0; mi &= mi - 1) {
      const auto i = static_cast<std::size_t>(std::countr_zero(mi));
      // On A's corner i: on the lines of both of A's sides there.
      const std::size_t before = (i + na_n - 1) % na_n;
      shared |= std::abs(side_a[i * nb_n + j]) <= tol_a[i] && std::abs(side_a[before * nb_n + j]) <= tol_a[before];
    }
    if (shared) continue;
    PrimitiveContact c{pb.pts[j] - (b.radius - 0.5 * pen) * na, na, pen};
    out.push_back({feature_code(FeatureKind::face, fa), feature_code(FeatureKind::vertex, ib[j]), c});
  }
  // Rim crossings: side i of A (corners i, i1) and side j of B (corners j, j1) cross when
  // each has its ends clearly on both sides of the other's line.
  auto clearly_apart = [](double x, double y, double tol) { return (x > tol && y < -tol) || (x < -tol && y > tol); };
  for (std::size_t i = 0; i < na_n; ++i) {
    const std::size_t i1 = (i + 1) % na_n;
    std::uint64_t crosses = 0;
    for (std::size_t j = 0; j < nb_n; ++j) {
      const std::size_t j1 = (j + 1) % nb_n;
      const bool cross = clearly_apart(side_b[i * nb_n + j], side_b[i1 * nb_n + j], tol_b[j]) &
                         clearly_apart(side_a[i * nb_n + j], side_a[i * nb_n + j1], tol_a[i]);
      crosses |= static_cast<std::uint64_t>(cross) << j;
    }
    for (; crosses != 0; crosses &= crosses - 1) {
      const auto j = static_cast<std::size_t>(std::countr_zero(crosses));
      const std::size_t j1 = (j + 1) % nb_n;
      // Where the side values along each side pass zero.
      const double s = side_b[i * nb_n + j] / (side_b[i * nb_n + j] - side_b[i1 * nb_n + j]);
      const double t = side_a[i * nb_n + j] / (side_a[i * nb_n + j] - side_a[i * nb_n + j1]);
      const Eigen::Vector3d qa = pa.pts[i] + s * (pa.pts[i1] - pa.pts[i]);
      const Eigen::Vector3d qb = pb.pts[j] + t * (pb.pts[j1] - pb.pts[j]);
      const double pen = radii - (qb - qa).dot(n);
      if (pen <= -margin) continue;
      PrimitiveContact c{qa + (a.radius - 0.5 * pen) * n, n, pen};
      out.push_back({feature_code(FeatureKind::edge, static_cast<std::uint32_t>(rim_ia[i])),
                     feature_code(FeatureKind::edge, static_cast<std::uint32_t>(rim_ib[j])), c});
    }
  }
}

bool face_has_vertex(const geometry::ContactPrimitives& p, std::size_t f, std::uint32_t v) {
  const auto& vs = p.faces[f].vertices;
  return std::find(vs.begin(), vs.end(), static_cast<int>(v)) != vs.end();
}

/// Whether feature `code` of shape p lies on face f (the face, one of its edges or corners).
bool feature_on_face(const geometry::ContactPrimitives& p, std::uint32_t code, std::size_t f) {
  const auto kind = static_cast<FeatureKind>(code >> 16);
  const std::uint32_t index = code & 0xFFFFu;
  switch (kind) {
    case FeatureKind::face: return index == f;
    case FeatureKind::edge:
      return static_cast<std::size_t>(p.edges[index].left_face) == f ||
             static_cast<std::size_t>(p.edges[index].right_face) == f;
    case FeatureKind::vertex: return face_has_vertex(p, f, index);
  }
  return false;
}

/// The face of `s` that looks most towards `other` (its outward normal nearest the line of
/// centres): the separating axis the early outs try.
std::size_t facing_face(const PosedShape& s, const PosedShape& other) {
  const Eigen::Vector3d towards = other.centre - s.centre;
  std::size_t best = 0;
  double best_dot = -std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < s.faces; ++f) {
    const double d = s.face_normal(f).dot(towards);
    if (d > best_dot) {
      best_dot = d;
      best = f;
    }
  }
  return best;
}

/// Separating-axis early out: when every vertex of `other` is beyond reach of the plane of
/// `s`'s facing face the two cannot touch. Most pairs found by the bounding-sphere search
/// end here, before the full distance tables are built.
bool separated_by_facing_face(const PosedShape& s, const PosedShape& other, double reach) {
  const std::size_t best = facing_face(s, other);
  const Eigen::Vector3d n = s.face_normal(best);
  const double offset = s.face_offset(best) + reach;
  for (const auto& v : other.vertices) {
    if (n.dot(v) < offset) return false;
  }
  return true;
}

/// A convex polyhedron has at most 3 V - 6 edges.
constexpr std::size_t kMaxEdges = kContactLimits.edges;
static_assert(kMaxEdges == 3 * kMaxVertices, "a convex polyhedron has at most 3V - 6 edges");
static_assert(kMaxVertices <= 64 && kMaxFaces <= 64 && kMaxEdges <= 192,
              "vertex and face masks are 64 bits, edge masks 192");
using EdgeMask = std::array<std::uint64_t, 3>;
bool has_edge(const EdgeMask& m, std::size_t e) { return ((m[e >> 6] >> (e & 63)) & 1u) != 0; }
EdgeMask all_edges(std::size_t n) {
  return {all_bits(n), n > 64 ? all_bits(n - 64) : 0, n > 128 ? all_bits(n - 128) : 0};
}

/// The features the search looks at: everything (the full search) or a pair's cached near
/// features. Rows are the vertices whose plane distances have been computed.
struct FeatureSet {
  std::uint64_t vertices_a, vertices_b;
  EdgeMask edges_a, edges_b;
  const std::array<std::uint8_t, 2>* face_pairs = nullptr;  ///< nullptr: every face pair
  std::size_t face_pair_count = 0;
  bool culls = true;  ///< edge_pair_culled and vertex_against's edge cull (off: to check they change nothing)
};

/// Whether face fa of A and face fb of B face each other (outward normals opposite within
/// about 6 degrees, the cosine's bound widened by `turn`) with each face's nearest corner
/// within `reach` of the other's plane and not deeper than `reach` behind it.
bool faces_facing(const PosedShape& a, std::size_t fa, const PosedShape& b, std::size_t fb,
                  const PlaneDistances& a_to_b, const PlaneDistances& b_to_a, double reach,
                  double turn = 0.0) {
  if (a.face_normal(fa).dot(b.face_normal(fb)) > -kFaceToFaceCos + turn) return false;
  double da = std::numeric_limits<double>::infinity(), db = da;
  for (int v : a.primitives->faces[fa].vertices) da = std::min(da, a_to_b.at(v, fb));
  for (int v : b.primitives->faces[fb].vertices) db = std::min(db, b_to_a.at(v, fa));
  return !(da >= reach || db >= reach || da < -reach || db < -reach);
}

/// The search over the features of `set`, the distance tables holding their rows.
void contacts_over(const PosedShape& a, const PosedShape& b, double margin, const FeatureSet& set,
                   const PlaneDistances& a_to_b, const PlaneDistances& b_to_a,
                   std::vector<FeatureContact>& out) {
  const double reach = a.radius + b.radius + margin;
  // Face-to-face touches first: their patches replace the vertex and edge contacts of the
  // two faces. Each face of A takes the first face of B it faces, if any.
  std::array<Patch, 8> patches;
  std::size_t n_patches = 0;
  std::uint64_t covered_a = 0, covered_b = 0;
  auto try_patch = [&](std::size_t fa, std::size_t fb) {
    if (!faces_facing(a, fa, b, fb, a_to_b, b_to_a, reach)) return false;
    const std::size_t before = out.size();
    face_patch(a, fa, b, fb, a_to_b, b_to_a, margin, out, covered_a, covered_b);
    if (out.size() > before) patches[n_patches++] = {fa, fb};
    return true;
  };
  if (set.face_pairs == nullptr) {
    for (std::size_t fa = 0; fa < a.faces && n_patches < patches.size(); ++fa) {
      for (std::size_t fb = 0; fb < b.faces; ++fb) {
        if (try_patch(fa, fb)) break;
      }
    }
  } else {
    for (std::size_t k = 0; k < set.face_pair_count && n_patches < patches.size();) {
      const std::uint8_t fa = set.face_pairs[k][0];
      bool taken = false;
      for (; k < set.face_pair_count && set.face_pairs[k][0] == fa; ++k) {
        if (!taken) taken = try_patch(fa, set.face_pairs[k][1]);
      }
    }
  }
  auto in_patch_a = [&](std::uint32_t code_a, std::uint32_t code_b) {
    for (std::size_t k = 0; k < n_patches; ++k) {
      if (feature_on_face(*a.primitives, code_a, patches[k].fa) &&
          feature_on_face(*b.primitives, code_b, patches[k].fb)) {
        return true;
      }
    }
    return false;
  };

  PrimitiveContact c;
  std::uint32_t feature = 0;
  for (std::uint64_t m = set.vertices_a & ~covered_a; m != 0; m &= m - 1) {
    const auto v = static_cast<std::size_t>(std::countr_zero(m));
    if (vertex_against(a, v, b, a_to_b, margin, true, set.culls, feature, c)) {
      const std::uint32_t code = feature_code(FeatureKind::vertex, static_cast<std::uint32_t>(v));
      if (!in_patch_a(code, feature)) out.push_back({code, feature, c});
    }
  }
  for (std::uint64_t m = set.vertices_b & ~covered_b; m != 0; m &= m - 1) {
    const auto v = static_cast<std::size_t>(std::countr_zero(m));
    if (vertex_against(b, v, a, b_to_a, margin, false, set.culls, feature, c)) {
      c.normal = -c.normal;  // from A towards B
      const std::uint32_t code = feature_code(FeatureKind::vertex, static_cast<std::uint32_t>(v));
      if (!in_patch_a(feature, code)) out.push_back({feature, code, c});
    }
  }
  // Edge against edge. Which edges can reach the other body, and which lie on a patched
  // face, are worked out once per pair rather than once per edge pair; the pairs are then
  // ruled out on plane distances (edge_pair_culled) before an edge's geometry is made.
  // These tests pass or fail as good as at random to a branch predictor, so the lists of
  // what passes are made without branching: each entry is written, and kept by advancing
  // the list's end or not.
  const auto& ea = a.primitives->edges;
  const auto& eb = b.primitives->edges;
  struct Segment {
    Eigen::Vector3d mid, dir;
    double half;
  };
  // A side's near edges in ascending order, with the patches whose face they lie on (bit k:
  // patch k).
  struct NearEdges {
    std::array<std::uint8_t, kMaxEdges> edge, patches;
    std::size_t n = 0;
  };
  auto near_edges = [&](const std::vector<geometry::ContactEdge>& edges, const EdgeMask& mask,
                        const PlaneDistances& dist, bool side_a, NearEdges& out) {
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const auto& E = edges[e];
      std::uint8_t on = 0;
      for (std::size_t k = 0; k < n_patches; ++k) {
        const auto f = static_cast<int>(side_a ? patches[k].fa : patches[k].fb);
        on |= static_cast<std::uint8_t>(((E.left_face == f) | (E.right_face == f)) << k);
      }
      out.edge[out.n] = static_cast<std::uint8_t>(e);
      out.patches[out.n] = on;
      // Only a masked edge's ends have distance rows (and `beyond` masks).
      out.n += has_edge(mask, e) & edge_near(dist, E);
    }
  };
  NearEdges near_a, near_b;
  near_edges(eb, set.edges_b, b_to_a, false, near_b);
  if (near_b.n == 0) return;
  near_edges(ea, set.edges_a, a_to_b, true, near_a);
  std::array<Segment, kMaxEdges> seg_b;
  std::array<bool, kMaxEdges> made_b{};
  std::array<std::uint8_t, kMaxEdges> candidates;
  for (std::size_t ia = 0; ia < near_a.n; ++ia) {
    const std::size_t i = near_a.edge[ia];
    const auto& E = ea[i];
    std::size_t n_candidates = 0;
    for (std::size_t k = 0; k < near_b.n; ++k) {
      const bool patched = (near_a.patches[ia] & near_b.patches[k]) != 0;  // the patch has them
      const bool culled = set.culls && edge_pair_culled(E, a_to_b, eb[near_b.edge[k]], b_to_a);
      candidates[n_candidates] = static_cast<std::uint8_t>(k);
      n_candidates += !(patched | culled);
    }
    if (n_candidates == 0) continue;
    const Eigen::Vector3d& p1 = a.vertices[E.a];
    const Eigen::Vector3d& q1 = a.vertices[E.b];
    const Segment seg_a{0.5 * (p1 + q1), a.edge_direction(i), 0.5 * a.primitives->edge_lengths[i]};
    for (std::size_t c = 0; c < n_candidates; ++c) {
      const std::size_t k = candidates[c];
      const std::size_t j = near_b.edge[k];
      const Eigen::Vector3d& p2 = b.vertices[eb[j].a];
      const Eigen::Vector3d& q2 = b.vertices[eb[j].b];
      if (!made_b[k]) {
        seg_b[k] = {0.5 * (p2 + q2), b.edge_direction(j), 0.5 * b.primitives->edge_lengths[j]};
        made_b[k] = true;
      }
      // Two segments whose midpoints are further apart than their half lengths plus the
      // reach cannot touch.
      const double bound = seg_a.half + seg_b[k].half + reach;
      if ((seg_b[k].mid - seg_a.mid).squaredNorm() > bound * bound) continue;
      if (seg_a.dir.cross(seg_b[k].dir).squaredNorm() < 1e-12) continue;  // parallel
      auto hit = cylinder_cylinder(p1, q1, a.radius, p2, q2, b.radius, margin);
      if (!hit) continue;
      if (!in_normal_cone(a, E, hit->normal) || !in_normal_cone(b, eb[j], -hit->normal)) continue;
      out.push_back({feature_code(FeatureKind::edge, static_cast<std::uint32_t>(i)),
                     feature_code(FeatureKind::edge, static_cast<std::uint32_t>(j)), *hit});
    }
  }
}

bool within_buffers(const PosedShape& a, const PosedShape& b) {
  return a.vertices.size() <= kMaxVertices && b.vertices.size() <= kMaxVertices &&
         a.faces <= kMaxFaces && b.faces <= kMaxFaces &&
         a.primitives->edges.size() <= kMaxEdges && b.primitives->edges.size() <= kMaxEdges;
}

/// How far apart A and B certainly are beyond `reach`, by early_out's tests: the largest
/// margin by which the boxes, or one body's vertices beyond the other's facing face, clear
/// it; negative when no test separates them (early_out is then false).
double separation(const PosedShape& a, const PosedShape& b, double reach) {
  double gap = -1.0;
  for (int k = 0; k < 3; ++k) {
    const double g = std::max(a.lo[k] - reach - b.hi[k], b.lo[k] - reach - a.hi[k]);
    if (g > 0.0) gap = std::max(gap, g);
  }
  if (gap > 0.0) return gap;
  for (const auto& [s, other] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
    const std::size_t best = facing_face(*s, *other);
    const Eigen::Vector3d n = s->face_normal(best);
    const double offset = s->face_offset(best) + reach;
    double least = std::numeric_limits<double>::infinity();
    for (const auto& v : other->vertices) least = std::min(least, n.dot(v) - offset);
    if (least >= 0.0) gap = std::max(gap, least);
  }
  return gap;
}

/// The broad early outs: boxes, then a separating face plane from either side. When one
/// holds for `reach`, no feature of A is within `reach` of B.
bool early_out(const PosedShape& a, const PosedShape& b, double reach) {
  // Boxes first: far cheaper than the face tests, and enough for most pairs of elongated
  // bodies whose bounding spheres overlap. Most pairs found by the bounding-sphere search
  // end at the face test, before the full distance tables are built.
  if ((a.lo.array() - reach > b.hi.array()).any() || (b.lo.array() - reach > a.hi.array()).any()) {
    return true;
  }
  return separated_by_facing_face(a, b, reach) || separated_by_facing_face(b, a, reach);
}

FeatureSet every_feature(const PosedShape& a, const PosedShape& b) {
  return {all_bits(a.vertices.size()), all_bits(b.vertices.size()), all_edges(a.primitives->edges.size()),
          all_edges(b.primitives->edges.size())};
}

/// The motion bounds and lever of a search at this pose.
void start_near_features(const PosedShape& a, const PosedShape& b, double skin, NearFeatures& near) {
  near.travel = a.travel + b.travel;
  near.turn = a.turn + b.turn;
  near.gap = 0.0;  // a gap is found within one cache's time (its lever bounds the motion)
  near.lever = a.primitives->bounding_radius + b.primitives->bounding_radius + (b.centre - a.centre).norm() + skin;
}

/// Fills `near` with the features within reach + skin, from full distance tables.
void cache_near_features(const PosedShape& a, const PosedShape& b, double reach, double skin,
                         const PlaneDistances& a_to_b, const PlaneDistances& b_to_a, NearFeatures& near) {
  start_near_features(a, b, skin, near);
  const double wide = reach + skin;
  auto vertices_within = [wide](std::size_t n, const PlaneDistances& dist) {
    std::uint64_t m = 0;
    for (std::size_t v = 0; v < n; ++v) {
      double dmax = -std::numeric_limits<double>::infinity();
      for (std::size_t f = 0; f < dist.faces; ++f) dmax = std::max(dmax, dist.at(v, f));
      if (dmax < wide) m |= std::uint64_t{1} << v;
    }
    return m;
  };
  near.vertices_a = vertices_within(a.vertices.size(), a_to_b);
  near.vertices_b = vertices_within(b.vertices.size(), b_to_a);
  near.rows_a = near.vertices_a;
  near.rows_b = near.vertices_b;
  auto edges_within = [wide](const std::vector<geometry::ContactEdge>& edges, const PlaneDistances& dist,
                             std::uint64_t& rows) {
    EdgeMask m{};
    for (std::size_t e = 0; e < edges.size(); ++e) {
      if (!edge_near(dist, edges[e], wide)) continue;
      m[e >> 6] |= std::uint64_t{1} << (e & 63);
      rows |= (std::uint64_t{1} << edges[e].a) | (std::uint64_t{1} << edges[e].b);
    }
    return m;
  };
  near.edges_a = edges_within(a.primitives->edges, a_to_b, near.rows_a);
  near.edges_b = edges_within(b.primitives->edges, b_to_a, near.rows_b);
  // A normal turns by at most 2 (turn of A + turn of B) < skin / (2 lever) while the cache
  // holds; the face test's thresholds are widened by the skin.
  const double turn = skin / near.lever;
  near.face_pair_count = 0;
  for (std::size_t fa = 0; fa < a.faces; ++fa) {
    for (std::size_t fb = 0; fb < b.faces; ++fb) {
      if (!faces_facing(a, fa, b, fb, a_to_b, b_to_a, wide, turn)) continue;
      if (near.face_pair_count == near.face_pairs.size()) {  // too many to cache
        near.skin = 0.0;
        return;
      }
      near.face_pairs[near.face_pair_count++] = {static_cast<std::uint8_t>(fa), static_cast<std::uint8_t>(fb)};
      for (int v : a.primitives->faces[fa].vertices) near.rows_a |= std::uint64_t{1} << v;
      for (int v : b.primitives->faces[fb].vertices) near.rows_b |= std::uint64_t{1} << v;
    }
  }
  near.none = (near.vertices_a | near.vertices_b | near.edges_a[0] | near.edges_a[1] | near.edges_a[2] |
               near.edges_b[0] | near.edges_b[1] | near.edges_b[2]) == 0 &&
              near.face_pair_count == 0;
  near.skin = skin;
}

/// Whether the bodies have moved since the search by less than half the cached skin. A
/// point of A moves by at most A's travel plus twice its distance from A's centre times A's
/// turn. The distance of a point p from a face plane of B, n . (p - c_B) - h, changes by at
/// most |dn| |p - c_B| + |dp| + |dc_B|, with |dn| <= 2 B's turn; the lever bounds |p - c_B|
/// and the distances from A's centre while this holds.
bool near_features_hold(const PosedShape& a, const PosedShape& b, const NearFeatures& near) {
  if (near.skin <= 0.0) return false;
  const double moved = (a.travel + b.travel - near.travel) + 2.0 * near.lever * (a.turn + b.turn - near.turn);
  return moved < 0.5 * near.skin;
}

/// The pair was found apart by `near.gap` since its cache was filled, and its motion since
/// stays under half of it (the cache's lever bounds the bodies' points).
bool gap_holds(const PosedShape& a, const PosedShape& b, const NearFeatures& near) {
  const double moved =
      (a.travel + b.travel - near.gap_travel) + 2.0 * near.lever * (a.turn + b.turn - near.gap_turn);
  return near.gap > 0.0 && moved < 0.5 * near.gap;
}

}  // namespace

void polyhedron_contacts(const PosedShape& a, const PosedShape& b, double margin,
                         std::vector<FeatureContact>& out, bool culls) {
  if (!within_buffers(a, b)) return;  // World::add_shape refuses shapes beyond the buffers
  const double reach = a.radius + b.radius + margin;
  if (early_out(a, b, reach)) return;
  FeatureSet all = every_feature(a, b);
  all.culls = culls;
  PlaneDistances a_to_b, b_to_a;
  plane_distances(a, b, all.vertices_a, reach, a_to_b);  // A's vertices against B's faces
  plane_distances(b, a, all.vertices_b, reach, b_to_a);  // B's vertices against A's faces
  contacts_over(a, b, margin, all, a_to_b, b_to_a, out);
}

bool polyhedron_contacts(const PosedShape& a, const PosedShape& b, double skin, NearFeatures& near,
                         std::vector<FeatureContact>& out) {
  const bool hold = near_features_hold(a, b, near);
  if (hold && near.none) return true;  // the commonest case, on the fewest cache lines
  if (hold && gap_holds(a, b, near)) return true;  // apart by a gap found since, and still
  if (!within_buffers(a, b)) return false;
  const double reach = a.radius + b.radius;
  PlaneDistances a_to_b, b_to_a;
  if (hold) {
    // The early outs rule out only pairs that the search would find apart; a pair that
    // touched at the last search most likely still does, and goes straight to the search.
    if (!near.touching) {
      // Apart by these tests: and certainly so while the motion stays under half the gap
      // they leave (near_features_apart), which saves the geometry and the tests.
      const double gap = separation(a, b, reach);
      if (gap >= 0.0) {
        near.gap = gap;
        near.gap_travel = a.travel + b.travel;
        near.gap_turn = a.turn + b.turn;
        return true;
      }
    }
    plane_distances(a, b, near.rows_a, reach, a_to_b);
    plane_distances(b, a, near.rows_b, reach, b_to_a);
    const FeatureSet set{near.vertices_a, near.vertices_b, near.edges_a, near.edges_b,
                         near.face_pairs.data(), near.face_pair_count};
    const std::size_t before = out.size();
    contacts_over(a, b, 0.0, set, a_to_b, b_to_a, out);
    near.touching = out.size() > before;
    return true;
  }
  // A full search, caching what lies within reach + skin. A pair apart by the skin on top
  // of the reach caches nothing, which stays right while the cache holds.
  if (early_out(a, b, reach + skin)) {
    near = NearFeatures{};  // no features
    start_near_features(a, b, skin, near);
    near.none = true;
    near.skin = skin;
    return false;
  }
  const FeatureSet all = every_feature(a, b);
  plane_distances(a, b, all.vertices_a, reach, a_to_b);
  plane_distances(b, a, all.vertices_b, reach, b_to_a);
  cache_near_features(a, b, reach, skin, a_to_b, b_to_a, near);
  const std::size_t before = out.size();
  if (!early_out(a, b, reach)) contacts_over(a, b, 0.0, all, a_to_b, b_to_a, out);
  near.touching = out.size() > before;
  return false;
}

bool near_features_apart(const PosedShape& a, const PosedShape& b, const NearFeatures& near) {
  return near_features_hold(a, b, near) && (near.none || gap_holds(a, b, near));
}

}  // namespace cleave::physics
