#!/usr/bin/env bash
# Real scans in general (docs/metrics.md, "The real-scan bench"): `semvox run` and `semvox eval` on every real
# scan in ../shared/data that has ground truth, the generated randomised validation beside them, and one
# table: per scan its headline score (box recall or point accuracy), mean class recall, floor recall, wall
# share, rooms and seconds; then the mean of the real scans' headline scores and per-class recall.
#   the ScanNet studio       scannet_scene0000_00  furniture boxes (gt.json)       mean box recall
#   the SUN RGB-D view       sunrgbd_000017        bed and night stand (tsv)       mean box recall
#   the S3DIS office room    s3dis_office_room     a NYU40 label per point         point accuracy (nearest voxel within 7.5 cm)
#   randomised validation    semvox generate --randomised, seeds 100-109          visible-voxel accuracy
# and, per real scan, how far the voxels' confidence can be trusted: ECE and AUROC (docs/metrics.md).
# A scan whose data is absent is skipped with a line saying so.
#
# Usage: scripts/bench_real.sh [--config FILE.yaml] [--seeds A-B | --seeds none] [--out DIR] [--build DIR]
#   --config   passed to every `semvox run` (e.g. mapping.voxel_size_m, a step switched off)
#   --seeds    randomised validation seeds (default 100-109; `none` skips them)
#   --out      keep every run's outputs and the figures (bench.json) in DIR (default: a temporary directory)
#   --build    build directory (default $SEMVOX_BUILD_DIR or build)
# Environment: SEMVOX_DATA (default ../shared/data), SEMVOX_GENERATED (cache of generated scans, default
# data/generated/randomised; generated once per seed), SEMVOX_BIN (a semvox binary to use as it is, e.g. a
# copy kept while the tree changes; default: build the `semvox` target and use it).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${SEMVOX_BUILD_DIR:-build}
DATA=${SEMVOX_DATA:-../shared/data}
GEN=${SEMVOX_GENERATED:-data/generated/randomised}
CONFIG=""
SEEDS=100-109
OUT=""
while [ $# -gt 0 ]; do
  case "$1" in
    --config) CONFIG=$2; shift 2 ;;
    --seeds) SEEDS=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --build) BUILD_DIR=$2; shift 2 ;;
    *) echo "usage: $0 [--config FILE.yaml] [--seeds A-B|none] [--out DIR] [--build DIR]" >&2; exit 2 ;;
  esac
done
if [ -n "$CONFIG" ] && [ ! -f "$CONFIG" ]; then
  echo "bench_real.sh: error: $CONFIG: no such config file" >&2
  exit 2
fi
SEMVOX=${SEMVOX_BIN:-}
if [ -z "$SEMVOX" ]; then
  [ -f "$BUILD_DIR/build.ninja" ] || cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  ninja -C "$BUILD_DIR" -j"$(nproc)" semvox >/dev/null
  SEMVOX=$BUILD_DIR/bin/semvox
fi
if [ -z "$OUT" ]; then
  OUT=$(mktemp -d)
  trap 'rm -rf "$OUT"' EXIT
fi
mkdir -p "$OUT"
RUN_ARGS=(-q)
[ -n "$CONFIG" ] && RUN_ARGS+=(--config "$CONFIG")
echo "load: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores${CONFIG:+; config $CONFIG}"

# run NAME INPUT EVAL-FLAG GROUND-TRUTH: one scan run, timed, and scored into $OUT/NAME.eval.json.
run() {
  local name=$1 input=$2 flag=$3 gt=$4 start end
  start=$(date +%s.%N)
  "$SEMVOX" run "$input" -o "$OUT/$name" "${RUN_ARGS[@]}" 2> "$OUT/$name.log" || { cat "$OUT/$name.log" >&2; exit 1; }
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f\n", b - a }' > "$OUT/$name.seconds"
  "$SEMVOX" eval --pred "$OUT/$name" "$flag" "$gt" -o "$OUT/$name.eval.json" -q > "$OUT/$name.eval.txt"
}

if [ -f "$DATA/scannet_scene0000_00/scene0000_00.ply" ]; then
  run studio "$DATA/scannet_scene0000_00/scene0000_00.ply" --boxes "$DATA/scannet_scene0000_00/gt.json"
else echo "bench_real.sh: the ScanNet studio skipped: no $DATA/scannet_scene0000_00/scene0000_00.ply"; fi
if [ -f "$DATA/sunrgbd_000017/000017_points.ply" ]; then
  run sun "$DATA/sunrgbd_000017/000017_points.ply" --boxes "$DATA/sunrgbd_000017/gt_boxes.tsv"
else echo "bench_real.sh: the SUN RGB-D view skipped: no $DATA/sunrgbd_000017/000017_points.ply"; fi
if [ -f "$DATA/s3dis_office_room/office_room.ply" ]; then
  run s3dis "$DATA/s3dis_office_room/office_room.ply" --points "$DATA/s3dis_office_room/office_room.ply"
else echo "bench_real.sh: the S3DIS office room skipped: no $DATA/s3dis_office_room/office_room.ply"; fi
if [ "$SEEDS" != none ]; then
  for seed in $(seq "${SEEDS%-*}" "${SEEDS#*-}"); do
    dir=$GEN/seed_$(printf '%04d' "$seed")
    [ -f "$dir/scan.ply" ] || "$SEMVOX" -q generate --seed "$seed" --randomised -o "$dir"
    run "randomised_$seed" "$dir/scan.ply" --gt "$dir"
  done
fi

python3 - "$OUT" <<'PY'
import json, os, sys
out = sys.argv[1]
def load(name):
    p = os.path.join(out, name + ".eval.json")
    return json.load(open(p)) if os.path.exists(p) else None
def val(s):
    return s["value"] if s and s.get("present") else None
def secs(name):
    return float(open(os.path.join(out, name + ".seconds")).read())
def f3(v):
    return "  -  " if v is None else "%.3f" % v
rows, bench = [], {"scans": {}}
for name, title in (("studio", "ScanNet studio (box recall)"), ("sun", "SUN RGB-D view (box recall)"),
                    ("s3dis", "S3DIS office (point acc.)")):
    e = load(name)
    if e is None:
        continue
    if "mean_box_recall" in e:
        head = val(e["mean_box_recall"])
        classes = {k: val(c["recall"]) for k, c in e["per_class"].items()}
    else:
        head = val(e["accuracy"])
        classes = {k: val(c["recall"]) for k, c in e["per_class"].items()}
    present = [v for v in classes.values() if v is not None]
    mcr = sum(present) / len(present) if present else None
    rooms = ", ".join("%s %.1f" % (r["type"], r["area_m2"]) for r in e.get("rooms", []))
    conf = e.get("confidence", {})
    bench["scans"][name] = {"score": head, "mean_class_recall": mcr, "floor_recall": val(e["floor_recall"]),
                            "wall_share": val(e["wall_share"]), "per_class": classes, "rooms": rooms, "seconds": secs(name),
                            "ece": val(conf.get("ece")), "auroc": val(conf.get("auroc"))}
    rows.append((title, head, mcr, val(e["floor_recall"]), val(e["wall_share"]), secs(name), rooms))
seeds = sorted(n[len("randomised_"):-len(".eval.json")] for n in os.listdir(out)
               if n.startswith("randomised_") and n.endswith(".eval.json"))
if seeds:
    acc, mean_recall, sec, ece, auroc = [], [], [], [], []
    for s in seeds:
        e = load("randomised_" + s)
        conf = e.get("f_confidence", {})
        ece.append(val(conf.get("ece")))
        auroc.append(val(conf.get("auroc")))
        acc.append(val(e["b_visible_voxels"]["accuracy"]))
        mean_recall.append(val(e["b_visible_voxels"]["mean_recall"]))
        sec.append(secs("randomised_" + s))
    a = sum(x for x in acc if x is not None) / len(acc)
    m = sum(x for x in mean_recall if x is not None) / len(mean_recall)
    mean = lambda v: sum(x for x in v if x is not None) / len([x for x in v if x is not None]) if any(x is not None for x in v) else None
    bench["randomised"] = {"seeds": seeds, "visible_accuracy": a, "visible_mean_recall": m, "seconds": sum(sec) / len(sec),
                           "ece": mean(ece), "auroc": mean(auroc)}
print("%-30s %7s %7s %7s %7s %7s  %s" % ("scan", "score", "class", "floor", "wall", "s", "rooms"))
for t, h, m, f, w, s, r in rows:
    print("%-30s %7s %7s %7s %7s %7.1f  %s" % (t, f3(h), f3(m), f3(f), f3(w), s, r))
heads = [r[1] for r in rows if r[1] is not None]
if heads:
    bench["real_mean"] = sum(heads) / len(heads)
    print("%-30s %7s" % ("mean over %d real scans" % len(heads), f3(bench["real_mean"])))
if seeds:
    r = bench["randomised"]
    print("%-30s %7s %7s %7s %7s %7.1f" % ("randomised %s-%s (visible acc.)" % (seeds[0], seeds[-1]), f3(r["visible_accuracy"]),
                                           f3(r["visible_mean_recall"]), "", "", r["seconds"]))
print("confidence (scored voxels or points): ECE / AUROC of right vs wrong")
for name, sc in bench["scans"].items():
    print("  %-10s %s / %s" % (name, f3(sc["ece"]), f3(sc["auroc"])))
if seeds:
    print("  %-10s %s / %s (mean over its scans)" % ("randomised", f3(bench["randomised"]["ece"]), f3(bench["randomised"]["auroc"])))
print("per-class recall:")
for name, sc in bench["scans"].items():
    print("  %-7s %s" % (name, ", ".join("%s %s" % (k, f3(v)) for k, v in sorted(sc["per_class"].items()))))
json.dump(bench, open(os.path.join(out, "bench.json"), "w"), indent=1)
PY
