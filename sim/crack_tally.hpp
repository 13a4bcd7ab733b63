#pragma once
/// \file
/// The crack surfaces of a run as areas: intergranular cracks (broken bonds, each the
/// grain-boundary face it stood for) against transgranular ones (split sections, each its
/// exact cleavage section), and the transgranular share of both, by area and by count. The
/// dissertation's objective (seed 000, sec. 1.3) is how grain-boundary strength and
/// stiffness move a polycrystal between intergranular and transgranular failure; a count
/// weighs a small bond like a whole cleaved grain, an area does not.

#include <cstddef>
#include <map>
#include <optional>
#include <span>

#include "physics/dem/exact_sum.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "physics/transgranular/transgranular.hpp"

namespace cleave::sim {

/// Crack areas (m^2) and counts: the cracks so far, or those between two such snapshots.
struct CrackTotals {
  double intergranular_area = 0.0, transgranular_area = 0.0;
  std::size_t intergranular = 0, transgranular = 0;  ///< bonds broken, grains split

  /// T / (I + T) by area; nothing before the first crack (0/0). The intergranular
  /// fraction is one minus it (I / (I + T) to an ulp): the two sum to one exactly.
  [[nodiscard]] std::optional<double> transgranular_area_fraction() const;
  [[nodiscard]] std::optional<double> intergranular_area_fraction() const;
  /// The same by count.
  [[nodiscard]] std::optional<double> transgranular_count_fraction() const;
  [[nodiscard]] std::optional<double> intergranular_count_fraction() const;
  /// What opened after `before` (an earlier snapshot of the same run).
  [[nodiscard]] CrackTotals since(const CrackTotals& before) const;
};

void put_totals(physics::StateWriter& w, const CrackTotals& c);
CrackTotals get_totals(physics::StateReader& r);

/// The run's cracks so far, kept up to date after every step. Everything it holds follows
/// from the world (its bond breaks) and the fracture book (its pieces), so a run restarted
/// from a checkpoint makes it again (rebuild) and reads the same bits.
class CrackTally {
 public:
  /// Takes in the world's bond breaks since the last call: each adds its face area
  /// (BondBreak::face_area), summed exactly (physics::ExactSum: any order, same bits).
  void add_breaks(const physics::World& world);
  /// Takes in a step's splits: their grains' transgranular areas are summed anew from the
  /// book (FractureBook::grain_section_area, exact per grain and plane).
  void add_splits(const physics::World& world, const physics::FractureBook& book,
                  std::span<const physics::TransgranularEvent> events);
  /// From scratch: every break of `world`, every split grain of `book` (may be null), and
  /// `splits` splits so far.
  void rebuild(const physics::World& world, const physics::FractureBook* book, std::size_t splits);
  [[nodiscard]] CrackTotals totals() const;

 private:
  std::size_t breaks_seen_ = 0;
  physics::ExactSum intergranular_;
  std::map<int, double> grain_area_;  // transgranular area by grain
  std::size_t splits_ = 0;
  double intergranular_area_ = 0.0, transgranular_area_ = 0.0;  // the sums' values
  void sum_grains();
};

}  // namespace cleave::sim
