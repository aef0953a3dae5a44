#!/usr/bin/env bash
# Serving the terrain (issue 27): Cesium quantized-mesh tiles from SQL and
# exact contours, side by side with what PostGIS offers, in one run; medians
# (ms). Tiles: every tile of a zoom over the UTM terrain, one query each
# zoom (tin_quantized_mesh; with normals; with fill), against the SQL-only
# PostGIS way of getting the same triangles cut to the tiles (the level's
# triangles transformed to EPSG:4326 with a GiST index, ST_Intersection
# with each tile's envelope, as WKB: no quantization or encoding, so a
# lower bound of that way). No batch tiler (ctb-tile, tin-terrain) is
# packaged for Debian, so none is timed. Contours: tin_contours of the
# finest level against ST_Contour (GDAL's contouring of the raster, the
# same 25 m interval). Water: the tiles with the water mask of two lakes
# (one with an island) against PostGIS's mask of the same lakes on each
# tile's 256 x 256 grid (ST_AsRaster of the lakes in degrees, the raster
# alone: no mesh); with the metadata extension. Part of `make bench`;
# table in docs/performance.md.
# bench() comes from scripts/bench-fn.sql, shared with scripts/bench.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/cluster.sh start >/dev/null
db=tinmerge_serve
q() { scripts/cluster.sh psql -qAtX -v ON_ERROR_STOP=1 -d $db "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh $db >/dev/null
q -f scripts/bench-fn.sql
q <<'SQL'
CREATE TABLE terrain AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem;
CREATE TABLE layer AS SELECT tin_quantized_mesh_layer(t) AS j FROM terrain;
CREATE TABLE tiles AS
SELECT z, x, y, ST_MakeEnvelope(-180 + x * s, -90 + y * s, -180 + (x + 1) * s, -90 + (y + 1) * s, 4326) AS e
FROM layer, generate_series(10, 15) z, LATERAL (SELECT 180 / 2.0 ^ z AS s, j->'available'->z->0 AS a) r,
     generate_series((a->>'startX')::int, (a->>'endX')::int) x, generate_series((a->>'startY')::int, (a->>'endY')::int) y;
-- the PostGIS way: the level a zoom uses, as rows in degrees with a GiST index
CREATE TABLE tri_deg AS SELECT lv, ST_Transform(geom, 4326) AS geom FROM terrain, generate_series(0, 4) lv, tin_triangles(t, lv);
CREATE INDEX ON tri_deg USING gist (geom);
ANALYZE;
-- two lakes at the terrain's centre (one with an island), in its UTM SRID
CREATE TABLE lakes AS
SELECT ST_Difference(ST_Buffer(c, 2500, 64), ST_Buffer(ST_Translate(c, 300, 200), 600, 16)) AS geom FROM (SELECT ST_Centroid(tin_envelope(t)) AS c FROM terrain) s
UNION ALL SELECT ST_Buffer(ST_Translate(c, -3500, 4000), 1200, 32) FROM (SELECT ST_Centroid(tin_envelope(t)) AS c FROM terrain) s;
CREATE TABLE water AS SELECT ST_Collect(geom) AS g, ST_Transform(ST_Collect(geom), 4326) AS deg FROM lakes;
SELECT tin_num_triangles(t) FROM terrain;  -- decode once before timing
SQL
q -F ' | ' -c "SELECT z, count(*) AS tiles FROM tiles GROUP BY z ORDER BY z"
q -F ' | ' <<'SQL'
SELECT * FROM bench('tinmerge: zoom 12, 56 tiles (level 1)', 'SELECT sum(length(tin_quantized_mesh(t, z, x, y))) FROM terrain, tiles WHERE z = 12', 5)
UNION ALL SELECT * FROM bench('tinmerge: zoom 13, 224 tiles (level 2)', 'SELECT sum(length(tin_quantized_mesh(t, z, x, y))) FROM terrain, tiles WHERE z = 13', 5)
UNION ALL SELECT * FROM bench('tinmerge: zoom 13, with normals', 'SELECT sum(length(tin_quantized_mesh(t, z, x, y, normals => true))) FROM terrain, tiles WHERE z = 13', 5)
UNION ALL SELECT * FROM bench('tinmerge: zoom 13, with normals and fill', 'SELECT sum(length(tin_quantized_mesh(t, z, x, y, normals => true, fill => 240))) FROM terrain, tiles WHERE z = 13', 5)
UNION ALL SELECT * FROM bench('tinmerge: zoom 13, with the water mask of 2 lakes', 'SELECT sum(length(tin_quantized_mesh(t, z, x, y, water => g))) FROM terrain, tiles, water WHERE z = 13', 5)
UNION ALL SELECT * FROM bench('PostGIS: zoom 13, 256 x 256 masks of the lakes (ST_AsRaster, no mesh)', 'SELECT sum(length(ST_AsBinary(ST_AsRaster(deg, ST_MakeEmptyRaster(256, 256, ST_XMin(e), ST_YMax(e), (ST_XMax(e) - ST_XMin(e)) / 256, -(ST_YMax(e) - ST_YMin(e)) / 256, 0, 0, 4326), ''8BUI'', 255, 0)))) FROM tiles, water WHERE z = 13', 5)
UNION ALL SELECT * FROM bench('tinmerge: zoom 13, with metadata', 'SELECT sum(length(tin_quantized_mesh(t, z, x, y, metadata => true))) FROM terrain, tiles WHERE z = 13', 5)
UNION ALL SELECT * FROM bench('tinmerge: zoom 15, every tile (finest level)', 'SELECT sum(length(tin_quantized_mesh(t, z, x, y))) FROM terrain, tiles WHERE z = 15', 3)
UNION ALL SELECT * FROM bench('PostGIS: zoom 12, triangles cut to the tiles as WKB', 'SELECT sum(length(ST_AsBinary(ST_Intersection(r.geom, e)))) FROM tiles JOIN tri_deg r ON r.geom && e AND lv = 1 WHERE z = 12', 3)
UNION ALL SELECT * FROM bench('PostGIS: zoom 13, triangles cut to the tiles as WKB', 'SELECT sum(length(ST_AsBinary(ST_Intersection(r.geom, e)))) FROM tiles JOIN tri_deg r ON r.geom && e AND lv = 2 WHERE z = 13', 3)
UNION ALL SELECT * FROM bench('PostGIS: zoom 15, triangles cut to the tiles as WKB', 'SELECT sum(length(ST_AsBinary(ST_Intersection(r.geom, e)))) FROM tiles JOIN tri_deg r ON r.geom && e AND lv = 4 WHERE z = 15', 1)
UNION ALL SELECT * FROM bench('tinmerge: tin_quantized_mesh_layer', 'SELECT tin_quantized_mesh_layer(t) FROM terrain', 5)
UNION ALL SELECT * FROM bench('tinmerge: tin_contours every 25 m, finest level', 'SELECT count(*) FROM terrain, tin_contours(t, 25)', 5)
UNION ALL SELECT * FROM bench('tinmerge: tin_contours every 25 m, level 2', 'SELECT count(*) FROM terrain, tin_contours(t, 25, 2)', 5)
UNION ALL SELECT * FROM bench('PostGIS: ST_Contour every 25 m (GDAL, on the raster)', 'SELECT count(*) FROM dem, ST_Contour(rast, 1, 25.0)', 5);
SQL
q -F ' | ' -c "SELECT 'tin_contours finest' AS what, count(*) AS lines, round(sum(ST_Length(geom))) AS length_m FROM terrain, tin_contours(t, 25) UNION ALL SELECT 'ST_Contour', count(*), round(sum(ST_Length(geom))) FROM dem, ST_Contour(rast, 1, 25.0)"
