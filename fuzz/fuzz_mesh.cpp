/// \file
/// libFuzzer target: the mesh-grain import, io::load_mesh_grains -- assimp's reader
/// (io::read_meshes) and the closed/manifold/oriented/convex checks and exact shape of
/// geometry::convex_shape_from_mesh -- on arbitrary bytes written to a file.
/// The file's extension follows its content, so the seeds stay plain mesh files: "ply..."
/// -> .ply, "solid..." -> .stl (ASCII), text with OBJ statements -> .obj, else .stl (binary).
/// An odd input length asks for the convex hull (convex_hull = true), an even one for the
/// mesh as given. Expected for bad input: io::MeshGrainError; anything else is a bug.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "io/mesh_grains.hpp"

namespace {

std::string extension_for(std::string_view bytes) {
  if (bytes.starts_with("ply")) return ".ply";
  if (bytes.starts_with("solid")) return ".stl";
  if (bytes.starts_with("v ") || bytes.starts_with("#") || bytes.starts_with("o ") ||
      bytes.starts_with("g ") || bytes.find("\nv ") != std::string_view::npos ||
      bytes.find("\nf ") != std::string_view::npos) {
    return ".obj";
  }
  return ".stl";
}

const std::filesystem::path& work_dir() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("cleave_fuzz_mesh_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  cleave::io::MeshGrainSpec spec;
  spec.file = work_dir() / ("grain" + extension_for(bytes));
  spec.convex_hull = size % 2 == 1;
  {
    std::ofstream out(spec.file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  try {
    auto grains = cleave::io::load_mesh_grains(spec);
    (void)grains;
  } catch (const cleave::io::MeshGrainError&) {
  }
  std::error_code ec;
  std::filesystem::remove(spec.file, ec);
  return 0;
}
