#pragma once
/// \file
/// Consistent tractions on one planar face of a discrete element (sec. 3.2 of the
/// dissertation, seed 000, eqs 3.1-3.19): the discrete contact forces on the face are
/// replaced by a uniform shear traction (t_x, t_y) and a linear normal traction
/// t_n = t_o + C1 x + C2 y that do the same virtual work under the six rigid relative motions
/// of the face (eqs 3.8-3.12). The result is the 3x3 system of eq. 3.15 for (t_o, C1, C2),
/// t_x and t_y from eq. 3.14, and the torque M_z of eq. 3.14f / 3.18 kept on the side.
///
/// Conventions: the face frame is right-handed, (x_axis, y_axis, normal) with y = n x x and
/// the normal pointing out of the body; x and y are measured from the frame origin (the area
/// centroid unless a caller builds a FaceGeometry by hand). A traction is the force per area
/// that the surroundings put on the body, so t_n > 0 pulls the face outwards (tension) and a
/// contact pushing on the face gives t_n < 0.
///
/// Readings fixed here (the text leaves them open or misprints them):
/// - Eqs 3.11, 3.12, 3.14 and 3.15 print the right-hand sides as x (sum f_z), y (sum f_z) and
///   x (sum f_y) - y (sum f_x), with one x and one y for all forces. Each force acts at its
///   own point, so the consistent reading is sum_n x_n f_z^n, sum_n y_n f_z^n and
///   sum_n (x_n f_y^n - y_n f_x^n): the first moments of the normal forces and the twisting
///   moment about the frame origin. With that reading the right-hand sides are just the
///   components of the resultant force F and of its moment M about the origin in the face
///   frame: sum f_z = F.n, sum x f_z = -M.y_axis, sum y f_z = M.x_axis, M_z = M.n, which is
///   how `tractions_from_resultant` takes them.
/// - Eq. 3.8 prints the normal virtual motion as dw_o + x dtheta_x + xy dtheta_y; eq. 3.7 and
///   eq. 3.10 give dw_o + x dtheta_x + y dtheta_y, which is the one used (the "xy" is a slip).
/// - Eq. 3.13 defines I_ab = integral of a b dA, and eq. 3.14 pairs C1 with I_xx in the row of
///   integral x t_n dA, so I_xx = integral x^2 dA, I_yy = integral y^2 dA,
///   I_xy = integral x y dA. (In beam notation I_xx here is the moment about the y axis.)
///   Likewise Q_y = integral x dA and Q_x = integral y dA (eq. 3.13). Eq. 3.15 is solved in
///   full, so a frame origin away from the centroid (Q != 0) gives the same traction field.
/// - The kinematics of eq. 3.7 only know in-plane coordinates, so every contact point is
///   projected onto the face plane; the moment that enters (and the `moment` returned) uses
///   the projected points. A point's small offset along the normal (the overlap) adds no arm.
/// - The m a terms of eqs 3.8-3.19 are the body's d'Alembert force. It cannot be charged to
///   each face (it would be counted once per face), so the face tractions take the contact
///   forces alone; the inertia of a fragment enters at the crack plane (crack_plane.hpp).
/// - Uniform shear cannot represent a twist: t_x, t_y carry the in-plane force only and their
///   moment about the centroid is zero. The twisting moment M_z (eq. 3.14f, 3.18) is returned
///   on its own; `integrate_tractions` gives the field alone (no twist), `face_load` adds the
///   part of M_z the field does not carry, so it returns the discrete force and moment.
/// - The world frame is cleave's right-handed one; the change of basis of eqs 3.1-3.5 is a
///   projection on the orthonormal face axes (the matrix of eq. 3.4 is a rotation).

#include <Eigen/Dense>
#include <span>

namespace cleave::physics {

/// A planar face, its frame and its area moments (eq. 3.13) in that frame.
struct FaceGeometry {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< outward unit normal (local z)
  Eigen::Vector3d x_axis = Eigen::Vector3d::UnitX();  ///< in-plane unit axis (local x)
  Eigen::Vector3d y_axis = Eigen::Vector3d::UnitY();  ///< normal x x_axis (local y)
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   ///< frame origin (the centroid)
  double area = 0.0;                                  ///< A
  double q_x = 0.0;   ///< Q_x = integral of y dA (zero about the centroid)
  double q_y = 0.0;   ///< Q_y = integral of x dA (zero about the centroid)
  double i_xx = 0.0;  ///< I_xx = integral of x^2 dA
  double i_yy = 0.0;  ///< I_yy = integral of y^2 dA
  double i_xy = 0.0;  ///< I_xy = integral of x y dA

  /// In-plane coordinates (x, y) of the projection of world point p.
  [[nodiscard]] Eigen::Vector2d to_local(const Eigen::Vector3d& p) const;
  /// World point of in-plane coordinates (x, y).
  [[nodiscard]] Eigen::Vector3d to_world(double x, double y) const;
};

/// Area, centroid and second moments of a planar polygon (vertices in 3D, in order around
/// the boundary, either sense; projected onto the plane through their mean with unit
/// `normal`). The frame has `normal`, the unit projection of `x_axis` onto the plane and
/// y = normal x x; its origin is the area centroid, so q_x = q_y = 0.
FaceGeometry face_geometry(std::span<const Eigen::Vector3d> polygon, const Eigen::Vector3d& normal,
                           const Eigen::Vector3d& x_axis);

/// As above, with the normal from Newell's formula (counter-clockwise vertices seen from
/// outside give the outward normal) and the first edge as the x axis.
FaceGeometry face_geometry(std::span<const Eigen::Vector3d> polygon);

/// One discrete force on a face: where it acts (world) and the force (world).
struct PointForce {
  Eigen::Vector3d point;
  Eigen::Vector3d force;
};

/// A statically equivalent load: force, and moment about `point` (all world).
struct FaceLoad {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
};

/// Moment of `load` about world point p: M + (point - p) x F.
Eigen::Vector3d moment_about(const FaceLoad& load, const Eigen::Vector3d& p);

/// The consistent tractions of one face (eqs 3.14-3.19), in its frame.
struct FaceTractions {
  double t_x = 0.0;  ///< uniform shear along x_axis (eq. 3.14a)
  double t_y = 0.0;  ///< uniform shear along y_axis (eq. 3.14b)
  double t_o = 0.0;  ///< normal traction at the frame origin (eq. 3.15)
  double c1 = 0.0;   ///< normal traction gradient along x (eq. 3.15)
  double c2 = 0.0;   ///< normal traction gradient along y (eq. 3.15)
  double m_z = 0.0;  ///< twisting moment about the origin along the normal (eq. 3.14f)
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< resultant force (world)
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  ///< resultant moment about the origin

  /// Normal traction at in-plane coordinates (x, y), eq. 3.9.
  [[nodiscard]] double t_n(double x, double y) const { return t_o + c1 * x + c2 * y; }
  /// Shear traction magnitude, eq. 3.9 / 3.18.
  [[nodiscard]] double t_s() const;
};

/// Consistent tractions, eq. 3.15 of the dissertation, for a face carrying resultant `force`
/// and resultant moment `moment` about the frame origin (both world): the six right-hand
/// sides of eq. 3.14 are their components in the face frame.
FaceTractions tractions_from_resultant(const FaceGeometry& face, const Eigen::Vector3d& force,
                                       const Eigen::Vector3d& moment);

/// Consistent tractions, eqs 3.14-3.16, of the discrete forces on a face (points projected
/// onto the face plane).
FaceTractions face_tractions(const FaceGeometry& face, std::span<const PointForce> forces);

/// Eq. 3.20: the face's total force and moment (about the frame origin) from its tractions,
/// in closed form: the traction field's force and bending moments plus the twist M_z that
/// the uniform shear does not carry. Equals the discrete resultant.
FaceLoad face_load(const FaceGeometry& face, const FaceTractions& t);

/// The force and moment (about the frame origin) of the traction field alone over a polygon
/// in the face plane (the whole face, or a part of it), integrated triangle by triangle with
/// the edge-midpoint rule, exact for the linear force and quadratic moment integrands. No
/// twist beyond what the uniform shear itself carries.
FaceLoad integrate_tractions(const FaceGeometry& face, const FaceTractions& t,
                             std::span<const Eigen::Vector3d> polygon);

}  // namespace cleave::physics
