#!/usr/bin/env bash
# Runs the full-resolution fracture validations (seed 002, sec. 7), reports the wall time of
# each, and remakes the report docs/VALIDATION.md from their files.
#
#   tools/run_validations.sh [--jobs N] [NAME ...]   (default: the whole set below)
#
# NAME is a file of scenarios/validation/ without .toml. Each run writes its folder under
# results/validation/NAME (measured.csv, analytic.csv, cohesive_beam.csv, errors.csv,
# errors_cohesive_beam.csv, load_deflection.svg, run.toml) and its log NAME.log beside it.
# --jobs N runs N at a time, each on nproc / N threads (default 1: one run at a time on
# every core; one lattice run on 2 threads goes 1.7 times as fast as on one, so two runs side
# by side on one thread each finish a set of equal runs a little sooner, and a lone long one
# later). When all have run, tools/validation_report.py archives them into docs/validation/
# and rewrites the results of docs/VALIDATION.md.
# Exit status: 0 when every run passed its bounds, 1 when one did not, 2 when one could not run.
set -u
cd "$(dirname "$0")/.."
cleave=./build/app/cleave
jobs=1
if [[ ${1:-} == --jobs ]]; then
  jobs=${2:?--jobs needs a number}
  shift 2
fi
if ! [[ $jobs =~ ^[1-9][0-9]*$ ]]; then
  echo "run_validations: --jobs must be a positive whole number, not '$jobs'" >&2
  exit 2
fi
if [[ ! -x $cleave ]]; then
  echo "run_validations: $cleave not found; build first (./build.sh demo or cmake --build build)" >&2
  exit 2
fi
names=("$@")
[[ ${#names[@]} -eq 0 ]] && names=(dcb enf mmb_20 mmb_50 mmb_80)
for name in "${names[@]}"; do
  if [[ ! -f scenarios/validation/$name.toml ]]; then
    echo "run_validations: no scenario scenarios/validation/$name.toml" >&2
    exit 2
  fi
done
threads=$(( $(nproc) / jobs ))
(( threads < 1 )) && threads=1
out=results/validation
mkdir -p "$out"

run_one() {
  local name=$1 start rc wall
  start=$(date +%s)
  OMP_NUM_THREADS=$threads "$cleave" validate "scenarios/validation/$name.toml" -o "$out/$name" \
    > "$out/$name.log" 2>&1
  rc=$?
  wall=$(( $(date +%s) - start ))
  printf '%s: exit %d after %d min %02d s (%d threads)\n' "$name" "$rc" $((wall / 60)) $((wall % 60)) \
    "$threads" | tee -a "$out/wall_times.txt"
  echo "$rc" > "$out/$name.rc"
}

echo "run_validations: ${names[*]}; $jobs at a time, $threads threads each; logs in $out/NAME.log" >&2
status=0
set_start=$(date +%s)
for name in "${names[@]}"; do
  rm -f "$out/$name.rc"
  while (( $(jobs -rp | wc -l) >= jobs )); do wait -n; done
  run_one "$name" &
done
wait
for name in "${names[@]}"; do
  rc=$(cat "$out/$name.rc" 2>/dev/null || echo 2)
  if (( rc >= 2 )); then
    echo "run_validations: $name could not run (exit $rc; see $out/$name.log)" >&2
    status=2
  elif (( rc == 1 && status == 0 )); then
    status=1
  fi
done
total=$(( $(date +%s) - set_start ))
printf 'the set: %d min %02d s of wall time\n' $((total / 60)) $((total % 60))
/usr/bin/python3 tools/validation_report.py --results "$out" || status=2
exit $status
