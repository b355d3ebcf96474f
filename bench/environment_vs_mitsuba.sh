#!/usr/bin/env bash
# `vastray render --environment` beside vastray's analytic sky and Mitsuba 3's `envmap` emitter on
# the same city, camera, resolution, spp and depth (docs/PERFORMANCE.md, "Environment maps").
# Two maps: a constant one (1.0; the means of vastray's and Mitsuba's images compare the light
# transport, as neither depends on the map's orientation) and a 512x256 sky with a small bright
# sun (the case importance sampling is for; time only). Renders: the default sky and sun, each map
# in core, and the sky map at a budget 4x below the scene (out of core). Each vastray render runs
# three times (the first builds its pipelines); the figures are `render_seconds` of --stats-json.
#
#   usage (on the device machine, vastray on PATH, Mitsuba on PYTHONPATH):
#     bench/environment_vs_mitsuba.sh MITSUBA_ENVMAP.py OUT_DIR
#   Environment: TRIANGLES (10000000), SPP (16), DEPTH (5), BUDGET_OUT (the sky map's out-of-core
#   budget, 77MiB: the 74.5 MiB that puts city 10M 4x over budget (PERFORMANCE.md) plus the map's
#   2.5 MiB; the default sky and sun are rendered at 74.5MiB beside it).
set -uo pipefail
[ $# -eq 2 ] || { echo "usage: $0 MITSUBA_ENVMAP.py OUT_DIR" >&2; exit 2; }
mitsuba=$1 out=$2
mkdir -p "$out"
eye=1.6,1.1,1.9 spp=${SPP:-16} depth=${DEPTH:-5}
vastray generate city --triangles "${TRIANGLES:-10000000}" --seed 1 -o "$out/city.ply" > /dev/null
vastray import "$out/city.ply" -o "$out/city.vast" --progress none --chunk-size 4MiB > /dev/null
python3 - "$out" <<'PY'
import math, struct, sys
def pfm(path, w, h, f):  # rows bottom to top
    with open(path, "wb") as o:
        o.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        for y in reversed(range(h)):
            o.write(b"".join(struct.pack("<3f", *f(x, y)) for x in range(w)))
def sky(x, y, w=512, h=256):
    v = (y + 0.5) / h
    if abs(x - 80) <= 2 and abs(y - 50) <= 2:
        return (2000.0, 1800.0, 1500.0)
    return (0.3 + 0.5 * (1 - v), 0.4 + 0.4 * (1 - v), 0.8) if y < h // 2 else (0.2, 0.18, 0.15)
pfm(sys.argv[1] + "/const.pfm", 64, 32, lambda x, y: (1.0, 1.0, 1.0))
pfm(sys.argv[1] + "/sky.pfm", 512, 256, sky)
PY
meanOf() { python3 "$(dirname "$0")/pfm_mean.py" "$1"; }  # the mean R,G,B of a .pfm
render() {  # NAME BUDGET FLAGS...
  local name=$1 budget=$2; shift 2
  for round in 1 2 3; do
    vastray render "$out/city.vast" -o "$out/$name.pfm" --resolution 1920x1080 --eye "$eye" --target 0,0,0 \
      --spp "$spp" --max-depth "$depth" --memory-budget "$budget" --progress none --stats-json "$out/$name.json" "$@" \
      > "$out/$name.log" 2>&1 || { echo "$name: failed: $(tail -2 "$out/$name.log")"; return; }
    echo "$name r$round: render_seconds $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["render_seconds"])' "$out/$name.json")"
  done
  echo "$name mean_rgb $(meanOf "$out/$name.pfm")"
}
render sky-and-sun 8GiB
render const-map 8GiB --environment "$out/const.pfm"
render sky-map 8GiB --environment "$out/sky.pfm"
render sky-and-sun-out-of-core 74.5MiB
render sky-map-out-of-core "${BUDGET_OUT:-77MiB}" --environment "$out/sky.pfm"
for map in const sky; do
  timeout 300 python3 "$mitsuba" "$out/city.ply" "$out/$map.pfm" 1920 1080 "$spp" "$depth" "$eye" 0,0,0 0.8 2>&1 | tail -1
done
rm -f "$out/city.ply" "$out/city.vast" "$out"/*.pfm
