#pragma once
/// \file
/// The DCB of sec. 7.1 of Chen et al. (seed 002) as corrected beam theory with the paper's
/// cohesive zone instead of a sharp LEFM crack: each arm is an Euler-Bernoulli beam (EI, one
/// arm) resting, from the crack tip on, on a foundation that is the arm's own elastic
/// compliance (a Winkler spring, as in Kanninen's augmented DCB) in series with the weak
/// plane's linear-softening traction-separation law of eqs 14-30 in pure mode I (strength
/// sigma_c, opening at decohesion delta_c = 2 G_Ic / sigma_c, unloading to the origin, damage
/// from the largest opening). Its load-deflection curve is solved quasi-statically under
/// displacement control by finite elements and Newton's method. The ENF (mode II) and the
/// MMB (mixed mode) are solved the same way (see their functions below).
///
/// Why: eqs 59-61 are linear elastic fracture mechanics, exact only when the cohesive zone is
/// short against the arm. The material has Hillerborg's length E G_Ic / sigma_c^2 =
/// 6.4 mm, six arm thicknesses h, so the zone is millimetres long; this curve is what the
/// same beam theory says with that zone, and what a lattice that models the paper's law right
/// should follow. With sigma_c large it tends to eq. 59-61's curve (its tests check both
/// ends: Winkler's closed form before the zone opens, and J = G_Ic while the crack grows).
///
/// Widths and stiffness, so that the sharp-crack limit is eqs 59-61 of beam_theory.hpp:
/// - the foundation's spring per unit length k = 4 EI / (chi_I h)^4, whose decay length
///   1/beta = (4EI/k)^(1/4) = chi_I h is eq. 57's effective-length correction (Kanninen's
///   k = 2EB/h gives 0.639 h; chi_I h = 0.645 h for nu = 0.2);
/// - the cohesive law acts over the crack front width B' = B - 2r (text after eq. 49), so a
///   unit length of plane holds at most sigma_c B' and dissipates G_Ic B'.
/// The weak plane runs from a0 to L; past L the arm rests on the elastic foundation alone
/// (the intact beam) up to a clamp at L + intact_length.

#include <vector>

#include "validation/beam_theory.hpp"

namespace cleave::physics {

/// How finely the cohesive beam is solved.
struct CohesiveBeamOptions {
  double element = 0;   ///< element length (m); 0: h / 40
  int steps = 2000;     ///< equal deflection increments up to delta_max
};

/// One converged state of the cohesive beam.
struct CohesiveBeamPoint {
  double delta;         ///< opening at the load line, 2 w(0) (m)
  double load;          ///< end load P on each arm (N)
  double rotation;      ///< how far each arm has turned at the load line, -w'(0) (rad)
  double crack;         ///< where the plane has fully decohered, from the load line (m)
  double process_zone;  ///< the farthest point of the plane that has softened (m)
  /// MMB: how far the lever's load point has moved down (m), from the lever's kinematics:
  /// the mid-span deflection plus (mid-span deflection + Delta) C / L. 0 for the others.
  double load_point = 0.0;
};

/// The DCB's load-deflection path with a cohesive zone of strength sigma_c (Pa), from 0 to
/// delta_max, one point per converged increment (the origin first). The test must be a DCB;
/// intact_length (m) is the uncracked beam past L before the clamp (0: clamped at L).
/// Throws std::invalid_argument for a test that is not a DCB, a non-positive sigma_c, or a
/// softening branch steeper than the arm's spring (sigma_c^2 > G_Ic k / B': the plane would
/// snap back at a point; the law has no such branch), std::runtime_error if Newton's method
/// fails to converge even on a refined increment.
std::vector<CohesiveBeamPoint> cohesive_dcb_curve(const BeamTest& test, double sigma_c,
                                                  double intact_length, double delta_max,
                                                  const CohesiveBeamOptions& options = {});

/// The ENF (sec. 7.2) the same way, in mode II: two arms bending together and slipping along
/// the bonded plane against the arm's shear spring (decay length chi_II h, eq. 63's
/// correction) in series with the paper's law in pure shear (strength sigma_c over B',
/// G_IIc). Delta is the load line's deflection, P the mid-span load. Where eq. 63's stage II
/// snaps back, the path under displacement control has no nearby equilibrium: the load drops
/// at that Delta (two points at one Delta, before and after), found by relaxing with a slip
/// rate term until the slips stop changing. rotation is 0.
std::vector<CohesiveBeamPoint> cohesive_enf_curve(const BeamTest& test, double sigma_c,
                                                  double delta_max,
                                                  const CohesiveBeamOptions& options = {});

/// The MMB (sec. 7.3) the same way, in mixed mode: the upper and lower arms each bend and
/// stretch, the plane between them opens (against the DCB's foundation) and slips (against
/// the ENF's shear spring), each in series with the paper's law taken isotropic in the jump
/// (one G_c for all mixes: test.g_Ic, which must equal test.g_IIc; strength sigma_c in every
/// direction). The lever (arm test.C) ties the end's pull to the mid-span push (eq. 66).
/// Delta is the opening at the loaded end, P the lever load. Jumps are relaxed as the ENF's.
std::vector<CohesiveBeamPoint> cohesive_mmb_curve(const BeamTest& test, double sigma_c,
                                                  double delta_max,
                                                  const CohesiveBeamOptions& options = {});

/// The load of a cohesive-beam curve at deflection delta, linear between its points (the
/// curve is in increasing delta); NaN outside it.
double cohesive_load(const std::vector<CohesiveBeamPoint>& curve, double delta);

/// The foundation spring per unit length k = 4 EI / (chi_I h)^4 (N/m^2).
double cohesive_beam_spring(const BeamTest& test);

}  // namespace cleave::physics
