#!/usr/bin/env python3
"""Independent check of the hierarchy properties on the real Jacksboro DEM.

The oracle never calls tinmerge's own geometry code: triangles come out of
`tin_triangles` as PostGIS geometries, pixel centres and values come from
PostGIS's own `ST_PixelAsCentroids`, and the checks use numpy, shapely and
matplotlib's triangulation (TrapezoidMapTriFinder + LinearTriInterpolator).

Checked on both bundled DEMs (UTM 16N, 90 m pixels with a nodata border;
EPSG:4326, 1/1200 degree pixels, where tinmerge 0.2.0 built 15,490 slivers),
tolerance 2 m, 5 levels:
 0. no sliver: every triangle's smallest altitude is at least 1e-3 pixel,
    but for a triangle with a corner where the hull of the centres crosses
    the valid cells' outline (off the half-pixel lattice): that crossing and
    centres a few hundredths of a pixel inside the hull make thin triangles
    by the domain's own shape (docs/sql-reference.md), held to 1e-5 pixel;
 1. every level is a conforming triangulation of the same domain (where the
    raster has data, 0.10.0's default: the valid pixels' squares, PostGIS's
    ST_Polygon, within the convex hull of the valid pixel centres):
    counter-clockwise triangles, every edge shared by at most two triangles,
    edges used once lie on the domain's boundary, total area equals the
    domain's (so no overlaps, no gaps, no T-junctions);
 2. every triangle of level i+1 lies in its parent (up to 1e-7 pixel: a
    vertex at a grid-line crossing is on its parent's side up to the
    rounding of world coordinates), children tile their parent, and every
    edge of level i is a union of edges of level i+1;
 3. the vertical error at every valid pixel centre is <= the level tolerance;
 4. between the samples too (issue 43): along a grid line between two
    adjacent valid pixel centres the DEM is the straight line between them
    (gdal_contour's and bilinear sampling's surface), and a level is linear
    in each triangle, so its error on every grid line is largest at a pixel
    centre or where an edge crosses the grid line: at every such crossing of
    every edge (from tin_triangles) with a grid segment between two valid
    pixels (values from ST_PixelAsCentroids), and at every vertex on a grid
    line off the pixel centres, the error is <= the level tolerance (plus
    1e-9 relative): on the geographic DEM, on the UTM DEM's default build
    over its valid pixels and on the UTM DEM built on its lattice
    (fill_gaps => true). Vertices at such crossings are off the half-pixel
    lattice, so triangles with one are held to 1e-5 pixel, as those at the
    outline's crossings (property 0).
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
from shapely import STRtree
from shapely import wkt as shapely_wkt
from shapely.geometry import MultiPoint, Point, Polygon

wkt_loads = shapely_wkt.loads

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


def sql(command):
    subprocess.run(["psql", "-h", HOST, "-p", PORT, "-U", "postgres", "-d", DB, "-qAt", "-v", "ON_ERROR_STOP=1"],
                   input=command, text=True, check=True)


def main():
    failures = []

    def check(cond, msg):
        if not cond:
            failures.append(msg)
            print("FAIL:", msg)

    # the UTM DEM has nodata: tin_from_raster's default builds over its
    # valid pixels; with fill_gaps => true it is built on its lattice; both
    # between samples
    check_dem("dem", check)
    check_dem("dem_geo", check)
    check_crossings("dem", "fill_gaps => true", check)
    # round shapes as PostGIS makes them: within a disc with an off-centre
    # hole, and with a circle and the diagonal as soft lines (until 0.13.0
    # a few crossings beside the rings were over, up to 1.48x)
    centre = "ST_Centroid(ST_Envelope(rast))"
    width = "(ST_Width(rast) * ST_PixelWidth(rast))"
    for table in ("dem", "dem_geo"):
        check_crossings(table, f"boundary => ST_Difference(ST_Buffer({centre}, 0.4 * {width}), "
                               f"ST_Buffer(ST_Translate({centre}, 7.3 * ST_PixelWidth(rast), 0), 0.1 * {width}))", check)
        check_crossings(table, f"soft_breaklines => ST_Collect(ST_ExteriorRing(ST_Buffer({centre}, 0.3 * {width}, 16)), "
                               "ST_MakeLine(ST_PointN(ST_ExteriorRing(ST_Envelope(rast)), 1), "
                               "ST_PointN(ST_ExteriorRing(ST_Envelope(rast)), 3)))", check)
    if failures:
        print(f"{len(failures)} property checks FAILED")
        sys.exit(1)
    print("hierarchy properties 0-4 hold at every valid pixel and grid-line crossing of both DEMs; merges near split coarse edges "
          "agree with the oracle")


def check_crossings(table, options, check):
    """Property 4 alone, for tin_from_raster(rast, TOL, LEVELS, options)."""
    print(f"== {table} ({options}): property 4")
    sql(f"SET client_min_messages = warning; DROP TABLE IF EXISTS prop_cross; CREATE TABLE prop_cross AS "
        f"SELECT tin_from_raster(rast, {TOL}, {LEVELS}, {options}) AS t FROM {table}")
    ulx, uly, sx, sy = (float(v) for v in sql_rows(
        f"SELECT ST_UpperLeftX(rast), ST_UpperLeftY(rast), ST_ScaleX(rast), ST_ScaleY(rast) FROM {table}")[0])
    px = np.array(sql_rows(f"SELECT ST_X(geom), ST_Y(geom), val FROM {table}, ST_PixelAsCentroids(rast, 1, true)"),
                  dtype=float)
    grid = raster_grid(px, ulx, uly, sx, sy)
    for l in range(LEVELS):
        a = np.array(sql_rows(
            "SELECT ST_X(ST_PointN(r,1)), ST_Y(ST_PointN(r,1)), ST_Z(ST_PointN(r,1)), "
            "ST_X(ST_PointN(r,2)), ST_Y(ST_PointN(r,2)), ST_Z(ST_PointN(r,2)), "
            "ST_X(ST_PointN(r,3)), ST_Y(ST_PointN(r,3)), ST_Z(ST_PointN(r,3)) "
            f"FROM (SELECT ST_ExteriorRing(geom) r FROM prop_cross, tin_triangles(t, {l})) s"), dtype=float)
        c = a.reshape(-1, 3, 3)
        keys, tri = {}, np.empty((len(c), 3), dtype=np.int64)
        for i in range(len(c)):
            for k in range(3):
                tri[i, k] = keys.setdefault((c[i, k, 0], c[i, k, 1]), len(keys))
        verts = np.array(list(keys.keys()))
        z = np.zeros(len(verts))
        z[tri.ravel()] = c.reshape(-1, 3)[:, 2]
        edges = np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1), axis=0)
        tol = TOL * 2 ** (LEVELS - 1 - l)
        ge = grid_line_errors(edges, verts, z, grid)
        print(f"level {l}: {len(c)} triangles, {len(ge)} grid-line crossings, largest error {ge.max():.4f} m "
              f"({ge.max() / tol:.3f}x the tolerance)")
        check((ge <= tol * (1 + 1e-9)).all(),
              f"{table} ({options}) level {l}: {(ge > tol * (1 + 1e-9)).sum()} grid-line crossings over {tol}")
    sql("DROP TABLE prop_cross")


def raster_grid(px, ulx, uly, sx, sy):
    """The raster as an array (NaN where nodata), by each valid centre's
    column and row, with the geotransform grid_line_errors reads."""
    cols = np.rint((px[:, 0] - ulx) / sx - 0.5).astype(int)
    rows_ = np.rint((px[:, 1] - uly) / sy - 0.5).astype(int)
    arr = np.full((rows_.max() + 2, cols.max() + 2), np.nan)
    arr[rows_, cols] = px[:, 2]
    return (ulx, uly, sx, sy, arr)


def check_dem(table, check):
    print(f"== {table}")
    t0 = time.time()
    sql(f"SET client_min_messages = warning; DROP TABLE IF EXISTS prop_terrain; CREATE TABLE prop_terrain AS "
        f"SELECT tin_from_raster(rast, {TOL}, {LEVELS}) AS t FROM {table}")
    print(f"built the tin in SQL in {time.time() - t0:.2f} s")
    pxsize = float(sql_rows(f"SELECT abs(ST_PixelWidth(rast)) FROM {table}")[0][0])
    ulx, uly, sx, sy, kx, ky = (float(v) for v in sql_rows(
        f"SELECT ST_UpperLeftX(rast), ST_UpperLeftY(rast), ST_ScaleX(rast), ST_ScaleY(rast), "
        f"ST_SkewX(rast), ST_SkewY(rast) FROM {table}")[0])
    assert kx == 0 and ky == 0, "the half-pixel lattice test below assumes a raster without skew"

    def on_half_lattice(x, y):
        """Pixel centres and corners (raster coordinates in steps of 1/2)."""
        u, v = 2 * (x - ulx) / sx, 2 * (y - uly) / sy
        return np.abs(u - np.round(u)) < 1e-6 and np.abs(v - np.round(v)) < 1e-6

    px = np.array(sql_rows(f"SELECT ST_X(geom), ST_Y(geom), val FROM {table}, ST_PixelAsCentroids(rast, 1, true)"),
                  dtype=float)
    print(f"{len(px)} valid pixels (PostGIS ST_PixelAsCentroids)")
    hull = MultiPoint(px[:, :2]).convex_hull
    cells = wkt_loads(sql_rows(f"SELECT ST_AsText(ST_Polygon(rast)) FROM {table}")[0][0])
    domain = cells.intersection(hull)
    print(f"domain: {domain.area:.6g} (hull of the centres {hull.area:.6g}, {len(getattr(domain, 'geoms', [domain]))} part(s))")
    grid = raster_grid(px, ulx, uly, sx, sy)
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
        # property 0: no slivers (smallest altitude = 2 area / longest side, in pixels)
        sides = np.stack([np.hypot(c[:, (k + 1) % 3, 0] - c[:, k, 0], c[:, (k + 1) % 3, 1] - c[:, k, 1])
                          for k in range(3)], axis=1)
        alt = np.abs(area2) / sides.max(axis=1) / pxsize
        cut = np.array([not all(on_half_lattice(c[i, k, 0], c[i, k, 1]) for k in range(3)) for i in range(n)])
        check((alt[~cut] >= 1e-3).all(), f"level {l}: {(alt[~cut] < 1e-3).sum()} slivers (altitude under 1e-3 pixel)")
        check((alt >= 1e-5).all(), f"level {l}: {(alt < 1e-5).sum()} slivers (altitude under 1e-5 pixel)")
        print(f"level {l}: smallest altitude {alt[~cut].min():.4f} px; {cut.sum()} triangles at a crossing of the "
              f"hull with the outline, {(alt[cut] < 1e-3).sum()} of them under 1e-3 px, the thinnest "
              f"{alt[cut].min() if cut.any() else float('nan'):.1e} px")
        # property 1: edges shared by <= 2 triangles, boundary edges on the hull, areas add up
        edges = defaultdict(int)
        for i in range(n):
            for k in range(3):
                e = tuple(sorted((tri[i, k], tri[i, (k + 1) % 3])))
                edges[e] += 1
        check(max(edges.values()) <= 2, f"level {l}: an edge is shared by more than 2 triangles")
        boundary = [e for e, m in edges.items() if m == 1]
        ring = domain.boundary
        off = [e for e in boundary
               if ring.distance(Point(*((verts[e[0]] + verts[e[1]]) / 2))) > 1e-6
               or ring.distance(Point(*verts[e[0]])) > 1e-6]
        check(not off, f"level {l}: {len(off)} edges used by one triangle lie inside the domain (gap or T-junction)")
        total = area2.sum() / 2
        check(abs(total - domain.area) <= 1e-9 * domain.area,
              f"level {l}: triangles cover {total}, the domain {domain.area}")
        lv["tri"], lv["verts"], lv["edges"] = tri, verts, edges
        lv["vid"] = keys
        lv["z"] = np.zeros(len(verts))
        lv["z"][tri.ravel()] = c.reshape(-1, 3)[:, 2]

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
        # property 4: at every crossing of an edge with a grid segment
        # between two valid pixel centres, and at vertices on grid lines
        ge = grid_line_errors(np.array(list(edges.keys())), verts, lv["z"], grid)
        print(f"level {l}: {len(ge)} grid-line crossings and vertices on grid lines, largest error "
              f"{ge.max() if len(ge) else 0:.4f} m ({(ge.max() if len(ge) else 0) / tol:.3f}x the tolerance)")
        check((ge <= tol * (1 + 1e-9)).all(),
              f"level {l}: {(ge > tol * (1 + 1e-9)).sum()} grid-line crossings over the tolerance {tol}, "
              f"the worst {ge.max():.4f} m")

    # property 2: nesting and persistence of coarse edges
    for l in range(LEVELS - 1):
        P, C = levels[l], levels[l + 1]
        pc, cc, par = P["c"], C["c"], C["parent"]
        check(((par >= 0) & (par < len(pc))).all(), f"level {l + 1}: parent ids out of range")
        pp = pc[par]
        # a corner's distance outside its parent's sides, in pixels: a
        # vertex at a grid-line crossing lies on its parent's side only up
        # to the rounding of world coordinates (about 1e-11 pixel; in
        # barycentric terms that is 1e-8 of a parent 1e-3 pixel thin), so
        # 1e-7 pixel is allowed
        worst = 0.0
        for k in range(3):
            x, y = cc[:, k, 0], cc[:, k, 1]
            inside = np.full(len(cc), np.inf)
            for j in range(3):
                a, b = pp[:, j], pp[:, (j + 1) % 3]
                ln = np.hypot(b[:, 0] - a[:, 0], b[:, 1] - a[:, 1])
                sd = ((b[:, 0] - a[:, 0]) * (y - a[:, 1]) - (b[:, 1] - a[:, 1]) * (x - a[:, 0])) / ln / pxsize
                inside = np.minimum(inside, sd)
            out = inside < -1e-7
            worst = max(worst, float(-inside.min()))
            check(not out.any(), f"level {l + 1}: {out.sum()} triangles have a corner outside their parent "
                                 f"(by {-inside.min():.2e} pixel)")
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
        split = C.setdefault("split", [])
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
            # vertices of level l + 1 on a coarse edge: where 0.2.0 left slivers
            split.extend((a, b, cv[k]) for k in chain[1:-1])
        check(broken == 0, f"level {l}: {broken} edges do not persist at level {l + 1}")
        print(f"level {l} -> {l + 1}: children inside parents (the farthest corner {max(worst, 0.0):.1e} pixel "
              f"outside), tile them; {len(P['edges'])} edges persist")

    # areas and 3D lengths are refused on geographic tins (degrees mixed with metres)
    check_merges_near_split_edges(levels, pxsize, check, metric=(table != "dem_geo"))


def check_merges_near_split_edges(levels, pxsize, check, metric, per_level=40):
    """tin_height, tin_drape, tin_line_segments and tin_area_stats (area3d)
    around vertices that split a coarse edge, against the level's triangles
    (from tin_triangles) with matplotlib's interpolator and shapely."""
    rng = np.random.default_rng(22)
    feats = []  # (level, kind, wkt)
    for l in range(1, LEVELS):
        sp = levels[l].get("split", [])
        if not sp:
            continue
        for k in rng.choice(len(sp), size=min(per_level, len(sp)), replace=False):
            a, b, v = sp[k]
            d = np.array([b[0] - a[0], b[1] - a[1]])
            d /= np.hypot(*d)
            n = np.array([-d[1], d[0]])
            for s, t in ((0.25, 0.0), (-0.25, 0.0), (0.1, 0.3), (-0.1, -0.3), (1e-7, 0.0), (-1e-7, 0.0)):
                p = v + (s * n + t * d) * pxsize
                feats.append((l, "point", f"POINT({float(p[0])!r} {float(p[1])!r})"))
            for t in (0.0, 0.3):
                p, q = v + (-2 * n + t * d) * pxsize, v + (2 * n + t * d) * pxsize
                feats.append((l, "line", f"LINESTRING({float(p[0])!r} {float(p[1])!r},{float(q[0])!r} {float(q[1])!r})"))
            ang = 0.35
            ring = [v + 1.5 * pxsize * np.array([np.cos(ang + j * np.pi / 2), np.sin(ang + j * np.pi / 2)])
                    for j in range(4)]
            ring.append(ring[0])
            feats.append((l, "poly", "POLYGON((" + ",".join(f"{float(p[0])!r} {float(p[1])!r}" for p in ring) + "))"))
    if not feats:
        check(False, "no vertex splits a coarse edge: nothing near formerly-sliver edges was tested")
        return
    srid = sql_rows("SELECT tin_srid(t) FROM prop_terrain")[0][0]
    values = ",".join(f"({i},{l},'{k}',ST_GeomFromText('{w}',{srid}))" for i, (l, k, w) in enumerate(feats))
    sql(f"SET client_min_messages = warning; DROP TABLE IF EXISTS prop_feats; CREATE TABLE prop_feats(i int, l int, kind text, g geometry); "
        f"INSERT INTO prop_feats VALUES {values}")
    heights = {int(r[0]): (float(r[1]) if r[1] != "" else None) for r in sql_rows(
        "SELECT i, tin_height(t, g, l) FROM prop_terrain, prop_feats WHERE kind = 'point'")}
    drapes = defaultdict(list)
    for r in sql_rows("SELECT i, ST_X(p.geom), ST_Y(p.geom), ST_Z(p.geom) FROM prop_terrain, prop_feats, "
                      "ST_DumpPoints(tin_drape(t, g, l)) p WHERE kind = 'line'"):
        drapes[int(r[0])].append([float(x) for x in r[1:]])
    len3d = {} if not metric else {int(r[0]): float(r[1]) for r in sql_rows(
        "SELECT i, sum(s.length3d) FROM prop_terrain, prop_feats, tin_line_segments(t, g, l) s "
        "WHERE kind = 'line' GROUP BY i")}
    area3d = {} if not metric else {int(r[0]): float(r[1]) for r in sql_rows(
        "SELECT i, s.area3d FROM prop_terrain, prop_feats, tin_area_stats(t, g, l) s WHERE kind = 'poly'")}

    interps, trees = {}, {}
    bad = defaultdict(int)
    shown = []

    def example(msg):
        if len(shown) < 6:
            shown.append(msg)
            print("  e.g.", msg)
    for i, (l, kind, w) in enumerate(feats):
        lv = levels[l]
        if l not in interps:
            interps[l] = LinearTriInterpolator(Triangulation(lv["verts"][:, 0], lv["verts"][:, 1], lv["tri"]), lv["z"])
            trees[l] = STRtree([Polygon(t[:, :2]) for t in lv["c"]])
        def f(x, y, l=l, lv=lv):
            """Heights by the interpolator; points it leaves out (on the
            hull, up to rounding) from a triangle within 1e-9 pixel."""
            z = interps[l](x, y)
            m = np.ma.getmaskarray(z)
            if not m.any():
                return z
            z = np.ma.array(np.ma.getdata(z).astype(float), mask=m.copy())
            for j in np.atleast_1d(np.nonzero(m)[0]) if np.ndim(z) else [None]:
                px_, py_ = (x, y) if j is None else (x[j], y[j])
                near = [t for t in trees[l].query(Point(px_, py_).buffer(1e-9 * pxsize))
                        if Polygon(lv["c"][t][:, :2]).distance(Point(px_, py_)) <= 1e-9 * pxsize]
                if near:
                    zz = plane(lv["c"][near[0]], px_, py_)
                    if j is None:
                        return np.ma.array(zz)
                    z[j] = zz
                    z.mask[j] = False
            return z
        geom = wkt_loads(w)
        if kind == "point":
            zo = f(geom.x, geom.y)
            outside = np.ma.is_masked(zo) or np.isnan(float(zo))
            if outside != (heights[i] is None) or (not outside and abs(heights[i] - float(zo)) > 1e-6):
                bad["tin_height"] += 1
                example(f"tin_height {w} level {l}: {heights[i]} vs oracle {zo}")
        elif kind == "line":
            pts = np.array(drapes[i])
            zo = f(pts[:, 0], pts[:, 1])
            dz = np.abs(np.ma.getdata(zo) - pts[:, 2])
            if np.ma.getmaskarray(zo).any() or dz.max() > 1e-6:
                bad["tin_drape"] += 1
                example(f"tin_drape {w} level {l}: max |dz| {dz.max()} at "
                        f"{pts[dz.argmax()].tolist()}, oracle {zo[dz.argmax()]}, masked {np.ma.getmaskarray(zo).sum()}")
            # 3D length: the surface is linear between the line's crossings
            # with triangle edges (continuous: no cracks), so it is the sum
            # over those pieces of their 3D length, heights from the
            # interpolator (a line along an edge is in two triangles: not
            # counted twice this way)
            (x0, y0), (x1, y1) = geom.coords
            ts = {0.0, 1.0}
            for t in trees[l].query(geom):
                cut = geom.intersection(Polygon(lv["c"][t][:, :2]).exterior)
                for g in getattr(cut, "geoms", [cut]):
                    for (x, y) in getattr(g, "coords", []):
                        ts.add(((x - x0) * (x1 - x0) + (y - y0) * (y1 - y0)) / ((x1 - x0) ** 2 + (y1 - y0) ** 2))
            ts = np.array(sorted(t for t in ts if 0.0 <= t <= 1.0))
            xs, ys = x0 + ts * (x1 - x0), y0 + ts * (y1 - y0)
            zs = f(xs, ys)
            inside = ~np.ma.getmaskarray(zs)
            zs = np.ma.getdata(zs)
            ok = inside[:-1] & inside[1:]
            total = float(np.sum(np.sqrt(np.diff(xs) ** 2 + np.diff(ys) ** 2 + np.diff(zs) ** 2)[ok]))
            if metric and abs(total - len3d.get(i, 0.0)) > 1e-9 * max(total, 1.0):
                bad["tin_line_segments length3d"] += 1
                example(f"length3d {w} level {l}: {len3d.get(i)} vs oracle {total}")
        elif metric:
            total = 0.0
            for t in trees[l].query(geom):
                ct = lv["c"][t]
                a = geom.intersection(Polygon(ct[:, :2])).area
                if a > 0:
                    total += a * secant(ct)
            if abs(total - area3d.get(i, 0.0)) > 1e-9 * total:
                bad["tin_area_stats area3d"] += 1
                example(f"area3d {w} level {l}: {area3d.get(i)} vs oracle {total}")
    n = defaultdict(int)
    for (_, kind, _) in feats:
        n[kind] += 1
    print(f"merges near split coarse edges: {n['point']} points, {n['line']} lines, {n['poly']} polygons; "
          f"disagreements: {dict(bad) or 0}")
    check(not bad, f"merges near split coarse edges disagree with the oracle: {dict(bad)}")


def grid_line_errors(edges, verts, z, grid):
    """Errors of a level's surface at every crossing of its edges (vertex
    index pairs) with a grid segment between two valid pixel centres
    (against the straight line between them), and at its vertices on a
    grid line off the pixel centres. Lattice coordinates: the column and
    row of pixel centres, from the geotransform (no skew)."""
    ulx, uly, sx, sy, arr = grid
    u = (verts[:, 0] - ulx) / sx - 0.5
    v = (verts[:, 1] - uly) / sy - 0.5
    h, w = arr.shape

    def ref(c, r, axis):
        """The raster's height at lattice (c, r) on a grid line: column c
        (axis 0, r between rows) or row r (axis 1); NaN unless both pixels
        are valid."""
        if axis == 0:
            k = np.rint(c).astype(int)
            r0 = np.floor(r).astype(int)
            f = r - r0
            ok = (k >= 0) & (k < w) & (r0 >= 0) & (r0 + 1 < h)
            k, r0 = np.where(ok, k, 0), np.where(ok, r0, 0)
            za, zb = arr[r0, k], arr[np.minimum(r0 + 1, h - 1), k]
        else:
            k = np.rint(r).astype(int)
            c0 = np.floor(c).astype(int)
            f = c - c0
            ok = (k >= 0) & (k < h) & (c0 >= 0) & (c0 + 1 < w)
            k, c0 = np.where(ok, k, 0), np.where(ok, c0, 0)
            za, zb = arr[k, c0], arr[k, np.minimum(c0 + 1, w - 1)]
        # a point on a pixel centre: that pixel alone
        zz = np.where(f < 1e-9, za, za + f * (zb - za))
        return np.where(ok, zz, np.nan)

    out = []
    a, b = edges[:, 0], edges[:, 1]
    for axis, s in ((0, u), (1, v)):
        sa, sb = s[a], s[b]
        lo, hi = np.ceil(np.minimum(sa, sb)).astype(int), np.floor(np.maximum(sa, sb)).astype(int)
        n = np.maximum(hi - lo + 1, 0)
        e = np.repeat(np.arange(len(a)), n)
        k = np.repeat(lo, n) + (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n))
        den = sb[e] - sa[e]
        t = np.divide(k - sa[e], den, out=np.full(len(e), -1.0), where=den != 0)
        keep = (t > 1e-9) & (t < 1 - 1e-9)
        e, k, t = e[keep], k[keep], t[keep]
        ea, eb = a[e], b[e]
        other = (v if axis == 0 else u)
        o = other[ea] + t * (other[eb] - other[ea])
        c, r = (k.astype(float), o) if axis == 0 else (o, k.astype(float))
        zr = ref(c, r, axis)
        ze = z[ea] + t * (z[eb] - z[ea])
        good = ~np.isnan(zr)
        out.append(np.abs(ze - zr)[good])
    # vertices on a grid line, off the pixel centres
    nu, nv = np.abs(u - np.rint(u)) < 1e-6, np.abs(v - np.rint(v)) < 1e-6
    for axis, m in ((0, nu & ~nv), (1, nv & ~nu)):
        zr = ref(u[m], v[m], axis)
        good = ~np.isnan(zr)
        out.append(np.abs(z[m] - zr)[good])
    return np.concatenate(out)


def plane(ct, x, y):
    """Heights on the plane through a triangle's three corners."""
    (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = ct
    d = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    u = ((x - x0) * (y2 - y0) - (x2 - x0) * (y - y0)) / d
    v = ((x1 - x0) * (y - y0) - (x - x0) * (y1 - y0)) / d
    return z0 + u * (z1 - z0) + v * (z2 - z0)


def secant(ct):
    """3D area over 2D area of a triangle's plane."""
    p, q, r = ct
    nrm = np.cross(q - p, r - p)
    return np.linalg.norm(nrm) / abs(nrm[2])


if __name__ == "__main__":
    main()
