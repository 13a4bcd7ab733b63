#pragma once
/// \file
/// Scenario files (TOML, parsed with toml++). A scenario maps onto plain definition
/// structs with documented defaults; unknown keys, wrong types and impossible values are
/// errors that name the file, line, column and key.

#include <array>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/specimen.hpp"
#include "io/mesh_grains.hpp"
#include "io/mesh_io.hpp"
#include "physics/bonds/bond_law.hpp"
#include "physics/dem/contact_law.hpp"
#include "physics/dem/neighbour_search.hpp"
#include "physics/dem/wall.hpp"
#include "physics/transgranular/fracture_criterion.hpp"

namespace cleave::io {

/// A scenario error: `what()` reads "FILE:LINE:COL: key 'table.key': message". Without a
/// position (missing or unreadable file) it reads "FILE: message"; without a key (TOML
/// syntax errors) the "key '...': " part is left out.
class ScenarioError : public std::runtime_error {
 public:
  ScenarioError(std::string file, int line, int column, std::string key, std::string message);
  /// An error in a key set by an override (`cleave run --set KEY=VALUE`, Python's
  /// `overrides=`): `what()` reads "OVERRIDE: key 'table.key': message" (no line: the
  /// value is not in the file); file() is still the scenario.
  static ScenarioError in_override(const std::string& override_text, std::string file,
                                   std::string key, std::string message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& key() const { return key_; }  ///< dotted path, e.g. "grain.r_bar"
  const std::string& message() const { return message_; }  ///< what() without file and key

 private:
  ScenarioError(std::string what, std::string file, std::string key, std::string message);
  std::string file_;
  int line_;
  int column_;
  std::string key_;
  std::string message_;
};

struct SplitDef {
  /// Cuts leaving a fragment below this fraction of its parent's volume are refused.
  double min_fragment_fraction = 0.01;
  /// Cuts leaving a fragment whose equivalent-sphere diameter (6 V / pi)^(1/3) is below this
  /// (m) are refused; 0: no such bound.
  double min_fragment_diameter = 0.0;
};

struct OutputDef {
  MeshFormat mesh_format = MeshFormat::obj;
  MeshLayout mesh_layout = MeshLayout::scene;
  /// With [dynamics]: every frame's bodies (grains and fragments, named by lineage) are
  /// written as meshes too, frame_meshes/frame_NNNNNN.*, in their world pose.
  bool frame_meshes = false;
  /// With [dynamics]: a checkpoint every this many steps (0: only when interrupted);
  /// `cleave restart` continues from it (io/checkpoint.hpp).
  std::uint64_t checkpoint_every = 0;
};

/// [material]
struct MaterialDef {
  double density = 3100.0;  ///< kg/m^3 (a preset's unless the file gives `density` too)
  /// `preset`: a material of the library (io/material_library.hpp) as written, and the file
  /// it was found in (empty without a preset).
  std::string preset;
  std::string preset_file;
};

/// Where a value sits in the scenario file (for errors found after parsing).
struct SourcePosition {
  int line = 0;
  int column = 0;
};

/// [contact] with its two parameter sets (table 2.3).
struct ContactDef {
  double dilation_radius = 0.0;  ///< metres
  SourcePosition dilation_position;  ///< of dilation_radius, for the start checks
  physics::ContactParams particle_particle;
  physics::ContactParams particle_wall;
};

/// [dynamics]: a dynamic run of the specimen (present when the table is).
struct DynamicsDef {
  bool enabled = false;
  double dt = 0.0;             ///< s
  SourcePosition dt_position;  ///< of the dt key, for the time-step refusal
  double duration = 0.0;       ///< s
  Eigen::Vector3d gravity = Eigen::Vector3d(0, 0, -9.80665);  ///< m/s^2
  double lift = 0.0;           ///< metres between z = 0 and the specimen's lowest point
  int frames = 0;              ///< ParaView frames over the run
  double settle_ratio = 0.0;   ///< stop once KE < ratio x released potential energy
  double dt_safety = 0.2;      ///< dt <= dt_safety x 2 sqrt(m_min / k_max)
  physics::SearchMethod search = physics::SearchMethod::bounding_box;
  int threads = 0;             ///< 0: all cores; results do not depend on it
  double local_damping = 0.0;  ///< Cundall's local damping coefficient, [0, 1)
  /// Density (mass) scaling: the grains' masses and moments of inertia are the material's
  /// times this (>= 1), so that the stable time step grows by its square root. The loading
  /// stays quasi-static only while the kinetic energy stays small against the work done,
  /// which `cleave measure` reports; 1: none.
  double density_scale = 1.0;
  /// Persistent contact manifolds (physics::WorldSettings::manifold_tolerance): 0, the
  /// default, searches every touching pair every step (exact); above 0 a touching pair's
  /// contacts are carried with its bodies while their relative motion stays under half this
  /// fraction of the pair's dilation radii (faster, approximate).
  double manifold_tolerance = 0.0;
  /// Bodies move in the xy plane only (physics::WorldSettings::in_plane): for specimens one
  /// grain thick. Default false.
  bool in_plane = false;
  SourcePosition in_plane_position;  ///< of the in_plane key, for its refusal
};

/// [bond]: the bonded-particle law of sec. 2.3.3 (eqs 2.9, 2.14), SI units.
struct BondDef {
  bool enabled = false;
  physics::BondParams params;  ///< k_bn, k_bs in N/m^3; t_bn, t_bs in Pa
  /// Weibull modulus of the bonds' own strength factors (mean 1, drawn from the [orientation]
  /// seed and the two grains: physics::bond_strength_factor); 0: every bond as strong.
  double strength_modulus = 0.0;
};

/// [fracture]: transgranular fracture during a run (chapter 3, eqs 3.22-3.25).
struct FractureDef {
  bool enabled = false;
  physics::FractureParams params;  ///< sigma_f_hyd Pa, k_ic Pa sqrt(m), c, crack_length m
  int check_every = 1;             ///< steps between two checks
};

/// [thermal]: temperatures, thermal expansion and conduction (seed 003).
struct ThermalDef {
  bool enabled = false;
  double temperature = 293.15;  ///< K: every grain's at the start (and so at bonding)
  /// K/m: a linear field at the start, T = temperature + gradient . (x - the grains' mean
  /// centroid); zero: uniform.
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  SourcePosition gradient_at;  ///< where the file gives it, for messages
  double alpha_a = 0.0;         ///< 1/K: expansion across the c-axis
  double alpha_c = 0.0;         ///< 1/K: along it (= alpha_a: isotropic, `alpha`)
  /// 1/K: along the crystal's b axis (c_axis = crystal); = alpha_a for a uniaxial crystal.
  double alpha_b = 0.0;
  /// Each grain's c-axis: its prism axis (a honeycomb's grains all share it), a direction
  /// drawn uniformly on the sphere per grain from `seed` (a polycrystal's random texture),
  /// or the grain's own crystal ([crystal]: its a, b, c axes carry alpha_a, alpha_b, alpha_c).
  enum class Axis { prism, random, crystal } c_axis = Axis::prism;
  std::uint64_t seed = 1;
  double conductivity = 0.0;   ///< W/(m K); 0: no conduction
  double heat_capacity = 0.0;  ///< J/(kg K)
};

/// [periodic]: a periodic cell, the Voronoi specimen's box, periodic along the axes named.
struct PeriodicDef {
  bool enabled = false;
  std::array<bool, 3> axes{false, false, false};
  SourcePosition position;  ///< of `axes`, for messages
  /// A stress-free cell (Berendsen's pressure control, as MD codes do it): while no
  /// cell_strain_rate is set, each periodic axis also stretches at -sigma_ii / (modulus
  /// time), so the cell's mean normal stresses relax to zero in about `stress_control_time`
  /// (s); `stress_control_modulus` (Pa) estimates the cell's stiffness. 0: off (the cell
  /// follows only the grains' mean thermal expansion and the stages' rates).
  double stress_control_time = 0.0;
  double stress_control_modulus = 0.0;
};

/// One [[phase]]: a kind of grain in a several-phase specimen. Its grains take its density
/// and expansion; the bonds between two of its grains take its factors on the [bond] table.
struct PhaseDef {
  std::string name;
  double fraction = 0.0;  ///< the grains' volume fraction, in [0, 1] (the phases' sum to 1)
  /// `preset`: a material of the library as written and its file (empty without one).
  std::string preset;
  std::string preset_file;
  double density = 0.0;  ///< kg/m^3: `density`, else the preset's, else [material]'s
  /// 1/K, isotropic; NaN: the grain expands as [thermal] says (no `alpha` key).
  double alpha = std::numeric_limits<double>::quiet_NaN();
  /// Factors on [bond]'s k_bn and k_bs (the beam law's E_m), and on t_bn, t_bs (sigma_c,
  /// sigma_f), of a bond between two grains of this phase (physics::Bond::stiffness,
  /// strength).
  double stiffness = 1.0;
  double strength = 1.0;
  SourcePosition position;  ///< of the table's header
};

/// One [[boundary]]: the bonds between grains of two different phases. Without one, a pair
/// takes the mixing rule (sim/phases.hpp).
struct BoundaryDef {
  std::array<int, 2> phases{0, 0};  ///< indices into Scenario::phases, first < second
  double stiffness = 1.0;           ///< factor on [bond]'s k_bn, k_bs (E_m)
  double strength = 1.0;            ///< factor on t_bn, t_bs (sigma_c, sigma_f)
};

/// One [[stage]] of a staged run (sec. 2.5.2: compaction, bond initialisation, loading).
struct StageDef {
  enum class Kind { motion, bond };
  /// What ends a motion stage before its limit.
  enum class Until { limit, all_in_contact, walls_touch, load_drop };
  std::string name;
  Kind kind = Kind::motion;
  SourcePosition position;  ///< of the stage's header, for messages
  /// motion: wall name -> velocity (m/s); walls not listed stand still during the stage.
  std::vector<std::pair<std::string, Eigen::Vector3d>> wall_velocity;
  std::uint64_t steps = 0;  ///< limit in steps (0: use `time`)
  double time = 0.0;        ///< limit in simulated seconds (0: use `steps`)
  Until until = Until::limit;
  double load_drop = 0.5;   ///< load_drop: stop once the load < this fraction of its peak
  /// Walls whose load is measured (load_drop, the load-displacement curve); default: the
  /// walls that move in the stage.
  std::vector<std::string> load_walls;
  int frames = 10;          ///< ParaView frames over the stage's limit
  /// s: the walls' velocities grow linearly from 0 to wall_velocity over this time from the
  /// stage's start (a smooth start sends no impact wave through the specimen); 0: at once.
  double ramp_time = 0.0;
  double bond_distance = 0.0;  ///< bond: the bonding distance, m
  /// Where `distance` (bond), `steps` or `time` (motion) and each wall_velocity entry (in
  /// its order) are in the file, for the start checks (sim/world_assembly.hpp).
  SourcePosition distance_position, length_position;
  std::vector<SourcePosition> wall_velocity_positions;
  /// motion, with [thermal]: K/s every grain's temperature changes by over the stage (a
  /// uniform field added to conduction's), stopping at `temperature_target` K.
  double temperature_rate = 0.0;
  double temperature_target = 0.0;
  /// motion, with [thermal]: K/(m s), a linear field growing over the stage: each grain's
  /// temperature changes at temperature_gradient_rate . (x - the grains' mean centroid) per
  /// second on top of temperature_rate (a field T(x, t) prescribed piecewise linear in time).
  Eigen::Vector3d temperature_gradient_rate = Eigen::Vector3d::Zero();
  /// motion, with [thermal]: a prescribed field T(x, y, z, t), a formula (FieldExpression,
  /// io/field_expression.hpp) in the file's length unit and the seconds since the stage
  /// began; every grain not held by a quench takes its value at its centroid each step.
  /// Empty: none.
  std::string temperature_field;
  /// motion: no bond breaks and no grain splits during the stage (an elastic probe, such as
  /// a modulus test of a cracked specimen, that must not crack it further).
  bool hold_cracks = false;
  /// motion, with [thermal]: a thermal shock. The grains whose centroid lies within
  /// `quench_depth` (m) of wall `quench_wall`'s plane are held at `quench_temperature` (K)
  /// for the stage (conduction carries the shock inwards); empty: none.
  std::string quench_wall;
  double quench_temperature = 0.0;
  double quench_depth = 0.0;
  /// motion, with [periodic]: the periodic cell's stretching rates along x, y, z (1/s: the
  /// diagonal of its velocity gradient; zero on the axes that are not periodic).
  Eigen::Vector3d cell_strain_rate = Eigen::Vector3d::Zero();
  /// With one non-zero cell_strain_rate: Young's modulus and Poisson's ratio from the slope
  /// of the cell's stress against its strain over the stage, a row of modulus.csv.
  bool measure_modulus = false;
};

/// The name of an `until` event as written in scenario files.
const char* to_string(StageDef::Until until);

/// Metres per unit of a scenario's `length_unit` ("m", "mm" or "um"); throws
/// std::invalid_argument for another name (a loaded Scenario holds only these).
double length_unit_metres(std::string_view name);

/// The `length_unit` of a scenario file that names none: what its bare lengths are in.
std::string_view default_length_unit();

/// [specimen] shape = "tess" or "grain_file": where the grains were read from (SI).
struct TessellationFileSpec {
  std::string shape;           ///< "tess" or "grain_file"
  std::filesystem::path file;  ///< absolute
  double scale = 1.0;          ///< file lengths x scale = metres
};

struct Scenario {
  std::string source;            ///< file path (or a name for in-memory text)
  std::string name;              ///< [scenario] name, default: the file stem
  std::string description;       ///< [scenario] description
  std::string length_unit = "mm";  ///< unit of every length in the file: "m", "mm" or "um"
  geometry::SpecimenDef specimen;  ///< lengths converted to metres
  SplitDef split;
  OutputDef output;
  MaterialDef material;
  ContactDef contact;
  DynamicsDef dynamics;
  BondDef bond;
  FractureDef fracture;
  ThermalDef thermal;
  PeriodicDef periodic;
  std::vector<StageDef> stages;      ///< [[stage]] entries, in file order (empty: one run)
  std::vector<physics::Wall> walls;  ///< [[wall]] entries, in file order
  /// Per wall: `gap` (m), a plane or platen placed this far from the specimen's nearest grain
  /// surface (dilated by the contact radius) along its normal when the world is made, its
  /// point fixing only its position in its plane; NaN: at its point. A specimen whose size
  /// or grains change keeps its platens against it.
  std::vector<double> wall_gaps;
  /// Per wall: where its `point` key is in the file, for the start checks.
  std::vector<SourcePosition> wall_points;
  /// [[mesh_grain]] entries as read (absolute paths, SI); their grains are in
  /// specimen.custom_grains.
  std::vector<MeshGrainSpec> mesh_grains;
  /// shape = "tess" or "grain_file": the file read; its grains are in specimen.custom_grains
  /// and its orientations in specimen.orientations.
  std::optional<TessellationFileSpec> tessellation;
  /// [[phase]] tables in file order (empty: one material, as [material] and [thermal] say);
  /// their fractions are also specimen.phase_fractions.
  std::vector<PhaseDef> phases;
  std::vector<BoundaryDef> boundaries;  ///< [[boundary]] tables in file order
};

/// Reads and validates a scenario file. Throws ScenarioError (file, line, key) for a
/// missing file, TOML syntax errors, unknown keys, wrong types and impossible values.
Scenario load_scenario(const std::filesystem::path& file);
/// The same for text in memory; `source` names it in errors.
Scenario parse_scenario(std::string_view text, const std::string& source);

}  // namespace cleave::io
