#!/usr/bin/env bash
# Foundation benchmarks on the bundled DEM, side by side with the PostGIS way,
# in one run. Prints a table of medians (ms). Not a test: timings are noisy.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
# the benchmark-only SQL entry points (_tin_area_examined) need a bench build
TINMERGE_FEATURES=bench scripts/install.sh >/dev/null
scripts/cluster.sh start >/dev/null
q() { scripts/cluster.sh psql -qAt -d tinmerge_bench "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS tinmerge_bench" -c "CREATE DATABASE tinmerge_bench"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh tinmerge_bench
q -f scripts/bench-fn.sql
q <<'SQL'
CREATE TABLE terrain AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem;
CREATE TABLE pts AS SELECT geom FROM dem, ST_PixelAsCentroids(rast, 1, true);
SQL
echo "== build (UTM DEM, 344 x 363, $(q -c "SELECT count(*) FROM pts") valid pixels)"
q -F ' | ' <<'SQL'
SELECT * FROM bench('tinmerge: tin_from_raster 2 m, 5 levels', 'SELECT tin_from_raster(rast, 2.0, 5) FROM dem', 5)
UNION ALL SELECT * FROM bench('tinmerge: tin_from_raster 2 m, 1 level (free greedy Delaunay)', 'SELECT tin_from_raster(rast, 2.0, 1) FROM dem', 5)
UNION ALL SELECT * FROM bench('PostGIS: ST_DelaunayTriangles of all valid pixel centres (no simplification)', 'SELECT ST_DelaunayTriangles(ST_Collect(geom), 0, 2) FROM pts', 3);
SQL
echo "== triangles at 2 m: nested finest level vs free greedy Delaunay (one level)"
q -F ' | ' -c "SELECT tin_num_triangles(t) AS nested, (SELECT tin_num_triangles(tin_from_raster(rast, 2.0, 1)) FROM dem) AS free, round(tin_num_triangles(t)::numeric / (SELECT tin_num_triangles(tin_from_raster(rast, 2.0, 1)) FROM dem), 3) AS ratio, (SELECT ST_NumGeometries(ST_DelaunayTriangles(ST_Collect(geom), 0, 2)) FROM pts) AS postgis_full FROM terrain"
echo "== per-row reads of one stored tin (10000 rows)"
q -F ' | ' <<'SQL'
SELECT * FROM bench('header only: tin_num_triangles(t, 0) x 10000', 'SELECT sum(tin_num_triangles(t, 0)) FROM terrain, generate_series(1, 10000)', 5)
UNION ALL SELECT * FROM bench('full value via cache: tin_as_geometry(t, 0) x 100', 'SELECT count(tin_as_geometry(t, 0)) FROM terrain, generate_series(1, 100)', 5);
SQL

echo "== point merge: 200,000 random points over the DEM's bounding box"
# what PostGIS users do today: (a) the DEM loaded as 64x64 tiles with a GiST index
raster2pgsql -s 32616 -N -9999 -t 64x64 -I tests/data/jacksboro_fault_dem_utm16n.tif public.dem_tiles 2>/dev/null \
  | scripts/cluster.sh psql -q -d tinmerge_bench >/dev/null
q <<'SQL'
SELECT setseed(0.25);
CREATE TABLE rpts AS
SELECT i AS id, ST_SetSRID(ST_MakePoint(x0 + random() * w, y0 + random() * h), 32616) AS geom
FROM (SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h
      FROM (SELECT tin_envelope(t)::box2d e FROM terrain) s) b, generate_series(1, 200000) i;
-- (b) the triangles as POLYGON Z rows with a GiST index; height from the plane
CREATE TABLE tri_rows AS SELECT id, geom FROM terrain, tin_triangles(t);
CREATE INDEX ON tri_rows USING gist (geom);
CREATE FUNCTION plane_z(tri geometry, p geometry) RETURNS float8 LANGUAGE sql IMMUTABLE PARALLEL SAFE AS $$
  SELECT z0 - (nx * (ST_X(p) - x0) + ny * (ST_Y(p) - y0)) / nz
  FROM (SELECT x0, y0, z0,
               (y1 - y0) * (z2 - z0) - (z1 - z0) * (y2 - y0) AS nx,
               (z1 - z0) * (x2 - x0) - (x1 - x0) * (z2 - z0) AS ny,
               (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0) AS nz
        FROM (SELECT ST_X(a) x0, ST_Y(a) y0, ST_Z(a) z0, ST_X(b) x1, ST_Y(b) y1, ST_Z(b) z1, ST_X(c) x2, ST_Y(c) y2, ST_Z(c) z2
              FROM (SELECT ST_PointN(r, 1) a, ST_PointN(r, 2) b, ST_PointN(r, 3) c FROM (SELECT ST_ExteriorRing(tri) r) s) s) s) s
$$;
-- the same query on a ~1k-triangle tin and on a ~1M-triangle tin (synthetic
-- 720 x 720 grid with hashed noise of +-2 m, one level at 0.25 m)
CREATE TABLE terrain_1k AS SELECT tin_from_raster(rast, 120.0, 1) AS t FROM dem;
CREATE TABLE terrain_1m AS
SELECT tin_from_points(ST_SetSRID(ST_Collect(ST_MakePoint(x0 + i * w / 719, y0 + j * h / 719,
         50 * sin(i / 37.0) * cos(j / 53.0) + 20 * sin((i + j) / 17.0) + (hashint8(i * 1000 + j) % 1000) / 500.0)), 32616), 0.25, 1) AS t
FROM (SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h
      FROM (SELECT tin_envelope(t)::box2d e FROM terrain) s) b,
     generate_series(0, 719) i, generate_series(0, 719) j
GROUP BY x0, y0, w, h;
ANALYZE;
SQL
q -F ' | ' -c "SELECT 'terrain' AS tin, tin_num_triangles(t) FROM terrain UNION ALL SELECT 'terrain_1k', tin_num_triangles(t) FROM terrain_1k UNION ALL SELECT 'terrain_1m', tin_num_triangles(t) FROM terrain_1m"
# one core per query for both sides (parallel workers would each load the
# libraries and decode the tin again; per-row cost is what is compared)
q -F ' | ' <<'SQL'
SET max_parallel_workers_per_gather = 0;
SELECT * FROM bench('tinmerge: sum(tin_height(t, geom)), finest level (162k triangles)', 'SELECT sum(tin_height(t, geom)) FROM rpts, terrain', 5)
UNION ALL SELECT * FROM bench('tinmerge: count(tin_locate(t, geom)), finest level', 'SELECT count(tin_locate(t, geom)) FROM rpts, terrain', 5)
UNION ALL SELECT * FROM bench('tinmerge: count(tin_drape(t, geom)), finest level (POINT Z out)', 'SELECT count(tin_drape(t, geom)) FROM rpts, terrain', 5)
UNION ALL SELECT * FROM bench('PostGIS: count(ST_Force3D(geom)) (reading and writing the points alone)', 'SELECT count(ST_Force3D(geom)) FROM rpts', 5)
UNION ALL SELECT * FROM bench('PostGIS (a): sum(ST_Value(rast, 1, geom)), 64x64 tiles + GiST', 'SELECT sum(ST_Value(rast, 1, geom)) FROM rpts p JOIN dem_tiles r ON ST_Intersects(r.rast, p.geom)', 3)
UNION ALL SELECT * FROM bench('PostGIS (b): sum(plane_z(tri, geom)), POLYGON Z rows + GiST', 'SELECT sum(plane_z(t.geom, p.geom)) FROM rpts p JOIN LATERAL (SELECT geom FROM tri_rows t WHERE ST_Intersects(t.geom, p.geom) ORDER BY id LIMIT 1) t ON true', 3)
UNION ALL SELECT * FROM bench('PostGIS (b''): count(*) of the ST_Intersects join alone', 'SELECT count(*) FROM rpts p JOIN tri_rows t ON ST_Intersects(t.geom, p.geom)', 3)
UNION ALL SELECT * FROM bench('tinmerge: sum(tin_height(t, geom)) on the ~1k-triangle tin', 'SELECT sum(tin_height(t, geom)) FROM rpts, terrain_1k', 5)
UNION ALL SELECT * FROM bench('tinmerge: sum(tin_height(t, geom)) on the ~1M-triangle tin', 'SELECT sum(tin_height(t, geom)) FROM rpts, terrain_1m', 5);
SQL
echo "== footprints: 10,000 rectangles 200 m x 500 m at random angles, finest level"
q -F ' | ' <<'SQL'
SET max_parallel_workers_per_gather = 0;
CREATE TABLE rects AS SELECT id, geom, random() * 360 AS angle FROM rpts WHERE id <= 10000;
SELECT * FROM bench('tinmerge: tin_footprint(t, geom, 200, 500, angle)', 'SELECT count(*) FROM rects r, terrain, tin_footprint(t, r.geom, 200, 500, r.angle)', 3)
UNION ALL SELECT * FROM bench('PostGIS: ST_Intersects(tri, ST_Rotate(ST_MakeEnvelope(...))) + GiST', 'SELECT count(*) FROM rects r JOIN tri_rows t ON ST_Intersects(t.geom, ST_Rotate(ST_MakeEnvelope(ST_X(r.geom) - 100, ST_Y(r.geom) - 250, ST_X(r.geom) + 100, ST_Y(r.geom) + 250, 32616), -radians(r.angle), r.geom))', 3);
SQL
echo "== line merge: a fractal river of 100,000 vertices, real contours (gdal_contour, 50 m)"
scripts/python.sh scripts/fractal-river.py 744000 4050000 752000 4055000 17 0.3 100000 7 > target/river.wkt
q <<'SQL'
CREATE TABLE river_raw(wkt text);
\copy river_raw FROM 'target/river.wkt'
CREATE TABLE river AS SELECT ST_GeomFromText(wkt, 32616) AS geom FROM river_raw;
ALTER TABLE river ADD COLUMN lt linetree GENERATED ALWAYS AS (tin_linetree(geom)) STORED;
CREATE TABLE contour_trees AS SELECT id, geom, tin_linetree(geom) AS lt FROM contours;
SQL
q -F ' | ' -c "SELECT ST_NPoints(geom) AS river_vertices, round(ST_Length(geom)) AS river_length_m, (SELECT count(*) FROM tin_line_triangles(t, geom, 0)) AS level0_triangles_crossed, (SELECT count(*) FROM tin_line_triangles(t, geom)) AS finest_triangles_crossed, (tin_linetree_info(lt)->>'nodes') AS tree_nodes, pg_column_size(lt) AS tree_bytes FROM river, terrain"
q -F ' | ' -c "SELECT count(*) AS contours, sum(ST_NPoints(geom)) AS contour_vertices FROM contours"
q -F ' | ' -c "SELECT (SELECT array_agg(triangle ORDER BY seq) FROM tin_line_triangles(t, geom, 0)) = (SELECT array_agg(triangle ORDER BY seq) FROM tin_line_triangles(t, lt, 0)) AS river_same_level0, (SELECT array_agg(triangle ORDER BY seq) FROM tin_line_triangles(t, geom)) = (SELECT array_agg(triangle ORDER BY seq) FROM tin_line_triangles(t, lt)) AS river_same_finest FROM river, terrain"
q -F ' | ' <<'SQL'
SET max_parallel_workers_per_gather = 0;
SELECT 'warm-up', count(*) FROM terrain, river, tin_line_triangles(t, lt, 0);
SELECT * FROM bench('river, level 0: plain walk (geometry)', 'SELECT count(*) FROM terrain, river, tin_line_triangles(t, geom, 0)', 15)
UNION ALL SELECT * FROM bench('river, level 0: through the stored linetree', 'SELECT count(*) FROM terrain, river, tin_line_triangles(t, lt, 0)', 15)
UNION ALL SELECT * FROM bench('river, finest: plain walk (geometry)', 'SELECT count(*) FROM terrain, river, tin_line_triangles(t, geom)', 15)
UNION ALL SELECT * FROM bench('river, finest: through the stored linetree', 'SELECT count(*) FROM terrain, river, tin_line_triangles(t, lt)', 15)
UNION ALL SELECT * FROM bench('river, level 0, width 200 m: plain', 'SELECT count(*) FROM terrain, river, tin_line_triangles(t, geom, 0, 200)', 5)
UNION ALL SELECT * FROM bench('river, level 0, width 200 m: linetree', 'SELECT count(*) FROM terrain, river, tin_line_triangles(t, lt, 0, 200)', 5)
UNION ALL SELECT * FROM bench('river, finest, width 50 m: plain', 'SELECT count(*) FROM terrain, river, tin_line_triangles(t, geom, 4, 50)', 5)
UNION ALL SELECT * FROM bench('river, finest, width 50 m: linetree', 'SELECT count(*) FROM terrain, river, tin_line_triangles(t, lt, 4, 50)', 5)
UNION ALL SELECT * FROM bench('river: reading the stored linetree alone (tin_linetree_info: detoast + hash)', 'SELECT tin_linetree_info(lt) FROM river', 15)
UNION ALL SELECT * FROM bench('river, finest: tin_line_segments plain', 'SELECT count(*) FROM terrain, river, tin_line_segments(t, geom)', 5)
UNION ALL SELECT * FROM bench('river, finest: tin_line_segments linetree', 'SELECT count(*) FROM terrain, river, tin_line_segments(t, lt)', 5)
UNION ALL SELECT * FROM bench('624 contours, finest: tin_line_triangles plain', 'SELECT count(*) FROM terrain, contour_trees c, tin_line_triangles(t, c.geom)', 5)
UNION ALL SELECT * FROM bench('624 contours, finest: tin_line_triangles linetree', 'SELECT count(*) FROM terrain, contour_trees c, tin_line_triangles(t, c.lt)', 5)
UNION ALL SELECT * FROM bench('624 contours, level 0: tin_line_triangles plain', 'SELECT count(*) FROM terrain, contour_trees c, tin_line_triangles(t, c.geom, 0)', 5)
UNION ALL SELECT * FROM bench('624 contours, level 0: tin_line_triangles linetree', 'SELECT count(*) FROM terrain, contour_trees c, tin_line_triangles(t, c.lt, 0)', 5)
UNION ALL SELECT * FROM bench('624 contours, finest: tin_drape', 'SELECT count(tin_drape(t, geom)) FROM terrain, contours', 5)
UNION ALL SELECT * FROM bench('PostGIS: ST_Intersection of 624 contours with GiST-indexed finest triangles (pieces, no heights)', 'SELECT count(ST_Intersection(c.geom, r.geom)) FROM contours c JOIN tri_rows r ON ST_Intersects(c.geom, r.geom)', 3);
SQL

echo "== area merge: polygons from a small lake to nearly the whole domain, finest level"
# examined = triangles whose relation to the polygon was decided (sweep) or
# tested (scan-fill over every triangle at the level); PostGIS = the finest
# triangles as GiST-indexed POLYGON Z rows, ST_Intersects + ST_Within /
# ST_Intersection areas (same answer as tin_area_triangles' coverage)
med=$(q -c "SELECT round(percentile_cont(0.5) WITHIN GROUP (ORDER BY val)::numeric, 1) FROM dem, ST_PixelAsPoints(rast, 1, true)")
tmp=$(mktemp -d)
gdal_contour -q -p -f CSV -lco GEOMETRY=AS_WKT -amin lo -amax hi -fl "$med" \
  tests/data/jacksboro_fault_dem_utm16n.tif "$tmp/half.csv"
chmod -R a+rX "$tmp"
q <<SQL
CREATE TABLE half_raw(wkt text, id int, lo float8, hi float8);
\copy half_raw FROM '$tmp/half.csv' CSV HEADER
CREATE TABLE area_bench AS
WITH d AS (SELECT tin_envelope(t) AS e, ST_Area(tin_as_geometry(t, 0)) AS a FROM terrain)
SELECT 'circle ' || f || ' of the domain' AS name, ST_Buffer(ST_Centroid(e), sqrt(f * a / pi()), 32) AS geom, f AS ord
FROM d, unnest(ARRAY[0.001, 0.01, 0.1, 0.5]) f
UNION ALL
SELECT 'box 0.9 of the bounding box', ST_Expand(e, -(ST_XMax(e) - ST_XMin(e)) * (1 - sqrt(0.9)) / 2), 0.9 FROM d
UNION ALL
SELECT 'land below the median height $med m (gdal_contour -p)', ST_GeomFromText(wkt, 32616), 0.51 FROM half_raw WHERE hi <= $med;
DROP TABLE half_raw;
SQL
rm -rf "$tmp"
q -F ' | ' <<'SQL'
SET max_parallel_workers_per_gather = 0;
SELECT 'polygon', 'vertices', 'share of domain', 'rows full', 'rows compact',
       'examined: sweep', 'flat sweep', 'scan-fill', 'scan / sweep',
       'ms: compact', 'full', 'flat', 'scan-fill', 'stats', 'PostGIS', 'PostGIS / compact';
SELECT a.name, ST_NPoints(a.geom),
       round(((SELECT area2d FROM tin_area_stats(t, a.geom)) / ST_Area(tin_as_geometry(t, 0)))::numeric, 3),
       (SELECT count(*) FROM tin_area_triangles(t, a.geom)),
       (SELECT count(*) FROM tin_area_triangles(t, a.geom, compact => true)),
       h.examined, f.examined, s.examined, round(s.examined::numeric / h.examined, 1),
       mc, (SELECT median_ms FROM bench('', format('SELECT count(*) FROM terrain, tin_area_triangles(t, %L::geometry)', a.geom), 5)),
       (SELECT median_ms FROM bench('', format('SELECT _tin_area_examined(t, %L::geometry::bytea, NULL, ''flat'') FROM terrain', a.geom), 5)),
       (SELECT median_ms FROM bench('', format('SELECT _tin_area_examined(t, %L::geometry::bytea, NULL, ''scan'') FROM terrain', a.geom), 5)),
       (SELECT median_ms FROM bench('', format('SELECT * FROM terrain, tin_area_stats(t, %L::geometry)', a.geom), 5)),
       pg, round(pg / mc, 1)
FROM area_bench a, terrain,
LATERAL _tin_area_examined(t, a.geom::bytea, NULL, 'hierarchy') h,
LATERAL _tin_area_examined(t, a.geom::bytea, NULL, 'flat') f,
LATERAL _tin_area_examined(t, a.geom::bytea, NULL, 'scan') s,
LATERAL (SELECT (SELECT median_ms FROM bench('', format('SELECT count(*) FROM terrain, tin_area_triangles(t, %L::geometry, compact => true)', a.geom), 5)) AS mc) m,
LATERAL (SELECT (SELECT median_ms FROM bench('', format($q$SELECT count(*), sum(CASE WHEN ST_Within(r.geom, a.geom) THEN 1 ELSE ST_Area(ST_Intersection(r.geom, a.geom)) / ST_Area(r.geom) END)
                              FROM tri_rows r JOIN (SELECT %L::geometry AS geom) a ON ST_Intersects(r.geom, a.geom)$q$, a.geom), 3)) AS pg) p
ORDER BY a.ord;
SQL

echo "== raster merge: per-triangle mean of the DEM and a 4x finer copy, every level (tinmerge, exactextract, PostGIS)"
TINMERGE_DB=tinmerge_bench scripts/python.sh scripts/bench-raster.py
echo "== core raster sweep (cargo bench -p tinmerge-core --bench raster)"
cargo bench -p tinmerge-core --bench raster 2>/dev/null

echo "== core locate (cargo bench -p tinmerge-core --bench locate): ns per point"
cargo bench -p tinmerge-core --bench locate 2>/dev/null
echo "== TIN/TIN overlay from SQL: the DEM tin against one built at 1.5 m, levels 0-1 (tinmerge tin_overlay / tin_difference vs PostGIS ST_Intersection over a GiST join of tin_triangles)"
q <<'SQL'
CREATE TABLE epoch2 AS SELECT tin_from_raster(rast, 1.5, 5) AS t FROM dem;
CREATE TABLE ov_a AS SELECT l AS level, tr.id, tr.geom FROM terrain, generate_series(0, 1) l, tin_triangles(t, l) tr;
CREATE TABLE ov_b AS SELECT l AS level, tr.id, tr.geom FROM epoch2, generate_series(0, 1) l, tin_triangles(t, l) tr;
CREATE INDEX ON ov_b USING gist (geom);
ANALYZE ov_a; ANALYZE ov_b;
SQL
q -F ' | ' <<'SQL'
SELECT l AS level,
       (SELECT count(*) FROM terrain, epoch2, tin_overlay(terrain.t, epoch2.t, l, l)) AS output_triangles,
       b1.median_ms AS tin_overlay_ms, b2.median_ms AS tin_difference_ms, b3.median_ms AS postgis_intersection_ms,
       round(b3.median_ms / b1.median_ms, 1) AS ratio
FROM generate_series(0, 1) l,
     LATERAL bench('overlay', format('SELECT count(*), sum(ST_Area(geom_a)) FROM terrain, epoch2, tin_overlay(terrain.t, epoch2.t, %s, %s)', l, l), 3) b1,
     LATERAL bench('difference', format('SELECT * FROM terrain, epoch2, tin_difference(terrain.t, epoch2.t, %s, %s)', l, l), 3) b2,
     LATERAL bench('postgis', format('SELECT count(*), sum(ST_Area(ST_Intersection(a.geom, b.geom))) FROM ov_a a JOIN ov_b b ON b.level = %s AND ST_Intersects(a.geom, b.geom) WHERE a.level = %s', l, l), 1) b3
ORDER BY 1;
SQL
echo "== TIN/TIN overlay from SQL at 100k+ triangles: levels 3-4 (PostGIS join not run: over a minute per level)"
q -F ' | ' <<'SQL'
SELECT l AS level, tin_num_triangles(terrain.t, l) AS triangles_a, tin_num_triangles(epoch2.t, l) AS triangles_b,
       (SELECT count(*) FROM tin_overlay(terrain.t, epoch2.t, l, l)) AS output_triangles,
       b1.median_ms AS tin_overlay_ms, b2.median_ms AS tin_overlay_tin_ms, b3.median_ms AS tin_difference_ms
FROM terrain, epoch2, generate_series(3, 4) l,
     LATERAL bench('overlay', format('SELECT count(*), sum(ST_Area(geom_a)) FROM terrain, epoch2, tin_overlay(terrain.t, epoch2.t, %s, %s)', l, l), 3) b1,
     LATERAL bench('overlay_tin', format('SELECT tin_num_triangles(tin_overlay_tin(terrain.t, epoch2.t, %s, %s)) FROM terrain, epoch2', l, l), 3) b2,
     LATERAL bench('difference', format('SELECT * FROM terrain, epoch2, tin_difference(terrain.t, epoch2.t, %s, %s)', l, l), 3) b3
ORDER BY 1;
SQL
echo "== TIN/TIN overlay: the DEM tin against one at other tolerances and a shifted copy, every level, vs the naive CDT (cargo bench -p tinmerge-core --bench overlay)"
cargo bench -p tinmerge-core --bench overlay 2>/dev/null
echo "== cancellation: time from statement_timeout to the error"
scripts/cancel-latency.sh tinmerge_bench
echo "== pictures: one level as SVG / as a 3D mesh (tinmerge) vs the PostGIS way (ST_AsSVG of every triangle row / ST_AsX3D of the level as a TIN)"
q -F ' | ' <<'SQL'
SELECT * FROM bench('tinmerge: tin_as_svg(t, 0), 10k triangles, whole document', 'SELECT length(tin_as_svg(t, 0)) FROM terrain', 5)
UNION ALL SELECT * FROM bench('PostGIS: string_agg(ST_AsSVG(geom)) over tin_triangles(t, 0), paths only', 'SELECT length(string_agg(ST_AsSVG(geom, 0, 1), '' '')) FROM terrain, tin_triangles(t, 0)', 5)
UNION ALL SELECT * FROM bench('tinmerge: tin_as_svg(t, 4), 157k triangles', 'SELECT length(tin_as_svg(t, 4)) FROM terrain', 3)
UNION ALL SELECT * FROM bench('PostGIS: string_agg(ST_AsSVG(geom)) over tin_triangles(t, 4)', 'SELECT length(string_agg(ST_AsSVG(geom, 0, 1), '' '')) FROM terrain, tin_triangles(t, 4)', 3)
UNION ALL SELECT * FROM bench('tinmerge: tin_as_gltf(t, 4), binary glTF with normals and colours', 'SELECT octet_length(tin_as_gltf(t, 4)) FROM terrain', 3)
UNION ALL SELECT * FROM bench('PostGIS: ST_AsX3D(tin_as_geometry(t, 4)), X3D text', 'SELECT length(ST_AsX3D(tin_as_geometry(t, 4))) FROM terrain', 3)
UNION ALL SELECT * FROM bench('tinmerge: tin_as_gltf(t, 2, ST_HillShade(rast)), with a PNG texture', 'SELECT octet_length(tin_as_gltf(t, 2, ST_HillShade(d.rast))) FROM terrain, dem d', 3);
SQL
echo "== the surface as a raster: tin_as_raster (one sweep over the triangles) vs PostGIS ST_InterpolateRaster 'linear' (GDAL's Delaunay linear interpolation) of the level's vertices, same 10 m grid"
q <<'SQL'
CREATE TABLE ras_vertices AS
SELECT l AS level, ST_Collect(DISTINCT p.geom) AS geom
FROM terrain, generate_series(0, 4) l, ST_DumpPoints(tin_as_geometry(t, l)) p GROUP BY l;
-- (ST_Force3D below: ST_InterpolateRaster of PostGIS 3.3.2 reads these stored,
-- toasted MULTIPOINT Zs as without Z: an ERROR, or NULL)
CREATE TABLE ras_grid AS SELECT ST_MakeEmptyRaster(tin_as_raster(t, 10.0, 0)) AS rast FROM terrain;
SQL
q -F ' | ' <<'SQL'
SELECT l AS level, tin_num_triangles(t, l) AS triangles, ST_Width(g.rast) * ST_Height(g.rast) AS pixels,
       b1.median_ms AS tin_as_raster_ms,
       round(ST_Width(g.rast) * ST_Height(g.rast) / b1.median_ms / 1000, 1) AS mpx_per_s,
       b2.median_ms AS postgis_interpolate_ms, round(b2.median_ms / b1.median_ms, 1) AS ratio
FROM terrain, ras_grid g, generate_series(0, 2) l,
     LATERAL bench('tin_as_raster', format('SELECT octet_length(_tin_as_raster(t, g.rast::bytea, %s, ''64BF'', -9999)) FROM terrain, ras_grid g', l), 5) b1,
     LATERAL bench('interpolate', format($q$SELECT ST_Width(ST_InterpolateRaster(ST_Force3D(v.geom), 'linear', ST_AddBand(g.rast, '64BF'::text, 0, -9999))) FROM ras_vertices v, ras_grid g WHERE v.level = %s$q$, l), 1) b2
ORDER BY 1;
SELECT * FROM bench('tinmerge: tin_as_raster(t, 5.0, pixel_type => ''32BF''), the finest level, 41 M pixels, as a raster value', 'SELECT ST_Width(tin_as_raster(t, 5.0, pixel_type => ''32BF'')) FROM terrain', 3);
SQL
echo "== viewsheds: tin_viewshed (a fan of rays through the hierarchy) vs gdal_viewshed on the DEM, same observer, 10 km, the DEM's 90 m grid"
scripts/viewshed-compare.sh tinmerge_bench
echo "== viewshed on the 105-Mpixel terrain (its 10 km window's tin, 1 m, 6 levels) vs gdal_viewshed on the raster, 3.10 m cells (cargo bench -p tinmerge-core --bench viewshed; makes the DEM and the tin once, minutes)"
cargo bench -p tinmerge-core --bench viewshed 2>/dev/null
echo "== tinmerge.threads: raster statistics and builds on 1 and 2 threads (docs/scaling.md)"
cargo bench -p tinmerge-core --bench threads 2>/dev/null
echo "== parallel query: serial vs 2 workers (docs/scaling.md)"
scripts/bench-parallel.sh
echo "== serving: quantized-mesh tiles and contours (docs/performance.md)"
scripts/bench-serve.sh
echo "== first call in a fresh backend: stored values read in slices (docs/performance.md)"
scripts/bench-cold.sh
echo "== storage: sizes, encode and whole decode, cold and warm sliced reads in memory (cargo bench -p tinmerge-core --bench storage)"
cargo bench -p tinmerge-core --bench storage 2>/dev/null
