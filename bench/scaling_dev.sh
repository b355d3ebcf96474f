#!/usr/bin/env bash
# Scaling on this machine: generated scenes of 1M to 64M triangles, each imported (wall time,
# peak RSS) and rendered from its package by the Embree in-core reference and by the streaming
# Vulkan renderer (a GPU if there is one, else Mesa lavapipe) in core and out of core, all in the
# same run. Every render is timed with /usr/bin/time (wall, peak RSS) and writes --stats-json
# (chunk loads, bytes read and uploaded, trace/decode/upload seconds, peak device bytes).
# Writes docs/generated/scaling_dev.csv (every figure), docs/generated/scaling_dev.md (tables)
# and docs/scaling/*.png (plots), all through bench/scaling_report.py, relative to the current
# directory. `make bench-scaling` runs it.
#
#   bash bench/scaling_dev.sh BUILD_DIR
#
# Knobs (environment, defaults below): SIZES="1000000 4000000 16000000 64000000" KINDS=city
# CHUNK=16MiB (import's default) RESOLUTION=320x240 SPP=1 DEPTH=2 (path depth of the path rows;
# the primary rows are depth 0) OOC_FRACTION=4 (out-of-core budget = resident size / 4, raised to
# the scene's minimum when below it) HOST_CACHE=1GiB (the render default) WORK_DIR (temporary
# files: PLY, package, images; default a fresh directory under /tmp, removed at the end)
set -euo pipefail
build=${1:?usage: bash bench/scaling_dev.sh BUILD_DIR}
vastray="$build/vastray"
here=$(cd "$(dirname "$0")" && pwd)
[ -x "$vastray" ] || { echo "bench-scaling: $vastray not found; build first" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "bench-scaling: /usr/bin/time missing (Debian package time)" >&2; exit 1; }
py=${PYTHON:-/usr/bin/python3}
"$py" -c 'import matplotlib' 2> /dev/null || { echo "bench-scaling: $py lacks matplotlib (make deps installs python3-matplotlib)" >&2; exit 1; }

sizes=${SIZES:-"1000000 4000000 16000000 64000000"}
kinds=${KINDS:-city}
chunk=${CHUNK:-16MiB}
resolution=${RESOLUTION:-320x240}
spp=${SPP:-1}
depth=${DEPTH:-2}
ooc_fraction=${OOC_FRACTION:-4}
host_cache=${HOST_CACHE:-1GiB}
csv=${CSV_FILE:-docs/generated/scaling_dev.csv}
md=${OUT_FILE:-docs/generated/scaling_dev.md}
plots=${PLOT_DIR:-docs/scaling}
if [ -n "${WORK_DIR:-}" ]; then
  work=$WORK_DIR
  mkdir -p "$work"
else
  work=$(mktemp -d /tmp/vastray-scaling.XXXXXX)
  trap 'rm -rf "$work"' EXIT
fi
report() { "$py" -B "$here/scaling_report.py" "$@"; }

command_line="SIZES=\"$sizes\" KINDS=\"$kinds\" CHUNK=$chunk RESOLUTION=$resolution SPP=$spp DEPTH=$depth OOC_FRACTION=$ooc_fraction HOST_CACHE=$host_cache bash bench/scaling_dev.sh $build"
device=$(vulkaninfo --summary 2> /dev/null | sed -n 's/^[[:space:]]*deviceName[[:space:]]*= //p' | head -1 || true)
driver=$(vulkaninfo --summary 2> /dev/null | sed -n 's/^[[:space:]]*driverInfo[[:space:]]*= //p' | head -1 || true)
started=$(date -u '+%Y-%m-%d %H:%M UTC')
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
mkdir -p "$(dirname "$csv")" "$(dirname "$md")" "$plots"
report init "$csv"
# Process start-up alone (dynamic linking of OpenImageIO, Vulkan, Embree): part of every wall time below.
/usr/bin/time -f "%e %M" -o "$work/time.txt" "$vastray" --version > /dev/null
read -r wall rss < "$work/time.txt"
report add "$csv" kind=- requested_triangles=0 triangles=0 step=startup label="vastray --version" \
  wall_s="$wall" peak_rss_bytes=$((rss * 1024)) "load1=$(cut -d' ' -f1 /proc/loadavg)"

# Appends one CSV row: options (--stats/--info/--diff FILE) first, then key=value pairs; adds the
# 1-minute load average now.
row() { report add "$csv" "$@" "load1=$(cut -d' ' -f1 /proc/loadavg)"; }

# render LABEL BACKEND BUDGET DEPTH IMAGE REFERENCE [extra render flags...]
# REFERENCE: an image to `vastray diff` against ('-' for none).
render() {
  local label=$1 backend=$2 budget=$3 d=$4 image=$5 reference=$6
  shift 6
  local args=(render "$vast" -o "$image" --backend "$backend" --resolution "$resolution" --spp "$spp"
    --integrator path --max-depth "$d" --seed 1 --progress none --stats-json "$work/stats.json" "$@")
  [ "$backend" = vulkan ] && args+=(--memory-budget "$budget" --host-cache "$host_cache")
  rm -f "$work/stats.json" "$work/diff.json"
  echo "  $label ..." >&2
  if ! /usr/bin/time -f "%e %M" -o "$work/time.txt" "$vastray" "${args[@]}" > "$work/render.log" 2>&1; then
    cat "$work/render.log" >&2
    echo "bench-scaling: $kind $n: render '$label' failed: $vastray ${args[*]}" >&2
    exit 1
  fi
  local wall rss
  read -r wall rss < "$work/time.txt"
  local diff_args=()
  if [ "$reference" != - ]; then
    "$vastray" diff "$image" "$reference" --json > "$work/diff.json" || true
    diff_args=(--diff "$work/diff.json" "diff_against=$(basename "$reference" .exr)")
  fi
  row --stats "$work/stats.json" "${diff_args[@]}" kind="$kind" requested_triangles="$n" step=render \
    label="$label" backend="$backend" depth="$d" budget_bytes="${budget:-0}" wall_s="$wall" \
    peak_rss_bytes=$((rss * 1024)) chunk_size="$chunk" resolution="$resolution" spp="$spp" \
    host_cache="$([ "$backend" = vulkan ] && echo "$host_cache" || echo -)" image="$(basename "$image")"
}

for kind in $kinds; do
  for n in $sizes; do
    echo "bench-scaling: $kind $n (load $(cut -d' ' -f1 /proc/loadavg))" >&2
    ply="$work/$kind-$n.ply"
    vast="$work/$kind-$n.vast"
    /usr/bin/time -f "%e %M" -o "$work/time.txt" "$vastray" generate "$kind" --triangles "$n" --seed 1 -o "$ply" > /dev/null
    read -r gen_wall gen_rss < "$work/time.txt"
    ply_bytes=$(stat -c %s "$ply")
    /usr/bin/time -f "%e %M" -o "$work/time.txt" \
      "$vastray" import "$ply" -o "$vast" --chunk-size "$chunk" --progress none > "$work/import.log"
    read -r wall rss < "$work/time.txt"
    rm -f "$ply"
    parse=$(sed -n 's/^read .* in \([0-9.]*\) s.*/\1/p' "$work/import.log")
    package=$(sed -n 's/^  \([0-9.]*\) s total.*/\1/p' "$work/import.log")
    "$vastray" info "$vast" --json > "$work/info.json"
    row --info "$work/info.json" kind="$kind" requested_triangles="$n" step=import label=import \
      wall_s="$wall" peak_rss_bytes=$((rss * 1024)) parse_s="$parse" package_s="$package" \
      generate_s="$gen_wall" generate_peak_rss_bytes=$((gen_rss * 1024)) ply_bytes="$ply_bytes" \
      chunk_size="$chunk" threads="$(nproc)"

    # Budgets. The minimum (one slot of the largest chunk plus a minimal ray batch) comes from the
    # renderer's own error message for a 1-byte budget, asked with the primid AOV (primitive ids
    # make the slots larger, and the check render below needs them); in core gives every chunk a
    # slot of that size plus the largest ray batch; out of core is the resident size / OOC_FRACTION.
    minimum=$("$vastray" render "$vast" -o "$work/probe.exr" --aovs primid --resolution 1x1 --spp 1 \
      --memory-budget 1B --progress none 2>&1 | sed -n 's/.* = \([0-9]*\) bytes .*/\1/p' | head -1 || true)
    [ -n "$minimum" ] || { echo "bench-scaling: could not read the minimum budget of $vast" >&2; exit 1; }
    read -r chunks resident < <("$py" -c 'import json,sys; j=json.load(open(sys.argv[1])); print(j["chunks"], sum(c["resident_bytes"] for c in j["chunk"]))' "$work/info.json")
    in_core=$((chunks * minimum + 128 * 1024 * 1024))
    out_of_core=$((resident / ooc_fraction))
    [ "$out_of_core" -ge "$minimum" ] || out_of_core=$minimum

    # Embree first (the reference images); the primary render carries the primid AOV for the
    # agreement check (its extra pixel-centre rays are a negligible part of an Embree render).
    render "embree, primary" embree "" 0 "$work/embree-d0.exr" - --aovs primid
    render "embree, path depth $depth" embree "" "$depth" "$work/embree-d$depth.exr" -
    render "vulkan in core, primary" vulkan "$in_core" 0 "$work/vk-in-d0.exr" -
    render "vulkan in core, path depth $depth" vulkan "$in_core" "$depth" "$work/vk-in-d$depth.exr" "$work/embree-d$depth.exr"
    render "vulkan out of core, primary" vulkan "$out_of_core" 0 "$work/vk-out-d0.exr" "$work/vk-in-d0.exr"
    render "vulkan out of core, path depth $depth" vulkan "$out_of_core" "$depth" "$work/vk-out-d$depth.exr" "$work/embree-d$depth.exr"
    # Not a timing row: the primid AOV adds a second camera-ray stream, so it is rendered apart
    # (out of core, the harder case) and compared with Embree's primary render.
    render "check: vulkan out of core, primary + primid" vulkan "$out_of_core" 0 "$work/vk-out-d0-primid.exr" "$work/embree-d0.exr" --aovs primid
    rm -f "$vast" "$work"/*.exr
  done
done

load_end=$(cut -d' ' -f1-3 /proc/loadavg)
report report "$csv" --md "$md" --plots "$plots" --command "$command_line" --started "$started" \
  --finished "$(date -u '+%Y-%m-%d %H:%M UTC')" --load-start "$load_start" --load-end "$load_end" \
  --device "${device:-unknown} (${driver:-unknown driver})" --ooc-fraction "$ooc_fraction"
cat "$md"
