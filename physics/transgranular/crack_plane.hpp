#pragma once
/// \file
/// Tractions on a potential crack plane inside a discrete element (sec. 3.3 of the
/// dissertation, seed 000, eqs 3.20-3.21). The consistent tractions of each boundary face
/// (face_traction.hpp) give that face's force and moment (eq. 3.20); summed over the faces of
/// one fragment about the fragment's centroid and balanced, they give the force and moment
/// the rest of the element transmits through the crack section, and from those the
/// tractions on the section (eq. 3.21), in the same model as eq. 3.15: uniform shear and a
/// linear normal traction.
///
/// Conventions: a CrackPlane's normal points out of the fragment under study (from it into
/// the other part), so the fragment is the half-space (p - point).n <= 0 and the section's
/// normal traction is positive in tension, like a face's. The transmitted force and moment
/// are those the other part puts on the fragment.
///
/// Readings fixed here (the text leaves them open or misprints them):
/// - Sec. 3.3 writes M_crack = -M_centroid at "the centroid of the potential crack plane",
///   but M_centroid is summed about the fragment's centroid. The two points differ, so the
///   moment is moved: M_crack(c_s) = M_crack(g) + (g - c_s) x F_crack, with g the fragment
///   centroid and c_s the section centroid. In static equilibrium the result does not depend
///   on g at all.
/// - Equilibrium is d'Alembert's, as in eq. 3.8: F_crack = m a - F_faces and, about g,
///   M_crack = dH/dt - M_faces, where m a and dH/dt are the fragment's (FragmentInertia,
///   zero by default: the quasi-static balance printed in sec. 3.3). This is where the m a
///   terms of eqs 3.8-3.19 belong (see face_traction.hpp); the check (transgranular.hpp)
///   passes them from the grain's rigid motion (fragment_mass, fragment_inertia).
/// - Eq. 3.21 prints t = F(k) / Area_crack times a local axis, i.e. the components of the
///   crack force on the section axes divided by the section area. Those are the mean
///   tractions; t_x, t_y and t_o (the normal traction at the section centroid) keep exactly
///   these values. As asked by eq. 3.24 (which needs the bending moment), the moment about
///   the section centroid is not dropped: it sets C1, C2 through eq. 3.15 with the section's
///   area and second moments, and its normal component is the twist M_z.
/// - Sec. 3.3 notes that the smoothed tractions make faces cut by the crack easy to handle:
///   a cut face contributes the integral of its traction field over the part on the
///   fragment's side (`face_part_load`). Its twist M_z, which is no field, is shared in
///   proportion to area (a uniform distributed couple).

#include <Eigen/Dense>
#include <span>
#include <vector>

#include "physics/transgranular/face_traction.hpp"

namespace cleave::physics {

/// A potential crack plane: a point on it and the unit normal pointing out of the fragment.
struct CrackPlane {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

/// The part of a planar polygon (vertices in order) on the fragment's side of `plane`,
/// (p - point).normal <= 0, in the same order (Sutherland-Hodgman with one plane). Empty if
/// nothing is left; for a convex polygon the result is convex.
std::vector<Eigen::Vector3d> clip_polygon(std::span<const Eigen::Vector3d> polygon,
                                          const CrackPlane& plane);

/// clip_polygon into `out` (cleared first; its storage kept for the next call).
void clip_polygon_into(std::span<const Eigen::Vector3d> polygon, const CrackPlane& plane,
                       std::vector<Eigen::Vector3d>& out);

/// The load (moment about the face's frame origin) that the part of a face on the
/// fragment's side of `plane` carries: its traction field over the clipped polygon plus the
/// area share of the twist the field does not carry. For a face wholly on the fragment's
/// side it equals face_load(); for one wholly beyond it, zero.
FaceLoad face_part_load(const FaceGeometry& face, const FaceTractions& t,
                        std::span<const Eigen::Vector3d> face_polygon, const CrackPlane& plane);
/// face_part_load of a part already clipped (clip_polygon_into), for a caller that also
/// needs the part (the fragment's mass sum).
FaceLoad part_load(const FaceGeometry& face, const FaceTractions& t,
                   std::span<const Eigen::Vector3d> part);

/// The fragment's d'Alembert terms: its mass times the acceleration of its centroid, and
/// the rate of its angular momentum about its centroid (world).
struct FragmentInertia {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< m a
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  ///< dH/dt about the fragment centroid
};

/// Mass properties per unit density of a closed polyhedron: volume, centroid and the inertia
/// tensor about the centroid (world axes).
struct SolidMass {
  double volume = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

/// Sums a closed polyhedron face by face (divergence theorem: signed tetrahedra from
/// `origin`, a point near the solid, to each face's fan of triangles), exact for any
/// polyhedron up to round-off. Each face is a planar polygon with its outward normal; the
/// vertex order may run either way (it is taken about the normal).
class SolidMassSum {
 public:
  explicit SolidMassSum(const Eigen::Vector3d& origin) : origin_(origin) {}
  void add_face(std::span<const Eigen::Vector3d> polygon, const Eigen::Vector3d& outward);
  [[nodiscard]] SolidMass result() const;

 private:
  Eigen::Vector3d origin_;
  double six_volume_ = 0.0;                           // sum of det
  Eigen::Vector3d first_ = Eigen::Vector3d::Zero();   // 24 x integral of r dV
  Eigen::Matrix3d second_ = Eigen::Matrix3d::Zero();  // 120 x integral of r r^T dV
};

/// fragment_mass's sum, started about the mean of `section` (`plane`'s point when it is
/// empty); add the clipped faces, then the section, then take result().
SolidMassSum fragment_mass_sum(std::span<const Eigen::Vector3d> section, const CrackPlane& plane);

/// The part of a convex polyhedron (faces with outward normals) on the fragment's side of
/// `plane`, closed by `section` (the plane's cut through it, in order): its mass properties
/// per unit density.
SolidMass fragment_mass(std::span<const std::vector<Eigen::Vector3d>> faces,
                        std::span<const Eigen::Vector3d> outward,
                        std::span<const Eigen::Vector3d> section, const CrackPlane& plane);

/// A rigid body's motion at one instant, as a fragment of it shares it.
struct RigidMotion {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();      ///< the body's centroid G, world
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  ///< of G: a_G
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();         ///< angular velocity
  Eigen::Vector3d alpha = Eigen::Vector3d::Zero();         ///< angular acceleration
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();       ///< body force per mass on it
};

/// The d'Alembert terms of a fragment of density `rho` and mass properties `fragment` that
/// moves rigidly with `body`: m (a_G + alpha x r + omega x (omega x r) - g), r from G to the
/// fragment's centroid, and dH/dt = J alpha + omega x (J omega) about its centroid. The
/// fragment's weight is taken off its m a: gravity acts on it as a body force, not through
/// a face, so its faces and the section alone balance m (a - g).
FragmentInertia fragment_inertia(const RigidMotion& body, double rho, const SolidMass& fragment);

/// What the crack section carries (sec. 3.3).
struct CrackPlaneLoad {
  /// The crack section, normal out of the fragment, origin at its centroid.
  FaceGeometry section;
  /// Its vertices (world), as given.
  std::vector<Eigen::Vector3d> polygon;
  /// F_centroid: the sum of the fragment's face forces.
  Eigen::Vector3d applied_force = Eigen::Vector3d::Zero();
  /// M_centroid: their moment about the fragment centroid.
  Eigen::Vector3d applied_moment = Eigen::Vector3d::Zero();
  /// F_crack: the force the rest of the element puts on the fragment through the section.
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  /// M_crack: its moment about the section centroid.
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  /// Eq. 3.21 (the means t_x, t_y, t_o) with eq. 3.15's linear normal part and the twist.
  FaceTractions tractions;
};

/// Eqs 3.20-3.21: sums the loads of the fragment's faces (each with its own moment point)
/// about `fragment_centroid`, balances them (with the optional d'Alembert terms) and returns
/// the load transmitted through the crack section and its tractions. `section_polygon` is the
/// crack section (vertices on the plane, in order), `x_axis` the section's in-plane x axis
/// (projected onto the plane). The caller chooses which faces, or parts of faces
/// (face_part_load), belong to the fragment.
CrackPlaneLoad crack_plane_load(std::span<const FaceLoad> fragment_faces,
                                const Eigen::Vector3d& fragment_centroid,
                                std::span<const Eigen::Vector3d> section_polygon,
                                const CrackPlane& plane, const Eigen::Vector3d& x_axis,
                                const FragmentInertia& inertia = {});

}  // namespace cleave::physics
