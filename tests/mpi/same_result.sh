#!/usr/bin/env bash
# A scenario run by `cleave run` alone and under mpirun on 1, 2 and 4 processes
# (oversubscribed): the final state hash and every history table must be the same, byte for
# byte, and the result folder a finished one.
# With CHECKPOINT_EVERY, the 2-process run also writes checkpoints, and its last one is
# restarted on 1 and on 4 processes: both must end in the same state.
#   same_result.sh CLEAVE SCENARIO [MPIEXEC [CHECKPOINT_EVERY]]
set -euo pipefail
cleave="$1" scenario="$2" mpiexec="${3:-mpirun}" checkpoint_every="${4:-}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

export OMPI_MCA_mpi_yield_when_idle="${OMPI_MCA_mpi_yield_when_idle:-1}"  # oversubscribed: processes that wait give up the core

hash_of() { grep '^final_state_hash' "$1/run.toml" | cut -d"'" -f2; }
status_of() { grep '^status' "$1/run.toml" | cut -d"'" -f2; }

"$cleave" run "$scenario" -o "$work/serial" -q
reference="$(hash_of "$work/serial")"
[ -n "$reference" ] || { echo "FAIL: the single-process run wrote no final state hash"; exit 1; }
tables=$(cd "$work/serial" && ls *.csv)
echo "one process: final state hash $reference; tables: $(echo $tables)"
fail=0
for np in 1 2 4; do
  out="$work/np$np"
  start=$SECONDS
  mkdir -p "$work/tmp"
  extra=()
  [ "$np" = 2 ] && [ -n "$checkpoint_every" ] && extra=(--checkpoint-every "$checkpoint_every")
  TMPDIR="$work/tmp" "$mpiexec" --oversubscribe -np "$np" "$cleave" run "$scenario" -o "$out" -q "${extra[@]}"
  [ "${#extra[@]}" -eq 0 ] || cp -r "$out" "$work/checkpointed"
  got="$(hash_of "$out")"
  echo "mpirun -np $np: final state hash $got, status $(status_of "$out") ($((SECONDS - start)) s)"
  [ "$got" = "$reference" ] || { echo "FAIL: -np $np hash $got differs from $reference"; fail=1; }
  [ "$(status_of "$out")" = "finished" ] || { echo "FAIL: -np $np status is not finished"; fail=1; }
  "$cleave" check volume "$out" > "$work/check$np.log" ||
    { echo "FAIL: -np $np: cleave check volume"; tail -3 "$work/check$np.log"; fail=1; }
  for t in $tables; do
    cmp -s "$work/serial/$t" "$out/$t" || { echo "FAIL: -np $np: $t differs"; diff "$work/serial/$t" "$out/$t" | head -5; fail=1; }
  done
  # The other processes worked in scratch folders under TMPDIR, removed at their end.
  leftover=$(ls "$work/tmp" 2>/dev/null | wc -l)
  [ "$leftover" -eq 0 ] || { echo "FAIL: -np $np left $leftover scratch folders"; fail=1; }
done
if [ -n "$checkpoint_every" ]; then
  for np in 1 4; do
    rm -rf "$work/restart$np"
    cp -r "$work/checkpointed" "$work/restart$np"
    if [ "$np" = 1 ]; then
      "$cleave" restart "$work/restart$np" -q
    else
      TMPDIR="$work/tmp" "$mpiexec" --oversubscribe -np "$np" "$cleave" restart "$work/restart$np" -q
    fi
    got="$(hash_of "$work/restart$np")"
    echo "the 2-process checkpoint restarted on $np process(es): final state hash $got"
    [ "$got" = "$reference" ] || { echo "FAIL: restart on $np: hash $got differs from $reference"; fail=1; }
  done
fi
exit $fail
