#pragma once
/// \file
/// Fine contact detection between two dilated convex polyhedra (sec. 2.3.1, App. B.2 of
/// the dissertation, seed 000) from the primitive kernels of contact_kernels.hpp.
///
/// Which primitive pairs count, so that one touching region is never counted twice and
/// the result does not depend on how faces are triangulated (faces are whole polygons):
/// - a face of A and a face of B that face each other (outward normals opposite within
///   about 6 degrees) and are within reach form a patch: contacts at the corners of the
///   overlap of the two polygons seen along their common normal (A's corners over B's
///   face, B's corners over A's face, and the crossings of the two rims). These points move
///   continuously as the faces rock, where single-feature contacts would flicker. The
///   patch replaces every vertex and edge contact between those two faces;
/// - every vertex of A against B, and every vertex of B against A: the vertex's sphere is
///   tested against the one feature of the other body that holds its closest point (a
///   face interior -> sphere-facet, an edge interior -> sphere-cylinder, a corner ->
///   sphere-sphere); corner-corner pairs are taken from A's side only;
/// - edge against edge (cylinder-cylinder) only where the segments cross (not parallel)
///   and the contact normal lies in both edges' normal cones (boundary included): the
///   crossings of two faces' rims are the corners of a face-to-face contact patch that are
///   not corners of either body. Parallel edges are left to the vertex contacts at the
///   ends of their overlap.
/// A vertex found inside the other body (deeper than its dilation) is reported against the
/// face it is least deep under, so fast bodies are pushed back out rather than lost.

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "physics/dem/body.hpp"
#include "physics/dem/contact_kernels.hpp"
#include "physics/dem/rigid_shape.hpp"

namespace cleave::physics {

/// How far orientation q is from q0: the smaller of |q - q0| and |q + q0| (q and -q are one
/// orientation), so a point at distance r from the centre moves at most 2 r times it. The
/// squares summed in Eigen's order for four doubles, (x^2 + z^2) + (y^2 + w^2), written out:
/// under AVX Eigen reloaded two just-stored 16-byte halves as one 32-byte load, which store
/// forwarding cannot serve.
inline double turn_between(const Eigen::Quaterniond& q, const Eigen::Quaterniond& q0) {
  const double mx = q.x() - q0.x(), my = q.y() - q0.y(), mz = q.z() - q0.z(),
               mw = q.w() - q0.w();
  const double px = q.x() + q0.x(), py = q.y() + q0.y(), pz = q.z() + q0.z(),
               pw = q.w() + q0.w();
  return std::sqrt(std::min((mx * mx + mz * mz) + (my * my + mw * mw),
                            (px * px + pz * pz) + (py * py + pw * pw)));
}

/// The largest shape the polyhedron contact search takes: its buffers are fixed (vertex
/// and face masks are 64 bits). A shape beyond them would meet nothing, so
/// World::add_shape refuses it and a split that would make one is refused.
struct ContactLimits {
  std::size_t vertices = 64, faces = 64, edges = 192;
};
inline constexpr ContactLimits kContactLimits{};
[[nodiscard]] inline bool within_contact_limits(const geometry::ContactPrimitives& p) {
  return p.vertices.size() <= kContactLimits.vertices && p.faces.size() <= kContactLimits.faces &&
         p.edges.size() <= kContactLimits.edges;
}

/// A body's primitives placed in the world for one step (computed once per body per step).
struct PosedShape {
  // What a pair that the near-feature cache holds apart reads comes first, in one cache line.
  const geometry::ContactPrimitives* primitives = nullptr;
  double radius = 0.0;  ///< dilation radius
  /// Motion bounds summed over every update since the first: the centre's path length, and
  /// the sum of |q_new - q_old| (nearer sign), which bounds half the chord any unit vector of
  /// the body swept (a unit vector turned by theta moves 2 sin(theta/2) <= 2 |dq|). By the
  /// triangle inequality they bound the net motion between any two updates.
  double travel = 0.0, turn = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< principal frame -> world
  std::vector<Eigen::Vector3d> vertices;      ///< world
  /// The face planes (world, outward normals; normal . x = offset on the face) as four rows
  /// of plane_stride() numbers: the normals' x, y and z, then the offsets, the rows padded to
  /// an even length with zeros, so that the distance tables' loops take two faces at a time.
  std::vector<double> planes;
  std::size_t faces = 0;  ///< the shape's face count, kept beside the planes (one cache line less)
  std::size_t plane_stride() const { return planes.size() / 4; }
  Eigen::Vector3d face_normal(std::size_t f) const {
    const std::size_t s = plane_stride();
    return {planes[f], planes[s + f], planes[2 * s + f]};
  }
  double face_offset(std::size_t f) const { return planes[3 * plane_stride() + f]; }
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< principal frame -> world
  /// Edge e's unit direction (world, from edge.a to edge.b), turned when asked for.
  Eigen::Vector3d edge_direction(std::size_t e) const { return rotation * primitives->edge_units[e]; }
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();  ///< world box of the vertices (undilated)
  Eigen::Vector3d hi = Eigen::Vector3d::Zero();

  /// Both of the below.
  void update(const RigidShape& shape, const BodyState& state);
  /// The frame alone: centre, orientation, rotation, radius and the motion bounds (what the
  /// motion checks of the near-feature cache and of a contact manifold read).
  void update_frame(const RigidShape& shape, const BodyState& state);
  /// The vertices, face planes and box from the frame (what a search reads).
  void update_geometry();
  /// The vertices and box alone (what a wall reads).
  void update_vertices();
};

/// Feature codes: kind in the top bits, index below.
enum class FeatureKind : std::uint32_t { vertex = 0, edge = 1, face = 2 };
constexpr std::uint32_t feature_code(FeatureKind kind, std::uint32_t index) {
  return (static_cast<std::uint32_t>(kind) << 16) | index;
}

struct FeatureContact {
  std::uint32_t feature_a = 0;  ///< feature of A
  std::uint32_t feature_b = 0;  ///< feature of B
  PrimitiveContact contact;     ///< normal from A towards B
};

/// Appends every contact between A and B with penetration > -margin, in a fixed order.
/// `culls` = false turns off the search's shortcuts that skip feature pairs which provably
/// add nothing (edge pairs, and a corner's candidate edges, ruled out by plane distances):
/// only to check that the result is the same bit for bit.
void polyhedron_contacts(const PosedShape& a, const PosedShape& b, double margin,
                         std::vector<FeatureContact>& out, bool culls = true);

/// The features of a pair that a full search found within reach plus a skin `skin` of each
/// other, and the bodies' motion bounds at that search. While the motion since then moves
/// any distance between a point of A and a point of B, and any distance of a point of one
/// from a face plane of the other, by less than half the skin (bounded by the travels plus
/// twice the lever times the turns), no other feature can come within reach, so a search
/// over these alone finds exactly the contacts the full search would: the same contacts in
/// the same order, bit for bit.
struct NearFeatures {
  double travel = 0.0, turn = 0.0;  ///< A's plus B's PosedShape::travel and turn at the search
  /// Bounds, while the cache holds, the distance of any point of A or B from either centre.
  double lever = 0.0;
  double skin = 0.0;   ///< 0: nothing cached
  bool none = false;   ///< nothing below may come within reach (the pair was apart by the skin)
  /// A later check found the pair apart by this gap beyond reach, at these motion bounds: it
  /// stays apart while the motion since stays under half of it (0: none found).
  double gap = 0.0, gap_travel = 0.0, gap_turn = 0.0;
  bool touching = false;  ///< the last search found contacts (its early outs are then skipped)
  std::uint64_t vertices_a = 0, vertices_b = 0;  ///< vertices that may come within reach
  std::uint64_t rows_a = 0, rows_b = 0;          ///< vertices whose plane distances are read
  std::array<std::uint64_t, 3> edges_a{}, edges_b{};  ///< edges that may come within reach
  /// Face pairs that may turn into a face-to-face patch, ascending (face of A, face of B).
  std::array<std::array<std::uint8_t, 2>, 12> face_pairs{};
  std::uint8_t face_pair_count = 0;
};

/// polyhedron_contacts with margin 0 through `near`: searches the cached features while the
/// relative motion since they were found allows, otherwise searches in full and caches the
/// features within `skin` (m) of reach. The result is always that of the full search.
/// Returns true when the cached features were searched.
bool polyhedron_contacts(const PosedShape& a, const PosedShape& b, double skin, NearFeatures& near,
                         std::vector<FeatureContact>& out);

/// A pair's persistent contact manifold (WorldSettings::manifold_tolerance > 0; an
/// approximation of the search above, off by default). The contacts a search found for a
/// touching pair are held, each as the two material points that meet there (one in each
/// body's principal frame), the normal in A's frame and the penetration. While B's pose
/// relative to A stays within half the margin of its pose at that search (no point of B
/// moved by more, relative to A), the contacts are those points carried with their bodies:
/// the penetration at the search minus the normal component of the points' separation
/// since, at the point midway between them. That is exact to first order in the relative
/// motion for a vertex against a face, an edge against an edge or two faces (the distance
/// between two planes is linear in position). A contact that begins to overlap while the
/// manifold holds is missed until the next search; its penetration is then below the
/// motion. Tests bound the force error against the full search (ContactManifold tests).
struct ContactManifold {
  struct Entry {
    std::uint32_t feature_a = 0, feature_b = 0;
    Eigen::Vector3d point_a = Eigen::Vector3d::Zero();   ///< A's material point, A's frame
    Eigen::Vector3d point_b = Eigen::Vector3d::Zero();   ///< B's material point, B's frame
    Eigen::Vector3d normal_a = Eigen::Vector3d::UnitZ();  ///< from A towards B, A's frame
    double penetration = 0.0;                             ///< at the search
  };
  std::vector<Entry> entries;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();                ///< B's centre in A's frame
  Eigen::Quaterniond turn = Eigen::Quaterniond::Identity();        ///< B's frame in A's frame
  double lever = 0.0;   ///< bounds the distance of B's points from its centre
  double margin = 0.0;  ///< the motion budget (m): it holds under half of it; 0: nothing held
};

/// Fills `m` from the contacts `found` by a search of A and B as posed, with the motion
/// budget `margin` (m).
void capture_manifold(const PosedShape& a, const PosedShape& b, const std::vector<FeatureContact>& found,
                      double margin, ContactManifold& m);

/// While B's motion relative to A since `m` was captured stays under half its margin,
/// appends the held contacts that overlap now (in the order held) and returns true;
/// otherwise appends nothing and returns false.
bool manifold_contacts(const PosedShape& a, const PosedShape& b, const ContactManifold& m,
                       std::vector<FeatureContact>& out);

/// manifold_contacts in two halves: whether the manifold still holds (from the frames
/// alone), and the held contacts that overlap now, each handed to f(feature_a, feature_b,
/// contact) in the order held (it must hold; for a caller that files them in its own list).
bool manifold_holds(const PosedShape& a, const PosedShape& b, const ContactManifold& m);
template <class F>
void for_carried_contacts(const PosedShape& a, const PosedShape& b, const ContactManifold& m, F&& f) {
  for (const ContactManifold::Entry& e : m.entries) {
    const Eigen::Vector3d pa = a.centre + a.rotation * e.point_a;
    const Eigen::Vector3d pb = b.centre + b.rotation * e.point_b;
    const Eigen::Vector3d n = a.rotation * e.normal_a;
    const double penetration = e.penetration - n.dot(pb - pa);
    if (penetration > 0.0) f(e.feature_a, e.feature_b, PrimitiveContact{0.5 * (pa + pb), n, penetration});
  }
}

/// Whether the near-feature cache says the pair is apart and will stay so (read from the
/// frames alone): polyhedron_contacts through `near` would then find nothing, without
/// reading vertices or planes.
bool near_features_apart(const PosedShape& a, const PosedShape& b, const NearFeatures& near);

}  // namespace cleave::physics
