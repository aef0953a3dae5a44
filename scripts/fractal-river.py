#!/usr/bin/env python3
"""Print a fractal "river" (midpoint displacement, seeded) as one WKT
LINESTRING: fractal-river.py x0 y0 x1 y1 depth roughness npoints seed."""
import random
import sys

x0, y0, x1, y1 = map(float, sys.argv[1:5])
depth, rough, npts, seed = int(sys.argv[5]), float(sys.argv[6]), int(sys.argv[7]), int(sys.argv[8])
rng = random.Random(seed)
pts = [(x0, y0), (x1, y1)]
for _ in range(depth):
    nxt = []
    for (px, py), (qx, qy) in zip(pts, pts[1:]):
        s = rng.uniform(-rough, rough)
        nxt.append((px, py))
        nxt.append(((px + qx) / 2 - (qy - py) * s, (py + qy) / 2 + (qx - px) * s))
    nxt.append(pts[-1])
    pts = nxt
pts = pts[:npts]
print("LINESTRING(" + ",".join(f"{x:.3f} {y:.3f}" for x, y in pts) + ")")
