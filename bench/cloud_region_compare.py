"""Compares two renders of the volume bench (bench/volume_vs_mitsuba.sh) over the cloud only: the
pixels where either image differs from the background (1) by more than 1e-3, their means, and the
32x32-pixel block means' differences (red channel; the images are grey).

usage: python3 cloud_region_compare.py A.txt B.txt
where each .txt is `oiiotool --dumpdata:empty=0 IMAGE` of a W x H image (vastray's .pfm converted
with `oiiotool vastray.pfm -o vastray.exr`, and Mitsuba's .exr)."""
import math, re, sys


def load(path):
    pixels = {}
    for line in open(path):
        m = re.match(r'\s*Pixel \((\d+), (\d+)\): (\S+)', line)
        if m:
            pixels[(int(m.group(1)), int(m.group(2)))] = float(m.group(3))
    return pixels


a, b = load(sys.argv[1]), load(sys.argv[2])
w = 1 + max(x for x, _ in a)
h = 1 + max(y for _, y in a)
cloud = [k for k in a if abs(a[k] - 1) > 1e-3 or abs(b[k] - 1) > 1e-3]
sa, sb = sum(a[k] for k in cloud), sum(b[k] for k in cloud)
print("cloud pixels %d: A mean %.5f, B mean %.5f, relative %.2e" % (len(cloud), sa / len(cloud), sb / len(cloud),
                                                                     (sa - sb) / sb))
bs, diffs = 32, []
for by in range(0, h, bs):
    for bx in range(0, w, bs):
        block = [(x, y) for y in range(by, by + bs) for x in range(bx, bx + bs)]
        diffs.append(sum(a[k] - b[k] for k in block) / len(block))
print("32x32 block means: max |A - B| %.4f, rms %.4f" % (max(abs(d) for d in diffs),
                                                          math.sqrt(sum(d * d for d in diffs) / len(diffs))))
print("per-pixel rms difference over the cloud %.4f" % math.sqrt(sum((a[k] - b[k]) ** 2 for k in cloud) / len(cloud)))
