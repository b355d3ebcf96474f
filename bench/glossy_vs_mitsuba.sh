#!/usr/bin/env bash
# The metallic-roughness BSDF (docs/RENDERING.md, "Materials") against vastray's Lambertian and
# Mitsuba 3 on the same city, camera, resolution, spp and depth, lit by a constant environment
# map of 1 alone (so the means compare light transport whatever either program's map orientation):
# the city as a Lambertian 0.8 mesh (PLY) and as a white GGX metal of roughness ROUGHNESS (the
# same triangles as glTF, bench/ply_to_gltf.py), Mitsuba's `diffuse` and `roughconductor` (GGX,
# visible normals, Fresnel 1: single scattering only, so its metal is a little darker than
# vastray's, which adds the lost multiple scattering back; at roughness 0.3 the loss is ~1 %).
# Each vastray render runs three times (the first builds its pipelines); the figures are
# `render_seconds` of --stats-json (docs/PERFORMANCE.md, "Glossy materials").
#
#   usage (on the device machine, vastray on PATH, Mitsuba on PYTHONPATH):
#     bench/glossy_vs_mitsuba.sh MITSUBA_ENVMAP.py OUT_DIR
#   Environment: TRIANGLES (2000000), SPP (16), DEPTH (5), ROUGHNESS (0.3), RESOLUTION (1920x1080)
set -uo pipefail
[ $# -eq 2 ] || { echo "usage: $0 MITSUBA_ENVMAP.py OUT_DIR" >&2; exit 2; }
mitsuba=$1 out=$2 here=$(dirname "$0")
mkdir -p "$out"
eye=1.6,1.1,1.9 spp=${SPP:-16} depth=${DEPTH:-5} rough=${ROUGHNESS:-0.3} res=${RESOLUTION:-1920x1080}
vastray generate city --triangles "${TRIANGLES:-2000000}" --seed 1 -o "$out/city.ply" > /dev/null
python3 "$here/ply_to_gltf.py" "$out/city.ply" "$out/metal.gltf" 1,1,1 1 "$rough" || exit 1
vastray import "$out/city.ply" -o "$out/lambert.vast" --progress none --chunk-size 4MiB > /dev/null
vastray import "$out/metal.gltf" -o "$out/metal.vast" --progress none --chunk-size 4MiB > /dev/null
python3 - "$out" <<'PY'
import struct, sys
with open(sys.argv[1] + "/const.pfm", "wb") as o:
    o.write(b"PF\n64 32\n-1.0\n" + struct.pack("<3f", 1.0, 1.0, 1.0) * (64 * 32))
PY
render() {  # NAME PACKAGE
  local name=$1 package=$2
  for round in 1 2 3; do
    vastray render "$package" -o "$out/$name.pfm" --resolution "$res" --eye "$eye" --target 0,0,0 \
      --spp "$spp" --max-depth "$depth" --memory-budget 8GiB --progress none --stats-json "$out/$name.json" \
      --environment "$out/const.pfm" > "$out/$name.log" 2>&1 || { echo "$name: failed: $(tail -2 "$out/$name.log")"; return; }
    echo "$name r$round: render_seconds $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["render_seconds"])' "$out/$name.json")"
  done
  echo "$name mean_rgb $(python3 "$here/pfm_mean.py" "$out/$name.pfm")"
}
render lambert "$out/lambert.vast"
render metal "$out/metal.vast"
w=${res%x*} h=${res#*x}
for material in 0.8 "metal:1,1,1:$rough"; do
  timeout 300 python3 "$mitsuba" "$out/city.ply" "$out/const.pfm" "$w" "$h" "$spp" "$depth" "$eye" 0,0,0 "$material" 2>&1 | tail -1
done
rm -f "$out/city.ply" "$out"/*.vast "$out"/*.pfm "$out"/*.bin "$out"/*.gltf
