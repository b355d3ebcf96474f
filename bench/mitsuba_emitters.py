"""Mitsuba 3's render of emitter_sampling_bench's box (bench/emitter_sampling_bench.cpp, one lamp):
the same walls, lamp, camera and path depth, its `path` integrator sampling the area light with
MIS. Prints its render time (mitsuba_timing's four renders) and mean RGB as JSON and writes the
image as .pfm; with --compare VASTRAY.pfm also the relative RMSE between the two images and the
ratio of their means (both noisy: give both many samples).

usage: mitsuba_emitters.py [--variant llvm_ad_rgb] [--resolution 128x128] [--spp 1024] [--depth 5]
                           [--out box-mitsuba.pfm] [--compare box-vastray.pfm]"""
import argparse, array, json, sys

import mitsuba as mi
import drjit as dr

from mitsuba_timing import perspective_sensor, time_renders


def read_pfm(path):
    data = open(path, "rb").read()
    end = 0
    header = []
    for _ in range(3):
        nxt = data.index(b"\n", end) + 1
        header.append(data[end:nxt].decode().strip())
        end = nxt
    width, height = map(int, header[1].split())
    values = array.array("f")
    values.frombytes(data[end:])
    return width, height, values


def write_pfm(path, width, height, rows_top_first):
    """rows_top_first: flat RGB floats, row 0 at the top; PFM stores the bottom row first."""
    out = array.array("f")
    for y in reversed(range(height)):
        out.extend(rows_top_first[3 * width * y: 3 * width * (y + 1)])
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (width, height))
        f.write(out.tobytes())


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--variant", default="llvm_ad_rgb")
    p.add_argument("--resolution", default="128x128")
    p.add_argument("--spp", type=int, default=1024)
    p.add_argument("--depth", type=int, default=5, help="vastray's path depth (Mitsuba's max_depth is one more)")
    p.add_argument("--rr-depth", type=int, default=3,
                   help="Mitsuba's rr_depth: 3, vastray's roulette from the 3rd scattering event, by default "
                        "(Mitsuba's own default is 5; PERF_NOTES 73)")
    p.add_argument("--out", default="box-mitsuba.pfm")
    p.add_argument("--compare", default="")
    a = p.parse_args()
    mi.set_variant(a.variant)
    w, h = map(int, a.resolution.split("x"))
    T = mi.ScalarTransform4f

    def wall(to_world, rgb):
        return {"type": "rectangle", "to_world": to_world,
                "bsdf": {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": rgb}}}}

    white, red, green = [0.7, 0.7, 0.7], [0.6, 0.1, 0.1], [0.1, 0.6, 0.1]
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": a.depth + 1, "rr_depth": a.rr_depth},
        "sensor": perspective_sensor(mi, [0, 0, 0.95], [0, 0, -1], w, h, a.spp, fov=75, pixel_format="rgb"),
        "floor": wall(T().translate([0, -1, 0]) @ T().rotate([1, 0, 0], -90), white),
        "ceiling": wall(T().translate([0, 1, 0]) @ T().rotate([1, 0, 0], 90), white),
        "back": wall(T().translate([0, 0, -1]), white),
        "front": wall(T().translate([0, 0, 1]), white),
        "left": wall(T().translate([-1, 0, 0]) @ T().rotate([0, 1, 0], 90), red),
        "right": wall(T().translate([1, 0, 0]) @ T().rotate([0, 1, 0], -90), green),
        # The lamp: a square of side 0.5 just under the ceiling, emitting downwards only.
        "lamp": {"type": "rectangle",
                 "to_world": T().translate([0, 0.999, 0]) @ T().rotate([1, 0, 0], 90) @ T().scale([0.25, 0.25, 1]),
                 "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}},
                 "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [12, 10, 8]}}},
    })
    timing, img = time_renders(mi, dr, scene, a.spp)
    pixels = [float(v) for v in dr.ravel(img)]
    write_pfm(a.out, w, h, pixels)
    n = w * h
    mean = [sum(pixels[c::3]) / n for c in range(3)]
    result = {"variant": a.variant, "resolution": a.resolution, "spp": a.spp, "max_depth": a.depth + 1, "rr_depth": a.rr_depth,
              "mean_rgb": [round(m, 5) for m in mean], **timing}
    if a.compare:
        cw, ch, theirs = read_pfm(a.compare)
        if (cw, ch) != (w, h):
            sys.exit("%s is %dx%d, not %dx%d" % (a.compare, cw, ch, w, h))
        ours = read_pfm(a.out)[2]
        se = sum((x - y) ** 2 for x, y in zip(ours, theirs))
        energy = sum(y * y for y in theirs)
        their_mean = [sum(theirs[c::3]) / n for c in range(3)]
        result["vastray_mean_rgb"] = [round(m, 5) for m in their_mean]
        result["mean_ratio_mitsuba_over_vastray"] = [round(m / t, 5) if t else None for m, t in zip(mean, their_mean)]
        result["relative_rmse_vs_vastray"] = round((se / energy) ** 0.5, 5) if energy else None
    print(json.dumps(result))


if __name__ == "__main__":
    main()
