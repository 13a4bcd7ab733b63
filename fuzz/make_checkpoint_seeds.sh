#!/usr/bin/env bash
# Regenerates the checkpoint seeds of fuzz/corpus/fuzz_checkpoint/ from the two tiny
# scenarios in fuzz/seeds/ (run this when the checkpoint format changes):
#   fuzz/make_checkpoint_seeds.sh [path/to/cleave]   (default: build/app/cleave)
#   bonded_3_grains.ckpt        3 bonded grains, 3 bonds, 50 steps (no fracture book)
#   falling_1_grain.ckpt        1 grain falling onto a floor, 100 steps (book, no split yet)
#   falling_1_grain_split.ckpt  the same at step 300, after its grain split in two (step 270)
set -euo pipefail
cd "$(dirname "$0")/.."
cleave="${1:-build/app/cleave}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
out=fuzz/corpus/fuzz_checkpoint
mkdir -p "$out"
seed() {  # scenario steps name
  "$cleave" run "$1" --out "$work/$3" --max-steps "$2" --checkpoint-every "$2" --quiet
  cp "$work/$3/checkpoint" "$out/$3.ckpt"
}
seed fuzz/seeds/checkpoint_bonded.toml 50 bonded_3_grains
seed fuzz/seeds/checkpoint_falling.toml 100 falling_1_grain
seed fuzz/seeds/checkpoint_falling.toml 300 falling_1_grain_split
ls -l "$out"
