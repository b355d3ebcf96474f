"""Mitsuba 3 lit by a latitude-longitude environment map alone, for `vastray render --environment`.

usage: python3 mitsuba_envmap.py MESH.ply ENVMAP WIDTH HEIGHT SPP MAX_DEPTH EYE TARGET MATERIAL [VARIANT]
MATERIAL: a number (a diffuse mesh of that reflectance) or metal:R,G,B:ROUGHNESS (a
`roughconductor`: GGX of alpha ROUGHNESS^2 with visible-normal sampling, Fresnel 1 times R,G,B;
single scattering only, where vastray's metal adds the lost multiple scattering back).
Mitsuba's `envmap` emitter (importance sampled, MIS in its `path` integrator) and a diffuse mesh of
reflectance ALBEDO with face normals (as vastray shades a mesh without normals); no sun. max_depth is vastray's --max-depth + 1. Prints one JSON line: load
time, the first and the later renders' times, and the image's mean (RGB). With a constant map the
image does not depend on how either program orients the map, so the means compare the light
transport; with another map they compare only the time (Mitsuba's envmap turns the map its own
way: docs/RENDERING.md, "Environment map").
"""
import json, sys, time

mesh, envmap = sys.argv[1], sys.argv[2]
w, h, spp, depth = int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), int(sys.argv[6])
eye = [float(x) for x in sys.argv[7].split(",")]
target = [float(x) for x in sys.argv[8].split(",")]
material = sys.argv[9]
if material.startswith("metal:"):
    _, rgb, rough = material.split(":")
    bsdf = {"type": "roughconductor", "material": "none", "distribution": "ggx", "alpha": float(rough) ** 2,
            "specular_reflectance": {"type": "rgb", "value": [float(v) for v in rgb.split(",")]}}
else:
    bsdf = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [float(material)] * 3}}
variant = sys.argv[10] if len(sys.argv) > 10 else "cuda_ad_rgb"

import mitsuba as mi
import drjit as dr
from mitsuba_timing import perspective_sensor, time_renders

mi.set_variant(variant)
t0 = time.perf_counter()
scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "path", "max_depth": depth + 1, "rr_depth": 3},  # vastray's roulette (PERF_NOTES 73)
    "sensor": perspective_sensor(mi, eye, target, w, h, spp, pixel_format="rgb"),
    "sky": {"type": "envmap", "filename": envmap},
    # face_normals: Mitsuba would otherwise smooth the normals of a PLY without any over shared
    # vertices (a generated city's box corners), which vastray does not do.
    "mesh": {"type": "ply", "filename": mesh, "face_normals": True,
             "bsdf": bsdf},
})
load_s = time.perf_counter() - t0
figures, img = time_renders(mi, dr, scene, spp)
pixels = mi.TensorXf(img).numpy()
print(json.dumps({"program": "mitsuba " + variant, "envmap": envmap, "material": material, "load_and_bvh_s": round(load_s, 3), **figures,
                  "mean_rgb": [float(pixels[..., c].mean()) for c in range(3)]}), flush=True)
