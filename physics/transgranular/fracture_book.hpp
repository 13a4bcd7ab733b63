#pragma once
/// \file
/// The exact side of transgranular fracture (chapter 3 of the dissertation, seed 000): for
/// every body of a World, the exact shape it is (in its grain's own coordinates, so that
/// fragments of one grain can be summed and compared with it exactly whatever their
/// motion), its lineage (grain id, fragment path, the plane and time that made it) and
/// the cleavage planes it may still break along. `split` cuts a body exactly along one of
/// them and hands the pieces to World::split_body.
///
/// Pieces of the same shape cut along the same plane are the same pieces: their exact
/// shapes and rigid shapes are made once and shared (the grains of a specimen share one
/// prism, so most splits cost a lookup, not a CGAL call).

#include <Eigen/Dense>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "geometry/crystal.hpp"
#include "geometry/exact_polyhedron.hpp"
#include "geometry/specimen.hpp"
#include "physics/dem/world.hpp"

namespace cleave::physics {

/// One split, as logged.
struct SplitEvent {
  double time = 0.0;
  geometry::Lineage parent;                 ///< what broke
  std::vector<geometry::Lineage> pieces;    ///< what it became
  std::vector<BodyId> ids;                  ///< the pieces' bodies
  int plane = -1;                           ///< index into the grain's cleavage planes
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< the crack plane's normal, world
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< the parent's centroid, world
  /// The transgranular crack's area (m^2): the exact section of the cut (the `below`
  /// piece's face on the plane, ExactPolyhedron::area_on), rounded once.
  double section_area = 0.0;
};

class FractureBook {
 public:
  /// `dilation_radius` for the pieces' contact primitives; a cut leaving a piece below
  /// `min_fragment_fraction` of the body it cuts is refused.
  FractureBook(double dilation_radius, double min_fragment_fraction);

  /// Registers world shape `shape_index` as the exact `shape` (in grain coordinates).
  void add_shape(std::uint32_t shape_index, std::shared_ptr<const geometry::ExactPolyhedron> shape);
  /// Registers body `id` as intact grain `grain_id` of orientation `orientation`, made of
  /// the registered shape it was given in the world; its cleavage planes are those of the
  /// prism (ExactPolyhedron::cleavage_planes).
  void add_grain(const World& world, BodyId id, int grain_id,
                 const geometry::CrystalOrientation& orientation);
  /// As above with the grain's cleavage planes given (grain coordinates), e.g. a 3D
  /// crystal's (geometry::grain_cleavage_planes).
  void add_grain(const World& world, BodyId id, int grain_id, std::vector<geometry::ExactPlane> planes);
  /// The cleavage resistance of plane k of every grain (a 3D crystal's planes come in the
  /// same family order in every grain), the factor on the criterion's K_Ic or strength; 1
  /// for planes not given. Not checkpointed: it follows from the scenario, and a resumed
  /// run sets it again.
  void set_plane_resistance(std::vector<double> per_plane) { resistance_ = std::move(per_plane); }
  /// Cuts leaving a piece below `volume` (m^3) are refused from now on, as slivers are. Not
  /// checkpointed either: a resumed run sets it again from its scenario.
  void set_min_piece_volume(double volume) { min_volume_ = volume; }
  /// The resistance factor of cleavage plane `plane` (an index into a body's planes).
  [[nodiscard]] double resistance(int plane) const;

  /// Whether body `id` is registered (bodies that are not, e.g. fixed rig parts, never split).
  [[nodiscard]] bool knows(BodyId id) const;
  /// Indices (into `planes(id)`) of the cleavage planes that may still cut body `id`.
  [[nodiscard]] const std::vector<int>& candidates(BodyId id) const;
  /// The grain's cleavage planes, in grain coordinates.
  [[nodiscard]] const std::vector<geometry::ExactPlane>& planes(BodyId id) const;
  /// A plane's unit normal and a point on it, in the world, for body `id` as it is posed.
  [[nodiscard]] std::pair<Eigen::Vector3d, Eigen::Vector3d> world_plane(const World& world, BodyId id,
                                                                       int plane) const;
  [[nodiscard]] const geometry::Lineage& lineage(BodyId id) const;
  [[nodiscard]] const geometry::ExactPolyhedron& exact_shape(BodyId id) const;

  /// The area (m^2) of body `id`'s faces on its cleavage plane `plane` with the body on the
  /// plane's lower side (ExactPolyhedron::area_on): its share of the sections cut along
  /// that plane (each section is drawn and counted once, by the pieces below it). Zero
  /// when it has no such face. Memoised by shape and plane.
  [[nodiscard]] double section_area(BodyId id, int plane) const;
  /// When the cut along `plane` in body `id`'s lineage was made (s): its faces on that
  /// plane opened then. NaN when no cut of its lineage ran along it.
  [[nodiscard]] double opened_at(BodyId id, int plane) const;
  /// Grain `grain_id`'s transgranular crack area (m^2): per cleavage plane the exact sum
  /// of its live pieces' projected section areas (ExactPolyhedron::projected_area_on),
  /// turned into an area once per plane (ExactPlane::area_of_projection), then summed.
  /// The pieces' faces partition every section, so this is the sum of the sections of the
  /// grain's splits.
  [[nodiscard]] double grain_section_area(const World& world, int grain_id) const;

  /// Cuts body `id` exactly along its cleavage plane `plane` and replaces it in `world` by
  /// the two pieces (World::split_body: momentum kept, bonds follow their points). Returns
  /// the event, or nothing (no ids) when the cut is refused: the plane misses the body or
  /// leaves a piece below the minimum fraction (the plane is then dropped from the
  /// body's candidates).
  SplitEvent split(World& world, BodyId id, int plane);

  /// Every live body's lineage and exact shape, in slot order.
  struct Entry {
    BodyId id;
    geometry::Lineage lineage;
    std::shared_ptr<const geometry::ExactPolyhedron> shape;
  };
  [[nodiscard]] std::vector<Entry> entries(const World& world) const;

  /// Everything the book holds, for a checkpoint (io/checkpoint.hpp writes the exact shapes
  /// and planes as exact text): its settings, the exact shape of every world shape it
  /// knows, the cuts made so far, the cleavage plane sets (shared by a grain's pieces) and
  /// every slot's record (lineage, shape, remaining candidate planes).
  struct Saved {
    double dilation_radius = 0.0;
    double min_fragment_fraction = 0.0;
    std::vector<std::pair<std::uint32_t, std::shared_ptr<const geometry::ExactPolyhedron>>> shapes;
    struct Cut {
      std::uint32_t shape = 0;
      std::string plane;                   ///< ExactPlane::to_string
      std::vector<std::uint32_t> pieces;   ///< empty: the cut was refused
    };
    std::vector<Cut> cuts;
    std::vector<std::shared_ptr<const std::vector<geometry::ExactPlane>>> plane_sets;
    struct Body {
      std::uint32_t generation = 0;
      bool used = false;
      geometry::Lineage lineage;
      std::uint32_t shape = 0;
      int plane_set = -1;  ///< index into plane_sets; -1 for an unused slot
      std::vector<int> candidates;
      std::vector<std::pair<int, double>> opened;  ///< its lineage's cuts: (plane, time)
    };
    std::vector<Body> bodies;  ///< by slot
  };
  [[nodiscard]] Saved save() const;
  /// The book as saved, over `world` restored from the same checkpoint (whose rigid shapes
  /// the book's shapes refer to). Throws std::invalid_argument when they do not fit.
  static FractureBook restore(const Saved& saved, const World& world);

 private:
  struct Shape {
    std::shared_ptr<const geometry::ExactPolyhedron> exact;
    RigidShape rigid;
  };
  struct Record {
    std::uint32_t generation = 0;
    bool used = false;
    geometry::Lineage lineage;
    std::uint32_t shape = 0;  // world shape index
    std::shared_ptr<const std::vector<geometry::ExactPlane>> planes;
    std::vector<int> candidates;
    std::vector<std::pair<int, double>> opened;  // the cuts of its lineage: (plane, time)
  };
  const Record& record(BodyId id) const;
  /// Shape `shape`'s projected area on `plane` (ExactPolyhedron::projected_area_on), once.
  const geometry::ExactScalar& projected(std::uint32_t shape,
                                         const geometry::ExactPlane& plane) const;
  Record& record(BodyId id);

  double dilation_;
  double min_fraction_;
  double min_volume_ = 0.0;
  std::map<std::uint32_t, Shape> shapes_;  // by world shape index
  /// (shape, plane text) -> the two pieces' world shape indices (below, above); empty when
  /// the cut is refused.
  std::map<std::pair<std::uint32_t, std::string>, std::vector<std::uint32_t>> cuts_;
  std::vector<Record> by_slot_;
  std::vector<double> resistance_;  // by plane index
  /// (shape, plane text) -> projected_area_on; made again after a restore.
  mutable std::map<std::pair<std::uint32_t, std::string>, geometry::ExactScalar> projected_;
};

}  // namespace cleave::physics
