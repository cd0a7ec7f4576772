#!/usr/bin/env bash
# Rooms on real apartment layouts, end to end: each validation R2V plan (300-399 of ../shared/data/r2v, never
# trained on) built into a 3D apartment (`semvox generate --plan`: walls, door gaps with lintels, windows,
# fixtures, furniture by room type; --no-furniture: fixtures only), run whole through `semvox run` as mesh and as
# simulated fused cloud, and scored by
# `semvox eval`: room segmentation recall / precision, room-type pixel accuracy and class average, top-view
# coverage (the geometric accuracy: the share of floor-plan pixels whose free / occupied state is right), the
# labels (visible-voxel NYU40 accuracy and class-mean recall: the furniture the room types read), the run's seconds; per plan and mean, the room-type confusion in m² summed over the plans, then the ipa maps of
# ../shared/data beside them (scripts/bench_rooms.sh's figures, distance method). Exits 0 with a message when
# the plans are absent.
# Usage: scripts/bench_rooms_real.sh [--plans 300-399] [--inputs mesh,cloud] [--keep DIR] [--no-furniture] [--config FILE]
#   --config FILE     passed to every `semvox run` (e.g. a room_types section to compare settings)
#   SEMVOX_BUILD_DIR  build directory (default build)
#   SEMVOX_R2V        plan directory (default ../shared/data/r2v)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${SEMVOX_BUILD_DIR:-build}
R2V=${SEMVOX_R2V:-../shared/data/r2v}
PLANS=300-399
INPUTS=mesh,cloud
KEEP=
FURNITURE=
CONFIG=()
while [ $# -gt 0 ]; do
  case "$1" in
    --plans) PLANS=$2; shift 2 ;;
    --inputs) INPUTS=$2; shift 2 ;;
    --keep) KEEP=$2; shift 2 ;;
    --no-furniture) FURNITURE=--no-furniture; shift ;;
    --config) CONFIG=(--config "$(realpath "$2")"); shift 2 ;;
    *) echo "bench_rooms_real.sh: unknown argument $1 (hint: --plans A-B, --inputs mesh,cloud, --keep DIR, --no-furniture, --config FILE)" >&2; exit 2 ;;
  esac
done
if [ ! -d "$R2V" ]; then
  echo "bench_rooms_real.sh: skipped: no R2V plans in $R2V (hint: set SEMVOX_R2V)"
  exit 0
fi
[ -f "$BUILD_DIR/build.ninja" ] || cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C "$BUILD_DIR" -j2 semvox rooms_bench >/dev/null
SEMVOX="$BUILD_DIR/bin/semvox"
if [ -n "$KEEP" ]; then
  WORK=$KEEP
  mkdir -p "$WORK"
else
  WORK=$(mktemp -d)
  trap 'rm -rf "$WORK"' EXIT
fi
mapfile -t FILES < <(ls "$R2V"/plan_*.txt | sort)
first=${PLANS%-*}
last=${PLANS#*-}
echo "load: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores; plans $first-$last of ${#FILES[@]} (sorted order)"
for i in $(seq "$first" "$last"); do
  [ "$i" -lt "${#FILES[@]}" ] || break
  plan=${FILES[$i]}
  dir=$WORK/$i
  flags=$FURNITURE
  [[ $INPUTS == *cloud* ]] && flags="$flags --cloud"
  if ! "$SEMVOX" -q generate --plan "$plan" --seed "$i" $flags -o "$dir" 2>"$dir.err"; then
    echo "plan $i: generate failed: $(cat "$dir.err")"
    continue
  fi
  for input in ${INPUTS//,/ }; do
    file=$dir/mesh.ply
    [ "$input" = cloud ] && file=$dir/cloud.ply
    start=$(date +%s.%N)
    if ! "$SEMVOX" run "$file" -o "$dir/$input" "${CONFIG[@]}" -q 2>"$dir/$input.err"; then
      echo "plan $i $input: run failed: $(tail -1 "$dir/$input.err")"
      continue
    fi
    end=$(date +%s.%N)
    awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f\n", b - a }' >"$dir/$input.seconds"
    "$SEMVOX" eval --pred "$dir/$input" --gt "$dir" -q >/dev/null 2>&1 || true
  done
done
/usr/bin/env python3 - "$WORK" "$first" "$last" "$INPUTS" <<'EOF'
import json, os, sys
work, first, last, inputs = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4].split(',')
def val(s):
    return s['value'] if s.get('present') else None
for inp in inputs:
    rows, conf = [], {}
    for i in range(first, last + 1):
        p = os.path.join(work, str(i), inp, 'eval.json')
        if not os.path.exists(p):
            continue
        e = json.load(open(p))
        gt = json.load(open(os.path.join(work, str(i), 'gt.json')))
        secs = float(open(os.path.join(work, str(i), inp + '.seconds')).read())
        seg, rt = e['d_room_segmentation'], e['e_room_types']
        rows.append((i, val(seg['recall']), val(seg['precision']), seg['gt_rooms'], seg['predicted_rooms'],
                     val(rt['global']), val(rt['average']), val(e['a_top_view']['geometric_accuracy']), secs,
                     val(e['b_visible_voxels']['accuracy']), val(e['b_visible_voxels']['mean_recall'])))
        px = gt['rooms_gt']['resolution'] ** 2
        for g, row in rt.get('confusion_pixels', {}).items():
            for p_, n in row.items():
                conf.setdefault(g, {}).setdefault(p_, 0.0)
                conf[g][p_] += n * px
    print(f"\n{inp}: {len(rows)} plans through semvox run")
    print("  plan  recall  precision  rooms gt/pred  type pixel  type class-avg  coverage  seconds  labels  label recall")
    f = lambda v: '   -  ' if v is None else f"{v:6.3f}"
    for r in rows:
        print(f"  {r[0]:4d}  {f(r[1])}  {f(r[2])}     {r[3]:3d}/{r[4]:<3d}      {f(r[5])}      {f(r[6])}       {f(r[7])}  {r[8]:6.1f}  {f(r[9])}  {f(r[10])}")
    def mean(k):
        v = [r[k] for r in rows if r[k] is not None]
        return sum(v) / len(v) if v else None
    if rows:
        print(f"  mean  {f(mean(1))}  {f(mean(2))}                {f(mean(5))}      {f(mean(6))}       {f(mean(7))}  {mean(8):6.1f}  {f(mean(9))}  {f(mean(10))}")
        print(f"  coverage below 0.95 on {sum(1 for r in rows if r[7] is not None and r[7] < 0.95)} of {len(rows)} plans")
        types = sorted(set(conf) | {p for row in conf.values() for p in row})
        print("  room-type confusion, m² (rows: ground truth, columns: predicted)")
        print("  " + " " * 14 + "".join(f"{t[:9]:>10}" for t in types))
        for g in sorted(conf):
            print(f"  {g[:14]:14}" + "".join(f"{conf[g].get(t, 0):10.1f}" for t in types))
EOF
IPA=${SEMVOX_IPA_MAPS:-../shared/data/ipa_room_seg/test_maps}
if [ -d "$IPA" ]; then
  echo
  echo "ipa maps in $IPA (distance method), for comparison:"
  "$BUILD_DIR/bin/rooms_bench" --data "$IPA" --method distance --brief
fi
