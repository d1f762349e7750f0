#!/usr/bin/env python3
"""Writes a grayscale PNG heightfield of rolling hills (standard library only).

    scripts/make_terrain.py OUT.png [--size N] [--depth 8|16]

The image is N x N samples; pixel value v / full scale is the height as a
fraction of the scenario's height_scale. Row 0 (the top of the image) is the
scenario's origin y, so the image reads with +y downwards. The hills are a
few smooth waves over a 256-sample period, so any size has the same
features per sample (configs/hills.json: 257 samples of 1 m, 8 m high).
"""
import argparse
import math
import struct
import zlib


def heights(n):
    """Rows of heights in [0, 1]: separable waves, so each row is cheap."""
    k = 2 * math.pi / 256.0
    ax = [math.sin(k * i) for i in range(n)]
    bx = [math.cos(2 * k * i + 0.7) for i in range(n)]
    for j in range(n):
        ay = math.cos(k * j)
        by = math.sin(2 * k * j + 0.3)
        # range of 0.35 a b + 0.15 a' b' + 0.5 is [0, 1]
        yield [0.5 + 0.35 * a * ay + 0.15 * b * by for a, b in zip(ax, bx)]


def write_png(path, n, depth):
    full = (1 << depth) - 1
    raw = bytearray()
    fmt = ">%dH" % n if depth == 16 else "%dB" % n
    for row in heights(n):
        raw.append(0)  # filter type 0 for this row
        raw += struct.pack(fmt, *[int(round(h * full)) for h in row])

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", n, n, depth, 0, 0, 0, 0)  # grayscale, not interlaced
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(bytes(raw), 6))
                + chunk(b"IEND", b""))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--size", type=int, default=257)
    p.add_argument("--depth", type=int, choices=(8, 16), default=16)
    a = p.parse_args()
    write_png(a.out, a.size, a.depth)


if __name__ == "__main__":
    main()
