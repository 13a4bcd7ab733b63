#!/usr/bin/env bash
# cleave against Yade on the same settled pile of hexagonal prisms, from one run:
#   bench/peers/run_yade.sh [N]          (default N = 300; Yade's polyhedra are slow)
# Prints each code's microseconds per step and per touching prism pair per step, and
# their ratio. Yade is Debian's `yade` (polyhedra need its CGAL build); without it the
# script says so and exits 0 after timing cleave alone. Both run on 2 threads.
#   cleave: build/bench/cleave_bench_dynamics poured N (prisms poured and settled by cleave),
#           with the exact search and with persistent contact manifolds (--manifold, default
#           0.02; CLEAVE_MANIFOLD=0 times the exact search alone)
#   Yade:   bench/peers/yade_pile.py (the same prisms poured and settled by Yade)
# The piles are not the same bodies in the same places (each code pours its own), so the
# figure compared is the cost per touching pair, which does not depend on N or packing.
set -euo pipefail
cd "$(dirname "$0")/../.."
n="${1:-300}"
threads=2
bench=build/bench/cleave_bench_dynamics
if [ ! -x "$bench" ]; then
  echo "run_yade.sh: $bench is missing: build first (./build.sh)" >&2
  exit 2
fi
pile_dir="${CLEAVE_PILE_DIR:-/tmp/cleave_peer_piles}"
mkdir -p "$pile_dir"
manifold="${CLEAVE_MANIFOLD:-0.02}"
time_cleave() {  # $1: manifold tolerance (0: exact); sets c_step, c_pairs, c_pair
  local line
  line=$(OMP_NUM_THREADS=$threads "$bench" --pile "$pile_dir" --manifold "$1" poured "$n" | awk '$1 == "poured"')
  # case bodies us/step ns/contact pairs contacts/body us/pair/step MiB
  c_step=$(echo "$line" | awk '{print $3}')
  c_pairs=$(echo "$line" | awk '{print $5}')
  c_pair=$(echo "$line" | awk '{print $7}')
}
time_cleave 0
c_exact=$c_pair
echo "cleave N=$n pairs=$c_pairs us_per_step=$c_step us_per_pair_step=$c_pair threads=$threads (exact search)"
c_manifold=""
if [ "$manifold" != "0" ]; then
  time_cleave "$manifold"
  c_manifold=$c_pair
  echo "cleave N=$n pairs=$c_pairs us_per_step=$c_step us_per_pair_step=$c_pair threads=$threads (manifold_tolerance $manifold)"
fi
if ! command -v yade > /dev/null 2>&1; then
  echo "run_yade.sh: Debian's yade is not installed (apt-get install --no-install-recommends yade); cleave alone above"
  exit 0
fi
yline=$(N="$n" SETTLE="${SETTLE:-4000}" STEPS="${STEPS:-200}" yade -j"$threads" -n -x bench/peers/yade_pile.py 2>&1 |
  grep '^yade N=' || true)
if [ -z "$yline" ]; then
  echo "run_yade.sh: the Yade run printed no result (see: N=$n yade -j$threads -n -x bench/peers/yade_pile.py)" >&2
  exit 1
fi
echo "$yline"
y_pair=$(echo "$yline" | sed 's/.*us_per_pair_step=\([0-9.]*\).*/\1/')
awk -v y="$y_pair" -v c="$c_exact" 'BEGIN { printf "ratio: Yade / cleave per touching pair per step = %.0f (exact search)\n", y / c }'
if [ -n "$c_manifold" ]; then
  awk -v y="$y_pair" -v c="$c_manifold" -v m="$manifold" \
    'BEGIN { printf "ratio: Yade / cleave per touching pair per step = %.0f (manifold_tolerance %s)\n", y / c, m }'
fi
