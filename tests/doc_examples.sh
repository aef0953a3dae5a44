#!/usr/bin/env bash
# Every ```sql block of README.md and docs/sql-reference.md, as written
# (untyped literals included), against a database that has the tables they
# name: the bundled DEM, a terrain built from it, and small feature tables
# (wells, roads, rivers, lakes, parcels, LiDAR rows and patches, rasters)
# made from the DEM's own extent. Each block runs in a transaction that is
# rolled back (blocks that create the same table stand alone) and must run
# without an error; its rows are not compared (pg_regress and the property
# tests check the answers). Needs the running test cluster and the installed
# extension.
set -euo pipefail
cd "$(dirname "$0")/.."
db=tinmerge_examples
# the test cluster, or the one TINMERGE_PSQL reaches (scripts/installcheck.sh)
psqlc() {
  if [ -n "${TINMERGE_PSQL:-}" ]; then $TINMERGE_PSQL -v ON_ERROR_STOP=1 "$@"; else scripts/cluster.sh psql "$@"; fi
}
q() { psqlc -X -q -v ON_ERROR_STOP=1 -d $db "$@"; }
psqlc -X -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
q -c "CREATE EXTENSION tinmerge CASCADE" -c "CREATE EXTENSION pointcloud" -c "CREATE EXTENSION pointcloud_postgis" 2>/dev/null
scripts/load-data.sh $db >/dev/null
# the fixtures in their own schema, after public on the blocks' search_path:
# a block that creates a table of the same name (terrain, terrain_tiles)
# makes its own in public
q >/dev/null <<'SQL'
SET client_min_messages = warning;
CREATE SCHEMA fixtures;
SET search_path = fixtures, public;
CREATE TABLE terrain AS SELECT tin_from_raster(rast, 8.0, 4) AS t FROM dem;
-- features inside the DEM (UTM 16N, 730939..761899 E, 4036556..4069226 N)
CREATE TABLE wells AS
  SELECT i AS id, ST_SetSRID(ST_MakePoint(735000 + i * 2300, 4040000 + i * 2100), 32616) AS geom
  FROM generate_series(1, 10) i;
CREATE TABLE towers AS SELECT i AS id, ST_SetSRID(ST_MakePoint(x, y), 32616) AS geom FROM (VALUES (1, 744034, 4050191), (2, 741210, 4058004), (3, 752500, 4061000)) v(i, x, y);
CREATE TABLE roads AS
  SELECT i AS id, ST_SetSRID(ST_MakeLine(ST_MakePoint(734000 + i * 1000, 4040000), ST_MakePoint(736000 + i * 1500, 4065000)), 32616) AS geom
  FROM generate_series(1, 8) i;
CREATE TABLE roads_3d AS
  SELECT 1 AS id, 'SRID=32616;LINESTRING Z (740000 4050000 400, 750000 4060000 420)'::geometry AS geom;
CREATE TABLE road_edges AS SELECT * FROM roads_3d;
CREATE TABLE ridges AS
  SELECT 1 AS id, 'SRID=32616;LINESTRING(742000 4048000, 748000 4062000)'::geometry AS geom;
CREATE TABLE rivers AS
  SELECT i AS id, ST_SetSRID(ST_MakeLine(ARRAY[ST_MakePoint(733000, 4042000 + i * 3000), ST_MakePoint(745000, 4044000 + i * 2500),
                                              ST_MakePoint(758000, 4041000 + i * 3100)]), 32616) AS geom
  FROM generate_series(1, 6) i;
CREATE TABLE lakes AS
  SELECT 3 AS id, 'Norris' AS name, ST_Buffer('SRID=32616;POINT(747000 4052000)'::geometry, 2500) AS geom;
CREATE TABLE survey AS SELECT 1 AS id, ST_MakeEnvelope(736000, 4041000, 756000, 4064000, 32616) AS geom;
CREATE TABLE survey_area AS SELECT * FROM survey;
CREATE TABLE parcels AS
  SELECT i AS id, ST_MakeEnvelope(736000 + (i % 4) * 4000, 4042000 + (i / 4) * 4000,
                                  739000 + (i % 4) * 4000, 4045000 + (i / 4) * 4000, 32616) AS geom
  FROM generate_series(1, 12) i;
CREATE TABLE lidar AS
  SELECT (p.y * 1000 + p.x) AS id, CASE WHEN (p.x + p.y) % 5 = 0 THEN 5 ELSE 2 END AS class,
         ST_SetSRID(ST_MakePoint(ST_X(p.geom) + 7, ST_Y(p.geom) - 5, p.val), 32616) AS geom
  FROM dem_window, ST_PixelAsCentroids(rast) p WHERE p.x <= 60 AND p.y <= 60;
INSERT INTO pointcloud_formats (pcid, srid, schema) VALUES (1, 32616,
'<?xml version="1.0" encoding="UTF-8"?>
<pc:PointCloudSchema xmlns:pc="http://pointcloud.org/schemas/PC/1.1" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
  <pc:dimension><pc:position>1</pc:position><pc:size>8</pc:size><pc:name>X</pc:name><pc:interpretation>double</pc:interpretation></pc:dimension>
  <pc:dimension><pc:position>2</pc:position><pc:size>8</pc:size><pc:name>Y</pc:name><pc:interpretation>double</pc:interpretation></pc:dimension>
  <pc:dimension><pc:position>3</pc:position><pc:size>8</pc:size><pc:name>Z</pc:name><pc:interpretation>double</pc:interpretation></pc:dimension>
  <pc:dimension><pc:position>4</pc:position><pc:size>4</pc:size><pc:name>Classification</pc:name><pc:interpretation>int32_t</pc:interpretation></pc:dimension>
</pc:PointCloudSchema>');
CREATE TABLE lidar_patches AS
  SELECT PC_Patch(PC_MakePoint(1, ARRAY[ST_X(geom), ST_Y(geom), ST_Z(geom), class])) AS pa
  FROM lidar GROUP BY id / 1000;
CREATE TABLE slope AS SELECT ST_Slope(rast, 1, '32BF') AS rast FROM dem;
CREATE TABLE landcover AS SELECT ST_Reclass(rast, 1, '0-400:1, 400-600:2, 600-2000:3', '8BUI', 0) AS rast FROM dem;
CREATE TABLE ortho AS SELECT ST_AddBand(ST_AddBand(r, 1, '8BUI', 90, 0), 1, '8BUI', 60, 0) AS rast
  FROM (SELECT ST_Reclass(rast, 1, '0-2000:0-255', '8BUI', 0) AS r FROM dem) s;
CREATE TABLE dem_tiles AS SELECT ST_Tile(rast, 128, 128) AS rast FROM dem;
CREATE TABLE terrain_tiles AS SELECT tx, ty, t FROM dem, tin_tiles(rast, 128, 8.0, 4);
CREATE TABLE epochs AS
  SELECT 2020 AS year, t FROM terrain
  UNION ALL SELECT 2025, tin_from_raster(ST_MapAlgebra(rast, 1, '32BF', '[rast] + 1.5'), 8.0, 4) FROM dem;
ANALYZE;
SQL
blocks=$(mktemp -d)
trap 'rm -rf "$blocks"' EXIT
scripts/python.sh - "$blocks" README.md docs/sql-reference.md <<'PY'
import re, sys
out = sys.argv[1]
n = 0
for doc in sys.argv[2:]:
    text = open(doc).read()
    for m in re.finditer(r"^```sql\n(.*?)^```", text, re.S | re.M):
        n += 1
        line = text[: m.start()].count("\n") + 2
        open("%s/%03d.sql" % (out, n), "w").write("-- %s:%d\n%s" % (doc, line, m.group(1)))
print(n, "blocks")
PY
failed=0
count=0
for f in "$blocks"/*.sql; do
  count=$((count + 1))
  if ! { echo "BEGIN;"; echo "SET LOCAL search_path = public, fixtures;"; cat "$f"; echo; echo "ROLLBACK;"; } \
      | q -o /dev/null 2> "$f.err"; then
    echo "doc example $(head -1 "$f" | sed 's/^-- //') failed:"
    sed -n '2,$p' "$f" | head -20
    cat "$f.err"
    failed=$((failed + 1))
  fi
done
[ "$failed" -eq 0 ] || { echo "$failed of $count documented SQL blocks failed"; exit 1; }
echo "doc examples: $count SQL blocks of README.md and docs/sql-reference.md ran as written, no error"
