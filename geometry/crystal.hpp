#pragma once
/// \file
/// Crystallographic orientation of a grain and the cleavage planes it implies
/// (sec. 2.2.2.1, figs 2.8 and 2.9 of the dissertation, seed 000).
///
/// The hexagonal prism's basal plane is the xy plane. Its corners point along the
/// <11-20> directions and its side-face normals along the <10-10> directions. With the
/// lattice of table 2.1 / App. A the corners sit at 30, 90, 150 degrees from +x, and the
/// side-face normals at 0, 60, 120 degrees.
///
/// - family <11-20> (three slabs, fig. 2.8): two parallel cleavage planes normal to the
///   <11-20> direction at 30 + angle degrees, each through two corners (a short diagonal);
///   they leave an isosceles triangular prism, a rectangular prism and a second triangular
///   prism.
/// - family <10-10> (two slabs, fig. 2.9): one cleavage plane through the axis, normal to
///   the <10-10> direction at `angle` degrees; it runs through two opposite corners and
///   leaves two equal trapezoidal prisms.
///
/// `angle` is 0, 60 or 120 degrees (the three equivalent variants of each family).

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace cleave::geometry {

enum class CleavageFamily : std::uint8_t {
  a_11_20,  ///< <11-20>: three slabs
  m_10_10,  ///< <10-10>: two slabs
};

/// "11-20" or "10-10" (the Miller-Bravais direction without brackets).
std::string to_string(CleavageFamily family);
/// Parses "11-20" / "10-10"; throws std::invalid_argument otherwise.
CleavageFamily parse_cleavage_family(const std::string& text);
/// 3 for <11-20>, 2 for <10-10>.
int slab_count(CleavageFamily family);

struct CrystalOrientation {
  CleavageFamily family = CleavageFamily::a_11_20;
  int angle_deg = 0;  ///< 0, 60 or 120

  friend bool operator==(const CrystalOrientation&, const CrystalOrientation&) = default;
};

/// A cleavage plane of the hexagonal prism built by `ExactPolyhedron::hexagonal_prism`,
/// named by the two bottom-hexagon corners it passes through (corner n sits at
/// 90 - 60 n degrees, n = 0..5). The plane is vertical (contains the prism axis direction),
/// so it is exact: it passes through existing exact vertices.
struct CornerPlane {
  int corner_a;
  int corner_b;
};

/// The cleavage planes of a prism grain with this orientation, ordered across the grain so
/// that cutting by them in turn yields the slabs in order.
std::vector<CornerPlane> cleavage_corner_planes(const CrystalOrientation& orientation);

/// Unit normal (in the basal plane) of the cleavage planes of this orientation.
std::array<double, 3> cleavage_normal(const CrystalOrientation& orientation);

/// Deterministic orientation for grain `grain_index` of an ensemble with this `seed`:
/// the family is <11-20> with probability `family_mix`, else <10-10>; the angle is drawn
/// uniformly from `angles` (each 0, 60 or 120).
CrystalOrientation draw_orientation(std::uint64_t seed, std::uint64_t grain_index,
                                    double family_mix, std::span<const int> angles);

}  // namespace cleave::geometry
