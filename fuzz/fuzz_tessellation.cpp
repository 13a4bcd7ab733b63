/// \file
/// libFuzzer target: the microstructure imports -- io::parse_neper_tess (a Neper .tess,
/// rebuilt as exact Laguerre cells and checked against the file's vertices) and
/// io::parse_grain_file (centroids, volumes and Bunge angles, weights fitted) -- on
/// arbitrary text. Input starting with "***tess" goes to the .tess reader, anything else to
/// the grain-file reader in a unit box. Expected for bad input: io::TessellationFileError;
/// anything else is a bug.

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/neper_tess.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    if (text.rfind("***tess", 0) == 0) {
      (void)cleave::io::parse_neper_tess(text, "fuzz.tess");
    } else {
      (void)cleave::io::parse_grain_file(text, "fuzz.txt", 1.0, Eigen::Vector3d::Ones());
    }
  } catch (const cleave::io::TessellationFileError&) {
  }
  return 0;
}
