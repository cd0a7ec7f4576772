#!/usr/bin/env bash
# Whole-pipeline speed and labels: `semvox run` on the bundled demo, four generated flats
# (seeds 104 and 106 -- 57 and 91 m2 -- as mesh and as simulated fused cloud) and the ScanNet studio; per run
# the wall and CPU seconds of every stage (summary.json "seconds" / "cpu_seconds"), the classification views
# chosen of the candidates and their coverage, the process's peak memory (GNU time), and the labels of the
# same run: `semvox eval` on the generated flats (visible-voxel accuracy and mean recall, NYU-4 global, room
# types), the box scores on the studio (mean box recall, floor recall). A cloud costs about what a mesh of
# the same scene costs when its row is close to the mesh's. Machines are shared: compare CPU seconds, and
# repeat when in doubt.
# Usage: scripts/bench_pipeline.sh [build dir]
#   SEMVOX_BUILD_DIR   build directory when none is given (default build)
#   SEMVOX_STUDIO      ScanNet studio directory (default ../shared/data/scannet_scene0000_00; skipped if absent)
#   SEMVOX_BENCH_OUT   keep the runs here (default: a temporary directory, removed at exit)
#   SEMVOX_BENCH_CONFIG  a --config file for every run (e.g. semantic.view_selection: all for the slow reference)
#   SEMVOX_BENCH_ONLY  space-separated subset of: demo mesh104 cloud104 mesh106 cloud106 studio
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-${SEMVOX_BUILD_DIR:-build}}
STUDIO=${SEMVOX_STUDIO:-../shared/data/scannet_scene0000_00}
ONLY=${SEMVOX_BENCH_ONLY:-demo mesh104 cloud104 mesh106 cloud106 studio}
[ -x /usr/bin/time ] || { echo "bench_pipeline.sh: needs GNU time (/usr/bin/time; apt-get install time)" >&2; exit 2; }
[ -f "$BUILD_DIR/build.ninja" ] || cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C "$BUILD_DIR" -j2 semvox >/dev/null
SEMVOX=$BUILD_DIR/bin/semvox
if [ -n "${SEMVOX_BENCH_OUT:-}" ]; then
  OUT=$SEMVOX_BENCH_OUT
  mkdir -p "$OUT"
else
  OUT=$(mktemp -d)
  trap 'rm -rf "$OUT"' EXIT
fi
CONFIG=()
[ -n "${SEMVOX_BENCH_CONFIG:-}" ] && CONFIG=(--config "$SEMVOX_BENCH_CONFIG")
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); outputs in $OUT"

for seed in 104 106; do
  [ -f "$OUT/gen$seed/gt.json" ] || "$SEMVOX" generate --seed "$seed" --cloud -o "$OUT/gen$seed" >/dev/null 2>&1
done

# run NAME INPUT [GT_DIR|boxes:GT.json]
run() {
  local name=$1 input=$2 gt=${3:-}
  /usr/bin/time -v "$SEMVOX" run "$input" -o "$OUT/$name" -q "${CONFIG[@]}" 2> "$OUT/$name.time"
  if [[ "$gt" == boxes:* ]]; then
    "$SEMVOX" eval --pred "$OUT/$name" --boxes "${gt#boxes:}" -q > "$OUT/$name.boxes.txt"
  elif [ -n "$gt" ]; then
    "$SEMVOX" eval --pred "$OUT/$name" --gt "$gt" -q --json > "$OUT/$name.eval.json"
  fi
  python3 - "$OUT" "$name" <<'PY'
import json, os, re, sys
out, name = sys.argv[1], sys.argv[2]
s = json.load(open(os.path.join(out, name, "summary.json")))
t = open(os.path.join(out, name + ".time")).read()
peak = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024
sec, cpu = s["seconds"], s.get("cpu_seconds", {})
stages = ["load", "voxelize", "render", "classify", "voxel_crf", "rooms", "semantic_exports"]
cells = " ".join("%s %.1f/%.1f" % (k, sec.get(k, 0), cpu.get(k, 0)) for k in stages)
sel = s.get("semantic", {}).get("view_selection", {})
views = "%s of %s views" % (sel.get("chosen", s.get("semantic", {}).get("classification_views", "?")), sel.get("candidates", "?"))
if "coverage" in sel:
    views += ", coverage %.3f (candidates %.3f)" % (sel["coverage"], sel["coverage_candidates"])
labels = ""
e = os.path.join(out, name + ".eval.json")
if os.path.exists(e):
    j = json.load(open(e))
    v = lambda x: x["value"] if isinstance(x, dict) else x
    labels = "visible acc %.4f mean recall %.4f nyu4 %.4f room types %.4f" % (
        v(j["b_visible_voxels"]["accuracy"]), v(j["b_visible_voxels"]["mean_recall"]), v(j["c_nyu4"]["global"]), v(j["e_room_types"]["global"]))
b = os.path.join(out, name + ".boxes.txt")
if os.path.exists(b):
    txt = open(b).read()
    m1 = re.search(r"mean box recall\s+([\d.]+) %", txt)
    m2 = re.search(r"floor recall\s+([\d.]+) %", txt)
    labels = "mean box recall %s %% floor recall %s %%" % (m1.group(1) if m1 else "?", m2.group(1) if m2 else "?")
print("%-9s total %.1f s wall / %.1f s CPU, peak %.0f MB | %s | %s | %s" % (
    name, sec["total"], cpu.get("total", 0), peak, views, labels, cells))
PY
}

for what in $ONLY; do
  case $what in
    demo) run demo scenes/demo_apartment.ply ;;
    mesh104) run mesh104 "$OUT/gen104/mesh.ply" "$OUT/gen104" ;;
    cloud104) run cloud104 "$OUT/gen104/cloud.ply" "$OUT/gen104" ;;
    mesh106) run mesh106 "$OUT/gen106/mesh.ply" "$OUT/gen106" ;;
    cloud106) run cloud106 "$OUT/gen106/cloud.ply" "$OUT/gen106" ;;
    studio)
      if [ -f "$STUDIO/scene0000_00.ply" ] && [ -f "$STUDIO/gt.json" ]; then
        run studio "$STUDIO/scene0000_00.ply" "boxes:$STUDIO/gt.json"
      else
        echo "studio    skipped: no scene0000_00.ply and gt.json in $STUDIO (hint: set SEMVOX_STUDIO)"
      fi ;;
    *) echo "bench_pipeline.sh: unknown run $what" >&2; exit 2 ;;
  esac
done
echo "(stage columns: wall / CPU seconds; CPU / wall near the core count means the stage keeps every core busy)"
