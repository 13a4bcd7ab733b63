#pragma once
/// \file
/// Which phase each grain of a several-phase specimen is ([[phase]] tables): grains taken in
/// a seeded random order, each given to the phase furthest below its target volume.

#include <cstdint>
#include <vector>

namespace cleave::geometry {

/// The phase of each grain (indices into `fractions`), by volume fraction: the grains are
/// taken in a random order drawn from `seed` (a Fisher-Yates shuffle of SplitMix64), and
/// each goes to the phase whose volume lies furthest below fraction x total volume (the
/// lowest index on a tie; a phase of fraction 0 gets none). A phase ends at most one
/// grain's volume above its target; with two phases also at most one below (the other's
/// excess), with n phases at most n - 1 grains' volumes below. The same seed takes the
/// grains in the same order for every set of fractions, so a sweep over fractions changes
/// the fewest grains. `fractions` are >= 0 and sum to 1; `volumes` are > 0.
std::vector<int> assign_phases(const std::vector<double>& volumes,
                               const std::vector<double>& fractions, std::uint64_t seed);

}  // namespace cleave::geometry
