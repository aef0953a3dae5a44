#!/usr/bin/env bash
# A terrain bigger than one value, end to end, side by side with the PostGIS
# way in one run: the bundled DEM resampled FACTOR times finer with a
# deterministic fractal detail (scripts/make-big-dem.py; FACTOR 29: 9,976 x
# 10,527 = 105 million pixels of 3.1 m), loaded with raster2pgsql -t
# 256x256, built with tin_tiles_from_table on tinmerge.threads threads, then
# random points, lines and polygons merged with the tiles (the join patterns
# of docs/scaling.md) and with the raster tiles (ST_Value, ST_Clip +
# ST_SummaryStatsAgg), each cold (the first query of a new connection) and
# warm. Prints tables; timings are not asserted (noisy shared machine).
#
# It also checks, against PostGIS as the oracle, and exits non-zero when a
# check fails: every sampled valid pixel centre is within the tolerance of
# its pixel value at the finest level; points on tile seams get the same
# height from every tile that holds them; lines cut by the tiles keep their
# planar length; and (TINMERGE_BIG_WHOLE=1, the test-sized run) the tiles
# are bit for bit those tin_tiles builds from the raster as one value.
#
# With TINMERGE_BIG_SLICES=N it also builds the tiles again in N slices on N
# backends at once (slice => k, slices => N; one thread each, the default
# tinmerge.max_memory), reports each backend's peak memory and checks that
# the slices' tiles are byte for byte the one-backend build's. With
# TINMERGE_BIG_SERVE=1 it times one quantized-mesh tile at the terrain's
# centre at zoom 0, 8 and the finest, through the index of docs/serving.md,
# with the number of tins each reads. With TINMERGE_BIG_OVERVIEWS=1 it
# loads PostGIS's overviews too (raster2pgsql -l 4,16,64), builds the
# pyramid with tin_overviews (its table's layer checked byte for byte
# against the tiles), and serves the same tiles from it (with SERVE).
#
# usage: [TINMERGE_BIG_DB=database] scripts/bench-big.sh [FACTOR [POINTS LINES POLYGONS]]
#   (database tinmerge_big unless named)
#   make bench:  FACTOR 29, 1,000,000 points, 1,000 lines, 1,000 polygons;
#                scripts/bench-giga.sh: FACTOR 89 (a billion pixels), with
#                slices and serving
#   make test:   tests/big.sh runs FACTOR 6 (4.5 million pixels), fewer
#                features, with serving (the slices are checked by
#                pg_regress tiles)
set -euo pipefail
cd "$(dirname "$0")/.."
FACTOR="${1:-29}"
NPTS="${2:-1000000}"
NLINES="${3:-1000}"
NPOLYS="${4:-1000}"
TOL="${TINMERGE_BIG_TOLERANCE:-1.0}"
LEVELS=5
TILE=256
DB="${TINMERGE_BIG_DB:-tinmerge_big}"
scripts/cluster.sh start >/dev/null
q() { scripts/cluster.sh psql -v ON_ERROR_STOP=1 -qAt -d "$DB" "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $DB" -c "CREATE DATABASE $DB"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
q -f scripts/bench-fn.sql
peak_fn=$(q -c "SELECT count(*) FROM pg_proc WHERE proname = '_tin_heap_peak'")
# the backend's peak resident memory in kB (its own /proc status, as text)
HWM_KB="(regexp_match(pg_read_file('/proc/self/status'), 'VmHWM:\\s+(\\d+) kB'))[1]"

dir=target/big
mkdir -p "$dir"
echo "== the DEM: the bundled one x$FACTOR with fractal detail (scripts/make-big-dem.py)"
t0=$(date +%s.%N)
# TINMERGE_BIG_REUSE=1: keep a DEM made before (the VRT is written after the
# raw rows, so a VRT newer than them marks a finished one)
if [ "${TINMERGE_BIG_REUSE:-0}" = 1 ] && [ "$dir/dem$FACTOR.vrt" -nt "$dir/dem$FACTOR.raw" ]; then
  echo "(the DEM made before, reused: make_s is 0)"
else
  scripts/python.sh scripts/make-big-dem.py "$FACTOR" "$dir/dem$FACTOR.vrt"
fi
t1=$(date +%s.%N)
OVERVIEWS="${TINMERGE_BIG_OVERVIEWS:-0}"
raster2pgsql -s 32616 -N -9999 -t ${TILE}x${TILE} $( [ "$OVERVIEWS" = 1 ] && echo "-l 4,16,64" ) -I -Y "$dir/dem$FACTOR.vrt" public.big_tiles 2>/dev/null \
  | scripts/cluster.sh psql -q -d "$DB" >/dev/null
q -c "ANALYZE big_tiles"
t2=$(date +%s.%N)
valid=$(q -c "SELECT sum(ST_Count(rast)) FROM big_tiles")   # read once: it scans every pixel
q -F ' | ' <<SQL
SELECT 'pixels', sum(ST_Width(rast)::bigint * ST_Height(rast)) AS pixels,
       $valid AS valid_pixels, count(*) AS raster_tiles,
       round(max(ST_ScaleX(rast))::numeric, 4) AS pixel_m,
       pg_size_pretty(pg_total_relation_size('big_tiles')) AS raster_table,
       round(($t1 - $t0)::numeric, 1) AS make_s, round(($t2 - $t1)::numeric, 1) AS raster2pgsql_s
FROM big_tiles;
SQL

echo "== build: tin_tiles_from_table('big_tiles', $TOL, $LEVELS) on tinmerge.threads threads (one statement)"
if [ "$peak_fn" = 1 ]; then peak_reset="SELECT peak FROM _tin_heap_peak(true);"; peak_read="SELECT peak FROM _tin_heap_peak(false)"; else
  peak_reset="SELECT 0;"; peak_read="SELECT -1"; fi
out=$(q <<SQL
SET tinmerge.max_memory = -1;
$peak_reset
SELECT extract(epoch FROM clock_timestamp());
CREATE TABLE big_tins AS SELECT tx, ty, t FROM tin_tiles_from_table('big_tiles', $TOL, $LEVELS);
SELECT extract(epoch FROM clock_timestamp());
$peak_read;
SELECT current_setting('tinmerge.threads');
SELECT $HWM_KB;
SQL
)
read -r _ b0 b1 peak threads hwm <<<"$(echo $out)"
q -c "CREATE INDEX big_tins_envelope ON big_tins USING gist (tin_envelope(t)); ANALYZE big_tins"
q -F ' | ' <<SQL
SELECT 'tiles built' AS what, count(*) AS tins, sum(tin_num_triangles(t)) AS finest_triangles,
       sum(tin_num_vertices(t)) AS vertices, $threads AS threads,
       round(($b1 - $b0)::numeric, 1) AS build_s,
       round($valid / ($b1 - $b0)) AS valid_pixels_per_s,
       pg_size_pretty(pg_total_relation_size('big_tins')) AS tin_table,
       round(pg_total_relation_size('big_tins')::numeric / pg_total_relation_size('big_tiles'), 3) AS of_raster_table,
       round(sum(pg_column_size(t))::numeric / sum(tin_num_triangles(t)), 1) AS bytes_per_finest_triangle
FROM big_tins;
SELECT 'build memory' AS what,
       CASE WHEN $peak < 0 THEN 'n/a (install with TINMERGE_FEATURES=bench)' ELSE round($peak / 1048576.0, 1)::text END AS rust_heap_peak_mb,
       CASE WHEN $peak < 0 THEN NULL ELSE round($peak::numeric / (2 * (SELECT count(DISTINCT ST_UpperLeftX(rast)) FROM big_tiles) * $TILE * $TILE + $threads * ($TILE + 1) * ($TILE + 1)), 1) END AS bytes_per_pixel_held,
       CASE WHEN $peak < 0 THEN NULL ELSE round($peak::numeric / $valid, 2) END AS bytes_per_sample_of_raster,
       round($hwm / 1024.0, 1) AS backend_peak_rss_mb;
SQL

if [ "${TINMERGE_BIG_SLICES:-0}" -gt 0 ]; then
  N=$TINMERGE_BIG_SLICES
  echo "== build in $N slices at once, one backend each (tin_tiles_from_table(..., slice => k, slices => $N), tinmerge.threads = 1, default tinmerge.max_memory)"
  pids=()
  s0=$(date +%s.%N)
  for k in $(seq 0 $((N - 1))); do
    q -c "DROP TABLE IF EXISTS big_slice_$k" \
      -c "SET tinmerge.threads = 1" \
      -c "CREATE TABLE big_slice_$k AS SELECT tx, ty, t FROM tin_tiles_from_table('big_tiles', $TOL, $LEVELS, slice => $k, slices => $N)" \
      -c "SELECT extract(epoch FROM clock_timestamp()), $HWM_KB" \
      > "$dir/slice$k.txt" &
    pids+=($!)
  done
  for p in "${pids[@]}"; do wait "$p"; done
  slices_sql=$(for k in $(seq 0 $((N - 1))); do
    read -r end hwm_k <<<"$(tr '|' ' ' < "$dir/slice$k.txt")"
    echo "SELECT $k AS k, $end - $s0 AS s, $hwm_k AS hwm UNION ALL"
  done)
  q -F ' | ' <<SQL
SELECT 'slices' AS what, $N AS backends, round(max(s)::numeric, 1) AS wall_s,
       string_agg(round(s::numeric, 1)::text, ', ' ORDER BY k) AS each_s,
       string_agg(round(hwm / 1024.0, 1)::text, ', ' ORDER BY k) AS backend_peak_rss_mb
FROM ($slices_sql SELECT NULL, NULL, NULL) s WHERE k IS NOT NULL;
CREATE TABLE big_sliced AS $(for k in $(seq 0 $((N - 1))); do echo "SELECT * FROM big_slice_$k UNION ALL"; done) SELECT * FROM big_slice_0 WHERE false;
CREATE TABLE slice_check AS
SELECT count(*) AS tiles, count(a.t) AS one_backend, count(b.t) AS sliced,
       count(*) FILTER (WHERE a.t::text = b.t::text) AS same_bytes
FROM big_tins a FULL JOIN big_sliced b USING (tx, ty);
SELECT 'slices = one backend' AS check, * FROM slice_check;
SQL
fi

if [ "$OVERVIEWS" = 1 ]; then
  echo "== overviews: tin_overviews('big_tiles', $TOL, $LEVELS) on tinmerge.threads threads (the tiles and PostGIS's x4, x16, x64 overviews, one statement)"
  out=$(q <<SQL
SET tinmerge.max_memory = -1;
SELECT extract(epoch FROM clock_timestamp());
CREATE TABLE big_pyr AS SELECT * FROM tin_overviews('big_tiles', $TOL, $LEVELS);
SELECT extract(epoch FROM clock_timestamp());
SELECT $HWM_KB;
SQL
)
  read -r o0 o1 ohwm <<<"$(echo $out)"
  q -c "CREATE INDEX big_pyr_deg ON big_pyr USING gist (ST_Transform(ST_Segmentize(tin_envelope(t), 100), 4326)); ANALYZE big_pyr"
  q -F ' | ' <<SQL
SELECT 'pyramid built' AS what, round(($o1 - $o0)::numeric, 1) AS build_s, count(*) AS tins,
       pg_size_pretty(pg_total_relation_size('big_pyr')) AS pyramid_table, round($ohwm / 1024.0, 1) AS backend_peak_rss_mb
FROM big_pyr;
SELECT 'layer x' || factor AS layer, minzoom || '..' || maxzoom AS zooms, count(*) AS tins,
       round(sum(pg_column_size(t)) / 1e6, 1) AS stored_mb
FROM big_pyr GROUP BY factor, minzoom, maxzoom ORDER BY factor;
CREATE TABLE pyr_check AS
SELECT count(*) AS tiles, count(*) FILTER (WHERE p.t::text = b.t::text) AS same_bytes
FROM big_tins b FULL JOIN (SELECT tx, ty, t FROM big_pyr WHERE factor = 1) p USING (tx, ty);
SELECT 'pyramid x1 = the tiles' AS check, * FROM pyr_check;
SQL
fi

echo "== features: $NPTS random points, $NLINES lines of 1 km, $NPOLYS polygons (circles of 100 m radius) and $((NPOLYS / 10)) of 1 km², seeded"
q <<SQL
SELECT setseed(0.5);
CREATE TABLE ext AS SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h
FROM (SELECT ST_Extent(tin_envelope(t))::geometry e FROM big_tins) s;
CREATE TABLE big_pts AS SELECT i AS id, ST_SetSRID(ST_MakePoint(x0 + random() * w, y0 + random() * h), 32616) AS geom
FROM ext, generate_series(1, $NPTS) i;
CREATE TABLE big_lines AS SELECT i AS id, ST_SetSRID(ST_MakeLine(ST_MakePoint(x, y), ST_MakePoint(x + 1000 * cos(a), y + 1000 * sin(a))), 32616) AS geom
FROM (SELECT i, x0 + 1000 + random() * (w - 2000) x, y0 + 1000 + random() * (h - 2000) y, random() * 2 * pi() a
      FROM ext, generate_series(1, $NLINES) i) s;
CREATE TABLE big_polys AS SELECT i AS id, ST_Buffer(ST_SetSRID(ST_MakePoint(x0 + 200 + random() * (w - 400), y0 + 200 + random() * (h - 400)), 32616), 100) AS geom
FROM ext, generate_series(1, $NPOLYS) i;
CREATE TABLE big_polys_km AS SELECT i AS id, ST_Buffer(ST_SetSRID(ST_MakePoint(x0 + 600 + random() * (w - 1200), y0 + 600 + random() * (h - 1200)), 32616), 564.19) AS geom
FROM ext, generate_series(1, greatest($NPOLYS / 10, 1)) i;
CREATE INDEX ON big_pts USING gist (geom);
ANALYZE big_pts; ANALYZE big_lines; ANALYZE big_polys; ANALYZE big_polys_km;
SQL

# the queries, both ways; one core each (max_parallel_workers_per_gather = 0)
P_TIN="SELECT count(*), sum(tin_height(k.t, p.geom)) FROM big_pts p JOIN big_tins k ON tin_envelope(k.t) && p.geom"
P_PG="SELECT count(*), sum(ST_Value(r.rast, 1, p.geom)) FROM big_pts p JOIN big_tiles r ON ST_Intersects(r.rast, p.geom)"
L_TIN="SELECT l.id, sum(s.length2d) AS len2d, sum(s.length3d) AS len3d FROM big_lines l JOIN big_tins k ON tin_envelope(k.t) && l.geom, LATERAL tin_line_segments(k.t, ST_CollectionExtract(ST_Intersection(l.geom, tin_envelope(k.t)), 2)) s GROUP BY l.id"
L_PG="SELECT id, ST_3DLength(ST_MakeLine(ST_MakePoint(x, y, z) ORDER BY path)) AS len3d FROM (SELECT l.id, d.path, ST_X(d.geom) x, ST_Y(d.geom) y, (SELECT ST_Value(r.rast, 1, d.geom) FROM big_tiles r WHERE ST_Intersects(r.rast, d.geom) LIMIT 1) z FROM big_lines l, ST_DumpPoints(ST_Segmentize(l.geom, (SELECT ST_ScaleX(rast) FROM big_tiles LIMIT 1))) d) s WHERE z IS NOT NULL GROUP BY id"
A_TIN="SELECT b.id, sum(s.area2d) AS area2d, sum(s.area3d) AS area3d, sum(s.mean_z * s.area2d) / nullif(sum(s.area2d), 0) AS mean_z FROM big_polys b JOIN big_tins k ON tin_envelope(k.t) && b.geom, LATERAL tin_area_stats(k.t, ST_CollectionExtract(ST_Intersection(b.geom, tin_envelope(k.t)), 3)) s GROUP BY b.id"
A_PG="SELECT b.id, (ST_SummaryStatsAgg(ST_Clip(r.rast, b.geom), 1, true)).mean AS mean_z FROM big_polys b JOIN big_tiles r ON ST_Intersects(r.rast, b.geom) GROUP BY b.id"
K_TIN="${A_TIN//big_polys/big_polys_km}"
K_PG="${A_PG//big_polys/big_polys_km}"

# cold: the first run in a new connection; warm: the median of the next runs.
# count(s::text) needs every column of every row: with count(*) alone the
# planner would drop the unused heights and statistics (and never call the
# functions that make them).
cold_warm() { # label query warm_runs [setting]
  scripts/cluster.sh psql -qAt -F ' | ' -d "$DB" \
    -c "SET max_parallel_workers_per_gather = 0" \
    -c "${4:-SELECT}" \
    -c "SET client_min_messages = warning" \
    -c "CREATE TEMP TABLE r AS SELECT median_ms AS cold FROM bench('', \$q\$SELECT count(s::text) FROM ($2) s\$q\$, 1)" \
    -c "SELECT '$1', (SELECT cold FROM r), median_ms FROM bench('', \$q\$SELECT count(s::text) FROM ($2) s\$q\$, $3)"
}
echo "== merges (ms; one core per query): what | cold (first query of a connection) | warm median"
{
  cold_warm "$NPTS points, tinmerge: tin_height over the tin tiles (GiST on tin_envelope)" "$P_TIN" 3
  cold_warm "$NPTS points, tinmerge, tinmerge.cache_size = 4GB (every tile stays decoded)" "$P_TIN" 3 "SET tinmerge.cache_size = '4GB'"
  cold_warm "$NPTS points, PostGIS: ST_Value over the raster tiles (GiST on ST_ConvexHull)" "$P_PG" 1
  cold_warm "$NLINES lines, tinmerge: tin_line_segments per tile piece, summed (2D, 3D length)" "$L_TIN" 3
  cold_warm "$NLINES lines, PostGIS: ST_Segmentize to the pixel size, ST_Value per vertex, ST_3DLength" "$L_PG" 1
  cold_warm "$NPOLYS polygons, tinmerge: tin_area_stats per tile piece (area 2D/3D, mean z)" "$A_TIN" 3
  cold_warm "$NPOLYS polygons, PostGIS: ST_SummaryStatsAgg(ST_Clip(rast, polygon)) (mean z)" "$A_PG" 1
  cold_warm "$((NPOLYS / 10)) polygons of 1 km², tinmerge: tin_area_stats per tile piece" "$K_TIN" 3
  cold_warm "$((NPOLYS / 10)) polygons of 1 km², PostGIS: ST_SummaryStatsAgg(ST_Clip(rast, polygon))" "$K_PG" 1
} | tee "$dir/merges$FACTOR.txt"

echo "== answers, tinmerge against PostGIS (the tin interpolates a surface within $TOL m of every pixel; PostGIS reads the pixel a point falls in)"
q -F ' | ' <<SQL
SET client_min_messages = warning;
SELECT 'points' AS what, count(*) AS compared,
       round(avg(abs(a - b))::numeric, 3) AS mean_abs_diff_m, round(max(abs(a - b))::numeric, 3) AS max_abs_diff_m
FROM (SELECT p.id, tin_height(k.t, p.geom) a FROM big_pts p JOIN big_tins k ON tin_envelope(k.t) && p.geom WHERE p.id <= 100000) x
JOIN (SELECT p.id, ST_Value(r.rast, 1, p.geom) b FROM big_pts p JOIN big_tiles r ON ST_Intersects(r.rast, p.geom) WHERE p.id <= 100000) y USING (id)
WHERE a IS NOT NULL AND b IS NOT NULL;
SELECT 'lines: 3D length, tinmerge / PostGIS' AS what, count(*) AS compared,
       round(percentile_cont(0.5) WITHIN GROUP (ORDER BY a.len3d / b.len3d)::numeric, 4) AS median_ratio,
       round(min(a.len3d / b.len3d)::numeric, 4) AS min_ratio, round(max(a.len3d / b.len3d)::numeric, 4) AS max_ratio
FROM ($L_TIN) a JOIN ($L_PG) b USING (id)
WHERE abs(a.len2d - 1000) < 1e-6;
SELECT 'polygons: mean z, tinmerge - PostGIS' AS what, count(*) AS compared,
       round(percentile_cont(0.5) WITHIN GROUP (ORDER BY abs(a.mean_z - b.mean_z))::numeric, 3) AS median_abs_diff_m,
       round(max(abs(a.mean_z - b.mean_z))::numeric, 3) AS max_abs_diff_m
FROM ($A_TIN) a JOIN ($A_PG) b USING (id);
SELECT 'polygons of 1 km²: mean z, tinmerge - PostGIS' AS what, count(*) AS compared,
       round(percentile_cont(0.5) WITHIN GROUP (ORDER BY abs(a.mean_z - b.mean_z))::numeric, 3) AS median_abs_diff_m,
       round(max(abs(a.mean_z - b.mean_z))::numeric, 3) AS max_abs_diff_m
FROM ($K_TIN) a JOIN ($K_PG) b USING (id);
SQL

echo "== checks (PostGIS as the oracle)"
q -F ' | ' <<SQL
SET max_parallel_workers_per_gather = 0;
-- valid pixel centres, sampled: every one answered, each within the tolerance
CREATE TABLE centres AS
SELECT c.geom, c.val FROM (SELECT rast FROM big_tiles ORDER BY rid LIMIT 400) r, ST_PixelAsCentroids(r.rast, 1, true) c
WHERE hashint4(ST_X(c.geom)::int # ST_Y(c.geom)::int) % 97 = 0;
CREATE TABLE centre_check AS
SELECT *, tiles = 0 OR lo IS NULL AS unanswered, greatest(abs(lo - val), abs(hi - val)) > $TOL + 1e-4 AS beyond
FROM (SELECT c.val, min(tin_height(k.t, c.geom)) AS lo, max(tin_height(k.t, c.geom)) AS hi, count(k.t) AS tiles
      FROM centres c LEFT JOIN big_tins k ON tin_envelope(k.t) && c.geom GROUP BY c.geom, c.val) s;
SELECT 'pixel centres' AS check, count(*) AS sampled, count(*) FILTER (WHERE unanswered) AS unanswered,
       count(*) FILTER (WHERE beyond) AS beyond_tolerance,
       round(max(greatest(abs(lo - val), abs(hi - val)))::numeric, 4) AS worst_m
FROM centre_check;
-- points on the seams between tiles: the same height from every tile holding
-- them (each tile interpolates the seam edge from its own triangle: equal
-- up to rounding, 1e-9 m)
CREATE TABLE seam_pts AS
SELECT ST_SetSRID(ST_MakePoint(ST_XMax(e), ST_YMin(e) + f * (ST_YMax(e) - ST_YMin(e))), 32616) AS geom
FROM (SELECT tin_envelope(t)::box2d e FROM big_tins) s, (SELECT random() f FROM generate_series(1, 20)) g
UNION ALL
SELECT ST_SetSRID(ST_MakePoint(ST_XMin(e) + f * (ST_XMax(e) - ST_XMin(e)), ST_YMin(e)), 32616)
FROM (SELECT tin_envelope(t)::box2d e FROM big_tins) s, (SELECT random() f FROM generate_series(1, 20)) g;
CREATE TABLE seam_check AS
SELECT *, tiles >= 2 AND spread > 1e-9 AS disagree
FROM (SELECT p.geom, count(z) AS tiles, max(z) - min(z) AS spread
      FROM seam_pts p JOIN big_tins k ON tin_envelope(k.t) && p.geom, LATERAL (SELECT tin_height(k.t, p.geom) z) h
      GROUP BY p.geom) s;
SELECT 'seam points' AS check, count(*) FILTER (WHERE tiles >= 2) AS on_two_or_more_tiles,
       count(*) FILTER (WHERE disagree) AS heights_disagree, max(spread) AS worst_m
FROM seam_check;
-- lines: the planar length of the pieces = the line's length inside the tins'
-- domains (each the convex hull of its level 0, PostGIS ST_ConvexHull)
CREATE TABLE line_check AS
SELECT a.id, a.len2d, o.len AS oracle, abs(a.len2d - o.len) > 1e-6 AS differ FROM ($L_TIN) a JOIN (
  SELECT l.id, sum(ST_Length(ST_Intersection(ST_Intersection(l.geom, tin_envelope(k.t)), ST_ConvexHull(tin_as_geometry(k.t, 0))))) AS len
  FROM big_lines l JOIN big_tins k ON tin_envelope(k.t) && l.geom GROUP BY l.id) o USING (id);
SELECT 'lines: planar length of the pieces = ST_Length inside the domains' AS check, count(*) AS lines,
       count(*) FILTER (WHERE len2d < 999.999) AS through_nodata, count(*) FILTER (WHERE differ) AS differ
FROM line_check;
SQL
if [ "${TINMERGE_BIG_SERVE:-0}" = 1 ]; then
  echo "== serving: one quantized-mesh tile at the terrain's centre at zoom 0, 8 and the finest, through the index of docs/serving.md (cold | warm median, ms)"
  q -c "CREATE INDEX big_tins_deg ON big_tins USING gist (ST_Transform(ST_Segmentize(tin_envelope(t), 100), 4326)); ANALYZE big_tins"
  read -r lon lat top <<<"$(q -F ' ' -c "SELECT ST_X(c), ST_Y(c), (tin_quantized_mesh_layer(array_agg(t))::json ->> 'maxzoom')::int FROM big_tins, (SELECT ST_Transform(ST_SetSRID(ST_Centroid(ST_Extent(tin_envelope(t))), 32616), 4326) c FROM big_tins) s GROUP BY c")"
  for z in 0 8 "$top"; do
    read -r x y <<<"$(q -F ' ' -c "SELECT floor(($lon + 180) / (180 / 2 ^ $z))::int, floor(($lat + 90) / (180 / 2 ^ $z))::int")"
    env="ST_MakeEnvelope(-180 + $x * 180 / 2 ^ $z, -90 + $y * 180 / 2 ^ $z, -180 + ($x + 1) * 180 / 2 ^ $z, -90 + ($y + 1) * 180 / 2 ^ $z, 4326)"
    tile="SELECT tin_quantized_mesh(array_agg(t), $z, $x, $y) AS m FROM big_tins WHERE ST_Transform(ST_Segmentize(tin_envelope(t), 100), 4326) && $env"
    scripts/cluster.sh psql -qAt -F ' | ' -d "$DB" \
      -c "SET client_min_messages = warning" \
      -c "CREATE TEMP TABLE r AS SELECT median_ms AS cold FROM bench('', \$q\$SELECT length(m) FROM ($tile) s\$q\$, 1)" \
      -c "SELECT 'zoom $z tile $x/$y' AS tile, (SELECT count(*) FROM big_tins WHERE ST_Transform(ST_Segmentize(tin_envelope(t), 100), 4326) && $env) AS tins_read,
                 (SELECT length(m) FROM ($tile) s) AS bytes, (SELECT cold FROM r) AS cold_ms, median_ms AS warm_ms
          FROM bench('', \$q\$SELECT length(m) FROM ($tile) s\$q\$, 3)" \
      -c "SELECT 'backend peak RSS after the tiles, MB', round($HWM_KB::numeric / 1024, 1)"
    if [ "$OVERVIEWS" = 1 ]; then
      ptile="SELECT tin_quantized_mesh(array_agg(t), $z, $x, $y) AS m FROM big_pyr WHERE $z BETWEEN minzoom AND maxzoom AND ST_Transform(ST_Segmentize(tin_envelope(t), 100), 4326) && $env"
      scripts/cluster.sh psql -qAt -F ' | ' -d "$DB" \
        -c "SET client_min_messages = warning" \
        -c "CREATE TEMP TABLE r AS SELECT median_ms AS cold FROM bench('', \$q\$SELECT length(m) FROM ($ptile) s\$q\$, 1)" \
        -c "SELECT 'zoom $z tile $x/$y from the pyramid' AS tile, (SELECT count(*) || ' of layer x' || min(factor) FROM big_pyr WHERE $z BETWEEN minzoom AND maxzoom AND ST_Transform(ST_Segmentize(tin_envelope(t), 100), 4326) && $env) AS tins_read,
                   (SELECT length(m) FROM ($ptile) s) AS bytes, (SELECT cold FROM r) AS cold_ms, median_ms AS warm_ms
            FROM bench('', \$q\$SELECT length(m) FROM ($ptile) s\$q\$, 3)"
    fi
  done
fi
fail=$(q <<SQL
SELECT (SELECT count(*) FROM centre_check WHERE unanswered OR beyond IS NOT FALSE)
     + (SELECT count(*) FROM seam_check WHERE disagree)
     + (SELECT count(*) FROM line_check WHERE differ)
     + $( [ "$OVERVIEWS" = 1 ] && echo "(SELECT tiles - same_bytes FROM pyr_check)" || echo 0)
     + $( [ "${TINMERGE_BIG_SLICES:-0}" -gt 0 ] && echo "(SELECT tiles - same_bytes + CASE WHEN tiles = one_backend AND tiles = sliced THEN 0 ELSE 1 END FROM slice_check)" || echo 0) + (SELECT CASE WHEN count(*) = $NLINES THEN 0 ELSE 1 END FROM line_check)
     + (SELECT CASE WHEN count(*) FILTER (WHERE tiles >= 2) = 0 OR (SELECT count(*) FROM centre_check) = 0 THEN 1 ELSE 0 END FROM seam_check);
SQL
)
if [ "${TINMERGE_BIG_WHOLE:-0}" = 1 ]; then
  echo "== the same tiles from the raster as one value (tin_tiles): bit for bit"
  raster2pgsql -s 32616 -N -9999 -Y "$dir/dem$FACTOR.vrt" public.big_whole 2>/dev/null | scripts/cluster.sh psql -q -d "$DB" >/dev/null
  same=$(q -F ' | ' <<SQL
SET tinmerge.max_memory = -1;
SELECT count(*) AS tiles, count(w.t) AS matched, count(*) FILTER (WHERE f.t::text = w.t::text) AS same_bytes
FROM big_tins f FULL JOIN (SELECT w.* FROM big_whole, tin_tiles(rast, $TILE, $TOL, $LEVELS) w) w USING (tx, ty);
SQL
)
  echo "== the raster as one tin (tin_from_raster, one thread): what the tiles are compared with"
  { q -F ' | ' <<SQL
SET tinmerge.max_memory = -1;
$peak_reset
CREATE TEMP TABLE t0 AS SELECT clock_timestamp() AS t;
CREATE TABLE big_one AS SELECT tin_from_raster(rast, $TOL, $LEVELS) AS t FROM big_whole;
SELECT 'one tin' AS what, tin_num_triangles(t) AS finest_triangles,
       round(extract(epoch FROM clock_timestamp() - (SELECT t FROM t0))::numeric, 1) AS build_s,
       round($valid / extract(epoch FROM clock_timestamp() - (SELECT t FROM t0))) AS valid_pixels_per_s,
       CASE WHEN ($peak_read) < 0 THEN NULL ELSE round(($peak_read) / 1048576.0, 1) END AS rust_heap_peak_mb,
       CASE WHEN ($peak_read) < 0 THEN NULL ELSE round(($peak_read)::numeric / $valid, 1) END AS bytes_per_sample,
       pg_size_pretty(pg_column_size(t)::bigint) AS stored
FROM big_one;
SQL
  } | grep ' | '
  echo "tiles | matched | same_bytes"
  echo "$same"
  IFS='|' read -r n m s <<<"$(echo "$same" | tr -d ' ')"
  [ "$n" = "$m" ] && [ "$n" = "$s" ] || fail=$((fail + 1))
fi
if [ "$fail" != 0 ]; then
  echo "bench-big: $fail checks failed" >&2
  exit 1
fi
echo "== all checks passed"
