#!/usr/bin/env bash
# Out-of-core A/B runs of stream_render_bench on one package, in one device call, alternating the
# variants so that the machine's drift spreads over all of them (docs/PERF_NOTES.md records what
# each comparison predicted and got).
#
#   usage: bench/out_of_core_variants.sh OUT_DIR PACKAGE ROUNDS VARIANT...
#   VARIANT: NAME=FLAGS, FLAGS being stream_render_bench options (use , for spaces: e.g.
#   "noprefetch=--no-prefetch-scene" or "share35=--wave-share,0.35"); "base=" runs the defaults.
#   Environment: SPP (16), DEPTH (5), RATIOS (4), RESOLUTION (1920x1080), EYE/TARGET (the
#   device_vs_mitsuba.sh camera), BENCH_ARGS (more options for every variant).
set -uo pipefail
out=$1 package=$2 rounds=$3
shift 3
mkdir -p "$out"
for round in $(seq 1 "$rounds"); do
  for variant in "$@"; do
    name=${variant%%=*} flags=${variant#*=}
    # shellcheck disable=SC2086
    timeout 300 stream_render_bench --package "$package" --resolution "${RESOLUTION:-1920x1080}" \
      --spp "${SPP:-16}" --depth "${DEPTH:-5}" --ratios "${RATIOS:-4}" --repeat 1 --no-embree \
      --eye "${EYE:-1.6,1.1,1.9}" --target "${TARGET:-0,0,0}" ${BENCH_ARGS:-} ${flags//,/ } \
      --out "$out/${name}_${round}.md" 2>> "$out/bench.log" || echo "$name round $round failed: $?" >> "$out/bench.log"
  done
done
exit 0
