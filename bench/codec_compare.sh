#!/usr/bin/env bash
# Chunk codec comparison (issue 6): Draco through the package's chunk codec at encoder speeds
# 0/5/7/10 against meshoptimizer's codec, at 14/16/20 quantization bits, on one thread: bytes,
# bits per triangle, encode and decode M triangles/s. Render time end to end is not included
# yet. Builds nothing (build the codec_bench target first). Writes
# docs/generated/codec_comparison.md (the file docs/PERFORMANCE.md points to) and prints it.
#
#   bash bench/codec_compare.sh BUILD_DIR
#   TRIANGLES=1000000 CHUNK_TRIANGLES=65536 ENCODE_RUNS=3 DECODE_RUNS=7   (defaults)
#   BUNNY=../shared/data/meshes/stanford-bunny.obj (relative to the repository root; skipped
#   with a note in the table when absent)
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: bash bench/codec_compare.sh BUILD_DIR" >&2
  exit 2
fi
build=$1
bench="$(cd "$build" && pwd)/bench/codec_bench"
if [ ! -x "$bench" ]; then
  echo "$bench not found; build it first: cmake --build $build --target codec_bench" >&2
  exit 1
fi
cd "$(dirname "$0")/.."
triangles=${TRIANGLES:-1000000}
chunk=${CHUNK_TRIANGLES:-65536}
encode_runs=${ENCODE_RUNS:-3}
decode_runs=${DECODE_RUNS:-7}
bunny=${BUNNY:-../shared/data/meshes/stanford-bunny.obj}
out=docs/generated/codec_comparison.md
mkdir -p "$(dirname "$out")"
table=$(mktemp)
trap 'rm -f "$table"' EXIT

args=(--triangles "$triangles" --chunk-triangles "$chunk" --encode-runs "$encode_runs"
      --decode-runs "$decode_runs" --bunny "$bunny")
load=$(cut -d' ' -f1-3 /proc/loadavg)
"$bench" "$table" "${args[@]}" > /dev/null

{
  echo "Measured $(date -u '+%Y-%m-%d %H:%M UTC') on $(nproc) cores of $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'),"
  echo "$(free -g | awk '/Mem:/ {print $2}') GiB RAM, load average $load at the start (the machine is shared with other work:"
  echo "throughput varies between runs; sizes are exact)."
  echo "Command: \`TRIANGLES=$triangles CHUNK_TRIANGLES=$chunk ENCODE_RUNS=$encode_runs DECODE_RUNS=$decode_runs BUNNY=$bunny bash bench/codec_compare.sh $build\`"
  echo "(runs \`$build/bench/codec_bench OUT.md ${args[*]}\`)."
  echo
  cat "$table"
} > "$out"
cat "$out"
