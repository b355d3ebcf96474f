"""Pixels of the EXRs vastray writes, read in Python, and the error metrics the accuracy bench
reports.

A small reader of single-part scanline OpenEXR (no, ZIPS or ZIP compression; half, float and
uint channels) keeps each sweep point to one process (the render): the OpenImageIO Python
bindings are not a dependency, and an `oiiotool` or `vastray diff` per point costs seconds of
start-up on a loaded 2-core machine. The bench checks this reader against `vastray diff` once per
scene (sweep.py, crosscheck).
"""
import struct
import zlib

import numpy as np

_PIXEL_TYPES = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}  # UINT, HALF, FLOAT
_LINES_PER_BLOCK = {0: 1, 2: 1, 3: 16}  # NO_COMPRESSION, ZIPS_COMPRESSION, ZIP_COMPRESSION


def _cstring(data, pos):
    end = data.index(b"\0", pos)
    return data[pos:end].decode(), end + 1


def _header(data, path):
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError(f"{path}: not an OpenEXR file")
    version = struct.unpack_from("<i", data, 4)[0]
    if version & (0x200 | 0x800 | 0x1000):
        raise ValueError(f"{path}: tiled, deep or multi-part EXR is not supported by this reader")
    pos, attrs = 8, {}
    while data[pos] != 0:
        name, pos = _cstring(data, pos)
        kind, pos = _cstring(data, pos)
        size = struct.unpack_from("<i", data, pos)[0]
        attrs[name] = (kind, data[pos + 4:pos + 4 + size])
        pos += 4 + size
    return attrs, pos + 1


def _channels(raw):
    channels, pos = [], 0
    while raw[pos] != 0:
        name, pos = _cstring(raw, pos)
        ptype, _, _, xs, ys = struct.unpack_from("<iB3sii", raw, pos)
        if xs != 1 or ys != 1:
            raise ValueError(f"channel {name}: subsampled channels are not supported")
        channels.append((name, _PIXEL_TYPES[ptype]))
        pos += 16
    return channels


def _inflate(block, expected):
    """OpenEXR's ZIP: zlib, then a byte-delta predictor, then two interleaved halves."""
    if len(block) == expected:  # stored uncompressed when compression would not shrink it
        return block
    t = np.frombuffer(zlib.decompress(block), dtype=np.uint8).astype(np.int64)
    t[1:] -= 128
    t = (np.cumsum(t) & 0xFF).astype(np.uint8)
    half = (len(t) + 1) // 2
    out = np.empty(len(t), dtype=np.uint8)
    out[0::2], out[1::2] = t[:half], t[half:]
    return out.tobytes()


def read_exr(path):
    """{channel name: 2-D numpy array (height, width)} of a scanline EXR."""
    with open(path, "rb") as f:
        data = f.read()
    attrs, pos = _header(data, path)
    channels = _channels(attrs["channels"][1])
    compression = attrs["compression"][1][0]
    if compression not in _LINES_PER_BLOCK:
        raise ValueError(f"{path}: compression {compression} is not supported by this reader")
    x0, y0, x1, y1 = struct.unpack("<iiii", attrs["dataWindow"][1])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    lines = _LINES_PER_BLOCK[compression]
    blocks = (height + lines - 1) // lines
    offsets = struct.unpack_from(f"<{blocks}Q", data, pos)
    planes = {name: np.empty((height, width), dtype=dt) for name, dt in channels}
    for offset in offsets:
        y, size = struct.unpack_from("<ii", data, offset)
        n = min(lines, y1 - y + 1)
        expected = n * width * sum(dt.itemsize for _, dt in channels)
        raw = _inflate(data[offset + 8:offset + 8 + size], expected) if compression else data[offset + 8:offset + 8 + size]
        p = 0
        for row in range(y - y0, y - y0 + n):
            for name, dt in channels:
                planes[name][row] = np.frombuffer(raw, dtype=dt, count=width, offset=p)
                p += width * dt.itemsize
    return planes


class Image:
    """Linear RGB (float64, height x width x 3) and the primid AOV of one render."""

    def __init__(self, path):
        planes = read_exr(path)
        self.rgb = np.stack([planes[c].astype(np.float64) for c in ("R", "G", "B")], axis=-1)
        self.primid = planes.get("primid")


def rmse(a, b):
    """Root mean square over pixels and the three colour channels, as OIIO's compare (and so
    `vastray diff`) computes it."""
    _check(a, b)
    return float(np.sqrt(np.mean((a.rgb - b.rgb) ** 2)))


def relative_mse(a, b, eps=1e-2):
    """Mean over pixels and channels of (a - b)^2 / (b^2 + eps), b the reference. eps = 0.01 keeps
    black reference pixels from dominating (the usual choice in the denoising literature)."""
    _check(a, b)
    return float(np.mean((a.rgb - b.rgb) ** 2 / (b.rgb ** 2 + eps)))


def primid_agreement(a, b):
    """Fraction of all pixels (background included) whose primid is the same, as `vastray diff`."""
    _check(a, b)
    return float(np.mean(a.primid == b.primid))


def _check(a, b):
    if a.rgb.shape != b.rgb.shape:
        raise ValueError(f"images differ in size: {a.rgb.shape} vs {b.rgb.shape}")
