#pragma once
/// \file
/// The world: a stepper over the owners of its state (bodies, contacts, bonds, the thermal
/// field, the periodic cell, the stress sums), with the public face its callers use.
/// `step()` runs named stages in order (StepPhase, step_clock.hpp; docs/ARCHITECTURE.md):
///   kick_drift -> poses -> pair_search -> plan -> narrow -> walls -> contact_law ->
///   contact_sums -> bond_law -> bond_sums -> damping -> closing_kick.

#include <Eigen/Dense>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "physics/bonds/bond_law.hpp"
#include "physics/dem/bodies.hpp"
#include "physics/dem/body.hpp"
#include "physics/dem/bonds.hpp"
#include "physics/dem/cell_control.hpp"
#include "physics/dem/contact_law.hpp"
#include "physics/dem/contacts.hpp"
#include "physics/dem/domain.hpp"
#include "physics/dem/exact_sum.hpp"
#include "physics/dem/narrow_phase.hpp"
#include "physics/dem/neighbour_search.hpp"
#include "physics/dem/periodic_cell.hpp"
#include "physics/dem/rigid_shape.hpp"
#include "physics/dem/step_clock.hpp"
#include "physics/dem/step_listener.hpp"
#include "physics/dem/stress_sums.hpp"
#include "physics/dem/thermal_field.hpp"
#include "physics/dem/wall.hpp"
#include "physics/dem/world_settings.hpp"

namespace cleave::physics {

class StateWriter;
class StateReader;
class Exchange;

class World {
 public:
  explicit World(WorldSettings settings = {});

  /// Registers a shape; bodies refer to it by the returned index.
  std::uint32_t add_shape(RigidShape shape);
  [[nodiscard]] const RigidShape& shape(std::uint32_t index) const { return bodies_.shape(index); }
  [[nodiscard]] std::size_t shape_count() const { return bodies_.shape_count(); }

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
  [[nodiscard]] std::size_t body_count() const { return bodies_.count(); }

  /// Access by id; throws std::out_of_range for a stale or invalid id.
  [[nodiscard]] const BodyState& state(BodyId id) const;
  [[nodiscard]] BodyState& state(BodyId id);
  [[nodiscard]] const BodyInfo& info(BodyId id) const;
  /// Every slot's state and record, free slots included (their BodyInfo::alive is false):
  /// for readers that look at all bodies at once without copying (the Python module).
  /// The vectors move when a split adds slots.
  [[nodiscard]] const std::vector<BodyState>& slot_states() const { return bodies_.states(); }
  [[nodiscard]] const std::vector<BodyInfo>& slot_infos() const { return bodies_.infos(); }
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
  /// Sets bond k's stiffness factor (Bond::stiffness, > 0): its grains' phases.
  void set_bond_stiffness(std::size_t k, double factor);
  [[nodiscard]] const std::vector<Bond>& bonds() const { return bonds_.list(); }
  [[nodiscard]] BondCounts bond_counts() const;
  /// While held, no intact bond breaks, whatever its load (a stage's hold_cracks: an elastic
  /// probe of a cracked specimen). Not kept in checkpoints: the stage sets it.
  void hold_bonds(bool held) { bonds_.hold(held); }
  /// Every bond failure so far, in the order they happened.
  [[nodiscard]] const std::vector<BondBreak>& bond_breaks() const { return bonds_.breaks(); }

  /// Thermal expansion (seed 003: "l0(T) = l0(T0) + alpha (T - T0)", generalised to a tensor
  /// per grain). `alpha_world` is the body's expansion tensor in world axes now (1/K,
  /// symmetric); it is kept in the body's frame and turns with it. Bonds follow the change
  /// of each end's temperature from the next force evaluation on.
  void set_expansion(BodyId id, const Eigen::Matrix3d& alpha_world);
  /// The body's expansion tensor in world axes.
  [[nodiscard]] Eigen::Matrix3d expansion(BodyId id) const;
  /// alpha_a across the c-axis and alpha_c along it (world), the tensor of a hexagonal or
  /// trigonal crystal: alpha_a I + (alpha_c - alpha_a) c c^T.
  [[nodiscard]] static Eigen::Matrix3d crystal_expansion(const Eigen::Vector3d& c_axis,
                                                         double alpha_a, double alpha_c) {
    return ThermalField::crystal_expansion(c_axis, alpha_a, alpha_c);
  }
  /// Three principal coefficients along the crystal's a, b, c axes (an orthorhombic
  /// crystal, e.g. seed 003's aluminium titanate): R diag(alpha_a, alpha_b, alpha_c) R^T.
  [[nodiscard]] static Eigen::Matrix3d crystal_expansion(const Eigen::Quaterniond& crystal,
                                                         const Eigen::Vector3d& alpha_abc) {
    return ThermalField::crystal_expansion(crystal, alpha_abc);
  }
  /// Sets one body's temperature (K), or every live body's.
  void set_temperature(BodyId id, double kelvin);
  void set_temperature(double kelvin);
  /// Changes every live, not held body's temperature by `change` (K), stopping at `target`
  /// (a body already past it stays where it is): one step of a uniform heating or cooling.
  void ramp_temperature(double change, double target);
  [[nodiscard]] double temperature(BodyId id) const;
  /// Every slot's temperature and expansion (free slots included).
  [[nodiscard]] const std::vector<BodyThermal>& slot_thermal() const { return thermal_.slots(); }
  /// Whether some body has a non-zero expansion tensor (thermal terms are computed).
  [[nodiscard]] bool thermal() const { return thermal_.on(); }
  /// Heat conduction through the intact bonds (seed 003, after Terreros et al. 2013): each
  /// step every bond passes Q = lambda S_t (T_b - T_a) / d_ab dt from the hotter grain to the
  /// colder (S_t its transmission surface, d_ab the centroids' distance), and a grain's
  /// temperature changes by its heat over m c_p. `conductivity` lambda in W/(m K),
  /// `heat_capacity` c_p in J/(kg K); conductivity 0 turns it off (the default).
  void set_conduction(double conductivity, double heat_capacity);
  [[nodiscard]] double conductivity() const { return thermal_.conductivity(); }
  [[nodiscard]] double heat_capacity() const { return thermal_.heat_capacity(); }
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
  [[nodiscard]] const PeriodicCell* cell() const { return cell_.get(); }
  /// The cell's velocity gradient L (1/s; PeriodicCell): from the next step on the cell and
  /// the bodies' centroids follow dH/dt = L H. Throws std::logic_error without a cell.
  void set_velocity_gradient(const Eigen::Matrix3d& l);
  /// Berendsen's pressure control for the cell: on each periodic axis whose set rate is
  /// zero, the cell also stretches at -sigma_ii / (modulus tau) each step (sigma from the
  /// last force evaluation), so its mean normal stresses relax to zero with time constant
  /// about tau when `modulus` is its stiffness along the axis. tau = 0: off. Not kept in
  /// checkpoints (a stage sets it).
  void set_stress_control(double modulus, double tau) { cell_.set_stress_control(modulus, tau); }
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
    contacts_.clear_near();
  }

  /// Advances the world by one time step.
  void step();
  /// Clocks the parts of each step from now on (true) or stops (false); switching on starts
  /// the sums from zero. Off by default: a clock read per part and step when on.
  void set_timing(bool on);
  [[nodiscard]] const StepTimings& timings() const { return clock_.timings(); }
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
  using AppliedForce = physics::AppliedForce;
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
  [[nodiscard]] Role role(std::uint32_t slot) const { return bodies_.role(slot); }
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

  /// The exchange API of the owners for a domain decomposition (exchange.hpp): what
  /// parallel::MpiDomain packs, sends and unpacks.
  [[nodiscard]] Exchange exchange();

 private:
  /// The force evaluation: the stages from poses to damping (each timed by its name).
  void compute_forces();
  /// Before the step's first half kick: the listeners' before_step and needs, the clock, the
  /// periodic cell's rate for this step, and the first force evaluation if none was made.
  void begin_step();
  /// After the closing kick: time and step count advance, the listeners' after_step.
  void end_step();
  /// Stage kick_drift: the first half kick and drift, the cell's deformation and wrap,
  /// the walls' motion.
  void kick_drift(double h);
  /// Stage closing_kick: the second half kick, heat conduction.
  void closing_kick(double h);
  /// Stage damping: stress-criterion breaks, in-plane hold, local damping, the domain's
  /// exchange after the forces.
  void damping(int threads);
  /// What the stress sums read now.
  [[nodiscard]] StressSums::View stress_view() const;
  /// stress_sums and forces_on: whether the step's lists by body still describe the world.
  [[nodiscard]] bool by_body_current() const;

  WorldSettings settings_;
  Bodies bodies_;
  ThermalField thermal_;
  CellControl cell_;
  Contacts contacts_;
  Bonds bonds_;
  StressSums stress_;
  StepClock clock_;
  std::vector<Wall> walls_;
  Domain* domain_ = nullptr;
  std::vector<StepListener*> listeners_;
  double time_ = 0.0;
  std::uint64_t steps_ = 0;
  bool forces_current_ = false;
  /// Inside compute_forces, once the contacts and bonds are summed (the stress criterion
  /// reads the stresses from the lists by body).
  bool summed_ = false;
};

}  // namespace cleave::physics
