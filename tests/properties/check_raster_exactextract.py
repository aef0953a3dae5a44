#!/usr/bin/env python3
"""Coverage-weighted raster statistics against exactextract.

tin_raster_stats(..., weighted => true) must give, per triangle, the mean
exactextract computes for the same triangle as a polygon zone (each pixel
weighted by the fraction of its area inside), to 1e-6 relative, and report
exactly the triangles exactextract gives a mean for. The zones come out of
tin_triangles as GeoJSON, the pixel values out of PostGIS's ST_DumpValues:
nothing of tinmerge's own geometry reaches the oracle.

Rasters: the real DEM (levels 0, 2, 4), and a copy 2.5x coarser, shifted
off the DEM's grid by (1033.3 m, -517.7 m) so that part of it lies outside
the domain, with five rows of nodata (levels 0, 3).
"""
import csv
import io
import json
import os
import subprocess
import sys

import numpy as np
from exactextract import exact_extract
from exactextract.raster import NumPyRasterSource

csv.field_size_limit(sys.maxsize)
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HOST = os.path.join(ROOT, "target", "pg")
PORT = os.environ.get("TINMERGE_PORT", "28815")
DB = os.environ.get("TINMERGE_DB", "tinmerge_regress")


def psql(args):
    return subprocess.run(["psql", "-h", HOST, "-p", PORT, "-U", "postgres", "-d", DB, "-v", "ON_ERROR_STOP=1",
                           "-qAt"] + args, check=True, capture_output=True, text=True).stdout


def rows(query):
    return list(csv.reader(io.StringIO(psql(["-c", f"COPY ({query}) TO STDOUT WITH CSV"]))))


RASTERS = {
    "dem": "(SELECT rast FROM dem)",
    "window": """(SELECT ST_MapAlgebra(
                     ST_Rescale(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 1033.3, ST_UpperLeftY(rast) - 517.7), 225, -225, 'NearestNeighbor'),
                     1, '32BF', 'CASE WHEN [rast.y] BETWEEN 40 AND 44 THEN -9999 ELSE [rast] END', -9999)
                  FROM dem)""",
}
LEVELS = {"dem": [0, 2, 4], "window": [0, 3]}


def main():
    psql(["-c", "DROP TABLE IF EXISTS ee_terrain, ee_rasters",
          "-c", "CREATE TABLE ee_terrain AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem",
          "-c", "CREATE TABLE ee_rasters AS " + " UNION ALL ".join(
              f"SELECT '{k}' AS name, {v} AS rast" for k, v in RASTERS.items())])
    failures = []
    for name, levels in LEVELS.items():
        m = rows(f"SELECT ST_Width(rast), ST_Height(rast), ST_UpperLeftX(rast), ST_UpperLeftY(rast), ST_ScaleX(rast), "
                 f"ST_ScaleY(rast), ST_BandNoDataValue(rast) FROM ee_rasters WHERE name = '{name}'")[0]
        w, h = int(m[0]), int(m[1])
        ulx, uly, sx, sy, nd = map(float, m[2:])
        txt = rows(f"SELECT ST_DumpValues(rast, 1, false)::text FROM ee_rasters WHERE name = '{name}'")[0][0]
        a = np.array(json.loads(txt.replace("{", "[").replace("}", "]").replace("NULL", "null")), dtype=float)
        assert a.shape == (h, w), a.shape
        src = NumPyRasterSource(a, ulx, uly + h * sy, ulx + w * sx, uly, nodata=nd)
        for level in levels:
            feats = [{"type": "Feature", "id": int(i), "properties": {"id": int(i)}, "geometry": json.loads(g)}
                     for i, g in rows(f"SELECT id, ST_AsGeoJSON(geom, 17) FROM ee_terrain, tin_triangles(t, {level})")]
            ee = {}
            for f in exact_extract(src, feats, ["mean"], include_cols=["id"]):
                v = f["properties"]["mean"]
                if v is not None and not np.isnan(v):
                    ee[f["id"]] = v
            ours = {int(t): float(v) for t, v in rows(
                f"SELECT triangle, mean FROM ee_terrain, ee_rasters r, "
                f"tin_raster_stats(t, r.rast, {level}, weighted => true) WHERE r.name = '{name}'")}
            only_ee = sorted(set(ee) - set(ours))
            only_ours = sorted(set(ours) - set(ee))
            common = set(ee) & set(ours)
            worst = max((abs(ours[i] - ee[i]) / max(1.0, abs(ee[i])) for i in common), default=0.0)
            print(f"{name} level {level}: {len(feats)} triangles, {len(common)} with a mean in both, "
                  f"{len(only_ee)} only in exactextract, {len(only_ours)} only in tinmerge, "
                  f"worst relative difference {worst:.1e}")
            if only_ee or only_ours or worst > 1e-6 or not common:
                failures.append(f"{name} level {level}: only exactextract {only_ee[:5]}, only tinmerge "
                                f"{only_ours[:5]}, worst {worst}")
    psql(["-c", "DROP TABLE ee_terrain, ee_rasters"])
    if failures:
        print("FAILED:\n" + "\n".join(failures))
        sys.exit(1)
    print("weighted raster statistics agree with exactextract")


if __name__ == "__main__":
    main()
