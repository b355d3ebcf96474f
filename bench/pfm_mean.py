"""Prints the mean R,G,B of a 3-channel .pfm (vastray's and the benches' own; any byte order the
scale's sign gives is read as little-endian, which is what they write). usage: pfm_mean.py FILE.pfm"""
import array, sys

data = open(sys.argv[1], "rb").read()
header_end = 0
for _ in range(3):
    header_end = data.index(b"\n", header_end) + 1
values = array.array("f")
values.frombytes(data[header_end:])
n = len(values) // 3
print(",".join("%.5f" % (sum(values[c::3]) / n) for c in range(3)))
