#pragma once

// Spatial domain decomposition over MPI (Open MPI): each process owns the bodies whose
// centroid lies in its region of space, keeps ghost copies of the bodies near its region,
// and steps the world restricted to them (physics::World's Domain hooks). mpi.h stays in
// mpi_domain.cpp.

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "physics/dem/world.hpp"

namespace cleave::physics {
class Exchange;
}

namespace cleave::parallel {

/// MPI_Init / MPI_Finalize around a program (one per process).
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
};

/// Started by mpirun/mpiexec (Open MPI, MPICH or PMI sets its variables).
bool launched_by_mpirun();

/// Recursive coordinate bisection: space cut, along the longest extent of the bodies in a
/// part, at the point that gives each side its share of the bodies for its share of the
/// processes. Each process's region is a box (open sides infinite).
class Bisection {
 public:
  struct Point {
    Eigen::Vector3d x;
    std::uint32_t slot;
  };
  Bisection() = default;
  Bisection(std::vector<Point> points, int parts);
  [[nodiscard]] int owner(const Eigen::Vector3d& x) const;
  [[nodiscard]] int parts() const { return static_cast<int>(lo_.size()); }
  /// Distance from x to part p's box (0 inside).
  [[nodiscard]] double distance(int p, const Eigen::Vector3d& x) const;
  [[nodiscard]] const Eigen::Vector3d& lo(int p) const { return lo_[p]; }
  [[nodiscard]] const Eigen::Vector3d& hi(int p) const { return hi_[p]; }

 private:
  struct Node {
    int axis = -1;  ///< -1: a leaf
    double at = 0.0;
    int left = -1, right = -1;  ///< children (node indices)
    int part = -1;              ///< a leaf's process
  };
  int build(std::vector<Point>& points, std::size_t first, std::size_t last, int first_part, int parts,
            Eigen::Vector3d lo, Eigen::Vector3d hi);
  std::vector<Node> nodes_;
  std::vector<Eigen::Vector3d> lo_, hi_;
};

/// What the decomposition did, for the benchmark and the run's log.
struct DomainStats {
  std::uint64_t exchanges = 0;       ///< ghost exchanges (one per force evaluation)
  std::uint64_t repartitions = 0;    ///< ownership and ghosts made anew (the skin was spent)
  std::uint64_t rebalances = 0;      ///< ... of which with new cuts (imbalance past the threshold)
  double rebalance_seconds = 0.0;    ///< time in those re-partitions, this process
  double communication_seconds = 0.0;  ///< time in MPI calls, this process
  std::uint64_t bytes_sent = 0;      ///< this process, every message
  std::uint64_t ghost_bytes = 0;     ///< ... of which in the ghost exchanges between re-partitions
  std::uint64_t migrated = 0;        ///< bodies this process handed to another
  std::size_t owned = 0, ghosts = 0;  ///< now
};

class MpiDomain final : public physics::Domain {
 public:
  /// `rebalance`: re-cut space when the most bodies a process owns exceeds this times the
  /// mean (checked at each re-partition).
  explicit MpiDomain(double rebalance = 1.2);

  /// Splits `world` (the same whole world on every process) and makes this process's part of
  /// it; the world then steps through this domain.
  void attach(physics::World& world) override;

  void before_forces(physics::World& world) override;
  void after_forces(physics::World& world) override;
  void gather_all(physics::World& world, bool contacts = false) override;
  [[nodiscard]] int rank() const override { return rank_; }
  [[nodiscard]] int size() const override { return size_; }
  double sum(const physics::ExactSum& part) override;
  double max(double part) override;
  void max(std::span<double> parts) override;
  std::uint64_t count(std::uint64_t part) override;
  bool any(bool part) override;
  std::string first(const std::optional<std::string>& mine) override;
  std::vector<std::vector<char>> all_gather(const std::vector<char>& mine) override;

  [[nodiscard]] DomainStats stats() const { return stats_; }
  /// Every process's stats, on every process (a collective call).
  [[nodiscard]] std::vector<DomainStats> all_stats();
  [[nodiscard]] const Bisection& cuts() const { return cuts_; }
  [[nodiscard]] double halo() const { return halo_; }

 private:
  void repartition(physics::World& world, bool first);
  /// New cuts when the most bodies a process owns exceed the threshold; whether it cut.
  bool recut(const physics::Exchange& ex);
  /// The owned bodies that left this region to their new owners (with their contact
  /// histories and bonds), those that came in; `roles` gains this process's owned bodies.
  void migrate(physics::Exchange& ex, std::vector<physics::Role>& roles);
  /// The owned bodies within the halo of other regions to those processes, and theirs here
  /// (`roles` gains the ghosts).
  void send_ghosts(physics::Exchange& ex, std::vector<physics::Role>& roles);
  void exchange_ghost_states(physics::World& world);
  std::vector<std::vector<char>> all_to_all(const std::vector<std::vector<char>>& out);

  int rank_ = 0, size_ = 1;
  double rebalance_ = 1.2;
  double skin_ = 0.0, halo_ = 0.0;
  Bisection cuts_;
  bool attached_ = false;
  std::vector<Eigen::Vector3d> anchor_;  // by slot: an owned body's centroid at the last re-partition
  std::vector<std::vector<std::uint32_t>> send_, recv_;  // by process: ghost slots sent / received
  std::vector<char> send_buffer_, recv_buffer_;  // the ghost exchange's
  DomainStats stats_;
};

}  // namespace cleave::parallel
