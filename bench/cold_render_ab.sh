#!/usr/bin/env bash
# Cold renders, package on disk to image file in a fresh process, for vastray builds side by side
# and Mitsuba 3's load + BVH + first render of the same PLY (docs/PERFORMANCE.md, "Where the issue's
# targets stand"). Per scene size, config and round, each build renders twice: the page cache
# dropped first (root only), then with the package cached. Output: one line per run on stdout.
#
#   usage (on the device machine, the builds on PATH, Mitsuba on PYTHONPATH):
#     bench/cold_render_ab.sh MITSUBA_BENCH.py VASTRAY_PROGRAM...
#   Environment: SIZES (triangles, default "10000000 64000000"), CONFIGS (SPP:DEPTH pairs, default
#   "1:2 16:5"), ROUNDS (2), WORK (scratch folder, /tmp/vastray-cold), BUDGET (--memory-budget, 8GiB:
#   the scene in core, as Mitsuba holds it), CODEC (draco or meshopt; default: meshopt for scenes of
#   64M triangles or more, where Draco decoding would dominate, Draco below); 4 MiB chunks.
set -uo pipefail
[ $# -ge 2 ] || { echo "usage: $0 MITSUBA_BENCH.py VASTRAY_PROGRAM..." >&2; exit 2; }
mitsuba=$1; shift
eye=1.6,1.1,1.9 work=${WORK:-/tmp/vastray-cold}
dropCache() { sync; echo 3 > /proc/sys/vm/drop_caches 2>/dev/null; }
timed() { /usr/bin/time -f %e -o "$work/time.txt" "$@" > /dev/null 2>&1; cat "$work/time.txt"; }
mitsubaFirst() {  # load_and_bvh_s first_render_s
  timeout 120 python3 "$mitsuba" "$work/city.ply" 1920 1080 "$1" "$2" "$eye" 0,0,0 cuda_ad_rgb 2>/dev/null |
    python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["load_and_bvh_s"], d["first_render_s"])'
}
for n in ${SIZES:-10000000 64000000}; do
  mkdir -p "$work"
  codec=; [ "$n" -ge 64000000 ] && codec="--codec meshopt"
  [ -n "${CODEC:-}" ] && codec="--codec $CODEC"
  "$1" generate city --triangles "$n" --seed 1 -o "$work/city.ply" > /dev/null
  # shellcheck disable=SC2086
  "$1" import "$work/city.ply" -o "$work/city.vast" --progress none --chunk-size 4MiB $codec > /dev/null
  for round in $(seq 1 "${ROUNDS:-2}"); do
    for config in ${CONFIGS:-1:2 16:5}; do
      spp=${config%%:*} depth=${config##*:}
      for program in "$@"; do
        render=("$program" render "$work/city.vast" -o "$work/cold.pfm" --resolution 1920x1080 --eye "$eye"
                --target 0,0,0 --spp "$spp" --max-depth "$depth" --memory-budget "${BUDGET:-8GiB}" --progress none)
        dropCache; cold=$(timed "${render[@]}")
        cached=$(timed "${render[@]}")
        echo "$n s$spp d$depth r$round $program: dropped $cold cached $cached"
      done
      if [ "$round" = 1 ]; then
        dropCache; echo "$n s$spp d$depth mitsuba dropped: $(mitsubaFirst "$spp" "$depth")"
        echo "$n s$spp d$depth mitsuba cached: $(mitsubaFirst "$spp" "$depth")"
      fi
    done
  done
  rm -rf "$work"
done
