#!/usr/bin/env bash
# scripts/fuzz.sh refuses a FUZZ_PARALLEL that is not 1 to 999 targets at once, by name and before
# it builds anything (0 would loop for ever over empty batches).
#   usage: fuzz_parallel_refused.sh PROJECT_DIR
set -uo pipefail
project=$1
for value in 0 -1 abc 1000; do
  out=$(FUZZ_PARALLEL="$value" FUZZ_BUILD_DIR=/nonexistent-fuzz-build bash "$project/scripts/fuzz.sh" fuzz_pfm 2>&1)
  status=$?
  [ $status -eq 2 ] || { echo "FUZZ_PARALLEL='$value': exit $status, expected 2: $out"; exit 1; }
  [[ "$out" == *"FUZZ_PARALLEL '$value': expected 1 to 999"* ]] || { echo "FUZZ_PARALLEL='$value': message: $out"; exit 1; }
done
echo "every bad FUZZ_PARALLEL refused by name"
