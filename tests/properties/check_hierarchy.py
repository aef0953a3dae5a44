#!/usr/bin/env python3
"""Independent check of the hierarchy properties on the real Jacksboro DEM.

The oracle never calls tinmerge's own geometry code: triangles come out of
`tin_triangles` as PostGIS geometries, pixel centres and values come from
PostGIS's own `ST_PixelAsCentroids`, and the checks use numpy, shapely and
matplotlib's triangulation (TrapezoidMapTriFinder + LinearTriInterpolator).

Checked on the UTM DEM, tolerance 2 m, 5 levels:
 1. every level is a conforming triangulation of the same domain (the convex
    hull of the valid pixel centres): counter-clockwise triangles, every edge
    shared by at most two triangles, edges used once lie on the hull, total
    area equals the hull's (so no overlaps, no gaps, no T-junctions);
 2. every triangle of level i+1 lies in its parent, children tile their parent,
    and every edge of level i is a union of edges of level i+1;
 3. the vertical error at every valid pixel centre is <= the level tolerance.
"""
import csv
import io
import os
import subprocess
import sys
import time
from collections import defaultdict

import numpy as np
from matplotlib.tri import LinearTriInterpolator, Triangulation
from shapely.geometry import MultiPoint, Point

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HOST = os.path.join(ROOT, "target", "pg")
PORT = os.environ.get("TINMERGE_PORT", "28815")
DB = os.environ.get("TINMERGE_DB", "tinmerge_regress")
TOL, LEVELS = 2.0, 5


def sql_rows(query):
    out = subprocess.run(
        ["psql", "-h", HOST, "-p", PORT, "-U", "postgres", "-d", DB, "-v", "ON_ERROR_STOP=1",
         "-qAt", "-c", f"COPY ({query}) TO STDOUT WITH CSV"],
        check=True, capture_output=True, text=True).stdout
    return list(csv.reader(io.StringIO(out)))


def main():
    failures = []

    def check(cond, msg):
        if not cond:
            failures.append(msg)
            print("FAIL:", msg)

    t0 = time.time()
    subprocess.run(["psql", "-h", HOST, "-p", PORT, "-U", "postgres", "-d", DB, "-qAt", "-v", "ON_ERROR_STOP=1", "-c",
                    f"DROP TABLE IF EXISTS prop_terrain; CREATE TABLE prop_terrain AS "
                    f"SELECT tin_from_raster(rast, {TOL}, {LEVELS}) AS t FROM dem"], check=True)
    print(f"built the tin in SQL in {time.time() - t0:.2f} s")

    px = np.array(sql_rows("SELECT ST_X(geom), ST_Y(geom), val FROM dem, ST_PixelAsCentroids(rast, 1, true)"),
                  dtype=float)
    print(f"{len(px)} valid pixels (PostGIS ST_PixelAsCentroids)")
    hull = MultiPoint(px[:, :2]).convex_hull
    levels = []
    for l in range(LEVELS):
        rows = sql_rows(
            "SELECT id, coalesce(parent, -1), "
            "ST_X(ST_PointN(r,1)), ST_Y(ST_PointN(r,1)), ST_Z(ST_PointN(r,1)), "
            "ST_X(ST_PointN(r,2)), ST_Y(ST_PointN(r,2)), ST_Z(ST_PointN(r,2)), "
            "ST_X(ST_PointN(r,3)), ST_Y(ST_PointN(r,3)), ST_Z(ST_PointN(r,3)) "
            f"FROM (SELECT id, parent, ST_ExteriorRing(geom) r FROM prop_terrain, tin_triangles(t, {l})) s ORDER BY id")
        a = np.array(rows, dtype=float)
        levels.append({"id": a[:, 0].astype(int), "parent": a[:, 1].astype(int), "c": a[:, 2:].reshape(-1, 3, 3)})
    print("per-level triangle counts:", [len(lv["id"]) for lv in levels])

    for l, lv in enumerate(levels):
        c = lv["c"]
        n = len(c)
        check((lv["id"] == np.arange(n)).all(), f"level {l}: ids are not 0..n-1")
        # vertex ids by exact coordinates
        keys = {}
        tri = np.empty((n, 3), dtype=np.int64)
        for i in range(n):
            for k in range(3):
                key = (c[i, k, 0], c[i, k, 1])
                tri[i, k] = keys.setdefault(key, len(keys))
        verts = np.array(list(keys.keys()))
        area2 = ((c[:, 1, 0] - c[:, 0, 0]) * (c[:, 2, 1] - c[:, 0, 1])
                 - (c[:, 2, 0] - c[:, 0, 0]) * (c[:, 1, 1] - c[:, 0, 1]))
        check((area2 > 0).all(), f"level {l}: {(area2 <= 0).sum()} triangles not counter-clockwise / zero area")
        # property 1: edges shared by <= 2 triangles, boundary edges on the hull, areas add up
        edges = defaultdict(int)
        for i in range(n):
            for k in range(3):
                e = tuple(sorted((tri[i, k], tri[i, (k + 1) % 3])))
                edges[e] += 1
        check(max(edges.values()) <= 2, f"level {l}: an edge is shared by more than 2 triangles")
        boundary = [e for e, m in edges.items() if m == 1]
        ring = hull.exterior
        off = [e for e in boundary
               if ring.distance(Point(*((verts[e[0]] + verts[e[1]]) / 2))) > 1e-6
               or ring.distance(Point(*verts[e[0]])) > 1e-6]
        check(not off, f"level {l}: {len(off)} edges used by one triangle lie inside the domain (gap or T-junction)")
        total = area2.sum() / 2
        check(abs(total - hull.area) <= 1e-9 * hull.area,
              f"level {l}: triangles cover {total} m2, the hull of the pixels {hull.area} m2")
        lv["tri"], lv["verts"], lv["edges"] = tri, verts, edges
        lv["vid"] = keys

        # property 3: error at every valid pixel centre, by matplotlib's interpolator
        T = Triangulation(verts[:, 0], verts[:, 1], tri)
        z = np.zeros(len(verts))
        for i in range(n):
            for k in range(3):
                z[tri[i, k]] = c[i, k, 2]
        interp = LinearTriInterpolator(T, z)
        zi = interp(px[:, 0], px[:, 1])
        mask = np.ma.getmaskarray(zi)
        # pixels the trapezoid map leaves out (exactly on the hull): brute force
        if mask.any():
            for j in np.nonzero(mask)[0]:
                x, y = px[j, 0], px[j, 1]
                d = area2
                u = ((x - c[:, 0, 0]) * (c[:, 2, 1] - c[:, 0, 1]) - (c[:, 2, 0] - c[:, 0, 0]) * (y - c[:, 0, 1])) / d
                v = ((c[:, 1, 0] - c[:, 0, 0]) * (y - c[:, 0, 1]) - (x - c[:, 0, 0]) * (c[:, 1, 1] - c[:, 0, 1])) / d
                inside = np.nonzero((u >= -1e-9) & (v >= -1e-9) & (u + v <= 1 + 1e-9))[0]
                check(len(inside) > 0, f"level {l}: pixel ({x}, {y}) is in no triangle")
                if len(inside):
                    t = inside[0]
                    zi[j] = c[t, 0, 2] + u[t] * (c[t, 1, 2] - c[t, 0, 2]) + v[t] * (c[t, 2, 2] - c[t, 0, 2])
        err = np.abs(np.ma.getdata(zi) - px[:, 2])
        tol = TOL * 2 ** (LEVELS - 1 - l)
        print(f"level {l}: {n} triangles, {len(verts)} vertices, tolerance {tol:g} m, "
              f"max error at {len(px)} pixels {err.max():.4f} m ({mask.sum()} located by brute force)")
        check(err.max() <= tol + 1e-6, f"level {l}: max error {err.max()} > tolerance {tol}")

    # property 2: nesting and persistence of coarse edges
    for l in range(LEVELS - 1):
        P, C = levels[l], levels[l + 1]
        pc, cc, par = P["c"], C["c"], C["parent"]
        check(((par >= 0) & (par < len(pc))).all(), f"level {l + 1}: parent ids out of range")
        pp = pc[par]
        d = ((pp[:, 1, 0] - pp[:, 0, 0]) * (pp[:, 2, 1] - pp[:, 0, 1])
             - (pp[:, 2, 0] - pp[:, 0, 0]) * (pp[:, 1, 1] - pp[:, 0, 1]))
        for k in range(3):
            x, y = cc[:, k, 0], cc[:, k, 1]
            u = ((x - pp[:, 0, 0]) * (pp[:, 2, 1] - pp[:, 0, 1]) - (pp[:, 2, 0] - pp[:, 0, 0]) * (y - pp[:, 0, 1])) / d
            v = ((pp[:, 1, 0] - pp[:, 0, 0]) * (y - pp[:, 0, 1]) - (x - pp[:, 0, 0]) * (pp[:, 1, 1] - pp[:, 0, 1])) / d
            out = (u < -1e-9) | (v < -1e-9) | (u + v > 1 + 1e-9)
            check(not out.any(), f"level {l + 1}: {out.sum()} triangles have a corner outside their parent")
        ca = ((cc[:, 1, 0] - cc[:, 0, 0]) * (cc[:, 2, 1] - cc[:, 0, 1])
              - (cc[:, 2, 0] - cc[:, 0, 0]) * (cc[:, 1, 1] - cc[:, 0, 1])) / 2
        sums = np.bincount(par, weights=ca, minlength=len(pc))
        pa = ((pc[:, 1, 0] - pc[:, 0, 0]) * (pc[:, 2, 1] - pc[:, 0, 1])
              - (pc[:, 2, 0] - pc[:, 0, 0]) * (pc[:, 1, 1] - pc[:, 0, 1])) / 2
        bad = np.abs(sums - pa) > 1e-6 * pa + 1e-6
        check(not bad.any(), f"level {l}: {bad.sum()} triangles are not tiled by their children")
        # every coarse edge is a union of fine edges: walk from a to b over fine edges along the segment
        cv, cid, cedges = C["verts"], C["vid"], C["edges"]
        order = np.argsort(cv[:, 0])
        xs = cv[order, 0]
        broken = 0
        for (ia, ib) in P["edges"]:
            a, b = P["verts"][ia], P["verts"][ib]
            lo, hi = np.searchsorted(xs, min(a[0], b[0]) - 1e-9), np.searchsorted(xs, max(a[0], b[0]) + 1e-9, "right")
            cand = order[lo:hi]
            q = cv[cand]
            inb = (q[:, 1] >= min(a[1], b[1]) - 1e-9) & (q[:, 1] <= max(a[1], b[1]) + 1e-9)
            q, cand = q[inb], cand[inb]
            L2 = (b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2
            cross = (b[0] - a[0]) * (q[:, 1] - a[1]) - (b[1] - a[1]) * (q[:, 0] - a[0])
            on = np.abs(cross) <= 1e-9 * L2
            q, cand = q[on], cand[on]
            t = ((q[:, 0] - a[0]) * (b[0] - a[0]) + (q[:, 1] - a[1]) * (b[1] - a[1])) / L2
            chain = cand[np.argsort(t)]
            if len(chain) < 2 or cid.get((a[0], a[1])) != chain[0] or cid.get((b[0], b[1])) != chain[-1]:
                broken += 1
                continue
            if any(tuple(sorted((chain[i], chain[i + 1]))) not in cedges for i in range(len(chain) - 1)):
                broken += 1
        check(broken == 0, f"level {l}: {broken} edges do not persist at level {l + 1}")
        print(f"level {l} -> {l + 1}: children inside parents, tile them; {len(P['edges'])} edges persist")

    if failures:
        print(f"{len(failures)} property checks FAILED")
        sys.exit(1)
    print("hierarchy properties 1-3 hold at every valid pixel")


if __name__ == "__main__":
    main()
