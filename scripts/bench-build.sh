#!/usr/bin/env bash
# Build benchmark in SQL, on issue 25's case: the bundled UTM DEM
# ST_Rescale'd 4x (nearest neighbour: 1.89 million valid pixels), 2 m at the
# finest of 5 levels. One tin over the hull of the valid centres
# (tin_from_raster, fill_gaps => true: level 0 in one triangulation, the
# finer levels parent by parent on the pixel lattice, heights read in
# place), the same pixel centres as scattered points (tin_from_points:
# bucketed, the finer levels parent by parent with each edge's samples
# found up to rounding), the raster with breaklines (the bundled DEM's 624
# gdal_contour lines of 50 m as hard breaklines at their elevation, and
# three soft lines across it: docs/breaklines.md), over the valid pixels
# only (the default since 0.10.0: the DEM's nodata border), with a boundary (a
# concave polygon with a hole), and 256-pixel tiles
# (tin_tiles_from_table); 1 and 2 threads; median of 3
# wall times, and the Rust heap's peak in the backend (the counting
# allocator; a bench build). Not a test: timings are noisy.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
[ "${TINMERGE_SKIP_INSTALL:-}" = 1 ] || TINMERGE_FEATURES=bench scripts/install.sh >/dev/null
scripts/cluster.sh start >/dev/null
db=tinmerge_bench_build
q() { scripts/cluster.sh psql -qAt -d $db "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh $db >/dev/null
q <<'SQL'
CREATE TABLE dem_x4 AS SELECT ST_Rescale(rast, ST_ScaleX(rast) / 4, ST_ScaleY(rast) / 4, 'NearestNeighbor') AS rast FROM dem;
CREATE TABLE dem_x4_tiles AS SELECT ST_Tile(rast, 256, 256) AS rast FROM dem_x4;
CREATE TABLE bench_lines AS
SELECT (SELECT ST_Collect(ST_Force3D(geom, elev)) FROM contours) AS hard,
       ST_SetSRID(ST_Collect(ARRAY[
         ST_MakeLine(ST_MakePoint(ST_XMin(e) + 0.1 * w, ST_YMin(e) + 0.2 * h), ST_MakePoint(ST_XMin(e) + 0.9 * w, ST_YMin(e) + 0.7 * h)),
         ST_MakeLine(ST_MakePoint(ST_XMin(e) + 0.2 * w, ST_YMin(e) + 0.9 * h), ST_MakePoint(ST_XMin(e) + 0.6 * w, ST_YMin(e) + 0.1 * h)),
         ST_MakeLine(ST_MakePoint(ST_XMin(e) + 0.5 * w, ST_YMin(e) + 0.5 * h), ST_MakePoint(ST_XMin(e) + 0.95 * w, ST_YMin(e) + 0.95 * h))]), 32616) AS soft,
       ST_SetSRID(ST_MakePolygon(
         ST_MakeLine(ARRAY[ST_MakePoint(ST_XMin(e) + 0.1 * w, ST_YMin(e) + 0.1 * h), ST_MakePoint(ST_XMin(e) + 0.9 * w, ST_YMin(e) + 0.15 * h),
                           ST_MakePoint(ST_XMin(e) + 0.5 * w, ST_YMin(e) + 0.5 * h), ST_MakePoint(ST_XMin(e) + 0.85 * w, ST_YMin(e) + 0.9 * h),
                           ST_MakePoint(ST_XMin(e) + 0.15 * w, ST_YMin(e) + 0.85 * h), ST_MakePoint(ST_XMin(e) + 0.1 * w, ST_YMin(e) + 0.1 * h)]),
         ARRAY[ST_MakeLine(ARRAY[ST_MakePoint(ST_XMin(e) + 0.3 * w, ST_YMin(e) + 0.6 * h), ST_MakePoint(ST_XMin(e) + 0.3 * w, ST_YMin(e) + 0.7 * h),
                                 ST_MakePoint(ST_XMin(e) + 0.4 * w, ST_YMin(e) + 0.7 * h), ST_MakePoint(ST_XMin(e) + 0.3 * w, ST_YMin(e) + 0.6 * h)])]), 32616) AS b
FROM (SELECT ST_Envelope(rast) AS e, ST_XMax(ST_Envelope(rast)) - ST_XMin(ST_Envelope(rast)) AS w,
             ST_YMax(ST_Envelope(rast)) - ST_YMin(ST_Envelope(rast)) AS h FROM dem_x4) x;
CREATE TABLE dem_x4_pts AS SELECT ST_SetSRID(ST_Collect(ST_MakePoint(ST_X(geom), ST_Y(geom), val)), 32616) AS geom FROM dem_x4, ST_PixelAsCentroids(rast, 1, true);
SQL
n=$(q -c "SELECT sum(ST_Count(rast)) FROM dem_x4")
echo "== one tin, points, tiles: DEM x4 ($n valid pixels), 2 m, 5 levels"
echo "| build | threads | median s (of 3) | samples/s | Rust heap peak MB | bytes a sample | finest triangles |"
echo "|---|---:|---:|---:|---:|---:|---:|"
row() { # label, threads, statement making table out(t tin)
  q -F ' | ' <<SQL
SET tinmerge.threads = $2;
SET tinmerge.max_memory = '8GB';
CREATE TEMP TABLE runs(ms float8, peak bigint);
DO \$\$
DECLARE t0 timestamptz; p bigint;
BEGIN
  FOR i IN 1..3 LOOP
    DROP TABLE IF EXISTS out;
    PERFORM _tin_heap_peak(true);
    t0 := clock_timestamp();
    EXECUTE \$q\$ $3 \$q\$;
    SELECT peak INTO p FROM _tin_heap_peak(false);
    INSERT INTO runs VALUES (extract(epoch FROM clock_timestamp() - t0) * 1000, p);
  END LOOP;
END \$\$;
SELECT '| $1', $2, round((percentile_cont(0.5) WITHIN GROUP (ORDER BY ms) / 1000)::numeric, 2),
       round($n / (percentile_cont(0.5) WITHIN GROUP (ORDER BY ms) / 1000)),
       round(max(peak) / 1e6, 1), round(max(peak)::numeric / $n, 1),
       (SELECT sum(tin_num_triangles(t)) FROM out) || ' |'
FROM runs;
SQL
}
for th in 1 2; do
  row "tin_from_raster, fill_gaps => true (one tin over the hull)" $th "CREATE TABLE out AS SELECT tin_from_raster(rast, 2.0, 5, fill_gaps => true) AS t FROM dem_x4"
  row "tin_from_points of the pixel centres" $th "CREATE TABLE out AS SELECT tin_from_points(geom, 2.0, 5) AS t FROM dem_x4_pts"
  row "tin_from_raster with breaklines (624 contours hard, 3 lines soft)" $th "CREATE TABLE out AS SELECT tin_from_raster(rast, 2.0, 5, breaklines => hard, soft_breaklines => soft) AS t FROM dem_x4, bench_lines"
  row "tin_from_raster (the data only: the nodata border as pixel edges)" $th "CREATE TABLE out AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem_x4"
  row "tin_from_raster with a boundary (concave, one hole)" $th "CREATE TABLE out AS SELECT tin_from_raster(rast, 2.0, 5, boundary => b) AS t FROM dem_x4, bench_lines"
  row "tin_tiles_from_table, 256-pixel tiles" $th "CREATE TABLE out AS SELECT t FROM tin_tiles_from_table('dem_x4_tiles', 2.0, 5)"
done
