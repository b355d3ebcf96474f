"""Mitsuba 3's `volpath` on the cloud of bench/volume_cloud.cpp, for `vastray render` of the same
grid imported with `--volume` (docs/PERFORMANCE.md, "Volumes").

usage: python3 mitsuba_volume.py CLOUD.vol N WIDTH HEIGHT SPP MAX_DEPTH EYE TARGET FOV DENSITY ALBEDO G [VARIANT]
A `heterogeneous` medium (sigma_t: a trilinear `gridvolume` of the .vol scaled by DENSITY, albedo
ALBEDO, Henyey-Greenstein G) inside a cube (an OBJ of [-1, 1]^3 written beside the grid, since
the peer bundle's Mitsuba has no `cube` plugin) with a `null` BSDF, lit by a `constant` emitter of
radiance 1 (vastray: a constant --environment map of 1, no sun). vastray's voxel ijk sits at the
world point ijk * 2/N - 1; Mitsuba's voxel i at the grid's local (i + 0.5) / N, so the grid's
to_world is scale 2 then translate -1 - 1/N. max_depth is vastray's --max-depth + 1. Prints one
JSON line: load time, the first and the later renders' times, and the image's mean (RGB).
With MEDIUM=homogeneous in the environment, Mitsuba's own `homogeneous` medium of sigma_t DENSITY
fills the cube that volume_cloud's `box` grid holds (an independent check: no grid on its side).
"""
import json, os, sys, time

vol, n = sys.argv[1], int(sys.argv[2])
w, h, spp, depth = int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), int(sys.argv[6])
eye = [float(x) for x in sys.argv[7].split(",")]
target = [float(x) for x in sys.argv[8].split(",")]
fov, density, albedo, g = float(sys.argv[9]), float(sys.argv[10]), float(sys.argv[11]), float(sys.argv[12])
variant = sys.argv[13] if len(sys.argv) > 13 else "cuda_ad_rgb"

import mitsuba as mi
import drjit as dr
from mitsuba_timing import perspective_sensor, time_renders

mi.set_variant(variant)
T = mi.ScalarTransform4f
offset = -1.0 - 1.0 / n
# MEDIUM=homogeneous: Mitsuba's `homogeneous` medium (sigma_t = DENSITY) in the cube that
# volume_cloud's `box` grid fills: half size midway between the last voxel centre inside |c| < 0.8
# and the first outside (voxel centres at (i - n/2) 2/n).
homogeneous = None
cube = T().translate([offset + 1.0] * 3).scale(1.0)
if os.environ.get("MEDIUM") == "homogeneous":
    inside = max(k for k in range(n) if k * 2.0 / n < 0.8)
    half = (inside + 0.5) * 2.0 / n
    cube = T().scale(half)
    homogeneous = {"type": "homogeneous", "sigma_t": density, "albedo": {"type": "rgb", "value": [albedo] * 3},
                   "phase": {"type": "hg", "g": g}}


def write_cube(path):
    """[-1, 1]^3 as 12 triangles wound counter-clockwise seen from outside (outward normals)."""
    corners = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    index = {c: i + 1 for i, c in enumerate(corners)}
    faces = []
    for axis in range(3):
        for sign in (-1, 1):
            u, v = (axis + 1) % 3, (axis + 2) % 3
            quad = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                c = [0, 0, 0]
                c[axis], c[u], c[v] = sign, a * sign, b
                quad.append(index[tuple(c)])
            faces += [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
    with open(path, "w") as f:
        f.writelines("v %d %d %d\n" % c for c in corners)
        f.writelines("f %d %d %d\n" % t for t in faces)
    return path


t0 = time.perf_counter()
scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "volpath", "max_depth": depth + 1, "rr_depth": 3},  # vastray's roulette (PERF_NOTES 73)
    "sensor": perspective_sensor(mi, eye, target, w, h, spp, fov=fov, pixel_format="rgb"),
    "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}},
    "cloud": {
        "type": "obj",
        "filename": write_cube(vol + ".cube.obj"),
        "face_normals": True,
        "to_world": cube,
        "bsdf": {"type": "null"},
        "interior": homogeneous if homogeneous else {
            "type": "heterogeneous",
            "sigma_t": {"type": "gridvolume", "filename": vol, "filter_type": "trilinear",
                        "to_world": T().translate([offset] * 3).scale(2.0)},
            "albedo": {"type": "rgb", "value": [albedo] * 3},
            "scale": density,
            "phase": {"type": "hg", "g": g},
        },
    },
})
load_s = time.perf_counter() - t0
figures, img = time_renders(mi, dr, scene, spp)
pixels = mi.TensorXf(img).numpy()
mi.util.write_bitmap(sys.argv[1] + ".mitsuba.exr", img)
print(json.dumps({"program": "mitsuba volpath " + variant, "load_s": round(load_s, 3), **figures,
                  "mean_rgb": [float(pixels[..., c].mean()) for c in range(3)]}), flush=True)
