#pragma once
/// \file
/// The microscopic transgranular fracture criterion of sec. 3.4 of the dissertation (seed
/// 000, eqs 3.22-3.25): a grain may cleave once its mean stress passes a hydrostatic
/// threshold (eq. 3.22); then the beam-theory normal and shear stresses on the potential
/// crack plane (eq. 3.24) give stress intensity factors (eq. 3.23) that are checked against
/// the mixed-mode ellipse of Palaniswamy and Knauss (eq. 3.25).
///
/// Readings fixed here (the text leaves them open or misprints them):
/// - Stresses are positive in tension (cleave's convention, grain_stress.hpp), so eq. 3.22's
///   gate is tr(sigma) / 3 >= sigma_f_hyd with a tensile mean stress counting up. A negative
///   threshold lets grains under moderate compression through.
/// - Eq. 3.24 prints sigma = t_n / A +- M_z y / I, but t_n of eq. 3.21 is already a force per
///   area; the dimensionally consistent reading is sigma = t_n +- M y / I = N / A +- M y / I.
///   The moment that bends the section is about an in-plane axis (a moment about the
///   section normal, the local z, is a twist and gives no normal stress), so "M_z" is read as
///   the bending moment. The linear normal traction of eq. 3.15 on the section is this
///   formula for bending about any in-plane axis (unsymmetric sections included), and the
///   "+" branch, the most tensile fibre, is taken: sigma = max over the section of
///   t_o + C1 x + C2 y, reached at a vertex.
/// - Eq. 3.24 prints tau = t_s Q / (I b); with t_s a traction that is not a stress. It is read
///   as Jourawski's formula tau = V Q / (I b) with the shear force V = t_s A_c, evaluated on
///   the chord through the section centroid normal to the shear direction: Q is the first
///   moment about that chord of the part of the section beyond it, I the second moment of the
///   whole section about it and b the chord length (for a rectangle tau = 1.5 V / A_c).
///   Sections are taken convex (a plane through a convex grain cuts a convex section).
/// - The two maxima of eq. 3.24 sit at different points of the section; eq. 3.25 combines
///   them as the text does (a conservative check). The twist on the section is not used.
/// - Eq. 3.23 gives a signed K_I; a compressive normal stress closes the crack, so only the
///   opening part max(K_I, 0) enters eq. 3.25. K_II = |tau| sqrt(pi a).
/// - The algorithm after eq. 3.25 says "Check Stress Criterion 3.25" for the first stage; the
///   stress criterion is eq. 3.22. A grain fails when the gate of eq. 3.22 is open and eq.
///   3.25's left side is >= 1. (Its "six rectangular faces" are all the faces of the grain,
///   eight for a hexagonal prism.)

#include <Eigen/Dense>
#include <span>

#include "physics/transgranular/crack_plane.hpp"
#include "physics/transgranular/face_traction.hpp"

namespace cleave::physics {

/// What splits a grain.
enum class GrainCriterion {
  /// Sec. 3.4: the gate of eq. 3.22, then eqs 3.23-3.25 on each cleavage plane.
  lefm,
  /// Rankine: the largest principal stress of the grain's Love-Weber stress (eq. 2.17) above
  /// sigma_f; the grain cleaves on its candidate plane with the largest normal stress.
  rankine,
  /// Andre's hydrostatic criterion: the mean stress tr(sigma) / 3 above sigma_f; the same plane.
  hydrostatic,
};

/// Material constants of sec. 3.4.
struct FractureParams {
  double sigma_f_hyd = 0.0;   ///< hydrostatic threshold sigma_f^hyd of eq. 3.22, Pa (tension > 0)
  double k_ic = 0.0;          ///< mode I fracture toughness K_Ic, Pa sqrt(m)
  double c = 0.816;           ///< mode II / mode I toughness ratio C of eq. 3.25
  double crack_length = 0.0;  ///< crack length a of eq. 3.23, m
  GrainCriterion criterion = GrainCriterion::lefm;
  /// lefm: each fragment's d'Alembert terms (-m a and -dH/dt, eqs 3.8-3.19) enter the balance
  /// of the crack section (crack_plane.hpp); false: the quasi-static balance of sec. 3.3.
  bool inertia = true;
  double sigma_f = 0.0;  ///< Pa: the stress criteria's strength
};

/// Eq. 3.24's stresses on a crack section and the beam terms behind them.
struct BeamStresses {
  double sigma = 0.0;        ///< largest normal stress over the section (tension > 0)
  double tau = 0.0;          ///< Jourawski shear stress V Q / (I b) (>= 0)
  double shear_force = 0.0;  ///< V = t_s A_c
  double q = 0.0;            ///< Q, first moment of the part beyond the centroidal chord
  double inertia = 0.0;      ///< I, second moment about that chord
  double chord = 0.0;        ///< b, the chord length
};

/// Eq. 3.24 on a section (geometry with its origin at the centroid, its polygon, and the
/// tractions on it in its frame).
BeamStresses beam_stresses(const FaceGeometry& section, std::span<const Eigen::Vector3d> polygon,
                           const FaceTractions& t);

/// Eq. 3.24 on a crack section from crack_plane_load().
BeamStresses beam_stresses(const CrackPlaneLoad& crack);

/// The outcome of eqs 3.22-3.25 for one grain and one crack plane.
struct FractureResult {
  double mean_stress = 0.0;  ///< tr(sigma) / 3 (tension > 0)
  bool gate = false;         ///< eq. 3.22 met
  double k_i = 0.0;          ///< eq. 3.23, signed (negative: crack pressed shut)
  double k_ii = 0.0;         ///< eq. 3.23, >= 0
  double criterion = 0.0;    ///< left side of eq. 3.25
  bool fails = false;        ///< gate && criterion >= 1
};

/// Eqs 3.22, 3.23 and 3.25 for a grain with average stress `grain_stress` (tension > 0) and
/// crack-plane stresses `sigma` (normal, tension > 0) and `tau` (shear) from eq. 3.24.
FractureResult fracture_check(const FractureParams& p, const Eigen::Matrix3d& grain_stress,
                              double sigma, double tau);

/// As above with the stresses of beam_stresses().
FractureResult fracture_check(const FractureParams& p, const Eigen::Matrix3d& grain_stress,
                              const BeamStresses& s);

}  // namespace cleave::physics
