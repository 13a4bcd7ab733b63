#!/usr/bin/env bash
# Fails when a commit subject since the rule began (commit 7209f49) is over 72 characters.
# Skipped (exit 0) outside a git clone or in one too shallow to hold that commit.
set -euo pipefail
cd "$(dirname "$0")/.."
since=7209f49
git rev-parse --git-dir > /dev/null 2>&1 || { echo "commit_subjects: not a git clone; skipped"; exit 0; }
git cat-file -e "$since^{commit}" 2> /dev/null || { echo "commit_subjects: $since not in this clone; skipped"; exit 0; }
# Characters, not bytes: a subject may hold a Greek letter.
long="$(git log --format='%h %s' "$since..HEAD" |
  python3 -c 'import sys
for line in sys.stdin.buffer.read().decode().splitlines():
    h, _, s = line.partition(" ")
    if len(s) > 72: print(len(s), h, s)')"
if [ -n "$long" ]; then
  echo "commit subjects over 72 characters (put the details in the body):"
  echo "$long"
  exit 1
fi
echo "every subject since $since is at most 72 characters"
