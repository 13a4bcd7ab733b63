#pragma once
/// \file
/// The fracture tests of sec. 7 of Chen et al. 2020 (seed 002) on the cubic lattice: double
/// cantilever beam (DCB, mode I), end-notched flexure (ENF, mode II) and mixed-mode bending
/// (MMB), each a beam of height 2h split by a weak mid-plane with an initial notch a0, loaded
/// in displacement control with the ramp of eq. 56. No I/O: the rig steps the lattice and
/// reads the load P and deflection Delta that the closed forms (physics/beam_theory) predict.
///
/// Set-ups (x along the beam, z up; lines of bodies run across the breadth):
/// - DCB: the top and bottom lines of the left end are pulled apart at v each (Delta is their
///   opening, P the mean of their reactions); the right-end cross-section is clamped. The
///   weak plane runs `length` from the left end, then (intact_length > 0) the beam goes on
///   uncracked to the clamp, so that a fully split arm is a cantilever rooted in elastic
///   material (stage III of eq. 61). The notch runs a0 from the load line; the analytic
///   length L is the distance from the load line to the last column of the weak plane.
/// - ENF: the bottom lines at both ends rest on supports (z held; the left one also in x);
///   the top line at mid-span is pushed down at v (Delta is its travel, P its reaction); the
///   notch runs a0 from the left support; the analytic half span L is support to load line.
/// - MMB: supports as ENF; a rigid lever (Reeder & Crews) tied to the top line at the left
///   end and to the top line at mid-span, loaded at arm C beyond mid-span (eq. 67 gives C
///   from the mode mix). The lever's load point moves down at v; its one free rotation is
///   integrated with the tied bodies' inertia, so the end and mid-span forces take the
///   lever's ratio by themselves (the paper ties both points to the lever too). Delta is the
///   opening at the left end (eq. 68), P the lever's load.

#include <cstdint>
#include <limits>
#include <vector>

#include "validation/beam_theory.hpp"
#include "physics/lattice/cubic_lattice.hpp"

namespace cleave::physics {

struct BeamRigDef {
  BeamTestKind kind = BeamTestKind::dcb;
  double length = 0.0;         ///< specimen length (m): DCB L, ENF/MMB 2L
  double breadth = 0.0;        ///< B (m)
  double height = 0.0;         ///< 2h (m)
  double initial_crack = 0.0;  ///< a0 (m), from the load line (DCB, MMB) or support (ENF)
  double radius = 0.0;         ///< r (m): bodies are cubes of side 2r
  /// DCB: uncracked beam beyond the weak plane's end (m), clamped at its far end; 0 clamps
  /// the last column of the weak plane itself. Corrected beam theory's stage III (eq. 61,
  /// a = L + chi_I h) has the split arms rooted in elastic material, not in a rigid clamp,
  /// and a crack cannot run into a clamp: the clamped section's links never open.
  double intact_length = 0.0;
  double mode_mix = 0.5;       ///< MMB: beta = G_II / G_T
  double link_bending = 1.0;   ///< CubicLatticeDef::link_bending (0: the paper's lattice)
  bool tiled_areas = true;     ///< CubicLatticeDef::tiled_areas (false: eq. 10's areas as they stand)
  LatticeMaterial material;
  double g_Ic = 0.0, g_IIc = 0.0;  ///< for the closed forms (the lattice uses material.g_c)
  double velocity = 0.0;       ///< v0 (m/s), eq. 56
  double ramp_time = 0.0;      ///< t0 (s), eq. 56
  double global_damping = 0.0;  ///< c (1/s)
  double dt_safety = 0.9;      ///< fraction of the critical time step
};

/// What the rig reads after a step.
struct BeamReading {
  std::uint64_t step = 0;
  double time = 0.0;
  double delta = 0.0;        ///< Delta (m): its mean over the load window, as the load's
  double load = 0.0;         ///< P (N): its mean over the steps since the last load window began
  double load_instant = 0.0;  ///< P (N) at this step alone
  double delta_instant = 0.0;  ///< Delta (m) at this step alone
  double crack = 0.0;        ///< a: decohered crack length from the load line / support (m)
  double process_zone = 0.0;  ///< a plus the cohesive zone ahead of it (m)
  double kinetic = 0.0;      ///< J
  double external_work = 0.0;  ///< J
};

class BeamTestRig {
 public:
  explicit BeamTestRig(const BeamRigDef& def);

  /// The closed-form test this rig realises (geometry as built: L and a0 between lines of
  /// body centres, B' = B - 2r).
  [[nodiscard]] const BeamTest& analytic() const { return analytic_; }
  [[nodiscard]] const CubicLattice& lattice() const { return lattice_; }
  [[nodiscard]] double time_step() const { return dt_; }
  [[nodiscard]] double lever_arm() const { return analytic_.C; }

  void step();
  [[nodiscard]] std::uint64_t steps() const { return step_; }
  /// The load, deflection, crack and energies now (loops over all links: not every step).
  /// Its load is the mean over the steps since restart_load_window() (the impulse the grips
  /// passed on, over the time): a load cell's average over its sampling interval. The
  /// instantaneous force holds the arms' ringing at ~10^5-10^6 Hz; read once per thousands of
  /// steps it aliases into point-to-point jumps of several per cent that a quasi-static curve
  /// does not have. Delta is averaged over the same steps, so that a load proportional to
  /// Delta stays so (the window's mean load belongs to its mean Delta, half a window back).
  /// With no step in the window both are the instantaneous ones.
  [[nodiscard]] BeamReading reading() const;
  /// Begins a new load window (call after each reading that is kept).
  void restart_load_window() { load_impulse_ = delta_integral_ = load_window_ = 0.0; }

 private:
  std::vector<int> line(int ix, int iz) const;  ///< the bodies across the breadth at (ix, iz)
  double ramp(double t) const;
  double sum_fz(const std::vector<int>& bodies) const;
  double mean_z(const std::vector<int>& bodies) const;
  double instant_load() const;   ///< P now, from the forces on the driven bodies
  double instant_delta() const;  ///< Delta now, from the driven bodies' positions

  BeamRigDef def_;
  CubicLattice lattice_;
  BeamTest analytic_;
  double dt_ = 0.0;
  std::uint64_t step_ = 0;
  double time_ = 0.0;
  /// The load window: integrals of P dt and Delta dt, and its time (s).
  double load_impulse_ = 0.0, delta_integral_ = 0.0, load_window_ = 0.0;
  double x_origin_ = 0.0;  ///< x of the load line (DCB, MMB) or left support (ENF)
  std::vector<int> top_, bottom_;        // DCB: load lines; ENF: load line (top)
  std::vector<int> end_, mid_;           // MMB: tied lines
  double top_z0_ = 0.0, bottom_z0_ = 0.0, end_z0_ = 0.0;
  // MMB lever: rotation rate about the load point, inertia, and the load point's travel.
  double lever_rate_ = 0.0, lever_inertia_ = 0.0, lever_span_ = 0.0;
};

/// How far a measured curve lies from the closed form over one stage.
struct StageErrors {
  int stage = 0;
  double from = 0.0, to = 0.0;  ///< the deflections compared (m)
  int points = 0;
  double mean_error = 0.0, max_error = 0.0;  ///< relative load errors |P - P_cf| / P_cf
  /// The split stage (split_stage) only, else NaN: the slope P / Delta of the line through
  /// the origin fitted to the measured points (least squares), and its relative error
  /// against 1 / split_compliance.
  double slope = std::numeric_limits<double>::quiet_NaN();
  double slope_error = std::numeric_limits<double>::quiet_NaN();
};
/// Compares the measured loads with analytic_load over the stage's deflection range (from
/// stage_range), leaving out `margin` of the range at either end (the corners of LEFM that a
/// cohesive zone rounds off; an open-ended stage loses it at its start only).
/// The split stage (DCB III, ENF IV) is instead the measured points at which the crack has
/// reached the end of the weak plane, whenever that happened, against P = Delta /
/// split_compliance, and their slope; none if it never got there. Reached means: fully
/// decohered to within one arm thickness h of the end (crack >= split_crack - h), the
/// length scale below which beam theory does not place a crack tip (its corrections chi h
/// are of that size). The DCB needs the allowance: near the intact beam the opening of an
/// arrested tip falls to zero, so the last links stay cohesive until the load is far higher
/// (their share of the load fades as it grows).
StageErrors compare_with_closed_form(const BeamTest& test, const std::vector<BeamReading>& curve,
                                     int stage, double margin);

/// A lattice definition (without loads) for a rig definition: the grid that fills the beam,
/// the weak mid-plane and the notch.
CubicLatticeDef beam_lattice(const BeamRigDef& def);

/// The closed-form test that the rig for `def` realises (BeamTestRig::analytic), without
/// building its lattice: L and a0 between lines of body centres, B' = B - 2r.
BeamTest beam_analytic(const BeamRigDef& def);

}  // namespace cleave::physics
