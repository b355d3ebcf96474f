#!/usr/bin/env bash
# Every benchmark with numeric flags refuses a bad number by name, before it builds a scene or opens a
# device (bench/BenchFlags.h): the exit status is the program's usage error and the message names the
# flag, the text and the limit it crossed. Nothing here needs a GPU or writes a file.
#   usage: bench_flags_refused.sh BENCH_DIR
set -uo pipefail
dir=$1
failed=0
# expect STATUS "MESSAGE PART" PROGRAM ARGS...
expect() {
  local status=$1 part=$2 program=$3
  shift 3
  local out
  out=$("$dir/$program" "$@" 2>&1)
  local got=$?
  if [ $got -ne "$status" ]; then
    echo "$program $*: exit $got, expected $status: $out"
    failed=1
  elif [[ "$out" != *"$part"* ]]; then
    echo "$program $*: the message does not say '$part': $out"
    failed=1
  fi
}
# Every benchmark exits 2 on a bad command line.
expect 2 '--spp: "abc" is not a whole number in [1, 65536]' stream_render_bench --spp abc
expect 2 '--triangles: "-5" is not a whole number' stream_render_bench --triangles -5
expect 2 '--ratios "4,x": "x" is not a finite number' stream_render_bench --ratios 4,x
expect 2 '--wave-share: "inf" is not a finite number in [0, 1]' stream_render_bench --wave-share inf
expect 2 '--device-wave-cap: "1e99" is not a whole number in [1024, 2097120]' stream_render_bench --device-wave-cap 1e99
expect 2 '--depth: 99999999999 is above the largest' stream_render_bench --depth 99999999999
expect 2 "--budgets: size '12QiB' has unknown unit" stream_render_bench --budgets 12QiB
expect 2 '--spp: "1e3" is not a whole number in [1, 65536]' emitter_sampling_bench --spp 1e3
expect 2 '--threads: "-1" is not a whole number' embree_rays_bench --threads -1
# A scene that cannot be loaded is named; the exit status says it failed (1).
expect 1 'gen:city:abc: "abc" is not a whole number' embree_rays_bench --resolution 8x8 gen:city:abc
expect 1 'gen:cube:100: expected gen:KIND:TRIANGLES' embree_rays_bench --resolution 8x8 gen:cube:100
expect 2 '--triangles: "1.5" is not a whole number in [20,' gpu_trace_bench --triangles 1.5
expect 2 'TRIANGLES: "nan" is not a whole number' kd_depth_study sphere nan
expect 2 'N: "abc" is not an integer in [8, 2048]' volume_cloud abc /nonexistent/a.vdb /nonexistent/a.vol
expect 2 '--triangles: 99999999999999999999999 is above the largest 2147483648' codec_bench --triangles 99999999999999999999999
[ $failed -eq 0 ] && echo "every bad benchmark flag refused by name"
exit $failed
