#!/usr/bin/env bash
# Import throughput: generated scenes of several sizes imported with 1 and all cores;
# wall time, triangles/s, triangles/s per core, peak RSS, package bytes per triangle.
# Writes a markdown table to docs/generated/import_throughput.md (the file
# docs/PERFORMANCE.md points to) and prints it.
#
#   bash bench/import_throughput.sh [BUILD_DIR]
#   SIZES="1000000 4000000" KINDS="sphere soup" CHUNK=16MiB  (defaults shown below)
#   SIZES=100000000 KINDS=terrain THREADS_LIST=2 for the 100M-triangle memory check
set -euo pipefail
build=${1:-build}
vastray="$build/vastray"
sizes=${SIZES:-"1000000 4000000"}
kinds=${KINDS:-"sphere terrain soup city"}
chunk=${CHUNK:-16MiB}
threads_list=${THREADS_LIST:-"1 $(nproc)"}
work=${WORK_DIR:-$(mktemp -d)}
out=${OUT_FILE:-docs/generated/import_throughput.md}
mkdir -p "$(dirname "$out")"

{
  echo "Measured $(date -u +%Y-%m-%d) on $(nproc) cores of $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'),"
  echo "$(free -g | awk '/Mem:/ {print $2}') GiB RAM; chunk size $chunk, default quantization (20 bits), default Draco speed ($("$vastray" import --help | sed -n 's/.*--draco-speed INT=\([0-9]*\).*/\1/p'))."
  echo "Command: \`SIZES=\"$sizes\" KINDS=\"$kinds\" CHUNK=$chunk THREADS_LIST=\"$threads_list\" bash bench/import_throughput.sh\`"
  echo
  echo "Columns: *parse s* reads the PLY; *package s* is partition + Draco round trip + chunk KD-trees + write"
  echo "(the import target is counted on it); *wall s* is the whole command."
  echo
  echo "| scene | triangles | threads | parse s | package s | M tri/s/core (package) | wall s | peak RSS GiB | package B/tri | chunks |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
} > "$out"

for kind in $kinds; do
  for n in $sizes; do
    ply="$work/$kind-$n.ply"
    "$vastray" generate "$kind" --triangles "$n" --seed 1 -o "$ply" > /dev/null
    for threads in $threads_list; do
      vast="$work/$kind-$n.vast"
      log="$work/log.txt"
      /usr/bin/time -f "%e %M" -o "$work/time.txt" \
        "$vastray" import "$ply" -o "$vast" --threads "$threads" --chunk-size "$chunk" --progress none > "$log"
      read -r wall rss_kib < "$work/time.txt"
      tris=$("$vastray" info "$vast" --json | python3 -c 'import json,sys; j=json.load(sys.stdin); print(j["triangles"], j["chunks"], j["file_bytes"])')
      read -r count chunks bytes <<< "$tris"
      parse=$(sed -n 's/^read .* in \([0-9.]*\) s.*/\1/p' "$log")
      package=$(sed -n 's/^  \([0-9.]*\) s total.*/\1/p' "$log")
      python3 - "$kind" "$count" "$threads" "$wall" "$rss_kib" "$bytes" "$chunks" "$parse" "$package" >> "$out" <<'PY'
import sys
kind, count, threads, wall, rss, size, chunks, parse, package = sys.argv[1:]
count, threads, wall, rss, size, package = int(count), int(threads), float(wall), int(rss), int(size), float(package)
per_core = count / package / threads / 1e6
print(f"| {kind} | {count:,} | {threads} | {parse} | {package:.2f} | {per_core:.2f} | {wall:.2f} | {rss / 2**20:.2f} | {size / count:.1f} | {chunks} |")
PY
      rm -f "$vast"
    done
    rm -f "$ply"
  done
done
cat "$out"
