#pragma once
/// \file
/// Coarse contact detection on a cell grid (App. B of the dissertation, seed 000).
///
/// - basic: cells at least as large as the largest bounding sphere's diameter; each body
///   is placed in the one cell holding its centre, and searched against the 27 cells
///   around it. O(N) for bodies of similar size.
/// - bounding_box: cells sized by the smallest bodies; each body is listed in every cell
///   its bounding box overlaps and searched over the same cells, so one big body does not
///   make every cell big (fragments are much smaller than grains).
/// Both return the same set: every pair whose bounding spheres overlap within `margin`.

#include <Eigen/Dense>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace cleave::physics {

struct BoundingSphere {
  Eigen::Vector3d centre;
  double radius = 0.0;
};

enum class SearchMethod { basic, bounding_box };

using BodyPair = std::pair<std::uint32_t, std::uint32_t>;

namespace detail {
/// A cell of the hash table of occupied cells outside the dense window (neighbour_search.cpp).
struct CellSlot {
  std::int32_t x, y, z;
  std::uint32_t id;  ///< the cell's id; UINT32_MAX marks an empty slot
};
}  // namespace detail

class NeighbourSearch {
 public:
  explicit NeighbourSearch(SearchMethod method = SearchMethod::bounding_box) : method_(method) {}

  /// Every pair (i, j), i < j, with |c_i - c_j| <= r_i + r_j + margin, sorted ascending,
  /// without duplicates. Deterministic: the result does not depend on threads or on the
  /// grid's internal order. Reuses internal buffers between calls.
  /// The test is evaluated in double as dx*dx + dy*dy + dz*dz <= (r_i + r_j + margin)^2,
  /// with d = c_i - c_j (touching counts). Throws std::invalid_argument for a negative or
  /// non-finite margin, a negative or non-finite radius or a non-finite centre, and
  /// std::length_error past 2^28 bodies or (body, cell) entries.
  void find_pairs(std::span<const BoundingSphere> spheres, double margin,
                  std::vector<BodyPair>& pairs);

  [[nodiscard]] SearchMethod method() const { return method_; }

 private:
  SearchMethod method_;
  // Buffers kept between calls, so steady-state calls do not allocate; layout in
  // neighbour_search.cpp.
  std::vector<std::int32_t> homes_;         ///< per body: the cell of its box's low corner
  std::vector<std::int32_t> ranked_boxes_;  ///< per rank: cell box, low x y z then high x y z
  std::vector<std::uint32_t> order_;        ///< rank -> body
  std::vector<BoundingSphere> ranked_;      ///< the spheres in rank order
  std::vector<std::uint32_t> entry_cells_;  ///< per (body, cell) entry: the cell's id
  std::vector<std::uint32_t> items_;        ///< entries grouped by cell: rank | low-face bits
  std::vector<std::uint32_t> starts_;       ///< per cell id: first rank or entry; then end
  std::vector<detail::CellSlot> table_;     ///< open-addressing table of cells off the window
  std::vector<detail::CellSlot> hashed_;    ///< those cells by id
  std::vector<std::uint32_t> partners_;     ///< basic: the candidate ranks around one cell
  std::vector<BodyPair> found_;             ///< pairs as found, before the final sort
};

}  // namespace cleave::physics
