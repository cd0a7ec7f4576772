#!/usr/bin/env bash
# Regenerates the fixed train / validation split of generated apartments (semvox generate --seed N).
#   train:      seeds 0-39
#   validation: seeds 100-109 (every figure the project reports is measured on these)
# Usage: scripts/generate_dataset.sh [OUTDIR (default: data/generated)] [path/to/semvox]
# Each apartment goes to OUTDIR/{train,validation}/seed_NNNN/ (mesh.ply, gt_mesh.ply, cloud.ply, gt.json,
# rooms_gt.png, topview_gt.png, preview.png). The same seeds always give the same bytes.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$here/data/generated}"
semvox="${2:-}"
if [[ -z "$semvox" ]]; then
  for candidate in "$here/build/bin/semvox" "$here/build-gen/bin/semvox"; do
    if [[ -x "$candidate" ]]; then semvox="$candidate"; break; fi
  done
fi
if [[ -z "$semvox" || ! -x "$semvox" ]]; then
  echo "generate_dataset.sh: no semvox binary found (hint: build it first, or pass its path as the second argument)" >&2
  exit 2
fi
TRAIN_SEEDS=$(seq 0 39)
VALIDATION_SEEDS=$(seq 100 109)
gen() {
  local split="$1" seed="$2"
  local dir
  dir="$out/$split/$(printf 'seed_%04d' "$seed")"
  "$semvox" --quiet generate --seed "$seed" --cloud -o "$dir"
}
start=$(date +%s)
for s in $TRAIN_SEEDS; do gen train "$s"; done
for s in $VALIDATION_SEEDS; do gen validation "$s"; done
echo "generate_dataset.sh: $(echo $TRAIN_SEEDS | wc -w) train + $(echo $VALIDATION_SEEDS | wc -w) validation apartments in $out ($(( $(date +%s) - start )) s)"
