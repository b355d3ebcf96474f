"""A binary little-endian PLY of float x y z vertices and uchar-uint triangle lists (what
`vastray generate` writes) as a glTF 2.0 file with one metallic-roughness material, for
bench/glossy_vs_mitsuba.sh. Pure Python (the device machine has no numpy).

usage: python3 ply_to_gltf.py IN.ply OUT.gltf R,G,B METALLIC ROUGHNESS
"""
import json, os, struct, sys
from array import array

src, dst = sys.argv[1], sys.argv[2]
base = [float(v) for v in sys.argv[3].split(",")] + [1.0]
metallic, roughness = float(sys.argv[4]), float(sys.argv[5])
with open(src, "rb") as f:
    data = f.read()
end = data.index(b"end_header\n") + len(b"end_header\n")
header = data[:end].decode("ascii").splitlines()
if "format binary_little_endian 1.0" not in header:
    sys.exit(f"{src}: not a binary little-endian PLY")
counts = {line.split()[1]: int(line.split()[2]) for line in header if line.startswith("element ")}
vertices, faces = counts["vertex"], counts["face"]
if "property list uchar uint vertex_indices" not in header or header.count("property float x") != 1:
    sys.exit(f"{src}: expected float x y z vertices and uchar-uint face lists")
positions = array("f")
positions.frombytes(data[end:end + 12 * vertices])
indices = array("I")
for count, a, b, c in struct.iter_unpack("<BIII", data[end + 12 * vertices:end + 12 * vertices + 13 * faces]):
    if count != 3:
        sys.exit(f"{src}: a face with {count} corners")
    indices.extend((a, b, c))
lo = [min(positions[i::3]) for i in range(3)]
hi = [max(positions[i::3]) for i in range(3)]
bin_name = os.path.splitext(os.path.basename(dst))[0] + ".bin"
with open(os.path.join(os.path.dirname(dst) or ".", bin_name), "wb") as f:
    f.write(positions.tobytes())
    f.write(indices.tobytes())
gltf = {
    "asset": {"version": "2.0", "generator": "vastray bench/ply_to_gltf.py"},
    "buffers": [{"uri": bin_name, "byteLength": 12 * vertices + 12 * faces}],
    "bufferViews": [{"buffer": 0, "byteLength": 12 * vertices},
                    {"buffer": 0, "byteOffset": 12 * vertices, "byteLength": 12 * faces}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": vertices, "min": lo, "max": hi},
                  {"bufferView": 1, "componentType": 5125, "type": "SCALAR", "count": 3 * faces}],
    "materials": [{"name": "glossy", "doubleSided": True,
                   "pbrMetallicRoughness": {"baseColorFactor": base, "metallicFactor": metallic,
                                            "roughnessFactor": roughness}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0,
}
with open(dst, "w") as f:
    json.dump(gltf, f)
