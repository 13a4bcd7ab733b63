#include "io/provenance.hpp"

// Version headers only: CGAL/version.h and openvdb/version.h define macros and pull in no
// CGAL or OpenVDB code (this TU compiles in a second, without CGAL's flags).
#include <CGAL/version.h>
#include <Eigen/Core>
#include <assimp/version.h>
#include <fmt/format.h>
#include <openssl/crypto.h>
#include <openvdb/version.h>
#include <toml++/toml.h>

#include <ctime>

namespace cleave::io {

std::map<std::string, std::string> library_versions() {
  return {
      {"cgal_version", CGAL_VERSION_STR},
      {"assimp_version", fmt::format("{}.{}.{}", aiGetVersionMajor(), aiGetVersionMinor(),
                                     aiGetVersionPatch())},
      {"openvdb_version", OPENVDB_LIBRARY_VERSION_STRING},
      {"eigen_version",
       fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)},
      {"openssl_version", OpenSSL_version(OPENSSL_VERSION)},
      {"tomlplusplus_version", fmt::format("{}.{}.{}", TOML_LIB_MAJOR, TOML_LIB_MINOR, TOML_LIB_PATCH)},
      {"fmt_version", fmt::format("{}.{}.{}", FMT_VERSION / 10000, FMT_VERSION / 100 % 100, FMT_VERSION % 100)},
#ifdef __clang__
      {"compiler", fmt::format("clang {}", __clang_version__)},
#else
      {"compiler", fmt::format("gcc {}", __VERSION__)},
#endif
  };
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace cleave::io
