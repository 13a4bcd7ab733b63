#pragma once
/// \file
/// Fragment meshes in and out through assimp: STL (binary, ASCII) and OBJ.

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/polygon_mesh.hpp"

namespace cleave::io {

/// Thrown when a mesh file cannot be read or written; the message names the file.
class MeshIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class MeshFormat { stl_binary, stl_ascii, obj };
enum class MeshLayout {
  scene,         ///< one file holding one named mesh per body
  per_fragment,  ///< one file per body, named after it
};

/// "stl", "stl_ascii", "obj" <-> MeshFormat; "scene", "per_fragment" <-> MeshLayout.
/// parse_* throw std::invalid_argument listing the accepted values.
std::string to_string(MeshFormat f);
std::string to_string(MeshLayout l);
MeshFormat parse_mesh_format(const std::string& s);
MeshLayout parse_mesh_layout(const std::string& s);
/// File extension with the dot: ".stl" or ".obj".
std::string extension(MeshFormat f);

/// Writes `meshes` (closed, outward polygon meshes; STL gets them fan-triangulated) into
/// `dir`. With MeshLayout::scene one file `<stem><ext>` holds one named mesh per body;
/// with per_fragment each body goes to `<mesh.name><ext>`. Each file is written to a
/// temporary name and renamed when complete. Returns the paths written.
std::vector<std::filesystem::path> write_meshes(const std::vector<geometry::PolygonMesh>& meshes,
                                                const std::filesystem::path& dir,
                                                const std::string& stem, MeshFormat format,
                                                MeshLayout layout);

/// Reads every mesh of a file through assimp, with identical vertices joined (normals are
/// dropped first so STL facets share their corners). Throws MeshIoError naming the file
/// for a missing, truncated or corrupt file, or one that holds no mesh.
std::vector<geometry::PolygonMesh> read_meshes(const std::filesystem::path& file);

}  // namespace cleave::io
