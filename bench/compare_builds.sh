#!/usr/bin/env bash
# Times issue 22's cases for two builds, alternating them so that the machine's swings fall
# on both alike:
#   bench/compare_builds.sh BEFORE_BUILD_DIR AFTER_BUILD_DIR [ROUNDS] [PILE_DIR]
# e.g. git worktree add /tmp/base <commit> && cmake -S /tmp/base -B /tmp/base/build -G Ninja \
#        && cmake --build /tmp/base/build --target cleave_bench_dynamics cleave_bench_fracture
#   (a base older than --tiles needs bench_dynamics.cpp's --tiles, 9 lines, applied to it)
#      bench/compare_builds.sh /tmp/base/build build 3 /tmp/pile
# Cases: the poured 10k pile (--tiles) with manifolds 0.02 and exact (300 steps), the packed 10k with
# manifolds and exact (50 steps), and the bonded 10k disc with manifolds (transgranular check
# off, then every step; 500 timed steps each, CLEAVE_BENCH_STEPS: the default 100 take a
# second, too short for this machine's swings). Figures: the pile and the packed block's
# median 10-step block (us/step), the disc's mean (ms/step).
set -euo pipefail
before="${1:?usage: bench/compare_builds.sh BEFORE_BUILD_DIR AFTER_BUILD_DIR [ROUNDS] [PILE_DIR]}"
after="${2:?usage: bench/compare_builds.sh BEFORE_BUILD_DIR AFTER_BUILD_DIR [ROUNDS] [PILE_DIR]}"
rounds="${3:-3}"
pile="${4:-/tmp/pile}"
for d in "$before" "$after"; do
  for b in cleave_bench_dynamics cleave_bench_fracture; do
    [ -x "$d/bench/$b" ] || { echo "compare_builds: no $d/bench/$b (build it first)" >&2; exit 2; }
  done
done
# The pile is the poured tile's copies as they lie (--tiles): the same bodies for both builds,
# where each build's own settling ends in a pile of other contacts (7209f49's 3.96 contact
# points a body, f73c5d0's 4.43). Each build keeps its tile in PILE_DIR/before or /after.
mkdir -p "$pile/before" "$pile/after"
us() { tail -1 | awk '{print $3}'; }
disc() { tail -2 | grep -o 'transgranular o[nf]* *: [0-9.]*' | awk '{print $NF}' | tr '\n' ' '; }
date
for round in $(seq "$rounds"); do
  for who in before after; do
    d="$before"; [ "$who" = after ] && d="$after"
    dyn="$d/bench/cleave_bench_dynamics"
    kept="$pile/$who"
    echo "round $round $who:" \
      "pile+manifold $("$dyn" --tiles --pile "$kept" --manifold 0.02 --steps 300 poured 10000 2>&1 | us) us," \
      "pile $("$dyn" --tiles --pile "$kept" --steps 300 poured 10000 2>&1 | us) us," \
      "packed+manifold $("$dyn" --steps 50 --manifold 0.02 packed 10000 2>&1 | us) us," \
      "packed $("$dyn" --steps 50 packed 10000 2>&1 | us) us," \
      "disc+manifold (no check, check) $(CLEAVE_BENCH_STEPS="${CLEAVE_BENCH_STEPS:-500}" "$d/bench/cleave_bench_fracture" 10000 1e9 0 0.02 2>&1 | disc)ms"
  done
done
date
