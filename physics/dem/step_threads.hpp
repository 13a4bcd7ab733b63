#pragma once
/// \file
/// How the step's loops share out their work over OpenMP threads so that every result is
/// the same for any thread count (internal to physics/dem's step).

#include <cstddef>
#include <cstdint>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace cleave::physics::threads {

/// Loops shorter than this run on one thread: for small worlds the cost of waking threads
/// every step exceeds the work (and oversubscribed cores make it far worse).
inline constexpr std::ptrdiff_t kParallelMin = 512;

/// The contiguous block [begin, end) of n items that the calling thread takes, split over
/// the threads actually running (OpenMP may give fewer than asked): blocks follow thread
/// order, so joining them in order keeps the items' order.
struct Block {
  std::size_t thread, begin, end;
};
inline Block thread_block(std::size_t n) {
#ifdef _OPENMP
  const auto t = static_cast<std::size_t>(omp_get_thread_num());
  const auto teams = static_cast<std::size_t>(omp_get_num_threads());
#else
  const std::size_t t = 0, teams = 1;
#endif
  return {t, n * t / teams, n * (t + 1) / teams};
}

/// The threads a loop asks for: `wanted`, or OpenMP's default when 0.
inline int thread_count(int wanted) {
#ifdef _OPENMP
  return wanted > 0 ? wanted : omp_get_max_threads();
#else
  (void)wanted;
  return 1;
#endif
}

/// Items (pairs, bonds) listed by body: `ends(k)` gives item k's two slots (A, B); body i's
/// entries are list[start[i] .. start[i + 1]), each (k << 1) | (1 if it is the item's B), in
/// ascending k (a counting sort taking the items in order).
template <class Ends>
void list_by_body(std::size_t slots, std::size_t items, Ends&& ends,
                  std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& list) {
  start.assign(slots + 1, 0);
  for (std::size_t k = 0; k < items; ++k) {
    const auto [a, b] = ends(k);
    ++start[a + 1];
    ++start[b + 1];
  }
  for (std::size_t i = 0; i < slots; ++i) start[i + 1] += start[i];
  list.resize(start.back());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < items; ++k) {
    const auto [a, b] = ends(k);
    const auto code = static_cast<std::uint32_t>(k << 1);
    list[fill[a]++] = code;
    list[fill[b]++] = code | 1u;
  }
}

}  // namespace cleave::physics::threads
