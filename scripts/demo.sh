#!/usr/bin/env bash
# The main job: install what is missing, build and install tinmerge, start a
# throw-away PostgreSQL cluster under target/pg, load the bundled real DEM,
# build its TIN, print tin_info, per-level triangle counts and each merge,
# and write the demo page with pictures of them into target/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
echo "== building and installing tinmerge"
scripts/install.sh
scripts/cluster.sh start
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS tinmerge_demo" -c "CREATE DATABASE tinmerge_demo"
scripts/cluster.sh psql -q -d tinmerge_demo -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
echo "== loading the Jacksboro fault DEM (UTM 16N, 344 x 363, 90 m) with raster2pgsql"
scripts/load-data.sh tinmerge_demo
scripts/cluster.sh psql -d tinmerge_demo <<'SQL'
\timing on
\echo == building the hierarchy: 5 levels, the finest within 8 m of every pixel (128, 64, 32, 16, 8 m)
CREATE TABLE terrain AS SELECT 'jacksboro'::text AS name, tin_from_raster(rast, 8.0, 5) AS t FROM dem;
\timing off
\echo == adaptivity: the finest level against the raster (sizes as stored)
SELECT (SELECT count(*) FROM dem, ST_PixelAsCentroids(rast) WHERE val IS NOT NULL) AS valid_pixels,
       tin_num_vertices(t, 4) AS finest_level_vertices,
       round(100.0 * tin_num_vertices(t, 4) / (SELECT count(*) FROM dem, ST_PixelAsCentroids(rast) WHERE val IS NOT NULL)) AS percent_of_pixels,
       pg_size_pretty((SELECT pg_column_size(rast) FROM dem)::bigint) AS raster_stored,
       pg_size_pretty(pg_column_size(t)::bigint) AS tin_stored
FROM terrain;
\echo (the finest level keeps a third of the pixels as vertices, where the relief asks for them; the stored tin is
\echo  still larger than the raster of 4-byte heights: it holds all 5 levels, each triangle with its neighbours
\echo  and its parent, so that a point, line or area is located in O(1) and walked level by level)
\echo == tin_info
SELECT jsonb_pretty(tin_info(t)) FROM terrain;
\echo == per-level triangle counts
SELECT l AS level, tin_tolerance(t, l) AS tolerance_m, tin_num_triangles(t, l) AS triangles,
       tin_num_vertices(t, l) AS vertices,
       round(((tin_info(t)->'levels'->l)->>'max_error')::numeric, 3) AS max_error_m
FROM terrain, generate_series(0, tin_num_levels(t) - 1) l ORDER BY l;
\echo == point merge: height of one point at every level, its triangle, and a 30 m x 80 m footprint
SELECT l AS level, tin_locate(t, p, l) AS triangle, round(tin_height(t, p, l)::numeric, 2) AS height_m,
       (SELECT count(*) FROM tin_footprint(t, p, 30, 80, 45, l)) AS footprint_triangles
FROM terrain, generate_series(0, tin_num_levels(t) - 1) l,
     (SELECT ST_Centroid(tin_envelope(t)) AS p FROM terrain) c ORDER BY l;
\echo == line merge: a 3 km line across the terrain cut at every triangle edge, per level
SELECT l AS level, s.pieces, s.length2d_m, s.length3d_m, round(tin_line_climb(t, g, l)::numeric, 1) AS climb_m
FROM terrain, generate_series(0, tin_num_levels(t) - 1) l,
     (SELECT ST_MakeLine(ST_Translate(c, -1500, -500), ST_Translate(c, 1500, 500)) AS g
      FROM (SELECT ST_Centroid(tin_envelope(t)) AS c FROM terrain) c) g,
     LATERAL (SELECT count(*) AS pieces, round(sum(length2d)::numeric, 1) AS length2d_m,
                     round(sum(length3d)::numeric, 1) AS length3d_m FROM tin_line_segments(t, g, l)) s
ORDER BY l;
\echo == area merge: a 1 km circle (a lake), per level: triangles full vs compact, surface statistics, cut/fill at 500 m
SELECT l AS level, a.inside, a.boundary, a.compact_rows, round(s.area2d) AS area2d_m2, round(s.area3d) AS area3d_m2,
       round(s.mean_z::numeric, 1) AS mean_z, round(s.mean_slope::numeric, 1) AS mean_slope_deg,
       round(v.cut) AS cut_m3, round(v.fill) AS fill_m3
FROM terrain, generate_series(0, tin_num_levels(t) - 1) l,
     (SELECT ST_Buffer(ST_Centroid(tin_envelope(t)), 500, 32) AS g FROM terrain) g,
     LATERAL (SELECT count(*) FILTER (WHERE relation = 'inside') AS inside, count(*) FILTER (WHERE relation = 'boundary') AS boundary,
                     (SELECT count(*) FROM tin_area_triangles(t, g, l, true)) AS compact_rows
              FROM tin_area_triangles(t, g, l)) a,
     LATERAL tin_area_stats(t, g, l) s, LATERAL tin_volume(t, g, 500, l) v
ORDER BY l;
SQL
echo "== pictures: every level, each merge and the surface in 3D, into target/demo/"
scripts/demo-pictures.sh target/demo
echo
echo "Open target/demo/index.html in a browser (works offline, from file://)."
echo "The cluster is still running. Explore with: make psql   (database tinmerge_demo; table terrain)"
echo "e.g. SELECT id, parent, geom FROM terrain, tin_triangles(t, 0);   Stop it with: make stop"
