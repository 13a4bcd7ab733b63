#include "geometry/phases.hpp"

#include <stdexcept>

#include "geometry/rng.hpp"

namespace cleave::geometry {

std::vector<int> assign_phases(const std::vector<double>& volumes,
                               const std::vector<double>& fractions, std::uint64_t seed) {
  if (fractions.empty()) throw std::invalid_argument("assign_phases: no phases");
  double total = 0.0;
  for (const double v : volumes) {
    if (!(v > 0.0)) throw std::invalid_argument("assign_phases: a grain's volume is not positive");
    total += v;
  }
  // Fisher-Yates from the end, one draw per position: the order depends on the seed and the
  // grain count only.
  std::vector<std::size_t> order(volumes.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  SplitMix64 rng(seed ^ 0x5048415345530000ull);  // "PHASES": its own stream of the seed
  for (std::size_t i = order.size(); i > 1; --i) {
    const std::size_t j = rng.below(static_cast<std::uint32_t>(i));
    std::swap(order[i - 1], order[j]);
  }
  std::vector<double> below(fractions.size());  // target minus volume given so far
  for (std::size_t p = 0; p < fractions.size(); ++p) below[p] = fractions[p] * total;
  std::vector<int> phase(volumes.size(), 0);
  for (const std::size_t g : order) {
    std::size_t best = fractions.size();
    for (std::size_t p = 0; p < fractions.size(); ++p) {
      if (fractions[p] > 0.0 && (best == fractions.size() || below[p] > below[best])) best = p;
    }
    phase[g] = static_cast<int>(best);
    below[best] -= volumes[g];
  }
  return phase;
}

}  // namespace cleave::geometry
