#pragma once
// World::stress_sums, stress_sum, stress_sum_diagonals and forces_on against their
// definition: a walk over the contact records and the bonds, compared to the bit (tests of
// the bonds and of periodic cells).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstring>
#include <vector>

#include "eigen_reference.hpp"
#include "physics/dem/world.hpp"

namespace cleave::test {

using physics::Bond;
using physics::ContactRecord;
using physics::World;
using physics::StepListener;
using physics::StepNeeds;

/// Eq. 2.17's sums as a walk over the contact records and the bonds (the reference the
/// world's sums by body must give to the bit): B's lever from its image, A's force negated.
inline std::vector<Eigen::Matrix3d> stress_sums_from_records(const World& world) {
  std::vector<Eigen::Matrix3d> sum(world.slot_states().size(), Eigen::Matrix3d::Zero());
  const auto& x = world.slot_states();
  for (const ContactRecord& c : world.contacts()) {
    sum[c.b] += (c.point - c.shift - x[c.b].x) * c.force.transpose();
    if (!c.wall) sum[c.a] += (c.point - x[c.a].x) * (-c.force).transpose();
  }
  for (const Bond& bd : world.bonds()) {
    if (!bd.intact()) continue;
    sum[bd.b] += (bd.point - bd.shift - x[bd.b].x) * bd.force.transpose();
    sum[bd.a] += (bd.point - x[bd.a].x) * (-bd.force).transpose();
  }
  return sum;
}

/// The same walk, listing the forces on one slot.
inline std::vector<World::AppliedForce> forces_from_records(const World& world, std::uint32_t slot) {
  std::vector<World::AppliedForce> out;
  for (const ContactRecord& c : world.contacts()) {
    if (c.b == slot) out.push_back({c.point - c.shift, c.force});
    if (!c.wall && c.a == slot) out.push_back({c.point, -c.force});
  }
  for (const Bond& bd : world.bonds()) {
    if (!bd.intact()) continue;
    if (bd.b == slot) out.push_back({bd.point - bd.shift, bd.force});
    if (bd.a == slot) out.push_back({bd.point, -bd.force});
  }
  return out;
}

/// Asks every step it is registered for to sum eq. 2.17's diagonals with the forces.
struct SumsWithTheForces final : StepListener {
  [[nodiscard]] StepNeeds needs(const World&) const override { return {.stress_sums = true}; }
};

inline bool same_bits(const Eigen::Matrix3d& p, const Eigen::Matrix3d& q) {
  return std::memcmp(p.data(), q.data(), sizeof(double) * 9) == 0;
}

/// Every slot's sums and forces from the world's lists against the records' walk.
inline void expect_sums_match_the_records(const World& world, const char* when) {
  // The diagonals first: after a step a listener asked for the sums they are the ones summed with the
  // forces (stress_sums() does not touch them).
  const std::vector<Eigen::Vector3d> diagonals = world.stress_sum_diagonals();
  const std::vector<Eigen::Matrix3d> sums = world.stress_sums();
  const std::vector<Eigen::Matrix3d> reference = stress_sums_from_records(world);
  ASSERT_EQ(sums.size(), reference.size()) << when;
  std::size_t differing = 0, loaded = 0, forces_differing = 0;
  std::vector<World::AppliedForce> forces;
  for (std::uint32_t i = 0; i < sums.size(); ++i) {
    if (!world.slot_infos()[i].alive) continue;
    differing += !same_bits(sums[i], reference[i]);
    differing += !same_bits(world.stress_sum(i), reference[i]);
    differing += !same_bits(diagonals[i], Eigen::Vector3d(reference[i].diagonal()));
    loaded += !reference[i].isZero(0.0);
    world.forces_on(i, forces);
    const std::vector<World::AppliedForce> expected = forces_from_records(world, i);
    if (forces.size() != expected.size()) {
      ++forces_differing;
      continue;
    }
    for (std::size_t k = 0; k < forces.size(); ++k) {
      if (!same_bits(forces[k].point, expected[k].point) || !same_bits(forces[k].force, expected[k].force)) {
        ++forces_differing;
        break;
      }
    }
  }
  EXPECT_EQ(differing, 0u) << when;
  EXPECT_EQ(forces_differing, 0u) << when;
  EXPECT_GT(loaded, sums.size() / 2) << when;
}

}  // namespace cleave::test
