#pragma once
/// \file
/// The bond law of sec. 2.3.3 (eqs 2.9-2.16) of the dissertation (seed 000), as a pure
/// function: a bonded contact carries normal and shear forces and rolling (bending) and
/// torsional moments, all incremental from the relative motion at the bond, in parallel
/// with the contact law; it breaks for good when any of them passes its limit.
///
/// Readings fixed here:
/// - Eq. 2.11 prints K_br = k_bs J_b and K_bt = k_bn I_b, while eq. 2.15 limits bending by
///   t_bn I/r and torsion by t_bs J/r. As in the bonded-particle model the section follows
///   (Potyondy & Cundall 2004), bending goes with the normal stiffness and the area moment,
///   torsion with the shear stiffness and the polar moment: K_br = k_bn I_b, K_bt = k_bs J_b.
/// - Eq. 2.16 prints the moment conditions as equalities with a friction term; they are read
///   as M_br > M_r_limit and M_bt > M_t_limit, like the force conditions.
/// - The normal force is positive in tension; the tension limit applies to tension only.

#include <Eigen/Dense>
#include <cmath>

#include <cstdint>

#include "physics/bonds/cohesive_law.hpp"

namespace cleave::physics {

/// Which law a bond follows once it is loaded.
enum class BondLaw {
  /// The bonded-particle law of the dissertation (eqs 2.9-2.16): brittle, breaks at a limit.
  bonded_particle,
  /// The cohesive crack law of Chen et al. 2020 (seed 002, eqs 14-33): the same springs until
  /// the circular initiation criterion (eq. 32), then linear softening that dissipates G_c per
  /// unit bond area before the bond lets go (lambda = 1, eq. 16).
  cohesive,
  /// The cohesive beam of Andre et al. 2012 (seed 003, GranOO): an Euler-Bernoulli beam of
  /// radius R_m and Young's modulus E_m (Poisson's ratio nu_m for its shear modulus) from
  /// one grain's centroid to the other's, in tension, bending, shear and torsion; its
  /// forces follow from where its ends and their material frames are now (beam_force), not
  /// from increments.
  beam,
};

/// What breaks a bond (of the bonded-particle law).
enum class BondCriterion {
  /// Eqs 2.15-2.16 of the dissertation: its normal force, shear force, bending or torsion
  /// moment past its limit.
  limits,
  /// Rankine: the largest principal stress of its two grains' mean Love-Weber stress (eq.
  /// 2.17) above sigma_f (seed 003's "maximal normal stress" criterion, GranOO).
  rankine,
  /// Andre's hydrostatic criterion: the mean stress tr(sigma) / 3 of that tensor above
  /// sigma_f (GranOO, seed 003).
  hydrostatic,
};

/// Eqs 2.9 and 2.14: continuum stiffnesses (N/m^3: stress per opening) and strengths (Pa).
struct BondParams {
  double kbn = 0.0;  ///< bond normal stiffness k_bn
  double kbs = 0.0;  ///< bond shear stiffness k_bs
  double tbn = 0.0;  ///< bond normal ("tensile") strength t_bn (bonded-particle law)
  double tbs = 0.0;  ///< bond shear strength t_bs (bonded-particle law)
  BondLaw law = BondLaw::bonded_particle;
  double sigma_c = 0.0;  ///< cohesive law: strength (Pa), T_n0 = T_s0 = sigma_c
  double g_c = 0.0;      ///< cohesive law: critical energy release rate (N/m), eq. 18
  /// What breaks a bond; with a stress criterion the limits of eq. 2.15 are not used (the
  /// world applies it, as it needs the grains' stresses), breaks are logged as tension.
  BondCriterion criterion = BondCriterion::limits;
  double sigma_f = 0.0;  ///< Pa: the stress criteria's strength (and the beam's: see beam_force)
  double beam_young = 0.0;    ///< beam law: E_m (Pa)
  double beam_poisson = 0.0;  ///< beam law: nu_m; G_m = E_m / (2 (1 + nu_m))
  double beam_radius = 0.0;   ///< beam law: R_m (m)
};

/// The bond's section (eqs 2.10, 2.11, 2.15): radius r, A = pi r^2, I = pi r^4 / 4, J = 2 I.
struct BondSection {
  double radius = 0.0;
  // Inline: the bond law asks for them nine times a bond and step.
  [[nodiscard]] double area() const { return M_PI * radius * radius; }
  [[nodiscard]] double inertia() const { return 0.25 * M_PI * (radius * radius) * (radius * radius); }  ///< I_b
  [[nodiscard]] double polar() const { return 2.0 * inertia(); }  ///< J_b
};

/// What a bond carries from step to step (all on B, world axes).
struct BondState {
  double normal = 0.0;                                ///< F_bn, positive in tension
  Eigen::Vector3d shear = Eigen::Vector3d::Zero();    ///< F_bs
  Eigen::Vector3d bending = Eigen::Vector3d::Zero();  ///< M_br
  double torsion = 0.0;                               ///< M_bt about the normal
  bool broken = false;
  /// The cohesive law's phase and history (eqs 21, 33); last, out of the bonded-particle
  /// law's way (World::bond_forces reads the fields above every step).
  CohesiveState cohesive;
};

enum class BondFailure { none, tension, shear, bending, torsion };

struct BondResult {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< on B (A gets the opposite)
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  ///< on B
  BondFailure failure = BondFailure::none;           ///< set on the step it breaks
  BondState at_failure;  ///< the loads that broke it (when `failure` is set)
};

/// Lower-case name of a failure mode ("none", "tension", ...).
const char* to_string(BondFailure mode);

/// A bond's strength factor drawn from a Weibull distribution of modulus `modulus` and mean
/// 1, F(s) = 1 - exp(-(s Gamma(1 + 1/m))^m): the disorder of a polycrystal's grain
/// boundaries (bonds of one material are not all equally strong). The draw is a hash of the
/// seed and the two grains' ids (in either order), so it does not depend on the order the
/// bonds were found in or on the thread count.
double bond_strength_factor(std::uint64_t seed, int grain_a, int grain_b, double modulus);

/// What eqs 2.10, 2.11 and 2.15 make of a bond's parameters and section: its spring
/// stiffnesses and the limits on its four loads. The same for every bond of one section
/// and strength: World::bond_forces makes them once for a run of such bonds.
struct BondConstants {
  double kbn = 0.0, kbs = 0.0, kbr = 0.0, kbt = 0.0;  ///< K_bn, K_bs, K_br, K_bt (eqs 2.10, 2.11)
  /// Eq. 2.15: the limits on F_bn, |F_bs|, |M_br| and |M_bt|.
  double tension = 0.0, shear = 0.0, bending = 0.0, torsion = 0.0;
};
BondConstants bond_constants(const BondParams& p, const BondSection& s);

/// Eq. 2.16 against eq. 2.15's limits, checked in this order: F_bn, |F_bs|, |M_br|, |M_bt|.
[[nodiscard]] inline BondFailure limit_failure(const BondConstants& k, double normal, double shear_size,
                                               double bending_size, double torsion) {
  if (normal > k.tension) return BondFailure::tension;
  if (shear_size > k.shear) return BondFailure::shear;
  if (bending_size > k.bending) return BondFailure::bending;
  if (std::abs(torsion) > k.torsion) return BondFailure::torsion;
  return BondFailure::none;
}

/// A bond that breaks: its state is left broken (loads zero); returns the loads it broke
/// under.
inline BondState break_bond(BondState& b) {
  const BondState at = b;
  b = BondState{};
  b.broken = true;
  return at;
}

/// One step of the bond at unit normal n (from A towards B) with relative velocity
/// `velocity` (B's material point minus A's at the bond) and relative spin `spin`
/// (w_B - w_A): eqs 2.12-2.13 increment the state, eq. 2.16 checks the limits of eq. 2.15.
/// A bond that breaks returns no force and stays broken.
///
/// With the cohesive law, the springs of eqs 2.12-2.13 measure the separations, delta_n =
/// F_bn / K_bn and delta_s = |F_bs| / K_bs, which go through cohesive_traction with the
/// spring stiffnesses K_bn, K_bs and the bond area (a bond's traction is its force per area,
/// so eq. 2.9's k_bn is eq. 7's k_n / A). Readings: the bending and torsion moments of eq.
/// 2.13 (which the seed's point-contact model has no counterpart for) are carried while
/// connective and scaled by (1 - d) once cohesive; the limits of eq. 2.15 do not apply; a bond
/// whose lambda reaches 1 breaks, logged as tension or shear by the larger of <delta_n> and
/// delta_s at that moment.
BondResult bond_force(const BondParams& p, const BondSection& section, const Eigen::Vector3d& n,
                      const Eigen::Vector3d& velocity, const Eigen::Vector3d& spin,
                      BondState& state, double dt);
/// The same with the bond's constants made beforehand (bond_constants(p, section)).
BondResult bond_force(const BondParams& p, const BondConstants& k, const BondSection& section,
                      const Eigen::Vector3d& n, const Eigen::Vector3d& velocity, const Eigen::Vector3d& spin,
                      BondState& b, double dt);

/// Where a beam bond (BondLaw::beam) is now, in world axes: its two ends (material points of
/// A and B, their centroids at bonding) and, at each end, the beam's axis and a direction
/// across it as that body's material directions (equal at both ends at bonding, when the
/// axis runs from end A to end B).
struct BeamPose {
  Eigen::Vector3d end_a = Eigen::Vector3d::Zero(), end_b = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_a = Eigen::Vector3d::UnitX(), axis_b = Eigen::Vector3d::UnitX();
  Eigen::Vector3d across_a = Eigen::Vector3d::UnitY(), across_b = Eigen::Vector3d::UnitY();
  double rest_length = 0.0;  ///< L_m: the ends' distance at bonding (plus thermal growth)
};

/// The beam's loads: on B (force at end_b, moment) and on A (the opposite force at end_a,
/// its moment), and the section loads the stress check and the break log read.
struct BeamResult {
  Eigen::Vector3d force_b = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment_a = Eigen::Vector3d::Zero(), moment_b = Eigen::Vector3d::Zero();
  double axial = 0.0;    ///< N, positive in tension
  double shear = 0.0;    ///< |V|
  double bending = 0.0;  ///< the larger end moment |M|
  double torsion = 0.0;  ///< |T|
  /// The largest normal stress in the beam, N/A + |M| R_m / I at the more bent end (Pa):
  /// its outer fibre, what the beam's own strength sigma_f is held against.
  double peak_stress = 0.0;
};

/// The Euler-Bernoulli beam of Andre et al. 2012 between two grains, co-rotational (small
/// strain, large rigid motion): with chord c = end_b - end_a, L = |c|, e = c / L,
///   axial       N = E A (L - L_m) / L_m, on B: -N e;
///   bending     each end's turn from the chord, theta = e x axis (first order); the
///               element's end moments M_A = -(2 E I / L_m)(2 theta_A + theta_B), M_B =
///               -(2 E I / L_m)(theta_A + 2 theta_B), and the shear that balances them, on B:
///               e x (M_A + M_B) / L;
///   torsion     the twist psi of B's across-direction against A's about e, on B:
///               -(G J / L_m) psi e, on A the opposite;
/// A = pi R^2, I = pi R^4 / 4, J = 2 I. These are the stiffness matrix of a two-node
/// Hermite beam element, which is nodally exact for a beam loaded at its nodes.
BeamResult beam_force(const BondParams& p, const BeamPose& pose);

}  // namespace cleave::physics
