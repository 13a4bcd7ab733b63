#!/usr/bin/env bash
# Strong scaling of `cleave run` over MPI processes on this machine: the same specimen on
# 1 process (1 thread), 2 processes (1 thread each) and, for comparison, 1 process with 2
# OpenMP threads. Two specimens of about 10^5 grains:
#   block: prisms stacked in layers on a floor under gravity, every face at contact distance
#          (the settled state of a pile, built directly: pouring 10^5 grains takes hours);
#   disc:  a bonded Brazilian disc loaded between platens (bonds made, then loaded).
# The time per step is the difference of two runs' wall times (to 10 and to 10 + STEPS
# steps) over STEPS; each rank's MPI time and volume are the decomposition's own counters
# (printed at the end of the longer run; they include the set-up's and the end's gathers).
#   bench/mpi_scaling.sh [BUILD_DIR] [STEPS] [block|disc|both] [SCALE]
# ONLY_CEILING=1: only the one-process run and the two runs side by side.
# SCALE (default 1) multiplies the specimen's edge: 0.5 gives an eighth of the grains.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
steps="${2:-200}"
which="${3:-both}"
scale="${4:-1}"
cleave="$build/app/cleave"
command -v mpirun >/dev/null || { echo "mpi_scaling.sh: mpirun not found (apt-get install openmpi-bin)" >&2; exit 2; }
[ -x "$cleave" ] || { echo "mpi_scaling.sh: $cleave not built" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_WAIT_POLICY=passive
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

edge() { python3 -c "print(round($1 * $scale, 3))"; }

cat > "$work/block.toml" <<EOF
[scenario]
name = "mpi_block"
description = "prisms stacked in 20 layers on a floor, every face at contact distance"
length_unit = "mm"
[specimen]
shape = "box"
size = [$(edge 115.0), $(edge 115.0), 20.0]
[grain]
r = 1.0
r_bar = 0.9423   # neighbouring side faces 0.1 mm apart: the dilated surfaces touch
t = 1.0
t_bar = 0.9      # layers 0.1 mm apart: touching too
[orientation]
seed = 5
[material]
density = 3100.0
[contact]
dilation_radius = 0.05
[contact.particle_particle]
kn = 5000.0
ks = 2000.0
c_res = 2.0
mu_s = 0.3
mu_r = 0.5
[contact.particle_wall]
kn = 10000.0
ks = 2000.0
c_res = 10.0
mu_s = 0.3
[dynamics]
dt = 1.2e-6
duration = 1.0
gravity = [0.0, 0.0, -9.81]
frames = 0
[[wall]]
name = "floor"
kind = "plane"
point = [0.0, 0.0, -0.05]
normal = [0.0, 0.0, 1.0]
EOF

d=$(edge 110.0)
cat > "$work/disc.toml" <<EOF
[scenario]
name = "mpi_disc"
description = "bonded Brazilian disc, 10 planes of grains, loaded between platens"
length_unit = "mm"
[specimen]
shape = "disc"
diameter = $d
thickness = 10.0
keep = "centre_inside"
[grain]
r = 0.6
r_bar = 0.5
t = 1.0
t_bar = 0.9
[orientation]
seed = 2016
[material]
density = 3100.0
[contact]
dilation_radius = 0.05
[contact.particle_particle]
kn = 5.0
ks = 2.0
c_res = 2.0
mu_s = 0.0
mu_r = 0.5
[contact.particle_wall]
kn = 10.0
ks = 2.0
c_res = 10.0
mu_s = 0.0
[bond]
kbn = 6.366e8
kbs = 2.546e8
tbn = 1000.0
tbs = 1000.0
[dynamics]
dt = 1.5e-5
gravity = [0.0, 0.0, 0.0]
local_damping = 0.7
frames = 0
[[wall]]
name = "bottom"
kind = "platen"
point = [$(python3 -c "print($d/2)"), 0.02, 5.0]
normal = [0.0, 1.0, 0.0]
u = [1.0, 0.0, 0.0]
size = [$(python3 -c "print($d*1.5)"), 20.0]
[[wall]]
name = "top"
kind = "platen"
point = [$(python3 -c "print($d/2)"), $(python3 -c "print($d+0.5)"), 5.0]
normal = [0.0, -1.0, 0.0]
u = [1.0, 0.0, 0.0]
size = [$(python3 -c "print($d*1.5)"), 20.0]
[[stage]]
name = "bonding"
kind = "bond"
distance = 0.08
[[stage]]
name = "loading"
wall_velocity = { bottom = [0.0, 0.01, 0.0], top = [0.0, -0.01, 0.0] }
time = 60.0
frames = 0   # a stage's default, 10 frames over its steps, would be 10 frames of 10^5 bodies
             # in any run cut by --max-steps: the two runs' difference would be theirs
EOF

# Wall time of a run to --max-steps N.
timed() {  # log N launcher...
  local log="$1" n="$2"
  shift 2
  local t0 t1
  t0=$(date +%s.%N)
  "$@" "$cleave" run "$scenario" -o "$work/out" --max-steps "$n" > "$log" 2>&1 ||
    { echo "mpi_scaling.sh: $label failed:" >&2; tail -5 "$log" >&2; exit 1; }
  t1=$(date +%s.%N)
  python3 -c "print($t1 - $t0)"
}

# Two independent one-thread runs side by side: what the machine's two cores give any
# parallel version of this run at best (shared caches and memory bandwidth included).
timed_pair() {  # log N
  local log="$1" n="$2" t0 t1
  t0=$(date +%s.%N)
  OMP_NUM_THREADS=1 "$cleave" run "$scenario" -o "$work/out-a" --max-steps "$n" > "$log.a" 2>&1 &
  OMP_NUM_THREADS=1 "$cleave" run "$scenario" -o "$work/out-b" --max-steps "$n" > "$log.b" 2>&1 &
  wait
  t1=$(date +%s.%N)
  python3 -c "print($t1 - $t0)"
}

# The time of a step: two runs, to 10 and to 10 + STEPS steps, differ by STEPS steps and
# nothing else (set-up, bonding, the first search, output are the same in both).
run_one() {  # name label launcher...
  local name="$1"
  label="$2"
  shift 2
  scenario="$work/$name.toml"
  local short long us bodies
  short=$(timed "$work/$name-$label-short.log" 10 "$@")
  long=$(timed "$work/$name-$label.log" $((10 + steps)) "$@")
  us=$(python3 -c "print(round(($long - $short) / $steps * 1e6, 1))")
  bodies="$(grep -o 'bodies [0-9]*' "$work/$name-1proc_1thread.log" 2>/dev/null | tail -1 | cut -d' ' -f2)"
  printf '%-6s %-16s %8s bodies  %10s us/step  %7s steps/s  (runs of %.0f and %.0f s)\n' "$name" "$label" "${bodies:-?}" \
    "$us" "$(python3 -c "print(round(1e6 / $us, 2))")" "$short" "$long"
  eval "us_${name}_${label}=$us"
  grep '^  rank' "$work/$name-$label.log" | sed 's/^/         /' || true
}

echo "cleave $("$cleave" --version | cut -d' ' -f2): strong scaling, $steps steps each, $(nproc) cores"
for name in block disc; do
  [ "$which" = both ] || [ "$which" = "$name" ] || continue
  if [ -n "${ONLY_CEILING:-}" ]; then  # just the two runs side by side, against one
    run_one "$name" "1proc_1thread" env OMP_NUM_THREADS=1
  else
    run_one "$name" "1proc_1thread" env OMP_NUM_THREADS=1
    run_one "$name" "2procs_1thread" env OMP_NUM_THREADS=1 mpirun -np 2 --bind-to core
    run_one "$name" "1proc_2threads" env OMP_NUM_THREADS=2
  fi
  scenario="$work/$name.toml"
  short=$(timed_pair "$work/$name-pair-short.log" 10)
  long=$(timed_pair "$work/$name-pair.log" $((10 + steps)))
  us_pair=$(python3 -c "print(round(($long - $short) / $steps * 1e6, 1))")
  printf '%-6s %-16s %8s         %10s us/step for each of two runs side by side\n' "$name" "2 x 1proc_1thread" "" "$us_pair"
  if [ -n "${ONLY_CEILING:-}" ]; then
    eval "one=\$us_${name}_1proc_1thread"
    python3 -c "print('$name: two runs side by side give {:.2f}x the throughput of one (the ceiling)'.format(2 * $one / $us_pair))"
    continue
  fi
  eval "one=\$us_${name}_1proc_1thread two=\$us_${name}_2procs_1thread threads=\$us_${name}_1proc_2threads"
  python3 -c "print('$name: 2 processes run {:.2f}x as fast as 1 (1 thread each); 2 OpenMP threads in one process {:.2f}x; the machine gives two runs side by side {:.2f}x the throughput of one (the ceiling)'.format($one / $two, $one / $threads, 2 * $one / $us_pair))"
done
