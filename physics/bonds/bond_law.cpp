#include "physics/bonds/bond_law.hpp"

#include <algorithm>
#include <cmath>

#include "physics/bonds/bond_batch.hpp"

namespace cleave::physics {

BondConstants bond_constants(const BondParams& p, const BondSection& s) {
  BondConstants k;
  // Spring stiffnesses from the continuum ones (eqs 2.10, 2.11).
  k.kbn = p.kbn * s.area();
  k.kbs = p.kbs * s.area();
  k.kbr = p.kbn * s.inertia();
  k.kbt = p.kbs * s.polar();
  // Limits (eq. 2.15).
  const double r = s.radius;
  k.tension = p.tbn * s.area();
  k.shear = p.tbs * s.area();
  k.bending = p.tbn * s.inertia() / r;
  k.torsion = p.tbs * s.polar() / r;
  return k;
}

BondResult bond_force(const BondParams& p, const BondSection& s, const Eigen::Vector3d& n,
                      const Eigen::Vector3d& velocity, const Eigen::Vector3d& spin,
                      BondState& b, double dt) {
  return bond_force(p, bond_constants(p, s), s, n, velocity, spin, b, dt);
}

BondResult bond_force(const BondParams& p, const BondConstants& k, const BondSection& s, const Eigen::Vector3d& n,
                      const Eigen::Vector3d& velocity, const Eigen::Vector3d& spin, BondState& b, double dt) {
  BondResult out;
  if (b.broken) return out;
  const double Kbn = k.kbn, Kbs = k.kbs;
  // Increments (eqs 2.12, 2.13): bond_batch.hpp's, one lane.
  const V3 nn = v3(n);
  const BondLoads<double> next =
      bond_increment<double>({b.normal, v3(b.shear), v3(b.bending), b.torsion}, k.kbn, k.kbs, k.kbr,
                             k.kbt, nn, v3(velocity), v3(spin), dt);
  const V3 shear = next.shear, bending = next.bending;
  b.normal = next.normal;
  b.shear = eigen(shear);
  b.bending = eigen(bending);
  b.torsion = next.torsion;
  if (p.law == BondLaw::cohesive) {
    const double A = s.area();
    const double dn = b.normal / Kbn;
    const double shear = b.shear.norm();
    const double ds = Kbs > 0.0 ? shear / Kbs : 0.0;
    const CohesiveParams cp{Kbn, Kbs, A, p.sigma_c, p.g_c};
    const CohesiveLimits limits = cohesive_limits(cp);
    const CohesiveTraction t = cohesive_traction(cp, limits, dn, ds, b.cohesive);
    if (b.cohesive.phase == LinkPhase::contact) {
      out.failure = std::max(dn, 0.0) >= ds ? BondFailure::tension : BondFailure::shear;
      out.at_failure = break_bond(b);
      b.cohesive.phase = LinkPhase::contact;
      return out;
    }
    // Eqs 27-29: tractions times the area; tension pulls B back, shear opposes the slip.
    out.force = -A * t.tn * n;
    if (shear > 0.0) out.force += (A * t.ts / shear) * b.shear;
    out.moment = (1.0 - damage(limits, b.cohesive)) * (b.bending + b.torsion * n);
    return out;
  }
  // Limits (eq. 2.15) and failure (eq. 2.16).
  out.failure = limit_failure(k, b.normal, norm(shear), norm(bending), b.torsion);
  if (out.failure != BondFailure::none) {
    out.at_failure = break_bond(b);
    return out;
  }
  // Tension pulls B back towards A.
  out.force = eigen(-b.normal * nn + shear);
  out.moment = eigen(bending + b.torsion * nn);
  return out;
}

BeamResult beam_force(const BondParams& p, const BeamPose& pose) {
  /// The cohesive beam of seed 003 (Andre et al. 2012): four parameters L_m, R_m, E_m, nu_m.
  BeamResult out;
  const double r = p.beam_radius, l0 = pose.rest_length;
  const BondSection section{r};
  const double area = section.area(), inertia = section.inertia(), polar = section.polar();
  const double young = p.beam_young, shear_modulus = young / (2.0 * (1.0 + p.beam_poisson));
  const Eigen::Vector3d chord = pose.end_b - pose.end_a;
  const double length = chord.norm();
  if (!(length > 0.0) || !(l0 > 0.0)) return out;
  const Eigen::Vector3d e = chord / length;
  // Axial: tension positive, pulls B back towards A.
  out.axial = young * area * (length - l0) / l0;
  // Bending: each end's turn from the chord (rotation taking e to its axis, first order).
  const Eigen::Vector3d theta_a = e.cross(pose.axis_a), theta_b = e.cross(pose.axis_b);
  const double k = 2.0 * young * inertia / l0;
  out.moment_a = -k * (2.0 * theta_a + theta_b);
  out.moment_b = -k * (theta_a + 2.0 * theta_b);
  const Eigen::Vector3d shear = e.cross(out.moment_a + out.moment_b) / length;
  // Torsion: B's across-direction against A's, both seen across e.
  const Eigen::Vector3d ua = pose.across_a - pose.across_a.dot(e) * e;
  const Eigen::Vector3d ub = pose.across_b - pose.across_b.dot(e) * e;
  const double twist = std::atan2(e.dot(ua.cross(ub)), ua.dot(ub));
  const double torque = shear_modulus * polar * twist / l0;
  out.moment_b -= torque * e;
  out.moment_a += torque * e;
  out.force_b = -out.axial * e + shear;
  out.shear = shear.norm();
  const double bend_a = (out.moment_a - out.moment_a.dot(e) * e).norm();
  const double bend_b = (out.moment_b - out.moment_b.dot(e) * e).norm();
  out.bending = std::max(bend_a, bend_b);
  out.torsion = std::abs(torque);
  out.peak_stress = out.axial / area + out.bending * r / inertia;
  return out;
}

const char* to_string(BondFailure mode) {
  switch (mode) {
    case BondFailure::none: return "none";
    case BondFailure::tension: return "tension";
    case BondFailure::shear: return "shear";
    case BondFailure::bending: return "bending";
    case BondFailure::torsion: return "torsion";
  }
  return "unknown";
}

double bond_strength_factor(std::uint64_t seed, int grain_a, int grain_b, double modulus) {
  // splitmix64 of the seed and the ordered pair: a uniform U in (0, 1).
  const auto lo = static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(grain_a, grain_b)));
  const auto hi = static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::max(grain_a, grain_b)));
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + ((hi << 32) | lo);
  for (int round = 0; round < 2; ++round) {
    z += 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
  }
  const double u = (static_cast<double>(z >> 11) + 0.5) * 0x1.0p-53;
  // Inverse of F: s = (-ln(1 - U))^(1/m) / Gamma(1 + 1/m).
  return std::pow(-std::log1p(-u), 1.0 / modulus) / std::tgamma(1.0 + 1.0 / modulus);
}

}  // namespace cleave::physics
