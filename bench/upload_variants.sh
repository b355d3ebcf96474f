#!/usr/bin/env bash
# Chunk uploads mapped against DMA (PERF_NOTES 44), in one device call: a generated city is
# imported with 4 MiB chunks and rendered at 4× over budget by stream_render_bench, alternating
# the variants round by round so that the machine's drift spreads over all of them. Every
# table goes into one file, OUT_FILE, with each variant's name and round before it.
#
#   usage: bench/upload_variants.sh OUT_FILE ROUNDS VARIANT...
#   VARIANT: NAME=PROGRAM[,FLAG...]: a stream_render_bench build on PATH and its extra options,
#   e.g. "main=stream_render_bench_main" "dma=stream_render_bench,--upload,dma".
#   Environment: TRIANGLES (10000000), CHUNK (4MiB), SPP (16), DEPTH (5), RATIOS (4), RESOLUTION
#   (1920x1080), WORK
#   (scratch folder, /tmp/vastray-upload), BENCH_ARGS (more options for every variant).
set -uo pipefail
out=$1 rounds=$2
shift 2
work=${WORK:-/tmp/vastray-upload}
mkdir -p "$work"
{
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader 2>&1
  echo "cores: $(nproc)"
  vastray generate city --triangles "${TRIANGLES:-10000000}" --seed 1 -o "$work/city.ply" > /dev/null
  TIMEFORMAT="import wall %R s"
  time vastray import "$work/city.ply" -o "$work/city.vast" --progress none --chunk-size "${CHUNK:-4MiB}" 2>&1
} >> "$out" 2>&1
for round in $(seq 1 "$rounds"); do
  for variant in "$@"; do
    name=${variant%%=*} spec=${variant#*=}
    program=${spec%%,*} flags=
    [ "$program" != "$spec" ] && flags=${spec#*,}
    echo "## $name, round $round" >> "$out"
    # shellcheck disable=SC2086
    timeout 300 "$program" --package "$work/city.vast" --resolution "${RESOLUTION:-1920x1080}" --spp "${SPP:-16}" \
      --depth "${DEPTH:-5}" --ratios "${RATIOS:-4}" --repeat 1 --no-embree --eye 1.6,1.1,1.9 --target 0,0,0 \
      ${BENCH_ARGS:-} ${flags//,/ } >> "$out" 2>&1 || echo "$name round $round failed: $?" >> "$out"
  done
done
exit 0
