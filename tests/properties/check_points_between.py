#!/usr/bin/env python3
"""Independent check that point builds hold their tolerance between the
samples (issue 43), on both bundled DEMs.

Scattered samples say nothing about the ground between them but what a
triangulation of them says; the reference is their Delaunay triangulation,
here matplotlib's (qhull), never tinmerge's. A level is linear in each of
its triangles and so is the reference, so the level's error against the
reference is largest at a reference vertex (a sample) or where an edge of
the level crosses an edge of the reference. The oracle takes every level's
triangles from `tin_triangles` and the samples alone and checks, at every
level, that the error is within the level's tolerance (plus 1e-9
relative) at every sample, at every crossing of a level edge with a
reference edge, and at every vertex of the level that is not a sample.

Three sample sets per DEM, each built by a form users write (and the
scattered one again within a boundary with a hole, with a soft and a hard
breakline):
 - the DEM's pixel centres (every other row and column; PostGIS's
   ST_PixelAsCentroids) moved by up to a tenth of a pixel, seeded: a grid's
   own points are cocircular, so no Delaunay triangulation of them is *the*
   one (qhull and spade may pick other diagonals), and the check would
   compare two surfaces; built with tin_from_points(ST_Collect(...));
 - scattered samples: uniform in the extent, heights interpolated from the
   pixel centres; built with the aggregate tin_from_points_agg;
 - a LiDAR-like cloud: dense along slanted scan lines four pixels apart,
   5 cm of noise; built with tin_from_points(ST_Collect(...)).
"""
import csv
import io
import os
import subprocess
import sys

import numpy as np
from matplotlib.tri import LinearTriInterpolator, Triangulation
from shapely import STRtree, linestrings

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HOST = os.path.join(ROOT, "target", "pg")
PORT = os.environ.get("TINMERGE_PORT", "28815")
DB = os.environ.get("TINMERGE_DB", "tinmerge_regress")
TOL, LEVELS = 2.0, 4


def psql(args, stdin=None):
    return subprocess.run(["psql", "-h", HOST, "-p", PORT, "-U", "postgres", "-d", DB, "-v", "ON_ERROR_STOP=1",
                           "-qAt"] + args, input=stdin, check=True, capture_output=True, text=True).stdout


def sql_rows(query):
    return list(csv.reader(io.StringIO(psql(["-c", f"COPY ({query}) TO STDOUT WITH CSV"]))))


def sql(command):
    psql([], stdin=command)


def sample_sets(table, rng):
    """(name, samples as an n x 3 array, how it is built) for one DEM."""
    px = np.array(sql_rows(f"SELECT ST_X(geom), ST_Y(geom), val FROM {table}, ST_PixelAsCentroids(rast, 1, true)"),
                  dtype=float)
    ulx, uly, sx, sy = (float(v) for v in sql_rows(
        f"SELECT ST_UpperLeftX(rast), ST_UpperLeftY(rast), ST_ScaleX(rast), ST_ScaleY(rast) FROM {table}")[0])
    cols = np.rint((px[:, 0] - ulx) / sx - 0.5).astype(int)
    rows = np.rint((px[:, 1] - uly) / sy - 0.5).astype(int)
    keep = (cols % 2 == 0) & (rows % 2 == 0)
    grid = px[keep].copy()
    grid[:, 0] += (rng.random(len(grid)) - 0.5) * 0.2 * abs(sx)
    grid[:, 1] += (rng.random(len(grid)) - 0.5) * 0.2 * abs(sy)
    # heights between the pixel centres: linear in a triangulation of them
    dem = LinearTriInterpolator(Triangulation(px[:, 0], px[:, 1]), px[:, 2])
    x0, x1, y0, y1 = px[:, 0].min(), px[:, 0].max(), px[:, 1].min(), px[:, 1].max()
    xs, ys = x0 + rng.random(60000) * (x1 - x0), y0 + rng.random(60000) * (y1 - y0)
    zs = dem(xs, ys)
    ok = ~np.ma.getmaskarray(zs)
    scattered = np.column_stack([xs[ok], ys[ok], np.ma.getdata(zs)[ok]])[:30000]
    # scan lines across the extent, a slant of three pixels
    lines = []
    n_along = int((x1 - x0) / abs(sx) * 4)
    for k, yk in enumerate(np.arange(y0 + 2 * abs(sy), y1, 4 * abs(sy))):
        t = np.arange(n_along) / n_along
        x = x0 + t * (x1 - x0) + rng.random(n_along) * 0.05 * abs(sx)
        y = yk + t * 3 * abs(sy) + (rng.random(n_along) - 0.5) * 0.3 * abs(sy)
        lines.append(np.column_stack([x, y]))
    pts = np.concatenate(lines)
    zs = dem(pts[:, 0], pts[:, 1])
    ok = ~np.ma.getmaskarray(zs)
    lidar = np.column_stack([pts[ok], np.ma.getdata(zs)[ok] + (rng.random(ok.sum()) - 0.5) * 0.1])
    return [("DEM points moved up to a tenth of a pixel", grid, "collect"),
            ("scattered", scattered, "agg"),
            ("LiDAR-like", lidar, "collect")]


def domain_args(samples, srid):
    """A boundary (a rectangle inset from the samples' extent with a square
    hole), a soft line across it and a hard line (a level road 10 m over
    the mean height, heights of its own) away from the soft one, as
    shapely geometries and as tin_from_points' arguments in SQL."""
    from shapely.geometry import LineString, Polygon
    x0, x1 = samples[:, 0].min(), samples[:, 0].max()
    y0, y1 = samples[:, 1].min(), samples[:, 1].max()

    def at(u, v):
        return (x0 + u * (x1 - x0), y0 + v * (y1 - y0))
    shell = [at(0.05, 0.04), at(0.93, 0.06), at(0.95, 0.96), at(0.07, 0.94)]
    hole = [at(0.4, 0.45), at(0.4, 0.58), at(0.55, 0.58), at(0.55, 0.45)]
    area = Polygon(shell, [hole])
    soft = LineString([at(0.1, 0.2), at(0.5, 0.33), at(0.9, 0.31)])
    zr = float(samples[:, 2].mean()) + 10.0
    hard = LineString([(*at(0.15, 0.7), zr), (*at(0.6, 0.75), zr), (*at(0.85, 0.82), zr)])
    geo = lambda g: f"ST_GeomFromText('{g.wkt}', {srid})"
    args = f"breaklines => {geo(hard)}, soft_breaklines => {geo(soft)}, boundary => {geo(area)}"
    return area, soft, hard, args


def build(samples, srid, how, extra=""):
    sql("SET client_min_messages = warning; DROP TABLE IF EXISTS prop_pts; DROP TABLE IF EXISTS prop_ptin; "
        "CREATE TABLE prop_pts (x float8, y float8, z float8)")
    buf = io.StringIO()
    np.savetxt(buf, samples, fmt="%.17g", delimiter=",")
    psql(["-c", "COPY prop_pts FROM STDIN WITH CSV"], stdin=buf.getvalue())
    pt = f"ST_SetSRID(ST_MakePoint(x, y, z), {srid})"
    if how == "agg":
        body = f"SELECT tin_from_points_agg({pt}, {TOL}, {LEVELS}) AS t FROM prop_pts"
    else:
        body = f"SELECT tin_from_points(ST_Collect({pt}), {TOL}, {LEVELS}{extra}) AS t FROM prop_pts"
    sql(f"CREATE TABLE prop_ptin AS {body}")


def level(l):
    a = np.array(sql_rows(
        "SELECT ST_X(ST_PointN(r,1)), ST_Y(ST_PointN(r,1)), ST_Z(ST_PointN(r,1)), "
        "ST_X(ST_PointN(r,2)), ST_Y(ST_PointN(r,2)), ST_Z(ST_PointN(r,2)), "
        "ST_X(ST_PointN(r,3)), ST_Y(ST_PointN(r,3)), ST_Z(ST_PointN(r,3)) "
        f"FROM (SELECT ST_ExteriorRing(geom) r FROM prop_ptin, tin_triangles(t, {l})) s"), dtype=float)
    c = a.reshape(-1, 3, 3)
    keys, tri = {}, np.empty((len(c), 3), dtype=np.int64)
    for i in range(len(c)):
        for k in range(3):
            tri[i, k] = keys.setdefault((c[i, k, 0], c[i, k, 1]), len(keys))
    verts = np.array(list(keys.keys()))
    z = np.zeros(len(verts))
    z[tri.ravel()] = c.reshape(-1, 3)[:, 2]
    return verts, z, tri


def edges_of(tri):
    return np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1), axis=0)


def crossing_errors(ev, ez, ref_edges, rv, rz):
    """|level - reference| at every proper crossing of a level edge (ends
    ev, heights ez) with a reference edge, away from both edges' ends."""
    tree = STRtree(linestrings(rv[ref_edges]))
    li, ri = tree.query(linestrings(ev), predicate="intersects")
    a, b = ev[li, 0], ev[li, 1]
    u, v = rv[ref_edges[ri, 0]], rv[ref_edges[ri, 1]]

    def orient(p, q, r):
        return (q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0])

    oa, ob = orient(u, v, a), orient(u, v, b)
    ou, ov = orient(a, b, u), orient(a, b, v)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = oa / (oa - ob)
        s = ou / (ou - ov)
    eps = 1e-9
    proper = (oa * ob < 0) & (ou * ov < 0) & (t > eps) & (t < 1 - eps) & (s > eps) & (s < 1 - eps)
    zl = ez[li, 0] + t * (ez[li, 1] - ez[li, 0])
    zr = rz[ref_edges[ri, 0]] + s * (rz[ref_edges[ri, 1]] - rz[ref_edges[ri, 0]])
    return np.abs(zl - zr)[proper]


def check_set(name, samples, how, srid, check, domain=False):
    """The checks of one build; with `domain`, within domain_args's
    boundary and with its lines: the samples outside the boundary or on a
    line are no vertices, the reference's edges a hard line cuts (within
    1e-6 m: the surface there is the line's) and the level's vertices on
    it (the line's heights) are left out."""
    print(f"-- {name}: {len(samples)} samples ({'tin_from_points_agg' if how == 'agg' else 'tin_from_points(ST_Collect(...))'})")
    hard = None
    want = np.ones(len(samples), dtype=bool)
    if domain:
        from shapely import distance, points
        area, soft, hard, args = domain_args(samples, srid)
        build(samples, srid, how, ", " + args)
        p = points(samples[:, :2])
        # samples in the domain, away from its rings and the lines
        want = area.contains(p) & (distance(p, area.boundary) > 1e-6) & (distance(p, soft) > 1e-6) \
            & (distance(p, hard) > 1e-6)
        print(f"   within a boundary with a hole, a soft and a hard line: {want.sum()} samples inside")
    else:
        build(samples, srid, how)
    ref = Triangulation(samples[:, 0], samples[:, 1])
    ref_edges = ref.edges
    if hard is not None:
        from shapely import distance
        cut = distance(linestrings(samples[:, :2][ref_edges]), hard) <= 1e-6
        ref_edges = ref_edges[~cut]
        print(f"   {cut.sum()} reference edges cut by the hard line")
    ref_at = LinearTriInterpolator(ref, samples[:, 2])
    for l in range(LEVELS):
        tol = TOL * 2 ** (LEVELS - 1 - l)
        verts, z, tri = level(l)
        edges = edges_of(tri)
        ev = verts[edges]
        ez = z[edges]
        cross = crossing_errors(ev, ez, ref_edges, np.column_stack([samples[:, 0], samples[:, 1]]), samples[:, 2])
        # at the samples: the level's own triangles, matplotlib's interpolation
        lev = LinearTriInterpolator(Triangulation(verts[:, 0], verts[:, 1], tri), z)
        at = lev(samples[:, 0], samples[:, 1])
        inside = ~np.ma.getmaskarray(at) & want
        at_samples = np.abs(np.ma.getdata(at)[inside] - samples[inside, 2])
        # the level's vertices that are not samples: on the reference
        rz = ref_at(verts[:, 0], verts[:, 1])
        has = ~np.ma.getmaskarray(rz)
        if hard is not None:
            from shapely import distance, points
            has &= distance(points(verts), hard) > 1e-6
        at_verts = np.abs(np.ma.getdata(rz)[has] - z[has])
        worst = max(cross.max(initial=0), at_samples.max(initial=0), at_verts.max(initial=0))
        if at_verts.max(initial=0) > tol:
            k = np.flatnonzero(has)[np.argmax(at_verts)]
            print(f"   worst vertex POINT({verts[k, 0]!r} {verts[k, 1]!r}) at {z[k]!r}, the reference's {float(rz[k])!r}")
        print(f"level {l}: {len(tri)} triangles; {len(cross)} crossings with the reference's edges, largest error "
              f"{cross.max(initial=0):.4f} m; {inside.sum()} samples, {at_samples.max(initial=0):.4f} m; "
              f"{has.sum()} vertices, {at_verts.max(initial=0):.4f} m ({worst / tol:.3f}x the tolerance {tol:g})")
        check(worst <= tol * (1 + 1e-9), f"{name} level {l}: {worst} m off the samples' Delaunay surface, tolerance {tol}")
        check(inside.sum() == want.sum(), f"{name} level {l}: {want.sum() - inside.sum()} samples outside the level")
    sql("DROP TABLE prop_ptin; DROP TABLE prop_pts")


def main():
    failures = []

    def check(cond, msg):
        if not cond:
            failures.append(msg)
            print("FAIL:", msg)

    rng = np.random.default_rng(43)
    for table in ("dem", "dem_geo"):
        srid = sql_rows(f"SELECT ST_SRID(rast) FROM {table}")[0][0]
        print(f"== {table} (SRID {srid})")
        sets = sample_sets(table, rng)
        for name, samples, how in sets:
            check_set(f"{table} {name}", samples, how, srid, check)
        # the scattered samples again, within a boundary and with lines
        name, samples, _ = sets[1]
        check_set(f"{table} {name}, boundary and lines", samples, "collect", srid, check, domain=True)
    if failures:
        print(f"{len(failures)} point-build checks FAILED")
        sys.exit(1)
    print("point builds hold every level's tolerance against the samples' Delaunay surface (matplotlib's) at every "
          "sample, crossing and vertex, on both DEMs")


if __name__ == "__main__":
    main()
