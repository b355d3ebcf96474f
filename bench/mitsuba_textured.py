"""Mitsuba 3 on bench/textured_scene.py's terrain: the PLY (with u, v) under a bitmap texture, or
under the texture's mean colour ("plain"), or textured under a `normalmap` of NORMAL.png
("normal-mapped"), the same camera and lighting as mitsuba_bench.py.

usage: python3 mitsuba_textured.py TERRAIN.ply ALBEDO.png NORMAL.png WIDTH HEIGHT SPP MAX_DEPTH EYE TARGET
Prints one JSON line per material (textured, plain): load time, the median of three renders
after a first (JIT) one, GPU memory from nvidia-smi.
"""
import json, subprocess, sys, time

ply, png, normal_png = sys.argv[1], sys.argv[2], sys.argv[3]
w, h, spp, depth = int(sys.argv[4]), int(sys.argv[5]), int(sys.argv[6]), int(sys.argv[7])
eye = [float(x) for x in sys.argv[8].split(",")]
target = [float(x) for x in sys.argv[9].split(",")]

import mitsuba as mi
import drjit as dr
from mitsuba_timing import perspective_sensor, time_renders

mi.set_variant("cuda_ad_rgb")


def gpu_used_mib():
    try:
        out = subprocess.run(["nvidia-smi", "--query-gpu=memory.used", "--format=csv,noheader,nounits"],
                             capture_output=True, text=True, timeout=20).stdout
        return int(out.split()[0])
    except Exception:  # noqa: BLE001
        return None


textured = {"type": "bitmap", "filename": png, "filter_type": "bilinear"}
for name, bsdf in (("textured", {"type": "diffuse", "reflectance": textured}),
                   ("plain", {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.5, 0.5, 0.5]}}),
                   ("normal-mapped", {"type": "normalmap",
                                      "normalmap": {"type": "bitmap", "filename": normal_png, "raw": True,
                                                    "filter_type": "bilinear"},
                                      "bsdf": {"type": "diffuse", "reflectance": textured}})):
    before = gpu_used_mib()
    t0 = time.perf_counter()
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": depth + 1, "rr_depth": 3},  # vastray's roulette (PERF_NOTES 73)
        "sensor": perspective_sensor(mi, eye, target, w, h, spp),
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [0.8, 0.9, 1.0]}},
        "sun": {"type": "directional", "direction": [-0.3, -1.0, -0.2], "irradiance": {"type": "rgb", "value": [3.0, 3.0, 3.0]}},
        "mesh": {"type": "ply", "filename": ply, "bsdf": bsdf},
    })
    load_s = time.perf_counter() - t0
    figures, _ = time_renders(mi, dr, scene, spp)
    print(json.dumps({"material": name, "resolution": f"{w}x{h}", "spp": spp, "vastray_depth": depth,
                      "load_s": round(load_s, 3), "first_render_s": figures["first_render_s"],
                      "render_s_median": figures["render_s_median"], "gpu_mib_before": before,
                      "gpu_mib_after": gpu_used_mib()}),
          flush=True)
    del scene
