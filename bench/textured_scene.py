"""A textured height-field scene for bench/textured_vs_mitsuba.sh, with the standard library only.

usage: python3 textured_scene.py OUT_DIR GRID TEXELS
Writes OUT_DIR/terrain.obj (+ terrain.mtl whose map_Kd is albedo.png), OUT_DIR/plain.obj (the
same mesh without a material), OUT_DIR/terrain.ply (binary, with u, v: what Mitsuba reads) and
OUT_DIR/albedo.png (TEXELS x TEXELS RGB: cells of 16 x 16 texels of hashed colours, so that no
page repeats and the pages compress well), and the normal-mapped variant: OUT_DIR/terrain-nm.obj
(+ terrain-nm.mtl: the same map_Kd and `norm normal.png`) and OUT_DIR/normal.png (TEXELS/4 square,
a tangent-space normal map of 32 x 32 bumps per repetition, linear RGB = (n + 1) / 2; the
bumps' normals are symmetric under a flip of either tangent axis, so the image's mean does not
depend on the renderer's green-channel convention). The grid has
GRID x GRID quads (2 GRID^2 triangles) over [-1, 1]^2 in x-z, y a sum of sines; UVs span [0, 4]
(the texture repeats four times across).
"""
import math, os, struct, sys, zlib

out, grid, texels = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
os.makedirs(out, exist_ok=True)

def height(x, z):
    return 0.08 * math.sin(3.1 * x) * math.cos(2.3 * z) + 0.03 * math.sin(11.0 * x + 7.0 * z)

n = grid + 1
verts, uvs = [], []
for j in range(n):
    for i in range(n):
        x, z = -1.0 + 2.0 * i / grid, -1.0 + 2.0 * j / grid
        verts.append((x, height(x, z), z))
        uvs.append((4.0 * i / grid, 4.0 * j / grid))
faces = []
for j in range(grid):
    for i in range(grid):
        a = j * n + i
        faces.append((a, a + n, a + 1))
        faces.append((a + 1, a + n, a + n + 1))

with open(os.path.join(out, "terrain.mtl"), "w") as f:
    f.write("newmtl ground\nKd 1 1 1\nmap_Kd albedo.png\n")
with open(os.path.join(out, "terrain-nm.mtl"), "w") as f:
    f.write("newmtl ground\nKd 1 1 1\nmap_Kd albedo.png\nnorm normal.png\n")
for name, textured in (("terrain.obj", "terrain.mtl"), ("terrain-nm.obj", "terrain-nm.mtl"), ("plain.obj", None)):
    with open(os.path.join(out, name), "w") as f:
        if textured:
            f.write("mtllib %s\nusemtl ground\n" % textured)
        f.write("".join("v %.6f %.6f %.6f\n" % v for v in verts))
        if textured:
            f.write("".join("vt %.6f %.6f\n" % t for t in uvs))
            f.write("".join("f %d/%d %d/%d %d/%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1) for a, b, c in faces))
        else:
            f.write("".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in faces))

with open(os.path.join(out, "terrain.ply"), "wb") as f:
    f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
             "property float z\nproperty float u\nproperty float v\nelement face %d\n"
             "property list uchar int vertex_indices\nend_header\n" % (len(verts), len(faces))).encode())
    f.write(b"".join(struct.pack("<5f", *v, *t) for v, t in zip(verts, uvs)))
    f.write(b"".join(struct.pack("<B3i", 3, *face) for face in faces))

def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

rows = bytearray()
for y in range(texels):
    rows.append(0)
    for x in range(texels):
        h = ((x >> 4) * 73856093 ^ (y >> 4) * 19349663) & 0xFFFFFF
        rows += bytes((64 + (h & 0x7F), 64 + ((h >> 8) & 0x7F), 64 + ((h >> 16) & 0x7F)))
with open(os.path.join(out, "albedo.png"), "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", texels, texels, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(bytes(rows), 6)) + chunk(b"IEND", b""))
normal_texels = max(texels // 4, 64)
cell = normal_texels / 32.0
rows = bytearray()
for y in range(normal_texels):
    rows.append(0)
    for x in range(normal_texels):
        nx = 0.45 * math.sin(2.0 * math.pi * (x + 0.5) / cell)
        ny = 0.45 * math.sin(2.0 * math.pi * (y + 0.5) / cell)
        nz = math.sqrt(max(0.0, 1.0 - nx * nx - ny * ny))
        rows += bytes(min(255, max(0, int(round((c + 1.0) * 127.5)))) for c in (nx, ny, nz))
with open(os.path.join(out, "normal.png"), "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", normal_texels, normal_texels, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(bytes(rows), 6)) + chunk(b"IEND", b""))
print("faces %d, vertices %d, texels %d^2, normal map %d^2" % (len(faces), len(verts), texels, normal_texels))
