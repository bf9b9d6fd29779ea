#!/usr/bin/env python3
"""The export measured from the part's side: how far the exact edges and
corners of plain boxes lie from the file written, for two builds of kerf.

The samples over a file's triangles (what `kerf export` reports) measure the
other way only: a chamfer whose vertices lie on the faces passes them while
the edge it cuts off lies further away. Boxes have their edges where the
document says, so they are sampled along them (33 points an edge, the
corners too) and each sample's distance to the nearest triangle of the file
as read back (binary STL, float32) is taken.

Every other box is turned by random angles; feature sizes cycle through
0.5, 1 and 2 mm; the tolerance is kerf's default (0.05 mm).

    python3 bench/box-edges.py BEFORE_KERF AFTER_KERF [COUNT] [SEED]
"""
import json
import math
import os
import random
import struct
import subprocess
import sys
import tempfile


def read_stl(path):
    data = open(path, "rb").read()
    count = struct.unpack_from("<I", data, 80)[0]
    triangles = []
    for i in range(count):
        v = struct.unpack_from("<12f", data, 84 + 50 * i)
        triangles.append((v[3:6], v[6:9], v[9:12]))
    return triangles


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def along(a, d, t):
    return (a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2])


def point_triangle(p, a, b, c):
    """Distance from p to the triangle abc (Ericson 5.1.5)."""
    ab, ac, ap = sub(b, a), sub(c, a), sub(p, a)
    d1, d2 = dot(ab, ap), dot(ac, ap)
    if d1 <= 0 and d2 <= 0:
        return math.dist(p, a)
    bp = sub(p, b)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    if d3 >= 0 and d4 <= d3:
        return math.dist(p, b)
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        return math.dist(p, along(a, ab, d1 / (d1 - d3)))
    cp = sub(p, c)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    if d6 >= 0 and d5 <= d6:
        return math.dist(p, c)
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        return math.dist(p, along(a, ac, d2 / (d2 - d6)))
    va = d3 * d6 - d5 * d4
    if va <= 0 and d4 - d3 >= 0 and d5 - d6 >= 0:
        return math.dist(p, along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))))
    denom = va + vb + vc
    if denom <= 0:
        return math.dist(p, a)
    v, w = vb / denom, vc / denom
    return math.dist(p, (a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w))


def rotate(degrees, p):
    """The document's rotation: about X, then Y, then Z (fixed axes)."""
    x, y, z = p
    a, b, c = (math.radians(d) for d in degrees)
    y, z = math.cos(a) * y - math.sin(a) * z, math.sin(a) * y + math.cos(a) * z
    x, z = math.cos(b) * x + math.sin(b) * z, -math.sin(b) * x + math.cos(b) * z
    x, y = math.cos(c) * x - math.sin(c) * y, math.sin(c) * x + math.cos(c) * y
    return (x, y, z)


def corners(size, at, degrees):
    out = []
    for c in range(8):
        local = tuple((0.5 if c & (1 << k) else -0.5) * size[k] for k in range(3))
        r = rotate(degrees, local)
        out.append((r[0] + at[0], r[1] + at[1], r[2] + at[2]))
    return out


def measure(triangles, box_corners):
    """The farthest corner and the farthest edge sample (corners excluded) from the file."""
    def distance(p):
        return min(point_triangle(p, *t) for t in triangles)
    corner = max(distance(c) for c in box_corners)
    edge = 0.0
    for c in range(8):
        for axis in range(3):
            if c & (1 << axis):
                continue
            a, b = box_corners[c], box_corners[c | (1 << axis)]
            for k in range(1, 32):
                edge = max(edge, distance(along(a, sub(b, a), k / 32)))
    return corner, edge


def main():
    before, after = sys.argv[1], sys.argv[2]
    count = int(sys.argv[3]) if len(sys.argv) > 3 else 16
    rng = random.Random(int(sys.argv[4]) if len(sys.argv) > 4 else 7)
    print("| box | turned | cells mm | triangles before → after | worst corner mm before → after "
          "| worst edge mm before → after |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as scratch:
        for i in range(count):
            size = [5 + 395 * rng.random(), 5 + 95 * rng.random(), 5 + 95 * rng.random()]
            at = [400 * rng.random() - 200, 400 * rng.random() - 200, 100 * rng.random()]
            degrees = [90 * rng.random() for _ in range(3)] if i % 2 else [0.0, 0.0, 0.0]
            cells = [0.5, 1.0, 2.0][i % 3]
            document = {"format": "kerf", "version": 1, "settings": {"feature_size": cells},
                        "root": {"id": "b", "type": "box", "size": size,
                                 "transform": {"translate": at, "rotate": degrees}}}
            part = os.path.join(scratch, "box.kerf")
            with open(part, "w") as f:
                json.dump(document, f)
            row = []
            for kerf in (before, after):
                mesh = os.path.join(scratch, "box.stl")
                subprocess.run([kerf, "export", part, "-o", mesh], check=True, capture_output=True)
                triangles = read_stl(mesh)
                row.append((len(triangles),) + measure(triangles, corners(size, at, degrees)))
            (tb, cb, eb), (ta, ca, ea) = row
            print(f"| {i} | {'yes' if i % 2 else 'no'} | {cells} | {tb} → {ta} | {cb:.4f} → {ca:.4f} "
                  f"| {eb:.4f} → {ea:.4f} |", flush=True)


if __name__ == "__main__":
    main()
