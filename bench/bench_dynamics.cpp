// DEM step cost: a poured pile, a packed box and falling grains of N hexagonal prisms.
//   ./build/bench/cleave_bench_dynamics [--full-search] [--pile DIR] [--tiles] [--steps K]
//                                       [poured|packed|falling ...] [N ...]
//   (default: all three cases, N = 168 1000 10000 100000)
// --pile DIR keeps each poured pile in DIR/pile-<n>.bin and reuses it on the next run (the
// pour takes a minute; a file of the wrong length, e.g. from a build with another state
// layout, is poured again), and the settled world of each poured case, tiles and contact
// histories, in DIR/world-<N>.state (World::save_state; made again when its tile or the
// state layout differs; another build reuses it, so two builds are timed from one state),
// which saves the 2,000 settling steps of the tiles; --tiles leaves those steps out and times
// the tiles' copies as they lie (no DIR/world file): the same bodies for any build, where
// each build's settling ends in a pile of its own; --steps K times
// K steps per case instead of 2e6/N (3 to 200); --phases prints, under each case, where its
// timed steps went (World::set_timing: search, narrow phase, contact law, bonds, ...).
// CLEAVE_BENCH_HASH=1 prints each case's state hash after its timed steps (World::state_hash):
// two builds that should give the same bits can be checked on the same cases.
// For each case, in its own child process (so peak memory is its own): build the world,
// take a few warm-up steps, time a fixed number of steps at the stable time step in blocks
// of 10 and print microseconds per step (of the median block), nanoseconds per primitive contact,
// touching body pairs and contacts per body, the cost per touching pair, and the peak resident
// memory. Finally the exponent of a log-log fit of step time against N. --full-search turns the
// narrow phase's near-feature cache off (WorldSettings::feature_skin = 0), for comparison.
//
// Poured pile (the settled pile): prisms of random orientation poured into a box and left
// to settle under gravity (pour); N above 1,000 are copies of one poured 1,000-prism pile
// side by side, settled again together.
// Packed box (the worst case): a box of prisms on the honeycomb lattice (r = t = 1 mm) on a
// floor, every grain pressed 5 um into its neighbours' dilated surfaces: every grain touches
// its 6 in-plane and 2 stacked neighbours face to face, 5 contacts a pair.
// Falling grains: the same lattice with 0.2 mm gaps, high above the floor: bounding spheres
// overlap, so the broad phase and the narrow phase's early outs are what is measured.

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "geometry/specimen.hpp"
#include "geometry/rng.hpp"
#include "physics/dem/contact_law.hpp"
#include "io/result_dir.hpp"
#include "physics/dem/state_codec.hpp"
#include "physics/dem/world.hpp"
#include "step_phases.hpp"

using namespace cleave;

namespace {

constexpr double kR = 1e-3, kT = 1e-3, kDilation = 0.05e-3, kRho = 3100.0;
constexpr int kTile = 1000;  // bodies poured at once for the poured pile
double g_feature_skin = 0.5;  // WorldSettings::feature_skin of every case (--full-search: 0)
double g_manifold = 0.0;       // WorldSettings::manifold_tolerance (--manifold TOL)
bool g_phases = false;         // --phases: where each case's step goes (World::set_timing)
// --tiles: the poured pile as the tile's copies, not settled together (no --pile world): the
// same bodies for any build, where each build's 2,000 settling steps end in another pile.
bool g_tiles = false;
std::string g_pile_dir;        // --pile DIR, or empty
int g_steps = 0;              // timed steps per case (0: 2e6/N, clamped to 3..200)

struct Result {
  double us_per_step = 0, contacts = 0, touching_pairs = 0, bodies = 0, peak_mib = 0;
  physics::StepTimings phases;  // --phases
};

/// Every case's contact parameters (table 2.3's particle set, mu_s = 0.3) and the stable
/// step for them. The timed steps run at this step, so that the bodies move as they would.
physics::WorldSettings bench_settings(const physics::RigidShape& shape) {
  physics::WorldSettings ws;
  ws.gravity = {0, 0, -9.81};
  ws.particle_particle.kn = 5000;
  ws.particle_particle.ks = 2000;
  ws.particle_particle.c_res = 2;
  ws.particle_particle.mu_s = 0.3;
  ws.particle_wall = ws.particle_particle;
  ws.local_damping = 0.7;  // the poured pile's settling
  ws.feature_skin = g_feature_skin;
  ws.manifold_tolerance = g_manifold;
  // The stable step as cleave's scenario check computes it (sim/world_assembly.cpp): 0.2 of
  // 2 sqrt(m/k) for translation and for rotation about the weakest axis, with the stiffest
  // spring C_res K_n acting at the bounding radius.
  const double k = ws.particle_particle.c_res * ws.particle_particle.kn;
  const double arm = shape.bounding_radius();
  ws.dt = 0.2 * std::min(physics::critical_time_step(kRho * shape.volume, k),
                         physics::critical_time_step(kRho * shape.principal_moments.minCoeff(), k * arm * arm));
  return ws;
}

physics::World make_case(int n, bool settled, int& bodies) {
  // A box of about n cells: 4 layers, square footprint.
  const double cell_area = 1.5 * std::sqrt(3.0) * kR * kR;
  const double side = std::sqrt(n / 4.0 * cell_area) + kR;
  geometry::SpecimenDef def;
  def.outline = geometry::Outline::box(side, side, 4 * kT);
  def.r = kR;
  def.t = kT;
  const double press = settled ? 5e-6 : -0.2e-3;  // overlap of the dilated surfaces
  def.r_bar = kR - (2 * kDilation - press) / std::sqrt(3.0);
  def.t_bar = kT - (2 * kDilation - press);
  const geometry::Specimen s = geometry::build_specimen(def);
  const physics::RigidShape shape = physics::make_rigid_shape(s.prism, kDilation);
  physics::WorldSettings ws = bench_settings(shape);
  ws.local_damping = 0.0;
  // A tiny step keeps the configuration (and so the contact count) what it was built as
  // over the timed steps (at the stable step the pressed box springs apart): a step's cost
  // does not depend on dt, but with nothing moving every pair's near-feature cache holds.
  ws.dt = 1e-8;
  physics::World world(ws);
  const auto sh = world.add_shape(shape);
  const double lift = settled ? (kDilation - press / 2) : 0.05;
  for (const auto& g : s.grains) {
    world.add_body(sh, 3100.0, g.site.centre + Eigen::Vector3d(0, 0, lift - kT / 2 + def.t_bar / 2),
                   shape.orientation_for());
  }
  world.add_wall(physics::Wall::plane("floor", {0, 0, 0}, {0, 0, 1}));
  bodies = static_cast<int>(s.grains.size());
  return world;
}

physics::RigidShape poured_shape() {
  geometry::SpecimenDef def;
  def.outline = geometry::Outline::box(3 * kR, 3 * kR, kT);
  def.r = kR;
  def.t = kT;
  def.r_bar = kR - 2 * kDilation / std::sqrt(3.0);
  def.t_bar = kT - 2 * kDilation;
  return physics::make_rigid_shape(geometry::build_specimen(def).prism, kDilation);
}

/// A poured pile's bodies, positions relative to its box's corner.
struct Pile {
  std::vector<physics::BodyState> bodies;
  double side = 0;  ///< the box's inner side
  int steps = 0;    ///< steps taken to pour it
  double seconds = 0;
};

/// Pours n prisms of random orientation (uniform rotations, fixed seed), from a loose grid
/// of 2.3 mm pitch about 6 layers high, into a square box of four side walls and a floor,
/// under gravity with local damping 0.7, until the kinetic energy is below 1e-4 of the
/// potential energy released (at least 20,000 steps; about 1e-4 is where a pile of
/// frictional prisms keeps creeping).
Pile pour(int n) {
  const physics::RigidShape shape = poured_shape();
  physics::World world(bench_settings(shape));
  const auto sh = world.add_shape(shape);
  const double pitch = 2.3e-3;
  const int m = static_cast<int>(std::ceil(std::sqrt(n / 6.0)));
  Pile pile;
  pile.side = m * pitch;
  geometry::SplitMix64 rng(2026);
  for (int i = 0; i < n; ++i) {
    const int layer = i / (m * m), k = i % (m * m);
    const Eigen::Vector3d x((k % m + 0.5) * pitch, (k / m + 0.5) * pitch, (layer + 0.5) * pitch);
    const double u1 = rng.uniform(), u2 = 2 * M_PI * rng.uniform(), u3 = 2 * M_PI * rng.uniform();
    const Eigen::Quaterniond q(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
                               std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
    world.add_body(sh, kRho, x, q);
  }
  world.add_wall(physics::Wall::plane("floor", {0, 0, 0}, {0, 0, 1}));
  world.add_wall(physics::Wall::plane("x0", {0, 0, 0}, {1, 0, 0}));
  world.add_wall(physics::Wall::plane("x1", {pile.side, 0, 0}, {-1, 0, 0}));
  world.add_wall(physics::Wall::plane("y0", {0, 0, 0}, {0, 1, 0}));
  world.add_wall(physics::Wall::plane("y1", {0, pile.side, 0}, {0, -1, 0}));
  const double pe0 = world.potential_energy();
  const auto t0 = std::chrono::steady_clock::now();
  for (int step = 1;; ++step) {
    world.step();
    if (step % 1000 == 0) {
      const double ratio = world.kinetic_energy() / (pe0 - world.potential_energy());
      if ((step >= 20000 && ratio < 1e-4) || step >= 150000) {
        pile.steps = step;
        break;
      }
    }
  }
  pile.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (const auto& id : world.body_ids()) pile.bodies.push_back(world.state(id));
  return pile;
}

/// Poured pile of n prisms: copies of one poured tile side by side on one floor (a tile's
/// side walls are left out; 0.5 mm between tiles), then 2,000 steps for the copies to
/// take up their shear springs again.
physics::World make_poured(int n, const Pile& tile, int& bodies) {
  const physics::RigidShape shape = poured_shape();
  physics::World world(bench_settings(shape));
  const auto sh = world.add_shape(shape);
  const int per_tile = static_cast<int>(tile.bodies.size());
  const int tiles = (n + per_tile - 1) / per_tile;
  const int columns = static_cast<int>(std::ceil(std::sqrt(tiles)));
  const double pitch = tile.side + 0.5e-3;
  for (int t = 0; t < tiles; ++t) {
    const Eigen::Vector3d offset((t % columns) * pitch, (t / columns) * pitch, 0.0);
    for (const auto& b : tile.bodies) world.add_body(sh, kRho, b.x + offset, b.q, b.v, b.w);
  }
  world.add_wall(physics::Wall::plane("floor", {0, 0, 0}, {0, 0, 1}));
  for (int i = 0; i < (g_tiles ? 0 : 2000); ++i) world.step();
  bodies = tiles * per_tile;
  return world;
}

/// A kept file's bytes, or none when there is no such file or it cannot be read.
std::string read_kept(const std::string& path) {
  try {
    return std::filesystem::exists(path) ? io::read_file(path) : std::string();
  } catch (const std::exception&) {
    return {};
  }
}

/// Writes `bytes` to `path` (whole or not at all), or warns.
void keep_file(const std::string& path, const std::string& bytes) {
  try {
    io::write_file_atomically(path, bytes);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "warning: could not keep %s (%s)\n", path.c_str(), e.what());
  }
}

/// FNV-1a of a pile's bodies' positions, orientations and velocities (not their padding):
/// which tile a kept world was made from.
std::uint64_t tile_hash(const Pile& tile) {
  std::uint64_t h = 1469598103934665603ull;
  auto add = [&h](const double* v, int n) {
    const auto* p = reinterpret_cast<const unsigned char*>(v);
    for (std::size_t i = 0; i < n * sizeof(double); ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  for (const auto& b : tile.bodies) {
    add(b.x.data(), 3);
    add(b.q.coeffs().data(), 4);
    add(b.v.data(), 3);
    add(b.w.data(), 3);
  }
  return h;
}

/// make_poured, or with --pile the world it made before from the same tile, read back bit
/// for bit (so the timed steps are the same either way).
physics::World poured_world(int n, const Pile& tile, int& bodies) {
  const std::string kept = g_pile_dir.empty() ? std::string() : g_pile_dir + "/world-" + std::to_string(n) + ".state";
  const std::uint64_t hash = tile_hash(tile);
  if (!kept.empty()) {
    const std::string bytes = read_kept(kept);
    if (bytes.size() > sizeof hash && std::memcmp(bytes.data(), &hash, sizeof hash) == 0) {
      physics::World world(bench_settings(poured_shape()));
      try {
        physics::StateReader r(std::string_view(bytes).substr(sizeof hash));
        world.load_state(r);
        bodies = static_cast<int>(world.body_ids().size());
        std::printf("(settled pile of %d prisms reused from %s)\n", bodies, kept.c_str());
        std::fflush(stdout);
        return world;
      } catch (const physics::StateError&) {
        // another build's state layout: made again below
      }
    }
  }
  physics::World world = make_poured(n, tile, bodies);
  if (!kept.empty()) {
    physics::StateWriter w;
    world.save_state(w);
    std::string bytes(reinterpret_cast<const char*>(&hash), sizeof hash);
    bytes += w.bytes();
    keep_file(kept, bytes);
  }
  return world;
}

enum class Case { poured, packed, falling };
const char* name(Case c) { return c == Case::poured ? "poured" : c == Case::packed ? "packed" : "falling"; }

Result run_case(int n, Case kind, const Pile& tile) {
  Result r;
  int bodies = 0;
  physics::World world = kind != Case::poured ? make_case(n, kind == Case::packed, bodies)
                         : g_tiles ? make_poured(n, tile, bodies) : poured_world(n, tile, bodies);
  r.bodies = bodies;
  for (int i = 0; i < 3; ++i) world.step();  // warm-up: buffers, contact history
  world.set_timing(g_phases);
  const int steps = g_steps > 0 ? g_steps : std::clamp(static_cast<int>(2e6 / std::max(1, bodies)), 3, 200);
  // Timed in blocks of 10 steps; the median block is reported, which a moment of
  // interference from elsewhere on the machine does not move.
  constexpr int kBlock = 10;
  std::vector<double> blocks;
  auto t0 = std::chrono::steady_clock::now();
  double contacts = 0, pairs = 0;
  for (int i = 0; i < steps; ++i) {
    world.step();
    if ((i + 1) % kBlock == 0 || i + 1 == steps) {
      const auto t1 = std::chrono::steady_clock::now();
      blocks.push_back(std::chrono::duration<double>(t1 - t0).count() / ((i % kBlock) + 1));
      contacts += static_cast<double>(world.contacts().size()) * ((i % kBlock) + 1);
      t0 = std::chrono::steady_clock::now();
    }
    std::set<std::pair<std::uint32_t, std::uint32_t>> touching;
    if (i == steps - 1) {
      for (const auto& c : world.contacts()) {
        if (!c.wall) touching.emplace(c.a, c.b);
      }
      pairs = static_cast<double>(touching.size());
    }
  }
  std::sort(blocks.begin(), blocks.end());
  r.us_per_step = 1e6 * blocks[blocks.size() / 2];
  r.contacts = contacts / steps;
  r.touching_pairs = pairs;
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  r.peak_mib = u.ru_maxrss / 1024.0;
  r.phases = world.timings();
  if (const char* h = std::getenv("CLEAVE_BENCH_HASH"); h != nullptr && *h != '\0' && *h != '0')
    std::printf("  state hash after %d steps: %016llx\n", steps,
                static_cast<unsigned long long>(world.state_hash()));
  std::fflush(stdout);  // (the child leaves by _exit)
  return r;
}


/// Runs `work` in a child process and returns the bytes it produced (OpenMP's threads do
/// not survive a fork, so everything that steps a world runs in a child of its own; each
/// child's peak memory is its own too). Exits on failure.
template <class Work>
std::string in_child(Work work) {
  int fd[2];
  if (pipe(fd) != 0) std::exit(1);
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    const std::string bytes = work();
    for (std::size_t done = 0; done < bytes.size();) {
      const ssize_t k = write(fd[1], bytes.data() + done, bytes.size() - done);
      if (k <= 0) std::_Exit(1);
      done += static_cast<std::size_t>(k);
    }
    std::_Exit(0);
  }
  close(fd[1]);
  std::string bytes;
  char buffer[65536];
  for (ssize_t k; (k = read(fd[0], buffer, sizeof buffer)) > 0;) bytes.append(buffer, static_cast<std::size_t>(k));
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.empty()) {
    std::fprintf(stderr, "a benchmark child failed\n");
    std::exit(1);
  }
  return bytes;
}

template <class T>
std::string as_bytes(const T& value) {
  return std::string(reinterpret_cast<const char*>(&value), sizeof value);
}

}  // namespace

int usage(const char* why) {
  std::fprintf(stderr,
               "cleave_bench_dynamics: %s\nusage: cleave_bench_dynamics [--full-search] [--manifold TOL] [--pile DIR] [--tiles] [--phases] "
               "[--steps K] [poured|packed|falling ...] [N ...]\n",
               why);
  return 2;
}

int main(int argc, char** argv) {
  std::vector<int> sizes;
  std::vector<Case> kinds;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--tiles") {
      g_tiles = true;
    } else if (arg == "--phases") {
      g_phases = true;
    } else if (arg == "--full-search") {
      g_feature_skin = 0.0;
    } else if (arg == "--pile" || arg == "--steps" || arg == "--manifold") {
      if (i + 1 == argc) return usage(("'" + arg + "' needs a value").c_str());
      if (arg == "--manifold") {
        char* end = nullptr;
        g_manifold = std::strtod(argv[++i], &end);
        if (*end != '\0' || !(g_manifold >= 0.0 && g_manifold < 1.0))
          return usage("--manifold needs a tolerance in [0, 1) (a fraction of the pair's dilation radii)");
      } else if (arg == "--pile") {
        g_pile_dir = argv[++i];
      } else if ((g_steps = std::atoi(argv[++i])) <= 0) {
        return usage("--steps needs a positive number of steps");
      }
    } else if (arg == name(Case::poured) || arg == name(Case::packed) || arg == name(Case::falling)) {
      kinds.push_back(arg == name(Case::poured) ? Case::poured : arg == name(Case::packed) ? Case::packed : Case::falling);
    } else if (const int n = std::atoi(argv[i]); n > 0 && std::to_string(n) == arg) {
      sizes.push_back(n);
    } else {
      return usage(("unknown argument '" + arg + "'").c_str());
    }
  }
  if (sizes.empty()) sizes = {168, 1000, 10000, 100000};
  if (kinds.empty()) kinds = {Case::poured, Case::packed, Case::falling};
  std::printf("near-feature cache: %s\n", g_feature_skin > 0 ? "on (feature_skin 0.5)" : "off (--full-search)");
  if (g_manifold > 0)
    std::printf("persistent contact manifolds: on (manifold_tolerance %g: an approximation)\n", g_manifold);
  std::printf("%-8s %8s %12s %14s %14s %12s %16s %10s\n", "case", "bodies", "us/step",
              "ns/contact", "touching pairs", "contacts/body", "us/pair/step", "peak MiB");
  // The poured piles: one per size below a tile, one tile for the rest.
  std::map<int, Pile> piles;
  for (int n : sizes) {
    const int size = std::min(n, kTile);
    if (piles.count(size) != 0 || std::find(kinds.begin(), kinds.end(), Case::poured) == kinds.end()) continue;
    const std::string cached = g_pile_dir.empty() ? std::string() : g_pile_dir + "/pile-" + std::to_string(size) + ".bin";
    std::string bytes;
    bool reused = false;
    if (!cached.empty()) {
      bytes = read_kept(cached);
      const std::size_t header = sizeof(Pile::side) + sizeof(Pile::steps) + sizeof(Pile::seconds);
      reused = bytes.size() == header + static_cast<std::size_t>(size) * sizeof(physics::BodyState);
      if (!reused) bytes.clear();  // not a pile of this size from this build: pour again
    }
    if (bytes.empty()) {
      bytes = in_child([size] {
        const Pile p = pour(size);
        std::string out = as_bytes(p.side) + as_bytes(p.steps) + as_bytes(p.seconds);
        for (const auto& b : p.bodies) out += as_bytes(b);
        return out;
      });
      if (!cached.empty()) keep_file(cached, bytes);
    }
    Pile& p = piles[size];
    std::size_t at = 0;
    auto take = [&](auto& value) {
      std::memcpy(static_cast<void*>(&value), bytes.data() + at, sizeof value);
      at += sizeof value;
    };
    take(p.side);
    take(p.steps);
    take(p.seconds);
    while (at + sizeof(physics::BodyState) <= bytes.size()) take(p.bodies.emplace_back());
    std::printf("(poured %d prisms in %d steps, %.0f s%s%s)\n", size, p.steps, p.seconds,
                reused ? "; reused from " : "", reused ? cached.c_str() : "");
    std::fflush(stdout);
  }
  for (const Case kind : kinds) {
    std::vector<std::pair<double, double>> fit;  // (log N, log us/step)
    for (int n : sizes) {
      const Pile& tile = kind == Case::poured ? piles.at(std::min(n, kTile)) : Pile{};
      const std::string bytes = in_child([&] { return as_bytes(run_case(n, kind, tile)); });
      Result r;
      std::memcpy(&r, bytes.data(), sizeof r);
      std::printf("%-8s %8.0f %12.1f %14.1f %14.0f %12.2f %16.3f %10.1f\n",
                  name(kind), r.bodies, r.us_per_step,
                  r.contacts > 0 ? 1e3 * r.us_per_step / r.contacts : 0.0, r.touching_pairs,
                  r.contacts / r.bodies, r.touching_pairs > 0 ? r.us_per_step / r.touching_pairs : 0.0,
                  r.peak_mib);
      if (g_phases) cleave::bench::print_phases("where the step goes (mean of the timed steps)", r.phases);
      std::fflush(stdout);
      fit.emplace_back(std::log(r.bodies), std::log(r.us_per_step));
    }
    if (fit.size() >= 2) {
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (const auto& [x, y] : fit) {
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
      }
      const double k = static_cast<double>(fit.size());
      std::printf("%-8s cost per step ~ N^%.3f (least squares on log-log)\n",
                  name(kind), (k * sxy - sx * sy) / (k * sxx - sx * sx));
    }
  }
  return 0;
}
