#!/usr/bin/env python3
"""Writes a grayscale PNG heightfield of rolling hills or a valley road (standard library only).

    scripts/make_terrain.py OUT.png [--size N] [--depth 8|16]
    scripts/make_terrain.py OUT.png --valley-road [--depth 8|16]

The image is N x N samples; pixel value v / full scale is the height as a
fraction of the scenario's height_scale. Row 0 (the top of the image) is the
scenario's origin y, so the image reads with +y downwards. The hills are a
few smooth waves over a 256-sample period, so any size has the same
features per sample (configs/hills.json: 257 samples of 1 m, 8 m high).

--valley-road writes a road car's terrain (configs/sedan_hills.json): a
valley 2048 m long (x, 1025 columns of 2 m) and 128 m wide (y, 65 rows),
its floor along the centre row a road of gentle grades (ROAD_GRADES: flat,
+5% for 450 m, -3% for 400 m, +4% for 300 m, flat), the grade blended
between sections over 100-150 m by a half cosine (so the height is C2), and
the sides rising as 30 m (y / 64 m)^4 (the road bed is flat across: 0.01 mm
of rise at a wheel's 0.78 m from the centre). Heights span [0, VALLEY_SCALE]
m; pixel = height / VALLEY_SCALE of full scale.
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


# (x where the section starts, m; grade from there on). Between sections the
# grade blends over the gap to the next start minus the section's plateau.
ROAD_GRADES = [(0.0, 0.0), (250.0, 0.05), (850.0, -0.03), (1400.0, 0.04), (1850.0, 0.0)]
ROAD_BLEND = [(150.0, 250.0), (700.0, 850.0), (1250.0, 1400.0), (1700.0, 1850.0)]
VALLEY_NX, VALLEY_NY, VALLEY_CELL = 1025, 65, 2.0
VALLEY_SCALE = 64.0  # m at full scale


def road_grade(x):
    """Grade of the road at x (m): constant sections, half-cosine blends."""
    g = 0.0
    for (a, b), (_, g_next) in zip(ROAD_BLEND, ROAD_GRADES[1:]):
        if x >= b:
            g = g_next
        elif x > a:
            w = 0.5 - 0.5 * math.cos(math.pi * (x - a) / (b - a))
            return g + w * (g_next - g)
    return g


def road_profile(n, cell, steps=20):
    """Road height at each column (m), the grade integrated by Simpson's rule."""
    z, out = 0.0, [0.0]
    for i in range(1, n):
        x0, h = (i - 1) * cell, cell / steps
        acc = road_grade(x0) + road_grade(x0 + cell)
        for k in range(1, steps):
            acc += (4 if k % 2 else 2) * road_grade(x0 + k * h)
        z += acc * h / 3.0
        out.append(z)
    return out


def valley_rows():
    """Rows (y from -64 m) of heights as fractions of VALLEY_SCALE."""
    road = road_profile(VALLEY_NX, VALLEY_CELL)
    half = (VALLEY_NY - 1) // 2
    for j in range(VALLEY_NY):
        side = 30.0 * ((j - half) / half) ** 4
        yield [(z + side) / VALLEY_SCALE for z in road]


def write_png(path, n, depth, rows=None, width=None):
    full = (1 << depth) - 1
    raw = bytearray()
    width = width or n
    fmt = ">%dH" % width if depth == 16 else "%dB" % width
    rows = list(rows) if rows is not None else heights(n)
    for row in rows:
        raw.append(0)  # filter type 0 for this row
        raw += struct.pack(fmt, *[int(round(h * full)) for h in row])

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", width, len(raw) // (1 + width * depth // 8), depth, 0, 0, 0, 0)  # grayscale, not interlaced
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(bytes(raw), 6))
                + chunk(b"IEND", b""))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--size", type=int, default=257)
    p.add_argument("--depth", type=int, choices=(8, 16), default=16)
    p.add_argument("--valley-road", action="store_true", help="the road car's valley road (see above)")
    a = p.parse_args()
    if a.valley_road:
        write_png(a.out, VALLEY_NX, a.depth, valley_rows(), VALLEY_NX)
    else:
        write_png(a.out, a.size, a.depth)


if __name__ == "__main__":
    main()
