#!/usr/bin/env bash
# Time against error: streaming (vulkan) renders swept over samples per pixel, position
# quantization, memory budget and chunk size, each timed and compared with a high-sample Embree
# reference of the lossless scene (cached by content hash under BUILD_DIR/bench-accuracy/refs).
# Writes docs/generated/accuracy/*.csv|md, docs/accuracy/*.png and the generated section of
# docs/ACCURACY.md. `make bench-accuracy` runs it.
#
#   bash bench/accuracy/run.sh [BUILD_DIR]
#
# Knobs (environment, defaults in bench/accuracy/sweep.py): REF_SPP=4096 RES=160x120
# SPP_LIST="1 2 4 8 16" QUANT_LIST="14 16 18 20 24 0" BUDGET_FACTORS="1 2 4 8 16"
# CHUNK_LIST="128KiB 512KiB 2MiB 16MiB" GEN_TRIANGLES=200000 MESH_DIR=../shared/data/meshes
# SCENES="terrain city" (subset), FULL=1 adds a 10M-triangle city (FULL_TRIANGLES, FULL_REF_SPP).
set -euo pipefail
build=${1:-build}
here=$(cd "$(dirname "$0")" && pwd)
[ -x "$build/vastray" ] || { echo "bench-accuracy: $build/vastray not found; build first" >&2; exit 1; }
command -v oiiotool > /dev/null || { echo "bench-accuracy: oiiotool missing (openimageio-tools)" >&2; exit 1; }
# Debian's python3 (where python3-matplotlib installs), not whatever python3 is first on PATH.
py=${PYTHON:-/usr/bin/python3}
"$py" -c 'import matplotlib' 2> /dev/null || { echo "bench-accuracy: $py lacks matplotlib (make deps installs python3-matplotlib)" >&2; exit 1; }
export BENCH_COMMAND=${BENCH_COMMAND:-"$(env | grep -E '^(REF_SPP|RES|SPP_LIST|QUANT_[A-Z]+|BUDGET_[A-Z]+|CHUNK_[A-Z]+|GEN_[A-Z]+|FULL[A-Z_]*|SCENES|MESH_DIR|MAX_DEPTH)=' | sed -E 's/=(.*)/="\1"/' | tr '\n' ' ')bash bench/accuracy/run.sh $build"}
"$py" -B "$here/sweep.py" "$build"
"$py" -B "$here/report.py"
