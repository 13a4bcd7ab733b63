#include "physics/dem/world.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "physics/dem/exchange.hpp"
#include "physics/dem/step_threads.hpp"

namespace cleave::physics {

World::World(WorldSettings settings) : settings_(std::move(settings)), contacts_(settings_.search) {
  if (!(settings_.dt > 0.0)) throw std::invalid_argument("time step must be positive");
  if (!(settings_.search_skin >= 0.0)) throw std::invalid_argument("search skin must be >= 0");
}

// ---------------------------------------------------------------------------------------
// The step

void World::step() {
  begin_step();
  const double h = settings_.dt;
  kick_drift(h);
  clock_.lap(StepPhase::kick_drift);
  compute_forces();  // poses ... damping
  closing_kick(h);
  clock_.lap(StepPhase::closing_kick);
  end_step();
}

void World::compute_forces() {
  if (domain_) domain_->before_forces(*this);  // ghosts current, roles set
  bonds_.begin_evaluation();
  // The diagonals of eq. 2.17's sums along with the forces, when a listener asked for them;
  // not across processes (the ghosts' bonds change after the sums).
  stress_.begin_evaluation(domain_ == nullptr, bodies_.slots());
  const int nt = threads::thread_count(settings_.threads);
  const bool stale = contacts_.pose(bodies_, walls_, cell_, settings_, nt);
  for (auto& w : walls_) w.reaction.setZero();
  clock_.lap(StepPhase::poses);
  if (stale) {
    contacts_.search(bodies_, cell_, settings_);
    if (cell_.on()) cell_.note_search();
    clock_.lap(StepPhase::pair_search);
  }
  contacts_.plan(cell_, settings_, nt);
  clock_.lap(StepPhase::plan);
  contacts_.narrow(cell_, settings_, nt);
  clock_.lap(StepPhase::narrow);
  contacts_.walls(bodies_, walls_, cell_.on(), nt);
  clock_.lap(StepPhase::walls);
  contacts_.apply_law(bodies_, walls_, bonds_, thermal_, cell_, settings_, nt);
  clock_.lap(StepPhase::contact_law);
  contacts_.sum(bodies_, walls_, stress_.summing(), nt);
  clock_.lap(StepPhase::contact_sums);
  bonds_.apply_law(bodies_, thermal_, cell_, settings_.dt, nt, time_, steps_);
  clock_.lap(StepPhase::bond_law);
  bonds_.sum(bodies_, cell_.on(), stress_.summing(), nt);
  clock_.lap(StepPhase::bond_sums);
  summed_ = true;
  stress_.end_sums();
  // The temperatures the bonds (and a periodic cell) have followed up to now.
  if (thermal_.on()) thermal_.mark_bonded();
  damping(nt);
  clock_.lap(StepPhase::damping);
  summed_ = false;
  forces_current_ = true;
}

void World::begin_step() {
  StepNeeds needs;
  for (StepListener* l : listeners_) {
    l->before_step(*this);
    needs |= l->needs(*this);
  }
  stress_.want_diagonals(needs.stress_sums);
  clock_.start_step();
  if (cell_.on()) {
    // The cell's velocity gradient this step: the one set, plus, when the grains expand,
    // their volume-mean expansion since the last evaluation over the step (the cell of a
    // free polycrystal follows its mean thermal strain; the grains' mismatch stays in them).
    Eigen::Matrix3d gradient = cell_.cell().velocity_gradient();
    if (thermal_.on())
      thermal_.add_mean_strain_rate(bodies_.states(), bodies_.infos(), bodies_.shapes(),
                                    settings_.dt, gradient);
    const bool control = cell_.stress_controlled() && forces_current_;
    const Eigen::Matrix3d sigma = control ? cell_stress() : Eigen::Matrix3d::Zero();
    cell_.begin_step(gradient, control ? &sigma : nullptr);
  }
  if (!forces_current_) {
    clock_.pause();  // the first evaluation is not a step's
    compute_forces();
    clock_.start_step();
  }
}

void World::kick_drift(double h) {
  bodies_.kick_drift(h, threads::thread_count(settings_.threads));
  if (cell_.on()) {
    cell_.deform(bodies_.states(), bodies_.infos(), h);
    bonds_.follow_wrap(cell_.wrap(bodies_.states(), bodies_.infos()), cell_.cell());
  }
  for (auto& w : walls_) w.origin += h * w.velocity;
}

void World::damping(int nt) {
  if (bonds_.stress_criterion()) {
    if (bonds_.break_by_stress(stress_.body_stresses(stress_view()), bodies_.infos(), time_,
                               steps_) > 0)
      stress_.invalidate();  // the sums still hold the bonds that broke
  }
  if (settings_.in_plane) bodies_.hold_in_plane(contacts_.live());
  if (settings_.local_damping > 0.0)
    bodies_.apply_local_damping(settings_.local_damping, contacts_.live(), nt);
  if (domain_) domain_->after_forces(*this);
}

void World::closing_kick(double h) {
  bodies_.closing_kick(h, threads::thread_count(settings_.threads));
  if (thermal_.conductivity() > 0.0)
    thermal_.conduct(bodies_.states(), bodies_.infos(), bonds_.list(), h);
}

void World::end_step() {
  clock_.end_step();
  time_ += settings_.dt;
  ++steps_;
  for (StepListener* l : listeners_) l->after_step(*this);
}

void World::set_timing(bool on) {
  clock_.set_on(on);
}

void World::add_listener(StepListener* listener) {
  if (std::find(listeners_.begin(), listeners_.end(), listener) == listeners_.end())
    listeners_.push_back(listener);
}

void World::remove_listener(StepListener* listener) {
  listeners_.erase(std::remove(listeners_.begin(), listeners_.end(), listener), listeners_.end());
}

// ---------------------------------------------------------------------------------------
// Bodies

std::uint32_t World::add_shape(RigidShape shape) {
  const auto& p = shape.primitives;
  if (!within_contact_limits(p)) {
    throw std::invalid_argument(
        "a grain of " + std::to_string(p.vertices.size()) + " vertices, " + std::to_string(p.faces.size()) +
        " faces and " + std::to_string(p.edges.size()) + " edges is beyond what the contact search takes (" +
        std::to_string(kContactLimits.vertices) + ", " + std::to_string(kContactLimits.faces) + " and " +
        std::to_string(kContactLimits.edges) + "): use more grains, a smaller size spread or another seed");
  }
  return bodies_.add_shape(std::move(shape));
}

BodyId World::add_body(std::uint32_t shape, double rho, const Eigen::Vector3d& x,
                       const Eigen::Quaterniond& q, const Eigen::Vector3d& v,
                       const Eigen::Vector3d& w, int grain_id) {
  const BodyId id = bodies_.add(shape, rho, x, q, v, w, grain_id);
  thermal_.reset(id.index, bodies_.slots());
  forces_current_ = false;
  contacts_.forget_pairs();
  return id;
}

void World::remove_body(BodyId id) {
  const std::uint32_t slot = bodies_.slot_of(id, "remove_body: ");
  bodies_.remove(id);
  contacts_.forget_slot(slot);
  bonds_.forget_slot(slot);
}

std::vector<BodyId> World::split_body(BodyId parent, const std::vector<Fragment>& pieces) {
  const std::uint32_t old_slot = bodies_.slot_of(parent, "split_body: ");
  if (pieces.empty()) throw std::invalid_argument("split_body: no pieces");
  const BodyState ps = bodies_.states()[old_slot];
  const BodyInfo pi = bodies_.infos()[old_slot];
  const BodyThermal pt = thermal_[old_slot];
  const double rho = pi.mass / bodies_.shape(pi.shape).volume;
  // The parent's bonds and stored overlaps, taken before its slot is freed.
  Bonds::Parted parted = bonds_.part(old_slot);
  const Role parent_role = bodies_.role(old_slot);
  remove_body(parent);  // drops the parent's bonds, offsets and contact history
  std::vector<BodyId> ids;
  for (const Fragment& f : pieces) {
    if (f.shape >= bodies_.shape_count())
      throw std::out_of_range("split_body: no shape " + std::to_string(f.shape));
    const Eigen::Vector3d x = ps.x + ps.q * f.offset;
    const BodyId id =
        add_body(f.shape, rho, x, ps.q * f.turn, ps.v + ps.w.cross(x - ps.x), ps.w, pi.grain_id);
    bodies_.infos()[id.index].fixed = pi.fixed;
    bodies_.set_role(id.index, parent_role);  // the parent's owner holds its pieces
    // The piece is of the parent's material: its temperature, and its expansion tensor
    // turned into the piece's own frame.
    thermal_.inherit(id.index, pt, f.turn.toRotationMatrix(), ps, bodies_.states()[id.index].q, x);
    ids.push_back(id);
  }
  bonds_.follow_split(std::move(parted), old_slot, ps, ids, bodies_);
  forces_current_ = false;
  return ids;
}

void World::set_fixed(BodyId id, bool fixed) {
  bodies_.infos()[bodies_.slot_of(id, "set_fixed: ")].fixed = fixed;
}
bool World::contains(BodyId id) const {
  return bodies_.contains(id);
}
const BodyState& World::state(BodyId id) const {
  return bodies_.states()[bodies_.slot_of(id, "")];
}
BodyState& World::state(BodyId id) {
  return bodies_.states()[bodies_.slot_of(id, "")];
}
const BodyInfo& World::info(BodyId id) const {
  return bodies_.infos()[bodies_.slot_of(id, "")];
}
BodyId World::id_at(std::uint32_t slot) const {
  return bodies_.id_at(slot);
}
std::vector<BodyId> World::body_ids() const {
  return bodies_.ids();
}

void World::set_angular_velocity(BodyId id, const Eigen::Vector3d& w) {
  bodies_.set_angular_velocity(bodies_.slot_of(id, ""), w);
}

std::size_t World::add_wall(Wall wall) {
  walls_.push_back(std::move(wall));
  forces_current_ = false;
  return walls_.size() - 1;
}

double World::kinetic_energy() const {
  return bodies_.kinetic_energy();
}
double World::potential_energy() const {
  return bodies_.potential_energy(settings_.gravity);
}
ExactSum World::owned_kinetic_energy() const {
  return bodies_.owned_kinetic_energy();
}
ExactSum World::owned_potential_energy() const {
  return bodies_.owned_potential_energy(settings_.gravity);
}
Eigen::Vector3d World::linear_momentum() const {
  return bodies_.linear_momentum();
}
Eigen::Vector3d World::angular_momentum() const {
  return bodies_.angular_momentum();
}

// ---------------------------------------------------------------------------------------
// Bonds

std::size_t World::initialise_bonds(const BondParams& params, double distance) {
  if (!bonds_.empty()) throw std::logic_error("initialise_bonds: the bodies are already bonded");
  if (!(distance >= 0.0)) throw std::invalid_argument("initialise_bonds: distance must be >= 0");
  if (domain_) {
    // Bonding happens once: every process makes the whole world's bonds from the whole
    // world's state, as one process would (the same list everywhere), then goes back to
    // its own bodies.
    if (params.criterion != BondCriterion::limits)
      throw std::invalid_argument("initialise_bonds: a stress criterion is single-process for now");
    Domain* domain = domain_;
    domain->gather_all(*this);
    std::vector<Role> roles = bodies_.take_roles();
    domain_ = nullptr;
    contacts_.forget_search();
    // Every body posed and searched afresh (the histories this evaluation advances are
    // cleared below, as after any bonding).
    forces_current_ = false;
    const std::size_t n = initialise_bonds(params, distance);
    domain_ = domain;
    set_roles(std::move(roles));
    return n;
  }
  if (!forces_current_) compute_forces();  // posed shapes and live slots of this state
  contacts_.pose_geometry();               // a lazy pose may have skipped some
  bonds_.make(params, distance, bodies_, contacts_.posed(), contacts_.live(), cell_,
              settings_.search);
  // Bonded at this temperature: their rest state is the present one.
  thermal_.mark_bonded();
  // The stress-free start: at rest, no shear or rolling springs, forces recomputed.
  for (std::uint32_t slot : contacts_.live()) {
    if (bodies_.infos()[slot].fixed) continue;
    BodyState& s = bodies_.states()[slot];
    s.v.setZero();
    s.L.setZero();
    s.w.setZero();
  }
  contacts_.clear_history();
  forces_current_ = false;
  compute_forces();
  return bonds_.list().size();
}

void World::set_bond_strength(std::size_t k, double factor) {
  bonds_.set_strength(k, factor);
}
void World::set_bond_stiffness(std::size_t k, double factor) {
  bonds_.set_stiffness(k, factor);
}
BondCounts World::bond_counts() const {
  return bonds_.counts();
}

// ---------------------------------------------------------------------------------------
// Thermal field

void World::set_expansion(BodyId id, const Eigen::Matrix3d& alpha_world) {
  const std::uint32_t slot = bodies_.slot_of(id, "set_expansion: ");
  thermal_.set_expansion(slot, bodies_.states()[slot].q, alpha_world);
}

Eigen::Matrix3d World::expansion(BodyId id) const {
  const std::uint32_t slot = bodies_.slot_of(id, "expansion: ");
  return thermal_.expansion(slot, bodies_.states()[slot].q);
}

void World::set_temperature(BodyId id, double kelvin) {
  thermal_.set_temperature(bodies_.slot_of(id, "set_temperature: "), kelvin);
}
void World::set_temperature(double kelvin) {
  thermal_.set_temperature(bodies_.infos(), kelvin);
}
void World::ramp_temperature(double change, double target) {
  thermal_.ramp_temperature(bodies_.infos(), change, target);
}
double World::temperature(BodyId id) const {
  return thermal_.temperature(bodies_.slot_of(id, "temperature: "));
}
void World::set_conduction(double conductivity, double heat_capacity) {
  thermal_.set_conduction(conductivity, heat_capacity);
}
void World::set_temperature_held(BodyId id, bool held) {
  thermal_.set_held(bodies_.slot_of(id, "set_temperature_held: "), held);
}

// ---------------------------------------------------------------------------------------
// Periodic cell

void World::set_cell(const PeriodicCell& cell) {
  CellControl::check(cell);
  if (settings_.manifold_tolerance > 0.0)
    throw std::invalid_argument(
        "set_cell: a periodic cell uses the exact search (manifold_tolerance 0)");
  if (!bonds_.empty()) throw std::logic_error("set_cell: set the cell before the bonds are made");
  cell_.set(cell);
  bonds_.follow_wrap(cell_.wrap(bodies_.states(), bodies_.infos()), cell_.cell());
  contacts_.forget_pairs();
  forces_current_ = false;
}

void World::set_velocity_gradient(const Eigen::Matrix3d& l) {
  cell_.set_velocity_gradient(l);
}

// ---------------------------------------------------------------------------------------
// Contacts and stress sums

const std::vector<ContactRecord>& World::contacts() const {
  return contacts_.records(settings_.threads);
}

bool World::by_body_current() const {
  // The per-body lists of the last evaluation (the contact and bond sums) describe the
  // contact lists and bonds as they are: nothing has been split, added or loaded since.
  return (forces_current_ || summed_) && contacts_.by_body_current(bodies_.slots()) &&
         bonds_.by_body_current(bodies_.slots());
}

StressSums::View World::stress_view() const {
  return {bodies_,           contacts_,          bonds_,           cell_,
          by_body_current(), domain_ != nullptr, settings_.threads};
}

Eigen::Matrix3d World::cell_stress() const {
  return StressSums::cell_stress(stress_view());
}
const std::vector<Eigen::Matrix3d>& World::stress_sums() const {
  return stress_.sums(stress_view());
}
Eigen::Matrix3d World::stress_sum(std::uint32_t slot) const {
  return stress_.sum(stress_view(), slot);
}
const std::vector<Eigen::Vector3d>& World::stress_sum_diagonals() const {
  return stress_.diagonals(stress_view());
}
void World::forces_on(std::uint32_t slot, std::vector<AppliedForce>& out) const {
  stress_.forces_on(stress_view(), slot, out);
}
std::vector<Eigen::Matrix3d> World::body_stresses() const {
  return stress_.body_stresses(stress_view());
}

// ---------------------------------------------------------------------------------------
// Domain decomposition

void World::set_domain(Domain* domain, std::vector<Role> roles) {
  domain_ = domain;
  set_roles(std::move(roles));
}

void World::set_roles(std::vector<Role> roles) {
  bodies_.set_roles(std::move(roles));
  // Another set of bodies here: the pair list and its caches are searched afresh.
  contacts_.forget_search();
}

std::size_t World::owned_contact_count() const {
  return contacts_.owned_count(bodies_);
}

Exchange World::exchange() {
  return Exchange(bodies_, contacts_, bonds_, walls_);
}

}  // namespace cleave::physics
