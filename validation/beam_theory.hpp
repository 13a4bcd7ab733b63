#pragma once
/// \file
/// Closed-form load-deflection curves of the three fracture tests of sec. 7 (eqs 56-70) of
/// Chen et al. (seed 002), from corrected beam theory and linear elastic fracture mechanics:
/// the double cantilever beam (DCB, mode I), the end notched flexure (ENF, mode II) and the
/// mixed-mode bending test (MMB). The simulations of those tests are checked against them.
///
/// Notation: I = B h^3 / 12 is the second moment of area of one arm (h thick); the energy
/// release rate G = P^2 / (2 B') dC/da (eq. 49 at fixed load) uses the reduced crack front
/// width B' = B - 2r (text after eq. 49); C(a) is the compliance Delta / P with the crack held
/// at a. Effective crack lengths a_I = a + chi_I h and a_II = a + chi_II h carry the
/// root-rotation and shear corrections (eqs 57-58 and text after eq. 63).
///
/// The printed equations are garbled; these are the readings, each re-derived from C(a):
/// - DCB (two cantilevers a_I long): C = 2 a_I^3 / (3EI) (eqs 56, 59);
///   G_I = P^2 a_I^2 / (B' E I), so crack growth runs along P a_I = sqrt(B' E I G_Ic) (eq. 60)
///   for a0 <= a <= L; after that the arms are split and C = 2 (L + chi_I h)^3 / (3EI) (eq. 61).
/// - ENF (span 2L, load P at mid-span, Delta the mid-span deflection): a simply supported
///   beam whose cracked part bends with 2EI and the intact part with 8EI. For a_II <= L,
///   C = (2L^3 + 3 a_II^3) / (96EI) (eq. 63) and G_II = 3 P^2 a_II^2 / (64 B' E I); for
///   a_II > L, with b = 2L - a_II, C = (8L^3 - 3 b^3) / (96EI) (eq. 64) and
///   G_II = 3 P^2 b^2 / (64 B' E I). Stages II and III meet at a_II = L (5 P L^3 / (96EI)).
///   As b -> 0 the load of stage III grows without bound and its curve approaches the split
///   beam's line C = L^3 / (12EI) (eq. 65, stage IV) from above (stage III is the stiffer):
///   on the LEFM path stage IV is a limit, never reached at finite load (see analytic_curve
///   and stage_range); with the paper's ENF the crack comes within h of the far support only
///   at Delta = 17 mm. Should a simulated crack run through earlier (the paper's runs did
///   past Delta = 2 mm), its stage IV is the part of its curve after that (split_stage).
/// - MMB (eq. 66): the lever load P splits into an opening pair P_I = (3C - L) P / (4L) on
///   the arms' loaded ends and an ENF-like load P_II = (C + L) P / L whose end reaction is
///   shared equally by the two arms. The two parts deform the arms antisymmetrically and
///   symmetrically, so their energies add and G = G_I + G_II with G_I from the DCB part and
///   G_II from the ENF part. Delta is the opening at the loaded end (eq. 68). Growth follows
///   the linear criterion G_I / G_Ic + G_II / G_IIc = 1 (eq. 69), which at a given crack length
///   is quadratic in P (no root finding: P = (F(a))^-1/2).
/// - MMB beyond mid-span (eq. 70, unreadable in print; our derivation): once the mode-I
///   effective root passes the mid-span load (a_I > L), P_II sits on the upper arm inside
///   the cracked part. Splitting it equally between the arms leaves, in the mode-I part, a
///   closing pair P_II / 2 at x = L, so the moment at the effective root is
///   M = P_I a_I - (P_II / 2)(a_I - L) and G_I = M^2 / (B' E I); G_II is the ENF expression
///   with b = 2L - a_II when a_II > L. Castigliano on the mode-I part gives the end opening
///   Delta = 2 P_I a_I^3 / (3EI) - P_II (a_I - L)^2 (2 a_I + L) / (6EI). The paper substitutes
///   a into eq. 68 unchanged; we keep the second term, without which Delta and G would not
///   come from the same compliance. Everything is continuous at a_I = L.
/// - MMB stage III ends where the mode-I root moment M reaches zero (beyond that the faces
///   close behind the tip and beam theory would need a contact analysis, which we do not do),
///   or where a_I reaches 2L, whichever comes first; the curve stops there.
/// - Stage boundaries use effective crack lengths: ENF stage III starts at a_II = L, MMB
///   stage III at a_I = L (with chi = 0 both are the paper's a = L); the DCB crack stops at
///   the physical end a = L. CurvePoint::crack is always the physical crack length a.
///
/// Displacement control: a branch on which Delta decreases while the crack grows (the ENF
/// snap-back for a_II < L / 3^(1/3)) cannot be followed; the deflection jumps at constant
/// Delta to the first later point of the path with the same Delta. A point of the path is
/// reachable when its Delta is at least every earlier Delta on the path; analytic_load and
/// stage_range describe the reachable points only, analytic_curve the whole path.

#include <optional>
#include <utility>
#include <vector>

namespace cleave::physics {

/// The three beam tests of sec. 7.
enum class BeamTestKind { dcb, enf, mmb };

/// Geometry and material of one beam test (SI units).
struct BeamTest {
  BeamTestKind kind;
  double E, nu;  ///< Young's modulus (Pa) and Poisson's ratio
  double B;      ///< breadth (m)
  double h;      ///< half height (m): each arm is h thick
  double L;      ///< DCB: length of the beam; ENF/MMB: half span (2L is the span)
  double a0;  ///< initial crack length, from the load line (DCB, MMB end) or from the support (ENF)
  double r;   ///< particle radius: the crack front width is B - 2r (sec. 7, text after eq. 49)
  double g_Ic, g_IIc;  ///< critical energy release rates (N/m)
  double C = 0;        ///< MMB lever arm (m)
};

/// Eqs 57-58: chi_I = sqrt(E/(11G) (3 - 2 (Gamma/(1+Gamma))^2)), Gamma = 1.18 E/G,
/// G = E/(2(1+nu)).
double chi_I(double E, double nu);

/// chi_II = 0.42 chi_I (text after eq. 63).
double chi_II(double E, double nu);

/// Eq. 67: the MMB lever arm C = L (1 + q) / (3q - 1), q = (2/sqrt 3) sqrt(beta/(1-beta)),
/// that gives the mode ratio beta = G_II / (G_I + G_II) (from G_II / G_I =
/// 3 (C + L)^2 / (4 (3C - L)^2), effective-length corrections left out). Needs
/// 1/13 < beta < 1; throws std::domain_error otherwise.
double mmb_lever_arm(double beta, double L);

/// The mode-I and mode-II loads of an MMB lever load.
struct MmbLoads {
  double p_I, p_II;
};

/// Eq. 66: P_I = (3C-L)/(4L) P, P_II = (C+L)/L P.
MmbLoads mmb_loads(double P, double C, double L);

/// One point of an analytic curve.
struct CurvePoint {
  double delta;  ///< deflection Delta (m): DCB/MMB opening at the loaded end, ENF mid-span
  double load;   ///< load P (N): DCB end load, ENF mid-span load, MMB lever load
  int stage;     ///< 1, 2, 3 or 4, as in the paper's figures
  double crack;  ///< physical crack length a (m)
};

/// The analytic equilibrium path, parametrised by crack length: stage I (a = a0, load from 0
/// up to initiation), stage II (a from a0 to its end), then the later stages (DCB III: the
/// split arms loaded further; ENF III; MMB III), n points per stage (at least 2; neighbouring
/// stages share their end point). Snap-backs are included. The path stops where it first
/// reaches delta_max (or where it ends, MMB). For the ENF the split beam's line (stage IV,
/// eq. 65) follows as a reference line from the origin to delta_max, with crack = 2L.
/// Throws std::invalid_argument for an inconsistent test (e.g. a0 past the end of growth).
std::vector<CurvePoint> analytic_curve(const BeamTest& test, double delta_max, int n_per_stage);

/// The load of the analytic path at deflection delta on a given stage, where that stage's
/// branch exists and is reachable under displacement control (delta within stage_range);
/// nullopt otherwise, e.g. inside an ENF snap-back, past the stage's end, or for ENF stage IV.
std::optional<double> analytic_load(const BeamTest& test, int stage, double delta);

/// The deflection range [lo, hi] over which a stage is reached under displacement control
/// (hi = +inf for DCB stage III and ENF stage III; both NaN for a stage never reached, such
/// as ENF stage II when the snap-back jumps past the mid-span, ENF stage IV, or a stage the
/// test does not have).
std::pair<double, double> stage_range(const BeamTest& test, int stage);

/// The stage on which the beam is split along the whole weak plane and loaded as stationary
/// beams: DCB stage III (the arms clamped at a = L, eq. 61) and ENF stage IV (two beams on
/// top of each other, eq. 65); 0 for the MMB, whose path ends before that.
int split_stage(BeamTestKind kind);

/// The compliance Delta / P of the split beam of split_stage: 2 (L + chi_I h)^3 / (3EI) for
/// the DCB (eq. 61), L^3 / (12EI) for the ENF (eq. 65). NaN for the MMB.
double split_compliance(const BeamTest& test);

/// The crack length at which the beam is split along the whole weak plane: L for the DCB
/// (from the load line), 2L for the ENF (from the left support). NaN for the MMB.
double split_crack(const BeamTest& test);

}  // namespace cleave::physics
