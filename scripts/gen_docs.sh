#!/usr/bin/env bash
# Writes the generated reference docs from the semvox binary's own tables:
#   docs/configuration.md  from `semvox config --dump` (the options structs' Options() tables: key, default, range, meaning)
#   docs/labels.md         from `semvox labels`        (core/labels_table.cc: NYU40, Eigen-13, NYU-4, room types)
# Usage: scripts/gen_docs.sh [--check] [SEMVOX_BINARY]   (default binary: build/bin/semvox)
# --check writes nothing and fails when a doc differs from what the binary prints (ctest docs_in_sync).
set -euo pipefail
cd "$(dirname "$0")/.."
check=0
if [ "${1:-}" = "--check" ]; then check=1; shift; fi
SEMVOX=${1:-build/bin/semvox}
[ -x "$SEMVOX" ] || { echo "gen_docs.sh: $SEMVOX: no such executable (hint: build first, or pass the binary)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

{
  cat <<'INTRO'
# Configuration reference

Every option of `semvox run` (and the sections `semvox render` and `semvox rooms` use) lives in one YAML file
with one section per stage; every key is optional and takes the default below. Unknown sections or keys and
values outside the range are errors naming the key and the allowed range (exit code 2). The effective
configuration of a run is written beside its outputs as `config_used.yaml`.

```sh
semvox config --dump              # every key with its default, meaning and range (YAML; a valid config file)
semvox config --check my.yaml     # validate a file
semvox run scan.ply -o out --config my.yaml
```

```yaml
# my.yaml: coarser voxels and fewer views
mapping:
  voxel_size_m: 0.1
render:
  grid_spacing_m: 2.0
```

Command-line flags override the file: `--up` (input.up), `--scale` (input.scale), `--max-voxels`
(mapping.max_voxels).

This page is generated from `semvox config --dump` by `scripts/gen_docs.sh`; the test `docs_in_sync` fails
when it is out of date. Each key is described once, in the static `Options()` table of its stage's options
struct (`core/option_table.h`), which also gives that struct's `Check()` its ranges. Ranges are inclusive;
`a, b, c` lists the allowed words.
INTRO
  "$SEMVOX" config --dump | awk '
    /^#/ { next }
    /^[^ ].*:$/ { sec = $0; sub(/:$/, "", sec); printf "\n## `%s`\n\n| key | default | range | meaning |\n|---|---|---|---|\n", sec; next }
    /^  / {
      line = substr($0, 3)
      c = index(line, ": "); key = substr(line, 1, c - 1); rest = substr(line, c + 2)
      h = index(rest, "  # "); value = substr(rest, 1, h - 1); comment = substr(rest, h + 4)
      # The range follows the last "; ".
      n = split(comment, parts, "; "); range = parts[n]; doc = parts[1]
      for (i = 2; i < n; ++i) doc = doc "; " parts[i]
      gsub(/ \| /, ", ", range); gsub(/\|/, "\\|", doc)
      printf "| `%s.%s` | `%s` | %s | %s |\n", sec, key, value, range, doc
      next
    }'
} > "$tmp/configuration.md"

{
  cat <<'INTRO'
# Labels and room types

semvox labels voxels with the 40 NYU Depth v2 classes (the NYU40 ids ScanNet and Matterport3D use; 0 =
unlabeled) and reports the Eigen/Couprie 13-class and the NYU 4-class (1 ground, 2 structure, 3 furniture,
4 props) super-classes through the mappings below. Rooms get one of 12 room types (0 = unknown) from the
room-labelling paper's scene types. Where the ids appear: `voxels.ply` (`label`, NYU40), `map.ot` (per-voxel
label), `semantic_topview_labels.png` (16-bit NYU40 id per cell), `rooms.geojson` (`type`, `type_id`), and the
per-view classifiers' models (NYU-4 first level, NYU40 second level; docs/perception.md).

The source tables are `../shared/spec/nyu40_classes.tsv` and `room_types.tsv` (which also lists the Places365,
R2V, Matterport3D and ZInD names mapped onto each room type); display colours are semvox's own (evenly spread
hues) and colour `semantic_topview.png` and the completed voxels of `voxels.ply` that have no observed
colour nearby.

This page is generated from `semvox labels` (core/labels_table.cc) by `scripts/gen_docs.sh`; the test
`docs_in_sync` fails when it is out of date.

INTRO
  "$SEMVOX" labels
} > "$tmp/labels.md"

status=0
for f in configuration.md labels.md; do
  if [ $check -eq 1 ]; then
    if ! cmp -s "$tmp/$f" "docs/$f"; then
      echo "gen_docs.sh: docs/$f is out of date with $SEMVOX (hint: run scripts/gen_docs.sh $SEMVOX and commit docs/$f)" >&2
      diff -u "docs/$f" "$tmp/$f" | head -20 >&2 || true
      status=1
    fi
  else
    cp "$tmp/$f" "docs/$f"
    echo "wrote docs/$f"
  fi
done
exit $status
