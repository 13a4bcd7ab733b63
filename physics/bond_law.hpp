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

namespace cleave::physics {

/// Eqs 2.9 and 2.14: continuum stiffnesses (N/m^3: stress per opening) and strengths (Pa).
struct BondParams {
  double kbn = 0.0;  ///< bond normal stiffness k_bn
  double kbs = 0.0;  ///< bond shear stiffness k_bs
  double tbn = 0.0;  ///< bond normal ("tensile") strength t_bn
  double tbs = 0.0;  ///< bond shear strength t_bs
};

/// The bond's section (eqs 2.10, 2.11, 2.15): radius r, A = pi r^2, I = pi r^4 / 4, J = 2 I.
struct BondSection {
  double radius = 0.0;
  [[nodiscard]] double area() const;
  [[nodiscard]] double inertia() const;  ///< I_b
  [[nodiscard]] double polar() const;    ///< J_b
};

/// What a bond carries from step to step (all on B, world axes).
struct BondState {
  double normal = 0.0;                                ///< F_bn, positive in tension
  Eigen::Vector3d shear = Eigen::Vector3d::Zero();    ///< F_bs
  Eigen::Vector3d bending = Eigen::Vector3d::Zero();  ///< M_br
  double torsion = 0.0;                               ///< M_bt about the normal
  bool broken = false;
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

/// One step of the bond at unit normal n (from A towards B) with relative velocity
/// `velocity` (B's material point minus A's at the bond) and relative spin `spin`
/// (w_B - w_A): eqs 2.12-2.13 increment the state, eq. 2.16 checks the limits of eq. 2.15.
/// A bond that breaks returns no force and stays broken.
BondResult bond_force(const BondParams& p, const BondSection& section, const Eigen::Vector3d& n,
                      const Eigen::Vector3d& velocity, const Eigen::Vector3d& spin,
                      BondState& state, double dt);

}  // namespace cleave::physics
