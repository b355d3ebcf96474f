#!/usr/bin/env bash
# The main job on a built-in demo scene: generate a procedural city, import it into a
# chunked scene package with a small chunk size, verify it and describe it.
# Rendering the package arrives with the renderer (see README "Status").
set -euo pipefail
vastray=${1:-build/vastray}
out=${2:-build/demo}
mkdir -p "$out"
"$vastray" generate city --triangles 300000 --seed 7 -o "$out/city.ply"
"$vastray" import "$out/city.ply" -o "$out/city.vast" --chunk-size 1MiB
"$vastray" info "$out/city.vast" --verify --export-cells "$out/city-cells.obj"
echo
echo "demo: scene package $out/city.vast; its cells (open in Blender/Houdini): $out/city-cells.obj"
