#pragma once
/// \file
/// What produced a result: the versions of the libraries cleave was built with and runs
/// on, for the `[provenance]` table of a result folder's manifest (io/result_dir.hpp).

#include <map>
#include <string>

namespace cleave::io {

/// "cgal_version", "assimp_version", "openvdb_version", "eigen_version", "openssl_version",
/// "tomlplusplus_version", "fmt_version", "compiler" -> version strings. CGAL, OpenVDB,
/// Eigen, toml++ and fmt from their version macros (the headers built against); assimp and
/// OpenSSL from the library linked in. Only this translation unit includes the version
/// headers of CGAL and OpenVDB (just their version macros, none of their code).
std::map<std::string, std::string> library_versions();

/// The current UTC time as "YYYY-MM-DDTHH:MM:SSZ".
std::string utc_now();

}  // namespace cleave::io
