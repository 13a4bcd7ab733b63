#pragma once
/// \file
/// ParaView output: VTK XML PolyData files (.vtp) and a .pvd collection that indexes them
/// by time, written by hand (no VTK dependency). Files are written atomically.

#include <Eigen/Dense>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "geometry/polygon_mesh.hpp"

namespace cleave::io {

/// Per-item data arrays: scalars (1 component), vectors (3), integer ids or strings (a
/// vtkStringArray: a wall's name).
struct FieldSet {
  std::map<std::string, std::vector<double>> scalars;
  std::map<std::string, std::vector<Eigen::Vector3d>> vectors;
  std::map<std::string, std::vector<long long>> ids;
  std::map<std::string, std::vector<std::string>> strings;
};

/// Bodies as polygons: every body's world-space mesh; `body_fields` hold one value per
/// body and are written as cell data (repeated on each of the body's faces). The same serves
/// for walls and crack faces, with another `index_name`.
struct BodyFrame {
  std::vector<geometry::PolygonMesh> meshes;
  FieldSet body_fields;
  /// The cell array giving each cell's mesh index.
  std::string index_name = "body_index";
  /// A field ParaView colours by when the file is opened (the cell data's active scalars);
  /// empty: none.
  std::string active_scalars;
};

/// Contacts (or bonds) as lines from `a[i]` to `b[i]` (a zero-length line is written as a
/// vertex, i.e. a point); `fields` hold one value per contact (cell data).
struct LinkFrame {
  std::vector<Eigen::Vector3d> a;
  std::vector<Eigen::Vector3d> b;
  FieldSet fields;
};

/// Writes a .vtp with raw binary appended data (as VTK's own writer does without base64;
/// ParaView 5.x opens it; strings are written inline as ASCII, VTK's way for a
/// vtkStringArray). Bodies get a cell array named `index_name` (the mesh's index in the
/// frame); links are written as Verts (zero-length links) then Lines, each in input order,
/// with a cell array "link_index" giving each cell's link number. NaN and +-inf are written
/// as they are. Field names must be non-empty, unique, free of control characters and not
/// the index array's name. Throws std::runtime_error naming the file for a field whose
/// length does not match, a bad name, a face with fewer than 3 or out-of-range vertices,
/// or a file that cannot be written.
void write_vtp(const std::filesystem::path& file, const BodyFrame& frame);
void write_vtp(const std::filesystem::path& file, const LinkFrame& frame);

/// A time series of files for ParaView: `add` records (time, file relative to the .pvd's
/// folder, part index) and rewrites the .pvd at once, so a run that stops early still has a
/// valid series of the frames written so far. `add` throws std::runtime_error for a
/// non-finite time, an empty file name or a failed write; a failed entry is not kept. A
/// dataset at the time and part of the last entry replaces that entry: one entry per time.
class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path pvd_file);
  void add(double time, const std::filesystem::path& relative_file, int part = 0);
  [[nodiscard]] const std::filesystem::path& file() const { return file_; }

  struct Entry {
    double time;
    std::string file;
    int part;
  };
  /// The datasets listed so far (a checkpoint keeps them) ...
  [[nodiscard]] const std::vector<Entry>& entries() const { return entries_; }
  /// ... and the list restored from one (the .pvd file is rewritten at the next add()).
  void restore(std::vector<Entry> entries) { entries_ = std::move(entries); }

 private:
  std::filesystem::path file_;
  std::vector<Entry> entries_;
};

}  // namespace cleave::io
