#pragma once
/// \file
/// Exact convex polyhedra (CGAL Epeck, rational arithmetic) behind a CGAL-free interface.
///
/// Every grain and fragment shape is held once, exactly, in its own shape frame. Splitting
/// along a plane is exact, so fragment volumes sum to the parent volume with no rounding;
/// `ExactScalar` lets callers compare such sums exactly. Double data for the dynamics
/// (mass properties, contact primitives, meshes) is derived from the exact shape once.
///
/// CGAL itself is confined to exact_polyhedron.cpp, convex_mesh.cpp and cgal_validation.cpp.

#include <Eigen/Dense>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/crystal.hpp"
#include "geometry/polygon_mesh.hpp"

namespace cleave::geometry {

/// Thrown for an invalid shape (not closed, not convex, inward faces, bad exact text).
class GeometryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An exact rational number (a volume, a coordinate). Immutable, cheap to copy.
class ExactScalar {
 public:
  ExactScalar();                      ///< zero
  explicit ExactScalar(double value); ///< the double's exact value
  ExactScalar operator+(const ExactScalar& other) const;
  ExactScalar operator-(const ExactScalar& other) const;
  ExactScalar operator*(const ExactScalar& other) const;
  bool operator==(const ExactScalar& other) const;  ///< exact comparison
  bool operator<(const ExactScalar& other) const;   ///< exact comparison
  [[nodiscard]] double to_double() const;
  /// "numerator/denominator" in lowest terms (or an integer), exactly.
  [[nodiscard]] std::string to_string() const;
  static ExactScalar parse(const std::string& text);  ///< inverse of to_string
  struct Impl;

 private:
  explicit ExactScalar(std::shared_ptr<const Impl> impl);
  std::shared_ptr<const Impl> impl_;
  friend class ExactPolyhedron;
  friend class ExactPlane;
  friend struct ExactAccess;
};

class ExactPolyhedron;

/// An oriented plane a x + b y + c z + d = 0 with exact coefficients. Its positive side is
/// where a x + b y + c z + d > 0, i.e. the side the normal (a, b, c) points to.
class ExactPlane {
 public:
  /// n . x = offset, with the doubles taken exactly.
  static ExactPlane from_normal_offset(const Eigen::Vector3d& normal, double offset);
  /// Through three points (taken exactly), normal (q - p) x (r - p). Throws if collinear.
  static ExactPlane through_points(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                   const Eigen::Vector3d& r);
  /// Through three vertices of `body`, exactly. Throws if collinear.
  static ExactPlane through_vertices(const ExactPolyhedron& body, int i, int j, int k);
  /// Through vertex `i` of `body` (exactly), with normal `normal` (taken exactly).
  static ExactPlane through_vertex(const ExactPolyhedron& body, int i, const Eigen::Vector3d& normal);
  /// Containing the segment from vertex `i` to vertex `j` of `body` (exactly) and the
  /// direction `along` (taken exactly). Throws if `along` is parallel to the segment.
  static ExactPlane through_segment(const ExactPolyhedron& body, int i, int j,
                                    const Eigen::Vector3d& along);
  /// The perpendicular bisector of `p` and `q` (taken exactly): the points equally far from
  /// both, exactly. `p` lies on its positive side. Throws if p == q.
  static ExactPlane bisector(const Eigen::Vector3d& p, const Eigen::Vector3d& q);
  /// The bisector of `p` and `q + shift`, the sum taken exactly (an image of q in a
  /// periodic box: the bisectors of images match their translates exactly).
  static ExactPlane bisector(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& shift);
  /// The power (Laguerre) bisector of `p` with weight `wp` and `q + shift` with weight `wq`:
  /// the points x with |x - p|^2 - wp = |x - q'|^2 - wq, i.e.
  /// 2 (q' - p) . x = |q'|^2 - |p|^2 - (wq - wp), every term formed exactly from the doubles.
  /// Its positive side is where p's power is the smaller (p's cell), which need not hold p.
  /// Throws if p == q'.
  static ExactPlane power_bisector(const Eigen::Vector3d& p, double wp, const Eigen::Vector3d& q,
                                   double wq,
                                   const Eigen::Vector3d& shift = Eigen::Vector3d::Zero());

  [[nodiscard]] ExactPlane opposite() const;
  /// The area of a region of this plane whose projection (ExactPolyhedron::
  /// projected_area_on) has exact area `projected`: with normal n = (a, b, c) and k the axis
  /// of n's largest |n_k|, A = P |n| / |n_k|. |n| is a square root, so A^2 = P^2 |n|^2 /
  /// n_k^2 is formed exactly and rounded to double once before the square root: A is
  /// within an ulp or two of the true area.
  [[nodiscard]] double area_of_projection(const ExactScalar& projected) const;
  /// Approximate unit normal and offset (n . x = offset) in doubles.
  [[nodiscard]] Eigen::Vector3d normal_approx() const;
  [[nodiscard]] double offset_approx() const;
  /// Exact coefficients as text "a b c d" (rationals).
  [[nodiscard]] std::string to_string() const;
  static ExactPlane parse(const std::string& text);
  struct Impl;

 private:
  explicit ExactPlane(std::shared_ptr<const Impl> impl);
  std::shared_ptr<const Impl> impl_;
  friend class ExactPolyhedron;
  friend struct ExactAccess;
};

/// Mass properties of a shape of unit density, computed in exact arithmetic from the
/// exact polyhedron and then rounded to double.
struct MassProperties {
  double volume = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< in the shape frame
  /// Inertia tensor about the centroid (axes of the shape frame), per unit density:
  /// I = integral of (|r|^2 Id - r r^T) dV with r measured from the centroid.
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();  ///< ascending
  Eigen::Matrix3d principal_axes = Eigen::Matrix3d::Identity(); ///< columns, right-handed

  /// Mass and inertia of a body of this shape with density rho (kg/m^3).
  [[nodiscard]] double mass(double rho) const { return rho * volume; }
  [[nodiscard]] Eigen::Matrix3d inertia_tensor(double rho) const { return rho * inertia; }
};

/// Why a split was refused.
enum class SplitStatus {
  split,        ///< two fragments made
  misses_body,  ///< the plane does not cut the interior (all vertices on one side or on it)
  sliver,       ///< a fragment would be below the minimum volume fraction
};

struct SplitResult;

/// A closed convex polyhedron with exact (rational) vertex coordinates and outward polygon
/// faces. Immutable; copies share the same data.
class ExactPolyhedron {
 public:
  /// The hexagonal prism grain of table 2.2 / App. A, centred at the origin: side `side`
  /// (r-bar), thickness `thickness`, axis along z. Vertex n (0..5) is bottom corner n at
  /// z = -thickness/2 (see hexagon_corner), vertex 6+n the top corner above it. Faces:
  /// bottom, top, then side n between corners n and n+1.
  static ExactPolyhedron hexagonal_prism(double side, double thickness);

  /// From double vertices (taken exactly) and polygon faces (CCW seen from outside).
  /// Throws GeometryError unless the result is closed, convex and outward oriented.
  static ExactPolyhedron from_mesh(const PolygonMesh& mesh);

  /// Parses the text written by `to_exact_text`; throws GeometryError on bad text.
  static ExactPolyhedron from_exact_text(const std::string& text);
  /// Exact serialisation: "vertices N" then N lines "x y z" (rationals), "faces M" then M
  /// lines "k i0 i1 ... ik-1". Round-trips exactly.
  [[nodiscard]] std::string to_exact_text() const;

  [[nodiscard]] int num_vertices() const;
  [[nodiscard]] int num_faces() const;
  [[nodiscard]] int num_edges() const;
  [[nodiscard]] const std::vector<std::vector<int>>& faces() const;
  /// Vertex coordinates rounded to double.
  [[nodiscard]] std::vector<Eigen::Vector3d> vertices_approx() const;
  /// The shape as a double polygon mesh, translated by `offset`, named `name`.
  [[nodiscard]] PolygonMesh to_mesh(const std::string& name = {},
                                    const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) const;

  /// Exact volume.
  [[nodiscard]] ExactScalar volume() const;
  /// Volume from the double vertices (for thresholds and reports, not for invariants).
  [[nodiscard]] double volume_approx() const;
  /// Exact mass properties, rounded to double at the end.
  [[nodiscard]] MassProperties mass_properties() const;

  /// True when every vertex is exactly on the closed inner side of every face plane of
  /// `container` (i.e. this shape lies inside `container`).
  [[nodiscard]] bool is_inside(const ExactPolyhedron& container) const;
  /// Exact check of the invariants: closed 2-manifold, every face planar and convex, every
  /// vertex on the inner side of every face plane, positive volume.
  [[nodiscard]] bool is_valid_convex() const;

  /// Splits by `plane` into the part on its negative side (`below`) and positive side
  /// (`above`). Refuses (no fragments, a reason) when the plane misses the interior, or
  /// when either part would be smaller than `min_volume_fraction` of this volume.
  /// Planes through vertices, along edges or touching faces are handled exactly.
  [[nodiscard]] SplitResult split(const ExactPlane& plane, double min_volume_fraction = 0.0) const;

  /// The part on the closed positive side of `plane`, exactly: this shape when no vertex is
  /// strictly below it, nothing when no vertex is strictly above it (no interior left).
  [[nodiscard]] std::optional<ExactPolyhedron> clipped(const ExactPlane& plane) const;

  /// Splits the shape into its cleavage slabs (figs 2.8/2.9; see cleavage_planes), ordered
  /// along the cleavage normal. For the prism every plane passes through existing
  /// vertices, so no new coordinates are made. A cut whose smaller part would be below
  /// `min_volume_fraction` of the piece it cuts is skipped (that piece stays whole).
  [[nodiscard]] std::vector<ExactPolyhedron> cleavage_slabs(const CrystalOrientation& orientation,
                                                            double min_volume_fraction = 0.0) const;
  /// The exact cleavage planes for `orientation` (normals along cleavage_normal), in the
  /// order cleavage_slabs cuts them. For the prism made by `hexagonal_prism` (recognised by
  /// its vertex and face layout) they pass through its own corners (figs 2.8/2.9). Any
  /// other convex shape (a grain from a mesh, a Voronoi cell) gets the same family's
  /// planes placed as they sit in the prism relative to its extent along the normal:
  /// <10-10> one plane halving the extent, <11-20> two planes at its quarter points
  /// (offsets from the rounded vertices, then taken exactly).
  [[nodiscard]] std::vector<ExactPlane> cleavage_planes(
      const CrystalOrientation& orientation) const;

  /// The faces of this shape lying on `plane` whose outward normal is the plane's own
  /// normal (the shape lies on the plane's negative side there: a cut's `below` piece has
  /// its section there), their area projected onto the coordinate plane across the axis k
  /// of the plane normal's largest |n_k| (the k component of the faces' vector area
  /// 1/2 sum v_i x v_i+1, sign n_k), exactly. Zero when no face lies there. Projected areas
  /// of faces on one plane add exactly; ExactPlane::area_of_projection turns a sum into an
  /// area.
  [[nodiscard]] ExactScalar projected_area_on(const ExactPlane& plane) const;
  /// The area of those faces, m^2 when the coordinates are m:
  /// plane.area_of_projection(projected_area_on(plane)). For a split's `below` piece and
  /// its plane: the exact section of the cut, rounded once.
  [[nodiscard]] double area_on(const ExactPlane& plane) const;

  /// A copy moved by `offset` (exactly).
  [[nodiscard]] ExactPolyhedron translated(const Eigen::Vector3d& offset) const;

  struct Impl;

 private:
  explicit ExactPolyhedron(std::shared_ptr<const Impl> impl);
  std::shared_ptr<const Impl> impl_;
  friend struct ExactAccess;
};

struct SplitResult {
  SplitStatus status = SplitStatus::misses_body;
  std::string reason;  ///< empty when split
  std::optional<ExactPolyhedron> below;  ///< negative side of the plane
  std::optional<ExactPolyhedron> above;  ///< positive side of the plane
  double below_fraction = 0.0;           ///< approximate volume fractions of the parent
  double above_fraction = 0.0;
  [[nodiscard]] bool ok() const { return status == SplitStatus::split; }
};

/// Exact sum of volumes.
ExactScalar total_volume(const std::vector<ExactPolyhedron>& parts);

/// Independent check with CGAL's own algorithms (Surface_mesh, Polygon_mesh_processing):
/// the shape as a CGAL surface mesh is valid, closed, outward oriented, and its PMP volume
/// equals `volume()` exactly. Used by tests; defined in cgal_validation.cpp.
struct CgalValidation {
  bool valid_mesh = false;
  bool closed = false;
  bool outward_oriented = false;
  bool volume_matches = false;
  [[nodiscard]] bool ok() const { return valid_mesh && closed && outward_oriented && volume_matches; }
};
CgalValidation validate_with_cgal(const ExactPolyhedron& shape);

}  // namespace cleave::geometry
