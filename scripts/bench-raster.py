#!/usr/bin/env python3
"""Raster merge benchmark (called by scripts/bench.sh on its database).

Per-triangle mean of the bundled DEM and of a 4x finer copy (ST_Rescale,
nearest: ~2M pixels) at every level, three ways, in one run:
  * tinmerge: tin_raster_stats (pixel-centre rule, scanline sweep) and
    tin_raster_stats(weighted => true) (exact coverage), median of 5 runs in
    one session (the tin decoded once, as for any per-row use);
  * exactextract (Python package): the triangles exported from SQL with
    tin_triangles as GeoJSON, then exact_extract(mean) on the raster held in
    numpy (reading the raster is not counted: generous to exactextract);
    median of 3 runs; its means are compared with weighted => true;
  * PostGIS: the raster as 100 x 100 tiles with a GiST index, per triangle
    ST_Clip + ST_SummaryStats over the tiles it meets (sum / count), one run,
    at levels 0, 2 and 4 only (minutes each at the fine levels).
Pixels per second = valid pixels of the raster / time. Not a test.
"""
import csv
import io
import json
import os
import statistics
import subprocess
import sys
import time

import numpy as np
from exactextract import exact_extract
from exactextract.raster import NumPyRasterSource

csv.field_size_limit(sys.maxsize)
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HOST = os.path.join(ROOT, "target", "pg")
PORT = os.environ.get("TINMERGE_PORT", "28815")
DB = os.environ.get("TINMERGE_DB", "tinmerge_bench")


def psql(args, stdin=None):
    return subprocess.run(["psql", "-h", HOST, "-p", PORT, "-U", "postgres", "-d", DB, "-v", "ON_ERROR_STOP=1",
                           "-qAt"] + args, check=True, capture_output=True, text=True, input=stdin).stdout


def rows(query):
    return list(csv.reader(io.StringIO(psql(["-c", f"COPY ({query}) TO STDOUT WITH CSV"]))))


def setup():
    psql([], """
DROP TABLE IF EXISTS rb_rasters, rb_tiles;
CREATE TABLE rb_rasters AS
  SELECT 'dem' AS name, rast FROM dem
  UNION ALL
  SELECT 'dem x4', ST_Rescale(rast, ST_ScaleX(rast) / 4, ST_ScaleY(rast) / 4, 'NearestNeighbor') FROM dem;
CREATE TABLE rb_tiles AS SELECT name, ST_Tile(rast, 100, 100) AS rast FROM rb_rasters;
CREATE INDEX ON rb_tiles USING gist (ST_ConvexHull(rast));
ANALYZE rb_tiles;
""")


def numpy_source(name):
    m = rows(f"SELECT ST_Width(rast), ST_Height(rast), ST_UpperLeftX(rast), ST_UpperLeftY(rast), ST_ScaleX(rast), "
             f"ST_ScaleY(rast), ST_BandNoDataValue(rast) FROM rb_rasters WHERE name = '{name}'")[0]
    w, h = int(m[0]), int(m[1])
    ulx, uly, sx, sy, nd = map(float, m[2:])
    txt = rows(f"SELECT ST_DumpValues(rast, 1, false)::text FROM rb_rasters WHERE name = '{name}'")[0][0]
    a = np.array(json.loads(txt.replace("{", "[").replace("}", "]")), dtype=float)
    assert a.shape == (h, w)
    valid = int(np.sum(a != nd))
    return NumPyRasterSource(a, ulx, uly + h * sy, ulx + w * sx, uly, nodata=nd), valid, w * h


def sql_median(query, n):
    out = psql(["-c", "SET max_parallel_workers_per_gather = 0",
                "-c", f"SELECT median_ms FROM bench('', $q${query}$q$, {n})"])
    return float(out.strip().splitlines()[-1])


def exactextract_run(src, level):
    t0 = time.perf_counter()
    feats = [{"type": "Feature", "id": int(i), "properties": {"id": int(i)}, "geometry": json.loads(g)}
             for i, g in rows(f"SELECT id, ST_AsGeoJSON(geom, 17) FROM terrain, tin_triangles(t, {level})")]
    res = exact_extract(src, feats, ["mean"], include_cols=["id"])
    ms = (time.perf_counter() - t0) * 1000
    return ms, {f["id"]: f["properties"]["mean"] for f in res}


def main():
    setup()
    print("raster | pixels | level | triangles | tinmerge ms | Mpx/s | weighted ms | Mpx/s | "
          "exactextract ms | Mpx/s | exactextract / tinmerge | exactextract / weighted | max rel diff of means "
          "(weighted vs exactextract) | PostGIS ms | PostGIS / tinmerge")
    for name in ["dem", "dem x4"]:
        src, valid, total = numpy_source(name)
        for level in range(5):
            ntri = int(rows(f"SELECT tin_num_triangles(t, {level}) FROM terrain")[0][0])
            r = f"(SELECT rast FROM rb_rasters WHERE name = '{name}')"
            ours = sql_median(f"SELECT count(*) FROM terrain, tin_raster_stats(t, {r}, {level})", 5)
            wtd = sql_median(f"SELECT count(*) FROM terrain, tin_raster_stats(t, {r}, {level}, weighted => true)", 5)
            runs = [exactextract_run(src, level) for _ in range(3)]
            ee = statistics.median(ms for ms, _ in runs)
            ee_means = runs[0][1]
            mine = {int(a): float(b) for a, b in rows(
                f"SELECT triangle, mean FROM terrain, tin_raster_stats(t, {r}, {level}, weighted => true)")}
            worst = 0.0
            for i, m in ee_means.items():
                if m is None or (isinstance(m, float) and np.isnan(m)):
                    worst = max(worst, float("inf") if i in mine else 0.0)
                    continue
                worst = max(worst, abs(mine.get(i, float("inf")) - m) / max(1.0, abs(m)))
            pg, ratio = "-", "-"
            if level in (0, 2, 4):
                pg_ms = sql_median(
                    f"""SELECT count(m), sum(m) FROM (SELECT x.id, sum((s).sum) / nullif(sum((s).count), 0) AS m
                        FROM (SELECT tr.id, ST_SummaryStats(ST_Clip(ti.rast, tr.geom)) AS s
                              FROM terrain, tin_triangles(t, {level}) tr
                              JOIN rb_tiles ti ON ti.name = '{name}' AND ST_Intersects(ST_ConvexHull(ti.rast), tr.geom)) x
                        GROUP BY 1) y""", 1)
                pg, ratio = f"{pg_ms:.0f}", f"{pg_ms / ours:.0f}"
            print(f"{name} | {valid} | {level} | {ntri} | {ours:.1f} | {valid / ours / 1000:.0f} | {wtd:.1f} | "
                  f"{valid / wtd / 1000:.0f} | {ee:.0f} | {valid / ee / 1000:.1f} | {ee / ours:.1f} | {ee / wtd:.1f} | "
                  f"{worst:.1e} | {pg} | {ratio}", flush=True)


if __name__ == "__main__":
    main()
