#!/usr/bin/env bash
# The unit tests of the parsers and the package (core_tests, streamer_tests: importers, package
# reader and writer, chunk codecs, triangulation, the fuzz seeds replayed) built with clang-14,
# AddressSanitizer and UndefinedBehaviorSanitizer in the fuzzing build folder, and run there
# (issue 16). `make test-asan`; .ci/run runs it after `make test`.
#
# The GPU, server and CLI tests are not in it: lavapipe under ASan runs the kernels ~10x slower
# and the server's tests start real processes; docs/HARDENING.md says what is covered.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${FUZZ_BUILD_DIR:-build-fuzz}
JOBS=${JOBS:-$(nproc)}
if [ ! -f "$BUILD/build.ninja" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 -DVASTRAY_FUZZ=ON
fi
# ASAN_BUILD_ALSO: more targets of the same build to compile in the same ninja run (CI names
# fuzz_targets, which fuzz-smoke builds next: one run keeps both cores busy where the tests' last
# large files would compile alone).
cmake --build "$BUILD" -j "$JOBS" --target core_tests streamer_tests ${ASAN_BUILD_ALSO:-}
ROOT=$PWD
cd "$BUILD"
# Leaks are failures too (except inside libassimp: fuzz/lsan.supp says why); UBSan stops at the
# first report (the build has -fno-sanitize-recover).
ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$ROOT/fuzz/lsan.supp \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --output-on-failure -j "$JOBS" -L '^(core_tests|streamer_tests)$'
