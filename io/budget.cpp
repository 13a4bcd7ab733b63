#include "io/budget.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <mutex>
#include <stdexcept>

#include "geometry/lattice.hpp"

namespace cleave::io {

namespace fs = std::filesystem;

// ---- input files ------------------------------------------------------------------------

std::string input_file_problem(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows symbolic links
  if (ec && st.type() != fs::file_type::not_found) return "cannot be read (" + ec.message() + ")";
  switch (st.type()) {
    case fs::file_type::regular:
      return {};
    case fs::file_type::not_found:
      return fs::is_symlink(fs::symlink_status(path, ec)) ? "is a symbolic link to nothing"
                                                          : "does not exist";
    case fs::file_type::directory:
      return "is a directory";
    case fs::file_type::fifo:
      return "is a FIFO (named pipe)";
    case fs::file_type::socket:
      return "is a socket";
    case fs::file_type::character:
      return "is a character device";
    case fs::file_type::block:
      return "is a block device";
    default:
      return "is not a regular file";
  }
}

void require_input_file(const fs::path& path) {
  const std::string problem = input_file_problem(path);
  if (!problem.empty())
    throw std::runtime_error(
        fmt::format("{}: it {}; cleave reads only regular files", path.string(), problem));
}

// ---- memory -----------------------------------------------------------------------------

std::uint64_t parse_memory_size(std::string_view text) {
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument(fmt::format(
        "memory size '{}': {} (give a number with K, M, G or T, e.g. 4G or 512M)", text, why));
  };
  std::string s(text);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  double value = 0.0;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, value);
  if (ec != std::errc() || ptr == s.data()) throw bad("not a number");
  std::string unit(ptr, end);
  std::transform(unit.begin(), unit.end(), unit.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (!unit.empty() && unit.front() == ' ') unit.erase(0, 1);
  double scale = 1.0;
  if (!unit.empty() && unit != "b") {
    const std::string_view prefixes = "kmgt";
    const std::size_t p = prefixes.find(unit.front());
    const std::string rest = unit.substr(1);
    if (p == std::string_view::npos || !(rest.empty() || rest == "b" || rest == "ib"))
      throw bad("unknown unit '" + unit + "'");
    scale = std::pow(1024.0, static_cast<double>(p + 1));
  }
  const double bytes = value * scale;
  if (!(bytes >= 1.0)) throw bad("must be at least 1 byte");
  if (!(bytes <= std::ldexp(1.0, 60))) throw bad("is above 2^60 bytes");
  return static_cast<std::uint64_t>(bytes);
}

std::string format_bytes(double bytes) {
  constexpr const char* kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (u < 6 && bytes >= 1024.0) {
    bytes /= 1024.0;
    ++u;
  }
  if (bytes >= 1024.0) return fmt::format("{:.3g} EiB", bytes);
  return fmt::format("{:.3g} {}", bytes, kUnits[u]);
}

namespace {

std::mutex g_limit_mutex;
MemoryLimit g_limit;  // bytes 0: not set

/// A number of kB from /proc/meminfo's line `key`, or 0.
std::uint64_t meminfo_kb(const std::string& key) {
  std::ifstream in("/proc/meminfo");
  std::string name;
  std::uint64_t kb = 0;
  std::string unit;
  while (in >> name >> kb) {
    std::getline(in, unit);
    if (name == key + ":") return kb;
  }
  return 0;
}

/// A cgroup v2 file holding one number (or "max"), or 0.
std::uint64_t cgroup_number(const char* file) {
  std::ifstream in(file);
  std::string text;
  if (!(in >> text) || text == "max") return 0;
  std::uint64_t v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  return ec == std::errc() ? v : 0;
}

}  // namespace

void set_memory_limit(std::uint64_t bytes, std::string what) {
  const std::lock_guard lock(g_limit_mutex);
  g_limit = MemoryLimit{bytes, std::move(what)};
}

MemoryLimit memory_limit() {
  {
    const std::lock_guard lock(g_limit_mutex);
    if (g_limit.bytes > 0) return g_limit;
  }
  MemoryLimit m;
  if (const std::uint64_t kb = meminfo_kb("MemAvailable"); kb > 0) {
    m.bytes = kb * 1024;
    m.what = "the memory available now (MemAvailable in /proc/meminfo)";
  } else {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) {
      m.bytes = static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
      m.what = "the machine's physical memory";
    }
  }
  // A container's own limit, when it is below what the machine has free.
  if (const std::uint64_t max = cgroup_number("/sys/fs/cgroup/memory.max"); max > 0) {
    const std::uint64_t used = cgroup_number("/sys/fs/cgroup/memory.current");
    const std::uint64_t left = max > used ? max - used : 0;
    if (m.bytes == 0 || left < m.bytes) {
      m.bytes = std::max<std::uint64_t>(left, 1);
      m.what = "the memory left to this container (cgroup memory.max)";
    }
  }
  if (m.bytes > 0) m.what += "; --max-memory sets another limit";
  return m;
}

// ---- specimen estimate ------------------------------------------------------------------

namespace {

constexpr double kSqrt3 = 1.7320508075688772;

/// floor(x) for a count, with the lattice's own tolerance on exact fits; 0 below zero.
double whole(double x) {
  return x < 0.0 ? 0.0 : std::floor(x + 1e-9);
}

}  // namespace

double lattice_grain_estimate(const geometry::SpecimenDef& def) {
  const double r = def.r, t = def.t, h = 1.5 * r;
  const Eigen::Vector3d& L = def.outline.size;
  const bool cell = def.keep == geometry::KeepRule::cell_inside;
  // Layers at z = t/2 + (k-1) t; rows at y = r + s h (s >= 0); along x a row-1 point every
  // sqrt3 r from sqrt3 r, a row-2 point from sqrt3 r / 2 (geometry/lattice.hpp).
  const double layers = cell ? whole(L.z() / t) : whole(L.z() / t + 0.5);
  const double per_row =
      cell ? 0.5 * (whole(L.x() / (kSqrt3 * r)) + whole(L.x() / (kSqrt3 * r) - 0.5))
           : 0.5 * (whole(L.x() / (kSqrt3 * r) + 0.5) + whole(L.x() / (kSqrt3 * r)));
  const double span_y = cell ? L.y() - 2.0 * r : L.y() - r;
  const double rows = span_y < -1e-9 * r ? 0.0 : whole(span_y / h) + 1.0;
  switch (def.outline.kind) {
    case geometry::Outline::Kind::disc: {
      // By area: a cell inside the circle has its centre about 0.93 r (between the apothem
      // and the corner distance) inside the rim.
      const double radius = 0.5 * L.x() - (cell ? 0.5 * (1.0 + 0.5 * kSqrt3) * r : 0.0);
      if (radius <= 0.0) return 0.0;
      return layers * M_PI * radius * radius / (1.5 * kSqrt3 * r * r);
    }
    case geometry::Outline::Kind::beam: {
      const double box = layers * rows * per_row;
      if (def.outline.notch_width <= 0.0 || def.outline.notch_depth <= 0.0) return box;
      // The rows the notch reaches lose the cells across its width.
      const double notched_rows = std::ceil(def.outline.notch_depth / h);
      const double lost = def.outline.notch_width / (kSqrt3 * r) + 1.0;
      return std::max(0.0, box - layers * std::min(rows, notched_rows) * lost);
    }
    default:
      return layers * rows * per_row;
  }
}

SpecimenEstimate estimate_specimen(const Scenario& s) {
  SpecimenEstimate e;
  const geometry::SpecimenDef& d = s.specimen;
  double own = 0.0;  // bytes of the grains' own exact shapes
  switch (d.kind) {
    case geometry::SpecimenKind::lattice:
      e.grains = lattice_grain_estimate(d);
      // Small lattices are counted exactly (no grain is built): an outline that holds none
      // is refused here rather than after the result folder is made.
      // Only where the lattice's candidate points are few: a thin outline of vast extent
      // holds no grain but would take as long to search as a full one.
      if (e.grains < 1e5 && d.r > 0.0 && d.t > 0.0 &&
          (d.outline.size.x() / (kSqrt3 * d.r) + 2.0) * (d.outline.size.y() / (1.5 * d.r) + 2.0) *
                  (d.outline.size.z() / d.t + 2.0) <
              1e7)
        e.grains =
            static_cast<double>(geometry::honeycomb_sites(d.r, d.t, d.outline, d.keep).size());
      break;
    case geometry::SpecimenKind::voronoi:
      e.grains = d.voronoi.cells;
      own = e.grains * kExactCellBytes;
      break;
    case geometry::SpecimenKind::meshes:
      e.grains = static_cast<double>(d.custom_grains.size());
      for (const auto& g : d.custom_grains)
        own += kExactCellBytes *
               std::max(1.0, static_cast<double>(g.shape.vertices_approx().size()) / 26.0);
      break;
  }
  e.bytes = kBaseBytes + own;
  if (s.dynamics.enabled) {
    e.contacts = e.grains * kContactsPerGrain;
    const bool bonds = std::any_of(s.stages.begin(), s.stages.end(), [](const StageDef& st) {
      return st.kind == StageDef::Kind::bond;
    });
    e.bonds = bonds ? e.grains * kBondsPerGrain : 0.0;
    e.bytes += e.grains * kBodyBytes + e.contacts * kContactBytes + e.bonds * kBondBytes;
  } else {
    e.bytes += e.grains * kGrainBytes;
  }
  return e;
}

namespace {

std::string keys_text(const std::vector<SizeKey>& keys) {
  std::string out;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    out += i == 0 ? "" : (i + 1 == keys.size() ? " and " : ", ");
    // No line for each: after an override (--set) the text is rewritten and its lines move;
    // the error's own position is the first key's.
    out += fmt::format("{} = {}", keys[i].key, keys[i].written);
  }
  return out;
}

}  // namespace

void check_specimen_budget(const Scenario& s, const std::vector<SizeKey>& keys) {
  if (keys.empty()) return;
  const SpecimenEstimate e = estimate_specimen(s);
  const SizeKey& first = keys.front();
  const auto refuse = [&](const std::string& message) {
    throw ScenarioError(s.source, first.at.line, first.at.column, first.key, message);
  };
  const bool lattice = s.specimen.kind == geometry::SpecimenKind::lattice;
  if (lattice && e.grains < 1.0) {
    const bool cell = s.specimen.keep == geometry::KeepRule::cell_inside;
    refuse(fmt::format(
        "{} make a specimen of no grain: {} (keep = \"{}\"); use a larger "
        "specimen or smaller grains",
        keys_text(keys),
        cell ? fmt::format("no whole lattice cell (a hexagon {:.4g} {} across its corners, "
                           "t thick) fits in the outline",
                           2.0 * s.specimen.r / length_unit_metres(s.length_unit), s.length_unit)
             : std::string("no lattice point lies inside the outline"),
        cell ? "cell_inside" : "centre_inside"));
  }
  const std::string holds = fmt::format("{} make {}about {:.3g} grains", keys_text(keys),
                                        lattice ? "a specimen of " : "", e.grains);
  if (e.grains > kMaxGrains) {
    refuse(fmt::format("{}; at most {:g} are supported: use a smaller specimen or larger grains",
                       holds, kMaxGrains));
  }
  const MemoryLimit limit = memory_limit();
  if (limit.bytes > 0 && e.bytes > static_cast<double>(limit.bytes)) {
    std::string parts = fmt::format("{:.3g} grains", e.grains);
    if (e.contacts > 0.0) parts += fmt::format(", {:.3g} contact points", e.contacts);
    if (e.bonds > 0.0) parts += fmt::format(", {:.3g} bonds", e.bonds);
    refuse(
        fmt::format("{}, which need about {} ({}), more than the limit of {} ({}); use a "
                    "smaller specimen or larger grains",
                    holds, format_bytes(e.bytes), parts,
                    format_bytes(static_cast<double>(limit.bytes)), limit.what));
  }
}

double cubic_lattice_bytes(double bodies) {
  return kBaseBytes + bodies * kCubicBodyBytes;
}

}  // namespace cleave::io
