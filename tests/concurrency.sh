#!/usr/bin/env bash
# Concurrency: 8 clients (pgbench) run mixed merges on shared tin rows for
# TINMERGE_CONC_SECONDS (default 60) seconds; every result must equal the
# single-client result of the same case, with no failed transaction and no
# crash. Needs the running test cluster and the tinmerge_regress database
# (tables terrain and dem from pg_regress).
set -euo pipefail
cd "$(dirname "$0")/.."
DIR="$PWD/target/pg"; PORT="${TINMERGE_PORT:-28815}"
SECS="${TINMERGE_CONC_SECONDS:-60}"
q() { scripts/cluster.sh psql -qAt -v ON_ERROR_STOP=1 -d tinmerge_regress "$@"; }

q <<'SQL'
SET client_min_messages = warning;
DROP TABLE IF EXISTS conc_epoch, conc_pts, conc_feat, conc_ref, conc_out;
CREATE TABLE conc_epoch AS SELECT tin_from_raster(rast, 3.0, 4) AS t FROM dem;
-- 2,000 fixed points over the domain, one line, one polygon
CREATE TABLE conc_pts AS
  SELECT ST_SetSRID(ST_MakePoint(ST_XMin(e) + (ST_XMax(e) - ST_XMin(e)) * ((i * 7919) % 1000) / 1000.0,
                                 ST_YMin(e) + (ST_YMax(e) - ST_YMin(e)) * ((i * 104729) % 997) / 997.0), 32616) AS geom
  FROM terrain, tin_envelope(t) e, generate_series(1, 2000) i;
CREATE TABLE conc_feat AS
  SELECT ST_SetSRID(ST_MakeLine(ST_MakePoint(ST_XMin(e), ST_YMin(e)), ST_MakePoint(ST_XMax(e), ST_YMax(e))), 32616) AS line,
         ST_Buffer(ST_Centroid(e), (ST_XMax(e) - ST_XMin(e)) / 4, 64) AS poly
  FROM terrain, tin_envelope(t) e;
CREATE OR REPLACE FUNCTION conc_case(k int) RETURNS text LANGUAGE plpgsql AS $$
DECLARE r text;
BEGIN
  SET LOCAL max_parallel_workers_per_gather = 0;
  CASE k
  WHEN 1 THEN SELECT round(sum(tin_height(t, geom))::numeric, 6)::text INTO r FROM terrain, conc_pts;
  WHEN 2 THEN SELECT round(sum(length3d)::numeric, 6)::text INTO r FROM terrain, conc_feat, tin_line_segments(t, line, 3);
  WHEN 3 THEN SELECT (SELECT round(s.area3d::numeric, 4) || '/' || round(s.mean_z::numeric, 6) FROM tin_area_stats(t, poly) s) INTO r FROM terrain, conc_feat;
  WHEN 4 THEN SELECT count(*) || '/' || round(sum(s.mean)::numeric, 4) INTO r FROM terrain, dem, tin_raster_stats(t, rast, 2) s;
  WHEN 5 THEN SELECT round(d.cut::numeric, 3) || '/' || round(d.fill::numeric, 3) INTO r FROM terrain, conc_epoch, tin_difference(terrain.t, conc_epoch.t, 2, 2) d;
  WHEN 6 THEN SELECT string_agg(tin_num_triangles(t, l)::text, ',' ORDER BY l) INTO r FROM terrain, generate_series(0, 4) l;
  ELSE SELECT count(*)::text INTO r FROM terrain, tin_area_triangles(t, (SELECT poly FROM conc_feat), 1);
  END CASE;
  RETURN r;
END $$;
CREATE TABLE conc_ref AS SELECT k, conc_case(k) AS v FROM generate_series(1, 7) k;
CREATE TABLE conc_out (k int, v text);
SQL

echo "single-client results (case|value):"; q -c "SELECT k, v FROM conc_ref ORDER BY k"
nulls=$(q -c "SELECT count(*) FROM conc_ref WHERE v IS NULL OR v = ''")
[ "$nulls" = "0" ] || { echo "$nulls cases give no value"; exit 1; }
script="$PWD/target/conc.pgbench"
cat > "$script" <<'EOF'
\set k random(1, 7)
INSERT INTO conc_out SELECT :k, conc_case(:k);
EOF
echo "== $SECS s, 8 clients, 7 mixed merge cases on shared tin rows"
/usr/lib/postgresql/15/bin/pgbench -h "$DIR" -p "$PORT" -U postgres -n -c 8 -j 2 -T "$SECS" \
  -f "$script" tinmerge_regress > target/conc.log 2>&1 || { cat target/conc.log; echo "pgbench failed"; exit 1; }
grep -E "number of (transactions actually processed|failed transactions)|tps" target/conc.log || true
if grep -qE "number of failed transactions: [1-9]" target/conc.log; then
  echo "failed transactions"; exit 1
fi
q -c "SELECT k, count(*) AS runs, count(*) FILTER (WHERE o.v IS DISTINCT FROM r.v) AS differ FROM conc_out o JOIN conc_ref r USING (k) GROUP BY k ORDER BY k"
bad=$(q -c "SELECT count(*) FROM conc_out o JOIN conc_ref r USING (k) WHERE o.v IS DISTINCT FROM r.v")
cases=$(q -c "SELECT count(DISTINCT k) FROM conc_out")
runs=$(q -c "SELECT count(*) FROM conc_out")
[ "$bad" = "0" ] || { echo "$bad concurrent results differ from the single-client run"; exit 1; }
[ "$cases" = "7" ] || { echo "only $cases of 7 cases ran"; exit 1; }
echo "concurrency: $runs merges by 8 clients, all equal to the single-client results"
q -c "DROP TABLE conc_epoch, conc_pts, conc_feat, conc_ref, conc_out; DROP FUNCTION conc_case(int)"
