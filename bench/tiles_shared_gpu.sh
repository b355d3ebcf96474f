#!/usr/bin/env bash
# Issue "Measure: one job's tiles across the GPUs of one host", on what the lent device kinds
# allow: one GPU. One frame rendered whole by one process, then as two tiles (left and right
# halves, equal pixel counts) by two processes at once on the same GPU, each with its own pool
# and host cache (as two `vastray serve` workers or two Kubernetes tile pods on one GPU would),
# resident and out of core; Mitsuba 3 on the whole frame for reference. Tiles assemble to the
# whole frame bit for bit (tested on lavapipe in CI: RegionStreamCliTest, OpenJdTemplateTest);
# the device machine cannot write images (the OpenImageIO module does not travel), so this
# measures render time only.
#
#   usage (device machine; vastray, stream_render_bench on PATH, Mitsuba on PYTHONPATH):
#     bench/tiles_shared_gpu.sh OUT_DIR MITSUBA_BENCH.py [TRIANGLES]
#   Environment: RATIOS (out-of-core ratios, default 4), REPEAT (default 3), IMPORT_ARGS,
#   SPP (16), DEPTH (5), NO_MITSUBA=1. Write the figures into one file (the device tool returns 8 files).
set -uo pipefail
out=$1 mitsuba=$2 triangles=${3:-64000000}
spp=${SPP:-16} depth=${DEPTH:-5} width=1920 height=1080 eye=1.6,1.1,1.9 target=0,0,0
work=${WORK:-/tmp/vastray-tiles}
mkdir -p "$out" "$work"
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader > "$out/machine.txt" 2>&1
nproc >> "$out/machine.txt"
start=$(date +%s.%N)
vastray generate city --triangles "$triangles" --seed 1 -o "$work/city.ply" > /dev/null
vastray import "$work/city.ply" -o "$work/city.vast" --progress none ${IMPORT_ARGS:-} > "$out/import.txt" 2>&1
echo "generate + import $(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {print b - a}') s" >> "$out/import.txt"
common=(--package "$work/city.vast" --resolution "${width}x${height}" --spp "$spp" --depth "$depth"
        --ratios "${RATIOS:-4}" --repeat "${REPEAT:-3}" --no-embree --eye "$eye" --target "$target")
t0=$(date +%s.%N)
timeout 280 stream_render_bench "${common[@]}" --out "$out/whole.md" 2> "$out/whole.log"
t1=$(date +%s.%N)
half=$((width / 2))
timeout 280 stream_render_bench "${common[@]}" --region "0,0,$half,$height" --out "$out/left.md" 2> "$out/left.log" &
timeout 280 stream_render_bench "${common[@]}" --region "$half,0,$width,$height" --out "$out/right.md" 2> "$out/right.log" &
wait
t2=$(date +%s.%N)
seconds() { awk -v a="$1" -v b="$2" 'BEGIN {print b - a}'; }
echo "whole frame, one process: $(seconds "$t0" "$t1") s wall (all rows); two tile processes at once: $(seconds "$t1" "$t2") s wall" > "$out/wall.txt"
[ -n "${NO_MITSUBA:-}" ] || timeout 300 python3 "$mitsuba" "$work/city.ply" "$width" "$height" "$spp" "$depth" "$eye" \
  "$target" cuda_ad_rgb > "$out/mitsuba.jsonl" 2> "$out/mitsuba.log"
exit 0
