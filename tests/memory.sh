#!/usr/bin/env bash
# tinmerge.max_memory seen from outside: the backend's own peak resident
# memory (VmHWM of /proc/<pid>/status), not the extension's counters.
#
# 1. tin_from_raster of the bundled DEM 8x finer (bilinear, 2752 x 2904,
#    7.6 million valid pixels, as a 2.75 km tile of a 1 m LiDAR DEM is),
#    2 m and 5 levels, builds under the default settings (the worst-case
#    estimate refused it: "needs about 8843 MB").
# 2. A raster whose build really needs more than the limit (white noise:
#    every pixel a vertex, about 1.7 kB a pixel) passes the up-front
#    estimate, which is the typical cost, and is stopped by the running
#    check with SQLSTATE 53400 before the backend's peak passes the limit
#    (past a quarter of the limit, the check reads the backend's private
#    resident memory too, which holds what the allocator keeps of freed
#    memory, and stops at seven eighths of the limit: the last eighth is
#    for what grows between two checks).
# 3. The same session still answers afterwards.
#
# Needs the running test cluster and the installed extension.
set -euo pipefail
cd "$(dirname "$0")/.."
q() { scripts/cluster.sh psql -qAt "$@"; }
db=tinmerge_memory
work="$PWD/target/memory"; rm -rf "$work"; mkdir -p "$work"
q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
q -d $db -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null

gdal_translate -q -outsize 800% 800% -r bilinear tests/data/jacksboro_fault_dem_utm16n.tif "$work/x8.tif"
raster2pgsql -s 32616 -N -9999 "$work/x8.tif" public.dem8 2>/dev/null | q -d $db >/dev/null
# white noise, 1000 x 1000 pixels of 2 m, seeded
q -d $db -c "SELECT setseed(0.25)" -c "CREATE TABLE noise AS SELECT ST_SetValues(
    ST_AddBand(ST_MakeEmptyRaster(1000, 1000, 700000, 4060000, 2, -2, 0, 0, 32616), '32BF'::text, 0, -9999),
    1, 1, 1, (SELECT array_agg(v ORDER BY r) FROM (SELECT r, array_agg(300 + 50 * random() ORDER BY c) AS v
              FROM generate_series(1, 1000) r, generate_series(1, 1000) c GROUP BY r) s)) AS rast"

# a small build: two levels of a 100 x 100 window of the noise
small='tin_num_levels(tin_from_raster(ST_Clip(rast, ST_MakeEnvelope(700000, 4059800, 700200, 4060000, 32616)), 5.0, 2)) FROM noise'

# one session: the backend's VmHWM before, the query, VmHWM after, then
# what follows in the same session (kB; psql's \! runs on this machine,
# where the server is)
session() {
    local sql="$1" then="${2:-}"
    cat > "$work/s.sql" <<EOF
SELECT pg_backend_pid() AS pid \\gset
-- the libraries loaded (tinmerge, PostGIS, GDAL, PROJ: their pages are
-- resident once used) before the peak is read
SELECT $small \\g /dev/null
\\setenv BPID :pid
\\! echo "before \$(grep VmHWM /proc/\$BPID/status | tr -s ' \t' ' ' | cut -d' ' -f2)"
$sql
\\! echo "after \$(grep VmHWM /proc/\$BPID/status | tr -s ' \t' ' ' | cut -d' ' -f2)"
$then
EOF
    scripts/cluster.sh psql -qAt -d $db -v ON_ERROR_STOP=0 -f "$work/s.sql" 2>&1
}
kb() { awk -v k="$1" '$1 == k {print $2}'; }

echo "-- the DEM 8x finer under the default settings"
out=$(session "SELECT current_setting('tinmerge.max_memory'), (SELECT ST_Count(rast) FROM dem8), tin_num_vertices(t), tin_num_levels(t) FROM (SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem8) s;")
echo "$out"
grep -q '^1GB|7603232|[0-9]*|5$' <<<"$out" || { echo "FAIL: the 7.6-million-pixel build did not run under the default settings"; exit 1; }
before=$(kb before <<<"$out"); after=$(kb after <<<"$out")
echo "backend VmHWM: $before kB before, $after kB after ($(( (after - before) / 1024 )) MB for the build)"

echo "-- white noise past a 256 MB limit"
out=$(session "SET tinmerge.max_memory = '256MB';
\\set VERBOSITY verbose
SELECT tin_num_vertices(tin_from_raster(rast, 2.0, 5)) FROM noise;" \
    "SELECT 'again', $small;")
echo "$out"
grep -Eq 'ERROR:  53400: this call has used [0-9]+ MB( of heap and grown the backend by [0-9]+ MB .private resident memory., past seven eighths of|, more than) tinmerge.max_memory .256 MB.' <<<"$out" \
    || { echo "FAIL: the noise build was not stopped by the running check"; exit 1; }
grep -q '^again|2$' <<<"$out" || { echo "FAIL: the session did not answer after the refusal"; exit 1; }
before=$(kb before <<<"$out"); after=$(kb after <<<"$out")
grown=$(( (after - before) / 1024 ))
echo "backend VmHWM: $before kB before, $after kB after: grew $grown MB at a 256 MB limit"
[ "$grown" -le 256 ] || { echo "FAIL: the backend grew $grown MB, past the 256 MB limit"; exit 1; }
[ -n "${KEEP_DB:-}" ] || q -d postgres -c "DROP DATABASE $db"
echo "memory: ok"
