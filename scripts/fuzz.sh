#!/usr/bin/env bash
# libFuzzer runs of the importers, the package reader, the HTTP JSON bodies and the upload
# volume manifest (issue 16), with ASan and UBSan.
#
#   scripts/fuzz.sh                 # smoke: every target for FUZZ_SECONDS (30) from the seed corpus
#   FUZZ_SECONDS=3600 scripts/fuzz.sh fuzz_import_obj   # the documented long run, one target
#
# Builds in $FUZZ_BUILD_DIR (build-fuzz) with clang++-14 (scripts/install-deps.sh installs it).
# Seeds: fuzz/corpus/<format>/ (in the repository, read only); inputs the fuzzer finds go to
# $FUZZ_BUILD_DIR/corpus/<target>/; a crash, hang (>10 s per input) or leak stops the run with
# the input in $FUZZ_BUILD_DIR/artifacts/ and a non-zero exit. FUZZ_PARALLEL targets (default:
# one per core; 1 to 999) run at once, each on one core; every target still runs its FUZZ_SECONDS.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${FUZZ_BUILD_DIR:-build-fuzz}
SECONDS_PER_TARGET=${FUZZ_SECONDS:-30}
JOBS=${JOBS:-$(nproc)}
PARALLEL=${FUZZ_PARALLEL:-$(nproc)}
[[ "$PARALLEL" =~ ^[1-9][0-9]{0,2}$ ]] || { echo "FUZZ_PARALLEL '$PARALLEL': expected 1 to 999 targets at once" >&2; exit 2; }
declare -A SEEDS=([fuzz_import_obj]=obj [fuzz_import_ply]=ply [fuzz_import_gltf]=gltf
                  [fuzz_import_glb]=glb [fuzz_import_assimp]=assimp [fuzz_package]=vast [fuzz_chunk]=chunk
                  [fuzz_http_json]=json [fuzz_volume_manifest]=volumes [fuzz_environment_map]=envmap [fuzz_pfm]=pfm
                  [fuzz_ktx2]=ktx2)
TARGETS=("$@")
[ ${#TARGETS[@]} -eq 0 ] && TARGETS=(fuzz_import_obj fuzz_import_ply fuzz_import_gltf fuzz_import_glb fuzz_import_assimp fuzz_package fuzz_chunk
                                    fuzz_http_json fuzz_volume_manifest fuzz_environment_map fuzz_pfm fuzz_ktx2)

if [ ! -f "$BUILD/build.ninja" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 -DVASTRAY_FUZZ=ON
fi
cmake --build "$BUILD" -j "$JOBS" --target "${TARGETS[@]}"

mkdir -p "$BUILD/artifacts"
# One target's run; its output goes to $BUILD/artifacts/<target>.log.
fuzz_one() {
  local target=$1 corpus="$BUILD/corpus/$1"
  mkdir -p "$corpus"
  # detect_leaks: the importers return values; a leak is a bug (fuzz/lsan.supp: libassimp's own,
  # the one exception). The limits make an unbounded
  # allocation (rss) or a slow input (timeout) a failure rather than a stall.
  ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$PWD/fuzz/lsan.supp \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$BUILD/fuzz/$target" "$corpus" "fuzz/corpus/${SEEDS[$target]}" \
      -max_total_time="$SECONDS_PER_TARGET" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
      -artifact_prefix="$BUILD/artifacts/$target-" -print_final_stats=1 > "$BUILD/artifacts/$target.log" 2>&1
}
# Batches of PARALLEL targets; each target's last lines are printed when its batch is done, and
# the first target that failed fails the script (after its batch, so no run is left behind).
failed=""
for ((i = 0; i < ${#TARGETS[@]}; i += PARALLEL)); do
  batch=("${TARGETS[@]:i:PARALLEL}")
  pids=()
  for target in "${batch[@]}"; do
    echo "== $target: ${SECONDS_PER_TARGET} s"
    fuzz_one "$target" &
    pids+=($!)
  done
  for j in "${!batch[@]}"; do
    status=0
    wait "${pids[$j]}" || status=$?
    echo "== ${batch[$j]}: exit $status"
    tail -n 12 "$BUILD/artifacts/${batch[$j]}.log"
    [ $status -eq 0 ] || failed=${failed:-${batch[$j]}}
  done
  [ -z "$failed" ] || { echo "fuzz target $failed failed (its input: $BUILD/artifacts/$failed-*)" >&2; exit 1; }
done
