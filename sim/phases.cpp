#include "sim/phases.hpp"

#include <algorithm>

namespace cleave::sim {

BondFactors mixed_boundary(const io::PhaseDef& a, const io::PhaseDef& b) {
  return {2.0 * a.stiffness * b.stiffness / (a.stiffness + b.stiffness),
          std::min(a.strength, b.strength)};
}

BondFactors bond_factors(const io::Scenario& scenario, int a, int b) {
  if (scenario.phases.empty()) return {};
  if (a > b) std::swap(a, b);
  const io::PhaseDef& pa = scenario.phases.at(static_cast<std::size_t>(a));
  if (a == b) return {pa.stiffness, pa.strength};
  for (const io::BoundaryDef& boundary : scenario.boundaries) {
    if (boundary.phases[0] == a && boundary.phases[1] == b)
      return {boundary.stiffness, boundary.strength};
  }
  return mixed_boundary(pa, scenario.phases.at(static_cast<std::size_t>(b)));
}

double grain_density(const io::Scenario& scenario, const geometry::Grain& grain) {
  const double rho = scenario.phases.empty()
                         ? scenario.material.density
                         : scenario.phases.at(static_cast<std::size_t>(grain.phase)).density;
  return rho * scenario.dynamics.density_scale;
}

double lightest_density(const io::Scenario& scenario) {
  if (scenario.phases.empty()) return scenario.material.density;
  double rho = scenario.phases.front().density;
  for (const io::PhaseDef& p : scenario.phases) rho = std::min(rho, p.density);
  return rho;
}

double stiffest_bond_factor(const io::Scenario& scenario) {
  const int n = static_cast<int>(scenario.phases.size());
  double most = n == 0 ? 1.0 : 0.0;
  for (int a = 0; a < n; ++a) {
    for (int b = a; b < n; ++b) most = std::max(most, bond_factors(scenario, a, b).stiffness);
  }
  return most;
}

}  // namespace cleave::sim
