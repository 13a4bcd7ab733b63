/// \file
/// Coarse contact detection, App. B.1 of the dissertation (seed 000): the "basic" and the
/// "bounding box" spatial discretisation algorithms.
///
/// Pipeline, shared by both methods:
/// 1. Cell boxes (App. B step 1, bounding-box step 2). With h = r + margin / 2, two bodies
///    can pass the test only if their boxes [c - h, c + h] overlap. Coordinates go to cell
///    units, t = (x - ref) / cell with ref the per-axis median of a sample of centres, are
///    clamped to +-2^30 cells and floored. Both maps are monotone, so overlapping boxes
///    still overlap as cell ranges: coordinates of any sign and extent work, and bodies
///    beyond 2^30 cells only share the boundary layer (slower, still exact). Basic: a
///    body's box is the one cell holding its centre (basic step 2).
/// 2. Cell ids. A dense row-major window over the bulk numbers its cells 0..W-1 by linear
///    index; occupied cells outside it (far bodies, sparse systems) take the next ids from
///    an open-addressing hash table. The window is the whole occupied range when that has
///    at most kDenseCellsPerEntry cells per entry, else the range of the central bodies of
///    a sample when that is small enough, else empty (all cells hashed).
/// 3. Ranks. Bodies are counting-sorted by the cell of their box's low corner (ties in
///    index order) and copied in that order, so bodies near in space are near in memory.
///    Basic: each cell's ranks form one run, so this is the cell list. Bounding box: the
///    (rank, cell) entries of every cell of every box (step 3) are counting-sorted by cell
///    the same way.
/// 4. Candidates, and the exact test on the rank-ordered copy, cell by cell.
///    Basic (step 3): a cell against itself and against the neighbours with a larger id;
///    for a window cell these are the 13 cells after it in row-major order, 5 runs of ranks.
///    Bounding box (step 4): every two entries of a cell. A pair is tested only in the cell
///    holding the low corner of the intersection of the two boxes, so a pair sharing several
///    cells is tested once and no dedupe pass is needed: each entry carries three bits,
///    "this cell is on my box's low face" per axis, and that corner is the shared cell
///    where, on every axis, one of the two has its low face.
/// 5. Order. Radix sort by first index, then each short run by second index: the output
///    does not depend on the grid's internal order.
/// For a parallel version, step 4 is independent per cell (chunks of cells, each with its
/// own list of found pairs, concatenated), and steps 3 and 5 are counting / radix sorts.
///
/// Bounding-box cell size. App. B sizes cells by the smallest bodies, not the largest. Here
/// the cell is the smallest one with at most kEntryBudget (body, cell) entries per body in
/// expectation, but at least 1 / kMaxCellsPerAxis of the widest box. A body of width w
/// spans (w / cell + 1)^3 cells on average, so a budget of 4 gives cells about 1.7 times
/// the width of the bodies that dominate the count (the small ones). 4 was the fastest
/// budget on mixed sizes in bench_neighbour_search; equal sizes barely care.
/// A few huge bodies enlarge the cell only as far as their share of the entries needs,
/// and no body spans more than kMaxCellsPerAxis + 1 cells per axis.

#include "physics/dem/neighbour_search.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace cleave::physics {
namespace {

using detail::CellSlot;

/// Bounding-box entry: rank in the low kRankBits, low-face bits (x, y, z) above.
constexpr int kRankBits = 29;
constexpr std::uint32_t kRankMask = (std::uint32_t{1} << kRankBits) - 1;
/// Cell coordinates are clamped to +-kCoordLimit cells around the reference point.
constexpr double kCoordLimit = 0x1p30;
/// Slack in cell units that absorbs rounding: boxes grow by it (bounding box) and the
/// basic cell is 2 h_max / (1 - kSlack). Rounding errors stay below 2^-21 cell units.
constexpr double kSlack = 0x1p-10;
/// Bounding box: at most this many (body, cell) entries per body, in expectation.
constexpr double kEntryBudget = 4.0;
/// Bounding box: cells are at least 1 / kMaxCellsPerAxis of the widest box.
constexpr double kMaxCellsPerAxis = 32.0;
/// The dense window has at most this many cells per entry, plus a floor.
constexpr double kDenseCellsPerEntry = 8.0;
constexpr double kDenseCellsFloor = 4096.0;
/// Keeps every cell id and offset within 32 bits.
constexpr std::uint64_t kMaxEntries = std::uint64_t{1} << 28;
constexpr std::uint32_t kNoCell = std::numeric_limits<std::uint32_t>::max();
/// Bodies sampled (evenly spaced) for the reference point and the window.
constexpr std::size_t kSamples = 63;

/// The exact test of the contract, evaluated identically for every pair:
/// (c_a - c_b)^2 <= (r_a + r_b + margin)^2 (symmetric in a and b, bit for bit).
inline bool within_reach(const BoundingSphere& a, const BoundingSphere& b, double margin) {
  const double dx = a.centre.x() - b.centre.x();
  const double dy = a.centre.y() - b.centre.y();
  const double dz = a.centre.z() - b.centre.z();
  const double reach = a.radius + b.radius + margin;
  return dx * dx + dy * dy + dz * dz <= reach * reach;
}

/// Cell-unit coordinate to a cell index: clamp, then floor; both monotone.
inline std::int32_t to_cell(double t) {
  return static_cast<std::int32_t>(std::floor(std::clamp(t, -kCoordLimit, kCoordLimit)));
}

/// Per-axis median of the sampled centres, so that a few far bodies cannot push the bulk
/// into the clamped boundary layer.
Eigen::Vector3d reference_point(std::span<const BoundingSphere> spheres) {
  const std::size_t n = spheres.size();
  const std::size_t m = std::min(n, kSamples);
  std::array<double, kSamples> v{};
  Eigen::Vector3d ref;
  for (int a = 0; a < 3; ++a) {
    for (std::size_t k = 0; k < m; ++k) v[k] = spheres[k * n / m].centre[a];
    std::nth_element(v.begin(), v.begin() + m / 2, v.begin() + m);
    ref[a] = v[m / 2];
  }
  return ref;
}

/// Bounding box: the smallest cell whose expected entry count is within the budget. A box
/// of width 2h spans 2h / cell + 1 cells per axis on average, so
///   E(cell) = sum_i (2 h_i / cell + 1)^3 = N + 6 S1 u + 12 S2 u^2 + 8 S3 u^3,
/// with u = h_max / cell and S_k = sum (h_i / h_max)^k. E falls as the cell grows; solve
/// E = kEntryBudget N for u by bisection.
double budget_cell_size(std::span<const BoundingSphere> spheres, double half_margin, double hmax) {
  double s1 = 0.0, s2 = 0.0, s3 = 0.0;
  for (const BoundingSphere& b : spheres) {
    const double h = (b.radius + half_margin) / hmax;
    s1 += h;
    s2 += h * h;
    s3 += h * h * h;
  }
  const double excess = (kEntryBudget - 1.0) * static_cast<double>(spheres.size());
  const auto over = [&](double u) { return ((8.0 * s3 * u + 12.0 * s2) * u + 6.0 * s1) * u; };
  double lo = 0.0;
  double hi = excess / (6.0 * s1);  // over(hi) >= excess
  for (int k = 0; k < 64; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (over(mid) > excess) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return hmax / hi;
}

inline std::uint64_t cell_hash(std::int32_t x, std::int32_t y, std::int32_t z) {
  std::uint64_t h =
      (std::uint64_t{static_cast<std::uint32_t>(x)} << 32 | static_cast<std::uint32_t>(y)) *
      0x9E3779B97F4A7C15ull;
  h ^= (h >> 29) + std::uint64_t{static_cast<std::uint32_t>(z)} * 0xC2B2AE3D27D4EB4Full;
  return h * 0x94D049BB133111EBull;
}

/// Cell ids: the dense window (ids 0..window_cells-1, row-major), then the hashed cells.
struct CellIndex {
  std::array<std::int32_t, 3> lo{1, 1, 1};  ///< window, inclusive; empty while lo > hi
  std::array<std::int32_t, 3> hi{0, 0, 0};
  std::array<std::int64_t, 3> size{0, 0, 0};
  std::uint32_t window_cells = 0;
  std::uint32_t hashed = 0;  ///< number of cells in the hash table
  const CellSlot* slots = nullptr;
  std::size_t mask = 0;
  int shift = 64;
  const std::uint32_t* starts = nullptr;

  bool in_window(std::int32_t x, std::int32_t y, std::int32_t z) const {
    return x >= lo[0] && x <= hi[0] && y >= lo[1] && y <= hi[1] && z >= lo[2] && z <= hi[2];
  }
  std::uint32_t window_id(std::int32_t x, std::int32_t y, std::int32_t z) const {
    return static_cast<std::uint32_t>(
        (std::int64_t{x} - lo[0]) +
        size[0] * ((std::int64_t{y} - lo[1]) + size[1] * (std::int64_t{z} - lo[2])));
  }
  std::uint32_t hashed_id(std::int32_t x, std::int32_t y, std::int32_t z) const {
    if (hashed == 0) return kNoCell;
    for (std::size_t s = cell_hash(x, y, z) >> shift;; s = (s + 1) & mask) {
      const CellSlot& slot = slots[s];
      if (slot.id == kNoCell) return kNoCell;
      if (slot.x == x && slot.y == y && slot.z == z) return slot.id;
    }
  }
  std::uint32_t find(std::int32_t x, std::int32_t y, std::int32_t z) const {
    return in_window(x, y, z) ? window_id(x, y, z) : hashed_id(x, y, z);
  }
};

/// The dense window: the whole occupied range if small enough; else the range of the
/// central sampled bodies per axis (the 5 %..95 % quantiles, widened by a quarter of their
/// spread and 2 cells each side), if small enough; else empty.
void choose_window(CellIndex& grid, const std::array<std::int32_t, 3>& lo_all,
                   const std::array<std::int32_t, 3>& hi_all, const std::int32_t* homes,
                   std::size_t n, std::uint64_t entries) {
  const double budget = kDenseCellsPerEntry * static_cast<double>(entries) + kDenseCellsFloor;
  const auto volume = [](const auto& lo, const auto& hi) {
    double v = 1.0;
    for (int a = 0; a < 3; ++a) v *= static_cast<double>(std::int64_t{hi[a]} - lo[a] + 1);
    return v;
  };
  std::array<std::int32_t, 3> lo = lo_all, hi = hi_all;
  if (volume(lo, hi) > budget) {
    const std::size_t m = std::min(n, kSamples);
    const std::size_t q = m / 16;
    std::array<std::int32_t, kSamples> v{};
    for (int a = 0; a < 3; ++a) {
      for (std::size_t k = 0; k < m; ++k) v[k] = homes[3 * (k * n / m) + a];
      std::sort(v.begin(), v.begin() + m);
      const std::int64_t q_lo = v[q];
      const std::int64_t q_hi = v[m - 1 - q];
      const std::int64_t widen = (q_hi - q_lo + 1) / 4 + 2;
      lo[a] = static_cast<std::int32_t>(std::max<std::int64_t>(lo_all[a], q_lo - widen));
      hi[a] = static_cast<std::int32_t>(std::min<std::int64_t>(hi_all[a], q_hi + widen));
    }
    if (volume(lo, hi) > budget) return;
  }
  grid.lo = lo;
  grid.hi = hi;
  for (int a = 0; a < 3; ++a) grid.size[a] = std::int64_t{hi[a]} - lo[a] + 1;
  grid.window_cells = static_cast<std::uint32_t>(volume(lo, hi));
}

/// Id of an occupied cell outside the window: found in, or added to, the hash table
/// (linear probing, a power of two at most half full; hashed lists the cells by id).
/// Growing the table is the only allocation, and only past the largest size seen.
std::uint32_t hashed_cell_id(std::vector<CellSlot>& table, std::vector<CellSlot>& hashed,
                             std::uint32_t first_id, std::int32_t x, std::int32_t y,
                             std::int32_t z) {
  const auto home = [&](std::int32_t cx, std::int32_t cy, std::int32_t cz) {
    return cell_hash(cx, cy, cz) >> (64 - std::countr_zero(table.size()));
  };
  if (table.empty()) table.assign(64, CellSlot{0, 0, 0, kNoCell});
  std::size_t mask = table.size() - 1;
  std::size_t s = home(x, y, z);
  for (; table[s].id != kNoCell; s = (s + 1) & mask) {
    if (table[s].x == x && table[s].y == y && table[s].z == z) return table[s].id;
  }
  if (2 * (hashed.size() + 1) > table.size()) {
    table.assign(2 * table.size(), CellSlot{0, 0, 0, kNoCell});
    mask = table.size() - 1;
    for (const CellSlot& cell : hashed) {
      std::size_t t = home(cell.x, cell.y, cell.z);
      while (table[t].id != kNoCell) t = (t + 1) & mask;
      table[t] = cell;
    }
    for (s = home(x, y, z); table[s].id != kNoCell;) s = (s + 1) & mask;
  }
  const CellSlot cell{x, y, z, first_id + static_cast<std::uint32_t>(hashed.size())};
  table[s] = cell;
  hashed.push_back(cell);
  return cell.id;
}

/// Found pairs as (smaller index, larger index), written without branching on the test:
/// every candidate is stored and the count advances only if it passed. The buffer only
/// grows; its first `count` pairs are the result.
struct PairSink {
  std::vector<BodyPair>& buffer;
  std::size_t count = 0;

  /// Room for m more candidates; returns where the next one goes.
  BodyPair* reserve(std::size_t m) {
    if (count + m > buffer.size()) buffer.resize(std::max(2 * buffer.size(), count + m));
    return buffer.data() + count;
  }
  static BodyPair* put(BodyPair* out, std::uint32_t u, std::uint32_t v, bool hit) {
    // min / max by masks: the indices are in random order, a branch would mispredict.
    const std::uint32_t swap = (u ^ v) & (0u - static_cast<std::uint32_t>(v < u));
    *out = {u ^ swap, v ^ swap};
    return out + (hit ? 1 : 0);
  }
  void commit(const BodyPair* out) { count = static_cast<std::size_t>(out - buffer.data()); }
};

/// App. B basic search, step 3, cell by cell: bodies of the same or of neighbouring cells,
/// each pair of cells from the one with the smaller id.
void emit_basic(const CellIndex& grid, const std::vector<CellSlot>& hashed,
                const BoundingSphere* ranked, const std::uint32_t* order, double margin,
                std::vector<std::uint32_t>& partners, PairSink& found) {
  const std::uint32_t* starts = grid.starts;
  std::array<std::pair<std::uint32_t, std::uint32_t>, 26> runs;
  int count = 0;
  std::size_t in_runs = 0;
  const auto clear_runs = [&] {
    count = 0;
    in_runs = 0;
  };
  const auto add_run = [&](std::uint32_t b, std::uint32_t e) {
    if (b == e) return;
    runs[count++] = {b, e};
    in_runs += e - b;
  };
  // Ranks begin..end of one cell against the rest of their own run (up to own_end) and
  // the runs: the partners are first gathered into one list, so that each body has a
  // single loop.
  const auto scan = [&](std::uint32_t begin, std::uint32_t end, std::uint32_t own_end) {
    const std::size_t total = (own_end - begin) + in_runs;
    if (partners.size() < total) partners.resize(2 * total);
    std::uint32_t* p = partners.data();
    for (std::uint32_t b = begin; b < own_end; ++b) *p++ = b;
    for (int k = 0; k < count; ++k) {
      for (std::uint32_t b = runs[k].first; b < runs[k].second; ++b) *p++ = b;
    }
    for (std::uint32_t a = begin; a < end; ++a) {
      const BoundingSphere& sa = ranked[a];
      const std::uint32_t ua = order[a];
      const std::size_t first = a - begin + 1;
      BodyPair* out = found.reserve(total - first);
      for (std::size_t k = first; k < total; ++k) {
        const std::uint32_t b = partners[k];
        out = PairSink::put(out, ua, order[b], within_reach(sa, ranked[b], margin));
      }
      found.commit(out);
    }
  };
  // Any cell: look up the 26 neighbours, keep those with a larger id.
  const auto scan_any = [&](std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t id) {
    clear_runs();
    for (std::int32_t dz = -1; dz <= 1; ++dz) {
      for (std::int32_t dy = -1; dy <= 1; ++dy) {
        for (std::int32_t dx = -1; dx <= 1; ++dx) {
          const std::uint32_t c = grid.find(x + dx, y + dy, z + dz);
          if (c != kNoCell && c > id) add_run(starts[c], starts[c + 1]);
        }
      }
    }
    scan(starts[id], starts[id + 1], starts[id + 1]);
  };

  const std::int64_t sx = grid.size[0], sy = grid.size[1], sz = grid.size[2];
  std::uint32_t c = 0;
  for (std::int64_t z = 0; z < sz; ++z) {
    for (std::int64_t y = 0; y < sy; ++y) {
      for (std::int64_t x = 0; x < sx; ++x, ++c) {
        if (starts[c] == starts[c + 1]) continue;
        const bool interior = x > 0 && y > 0 && z > 0 && x + 1 < sx && y + 1 < sy && z + 1 < sz;
        if (grid.hashed != 0 && !interior) {
          scan_any(static_cast<std::int32_t>(x + grid.lo[0]),
                   static_cast<std::int32_t>(y + grid.lo[1]),
                   static_cast<std::int32_t>(z + grid.lo[2]), c);
          continue;
        }
        // The 13 cells after c in row-major order, clipped to the window: x + 1 in the
        // same run as c, then rows (y + 1, z), (y - 1..y + 1, z + 1), x - 1..x + 1 each.
        clear_runs();
        const std::int64_t x0 = std::max<std::int64_t>(x - 1, 0);
        const std::int64_t x1 = std::min<std::int64_t>(x + 1, sx - 1);
        const auto add_row = [&](std::int64_t ry, std::int64_t rz) {
          if (ry < 0 || ry >= sy || rz >= sz) return;
          const auto row = static_cast<std::uint32_t>(sx * (ry + sy * rz));
          add_run(starts[row + x0], starts[row + x1 + 1]);
        };
        add_row(y + 1, z);
        add_row(y - 1, z + 1);
        add_row(y, z + 1);
        add_row(y + 1, z + 1);
        scan(starts[c], starts[c + 1], starts[c + 1 + (x + 1 < sx ? 1 : 0)]);
      }
    }
  }
  for (const CellSlot& cell : hashed) scan_any(cell.x, cell.y, cell.z, cell.id);
}

/// App. B bounding-box search, step 4, cell by cell: every two entries of a cell, a pair
/// counted only in the low corner cell of the intersection of the two boxes, i.e. where
/// on every axis one of the two has its low face: (low bits of p | low bits of q) == 7.
void emit_bounding_box(const std::uint32_t* starts, std::uint32_t cells, const std::uint32_t* items,
                       const BoundingSphere* ranked, const std::uint32_t* order, double margin,
                       PairSink& found) {
  for (std::uint32_t c = 0; c < cells; ++c) {
    const std::uint32_t begin = starts[c];
    const std::uint32_t end = starts[c + 1];
    for (std::uint32_t p = begin; p + 1 < end; ++p) {
      const std::uint32_t rp = items[p] & kRankMask;
      const std::uint32_t low_p = items[p] >> kRankBits;
      const BoundingSphere& sp = ranked[rp];
      const std::uint32_t up = order[rp];
      BodyPair* out = found.reserve(end - p - 1);
      for (std::uint32_t q = p + 1; q < end; ++q) {
        const std::uint32_t rq = items[q] & kRankMask;
        const bool corner = ((low_p | items[q] >> kRankBits) == 7u);
        out = PairSink::put(out, up, order[rq], corner & within_reach(sp, ranked[rq], margin));
      }
      found.commit(out);
    }
  }
}

/// Step 5: LSD radix sort of the first `count` found pairs by first index (digits of at most
/// 11 bits), then each run of equal first index sorted by second index (runs are short,
/// except for big bodies).
void sort_pairs(std::vector<BodyPair>& found, std::size_t count, std::size_t n,
                std::vector<std::uint32_t>& buckets, std::vector<BodyPair>& pairs) {
  if (count >= kNoCell) throw std::length_error("NeighbourSearch: too many pairs");
  const auto bits = static_cast<int>(std::bit_width(n - 1));
  const int passes = std::max(1, (bits + 10) / 11);
  const int digit = (bits + passes - 1) / passes;
  const std::uint32_t mask = (std::uint32_t{1} << digit) - 1;
  // Ping-pong between found and pairs, arranged so that the last pass writes into pairs.
  pairs.resize(count);
  BodyPair* src = found.data();
  BodyPair* dst = pairs.data();
  if (passes % 2 == 0) {
    std::copy_n(found.data(), count, pairs.data());
    std::swap(src, dst);
  }
  for (int pass = 0; pass < passes; ++pass) {
    const int shift = pass * digit;
    buckets.assign(std::size_t{mask} + 1, 0);
    for (std::size_t k = 0; k < count; ++k) ++buckets[(src[k].first >> shift) & mask];
    std::uint32_t run = 0;
    for (std::uint32_t& b : buckets) run += std::exchange(b, run);
    for (std::size_t k = 0; k < count; ++k) dst[buckets[(src[k].first >> shift) & mask]++] = src[k];
    std::swap(src, dst);
  }
  const auto by_second = [](const BodyPair& p, const BodyPair& q) { return p.second < q.second; };
  for (auto first = pairs.begin(); first != pairs.end();) {
    auto last = first + 1;
    while (last != pairs.end() && last->first == first->first) ++last;
    if (last - first > 16) {
      std::sort(first, last, by_second);
    } else {
      for (auto k = first + 1; k < last; ++k) {
        const BodyPair p = *k;
        auto m = k;
        for (; m > first && p.second < (m - 1)->second; --m) *m = *(m - 1);
        *m = p;
      }
    }
    first = last;
  }
}

}  // namespace

void NeighbourSearch::find_pairs(std::span<const BoundingSphere> spheres, double margin,
                                 std::vector<BodyPair>& pairs) {
  pairs.clear();
  if (!(margin >= 0.0) || !std::isfinite(margin)) {
    throw std::invalid_argument("NeighbourSearch: margin must be finite and >= 0");
  }
  const std::size_t n = spheres.size();
  if (n > kRankMask) throw std::length_error("NeighbourSearch: too many bodies");
  const double half_margin = 0.5 * margin;
  double hmax = 0.0;
  for (const BoundingSphere& s : spheres) {
    const double h = s.radius + half_margin;
    if (!(s.radius >= 0.0) || !std::isfinite(h) || !s.centre.allFinite()) {
      throw std::invalid_argument("NeighbourSearch: centres and radii must be finite, r >= 0");
    }
    hmax = std::max(hmax, h);
  }
  if (n < 2) return;

  // 1. Cell size (App. B step 1 of both algorithms) and cell boxes.
  const bool basic = method_ == SearchMethod::basic;
  double cell = 1.0;  // points only (hmax == 0): any size works
  if (hmax > 0.0) {
    cell = basic ? 2.0 * hmax / (1.0 - kSlack)
                 : std::max(2.0 * hmax / kMaxCellsPerAxis,
                            budget_cell_size(spheres, half_margin, hmax));
    cell = std::max(cell, 0x1p-1000);  // keeps 1 / cell finite
  }
  const double inv = 1.0 / cell;
  const Eigen::Vector3d ref = reference_point(spheres);
  const auto box_of = [&](const BoundingSphere& s, std::int32_t* b) {
    const double hc = basic ? 0.0 : (s.radius + half_margin) * inv + kSlack;
    for (int a = 0; a < 3; ++a) {
      const double t = (s.centre[a] - ref[a]) * inv;
      b[a] = to_cell(t - hc);
      b[a + 3] = to_cell(t + hc);
    }
  };
  homes_.resize(3 * n);
  std::array<std::int32_t, 3> lo_all, hi_all;
  lo_all.fill(std::numeric_limits<std::int32_t>::max());
  hi_all.fill(std::numeric_limits<std::int32_t>::min());
  std::uint64_t entries = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::array<std::int32_t, 6> b;
    box_of(spheres[i], b.data());
    std::uint64_t count = 1;
    for (int a = 0; a < 3; ++a) {
      homes_[3 * i + a] = b[a];
      lo_all[a] = std::min(lo_all[a], b[a]);
      hi_all[a] = std::max(hi_all[a], b[a + 3]);
      count *= static_cast<std::uint64_t>(std::int64_t{b[a + 3]} - b[a] + 1);
    }
    entries += count;
  }
  if (entries > kMaxEntries) throw std::length_error("NeighbourSearch: too many cell entries");

  // 2. Cell ids: the dense window, then the hash table (emptied if the last call used it).
  CellIndex grid;
  choose_window(grid, lo_all, hi_all, homes_.data(), n, entries);
  if (!hashed_.empty()) {
    std::fill(table_.begin(), table_.end(), CellSlot{0, 0, 0, kNoCell});
    hashed_.clear();
  }
  const auto id_of = [&](std::int32_t x, std::int32_t y, std::int32_t z) {
    return grid.in_window(x, y, z) ? grid.window_id(x, y, z)
                                   : hashed_cell_id(table_, hashed_, grid.window_cells, x, y, z);
  };

  // 3. Ranks: bodies counting-sorted by the cell of their box's low corner.
  entry_cells_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    entry_cells_[i] = id_of(homes_[3 * i], homes_[3 * i + 1], homes_[3 * i + 2]);
  }
  const auto counting_sort = [&](std::uint32_t cells, auto&& place) {
    starts_.assign(std::size_t{cells} + 1, 0);
    for (const std::uint32_t c : entry_cells_) ++starts_[c];
    std::uint32_t run = 0;
    for (std::uint32_t c = 0; c < cells; ++c) starts_[c] = run += starts_[c];
    starts_[cells] = run;
    place();  // backwards, so that starts_[c] ends at the first slot of cell c
  };
  order_.resize(n);
  counting_sort(grid.window_cells + static_cast<std::uint32_t>(hashed_.size()), [&] {
    for (std::size_t i = n; i-- > 0;) {
      order_[--starts_[entry_cells_[i]]] = static_cast<std::uint32_t>(i);
    }
  });
  ranked_.resize(n);
  for (std::size_t a = 0; a < n; ++a) ranked_[a] = spheres[order_[a]];

  // Bounding box: the boxes again in rank order, and their (rank, cell) entries,
  // counting-sorted by cell.
  if (!basic) {
    ranked_boxes_.resize(6 * n);
    for (std::size_t a = 0; a < n; ++a) box_of(ranked_[a], &ranked_boxes_[6 * a]);
    entry_cells_.resize(entries);
    std::size_t e = 0;
    for (std::size_t a = 0; a < n; ++a) {
      const std::int32_t* b = &ranked_boxes_[6 * a];
      for (std::int32_t z = b[2]; z <= b[5]; ++z) {
        for (std::int32_t y = b[1]; y <= b[4]; ++y) {
          for (std::int32_t x = b[0]; x <= b[3]; ++x) entry_cells_[e++] = id_of(x, y, z);
        }
      }
    }
    items_.resize(entries);
    counting_sort(grid.window_cells + static_cast<std::uint32_t>(hashed_.size()), [&] {
      for (std::size_t a = n; a-- > 0;) {
        const std::int32_t* b = &ranked_boxes_[6 * a];
        for (std::int32_t z = b[5]; z >= b[2]; --z) {
          for (std::int32_t y = b[4]; y >= b[1]; --y) {
            for (std::int32_t x = b[3]; x >= b[0]; --x) {
              const std::uint32_t low = std::uint32_t{x == b[0]} | (std::uint32_t{y == b[1]} << 1) |
                                        (std::uint32_t{z == b[2]} << 2);
              items_[--starts_[entry_cells_[--e]]] =
                  static_cast<std::uint32_t>(a) | (low << kRankBits);
            }
          }
        }
      }
    });
  }

  // 4. Candidates and the exact test.
  grid.starts = starts_.data();
  grid.hashed = static_cast<std::uint32_t>(hashed_.size());
  if (!table_.empty()) {
    grid.slots = table_.data();
    grid.mask = table_.size() - 1;
    grid.shift = 64 - std::countr_zero(table_.size());
  }
  PairSink sink{found_};
  if (basic) {
    emit_basic(grid, hashed_, ranked_.data(), order_.data(), margin, partners_, sink);
  } else {
    emit_bounding_box(starts_.data(), static_cast<std::uint32_t>(starts_.size() - 1), items_.data(),
                      ranked_.data(), order_.data(), margin, sink);
  }

  // 5. Sorted output.
  sort_pairs(found_, sink.count, n, starts_, pairs);
}

}  // namespace cleave::physics
