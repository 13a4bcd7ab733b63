#pragma once
/// \file
/// The particle-based cohesive crack model of secs 2-3 (eqs 7-33) of Chen et al. (seed 002),
/// as pure functions of one link between two particles: a link starts connective (linear
/// springs, eqs 7-11), turns cohesive when the circular initiation criterion of eq. 32 is met
/// (linear softening with damage, eqs 14-26) and ends in contact once the effective separation
/// of eq. 14 reaches one (Table 1); from then on the caller applies the Hertz-Mindlin contact
/// law (physics/lattice/hertz_mindlin.hpp).
///
/// Readings fixed here (ours, the paper leaves them open):
/// - The paper never states the critical separations delta_nc and delta_sc of eq. 14. We take
///   one value for both, dc = d0 + 2 G_c / sigma_c, with d0 the initiation separation of
///   eq. 32. With equal critical separations, lambda = |(<dn>, ds)| / dc, so the initiation
///   circle psi = 1 (|(<dn>, ds)| = d0) maps onto the single value lambda_cr = d0 / dc for
///   every mode mix, and along any radial path the softening integral of eq. 18,
///   dc * int_{lambda_cr}^{1} T dlambda = sigma_c (dc - d0) / 2, is G_c exactly, in pure
///   mode I, pure mode II and any mixture.
/// - G_c of eq. 18 is the energy dissipated on the softening branch only. The elastic energy
///   stored before initiation (k_n <dn>^2 + k_s ds^2) / (2A) is recoverable and comes on top.
/// - Because d0 = min(dn0, ds0) (eq. 32), a link with k_s < k_n initiates in shear at
///   ds = dn0 < ds0, where the spring carries only k_s d0 / A < sigma_c; the shear traction
///   then jumps to sigma_c as the cohesive branch takes over (the paper's model does the same).
/// - Compression (dn < 0) never counts towards psi or lambda; it meets the penalty
///   T_n = k_n dn / A in the connective and cohesive phases (sec. 3.2, text after eq. 14).
///
/// Initiation::traction, cleave's correction of the jump above (the paper's law is
/// Initiation::displacement, the default):
/// - The jump is not small: on the cubic lattice k_s / k_n = (1 - 4 nu) / (1 + nu), 1/6 at
///   nu = 0.2, so a link sheared to initiation carries sigma_c / 6 and then six times that:
///   its shear strength is sigma_c / 6 and its secant six times stiffer than its spring once
///   it starts to fail. The traction rule is the law without that jump, to compare with.
/// - With it, a link initiates on eq. 31's ellipse with dn0 and ds0 (eqs 12-13), which is
///   where its spring's traction |(T_n, T_s)| reaches sigma_c: the strength is sigma_c in
///   every direction (T_n0 = T_s0 = sigma_c, text after eq. 13).
/// - The softening is eq. 14-26's, isotropic in the separation (delta_nc = delta_sc), with
///   each link's own dc = d_i + 2 G_c / sigma_c fixed at initiation (d_i = |(<dn>, ds)| there)
///   and lambda_cr = d_i / dc: the traction's magnitude is sigma_c on both sides of
///   initiation in pure modes, and eq. 18 still gives G_c along any radial path.
/// - In pure mode I it is the paper's law (d_i = dn0).

#include <cstdint>
#include <limits>

namespace cleave::physics {

/// Parameters of one link: spring stiffnesses (N/m, eq. 3), effective area A (m^2, text
/// after eq. 9), cohesive strength sigma_c (Pa; T_n0 = T_s0 = sigma_c, text after eq. 13) and
/// critical energy release rate G_c (N/m, eq. 18).
/// Where a link turns cohesive (see the file comment).
enum class Initiation : std::uint8_t {
  displacement,  ///< the paper's eq. 32: |(<dn>, ds)| = min(dn0, ds0), one dc for all links
  traction,      ///< eq. 31's ellipse (|traction| = sigma_c), each link's dc from there
};

struct CohesiveParams {
  double kn = 0;       ///< normal spring stiffness k_n
  double ks = 0;       ///< shear spring stiffness k_s
  double area = 0;     ///< effective area A
  double sigma_c = 0;  ///< cohesive strength sigma_c
  double g_c = 0;      ///< critical energy release rate G_c
  Initiation initiation = Initiation::displacement;
};

/// The characteristic separations (m) that follow from a link's parameters.
struct CohesiveLimits {
  double dn0;        ///< eq. 12: A sigma_c / k_n
  double ds0;        ///< eq. 13: A sigma_c / k_s
  double d0;         ///< eq. 32: min(dn0, ds0)
  double dc;         ///< delta_nc = delta_sc = d0 + 2 G_c / sigma_c (our reading, see above)
  double lambda_cr;  ///< d0 / dc: lambda of eq. 14 on the initiation circle
};

/// The separations of eqs 12, 13 and 32 and our critical separation dc.
CohesiveLimits cohesive_limits(const CohesiveParams& p);

/// The three phases of a link (Table 1); a link only ever moves forward through them.
enum class LinkPhase : std::uint8_t { connective, cohesive, contact };

/// Lower-case name of a phase ("connective", "cohesive", "contact").
const char* to_string(LinkPhase phase);

/// What a link carries from one evaluation to the next.
struct CohesiveState {
  LinkPhase phase = LinkPhase::connective;
  double psi_max = 0;     ///< eq. 33: the largest psi of eq. 32 reached
  double lambda_max = 0;  ///< eq. 21: the largest lambda reached (>= lambda_cr once cohesive)
  /// Initiation::traction only, set at initiation (0 before, and always 0 otherwise): this
  /// link's critical separation dc and lambda_cr.
  double dc = 0, lambda_cr = 0;
};

/// Normal traction (positive = tension, pulls the pair together) and shear traction magnitude
/// (along the shear separation, resisting it), in Pa.
struct CohesiveTraction {
  double tn = 0;
  double ts = 0;
};

/// One evaluation at normal separation dn (positive = opening) and shear separation magnitude
/// ds >= 0 (eq. 10). Updates the state (phase transitions of Table 1, history maxima of
/// eqs 21 and 33). Connective: T_n = k_n dn / A, T_s = k_s ds / A (eqs 7-11). A link whose
/// psi reaches 1 turns cohesive in the same call and returns the cohesive traction: eqs 22-26
/// with delta_nc = delta_sc = dc, plus the compressive penalty. A link whose lambda reaches 1
/// turns to contact, and from then on returns zero traction for good.
CohesiveTraction cohesive_traction(const CohesiveParams& p, const CohesiveLimits& lim, double dn,
                                   double ds, CohesiveState& state,
                                   double closing = std::numeric_limits<double>::quiet_NaN());

/// Damage d of eq. 22: (lambda_max - lambda_cr) / (1 - lambda_cr) while cohesive, 0 while
/// connective, 1 in contact.
double damage(const CohesiveLimits& lim, const CohesiveState& state);

}  // namespace cleave::physics
