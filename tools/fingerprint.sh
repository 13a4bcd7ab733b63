#!/usr/bin/env bash
# The fingerprint of a result folder: the final state hash (run.toml) and the SHA-256 of
# every file the run wrote, except those that record when and with which build it ran
# (run.toml, SHA256SUMS, the checkpoint, whose header names the cleave version).
# scenario_as_run.toml names mesh files by absolute path; with CHECKOUT_ROOT given, that
# prefix is written as <root> before hashing, so the fingerprint holds in any checkout.
#   tools/fingerprint.sh RESULT_DIR [CHECKOUT_ROOT]
set -euo pipefail
dir="$1"
root="${2:-}"
cd "$dir"
hash=$(sed -n "s/^final_state_hash *= *['\"]\([0-9a-f]*\)['\"]/\1/p" run.toml || true)
echo "final_state_hash ${hash:-none}"
find . -type f ! -name run.toml ! -name SHA256SUMS ! -name checkpoint ! -name '*.tmp' -printf '%P\n' \
  | LC_ALL=C sort | while read -r f; do
  if [ -n "$root" ] && [ "$f" = scenario_as_run.toml ]; then
    echo "$(sed "s#\"$root/#\"<root>/#g" "$f" | sha256sum | cut -c1-64) $f"
  else
    echo "$(sha256sum "$f" | cut -c1-64) $f"
  fi
done
