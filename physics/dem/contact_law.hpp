#pragma once
/// \file
/// The contact force law of sec. 2.3.2 (eqs 2.1-2.8) of the dissertation (seed 000), as a
/// pure function of explicit inputs: Hooke normal spring with the unloading stiffness
/// multiplier C_res, incremental shear spring with a Coulomb cap, the velocity damping of
/// eq 2.6, and incremental rolling and torsional resistance with the damping of eq 2.8.
///
/// Readings fixed here (the text leaves them open):
/// - Normal force: the overlap is an absolute quantity (sec. 2.3.3), so F_n = K_n delta on
///   loading; on unloading the spring is C_res times stiffer (the "reciprocal of the
///   coefficient of restitution" multiplier), i.e. F_n = C_res K_n (delta - delta_0) with
///   delta_0 = delta_max (1 - 1/C_res) (Walton & Braun 1986). The work returned is 1/C_res
///   of the work stored, so an undamped collision has restitution e = 1/sqrt(C_res).
/// - Damping (eq 2.6, 2.8) opposes the relative velocity; m_crit is the reduced mass of the
///   pair (the body's mass against a wall), I_crit the reduced principal moment. The 0.1
///   factor is `damping_ratio` (0 turns damping off).
/// - The total normal force never pulls (unbonded contacts are compression-only).
/// - Rolling and torsional moments are capped by mu_r F_n times `lever` (eq 2.5 gives a
///   force; the lever, the dilation radius, turns it into a moment).

#include <Eigen/Dense>

namespace cleave::physics {

/// Table 2.3's parameter set for one pair of materials (particle-particle or -wall).
struct ContactParams {
  double kn = 0.0;     ///< normal spring stiffness K_n, N/m
  double ks = 0.0;     ///< shear spring stiffness K_s, N/m
  double kr = 0.0;     ///< rolling stiffness K_r, N m/rad
  double kt = 0.0;     ///< torsional stiffness K_t, N m/rad
  double c_res = 1.0;  ///< unloading stiffness multiplier (inverse coefficient of restitution)
  double mu_s = 0.0;   ///< Coulomb sliding friction
  double mu_r = 0.0;   ///< Coulomb rolling friction
  double damping_ratio = 0.1;  ///< the 0.1 of eqs 2.6 and 2.8
};

/// State variables a contact carries from step to step.
struct ContactHistory {
  Eigen::Vector3d shear = Eigen::Vector3d::Zero();    ///< elastic shear force on B, world
  Eigen::Vector3d rolling = Eigen::Vector3d::Zero();  ///< elastic rolling moment on B
  double torsion = 0.0;                               ///< elastic torsional moment on B along n
  double max_overlap = 0.0;                           ///< largest overlap so far
};

/// The relative motion at one contact point.
struct ContactKinematics {
  Eigen::Vector3d normal;        ///< unit, from A towards B
  double overlap = 0.0;          ///< penetration (> 0 when touching)
  Eigen::Vector3d velocity;      ///< velocity of B's material point minus A's, at the contact
  Eigen::Vector3d spin;          ///< angular velocity of B minus A
  /// Mass and moment of inertia for damping (the reduced ones), read only by the
  /// contact_force that makes the coefficients itself; World passes a ContactDamping.
  double m_crit = 0.0;
  double i_crit = 0.0;
  double lever = 0.0;            ///< arm of the rolling/torsional friction cap
};

/// Force on B at the contact point and pure moment on B; A receives the opposite.
struct ContactForce {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  bool sliding = false;
};

/// The coefficients of eqs 2.6 and 2.8 and the unloading offset of eq. 2.4's C_res, which
/// depend only on the parameters and on the pair's m_crit and i_crit: the same for every
/// contact point of one pair of bodies, so the caller may make them once per pair.
struct ContactDamping {
  double cn = 0.0;          ///< normal damping coefficient, eq. 2.6
  double cs = 0.0;          ///< shear damping coefficient, eq. 2.6
  double cr = 0.0;          ///< rolling damping coefficient, eq. 2.8
  double ct = 0.0;          ///< torsional damping coefficient, eq. 2.8
  double unload = 0.0;      ///< 1 - 1/C_res: delta_0 = delta_max unload
};
ContactDamping contact_damping(const ContactParams& p, double m_crit, double i_crit);

/// Evaluates eqs 2.3-2.8 for one step of length dt, updating `history`, with the pair's
/// coefficients `d` (contact_damping of p, k.m_crit and k.i_crit).
ContactForce contact_force(const ContactParams& p, const ContactKinematics& k, const ContactDamping& d,
                           ContactHistory& history, double dt);
/// The same, making the coefficients from k.m_crit and k.i_crit.
ContactForce contact_force(const ContactParams& p, const ContactKinematics& k,
                           ContactHistory& history, double dt);

/// contact_force for W contacts with the same parameters side by side (W = 1, 2 or 4 lanes
/// of physics/simd.hpp): lane i evaluates k[i] with d[i], updating h[i] and writing out[i],
/// with the bits contact_force gives it at any W (it is this at W = 1).
template <int W>
void contact_forces(const ContactParams& p, const ContactKinematics* const k[],
                    const ContactDamping* const d[], ContactHistory* const h[],
                    ContactForce* const out[], double dt);

/// Critical time step of a mass-spring pair, 2 sqrt(m / k), used with the stiffest spring
/// (C_res K_n on unloading) and the lightest body.
double critical_time_step(double mass, double stiffness);

}  // namespace cleave::physics
