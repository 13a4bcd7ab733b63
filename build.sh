#!/usr/bin/env bash
# cleave's one entry point for a fresh Debian 12 machine:
#   ./build.sh demo   install what is missing, build, run the default job (three scenarios)
#   ./build.sh test   install what is missing, build, run every test
#   ./build.sh bench  install what is missing, build, run the benchmarks
#   ./build.sh deps   only install what is missing
set -euo pipefail
cd "$(dirname "$0")"

mode="${1:-demo}"
build_dir="${CLEAVE_BUILD_DIR:-build}"
jobs="${CLEAVE_JOBS:-$(nproc)}"

packages=(
  cmake ninja-build g++ git pkg-config ccache lld
  libcgal-dev libgmp-dev libmpfr-dev libeigen3-dev
  libassimp-dev libopenvdb-dev libboost-iostreams-dev libtbb-dev
  libtomlplusplus-dev libcli11-dev libfmt-dev libssl-dev
  libgtest-dev libgmock-dev libbenchmark-dev
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
    cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="${CLEAVE_BUILD_TYPE:-RelWithDebInfo}"
  fi
  cmake --build "$build_dir" -j "$jobs"
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
  test)
    install_missing; build
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs"
    ;;
  bench)
    install_missing; build
    "$build_dir/bench/cleave_bench"
    ;;
  *) echo "usage: ./build.sh [demo|test|bench|deps]" >&2; exit 2 ;;
esac
