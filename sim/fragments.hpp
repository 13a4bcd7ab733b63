#pragma once
/// \file
/// Fragments in the fragmentation sense: the clusters of a world's bodies still held
/// together by intact bonds (a grain or a piece of one with no intact bond is a fragment of
/// its own). Each body's volume is taken exactly from its shape, so that the fragments'
/// volumes sum to the specimen's exactly while no body is lost.

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "geometry/exact_polyhedron.hpp"
#include "physics/dem/world.hpp"

namespace cleave::sim {

/// The connected components of `count` items joined by `links` (pairs of item indices below
/// `count`): each component's items ascending, the components by their first item.
std::vector<std::vector<std::uint32_t>> connected_clusters(
    std::size_t count, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& links);

/// One fragment: bodies (world slots) joined by intact bonds.
struct BondedFragment {
  std::vector<std::uint32_t> slots;
  double mass = 0.0;             ///< kg, the sum of the bodies' masses
  geometry::ExactScalar volume;  ///< m^3, the exact sum of the bodies' exact volumes
};

/// The fragments of `world`: its live bodies joined by its intact bonds;
/// `exact_volume(slot)` gives a body's exact volume.
std::vector<BondedFragment> bonded_fragments(
    const physics::World& world,
    const std::function<geometry::ExactScalar(std::uint32_t slot)>& exact_volume);

}  // namespace cleave::sim
