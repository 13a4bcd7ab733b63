#include "physics/bonds/cohesive_law.hpp"

#include <algorithm>
#include <cmath>

namespace cleave::physics {

CohesiveLimits cohesive_limits(const CohesiveParams& p) {
  CohesiveLimits lim{};
  lim.dn0 = p.area * p.sigma_c / p.kn;  // eq. 12
  lim.ds0 = p.area * p.sigma_c / p.ks;  // eq. 13
  lim.d0 = std::min(lim.dn0, lim.ds0);  // eq. 32
  // Our reading: delta_nc = delta_sc = dc, so that eq. 18 gives G_c for every mode mix.
  lim.dc = lim.d0 + (p.g_c > 0 ? 2.0 * p.g_c / p.sigma_c : 0.0);
  lim.lambda_cr = lim.d0 / lim.dc;
  return lim;
}

const char* to_string(LinkPhase phase) {
  switch (phase) {
    case LinkPhase::connective:
      return "connective";
    case LinkPhase::cohesive:
      return "cohesive";
    case LinkPhase::contact:
      return "contact";
  }
  return "unknown";
}

CohesiveTraction cohesive_traction(const CohesiveParams& p, const CohesiveLimits& lim, double dn,
                                   double ds, CohesiveState& s, double closing) {
  CohesiveTraction t;
  if (s.phase == LinkPhase::contact) return t;
  // The part of dn that is compression (the penalty's) and the rest, a separation: by
  // default the Macaulay bracket, <dn> apart and min(dn, 0) pressed.
  if (std::isnan(closing)) closing = std::min(dn, 0.0);
  const double apart = dn - closing;
  const double open = std::abs(apart);
  const bool traction = p.initiation == Initiation::traction;
  if (s.phase == LinkPhase::connective) {
    const double psi = traction ? std::hypot(open / lim.dn0, ds / lim.ds0)  // eq. 31
                                : std::hypot(open, ds) / lim.d0;            // eq. 32
    s.psi_max = std::max(s.psi_max, psi);                                   // eq. 33
    if (psi < 1.0) {
      t.tn = p.kn * dn / p.area;  // eqs 7, 11
      t.ts = p.ks * ds / p.area;
      return t;
    }
    // Table 1: connective -> cohesive; the history starts on the initiation circle.
    s.phase = LinkPhase::cohesive;
    if (traction) {
      // This link's own critical separation: G_c of softening beyond where it initiated.
      const double di = std::hypot(open, ds), gap = p.g_c > 0 ? 2.0 * p.g_c / p.sigma_c : 0.0;
      s.dc = di + gap;
      s.lambda_cr = (s.dc - gap) / s.dc;
      s.lambda_max = std::max(s.lambda_max, di / s.dc);
    } else {
      s.lambda_max = std::max(s.lambda_max, lim.lambda_cr);
    }
  }
  const double dc = traction ? s.dc : lim.dc;
  const double lambda_cr = traction ? s.lambda_cr : lim.lambda_cr;
  const double lambda = std::hypot(open / dc, ds / dc);  // eq. 14, delta_nc = delta_sc
  if (lambda >= 1.0) {  // eq. 16 / Table 1: complete decohesion, cohesive -> contact
    s.phase = LinkPhase::contact;
    s.lambda_max = std::max(s.lambda_max, lambda);
    return t;
  }
  s.lambda_max = std::max(s.lambda_max, lambda);                    // eq. 21
  const double d = (s.lambda_max - lambda_cr) / (1.0 - lambda_cr);  // eq. 22
  // Eqs 23-26: T = sigma_c (1 - d) lambda / lambda_max and T_i = T (delta_i / dc) / lambda;
  // the lambda cancels, which also covers lambda = 0 (zero traction at the origin).
  const double t_over_lambda = p.sigma_c * (1.0 - d) / s.lambda_max;
  t.tn = t_over_lambda * apart / dc + p.kn * closing / p.area;  // plus the compressive penalty
  t.ts = t_over_lambda * ds / dc;
  return t;
}

double damage(const CohesiveLimits& lim, const CohesiveState& s) {
  switch (s.phase) {
    case LinkPhase::connective:
      return 0.0;
    case LinkPhase::contact:
      return 1.0;
    case LinkPhase::cohesive:
      break;
  }
  const double lambda_cr = s.dc > 0 ? s.lambda_cr : lim.lambda_cr;
  if (lambda_cr >= 1.0) return 1.0;
  return std::clamp((s.lambda_max - lambda_cr) / (1.0 - lambda_cr), 0.0, 1.0);  // eq. 22
}

}  // namespace cleave::physics
