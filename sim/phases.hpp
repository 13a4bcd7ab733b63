#pragma once
/// \file
/// What a several-phase specimen's phases ([[phase]], [[boundary]]) give its grains and
/// bonds: each grain's density and expansion, each bond's stiffness and strength factors
/// on the [bond] table (physics::Bond::stiffness, strength).

#include "geometry/specimen.hpp"
#include "io/scenario.hpp"

namespace cleave::sim {

/// A bond's factors on the [bond] table: stiffness on k_bn and k_bs (the beam law's E_m),
/// strength on t_bn and t_bs (sigma_c, sigma_f).
struct BondFactors {
  double stiffness = 1.0;
  double strength = 1.0;
};

/// The default law of a boundary between two phases without a [[boundary]] table: the two
/// grains' halves of the bond in series (1/k = 1/(2 k_a) + 1/(2 k_b): the harmonic mean of
/// the two stiffness factors), as strong as the weaker phase.
BondFactors mixed_boundary(const io::PhaseDef& a, const io::PhaseDef& b);

/// The factors of a bond between grains of phases `a` and `b` (indices into
/// scenario.phases): the phase's own when a == b, else the [[boundary]] table that joins
/// them or mixed_boundary. {1, 1} without phases.
BondFactors bond_factors(const io::Scenario& scenario, int a, int b);

/// The density a grain's body carries (kg/m^3): its phase's (else [material]'s), times
/// [dynamics] density_scale.
double grain_density(const io::Scenario& scenario, const geometry::Grain& grain);

/// The lightest grain density and the largest stiffness factor any bond can have, for the
/// stable time step: [material]'s density and 1 without phases.
double lightest_density(const io::Scenario& scenario);
double stiffest_bond_factor(const io::Scenario& scenario);

}  // namespace cleave::sim
