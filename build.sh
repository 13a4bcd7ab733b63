#!/usr/bin/env bash
# cleave's one entry point for a fresh Debian 12 machine:
#   ./build.sh demo   install what is missing, build, run the default job (three scenarios)
#   ./build.sh test   install what is missing, build, run every test; then `sanitize` and `fuzz`
#   ./build.sh unit   install what is missing, build, run every test (the first part of `test`)
#   ./build.sh sanitize  clang + AddressSanitizer + UBSan build in build-asan, run the tests there
#   ./build.sh fuzz   the same build, then each libFuzzer target (fuzz/) on its corpus for a while
#                     (CLEAVE_FUZZ_SECONDS each, 20; or CLEAVE_FUZZ_RUNS inputs each)
#   ./build.sh bench  install what is missing, build, run the benchmarks
#   ./build.sh deps   only install what is missing
set -euo pipefail
cd "$(dirname "$0")"

mode="${1:-demo}"
build_dir="${CLEAVE_BUILD_DIR:-build}"
asan_dir="${CLEAVE_ASAN_BUILD_DIR:-build-asan}"
fuzz_seconds="${CLEAVE_FUZZ_SECONDS:-20}"  # per fuzz target (CI: the five take 100 s, a check of the corpus and a short search; longer runs by hand)
jobs="${CLEAVE_JOBS:-$(nproc)}"

packages=(
  cmake ninja-build g++ git pkg-config ccache lld
  libcgal-dev libgmp-dev libmpfr-dev libeigen3-dev
  libassimp-dev libopenvdb-dev libboost-iostreams-dev libtbb-dev
  libtomlplusplus-dev libcli11-dev libfmt-dev libssl-dev libmuparser-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libopenmpi-dev openmpi-bin  # `mpirun -np N cleave run` (parallel/)
  clang libclang-rt-14-dev libomp-dev  # sanitizer/fuzz build: ASan, UBSan, libFuzzer, OpenMP
  python3 python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib  # import cleave
  python3-vtk9 python3-meshio  # tests reading the outputs with VTK's and meshio's readers
  strace  # tests/test_result_folders.cpp: no write outside the result folder
)

install_missing() {
  local missing=()
  for p in "${packages[@]}"; do
    if [ "$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null)" != "installed" ]; then
      missing+=("$p")
    fi
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "build.sh: installing missing Debian packages: ${missing[*]}"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "build.sh: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
    sudo="sudo"
  fi
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

build() {
  if [ ! -f "$build_dir/build.ninja" ]; then
    # Debian's python3 (numpy, pybind11), not whatever python3 comes first on PATH.
    # Line tables, not full debug info (-g1): stack traces and perf keep file and line, and
    # the build compiles markedly faster. CLEAVE_CXX_FLAGS replaces them (e.g. "-O2 -g" for
    # gdb's variables).
    cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="${CLEAVE_BUILD_TYPE:-RelWithDebInfo}" \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="${CLEAVE_CXX_FLAGS:--O2 -g1 -DNDEBUG}" \
      -DPython3_EXECUTABLE=/usr/bin/python3
  fi
  cmake --build "$build_dir" -j "$jobs"
}

# clang with ASan + UBSan (any UB aborts) and libFuzzer coverage; tests in, benchmarks out.
build_sanitized() {
  if [ ! -f "$asan_dir/build.ninja" ]; then
    # Line tables are all a sanitizer's stack trace needs, and build much faster than -g.
    CC=clang CXX=clang++ cmake -S . -B "$asan_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
      -DCLEAVE_SANITIZE=ON -DCLEAVE_FUZZ=ON -DCLEAVE_BUILD_BENCH=OFF -DCLEAVE_PYTHON=OFF
  fi
  cmake --build "$asan_dir" -j "$jobs"
}

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:check_initialization_order=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$PWD/tools/sanitizers/lsan.supp:print_suppressions=0}"

# Tests left out of the sanitizer run (ctest -E regex): whole long runs (complete scenarios
# through the cleave binary, validations, sweeps, thread-identity runs of thousands of steps)
# that take 30-110 s each in the normal build and several times that under ASan. Their code
# paths are covered by the shorter tests that stay in.
sanitize_exclude="${CLEAVE_SANITIZE_EXCLUDE-^(BondedTest\.|QuasiStaticLoading\.|WallGap\.|CoarseValidation\.[DEM]|SweepCommand\.FourSeeds|CubicLattice\.BitIdentical|CantileverBending\.ConvergesToTimoshenko|BondedSpecimen\.BitIdentical|CustomGrainRun\.Voronoi|RunReference\.|Python\.|MaterialTest\.)}"

# Also left out: the tests that took longer than $sanitize_long s in the normal build's last
# run on this machine (ctest's own timings, build/Testing/Temporary/CTestCostData.txt), when
# there is one: under the sanitizers they take 20-70 times as long (physics loops of
# thousands of steps), and the shorter tests that stay in walk the same code. They are
# named in the log. CLEAVE_SANITIZE_LONG=0 keeps them all.
sanitize_long="${CLEAVE_SANITIZE_LONG-0.5}"

long_tests_regex() {
  local cost="$build_dir/Testing/Temporary/CTestCostData.txt"
  [ -f "$cost" ] && [ -n "$sanitize_long" ] && [ "$sanitize_long" != "0" ] || return 0
  awk -v th="$sanitize_long" '$0 == "---" { exit } NF >= 3 && $3 + 0 > th + 0 { print $1 }' "$cost" |
    sed -e 's/[][\\.^$*+?(){}|]/\\&/g' | paste -sd '|' -
}

run_sanitized_tests() {
  local start=$SECONDS exclude="$sanitize_exclude" long
  long="$(long_tests_regex)"
  if [ -n "$long" ]; then
    echo "build.sh: the sanitizer run leaves out $(echo "$long" | tr '|' '\n' | wc -l) tests that took over ${sanitize_long} s in the normal run:"
    echo "$long" | tr '|' '\n' | sed -e 's/\\//g' -e 's/^/  /'
    exclude="${exclude:+$exclude|}^($long)\$"
  fi
  if [ -n "$exclude" ]; then
    ctest --test-dir "$asan_dir" --output-on-failure -j "$jobs" -E "$exclude"
  else
    ctest --test-dir "$asan_dir" --output-on-failure -j "$jobs"
  fi
  echo "build.sh: sanitizer test run: $((SECONDS - start)) s"
}

# Each target runs on a scratch copy of its corpus (new inputs go to build-asan/fuzz/, the
# repository's fuzz/corpus/<target>/ is only read); a crash, sanitizer report, uncaught
# exception, leak or input slower than 30 s fails the run and leaves the input in
# build-asan/fuzz/artifacts/.
run_fuzzers() {
  local t scratch artifacts
  for t in fuzz_scenario fuzz_validation_scenario fuzz_mesh fuzz_checkpoint fuzz_cli fuzz_tessellation; do
    scratch="$asan_dir/fuzz/corpus/$t"
    artifacts="$asan_dir/fuzz/artifacts"
    mkdir -p "$scratch" "$artifacts"
    # CLEAVE_FUZZ_RUNS=N: N inputs each instead of a time (a deep run; DEVELOPMENT.md).
    local budget=(-max_total_time="$fuzz_seconds") what="for ${fuzz_seconds} s"
    if [ -n "${CLEAVE_FUZZ_RUNS:-}" ]; then budget=(-runs="$CLEAVE_FUZZ_RUNS"); what="for $CLEAVE_FUZZ_RUNS inputs"; fi
    echo "build.sh: fuzzing $t $what"
    "$asan_dir/fuzz/$t" "${budget[@]}" -timeout=30 -rss_limit_mb=4096 \
      -print_final_stats=1 -artifact_prefix="$artifacts/$t-" "$scratch" "fuzz/corpus/$t"
  done
}

case "$mode" in
  deps) install_missing ;;
  demo)
    install_missing; build
    "$build_dir/app/cleave" run scenarios/demo.toml --out results/demo
    "$build_dir/app/cleave" check volume --voxel --summary results/demo
    "$build_dir/app/cleave" run scenarios/demo_drop.toml --out results/demo_drop
    "$build_dir/app/cleave" run scenarios/four_point_bending.toml --out results/four_point_bending
    ;;
  unit)
    install_missing; build
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs"
    ;;
  test)
    install_missing; build
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs"
    build_sanitized
    run_sanitized_tests
    run_fuzzers
    ;;
  sanitize)
    install_missing; build_sanitized
    run_sanitized_tests
    ;;
  fuzz)
    install_missing; build_sanitized
    run_fuzzers
    ;;
  bench)
    install_missing; build
    "$build_dir/bench/cleave_bench"
    ;;
  *) echo "usage: ./build.sh [demo|test|unit|sanitize|fuzz|bench|deps]" >&2; exit 2 ;;
esac
