#include "geometry/crystal.hpp"

#include <cmath>
#include <stdexcept>

#include "geometry/rng.hpp"

namespace cleave::geometry {

std::string to_string(CleavageFamily family) {
  return family == CleavageFamily::a_11_20 ? "11-20" : "10-10";
}

CleavageFamily parse_cleavage_family(const std::string& text) {
  if (text == "11-20") return CleavageFamily::a_11_20;
  if (text == "10-10") return CleavageFamily::m_10_10;
  throw std::invalid_argument("unknown cleavage family '" + text + "' (expected 11-20 or 10-10)");
}

int slab_count(CleavageFamily family) { return family == CleavageFamily::a_11_20 ? 3 : 2; }

namespace {
int angle_step(int angle_deg) {
  if (angle_deg != 0 && angle_deg != 60 && angle_deg != 120) {
    throw std::invalid_argument("cleavage angle must be 0, 60 or 120 degrees, got " +
                                std::to_string(angle_deg));
  }
  return angle_deg / 60;
}
int corner(int n) { return ((n % 6) + 6) % 6; }
}  // namespace

std::vector<CornerPlane> cleavage_corner_planes(const CrystalOrientation& o) {
  const int step = angle_step(o.angle_deg);
  if (o.family == CleavageFamily::a_11_20) {
    // Normal along the <11-20> direction at 30 + angle degrees, i.e. towards corner m with
    // 90 - 60 m = 30 + angle. The two short diagonals across it join corners m-1, m+1
    // (offset +r/2) and m+2, m-2 (offset -r/2); listed from the negative side up.
    const int m = corner(1 - step);
    return {CornerPlane{corner(m + 2), corner(m - 2)}, CornerPlane{corner(m - 1), corner(m + 1)}};
  }
  // <10-10>: normal along the side-face normal at `angle` degrees; the plane through the
  // axis contains the corners at angle +- 90 degrees: 90 - 60 n = angle + 90 -> n = -step.
  const int a = corner(-step);
  return {CornerPlane{a, corner(a + 3)}};
}

std::array<double, 3> cleavage_normal(const CrystalOrientation& o) {
  const int step = angle_step(o.angle_deg);
  const double deg = (o.family == CleavageFamily::a_11_20 ? 30.0 : 0.0) + 60.0 * step;
  const double a = deg * M_PI / 180.0;
  return {std::cos(a), std::sin(a), 0.0};
}

CrystalOrientation draw_orientation(std::uint64_t seed, std::uint64_t grain_index,
                                    double family_mix, std::span<const int> angles) {
  if (angles.empty()) throw std::invalid_argument("draw_orientation: no angles to draw from");
  SplitMix64 rng = stream_for(seed, grain_index);
  CrystalOrientation o;
  o.family = rng.uniform() < family_mix ? CleavageFamily::a_11_20 : CleavageFamily::m_10_10;
  o.angle_deg = angles[rng.below(static_cast<std::uint32_t>(angles.size()))];
  angle_step(o.angle_deg);
  return o;
}

}  // namespace cleave::geometry
