#include "io/mesh_io.hpp"

#include <assimp/material.h>
#include <assimp/mesh.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <sstream>
#include <string_view>
#include <system_error>
#include <utility>

#include "io/budget.hpp"
#include "io/result_dir.hpp"

// What is written (checked by tests/test_mesh_io.cpp, and with meshio and VTK's readers by
// tests/python/test_paraview_outputs.py):
//  * Binary STL goes through assimp ("stlb"): it runs aiProcess_PreTransformVertices and
//    writes every mesh of the scene under a single facet count. Mesh names are lost, and a
//    scene file reads back as one mesh holding all bodies (disjoint bodies stay disjoint;
//    bodies that touch share their coincident corners after the join in read_meshes).
//    Per-fragment STL files keep the name in the file name. assimp is built with
//    single-precision ai_real, and binary STL stores float32 anyway.
//  * OBJ and ASCII STL are written here, in double precision: assimp 5.2's OBJ has one
//    "vn" per distinct normal, which meshio refuses (it wants one per "v"), and its ASCII STL
//    a blank line between facets, which meshio's reader cannot skip. The OBJ has one
//    "g <mesh name>" group per body with its polygons as they are, no normals and no .mtl;
//    the ASCII STL one solid named after the file's stem (one solid, as assimp writes).
//  * aiProcess_JoinIdenticalVertices is not used on import: it also merges some distinct
//    vertices closer than about 1e-6 (absolute), see read_meshes.

namespace cleave::io {

namespace {

namespace fs = std::filesystem;
using geometry::PolygonMesh;

[[noreturn]] void fail(const fs::path& file, const std::string& what) {
  throw MeshIoError("mesh file '" + file.string() + "': " + what);
}

const char* assimp_format_id(MeshFormat f) {
  switch (f) {
    case MeshFormat::stl_binary:
      return "stlb";
    case MeshFormat::stl_ascii:
      return "stl";
    case MeshFormat::obj:
      return "obj";
  }
  throw std::invalid_argument("unknown MeshFormat value " + std::to_string(static_cast<int>(f)));
}

/// A file name component we are willing to create: non-empty, no separators, not "." or "..".
bool is_plain_file_name(const std::string& s) {
  return !s.empty() && s != "." && s != ".." &&
         s.find_first_of(std::string_view("/\\\0", 3)) == std::string::npos;
}

/// Checks what assimp would otherwise crash on or silently mangle.
void check_mesh(const PolygonMesh& mesh, const fs::path& file) {
  const std::string who = "mesh '" + mesh.name + "'";
  if (mesh.name.size() >= MAXLEN) fail(file, who + " has a name too long for assimp");
  if (mesh.vertices.empty() || mesh.faces.empty()) fail(file, who + " has no faces to write");
  const auto n = static_cast<long long>(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    const auto& f = mesh.faces[i];
    if (f.size() < 3) {
      fail(file, who + " face " + std::to_string(i) + " has " + std::to_string(f.size()) +
                     " vertices (need at least 3)");
    }
    for (int v : f) {
      if (v < 0 || v >= n) {
        fail(file, who + " face " + std::to_string(i) + " refers to vertex " + std::to_string(v) +
                       " of " + std::to_string(n));
      }
    }
  }
}

/// Unit normal of a planar polygon by Newell's method (zero for a degenerate face).
aiVector3D face_normal(const PolygonMesh& mesh, const std::vector<int>& face) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < face.size(); ++i) {
    const Eigen::Vector3d& a = mesh.vertices[face[i]];
    const Eigen::Vector3d& b = mesh.vertices[face[(i + 1) % face.size()]];
    n += Eigen::Vector3d((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                         (a.x() - b.x()) * (a.y() + b.y()));
  }
  const double len = n.norm();
  if (len > 0.0) n /= len;
  return {static_cast<ai_real>(n.x()), static_cast<ai_real>(n.y()), static_cast<ai_real>(n.z())};
}

/// The mesh in assimp's "verbose" layout: every face corner has its own vertex, carrying the
/// face's normal. The exporters then find normals already there and skip generating them:
/// the STL facet normals are the true face normals, the OBJ gets flat shading, and assimp
/// 5.2.5 never runs its non-verbose export path (MakeVerboseFormat, then normal generation,
/// then JoinIdenticalVertices), which crashes on some polygon meshes. The OBJ exporter merges
/// equal positions again when it writes, so the file still shares its vertices.
aiMesh* to_ai_mesh(const PolygonMesh& mesh) {
  std::size_t corners = 0;
  for (const auto& f : mesh.faces) corners += f.size();
  auto out = std::make_unique<aiMesh>();
  out->mName.Set(mesh.name);
  out->mMaterialIndex = 0;
  out->mNumVertices = static_cast<unsigned>(corners);
  out->mVertices = new aiVector3D[corners];
  out->mNormals = new aiVector3D[corners];
  out->mNumFaces = static_cast<unsigned>(mesh.faces.size());
  out->mFaces = new aiFace[mesh.faces.size()];
  unsigned next = 0;
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    const auto& f = mesh.faces[i];
    const aiVector3D normal = face_normal(mesh, f);
    aiFace& face = out->mFaces[i];
    face.mNumIndices = static_cast<unsigned>(f.size());
    face.mIndices = new unsigned[f.size()];
    for (std::size_t k = 0; k < f.size(); ++k) {
      const Eigen::Vector3d& p = mesh.vertices[f[k]];
      out->mVertices[next] = aiVector3D(static_cast<ai_real>(p.x()), static_cast<ai_real>(p.y()),
                                        static_cast<ai_real>(p.z()));
      out->mNormals[next] = normal;
      face.mIndices[k] = next++;
    }
    out->mPrimitiveTypes |= f.size() == 3 ? aiPrimitiveType_TRIANGLE : aiPrimitiveType_POLYGON;
  }
  return out.release();
}

/// An in-memory scene: one material, a root node, and per mesh a child node named after it
/// that references it (the OBJ exporter names its groups after the meshes it meets).
std::unique_ptr<aiScene> build_scene(const std::vector<const PolygonMesh*>& meshes) {
  auto scene = std::make_unique<aiScene>();

  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial* [1] { new aiMaterial() };
  const aiString material_name("cleave_fragment");
  scene->mMaterials[0]->AddProperty(&material_name, AI_MATKEY_NAME);
  const aiColor3D grey(0.7f, 0.7f, 0.7f);
  scene->mMaterials[0]->AddProperty(&grey, 1, AI_MATKEY_COLOR_DIFFUSE);

  const auto n = static_cast<unsigned>(meshes.size());
  scene->mNumMeshes = n;
  scene->mMeshes = new aiMesh*[n]();
  scene->mRootNode = new aiNode("root");
  scene->mRootNode->mNumChildren = n;
  scene->mRootNode->mChildren = new aiNode*[n]();
  for (unsigned i = 0; i < n; ++i) {
    scene->mMeshes[i] = to_ai_mesh(*meshes[i]);
    auto* node = new aiNode(meshes[i]->name);
    scene->mRootNode->mChildren[i] = node;
    node->mParent = scene->mRootNode;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{i};
  }
  return scene;
}

/// A fresh, empty directory inside `dir`, removed (with what is left in it) on destruction.
class StagingDir {
 public:
  StagingDir(const fs::path& dir, const fs::path& target) {
    static std::atomic<unsigned long> counter{0};
    std::random_device rd;
    for (int attempt = 0; attempt < 100; ++attempt) {
      const fs::path p =
          dir / (".cleave-tmp-" + std::to_string(rd()) + "-" + std::to_string(++counter));
      std::error_code ec;
      if (fs::create_directory(p, ec)) {
        path_ = p;
        return;
      }
      if (ec)
        fail(target,
             "cannot create a temporary directory in '" + dir.string() + "': " + ec.message());
    }
    fail(target, "cannot find a free temporary directory name in '" + dir.string() + "'");
  }
  StagingDir(const StagingDir&) = delete;
  StagingDir& operator=(const StagingDir&) = delete;
  ~StagingDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// A double as the shortest text that reads back as the same double.
void append_number(std::string& out, double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, res.ptr);
}

void append_point(std::string& out, const Eigen::Vector3d& p) {
  for (int k = 0; k < 3; ++k) {
    out += ' ';
    append_number(out, p[k]);
  }
}

/// Wavefront OBJ: every body's vertices, then its group and polygons (1-based indices
/// counting over the whole file).
std::string obj_text(const std::vector<const PolygonMesh*>& meshes) {
  std::string out = "# cleave fragments: one group per body, named after its lineage\n";
  std::size_t base = 1;
  for (const PolygonMesh* m : meshes) {
    out += "g ";
    out += m->name;
    out += '\n';
    for (const auto& v : m->vertices) {
      out += 'v';
      append_point(out, v);
      out += '\n';
    }
    for (const auto& f : m->faces) {
      out += 'f';
      for (int v : f) {
        out += ' ';
        out += std::to_string(base + static_cast<std::size_t>(v));
      }
      out += '\n';
    }
    base += m->vertices.size();
  }
  return out;
}

/// ASCII STL: one solid `name` holding every body's triangles, each with its face normal.
std::string stl_ascii_text(const std::vector<const PolygonMesh*>& triangulated,
                           const std::string& name) {
  std::string out = "solid " + name + "\n";
  for (const PolygonMesh* m : triangulated) {
    for (const auto& f : m->faces) {
      const aiVector3D n = face_normal(*m, f);
      out += "facet normal";
      append_point(out, Eigen::Vector3d(n.x, n.y, n.z));
      out += "\nouter loop\n";
      for (int v : f) {
        out += "vertex";
        append_point(out, m->vertices[static_cast<std::size_t>(v)]);
        out += '\n';
      }
      out += "endloop\nendfacet\n";
    }
  }
  out += "endsolid " + name + "\n";
  return out;
}

/// Writes `text` to `target` atomically (io::write_file_atomically), failing as a mesh error.
void write_text_file(const fs::path& target, const std::string& text) {
  try {
    write_file_atomically(target, text);
  } catch (const std::runtime_error& e) {
    fail(target, e.what());
  }
}

/// Exports `meshes` as one file `dir/file_name`. OBJ and ASCII STL are written here; assimp
/// writes binary STL into a staging directory next to the target, then each file it made is
/// renamed into `dir`, companions first and the main file last. Returns the final paths,
/// main file first.
std::vector<fs::path> export_file(const std::vector<const PolygonMesh*>& meshes,
                                  const fs::path& dir, const std::string& file_name,
                                  MeshFormat format) {
  const fs::path target = dir / file_name;
  const bool stl = format != MeshFormat::obj;
  std::vector<PolygonMesh> triangulated;
  std::vector<const PolygonMesh*> to_write;
  for (const PolygonMesh* m : meshes) {
    check_mesh(*m, target);
    if (stl) triangulated.push_back(m->triangulated());
  }
  if (stl) {
    for (const PolygonMesh& m : triangulated) to_write.push_back(&m);
  } else {
    to_write = meshes;
  }
  if (format == MeshFormat::obj) {
    write_text_file(target, obj_text(to_write));
    return {target};
  }
  if (format == MeshFormat::stl_ascii) {
    write_text_file(target, stl_ascii_text(to_write, fs::path(file_name).stem().string()));
    return {target};
  }
  const std::unique_ptr<aiScene> scene = build_scene(to_write);

  const StagingDir staging(dir, target);
  const fs::path staged = staging.path() / file_name;
  Assimp::Exporter exporter;
  aiReturn rc = aiReturn_FAILURE;
  try {
    rc = exporter.Export(scene.get(), assimp_format_id(format), staged.string());
  } catch (const std::exception& e) {
    fail(target, std::string("assimp export threw: ") + e.what());
  }
  if (rc != aiReturn_SUCCESS)
    fail(target, std::string("assimp export failed: ") + exporter.GetErrorString());

  std::error_code ec;
  if (!fs::is_regular_file(staged, ec)) fail(target, "assimp reported success but wrote nothing");
  std::vector<fs::path> companions;
  for (const auto& entry : fs::directory_iterator(staging.path(), ec)) {
    if (entry.path().filename() != staged.filename()) companions.push_back(entry.path());
  }
  if (ec) fail(target, "cannot list the temporary directory: " + ec.message());
  std::sort(companions.begin(), companions.end());

  std::vector<fs::path> written{target};
  for (const fs::path& p : companions) {
    const fs::path final_path = dir / p.filename();
    fs::rename(p, final_path, ec);
    if (ec) fail(final_path, "cannot rename the finished temporary file: " + ec.message());
    written.push_back(final_path);
  }
  fs::rename(staged, target, ec);
  if (ec) fail(target, "cannot rename the finished temporary file: " + ec.message());
  return written;
}

/// Name of the first node (depth first) that references mesh `index`, or "".
std::string node_name_for_mesh(const aiNode* node, unsigned index) {
  if (node == nullptr) return {};
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    if (node->mMeshes[i] == index) return {node->mName.C_Str(), node->mName.length};
  }
  for (unsigned i = 0; i < node->mNumChildren; ++i) {
    std::string s = node_name_for_mesh(node->mChildren[i], index);
    if (!s.empty()) return s;
  }
  return {};
}

/// The solid name assimp's STL exporter writes whatever the meshes are called.
constexpr std::string_view kAssimpStlSolidName = "AssimpScene";

/// Name for mesh `index` read from `file`: the mesh's own name, else the name of the node
/// holding it, else the file stem (with "_<index>" when the file holds several meshes).
/// Empty names and assimp's placeholder STL solid name do not count.
std::string mesh_name(const aiScene& scene, unsigned index, const fs::path& file) {
  const auto usable = [](const std::string& s) { return !s.empty() && s != kAssimpStlSolidName; };
  const aiString& own = scene.mMeshes[index]->mName;
  std::string name(own.C_Str(), own.length);
  if (usable(name)) return name;
  name = node_name_for_mesh(scene.mRootNode, index);
  if (usable(name)) return name;
  name = file.stem().string();
  if (scene.mNumMeshes > 1) name += "_" + std::to_string(index);
  return name;
}

}  // namespace

std::string to_string(MeshFormat f) {
  switch (f) {
    case MeshFormat::stl_binary:
      return "stl";
    case MeshFormat::stl_ascii:
      return "stl_ascii";
    case MeshFormat::obj:
      return "obj";
  }
  throw std::invalid_argument("unknown MeshFormat value " + std::to_string(static_cast<int>(f)));
}

std::string to_string(MeshLayout l) {
  switch (l) {
    case MeshLayout::scene:
      return "scene";
    case MeshLayout::per_fragment:
      return "per_fragment";
  }
  throw std::invalid_argument("unknown MeshLayout value " + std::to_string(static_cast<int>(l)));
}

MeshFormat parse_mesh_format(const std::string& s) {
  if (s == "stl") return MeshFormat::stl_binary;
  if (s == "stl_ascii") return MeshFormat::stl_ascii;
  if (s == "obj") return MeshFormat::obj;
  throw std::invalid_argument("unknown mesh format '" + s +
                              "' (accepted: \"stl\", \"stl_ascii\", \"obj\")");
}

MeshLayout parse_mesh_layout(const std::string& s) {
  if (s == "scene") return MeshLayout::scene;
  if (s == "per_fragment") return MeshLayout::per_fragment;
  throw std::invalid_argument("unknown mesh layout '" + s +
                              "' (accepted: \"scene\", \"per_fragment\")");
}

std::string extension(MeshFormat f) {
  switch (f) {
    case MeshFormat::stl_binary:
    case MeshFormat::stl_ascii:
      return ".stl";
    case MeshFormat::obj:
      return ".obj";
  }
  throw std::invalid_argument("unknown MeshFormat value " + std::to_string(static_cast<int>(f)));
}

std::vector<fs::path> write_meshes(const std::vector<PolygonMesh>& meshes, const fs::path& dir,
                                   const std::string& stem, MeshFormat format, MeshLayout layout) {
  const std::string ext = extension(format);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) fail(dir, "cannot create the output directory: " + ec.message());

  std::vector<fs::path> written;
  if (layout == MeshLayout::scene) {
    if (!is_plain_file_name(stem)) fail(dir / (stem + ext), "the stem is not a plain file name");
    if (meshes.empty()) fail(dir / (stem + ext), "no meshes to write");
    std::vector<const PolygonMesh*> all;
    for (const PolygonMesh& m : meshes) all.push_back(&m);
    return export_file(all, dir, stem + ext, format);
  }

  std::set<std::string> seen;
  for (const PolygonMesh& m : meshes) {
    const fs::path target = dir / (m.name + ext);
    if (!is_plain_file_name(m.name)) {
      fail(target, "mesh name '" + m.name + "' is not a plain file name");
    }
    if (!seen.insert(m.name).second) fail(target, "two meshes are named '" + m.name + "'");
  }
  for (const PolygonMesh& m : meshes) {
    std::vector<fs::path> files = export_file({&m}, dir, m.name + ext, format);
    written.insert(written.end(), files.begin(), files.end());
  }
  return written;
}

namespace {

/// assimp 5.2's PLY reader never returns on a header it cannot find the end of (it spins in
/// its buffer; found by fuzz/fuzz_mesh, tests/test_fuzz_regressions.cpp): no "end_header"
/// line, or one that a control character such as a vertical tab follows. So a PLY file
/// (".ply", or content starting "ply") whose header is not printable text ending in a line
/// "end_header" is refused before assimp sees it.
/// Its element counts are bounded by the file's size too: assimp reserves what the header
/// claims, so a short file claiming 10^8 vertices would take gigabytes and minutes. Each
/// element needs at least its properties' bytes (binary) or two characters per property
/// (ASCII: a digit and a separator; a list at least its count).
void check_ply_header(const fs::path& file, std::uintmax_t file_size) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  std::ifstream in(file, std::ios::binary);
  std::string line;
  if (!std::getline(in, line)) return;  // empty: assimp refuses it
  if (ext != ".ply" && !line.starts_with("ply")) return;
  struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::uint64_t bytes = 0;  // the least one element takes
  };
  std::vector<Element> elements;
  bool ascii = true;
  const auto scalar_size = [](const std::string& type) -> std::uint64_t {
    for (auto [names, size] : {std::pair<std::string_view, int>{" char int8 uchar uint8 ", 1},
                               {" short int16 ushort uint16 ", 2},
                               {" int int32 uint uint32 float float32 ", 4},
                               {" double float64 ", 8}})
      if (names.find(" " + type + " ") != std::string_view::npos)
        return static_cast<std::uint64_t>(size);
    return 1;  // an unknown type: assimp refuses it; count it small
  };
  do {
    // The header is text: spaces, tabs, a CR before the LF, and printable characters.
    for (const char c : line) {
      const auto u = static_cast<unsigned char>(c);
      if ((u < 0x20 && c != '\t' && c != '\r') || u >= 0x7f)
        fail(file, fmt::format("its PLY header holds the byte 0x{:02x}, which is not text (the "
                               "header is lines of printable characters)", u));
    }
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "end_header") {
      const std::streamoff at = in.tellg();
      const std::uintmax_t header = at < 0 ? file_size : static_cast<std::uintmax_t>(at);
      const std::uintmax_t body = file_size > header ? file_size - header : 0;
      double need = 0.0;
      for (const Element& e : elements) {
        need += static_cast<double>(e.count) * static_cast<double>(ascii ? 2 * e.bytes : e.bytes);
        // ASCII's last value needs no separator after it.
        if (need > static_cast<double>(body) + (ascii ? 1.0 : 0.0)) {
          fail(file,
               fmt::format("its PLY header claims {} '{}' elements, which take at least {:.0f} "
                           "bytes, but the file holds {} bytes after its header",
                           e.count, e.name, need - (ascii ? 1.0 : 0.0), body));
        }
      }
      return;
    }
    std::vector<std::string> rest;
    for (std::string w; words >> w;) rest.push_back(w);
    // assimp 5.2 corrupts its heap or crashes on an element declared twice and misreads
    // lines it does not know (fuzz/fuzz_mesh): only the PLY header's own lines pass.
    const auto malformed = [&](const std::string& why) {
      fail(file, "its PLY header line '" + line + "' " + why);
    };
    if (word == "format") {
      if (rest.size() != 2) malformed("is not 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      ascii = rest[0] == "ascii";
    } else if (word == "element") {
      if (rest.size() != 2) malformed("is not 'element NAME COUNT'");
      Element e;
      e.name = rest[0];
      const std::string& count = rest[1];
      const auto [ptr, ec] = std::from_chars(count.data(), count.data() + count.size(), e.count);
      if (ec != std::errc() || ptr != count.data() + count.size())
        fail(file, "PLY element '" + e.name + "' has no whole count ('" + count + "')");
      for (const Element& before : elements)
        if (before.name == e.name) malformed("declares the element '" + e.name + "' a second time");
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) malformed("gives a property before any element");
      const bool list = !rest.empty() && rest[0] == "list";
      if (rest.size() != (list ? 4u : 2u))
        malformed("is not 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
      // The count's type: a list may be empty.
      elements.back().bytes += ascii ? 1 : scalar_size(list ? rest[1] : rest[0]);
    } else if (word != "ply" && word != "comment" && word != "obj_info" && !word.empty()) {
      malformed("is not a PLY header line (ply, format, comment, obj_info, element, property, "
                "end_header)");
    }
  } while (std::getline(in, line));
  fail(file, "PLY header has no 'end_header' line");
}

}  // namespace

std::vector<PolygonMesh> read_meshes(const fs::path& file) {
  if (const std::string problem = input_file_problem(file); !problem.empty())
    fail(file, problem == "does not exist" ? "no such file"
                                           : "it " + problem + "; cleave reads only regular files");
  // Only the three formats cleave documents: assimp picks its reader by the extension, and
  // the others' headers are not bounded here.
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext != ".obj" && ext != ".stl" && ext != ".ply")
    fail(file,
         "cleave reads OBJ, STL and PLY meshes: the file name must end in .obj, .stl or .ply");
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) fail(file, "its size cannot be read (" + ec.message() + ")");
  check_ply_header(file, size);  // a binary STL's facet count assimp checks against the size

  // No aiProcess_JoinIdenticalVertices: assimp 5.2.5 also welds distinct vertices that lie
  // within about 1e-6 of each other (absolute, in file units, and only for some of them),
  // which at grain scale in metres merges real micrometre features. Corners are joined below
  // on bit-identical positions instead; every exporter writes a shared corner identically.
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(file.string(), aiProcess_ValidateDataStructure);
  } catch (const std::exception& e) {
    fail(file, std::string("assimp import threw: ") + e.what());
  }
  if (scene == nullptr) {
    fail(file, std::string("assimp cannot read it: ") + importer.GetErrorString());
  }
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0) {
    fail(file, "assimp read it only partially (scene flagged incomplete)");
  }
  if (scene->mNumMeshes == 0 || scene->mMeshes == nullptr) fail(file, "it holds no mesh");

  std::vector<PolygonMesh> out;
  out.reserve(scene->mNumMeshes);
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    const std::string which = "mesh " + std::to_string(mi);
    if (m == nullptr || m->mNumFaces == 0 || m->mNumVertices == 0 || m->mVertices == nullptr ||
        m->mFaces == nullptr) {
      fail(file, which + " has no faces");
    }
    PolygonMesh pm;
    pm.name = mesh_name(*scene, mi, file);

    // Corner index in the aiMesh -> joined vertex index, lazily for the corners faces use.
    std::map<std::array<ai_real, 3>, int> joined;
    std::vector<int> remap(m->mNumVertices, -1);
    const auto vertex = [&](unsigned idx, unsigned fi) {
      if (idx >= m->mNumVertices) {
        fail(file, which + " face " + std::to_string(fi) + " refers to a missing vertex");
      }
      if (remap[idx] < 0) {
        const aiVector3D& p = m->mVertices[idx];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
          fail(file, which + " has a non-finite vertex coordinate");
        }
        const auto [it, inserted] =
            joined.try_emplace({p.x, p.y, p.z}, static_cast<int>(pm.vertices.size()));
        if (inserted) pm.vertices.emplace_back(p.x, p.y, p.z);
        remap[idx] = it->second;
      }
      return remap[idx];
    };

    pm.faces.reserve(m->mNumFaces);
    for (unsigned fi = 0; fi < m->mNumFaces; ++fi) {
      const aiFace& f = m->mFaces[fi];
      if (f.mNumIndices < 3 || f.mIndices == nullptr) {
        fail(file, which + " face " + std::to_string(fi) + " has " + std::to_string(f.mNumIndices) +
                       " vertices (points and lines do not bound a volume)");
      }
      std::vector<int> face;
      face.reserve(f.mNumIndices);
      for (unsigned k = 0; k < f.mNumIndices; ++k) face.push_back(vertex(f.mIndices[k], fi));
      pm.faces.push_back(std::move(face));
    }
    out.push_back(std::move(pm));
  }
  return out;
}

}  // namespace cleave::io
