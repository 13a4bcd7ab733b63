#pragma once
/// \file
/// Full 3D crystal orientations of grains: Bunge Euler angles, crystal symmetry, misorientation
/// angles, seeded sampling of uniform, fibre and preferred textures, and the misorientation-angle
/// density of randomly oriented grains (the reference for statistical tests).
///
/// Convention (shared by every part of cleave): an orientation is a unit quaternion q, canonical
/// form w >= 0, that rotates CRYSTAL coordinates into SPECIMEN coordinates (active rotation):
///
///     v_specimen = q * v_crystal.
///
/// Bunge Euler angles (phi1, Phi, phi2) name the passive matrix that maps specimen coordinates to
/// crystal coordinates (its rows are the crystal axes written in the specimen frame):
///
///     g = Rz(phi2) * Rx(Phi) * Rz(phi1),
///     Rz(a) = [[cos a, sin a, 0], [-sin a, cos a, 0], [0, 0, 1]],
///     Rx(a) = [[1, 0, 0], [0, cos a, sin a], [0, -sin a, cos a]],
///
/// so the orientation is the rotation g^T: q = qz(phi1) * qx(Phi) * qz(phi2) with qz(a), qx(a)
/// the active rotations by +a about z and x. The API takes radians; files hold degrees.
///
/// Crystal frames: cubic axes along x, y, z; hexagonal and trigonal with the c axis along
/// crystal z and an a axis along crystal x.

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace cleave::geometry {

/// From Bunge angles in radians (any range) to the canonical orientation quaternion.
Eigen::Quaterniond from_bunge(double phi1, double Phi, double phi2);

/// Bunge angles in radians: phi1, phi2 in [0, 2 pi), Phi in [0, pi]. At Phi = 0 (and Phi = pi)
/// only phi1 + phi2 (phi1 - phi2) is defined; phi2 = 0 is returned there.
std::array<double, 3> to_bunge(const Eigen::Quaterniond& q);

/// q or -q, whichever has w >= 0 (both are the same rotation), normalised.
Eigen::Quaterniond canonical(const Eigen::Quaterniond& q);

/// The rotation angle of q in [0, pi].
double rotation_angle(const Eigen::Quaterniond& q);

/// Proper point groups (rotations only: the Laue class's rotation subgroup).
enum class PointGroup : std::uint8_t {
  cubic,      ///< O (432): 24 rotations
  hexagonal,  ///< D6 (622): 12 rotations, c along z, two-fold axes every 30 deg from x
  trigonal,   ///< D3 (32, setting 321): 6 rotations, c along z, two-fold axes along the a axes
  orthorhombic,  ///< D2 (222): 4 rotations, two-fold axes along x, y and z
  none,       ///< C1: the identity only (triclinic, or symmetry ignored)
};

/// "cubic", "hexagonal", "trigonal", "orthorhombic", "none".
std::string to_string(PointGroup group);
/// Parses the names of to_string; throws std::invalid_argument listing them otherwise.
PointGroup parse_point_group(const std::string& text);

/// The group's rotations as quaternions acting in the crystal frame (canonical, identity first).
std::vector<Eigen::Quaterniond> symmetry_operators(PointGroup group);

/// The largest misorientation angle two grains of the group can have, in radians:
/// 62.80 deg (cubic), 93.84 deg (hexagonal), 104.48 deg (trigonal), 180 deg (none).
double max_misorientation_angle(PointGroup group);

/// The misorientation angle in [0, max_misorientation_angle(group)] between two grains of the
/// same group: the smallest rotation angle of S_i^-1 q1^-1 q2 S_j over the symmetry. Since
/// S_i^-1 (D S_j S_i^-1) S_i has the angle of D S_j S_i^-1, the minimum over D S_k alone is the
/// same, and that is what is computed.
double misorientation_angle(const Eigen::Quaterniond& q1, const Eigen::Quaterniond& q2,
                            PointGroup group);

/// A uniformly distributed orientation (Haar measure on SO(3)), Shoemake's method (Graphics
/// Gems III, 1992, "Uniform random rotations"): three uniforms u1, u2, u3 give
/// q = (sqrt(1-u1) sin 2 pi u2, sqrt(1-u1) cos 2 pi u2, sqrt(u1) sin 2 pi u3, sqrt(u1) cos 2 pi
/// u3). Drawn from stream_for(seed, grain): independent of the other grains.
Eigen::Quaterniond uniform_orientation(std::uint64_t seed, std::uint64_t grain);

/// A fibre texture: the crystal direction `crystal_dir` lies along the specimen direction
/// `specimen_axis` (neither need be unit), the rotation about that axis is uniform, and the
/// direction is then tilted away from the axis by an angle theta towards a uniform azimuth.
/// theta follows a Gaussian on the sphere of directions about the axis,
///     density of theta  ~  sin(theta) exp(-theta^2 / (2 spread^2)),  theta in [0, pi],
/// (for a small spread the tilt vector is a 2D Gaussian of standard deviation `spread` per
/// component). spread = 0 puts the direction exactly on the axis. spread in radians, >= 0.
Eigen::Quaterniond fibre_orientation(std::uint64_t seed, std::uint64_t grain,
                                     const Eigen::Vector3d& crystal_dir,
                                     const Eigen::Vector3d& specimen_axis, double spread);

/// A preferred orientation q0 with a spread: q = r * q0, r a rotation by omega about a uniformly
/// distributed axis, the orientation density a Gaussian of the rotation angle about q0:
///     density of omega  ~  (1 - cos omega) exp(-omega^2 / (2 spread^2)),  omega in [0, pi]
/// ((1 - cos omega) is the Haar measure; for a small spread the rotation vector is a 3D
/// Gaussian of standard deviation `spread` per component). spread = 0 returns q0 exactly
/// (canonical). spread in radians, >= 0; as spread grows the law tends to the uniform one.
Eigen::Quaterniond preferred_orientation(std::uint64_t seed, std::uint64_t grain,
                                         const Eigen::Quaterniond& q0, double spread);

/// Mackenzie's density of the misorientation angle of randomly oriented cubic (O) grains, per
/// radian, omega in radians; zero outside [0, 62.80 deg].
/// J. K. Mackenzie, "Second paper on statistics associated with the random disorientation of
/// cubes", Biometrika 45 (1958) 229-240; in per-degree units the first three pieces read
/// (2/15)(1 - cos w), (2/15)[3(sqrt2 - 1) sin w - 2(1 - cos w)] and
/// (2/15)[(3(sqrt2 - 1) + 4/sqrt3) sin w - 6(1 - cos w)]; the last one (60.72 to 62.80 deg)
/// adds back the overlaps of the excluded caps (see misorientation_angle_density).
double misorientation_angle_density_cubic(double omega);

/// The misorientation-angle density of randomly oriented grains of any of the groups, per
/// radian: Morawiec's closed form (A. Morawiec, "Misorientation-angle distribution of randomly
/// oriented symmetric objects", J. Appl. Cryst. 28 (1995) 289-293),
///     p(omega) = (N / pi) (1 - cos omega) chi(tan(omega / 2)),
/// N the group's order and chi(r) the fraction of the sphere of radius r in Rodrigues space that
/// lies in the fundamental zone (the polyhedron |r . n_k| <= tan(theta_k / 4), n_k a symmetry
/// axis and theta_k its smallest rotation angle), written as the sphere minus the caps cut off by
/// the faces plus the overlaps of adjacent caps (no three caps overlap below the largest angle).
double misorientation_angle_density(double omega, PointGroup group);

}  // namespace cleave::geometry
