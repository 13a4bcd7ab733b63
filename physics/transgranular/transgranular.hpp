#pragma once
/// \file
/// The transgranular fracture algorithm of sec. 3.4 (seed 000), run between steps: for
/// every grain or fragment, its average stress (eq. 2.17, contacts and bonds) against the
/// hydrostatic gate (eq. 3.22); then, for each cleavage plane it may still break along,
/// the consistent tractions of each face from the contact forces on it (eq. 3.15), the
/// load the fragment behind the plane puts through the crack section (eqs 3.20-3.21), the
/// beam stresses and stress intensities of eqs 3.23-3.24 and the mixed-mode test of eq.
/// 3.25. A body whose test holds is cut along the plane with the largest left side of
/// eq. 3.25 (FractureBook::split).
///
/// Readings fixed here:
/// - A contact (or bond) acts on the face of the body its point lies nearest to (largest
///   signed distance to the face planes): with dilated polyhedra the contact point sits
///   just outside the face it presses on.
/// - The fragment under study is the side the crack plane's normal points away from; the
///   other side gives the same section load with the opposite sign (with the d'Alembert
///   terms too: the two fragments' m a and dH/dt sum to the body's).
/// - The d'Alembert terms (FractureParams::inertia) come from the state the check sees, after
///   the step: the fragment moves rigidly with its body, whose omega is the step's (from L)
///   and whose a_G = (sum F + m g) / m and alpha (Euler's equations in the principal frame,
///   alpha = I^-1 (tau - omega x I omega)) come from the contact and bond forces of the last
///   force evaluation, the very forces the faces carry, and gravity. Local damping and the
///   in-plane hold are not forces on any face, so they are left out of a_G and alpha (with
///   them the two sides of a plane would not balance); in an in-plane run the motion out of
///   the plane, which the run removes, is dropped. The fragment's mass properties are those
///   of the polyhedron that the posed contact faces, clipped by the plane, and the section
///   close (fragment_mass), at the body's density.

#include <cstdint>
#include <utility>
#include <vector>

#include "physics/transgranular/fracture_book.hpp"
#include "physics/transgranular/fracture_criterion.hpp"
#include "physics/dem/step_listener.hpp"
#include "physics/dem/world.hpp"

namespace cleave::physics {

/// What the check found for one body and one plane (for logs and tests).
struct CrackAssessment {
  BodyId id;
  int plane = -1;
  FractureResult result;
  BeamStresses stresses;
  /// The load the rest of the body puts on the fragment through the section (world): the
  /// force, and its moment about the section's centroid (crack_plane_load).
  Eigen::Vector3d section_force = Eigen::Vector3d::Zero();
  Eigen::Vector3d section_moment = Eigen::Vector3d::Zero();
};

/// Eqs 3.22-3.25 for body `id` and each of its candidate planes, from the contacts and
/// bonds of the last force evaluation.
std::vector<CrackAssessment> assess(const World& world, const FractureBook& book, BodyId id,
                                    const FractureParams& params,
                                    const std::vector<Eigen::Matrix3d>& stresses);

/// The mean stress of eq. 2.17 for a body of volume `volume` whose sum of lever (x) force
/// has diagonal `diagonal`: the trace over three of the symmetrised sum over 2V, to the bit
/// of the full matrix's (`Eigen::Matrix3d s = (S + S^T) / (2V); s.trace() / 3`), from the
/// three coefficients the trace reads (transgranular_step's gate, eq. 3.22, for every body).
double mean_stress_from_diagonal(const Eigen::Vector3d& diagonal, double volume);

/// One split with what triggered it.
struct TransgranularEvent {
  SplitEvent split;
  CrackAssessment cause;
};

/// Checks every live body once and splits those that fail (at most one cut per body per
/// call; pieces are checked on the next call). Returns the splits, in body order.
std::vector<TransgranularEvent> transgranular_step(World& world, FractureBook& book,
                                                   const FractureParams& params);

/// transgranular_step as a step listener: every `every` steps (unless held), after the step;
/// the steps it reads sum eq. 2.17's diagonals with their forces (StepNeeds::stress_sums).
/// The splits accumulate in `events` until the owner takes them.
class TransgranularCheck final : public StepListener {
 public:
  TransgranularCheck(FractureBook& book, FractureParams params, std::uint64_t every)
      : book_(book), params_(params), every_(every < 1 ? 1 : every) {}
  /// While held, no check runs (a stage's hold_cracks).
  void hold(bool held) { held_ = held; }
  [[nodiscard]] StepNeeds needs(const World& world) const override;
  void after_step(World& world) override;
  /// The splits since the last take, in the order they happened.
  std::vector<TransgranularEvent> take_events() { return std::exchange(events_, {}); }
  /// Wall-clock seconds spent in the checks.
  [[nodiscard]] double seconds() const { return seconds_; }

 private:
  FractureBook& book_;
  FractureParams params_;
  std::uint64_t every_;
  bool held_ = false;
  std::vector<TransgranularEvent> events_;
  double seconds_ = 0.0;
};

}  // namespace cleave::physics
