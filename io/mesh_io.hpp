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
  scene,         ///< one file holding one named mesh per body (STL: one unnamed solid, below)
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
/// `dir` (created if missing). With MeshLayout::scene one file `<stem><ext>` holds one named
/// mesh per body; with per_fragment each body goes to `<mesh.name><ext>`. Each file is written
/// to a temporary name and renamed when complete. Returns the paths written.
/// Format limits: binary STL (through assimp 5.2) stores single precision, OBJ and ASCII STL
/// the shortest text of each double; an STL scene holds one solid (ASCII: named after the
/// stem), so it reads back as one mesh holding every body and the body names survive only in
/// per_fragment file names; OBJ keeps one named group ("g") per body and keeps polygons.
/// meshio 5+ and VTK's vtkOBJReader and vtkSTLReader read all three.
/// Throws MeshIoError naming the file for an empty scene, a mesh without faces or with an
/// out-of-range index, a per_fragment name that is not a plain file name or is used twice,
/// or any export or rename failure.
std::vector<std::filesystem::path> write_meshes(const std::vector<geometry::PolygonMesh>& meshes,
                                                const std::filesystem::path& dir,
                                                const std::string& stem, MeshFormat format,
                                                MeshLayout layout);

/// Reads every mesh of a file through assimp, joining face corners whose coordinates are
/// exactly equal (so STL facets share their corners; no distance tolerance). A mesh is named
/// after its own name, else its node, else the file stem (assimp's placeholder STL solid name
/// "AssimpScene" does not count). Faces come back as stored: triangles from STL, polygons
/// from OBJ. Throws MeshIoError naming the file for a missing, truncated or corrupt file, one
/// that holds no mesh, or one with point or line primitives or non-finite coordinates.
std::vector<geometry::PolygonMesh> read_meshes(const std::filesystem::path& file);

}  // namespace cleave::io
