#pragma once
/// \file
/// The contact model of sec. 4 (eqs 34-45) of Chen et al. (seed 002), used between two
/// particles once their link has fully decohered (physics/bonds/cohesive_law.hpp): a Hertz normal
/// force and a Mindlin tangential spring whose stiffness grows with the contact radius.
///
/// Readings fixed here (ours):
/// - The paper's tangential law rests on Mindlin's no-slip assumption and has no sliding
///   limit. We add a Coulomb cap |F_s| <= friction |F_n|; when it binds, the stored shear
///   displacement is shrunk to the one whose spring force equals the capped force, so that
///   unloading starts from the sliding force. friction = 0 gives frictionless sliding, which
///   is what the LEFM solution of the ENF test assumes for the crack faces.
/// - The stored shear displacement lives in world axes; each step it is first turned into the
///   current tangent plane with its length kept (physics/bonds/tangent.hpp), then incremented.
/// - It is reset to zero whenever the particles are apart (overlap <= 0), so a new contact
///   starts unloaded (eq. 42 integrates over the current period of persistent contact only).

#include <Eigen/Dense>

namespace cleave::physics {

/// Effective properties of one pair of particles (eqs 34-41).
struct HertzMindlinParams {
  double e_star;    ///< equivalent Young's modulus E* (Pa), eq. 35
  double g_star;    ///< equivalent shear modulus G* (Pa), eq. 41
  double r_star;    ///< equivalent radius r* (m), eq. 36
  double kappa;     ///< user penalty factor on the normal force, eq. 34
  double friction;  ///< Coulomb cap on the tangential force (our addition, see above)
};

/// eq. 35 E* = ((1-nu_i^2)/E_i + (1-nu_j^2)/E_j)^-1; eq. 36 r* = (1/r_i + 1/r_j)^-1;
/// eq. 41 G* = ((2-nu_i)/G_i + (2-nu_j)/G_j)^-1 with G = E/(2(1+nu)).
HertzMindlinParams hertz_mindlin_params(double E_i, double nu_i, double r_i, double E_j,
                                        double nu_j, double r_j, double kappa, double friction);

/// What a contact carries from step to step.
struct HertzMindlinState {
  Eigen::Vector3d shear = Eigen::Vector3d::Zero();  ///< shear displacement delta_s (eq. 42), world
  bool touching = false;                            ///< in contact at the last evaluation
};

/// The contact force on B; A receives the opposite.
struct HertzMindlinForce {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
};

/// One step of the contact law. n: unit normal from A to B; overlap = r_A + r_B - distance
/// (eqs 37-38), in contact only if > 0; velocity: B's material point minus A's at the contact
/// point (eqs 43-45). Normal force 4/3 kappa E* sqrt(r*) overlap^1.5 along +n on B (eq. 34);
/// shear displacement incremented by v_s dt with v_s = v - (v.n) n (eqs 42-43) and force
/// -16/3 G* sqrt(r* overlap) delta_s (eq. 40), capped at friction |F_n|.
HertzMindlinForce hertz_mindlin_force(const HertzMindlinParams& p, double overlap,
                                      const Eigen::Vector3d& n, const Eigen::Vector3d& velocity,
                                      HertzMindlinState& s, double dt);

}  // namespace cleave::physics
