#pragma once
/// \file
/// The connective lattice model of Chen et al. 2020 (seed 002, sec. 2) with its cohesive crack
/// (sec. 3) and contact (sec. 4) stages: equal bodies on a regular cubic lattice, each linked
/// to its 6 first and 12 second neighbours by a normal and two shear springs (eqs 1-6).
///
/// Choices fixed here (the paper leaves them open):
/// - The bodies are cubes of side 2r that tile the specimen, not spheres. The springs do not
///   care (they join centres), but two things do: the mass density of the lattice is the
///   solid's (m = rho (2r)^3), and a crack face is flat. Spheres on a square lattice make a
///   crack face a bumpy sheet whose bumps stand 0.27 r high (a sphere resting in the hollow of
///   four); sliding faces must climb them, which locks the mode II faces of an ENF test that
///   LEFM lets slide freely. Cube faces slide flat.
/// - Free surfaces are compensated (our addition; the paper has none). A body on a free
///   surface has lost the links that would leave the specimen, so with eq. 3 alone a surface
///   layer is softer than the solid: a cantilever four bodies thick bends 30% more than beam
///   theory says (two bodies thick: 55%), which would put every stage-I slope of sec. 7 out of
///   reach. The links lying in a free surface get extra stiffness chosen so that a surface body
///   stores exactly the strain energy of its cell for every plane-stress strain of the surface
///   (eps_zz = -nu/(1-nu)(eps_xx + eps_yy): the state a free surface is in), by the same
///   Cauchy-Born bookkeeping that gives eq. 3: see surface_compensation(). The crack faces of
///   the weak plane are free surfaces too, in proportion to the damage of the links across it.
/// - Connective first-neighbour links also carry a bending spring (our addition, as the
///   parallel bond of the bonded-particle model): a couple -k_b theta on the relative rotation
///   theta of the two bodies normal to the link, k_b = E (2r)^3 / 12 = E I_cell / (2r). Springs
///   joining centres sample a strain gradient at the link midpoints only, so each cell loses
///   its own bending energy about its centre line, E (2r)^5 kappa^2 / 24 per cell (the
///   midpoint rule's error): a beam four cells thick bends about 10% more than beam theory
///   says even with the surfaces compensated. Under bending, neighbours along the beam turn
///   by kappa 2r relative to each other, so k_b stores exactly that lost energy; under any
///   homogeneous strain the bodies do not turn relative to each other and eq. 3 is untouched.
///   Links across the weak plane carry none: their law is the cohesive one alone.
/// - Third neighbours carry no spring (eq. 3 gives them zero stiffness), so they are not
///   linked at all.
/// - Cracks run only through the links that cross one weak plane (sec. 7: "cohesive elements
///   are pre-defined as a weak layer"); every other link stays connective for good. The
///   links across the plane before the notch tip start decohered (in contact).
/// - Decohered faces touch as cube faces: the overlap along the mean face normal enters the
///   Hertz law (eq. 34, with the spheres' r* = r/2) scaled by the overlapping fraction of the
///   two faces, and Mindlin's tangential spring (eq. 40) with a Coulomb cap (our addition).
///   A cube that comes in from the side, deeper than it overlaps sideways, touches by its
///   side face instead (the axis of least penetration), as a beam's end does when it slides
///   past the end of the beam below it. Each upper face is tested against the 5 x 5 lower
///   faces around the one nearest under it, found anew each step, so the halves of a split
///   beam keep touching however far they slide along each other.
/// - Integration is the central-difference (leapfrog) scheme of sec. 6 (eqs 48-55) with
///   mass-proportional global damping, semi-implicit: v+ = ((1 - c dt/2) v- + dt F/m) / (1 +
///   c dt/2). A cube's inertia is isotropic (I = m (2r)^2 / 6), so the spin needs no frame.
/// - Normal separations are the change of centre distance (not an integral of velocities);
///   shear separations are integrated from the relative velocity at the link's midpoint (eqs
///   50-55) and turned with the link each step.

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "physics/bonds/cohesive_law.hpp"
#include "physics/lattice/hertz_mindlin.hpp"

namespace cleave::physics {

/// Which shortening of a link across the weak plane meets the compressive penalty of sec. 3.2
/// (and never counts towards psi or lambda), the rest counting as separation like an opening.
/// - plane (the default, cleave's reading): only the plane closing is compression: the mean
///   opening of the two first-neighbour links across the plane at the link's ends, where
///   negative, projected on the link; the rest of its shortening separates. Sheared rigidly,
///   the plane peaks at sigma_c and parts with G_c, as it does opened (a first neighbour is
///   treated as by the paper). The ENF then peaks within 3 % of beam theory with the same
///   cohesive zone, where the paper's reading peaks 13 % above it (README).
/// - link: the paper's reading, the link's own shortening. A second neighbour crosses the
///   plane at 45 degrees, so a slip s of the plane shortens half of them by s / sqrt 2 while
///   the plane does not close: those struts stay connective, in compression, until their
///   shear part alone reaches dc. Sheared rigidly, the plane then carries 39 sigma_c and
///   takes 57 G_c to part (measured: tests/test_cubic_lattice.cpp).
enum class Compression : std::uint8_t { plane, link };

/// Elastic solid and cohesive crack parameters (SI).
struct LatticeMaterial {
  double young = 0.0;     ///< E (Pa)
  double poisson = 0.0;   ///< nu, in [0, 0.25) so that eq. 3's shear springs are not negative
  double density = 0.0;   ///< rho (kg/m^3)
  double sigma_c = 0.0;   ///< cohesive strength (Pa), T_n0 = T_s0 (text after eq. 13)
  double g_c = 0.0;       ///< critical energy release rate G_c (N/m), eq. 18
  double kappa = 1.0;     ///< Hertz penalty factor (eq. 34)
  double friction = 0.0;  ///< Coulomb cap on Mindlin's tangential force (0: frictionless)
  /// Where a weak-plane link turns cohesive (physics/bonds/cohesive_law.hpp): the paper's eq. 32,
  /// or cleave's traction rule that keeps the traction continuous in shear.
  Initiation initiation = Initiation::displacement;
  /// What a weak-plane link counts as compression (the penalty's, never towards damage).
  Compression compression = Compression::plane;
};

/// Eq. 3 and the effective areas (text after eq. 10) for first (1) and second (2) neighbours.
struct LatticeSprings {
  double kn1 = 0, ks1 = 0, area1 = 0;
  double kn2 = 0, ks2 = 0, area2 = 0;
};
LatticeSprings lattice_springs(double young, double poisson, double radius);

/// Eq. 10's areas scaled by one factor, 144 / (41 pi) = 1.118, so that the links joining a
/// bulk body to the next layer (one first neighbour, four second neighbours) share out the
/// cell face (2r)^2 between them: a crack plane then dissipates G_c per unit area (each link
/// opens through A G_c). With the paper's areas as they stand the links across a plane sum
/// to 0.894 of it: the plane's fracture energy is 0.894 G_c and a crack grows at
/// sqrt(0.894) = 0.946 of the load that eq. 60 gives. The ratio of first to second
/// neighbour area (9/8) is the paper's. (Under a uniaxial stress across the plane the links
/// still begin to soften before the bulk stress reaches sigma_c: the first neighbours at
/// 0.66 sigma_c, the second, whose slip counts fully in eq. 32's circle, at 0.57.)
LatticeSprings tiled_areas(LatticeSprings springs, double radius);

/// The stiffness added to a link lying in a free surface (see above): normal and shear, for a
/// link along an edge of the surface's cells (first neighbours) and for one along a diagonal
/// of them (second neighbours). Derivation, per body on a face of normal z and in units of
/// r^2: the missing up-links store, under in-plane strain with eps_zz = -b (e_xx + e_yy),
/// b = nu/(1-nu), and s = e_xx + e_yy, P = e_xx^2 + e_yy^2,
///   (kn2 + ks2) P + (kn1 b^2 + 2b(b-1) kn2 + 2b(b+1) ks2) s^2 + 4 ks2 e_xy^2,
/// and extra stiffness on the body's in-plane links (one edge link along x and one along y,
/// one diagonal of each orientation, counting halves) stores
///   2 dkn_e P + 2 dkn_d s^2 + (4 dks_e + 8 dkn_d) e_xy^2   (with dks_d = 0).
struct SurfaceCompensation {
  double kn_edge = 0, ks_edge = 0, kn_diagonal = 0, ks_diagonal = 0;
};
SurfaceCompensation surface_compensation(const LatticeSprings& s, double poisson);

/// The specimen: nx * ny * nz cubes of side 2r, the first centred at (r, r, r).
struct CubicLatticeDef {
  int nx = 0, ny = 0, nz = 0;
  double radius = 0.0;
  LatticeMaterial material;
  /// The weak plane lies between layers weak_layer - 1 and weak_layer (z index); links that
  /// cross it may crack. 0 or nz: no weak plane.
  int weak_layer = 0;
  /// Links across the weak plane whose midpoint lies before notch_x start decohered (the
  /// notch). A link whose midpoint lies at notch_x (within 1e-6 r, so that the rounding of
  /// r + a0 cannot decide) stays connective.
  double notch_x = 0.0;
  /// Links across the weak plane whose midpoint lies beyond weak_end_x (by more than 1e-6 r)
  /// are bulk links that never crack: the weak plane ends there (infinity: it runs through).
  double weak_end_x = std::numeric_limits<double>::infinity();
  double global_damping = 0.0;  ///< c (1/s) of the mass-proportional damping
  /// Bending springs of the connective first-neighbour links, as a multiple of E (2r)^3 / 12
  /// (see the file comment); 0 gives the paper's lattice of point springs alone.
  double link_bending = 1.0;
  /// Effective areas that tile the plane (see tiled_areas): true by default; false gives the
  /// paper's areas of eq. 10 as they stand.
  bool tiled_areas = true;
};

/// One link (eq. 1): bodies i < j, rest length, shear separation and its cohesive state.
struct LatticeLink {
  int i = 0, j = 0;
  std::uint8_t kind = 1;     ///< 1: first neighbour, 2: second neighbour
  bool breakable = false;    ///< crosses the weak plane
  double rest = 0.0;         ///< centre distance at rest
  double kn = 0.0, ks = 0.0;  ///< spring stiffnesses (eq. 3 plus outer-surface compensation)
  /// Compensation that a crack face earns as the links across the weak plane decohere
  /// (links lying in a face of the weak plane only), and the two bodies whose damage sets it.
  double face_kn = 0.0, face_ks = 0.0;
  double kb = 0.0;  ///< bending stiffness (N m / rad)
  CohesiveState state;
};

/// Energies of the current state (J).
struct LatticeEnergy {
  double kinetic = 0.0;   ///< translational + rotational
  double elastic = 0.0;   ///< stored in connective links (k delta^2 / 2)
};

class CubicLattice {
 public:
  explicit CubicLattice(const CubicLatticeDef& def);

  [[nodiscard]] int size() const { return static_cast<int>(x_.size()); }
  [[nodiscard]] int index(int ix, int iy, int iz) const { return ix + nx_ * (iy + ny_ * iz); }
  [[nodiscard]] const CubicLatticeDef& def() const { return def_; }
  [[nodiscard]] const LatticeSprings& springs() const { return springs_; }
  [[nodiscard]] double mass() const { return mass_; }

  /// The critical time step of the central-difference scheme, bounded from Gershgorin's
  /// theorem on the stiffness of the fullest-linked body (translation and rotation).
  [[nodiscard]] double critical_time_step() const;

  /// Axes of body b whose velocity is prescribed (bit 0: x, 1: y, 2: z; bit 3: the spin is
  /// held at zero); those components of the velocity are set by set_velocity and kept
  /// whatever the forces.
  void prescribe(int b, unsigned axes);
  void set_velocity(int b, int axis, double v) { v_[b][axis] = v; }

  /// One step of length dt (eqs 48-55): kick-drift with the forces of the last evaluation,
  /// then the forces at the new positions.
  void step(double dt);

  [[nodiscard]] const std::vector<Eigen::Vector3d>& positions() const { return x_; }
  [[nodiscard]] const std::vector<Eigen::Vector3d>& velocities() const { return v_; }
  [[nodiscard]] const std::vector<Eigen::Vector3d>& forces() const { return f_; }
  [[nodiscard]] const std::vector<Eigen::Vector3d>& rest_positions() const { return x0_; }
  /// The links, grouped by colour (see the private part): the order is not the grid's.
  [[nodiscard]] const std::vector<LatticeLink>& links() const { return links_; }

  [[nodiscard]] const std::vector<Eigen::Vector3d>& moments() const { return m_; }

  /// Adds the forces and moments of links k .. k + W - 1 (links()' order) onto their bodies
  /// and advances their shear and bending histories by dt (eqs 1-6, 27-29 and 50-55), the W
  /// links side by side (physics/simd.hpp; W = 1 or 4). For W = 4 the links share no body
  /// and none is breakable. step() calls it; it is public so that a test can hold its widths
  /// against each other.
  template <int W>
  void add_link_forces(int k, double dt);

  [[nodiscard]] LatticeEnergy energy() const;
  /// Half the elastic energy of body b's connective links (J): its share of the stored energy,
  /// which for a bulk body under a homogeneous strain is the strain energy of its cell.
  [[nodiscard]] double body_elastic_energy(int b) const;
  /// Work done so far by the prescribed velocities on the bodies (J): the energy put in.
  [[nodiscard]] double external_work() const { return external_work_; }
  /// Work dissipated by the global damping so far (J).
  [[nodiscard]] double damping_work() const { return damping_work_; }

  /// Counts of the weak-plane links by phase.
  struct PhaseCounts {
    int connective = 0, cohesive = 0, contact = 0;
  };
  [[nodiscard]] PhaseCounts phase_counts() const;
  /// The largest x (midpoint) of a weak-plane link that is no longer connective; the crack
  /// tip including its cohesive zone. `contact_only`: of fully decohered links only.
  [[nodiscard]] double crack_front_x(bool contact_only) const;
  /// FNV-1a hash of positions, velocities and link states: equal runs give equal hashes.
  [[nodiscard]] std::uint64_t state_hash() const;

 private:
  void compute_forces(double dt);
  void face_contacts(double dt);
  /// The energy stored in link k if it is connective (J), else 0.
  [[nodiscard]] double link_elastic_energy(std::size_t k) const;

  CubicLatticeDef def_;
  int nx_, ny_, nz_;
  LatticeSprings springs_;
  CohesiveParams cohesive1_, cohesive2_;
  CohesiveLimits limits1_, limits2_;
  HertzMindlinParams hertz_;
  double mass_ = 0.0, inertia_ = 0.0;

  std::vector<Eigen::Vector3d> x0_, x_, v_, w_, f_, m_;
  std::vector<Eigen::Quaterniond> q_;
  std::vector<std::uint8_t> prescribed_;
  std::vector<LatticeLink> links_;
  // The step's hot data, link by link in links_'s order: the two bodies and the link's class
  // (its springs and rest length: a lattice has a few dozen distinct ones), and the integrated
  // shear separation and bending rotation: 12 + 48 bytes a link, where the step read and wrote
  // the whole 150-byte record and three per-link force buffers before: the loop was bound by
  // memory traffic (bench/bench_lattice.cpp).
  struct LinkClass {
    double rest = 0, kn = 0, ks = 0, face_kn = 0, face_ks = 0, kb = 0;
    std::uint8_t kind = 1;
    bool breakable = false, faced = false;
  };
  struct LinkEnds {
    int i = 0, j = 0, cls = 0;
  };
  std::vector<LinkClass> classes_;
  std::vector<LinkEnds> ends_;
  std::vector<Eigen::Vector3d> shear_, bend_;
  // Colours: links_[colour_start_[c], colour_start_[c + 1]) share no body, so one colour's
  // links add their forces straight onto both bodies from any number of threads, and each
  // body sums its links in colour order whatever the thread count (bit-identical runs). A
  // colour is one of the 9 link directions with i < j (3 first, then 6 second neighbours)
  // and the parity of i's cell along an axis on which the direction moves: 18 in all. Within
  // a colour the connective links come first, in the grid's order, then from
  // breakable_start_[c] the breakable ones (the order within a colour changes no sum).
  std::vector<int> colour_start_, breakable_start_;
  // Incident links of each body, CSR: link index * 2 + (1 if the body is j).
  std::vector<int> incident_start_, incident_;
  // Face contacts across the weak plane: body above, stencil slot (5 x 5 lower bodies around
  // the one nearest under it, contact_centre_, which follows the faces' slip).
  static constexpr int kStencil = 5;
  std::vector<HertzMindlinState> contact_state_;           // per upper body x 25
  std::vector<Eigen::Vector3d> contact_force_, contact_moment_down_;  // per slot, on the lower
  // Per upper body, bit s: slot s touched at this step (it has a force; a slot that does not
  // touch holds the zero state).
  std::vector<std::uint32_t> contact_live_;
  std::vector<std::array<int, 2>> contact_centre_;         // per upper body: (jx, jy) below
  std::vector<int> stencil_link_;  // per upper body x 25 offsets from its own (ix, iy)
  // Bodies next to the weak plane: how free each is (mean damage of its links across the
  // plane, 1 for decohered ones), by body index (0 elsewhere).
  std::vector<double> freedom_;
  std::vector<std::uint8_t> oriented_;     // bodies whose orientation is integrated
  std::vector<Eigen::Matrix3d> rotation_;  // face layers' rotations (lower, then upper)
  // The bodies next to the weak plane and, CSR, their links across it.
  std::vector<int> plane_bodies_, cross_start_, cross_links_;
  double external_work_ = 0.0, damping_work_ = 0.0;
  bool forces_current_ = false;
};

}  // namespace cleave::physics
