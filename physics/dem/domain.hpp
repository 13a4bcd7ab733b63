#pragma once
/// \file
/// A domain decomposition's hooks into the World: several processes step one world, each
/// owning the bodies of its region (parallel::MpiDomain, over MPI).

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "physics/dem/exact_sum.hpp"

namespace cleave::physics {

class World;

/// What one process of a domain decomposition holds of each body slot: nothing current
/// (dormant), a copy of a body another process owns, kept for the contacts and bonds across
/// the boundary (ghost), or the body itself (owned: integrated here).
enum class Role : unsigned char { dormant, ghost, owned };

/// A domain decomposition: the world calls it around each force evaluation; everything else
/// stays the single-process code, restricted to the bodies a process holds. It moves state
/// between processes through World::exchange (exchange.hpp).
class Domain {
 public:
  virtual ~Domain() = default;
  /// Splits `world` (the same whole world on every process) and makes it step as this
  /// process's part (World::set_domain).
  virtual void attach(World& world) = 0;
  /// Before the contacts are found: the ghosts' states in; re-partitions when the search's
  /// skin is spent (then sets the roles anew).
  virtual void before_forces(World& world) = 0;
  /// After the forces: the walls' reactions and this step's bond breaks made the whole world's.
  virtual void after_forces(World& world) = 0;
  /// Every body's state (and every bond's and contact history's) on every process; with
  /// `contacts`, every process's contact records too (World::contacts, in one process's order).
  virtual void gather_all(World& world, bool contacts = false) = 0;

  // Readings of the whole world: every process calls them at the same point of the run.
  [[nodiscard]] virtual int rank() const = 0;
  [[nodiscard]] virtual int size() const = 0;
  virtual double sum(const ExactSum& part) = 0;  ///< exact: the same on any number of processes
  virtual double max(double part) = 0;
  virtual void max(std::span<double> parts) = 0;  ///< element by element, in place
  virtual std::uint64_t count(std::uint64_t part) = 0;
  virtual bool any(bool part) = 0;
  /// The text of the lowest process whose `mine` is set (empty if none).
  virtual std::string first(const std::optional<std::string>& mine) = 0;
  /// Every process's bytes, in process order.
  virtual std::vector<std::vector<char>> all_gather(const std::vector<char>& mine) = 0;
};

}  // namespace cleave::physics
