#!/usr/bin/env bash
# The main job on a built-in demo scene: generate a procedural city, import it into a
# chunked scene package with a small chunk size, verify it, and render the package with
# the Embree reference renderer to demo.png (the streaming Vulkan tracer is not built yet).
set -euo pipefail
vastray=${1:-build/vastray}
out=${2:-build/demo}
mkdir -p "$out"
"$vastray" generate city --triangles 300000 --seed 7 -o "$out/city.ply"
"$vastray" import "$out/city.ply" -o "$out/city.vast" --chunk-size 1MiB
"$vastray" info "$out/city.vast" --verify --export-cells "$out/city-cells.obj"
"$vastray" render "$out/city.vast" -o "$out/demo.png" --backend embree --resolution 640x480 --spp 16 \
  --eye 1.6,1.1,1.9 --target 0,0,0 --stats
echo
echo "demo: image $out/demo.png"
echo "      scene package $out/city.vast, its cells (open in Blender/Houdini) $out/city-cells.obj"
