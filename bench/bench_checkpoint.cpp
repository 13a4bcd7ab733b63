// Checkpoint cost for a large specimen:
//   ./build/bench/cleave_bench_checkpoint [GRAINS] [DIR]     (default 10000, /tmp)
// A bonded Brazilian disc of about GRAINS prisms (the lattice of scenarios/brazilian.toml
// with the disc widened, as in bench_fracture.cpp) with transgranular fracture registered
// for every grain, squeezed for a few hundred steps so it has contacts with history, bond
// states and some splits; then the checkpoint (io/checkpoint.hpp) is encoded, written
// (fsync + rename), read back and decoded, and the restored world's state hash compared.
// Prints the size and each time (best of 3).

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "geometry/specimen.hpp"
#include "io/checkpoint.hpp"
#include "physics/transgranular/fracture_book.hpp"
#include "physics/transgranular/transgranular.hpp"
#include "physics/dem/world.hpp"
#include "bench_disc.hpp"

using namespace cleave;
using namespace cleave::physics;

using cleave::bench::Clock;
using cleave::bench::since;

int main(int argc, char** argv) {
  const int grains = argc > 1 ? std::atoi(argv[1]) : 10000;
  const std::filesystem::path dir = argc > 2 ? argv[2] : std::filesystem::temp_directory_path();

  // The disc of bench_fracture.cpp, every grain registered for splitting.
  const auto t_build = Clock::now();
  bench::Disc disc = bench::make_disc(grains, true);
  World& world = disc.world;
  FractureBook& book = *disc.book;
  const geometry::Specimen& specimen = disc.specimen;
  const std::size_t bonds = world.bonds().size();
  // Squeeze it with the gate open, so grains split and the book holds fragments too.
  FractureParams fp;
  fp.sigma_f_hyd = -1e30;
  fp.k_ic = 1e-6;
  fp.crack_length = 0.1e-3;
  std::size_t splits = 0;
  for (int i = 0; i < 300; ++i) {
    world.step();
    if (i % 100 == 99) splits += transgranular_step(world, book, fp).size();
  }
  std::printf("specimen: %zu grains, %zu bodies, %zu bonds, %zu contacts, %zu splits (%.1f s to build and load)\n",
              specimen.grains.size(), world.body_count(), bonds, world.contacts().size(), splits,
              since(t_build));

  io::CheckpointMeta meta;
  meta.cleave_version = "bench";
  meta.scenario_source = "bench.toml";
  meta.scenario_text = std::string(4000, '#');  // a scenario's worth of text
  const std::string run_state(200000, 'r');       // a long run's histories so far
  const std::filesystem::path file = dir / "cleave_bench_checkpoint";
  double t_encode = 1e9, t_write = 1e9, t_read = 1e9;
  std::string bytes;
  std::uint64_t restored_hash = 0;
  for (int rep = 0; rep < 3; ++rep) {
    auto t0 = Clock::now();
    bytes = io::encode_checkpoint(meta, world, &book, run_state);
    t_encode = std::min(t_encode, since(t0));
    t0 = Clock::now();
    io::write_checkpoint_file(file, bytes);
    t_write = std::min(t_write, since(t0));
    t0 = Clock::now();
    const io::Checkpoint ck = io::read_checkpoint(file);
    t_read = std::min(t_read, since(t0));
    restored_hash = ck.world.state_hash();
  }
  std::printf("checkpoint: %.2f MB; encode %.3f s, write (fsync + rename) %.3f s, read + decode %.3f s; "
              "restored hash %s\n",
              static_cast<double>(bytes.size()) / 1e6, t_encode, t_write, t_read,
              restored_hash == world.state_hash() ? "equal" : "DIFFERENT");
  std::filesystem::remove(file);
  return restored_hash == world.state_hash() ? 0 : 1;
}
