#!/usr/bin/env bash
# Parallel query: a join of a feature table with a terrain, serial vs 2
# parallel workers (max_parallel_workers_per_gather), medians of 7, with the
# plans. Part of `make bench`; the figures go to docs/scaling.md.
# Workloads: heights of 200,000 random points (tin_height), the DEM's real
# contour lines cut per triangle (tin_line_segments) and draped (tin_drape).
# Results of the serial and parallel runs must be equal (checked; each value
# is rounded to 1e-6 before an exact numeric sum, so the order workers add in
# does not matter).
# The terrain is given as a scalar subquery (an InitPlan, run once): PostgreSQL
# 15 makes no partial plan for a cross join without a join clause
# (`FROM rpts, terrain` keeps the join above the Gather), while a join on a key
# (`JOIN terrain USING (terrain_id)`) or the subquery both run the merge in the
# workers. See docs/scaling.md.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/cluster.sh start >/dev/null
db=tinmerge_parallel
q() { scripts/cluster.sh psql -qAtX -v ON_ERROR_STOP=1 -d $db "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh $db >/dev/null
q <<'SQL'
CREATE TABLE terrain AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem;
SELECT setseed(0.25);
CREATE TABLE rpts AS
SELECT i AS id, ST_SetSRID(ST_MakePoint(x0 + random() * w, y0 + random() * h), 32616) AS geom
FROM (SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h
      FROM (SELECT tin_envelope(t)::box2d e FROM terrain) s) b, generate_series(1, 200000) i;
-- 624 contours are a small table: let the planner use 2 workers on it
ALTER TABLE contours SET (parallel_workers = 2);
ALTER TABLE rpts SET (parallel_workers = 2);
CREATE TABLE contours8 AS SELECT c.* FROM contours c, generate_series(1, 8);
ALTER TABLE contours8 SET (parallel_workers = 2);
VACUUM ANALYZE terrain; VACUUM ANALYZE rpts; VACUUM ANALYZE contours; VACUUM ANALYZE contours8;
CREATE FUNCTION timed(query text, workers int, n int) RETURNS numeric LANGUAGE plpgsql AS $$
DECLARE t0 timestamptz; ms float8[] := '{}';
BEGIN
  EXECUTE format('SET LOCAL max_parallel_workers_per_gather = %s', workers);
  FOR i IN 1..n LOOP
    t0 := clock_timestamp();
    EXECUTE query;
    ms := ms || extract(epoch FROM clock_timestamp() - t0) * 1000;
  END LOOP;
  RETURN round((SELECT percentile_cont(0.5) WITHIN GROUP (ORDER BY x) FROM unnest(ms) x)::numeric, 1);
END $$;
SQL
declare -a names=("200,000 point heights: tin_height" "624 contours cut per triangle: tin_line_segments" "624 contours draped: tin_drape" "4,992 contours (8 x 624) cut per triangle: tin_line_segments")
declare -a queries=(
  "SELECT sum(round(tin_height((SELECT t FROM terrain), geom)::numeric, 6)) FROM rpts"
  "SELECT count(*), sum(round(length3d::numeric, 6)) FROM contours c, tin_line_segments((SELECT t FROM terrain), c.geom)"
  "SELECT sum(round(ST_3DLength(tin_drape((SELECT t FROM terrain), geom))::numeric, 6)) FROM contours"
  "SELECT count(*), sum(round(length3d::numeric, 6)) FROM contours8 c, tin_line_segments((SELECT t FROM terrain), c.geom)"
)
echo "| workload | serial ms | 2 workers ms | speed-up |"
echo "|---|---:|---:|---:|"
for i in "${!queries[@]}"; do
  qq="${queries[$i]}"
  serial=$(q -c "SET max_parallel_workers_per_gather = 0" -c "$qq")
  parallel=$(q -c "SET max_parallel_workers_per_gather = 2" -c "$qq")
  [ "$serial" = "$parallel" ] || { echo "parallel result differs for ${names[$i]}: $serial vs $parallel"; exit 1; }
  plan=$(q -c "SET max_parallel_workers_per_gather = 2" -c "EXPLAIN (COSTS OFF) $qq")
  echo "$plan" | grep -q "Gather" || { echo "no parallel plan for ${names[$i]}:"; echo "$plan"; exit 1; }
  s=$(q -c "BEGIN" -c "SELECT timed(\$q\$$qq\$q\$, 0, 7)" -c "COMMIT")
  p=$(q -c "BEGIN" -c "SELECT timed(\$q\$$qq\$q\$, 2, 7)" -c "COMMIT")
  echo "| ${names[$i]} | $s | $p | $(awk -v s="$s" -v p="$p" 'BEGIN { printf "%.2f", s / p }') |"
done
echo
echo "-- for comparison, the cross join form (PostgreSQL 15 keeps the join above the Gather, the merge runs in the leader):"
echo "EXPLAIN (COSTS OFF) SELECT sum(tin_height(t, geom)) FROM rpts, terrain"
q -c "SET max_parallel_workers_per_gather = 2" -c "EXPLAIN (COSTS OFF) SELECT sum(tin_height(t, geom)) FROM rpts, terrain"
echo
for i in "${!queries[@]}"; do
  echo "-- ${names[$i]}, 2 workers:"
  echo "EXPLAIN (ANALYZE, COSTS OFF, TIMING OFF, SUMMARY OFF) ${queries[$i]}"
  q -c "SET max_parallel_workers_per_gather = 2" -c "EXPLAIN (ANALYZE, COSTS OFF, TIMING OFF, SUMMARY OFF) ${queries[$i]}"
  echo
done
