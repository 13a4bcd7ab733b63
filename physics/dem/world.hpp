#pragma once
/// \file
/// The world: shapes, bodies in contiguous arrays addressed by stable ids, and the step
/// orchestrator. `step()` runs named stages in order (see docs/ARCHITECTURE.md):
///   kick + drift -> forces (gravity, then contacts) -> kick.

#include <Eigen/Dense>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>


#include "physics/dem/body.hpp"
#include "physics/bonds/bond_law.hpp"
#include "physics/bonds/vec3.hpp"
#include "physics/dem/contact_law.hpp"
#include "physics/dem/exact_sum.hpp"
#include "physics/dem/narrow_phase.hpp"
#include "physics/dem/neighbour_search.hpp"
#include "physics/dem/periodic_cell.hpp"
#include "physics/dem/rigid_shape.hpp"
#include "physics/dem/step_listener.hpp"
#include "physics/dem/wall.hpp"

namespace cleave::parallel {
class MpiDomain;
}

namespace cleave::physics {

class StateWriter;
class StateReader;
class World;

/// What one process of a domain decomposition holds of each body slot: nothing current
/// (dormant), a copy of a body another process owns, kept for the contacts and bonds across
/// the boundary (ghost), or the body itself (owned: integrated here).
enum class Role : unsigned char { dormant, ghost, owned };

/// A domain decomposition: several processes step one world, each owning the bodies of its
/// region (parallel::MpiDomain, over MPI). The world calls it around each force evaluation;
/// everything else stays the single-process code, restricted to the bodies a process holds.
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
  /// of its plane (USER_GUIDE, "Quasi-static loading"). A choice of the run, like
  /// manifold_tolerance: a restart takes it from the settings it is given, not the file.
  bool in_plane = false;
};

/// A bond between two bodies (sec. 2.3.3): eqs 2.9-2.16 act at the bond point in parallel
/// with the contact law (quasi-parallel model). The bond point and normal are material:
/// each is stored in both bodies' principal frames at bonding and followed as they move.
struct alignas(64) Bond {
  // What the bond law reads every step fills the first two cache lines, what it writes the
  // next three (World::bond_forces walks 30,000 of them a step in a 10,000-grain disc, at
  // the machine's memory bandwidth: its bytes set its pace); the rest after.
  std::uint32_t a = 0, b = 0;                       ///< body slots, a < b
  BondSection section;   ///< eq. 2.10: radius = dilation radius of the smaller body
  Eigen::Vector3d arm_a = Eigen::Vector3d::Zero();  ///< bond point from A's centroid, A's frame
  Eigen::Vector3d arm_b = Eigen::Vector3d::Zero();  ///< bond point from B's centroid, B's frame
  Eigen::Vector3d normal_a = Eigen::Vector3d::UnitZ();  ///< normal (A towards B), A's frame
  Eigen::Vector3d normal_b = Eigen::Vector3d::UnitZ();  ///< the same in B's frame
  /// This bond's strengths over the [bond] table's (t_bn, t_bs; sigma_c of the cohesive law):
  /// 1 unless the scenario scatters them (bond_strength_factor).
  double strength = 1.0;
  // Last force evaluation (world): the bond point, normal, and the force and moment on B;
  // from the third line (then the bonded-particle state: three lines written a step).
  alignas(64) Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  BondState state;  ///< its bonded-particle fields first (the cohesive history last)
  /// In a periodic cell, the image of B the bond joins A to: B acts from x_B + H image
  /// (World::cell), `shift` = H image as of the last evaluation. Zero without a cell (the
  /// bond law then reads a zero of its own, not this line).
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  // Read on a break, a split, a periodic image's change, or by the other laws.
  Eigen::Vector3i image = Eigen::Vector3i::Zero();  ///< B's image (see `shift`)
  BondFailure failure = BondFailure::none;  ///< the mode it broke in
  double broken_at = -1.0;                   ///< simulated time of the break, s
  /// The physical overlap of each touching feature pair at bonding (end of 2.3.3): later
  /// overlaps of the same features count from it, so the bonded assembly starts stress-free.
  /// Kept after the bond breaks, so a broken bond does not spring apart.
  struct Overlap {
    std::uint32_t fa, fb;  ///< kAnyFeature for both: any feature pair (after a split)
    double overlap;
  };
  static constexpr std::uint32_t kAnyFeature = 0xFFFFFFFFu;
  std::vector<Overlap> initial;
  /// The gap the two grains' thermal strain has opened at the bond along its normal since
  /// bonding (m; negative when they have grown into each other). The pair's contacts count
  /// their overlap from it as well, since the grains' shapes keep their reference size.
  double thermal_gap = 0.0;
  /// Heat conduction's transmission surface S_t (m^2): the area of the two grains' touching
  /// faces at bonding (the polygon of the contact points), the section's where they touch
  /// at an edge or a corner.
  double transmission = 0.0;
  /// The beam law's beam (BondLaw::beam): its ends (the centroids at bonding, moved to a
  /// piece's frame when a grain splits), its axis (A towards B) and a direction across it,
  /// each in A's and in B's principal frame, and its rest length L_m (which follows the
  /// grains' thermal expansion). Unused by the other laws.
  struct Beam {
    Eigen::Vector3d end_a = Eigen::Vector3d::Zero(), end_b = Eigen::Vector3d::Zero();
    Eigen::Vector3d axis_a = Eigen::Vector3d::UnitX(), axis_b = Eigen::Vector3d::UnitX();
    Eigen::Vector3d across_a = Eigen::Vector3d::UnitY(), across_b = Eigen::Vector3d::UnitY();
    double rest_length = 0.0;
  };
  Beam beam;
  [[nodiscard]] bool intact() const { return !state.broken; }
};

/// One bond failure (eq. 2.16), as logged.
struct BondBreak {
  double time = 0.0;
  std::uint64_t step = 0;
  std::size_t bond = 0;  ///< index into World::bonds()
  std::uint32_t a = 0, b = 0;
  int grain_a = -1, grain_b = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  BondFailure mode = BondFailure::none;
  BondState loads;  ///< the bond's forces and moments when it broke
};

/// One piece a body breaks into (chapter 3): a registered shape placed in the parent's
/// principal frame. `fragment_placement` computes the placement from the two shapes.
struct Fragment {
  std::uint32_t shape = 0;                               ///< World shape index
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();      ///< its centroid, parent's frame
  Eigen::Quaterniond turn = Eigen::Quaterniond::Identity();  ///< its frame -> parent's frame
};

/// Where piece `piece` (cut from `parent`'s exact shape, in the same shape coordinates)
/// sits in the parent's principal frame.
Fragment fragment_placement(const RigidShape& parent, const RigidShape& piece, std::uint32_t shape);

/// Intact bonds and broken ones by mode.
struct BondCounts {
  std::size_t intact = 0, tension = 0, shear = 0, bending = 0, torsion = 0;
  [[nodiscard]] std::size_t broken() const { return tension + shear + bending + torsion; }
};

/// One contact of the last step, for output and tests.
struct ContactRecord {
  std::uint32_t a = 0;          ///< body slot of A, or wall index when `wall` is set
  std::uint32_t b = 0;          ///< body slot of B
  bool wall = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< from A towards B
  double overlap = 0.0;  ///< beyond the overlap stored at bonding or a split (raw otherwise)
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< on B
  /// In a periodic cell, where B's image sits: B acts from x_B + shift, so its lever arm is
  /// point - shift - x_B (zero without a cell, and for walls).
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
};

/// The parts of World::step that World::set_timing clocks, in the order a step runs them.
enum class StepPhase : unsigned char {
  kick_drift,    ///< first half kick and drift (and a periodic cell's deformation)
  poses,         ///< bodies posed, walls in reach, the search's staleness test
  pair_search,   ///< the neighbour search, when the skin is used up
  plan,          ///< manifolds: which pairs carry their contacts, which bodies need vertices
  narrow,        ///< the narrow phase (or carried contacts), pair by pair
  walls,         ///< wall contacts, the contact lists joined
  contact_law,   ///< eqs 2.3-2.8 on every contact
  contact_sums,  ///< contact forces and torques summed onto the bodies
  bond_law,      ///< eqs 2.9-2.16 on every bond (and the breaks logged)
  bond_sums,     ///< bond forces and torques summed onto the bodies
  damping,       ///< stress-criterion breaks, in-plane hold, local damping, domain exchange
  closing_kick,  ///< second half kick, heat conduction
};
inline constexpr std::size_t kStepPhases = 12;
/// Lower-case name of a phase ("narrow", "bond_law", ...).
const char* to_string(StepPhase phase);

/// Wall-clock seconds spent in each part of World::step while timing was on (Yade's
/// timing.stats(), for one world): `seconds[phase]`, and the steps they cover.
struct StepTimings {
  double seconds[kStepPhases] = {};
  std::uint64_t steps = 0;
  [[nodiscard]] double total() const {
    double t = 0.0;
    for (double s : seconds) t += s;
    return t;
  }
};

class World {
 public:
  explicit World(WorldSettings settings = {});

  /// Registers a shape; bodies refer to it by the returned index.
  std::uint32_t add_shape(RigidShape shape);
  [[nodiscard]] const RigidShape& shape(std::uint32_t index) const { return shapes_[index]; }
  [[nodiscard]] std::size_t shape_count() const { return shapes_.size(); }

  /// Adds a body of `shape` with density `rho` (kg/m^3), centroid at `x`, principal frame
  /// turned to world by `q`, velocity `v` and angular velocity `w` (world).
  BodyId add_body(std::uint32_t shape, double rho, const Eigen::Vector3d& x,
                  const Eigen::Quaterniond& q, const Eigen::Vector3d& v = Eigen::Vector3d::Zero(),
                  const Eigen::Vector3d& w = Eigen::Vector3d::Zero(), int grain_id = -1);
  /// Removes a body; its id (and any copy of it) becomes invalid.
  void remove_body(BodyId id);
  /// Replaces a body by the pieces it breaks into (between steps). Each piece moves with
  /// the parent's rigid velocity field, v + w x r, and spins with w, so that mass, linear
  /// momentum and angular momentum are kept (exactly, up to round-off, when the pieces'
  /// mass properties add up to the parent's). Bonds of the parent go to the piece that
  /// holds the bond point (the one whose dilated shape it is deepest inside); their overlaps
  /// stored at bonding count for any feature pair of the new piece. Returns the new ids in
  /// the order of `pieces`; the parent's id becomes invalid.
  std::vector<BodyId> split_body(BodyId parent, const std::vector<Fragment>& pieces);
  [[nodiscard]] bool contains(BodyId id) const;
  [[nodiscard]] std::size_t body_count() const { return live_; }

  /// Access by id; throws std::out_of_range for a stale or invalid id.
  [[nodiscard]] const BodyState& state(BodyId id) const;
  [[nodiscard]] BodyState& state(BodyId id);
  [[nodiscard]] const BodyInfo& info(BodyId id) const;
  /// Every slot's state and record, free slots included (their BodyInfo::alive is false):
  /// for readers that look at all bodies at once without copying (the Python module).
  /// The vectors move when a split adds slots.
  [[nodiscard]] const std::vector<BodyState>& slot_states() const { return states_; }
  [[nodiscard]] const std::vector<BodyInfo>& slot_infos() const { return infos_; }
  /// The body in a slot (as contacts and bonds name them); throws std::out_of_range when no
  /// live body is there.
  [[nodiscard]] BodyId id_at(std::uint32_t slot) const;
  /// Sets a body's angular velocity (world), i.e. its angular momentum L = R I R^T w.
  void set_angular_velocity(BodyId id, const Eigen::Vector3d& w);
  /// A fixed body keeps its velocity and angular momentum whatever the forces (a prescribed
  /// motion, like PFC's "fix velocity" or Yade's blocked DOFs); forces on it are still
  /// summed, so they read as the reaction.
  void set_fixed(BodyId id, bool fixed);

  /// Bond initialisation (end of sec. 2.3.3): every pair of bodies whose dilated surfaces
  /// are within `distance` (m) of each other gets a bond with parameters `params`, at the
  /// mean of the pair's contact points, with the pair's mean normal; the overlaps at this
  /// moment are stored so that the assembly starts stress-free; velocities, contact
  /// histories, forces and moments are reset. Walls are never bonded. Returns the number
  /// of bonds made; throws std::logic_error when bonds already exist.
  std::size_t initialise_bonds(const BondParams& params, double distance);
  /// Sets bond k's strength factor (Bond::strength, > 0), e.g. drawn by bond_strength_factor.
  void set_bond_strength(std::size_t k, double factor);
  [[nodiscard]] const std::vector<Bond>& bonds() const { return bonds_; }
  [[nodiscard]] BondCounts bond_counts() const;
  /// While held, no intact bond breaks, whatever its load (a stage's hold_cracks: an elastic
  /// probe of a cracked specimen). Not kept in checkpoints: the stage sets it.
  void hold_bonds(bool held) { bonds_held_ = held; }
  /// Every bond failure so far, in the order they happened.
  [[nodiscard]] const std::vector<BondBreak>& bond_breaks() const { return breaks_; }

  /// Thermal expansion (seed 003: "l0(T) = l0(T0) + alpha (T - T0)", generalised to a tensor
  /// per grain). `alpha_world` is the body's expansion tensor in world axes now (1/K,
  /// symmetric); it is kept in the body's frame and turns with it. Bonds follow the change
  /// of each end's temperature from the next force evaluation on.
  void set_expansion(BodyId id, const Eigen::Matrix3d& alpha_world);
  /// The body's expansion tensor in world axes.
  [[nodiscard]] Eigen::Matrix3d expansion(BodyId id) const;
  /// alpha_a across the c-axis and alpha_c along it (world), the tensor of a hexagonal or
  /// trigonal crystal: alpha_a I + (alpha_c - alpha_a) c c^T.
  [[nodiscard]] static Eigen::Matrix3d crystal_expansion(const Eigen::Vector3d& c_axis, double alpha_a,
                                                         double alpha_c);
  /// Sets one body's temperature (K), or every live body's.
  void set_temperature(BodyId id, double kelvin);
  void set_temperature(double kelvin);
  /// Changes every live, not held body's temperature by `change` (K), stopping at `target`
  /// (a body already past it stays where it is): one step of a uniform heating or cooling.
  void ramp_temperature(double change, double target);
  [[nodiscard]] double temperature(BodyId id) const;
  /// Every slot's temperature and expansion (free slots included).
  [[nodiscard]] const std::vector<BodyThermal>& slot_thermal() const { return thermal_; }
  /// Whether some body has a non-zero expansion tensor (thermal terms are computed).
  [[nodiscard]] bool thermal() const { return thermal_on_; }
  /// Heat conduction through the intact bonds (seed 003, after Terreros et al. 2013): each
  /// step every bond passes Q = lambda S_t (T_b - T_a) / d_ab dt from the hotter grain to the
  /// colder (S_t its transmission surface, d_ab the centroids' distance), and a grain's
  /// temperature changes by its heat over m c_p. `conductivity` lambda in W/(m K),
  /// `heat_capacity` c_p in J/(kg K); conductivity 0 turns it off (the default).
  void set_conduction(double conductivity, double heat_capacity);
  [[nodiscard]] double conductivity() const { return conductivity_; }
  [[nodiscard]] double heat_capacity() const { return heat_capacity_; }
  /// A held body keeps the temperature it is set to (a quenched or heated boundary):
  /// conduction does not change it.
  void set_temperature_held(BodyId id, bool held);

  /// Periodic boundaries (periodic_cell.hpp): from now on every body interacts with the
  /// nearest image of every other across the periodic faces (search, contacts, bonds made
  /// after this), and a body whose centroid leaves the cell across a periodic face enters
  /// it at the opposite one, velocities unchanged. The bodies are wrapped into the cell now.
  /// The cell must be wider along each periodic axis than twice a pair's reach (2 x the
  /// largest bounding radius plus the search skin, twice): the next step throws
  /// std::runtime_error otherwise. Walls do not take part in the periodicity.
  void set_cell(const PeriodicCell& cell);
  /// The cell, or null without one.
  [[nodiscard]] const PeriodicCell* cell() const { return cell_on_ ? &cell_ : nullptr; }
  /// The cell's velocity gradient L (1/s; PeriodicCell): from the next step on the cell and
  /// the bodies' centroids follow dH/dt = L H. Throws std::logic_error without a cell.
  void set_velocity_gradient(const Eigen::Matrix3d& l);
  /// Berendsen's pressure control for the cell: on each periodic axis whose set rate is
  /// zero, the cell also stretches at -sigma_ii / (modulus tau) each step (sigma from the
  /// last force evaluation), so its mean normal stresses relax to zero with time constant
  /// about tau when `modulus` is its stiffness along the axis. tau = 0: off. Not kept in
  /// checkpoints (a stage sets it).
  void set_stress_control(double modulus, double tau) {
    stress_modulus_ = modulus;
    stress_tau_ = tau;
  }
  /// The average stress in the cell from the last force evaluation (Pa, tension positive):
  /// (1/V) sum over body contacts and intact bonds of -(x_B + shift - x_A) (x) F_B, plus
  /// (point - x_B) (x) F_B for wall contacts, symmetrised; V the cell's volume. It is the
  /// sum of the bodies' Love-Weber stresses (eq. 2.17) times their volumes, over V.
  /// Throws std::logic_error without a cell.
  [[nodiscard]] Eigen::Matrix3d cell_stress() const;

  /// Adds a wall; returns its index.
  std::size_t add_wall(Wall wall);
  [[nodiscard]] const std::vector<Wall>& walls() const { return walls_; }
  [[nodiscard]] Wall& wall(std::size_t i) { return walls_.at(i); }

  /// Sets WorldSettings::feature_skin (speed only: results are bit-identical for any value).
  void set_feature_skin(double fraction) {
    settings_.feature_skin = fraction;
    near_.clear();
  }

  /// Advances the world by one time step.
  void step();
  /// Clocks the parts of each step from now on (true) or stops (false); switching on starts
  /// the sums from zero. Off by default: a clock read per part and step when on.
  void set_timing(bool on);
  [[nodiscard]] const StepTimings& timings() const { return timings_; }
  /// Contacts of the last force evaluation.
  /// (Made from the last evaluation on the first call after it: not for concurrent calls.)
  [[nodiscard]] const std::vector<ContactRecord>& contacts() const;
  /// Slots of live bodies in ascending order, with their ids.
  [[nodiscard]] std::vector<BodyId> body_ids() const;
  /// The averaged stress (eq. 2.17, grain_stress.hpp) of every body from the contacts of
  /// the last force evaluation, indexed by slot (zero for slots without a live body).
  [[nodiscard]] std::vector<Eigen::Matrix3d> body_stresses() const;
  /// One force of the last evaluation acting on a body at a point (world axes): a contact's
  /// or an intact bond's (B's point taken at its image in a periodic cell).
  struct AppliedForce {
    Eigen::Vector3d point, force;
  };
  /// Eq. 2.17's sum before it is symmetrised, for every body slot: the sum of
  /// (point - centroid) (x) force over the forces acting on the body, its contacts in the
  /// order contacts() lists them, then its intact bonds in bonds()' order (zero for slots
  /// without a live body). The same bits as a walk over contacts() and bonds(), without
  /// making the records: in parallel by body from the lists the step keeps.
  /// (Made on the first call after an evaluation: not for concurrent calls.)
  [[nodiscard]] const std::vector<Eigen::Matrix3d>& stress_sums() const;
  /// The same sum for one body (its own forces walked).
  [[nodiscard]] Eigen::Matrix3d stress_sum(std::uint32_t slot) const;
  /// The diagonals of stress_sums() (what a mean stress, the trace, reads), each the same
  /// bits: summed with the forces when the evaluation was asked for them
  /// (a listener's StepNeeds::stress_sums), otherwise by body. (Not for concurrent calls.)
  [[nodiscard]] const std::vector<Eigen::Vector3d>& stress_sum_diagonals() const;
  /// Registers `listener` (not owned; it must outlive its registration): each step calls
  /// its before_step, asks its needs, and calls its after_step (step_listener.hpp).
  void add_listener(StepListener* listener);
  void remove_listener(StepListener* listener);
  /// The forces acting on body `slot`, in stress_sums' order (cleared first).
  void forces_on(std::uint32_t slot, std::vector<AppliedForce>& out) const;
  [[nodiscard]] double time() const { return time_; }
  [[nodiscard]] std::uint64_t steps() const { return steps_; }
  [[nodiscard]] const WorldSettings& settings() const { return settings_; }

  /// Totals over live bodies (for tests and reports).
  [[nodiscard]] double kinetic_energy() const;
  [[nodiscard]] double potential_energy() const;  ///< -m g . x
  [[nodiscard]] Eigen::Vector3d linear_momentum() const;
  [[nodiscard]] Eigen::Vector3d angular_momentum() const;  ///< about the world origin

  /// Steps this world as one process of `domain` (null: the whole world here): only the
  /// owned bodies are integrated, only contacts and bonds with an owned body are evaluated.
  /// `roles` by slot (empty: all owned). Periodic cells, thermal expansion, manifolds and stress
  /// criteria are single-process for now (refused by the caller).
  void set_domain(Domain* domain, std::vector<Role> roles);
  void set_roles(std::vector<Role> roles);
  [[nodiscard]] Domain* domain() const { return domain_; }
  [[nodiscard]] Role role(std::uint32_t slot) const { return roles_.empty() ? Role::owned : roles_[slot]; }
  [[nodiscard]] bool owns(std::uint32_t slot) const { return role(slot) == Role::owned; }
  /// The contacts this process counts: body pairs whose A it owns, wall contacts whose body
  /// it owns (each contact of the whole world is counted by exactly one process).
  [[nodiscard]] std::size_t owned_contact_count() const;
  /// kinetic_energy() and potential_energy() over the owned bodies, exactly (ExactSum): one
  /// process's share of the whole world's.
  [[nodiscard]] ExactSum owned_kinetic_energy() const;
  [[nodiscard]] ExactSum owned_potential_energy() const;

  /// Checkpoints (world_state.cpp): everything the world carries from one step to the
  /// next, bit for bit: settings, shapes, bodies (with the forces of the last evaluation,
  /// which the next step's first half-kick uses), free slots, walls, bonds with their state
  /// and stored overlaps, bond breaks, contact histories and records, pair offsets, the
  /// neighbour search's Verlet list, time and step count. A world that loads what another
  /// saved steps on exactly as the other would have. `threads` is kept as this world's.
  void save_state(StateWriter& out) const;
  /// Replaces this world's state by a saved one; throws StateError on malformed data.
  void load_state(StateReader& in);
  /// FNV-1a hash of the physical state: time, steps, every live body's slot, generation
  /// and state, walls, bonds (state, failure), contact histories and pair offsets. Equal
  /// runs (and a run restarted from a checkpoint) end with equal hashes.
  [[nodiscard]] std::uint64_t state_hash() const;

 private:
  friend class parallel::MpiDomain;
  Domain* domain_ = nullptr;
  std::vector<Role> roles_;  // by slot; empty: every body owned
  std::size_t breaks_at_step_ = 0;  // breaks_.size() when this force evaluation began
  bool bodies_changed_ = false;     // a body came or went since the domain last partitioned
  struct WallForceAt {  // a wall contact's force and its place in the contact list
    std::uint32_t wall, slot;
    std::uint64_t order;
    Eigen::Vector3d force;
  };
  [[nodiscard]] std::vector<WallForceAt> wall_forces() const;
  void compute_forces();
  /// Every pair of `spheres` within `margin` of each other, as NeighbourSearch::find_pairs
  /// gives them; in a periodic cell through the faces too (each pair once, whichever image).
  void find_body_pairs(NeighbourSearch& search, const std::vector<BoundingSphere>& spheres, double margin,
                       std::vector<BodyPair>& pairs) const;
  /// Periodic cell: the centroids that left the cell go back in by a cell vector; bonds
  /// follow (their images change).
  void wrap_bodies();
  /// `shape` placed as `posed`, moved by `shift` (B's image in a periodic cell).
  static void shifted_copy(const PosedShape& posed, const Eigen::Vector3d& shift, PosedShape& out);
  /// `stale`: the pairs of the last neighbour search may miss some (a body has moved half
  /// the search skin since, or bodies came or went).
  void body_contacts(int threads, bool stale);
  void wall_contacts(int nt);
  void evaluate_and_apply(int threads);
  void sum_forces(int threads);
  void bond_forces(int threads);
  void apply_local_damping(int threads);
  /// WorldSettings::in_plane: drops each free body's force and momentum along z and its
  /// torque and angular momentum about x and y.
  void hold_in_plane();
  struct BondFailureAt;
  /// BondLaw::beam: bond k's beam (bond_law.hpp, beam_force) from its bodies' poses.
  void beam_bond(Bond& bd, const BodyState& sa, const BodyState& sb, const BondParams& params,
                 std::vector<BondFailureAt>& failed, std::size_t k);
  /// BondCriterion::rankine or hydrostatic: breaks the intact bonds whose grains' mean stress
  /// passes sigma_f (times the bond's strength factor), after this evaluation's forces.
  void break_by_stress();
  /// The overlap stored at bonding for features (fa, fb) of bonded pair (a, b), or 0;
  /// `cursor` walks forward through bonds_ (sorted by pair) as keys ascend.
  double initial_overlap(std::uint32_t a, std::uint32_t b, std::uint32_t fa, std::uint32_t fb,
                         std::size_t& cursor) const;

  /// A contact's identity across steps: the two bodies (or wall and body) and the two
  /// features touching. Contacts are produced in ascending key order every step, so the
  /// history of the previous step is found by a forward merge, without hashing.
  struct ContactKey {
    std::uint32_t a, b, fa, fb;
    auto operator<=>(const ContactKey&) const = default;
  };
  struct HistoryEntry {
    ContactKey key;
    ContactHistory history;
  };
  /// A contact found this step, before the law is applied.
  struct Pending {
    ContactKey key;  // a carries kWallFlag for wall contacts
    PrimitiveContact contact;
  };
  const ContactHistory* previous_history(const ContactKey& key) const;
  /// Index of the first entry of history_ whose key is not below `key`.
  std::size_t history_index(const ContactKey& key) const;
  static constexpr std::uint32_t kWallFlag = 0x80000000u;
  /// Asks for the first four cache lines of posed_[slot] (its frame, travel and box).
  void prefetch_posed(std::uint32_t slot) const {
    const char* at = reinterpret_cast<const char*>(&posed_[slot]);
    for (int line = 0; line < 4; ++line) __builtin_prefetch(at + 64 * line);
  }
  /// The damping coefficients of the last pair contact_inputs saw (key a, body b), and
  /// what they were made from (a wall or not, A's and B's masses and least moments).
  struct PairDamping {
    std::uint32_t a = 0, b = 0;
    bool valid = false;
    bool wall = false;
    double mass_a = 0.0, mass_b = 0.0, moment_a = 0.0, moment_b = 0.0;
    ContactDamping damping;
  };
  /// The contact law's inputs for contact k (`p`, under `params`: the walls' or the
  /// pairs'): its kinematics into `kin`, the previous step's history copied into
  /// next_history_[k] (walking `history_cursor` forward through history_), the pair's
  /// coefficients into `pair` (kept from the pair before when the same). Reads the bodies'
  /// states, writes only slot k.
  void contact_inputs(const Pending& p, std::size_t k, const ContactParams& params,
                      std::size_t& history_cursor, std::size_t& bond_cursor, PairDamping& pair,
                      ContactKinematics& kin);

  WorldSettings settings_;
  std::vector<RigidShape> shapes_;
  std::vector<BodyState> states_;  // hot, indexed by slot
  std::vector<BodyInfo> infos_;    // cold, indexed by slot
  std::vector<BodyThermal> thermal_;  // by slot
  bool thermal_on_ = false;           // some body expands
  bool bonds_held_ = false;           // hold_bonds
  double conductivity_ = 0.0, heat_capacity_ = 0.0;
  std::vector<double> heat_;  // by slot: this step's conducted heat (J)
  void conduct(double h);
  std::vector<std::uint32_t> free_slots_;
  std::size_t live_ = 0;
  std::vector<Wall> walls_;
  std::vector<PosedShape> posed_;         // by slot, refreshed each force evaluation
  std::vector<std::uint32_t> live_slots_;
  std::vector<BoundingSphere> spheres_;
  std::vector<BodyPair> pairs_;
  PeriodicCell cell_;
  bool cell_on_ = false;
  Eigen::Matrix3d gradient_ = Eigen::Matrix3d::Zero();  // this step's: the cell's L plus its thermal rate
  bool moving_cell_ = false;                            // gradient_ is not zero
  double stress_modulus_ = 0.0, stress_tau_ = 0.0;      // set_stress_control
  Eigen::Matrix3d cell_at_search_ = Eigen::Matrix3d::Zero();  // the cell vectors at the last search
  std::vector<Eigen::Vector3i> pair_image_;  // by pair, in a cell: B's nearest image (fixed between searches)
  /// A list on cache lines of its own: lists that threads fill side by side shared the
  /// line holding their ends (false sharing: the wall contacts on two threads took longer
  /// than on one).
  template <class T>
  struct alignas(64) OwnLines {
    std::vector<T> list;
  };
  std::vector<OwnLines<Eigen::Vector3d>> chunk_shift_;  // in a cell: per chunk_pending_ entry, B's shift
  std::vector<Eigen::Vector3d> contact_shift_;             // in a cell: per pending contact (walls: zero)
  std::vector<NearFeatures> near_;  // by pair; cleared with each new pair list and on load
  std::vector<ContactManifold> manifolds_;  // by pair (manifold_tolerance > 0); follow the pairs
  std::vector<std::uint32_t> manifold_slots_;  // live slots when the pairs were listed
  std::vector<unsigned char> held_;             // by pair: its manifold holds contacts
  enum : unsigned char { kCarried, kApart, kSearch };
  std::vector<unsigned char> plan_;           // by pair, with manifolds: what body_contacts does
  std::vector<unsigned char> need_geometry_;  // by slot: a search reads its vertices and planes
  /// By slot, from the poses' loop: bit w set when wall w may touch the body (walls from 31
  /// on share bit 31, and are tested again one by one).
  std::vector<std::uint32_t> wall_reach_;
  void plan_pairs(int nt);
  std::vector<Eigen::Vector3d> searched_at_;  // centres at the last search, by live index
  std::vector<Eigen::Quaterniond> searched_q_;  // orientations at the last search, by live index
  double skin_ = 0.0;                         // margin of the last search
  bool pairs_current_ = false;
  NeighbourSearch search_;
  std::vector<HistoryEntry> history_, next_history_;  // sorted by key
  /// This step's contacts, in the order the law and the sums go through them: the lists of
  /// the chunks of pairs, then those of the walls (wall by wall, piece of body slots by
  /// piece), read in place rather than copied into one list.
  std::vector<OwnLines<Pending>> chunk_pending_, wall_pending_;
  std::vector<const std::vector<Pending>*> parts_;  // the lists in order
  std::vector<std::size_t> part_start_;             // index of each list's first contact; back(): all
  [[nodiscard]] std::size_t pending_count() const { return part_start_.empty() ? 0 : part_start_.back(); }
  /// Calls f(k, contact k) for k in [begin, end), in order.
  template <class F>
  void for_pending(std::size_t begin, std::size_t end, F&& f) const;
  void join_pending();
  std::vector<ContactForce> forces_;
  /// By pair: the index of its first contact in its chunk's list (body_contacts), so that a
  /// pair's contacts are [part_start_[chunk] + pair_first_[p], the next pair's or the chunk's end).
  std::vector<std::uint32_t> pair_first_;
  /// By slot, the body's pairs in ascending order, each as (pair index << 1) | (1 if it is the
  /// pair's B): sum_forces walks a body's contacts in list order through them. Made again
  /// after each new pair list (body_pairs_stale_).
  std::vector<std::uint32_t> body_pair_start_, body_pairs_;
  bool body_pairs_stale_ = true;
  void list_body_pairs();
  /// The same for the bonds: by slot, (bond index << 1) | (1 if the body is the bond's B).
  std::vector<std::uint32_t> body_bond_start_, body_bonds_;
  /// By bond, this step: what it adds to its bodies (force and moment on B, A's their
  /// opposites, at the bond point: the sum makes each torque about the body's centroid),
  /// written by the bond law, read by the sum.
  struct BondPush {
    V3 force, moment;   ///< on B (A's: their opposites)
    V3 point;           ///< the bond point: the lever of the torques, and stress_sums'
    bool live = false;  ///< intact: the sum adds it
  };
  std::vector<BondPush> bond_push_;
  bool body_bonds_stale_ = true;
  void list_body_bonds();
  std::vector<double> overlaps_;  // per pending contact: the overlap the law saw
  mutable std::vector<ContactRecord> records_;  // contacts(), made when first asked for
  mutable bool records_current_ = true;
  std::vector<Bond> bonds_;  // sorted by (a, b)
  /// Overlaps that count as zero between pairs that are not bonded (or no longer have the
  /// bond that stored them): pieces of one split, whose dilated surfaces overlap across
  /// the new crack by the sum of their dilation radii, and pieces of a split body with the
  /// parent's neighbours. Sorted by (a, b), a < b.
  struct PairOffset {
    std::uint32_t a, b;
    double overlap;
  };
  std::vector<PairOffset> offsets_;
  [[nodiscard]] double pair_offset(std::uint32_t a, std::uint32_t b) const;
  BondParams bond_params_;
  /// The bonds that broke in this step's bond_forces, one list per thread.
  struct BondFailureAt {
    std::size_t bond;
    BondFailure failure;
    BondState at;
  };
  std::vector<std::vector<BondFailureAt>> bond_failures_;
  std::vector<BondBreak> breaks_;
  double time_ = 0.0;
  std::uint64_t steps_ = 0;
  bool forces_current_ = false;
  // set_timing: the sums, and the clock at the last lap (a lap only counts inside step()).
  StepTimings timings_;
  bool timing_ = false, in_step_ = false;
  std::int64_t lap_ns_ = 0;
  /// Adds the time since the last lap to `phase` (when timing inside a step).
  void lap(StepPhase phase) {
    if (timing_ && in_step_) lap_to(phase);
  }
  void lap_to(StepPhase phase);
  /// stress_sums and forces_on: whether the step's lists by body still describe the world.
  [[nodiscard]] bool by_body_current() const;
  /// Inside compute_forces, once the contacts and bonds are summed (break_by_stress reads
  /// the stresses from the lists by body).
  bool summed_ = false;
  /// stress_sums() and stress_sum_diagonals(): the sums and whether they are this
  /// evaluation's; whether the next evaluation should sum the diagonals with the forces,
  /// and whether this one does.
  mutable std::vector<Eigen::Matrix3d> stress_sums_;
  mutable std::vector<Eigen::Vector3d> stress_diagonals_;
  mutable bool stress_sums_current_ = false, stress_diagonals_current_ = false;
  bool want_stress_sums_ = false, summing_stress_ = false;
  std::vector<StepListener*> listeners_;
  /// Calls f(point, force) (plain doubles) for each force acting on `slot`, in the order of
  /// a walk over contacts() and bonds() (the lists by body current).
  template <class F>
  void for_forces_on(std::uint32_t slot, F&& f) const;
  /// Calls f(is_b, contact, k) for each contact of body `slot` with another body, pair by
  /// pair in the pairs' order (k: its index in the contact list; is_b: the body is B).
  template <class F>
  void for_pair_contacts_of(std::size_t slot, F&& f) const;
  /// Where the walls' contacts start in the contact list (they follow every pair's).
  [[nodiscard]] std::size_t wall_contacts_begin() const;
  /// Sum::add(arm, force) over each live body's forces, in parallel, into out[slot]
  /// (Sum::store); stress_sums and stress_sum_diagonals.
  template <class Sum, class Out>
  void sum_by_body(std::vector<Out>& out) const;
};

}  // namespace cleave::physics
