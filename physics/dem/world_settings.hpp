#pragma once
/// \file
/// What a World is made with: gravity, the time step, the contact parameters and the
/// choices of the run (threads, skins, damping).

#include <Eigen/Dense>

#include "physics/dem/contact_law.hpp"
#include "physics/dem/neighbour_search.hpp"

namespace cleave::physics {

struct WorldSettings {
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.80665);  ///< m/s^2
  double dt = 1e-6;                                               ///< time step, s
  ContactParams particle_particle;  ///< table 2.3, particle-particle set
  ContactParams particle_wall;      ///< table 2.3, particle-wall set
  SearchMethod search = SearchMethod::bounding_box;
  /// Threads for the per-body and per-contact loops (0: OpenMP's default, i.e. all cores).
  /// Results are bit-identical for any count: work is split into ordered blocks and the
  /// forces are summed in contact order.
  int threads = 0;
  /// Verlet skin of the neighbour search, as a fraction of the smallest bounding radius:
  /// pairs are searched with this margin and reused until some body has moved more than
  /// half of it (0: search every step).
  double search_skin = 0.1;
  /// Local (non-viscous) damping of Cundall, as in PFC and Yade: every component of a
  /// body's force and torque is reduced by `local_damping` times its magnitude when it
  /// drives the motion and raised by as much when it resists it (0: none, 0.7: PFC's
  /// default for quasi-static loading). It removes kinetic energy without viscosity, so a
  /// slowly loaded specimen stays near equilibrium; it is not in the seed's model.
  double local_damping = 0.0;
  /// Skin of each pair's near-feature cache (narrow_phase.hpp), as a fraction of the sum of
  /// the pair's dilation radii: the features found within reach plus this skin are the only
  /// ones searched while the two bodies' motion since (a bound on how far any distance
  /// between them changed) stays under half of it (0: every pair searched in full every
  /// step). It changes speed only: results are bit-identical.
  double feature_skin = 0.5;
  /// Persistent contact manifolds (narrow_phase.hpp, ContactManifold), as a fraction of the
  /// sum of a pair's dilation radii: a touching pair's contacts, once found, are carried
  /// with the two bodies, without a search, while B's motion relative to A stays under half
  /// of it. 0 (the default): every pair is searched every step (exact, bit-identical for any
  /// feature_skin). Above 0 the contacts are an approximation whose error grows with it (its
  /// tests bound the force error); the manifolds are part of the saved state, so a restart
  /// carries on bit for bit.
  double manifold_tolerance = 0.0;
  /// Motion in the xy plane only: every free body's force along z and torque about x and y,
  /// and its momentum along z and angular momentum about x and y, are dropped before the
  /// kick, so that it keeps its z and turns about z alone (the
  /// blocked degrees of freedom of Yade's blockedDOFs = "zXY", the setting of PFC2D).
  /// For specimens one grain thick, whose bonds all sit at mid-thickness: a bond's bending
  /// stiffness (eq. 2.9 over the section of eq. 2.10) is all that holds such a grain against
  /// turning about an in-plane axis, and loaded slowly in compression the layer buckles out
  /// of its plane (USER_GUIDE, "Check that loading is quasi-static"). A choice of the run, like
  /// manifold_tolerance: a restart takes it from the settings it is given, not the file.
  bool in_plane = false;
};

}  // namespace cleave::physics
