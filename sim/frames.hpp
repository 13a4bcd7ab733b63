#pragma once
/// \file
/// The ParaView frames of a dynamic run: at each frame, the bodies, contacts, bonds, walls,
/// cracks and periodic cell as .vtp files under frames/, listed in their .pvd series, and
/// optionally every body as a mesh (frame_meshes/). A frame holding a value that is not
/// finite is not written; the writer names the first such item.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "geometry/specimen.hpp"
#include "io/scenario.hpp"
#include "io/vtk_output.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"
#include "physics/transgranular/fracture_book.hpp"

namespace cleave::sim {

class FrameWriter {
 public:
  /// The scenario and the specimen must outlive the writer.
  FrameWriter(std::filesystem::path out, const io::Scenario& scenario,
              const geometry::Specimen& specimen);

  /// The frame of the world's present step. On several processes the whole world is
  /// gathered first (unless `gathered`: it is here already) and the first (`root`) writes.
  /// A second frame at the step of the last one replaces it. Returns what is not finite
  /// (the frame is then not written), as a sentence naming the item, or nullopt.
  std::optional<std::string> write(physics::World& world, const physics::FractureBook* book,
                                   bool root, bool gathered = false);

  /// Frames written so far, and the step of the last (~0 before the first).
  [[nodiscard]] int frames() const { return frames_; }
  [[nodiscard]] std::uint64_t last_step() const { return last_step_; }

  /// What a checkpoint keeps of the series: the count, the last step, the series' lists.
  void set_frames(int frames) { frames_ = frames; }
  void set_last_step(std::uint64_t step) { last_step_ = step; }
  void put_series(physics::StateWriter& w) const;
  /// `walls`, `cracks`: whether those series are written (they list the bodies' times).
  void get_series(physics::StateReader& r, bool walls, bool cracks);

 private:
  bool writes_walls(const physics::World& world) const { return !world.walls().empty(); }
  bool writes_cracks(const physics::FractureBook* book) const;
  void write_meshes(const physics::World& world, const physics::FractureBook* book,
                    const std::string& stem) const;

  std::filesystem::path out_;
  const io::Scenario& scenario_;
  const geometry::Specimen& specimen_;
  io::PvdSeries bodies_, contacts_, bonds_, cell_, walls_, cracks_;
  int frames_ = 0;
  std::uint64_t last_step_ = ~0ull;
};

/// A body's shape in its world pose.
geometry::PolygonMesh world_mesh(const physics::World& world, physics::BodyId id);

}  // namespace cleave::sim
