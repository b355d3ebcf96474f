#!/usr/bin/env bash
# Textures on the device (issue 13, docs/PERFORMANCE.md "Textures on the device"): a textured
# height field (bench/textured_scene.py) rendered by vastray with its texture in core, with the
# texture pool four times over-subscribed (each with ray cones, then --texture-lod finest: level 0
# as Mitsuba samples), and without the texture (the same mesh, no material),
# beside Mitsuba 3 on the same PLY, textured and plain, same camera, resolution, spp and depth.
#
#   usage (on the device machine, vastray on PATH, Mitsuba on PYTHONPATH):
#     bench/textured_vs_mitsuba.sh OUT_DIR [GRID] [TEXELS] [SPP:DEPTH]
#   GRID x GRID quads (default 700: 980 k triangles), a TEXELS^2 texture (default 4096), default
#   16:5 at 1920x1080. Each vastray row is three processes (`vastray render --stats-json`; its
#   render_seconds excludes the process's and device's start-up). PACKAGE, PACKAGE_NM:
#   terrain.vast and terrain-nm.vast (the same with the normal map) imported elsewhere from the
#   same GRID and TEXELS (the device machine lacks the OpenImageIO module that reads the PNG at
#   import). Row normal-mapped: terrain-nm, in core, cones; Mitsuba's row of the same name wraps
#   its textured diffuse BSDF in a `normalmap` of normal.png.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=$1 grid=${2:-700} texels=${3:-4096} config=${4:-16:5}
spp=${config%%:*} depth=${config##*:}
eye=0,1.2,2.2 target=0,0,0 width=1920 height=1080
work=${WORK:-/tmp/vastray-textured}
mkdir -p "$out" "$work"
python3 "$here/textured_scene.py" "$work" "$grid" "$texels" > "$out/scene.txt"
if [ -n "${PACKAGE:-}" ]; then cp "$PACKAGE" "$work/terrain.vast"
else vastray import "$work/terrain.obj" -o "$work/terrain.vast" --progress none >> "$out/import.txt" 2>&1; fi
if [ -n "${PACKAGE_NM:-}" ]; then cp "$PACKAGE_NM" "$work/terrain-nm.vast"
else vastray import "$work/terrain-nm.obj" -o "$work/terrain-nm.vast" --progress none >> "$out/import.txt" 2>&1; fi
vastray import "$work/plain.obj" -o "$work/plain.vast" --progress none >> "$out/import.txt" 2>&1
vastray info "$work/terrain.vast" --json > "$out/info.json"
# The budget whose quarter (the texture pool's share) holds a quarter of the texture's pages.
texture_bytes=$(python3 -c "import json; t=json.load(open('$out/info.json'))['textures']; print(sum(x['pages'] for x in t) * 66564)")
tight=$((texture_bytes))
rows="in-core terrain 8GiB cone|pool-4x terrain $tight cone|in-core-finest terrain 8GiB finest|pool-4x-finest terrain $tight finest|untextured plain 8GiB cone|normal-mapped terrain-nm 8GiB cone"
IFS='|' read -ra row_list <<< "$rows"
for row in "${row_list[@]}"; do
  set -- $row
  for run in 1 2 3; do
    vastray render "$work/$2.vast" -o "$work/$1.pfm" --resolution "${width}x${height}" --eye "$eye" --target "$target" \
      --spp "$spp" --max-depth "$depth" --memory-budget "$3" --texture-lod "$4" --progress none \
      --stats-json "$out/$1-$run.json" \
      >> "$out/vastray.log" 2>&1 || echo "$1 run $run failed" >> "$out/vastray.log"
  done
done
timeout 300 python3 "$here/mitsuba_textured.py" "$work/terrain.ply" "$work/albedo.png" "$work/normal.png" "$width" "$height" "$spp" "$depth" \
  "$eye" "$target" >> "$out/mitsuba.jsonl" 2>> "$out/mitsuba.log" || echo "mitsuba failed: $?" >> "$out/mitsuba.log"
python3 - "$out" <<'PY' > "$out/summary.md"
import glob, json, statistics, sys
out = sys.argv[1]
print("| render | vastray render_seconds (median of 3) | texture page slots | page loads | pages read | peak device bytes |")
print("|---|---|---|---|---|---|")
for row in ("in-core", "pool-4x", "in-core-finest", "pool-4x-finest", "untextured", "normal-mapped"):
    runs = [json.load(open(f)) for f in sorted(glob.glob(f"{out}/{row}-[0-9].json"))]  # in-core-[0-9]: not in-core-finest-N
    if not runs:
        print(f"| {row} | failed | | | | |"); continue
    s = [r.get("streaming", r) for r in runs]
    med = statistics.median(r["render_seconds"] for r in runs)
    print(f"| {row} | {med:.4f} | {s[0].get('texture_page_slots')} | {s[0].get('texture_page_loads')} | "
          f"{s[0].get('texture_pages_read')} | {s[0].get('peak_device_bytes')} |")
for line in open(f"{out}/mitsuba.jsonl"):
    m = json.loads(line)
    print(f"| Mitsuba {m['material']} | {m['render_s_median']} (load {m['load_s']}, first {m['first_render_s']}) | | | | GPU {m['gpu_mib_after']} MiB |")
PY
cat "$out/summary.md"
exit 0
