#!/usr/bin/env bash
# Runs the cases of cases.txt with CLEAVE_BINARY and fails unless every fingerprint equals
# the reference in expected/ (made by the binary before the run loop moved into sim/).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
got="$(mktemp -d)"
trap 'rm -rf "$got"' EXIT
"$here/run_cases.sh" "$1" "$got"
diff -r "$here/expected" "$got"
echo "every output file and final state hash matches the reference"
