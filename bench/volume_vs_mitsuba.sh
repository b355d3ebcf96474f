#!/usr/bin/env bash
# A volume's render time and mean beside Mitsuba 3's `volpath` on the same grid, camera,
# resolution, spp and depth (docs/PERFORMANCE.md, "Volumes"): the fBm cloud of
# bench/volume_cloud.cpp (N^3 voxels over [-1, 1]^3) imported with `--volume` beside one small
# triangle far out of view (a package needs a mesh), lit by a constant environment of 1 and no
# sun (Mitsuba: a `constant` emitter), so that the two images' means compare the light transport.
# Each vastray render runs three times (the first builds its pipelines); the figures are
# `render_seconds` of --stats-json. Then twice out of core: --memory-budget at half the volume's
# device bytes, so that the volume's half of it (a pool of brick slots) holds a quarter of the
# bricks (docs/RENDERING.md, "Volumes out of core"); its image must equal the in-core one.
#
#   usage (on the device machine, vastray and volume_cloud on PATH, Mitsuba on PYTHONPATH):
#     bench/volume_vs_mitsuba.sh MITSUBA_VOLUME.py OUT_DIR
#   Environment: N (512), SPP (64), DEPTH (8), DENSITY (40), ALBEDO (0.8), G (0.3),
#   RESOLUTION (1024x1024), OOC_ROUNDS (2: out-of-core renders), CODEC (float: the bricks' NanoVDB
#   leaves, or fp16, fp8: --volume-codec), KIND (cloud; box: a homogeneous
#   cube of density 1 times DENSITY, which Mitsuba renders with its own `homogeneous` medium).
set -uo pipefail
[ $# -eq 2 ] || { echo "usage: $0 MITSUBA_VOLUME.py OUT_DIR" >&2; exit 2; }
mitsuba=$1 out=$2
mkdir -p "$out"
n=${N:-512} spp=${SPP:-64} depth=${DEPTH:-8} density=${DENSITY:-40} albedo=${ALBEDO:-0.8} g=${G:-0.3}
resolution=${RESOLUTION:-1024x1024} w=${resolution%x*} h=${resolution#*x}
eye=0,0.6,3.4 target=0,0,0 fov=40
start=$(date +%s.%N)
kind=${KIND:-cloud}
volume_cloud "$n" "$out/cloud.vdb" "$out/cloud.vol" "$kind" || exit 1
echo "cloud written in $(python3 -c "import sys; print(round(float(sys.argv[1]) - float(sys.argv[2]), 2))" "$(date +%s.%N)" "$start") s"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n50 50 50\n51 50 50\n50 51 50\n3 0 1 2\n' > "$out/far.ply"
python3 - "$out/const.pfm" <<'PY'
import struct, sys
with open(sys.argv[1], "wb") as o:
    o.write(b"PF\n8 4\n-1.0\n" + struct.pack("<96f", *([1.0] * 96)))
PY
start=$(date +%s.%N)
vastray import "$out/far.ply" -o "$out/cloud.vast" --progress none --volume "$out/cloud.vdb" --volume-density "$density" \
  --volume-albedo "$albedo" --volume-anisotropy "$g" --volume-codec "${CODEC:-float}" > "$out/import.log" 2>&1 || { cat "$out/import.log"; exit 1; }
echo "imported in $(python3 -c "import sys; print(round(float(sys.argv[1]) - float(sys.argv[2]), 2))" "$(date +%s.%N)" "$start") s: $(grep 'read volume' "$out/import.log")"
meanOf() { python3 "$(dirname "$0")/pfm_mean.py" "$1"; }  # the mean R,G,B of a .pfm
for round in 1 2 3; do
  vastray render "$out/cloud.vast" -o "$out/vastray.pfm" --resolution "$resolution" --eye "$eye" --target "$target" \
    --fov "$fov" --spp "$spp" --max-depth "$depth" --environment "$out/const.pfm" --progress none \
    --stats-json "$out/vastray.json" > "$out/render.log" 2>&1 || { echo "render failed: $(tail -2 "$out/render.log")"; exit 1; }
  echo "vastray r$round: render_seconds $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["render_seconds"])' "$out/vastray.json")"
done
echo "vastray mean_rgb $(meanOf "$out/vastray.pfm")"
volumeBytes=$(vastray info "$out/cloud.vast" --json | python3 -c 'import json,sys; print(sum(v["device_bytes"] for v in json.load(sys.stdin)["volumes"]))')
budget=$((volumeBytes / 2 / 1024))KiB
for round in $(seq 1 "${OOC_ROUNDS:-2}"); do
  vastray render "$out/cloud.vast" -o "$out/vastray-ooc.pfm" --resolution "$resolution" --eye "$eye" --target "$target" \
    --fov "$fov" --spp "$spp" --max-depth "$depth" --environment "$out/const.pfm" --progress none --memory-budget "$budget" \
    --stats-json "$out/vastray-ooc.json" > "$out/render-ooc.log" 2>&1 || { echo "render failed: $(tail -2 "$out/render-ooc.log")"; exit 1; }
  python3 - "$out/vastray-ooc.json" "$budget" "$volumeBytes" "$round" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"vastray out of core r{sys.argv[4]} (--memory-budget {sys.argv[2]}, volume {int(sys.argv[3]) / 2**20:.1f} MiB): "
      f"render_seconds {s['render_seconds']}, volume_brick_slots {s['volume_brick_slots']}, "
      f"volume_brick_loads {s['volume_brick_loads']}, submits {s['submits']}, peak_device_bytes {s['peak_device_bytes']}")
PY
done
if [ "${OOC_ROUNDS:-2}" -gt 0 ]; then
  cmp -s "$out/vastray.pfm" "$out/vastray-ooc.pfm" && echo "out-of-core image equals the in-core one bit for bit" \
    || echo "out-of-core image DIFFERS from the in-core one"
fi
[ "$kind" = box ] && export MEDIUM=homogeneous
timeout 400 python3 "$mitsuba" "$out/cloud.vol" "$n" "$w" "$h" "$spp" "$depth" "$eye" "$target" "$fov" "$density" \
  "$albedo" "$g" 2>&1 | tail -1
rm -f "$out/cloud.vdb" "$out/cloud.vol" "$out/cloud.vast"
