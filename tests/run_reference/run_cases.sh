#!/usr/bin/env bash
# Runs every case of cases.txt with a cleave binary and writes each result folder's
# fingerprint (tools/fingerprint.sh) into OUT_DIR/NAME.txt.
#   tests/run_reference/run_cases.sh CLEAVE_BINARY OUT_DIR [NAME...]
# Made the reference (tests/run_reference/expected/) with the binary of commit 203f528:
#   git worktree add /tmp/base 203f528 && (cd /tmp/base && ./build.sh ...)
#   tests/run_reference/run_cases.sh /tmp/base/build/app/cleave tests/run_reference/expected
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
cleave="$(realpath "$1")"
out="$(mkdir -p "$2" && cd "$2" && pwd)"
shift 2
only=("$@")
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$root"
grep -v '^#' "$here/cases.txt" | while read -r name scenario args; do
  [ -z "$name" ] && continue
  if [ ${#only[@]} -gt 0 ] && [[ ! " ${only[*]} " =~ " $name " ]]; then continue; fi
  # shellcheck disable=SC2086
  "$cleave" run "$scenario" --out "$work/$name" --quiet $args
  "$root/tools/fingerprint.sh" "$work/$name" "$root" > "$out/$name.txt"
  echo "$name: $(head -1 "$out/$name.txt") ($(($(wc -l < "$out/$name.txt") - 1)) files)"
done
