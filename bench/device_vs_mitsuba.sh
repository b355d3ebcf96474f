#!/usr/bin/env bash
# The figures of the device wavefront beside Mitsuba 3 on the same GPU, in one device call
# (docs/PERFORMANCE.md, "Device wavefront"): a generated city is written as PLY and imported;
# stream_render_bench renders it resident, in core and out of core, plus the Embree reference on
# the host's cores; ../shared/tools/mitsuba_bench.py renders the same PLY with the same camera,
# resolution, spp and depth; a cold CLI render per config times package-on-disk to image.
#
#   usage (on the device machine, with vastray and stream_render_bench on PATH and Mitsuba on
#   PYTHONPATH):  bench/device_vs_mitsuba.sh OUT_DIR MITSUBA_BENCH.py [TRIANGLES] [CONFIGS]
#   CONFIGS: space-separated SPP:DEPTH pairs (default "1:2 16:5"). Environment: RATIOS (out-of-core
#   ratios, default 4,16), REPEAT (renders per row, default 3), RESIDENT_ONLY=1 (resident rows and
#   Embree only), WORK (scratch folder), IMPORT_ARGS (extra `vastray import` options, e.g.
#   "--resident-bytes-per-triangle 0"), NO_MITSUBA=1 (skip the Mitsuba rows), COLD_BUDGET (the cold
#   render's --memory-budget, default 8GiB: the scene in core, as Mitsuba holds it), MITSUBA_RR_DEPTH
#   (3 by default: Mitsuba's path integrator starts Russian roulette where vastray does, at the 3rd
#   scattering event, so both trace the same bounces per sample; Mitsuba's own default is 5 —
#   PERF_NOTES 73; empty: MITSUBA_BENCH.py unchanged).
set -uo pipefail
out=$1 mitsuba=$2 triangles=${3:-10000000} configs=${4:-"1:2 16:5"}
mkdir -p "$out"
rrDepth=${MITSUBA_RR_DEPTH-3}
if [ -n "$rrDepth" ]; then  # a copy of the Mitsuba script whose integrator carries rr_depth
  sed "s/\"max_depth\": depth + 1}/\"max_depth\": depth + 1, \"rr_depth\": $rrDepth}/" "$mitsuba" > "$out/mitsuba_bench_rr.py"
  grep -q '"rr_depth"' "$out/mitsuba_bench_rr.py" || { echo "$mitsuba: no integrator line to give rr_depth" >&2; exit 2; }
  mitsuba=$out/mitsuba_bench_rr.py
fi
ratios=${RATIOS:-4,16} repeat=${REPEAT:-3} only=${RESIDENT_ONLY:+--resident-only}
eye=1.6,1.1,1.9 target=0,0,0 width=1920 height=1080
work=${WORK:-/tmp/vastray-bench}
mkdir -p "$out" "$work"
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader > "$out/machine.txt" 2>&1
nproc >> "$out/machine.txt"
vastray generate city --triangles "$triangles" --seed 1 -o "$work/city.ply" > /dev/null
{ /usr/bin/time -f "import wall %e s, peak RSS %M KiB" \
    vastray import "$work/city.ply" -o "$work/city.vast" --progress none ${IMPORT_ARGS:-}; } 2>> "$out/import.txt" >> "$out/import.txt"
vastray info "$work/city.vast" --json > "$out/info.json"
for config in $configs; do
  spp=${config%%:*} depth=${config##*:}
  timeout 400 stream_render_bench --package "$work/city.vast" --resolution "${width}x${height}" --spp "$spp" \
    --depth "$depth" --ratios "$ratios" --repeat "$repeat" $only --eye "$eye" --target "$target" \
    --out "$out/vastray-${triangles}-s${spp}-d${depth}.md" 2>> "$out/bench.log" || echo "bench $config failed: $?" >> "$out/bench.log"
  [ -n "${NO_MITSUBA:-}" ] || timeout 300 python3 "$mitsuba" "$work/city.ply" "$width" "$height" "$spp" "$depth" "$eye" "$target" cuda_ad_rgb \
    >> "$out/mitsuba.jsonl" 2>> "$out/mitsuba.log" || echo "mitsuba $config failed: $?" >> "$out/mitsuba.log"
done
# Cold: package on disk to image in a fresh process, for each config (a .pfm: written without the
# OpenImageIO module, which does not travel to the device machine). The page cache is dropped
# first where the machine lets us (root), so that "cold" includes reading the package.
for config in $configs; do
  spp=${config%%:*} depth=${config##*:}
  sync; echo 3 > /proc/sys/vm/drop_caches 2>/dev/null && echo "page cache dropped" >> "$out/cold.txt"
  { /usr/bin/time -f "cold render s${spp} d${depth} wall %e s" vastray render "$work/city.vast" -o "$work/cold.pfm" \
      --resolution "${width}x${height}" --eye "$eye" --target "$target" --spp "$spp" --max-depth "$depth" \
      --memory-budget "${COLD_BUDGET:-8GiB}" --progress none --stats-json "$out/cold-stats-s${spp}-d${depth}.json"; } >> "$out/cold.txt" 2>&1
done
exit 0
