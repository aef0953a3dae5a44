#!/usr/bin/env bash
# Slices benchmark (issue 48): one terrain's tiles built by one backend, and
# by two backends at once, each building one slice of the tile rows
# (tin_tiles_from_table(..., slice => k, slices => 2)). The bundled UTM DEM
# ST_Rescale'd 8x (nearest neighbour: 7.6 million pixels, 2752 x 2904) cut
# into 64-pixel tiles (43 x 46 tiles), 2 m at the finest of 5 levels.
# Median of 3 wall times; the slices' rows are checked to be the whole
# build's, byte for byte. Not a test: timings are noisy.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
[ "${TINMERGE_SKIP_INSTALL:-}" = 1 ] || scripts/install.sh >/dev/null
scripts/cluster.sh start >/dev/null
db=tinmerge_bench_slices
q() { scripts/cluster.sh psql -qAt -d $db "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh $db >/dev/null
q <<'SQL'
CREATE TABLE dem_x8_tiles AS
SELECT ST_Tile(ST_Rescale(rast, ST_ScaleX(rast) / 8, ST_ScaleY(rast) / 8, 'NearestNeighbor'), 64, 64) AS rast FROM dem;
CREATE TABLE whole (tx int, ty int, t tin);
CREATE TABLE sliced (tx int, ty int, t tin);
SQL
now() { date +%s.%N; }
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
build="tin_tiles_from_table('dem_x8_tiles', 2.0, 5"
whole() {
    q -c "TRUNCATE whole"
    local t0; t0=$(now)
    q -c "SET tinmerge.threads = $1" -c "INSERT INTO whole SELECT * FROM $build)"
    echo "$(now) - $t0" | bc
}
slices() {
    q -c "TRUNCATE sliced"
    local t0; t0=$(now)
    for k in $(seq 0 $(($1 - 1))); do
        q -c "SET tinmerge.threads = 1" -c "INSERT INTO sliced SELECT * FROM $build, slice => $k, slices => $1)" &
    done
    wait
    echo "$(now) - $t0" | bc
}
w1=$(for i in 1 2 3; do whole 1; done | median)
w2=$(for i in 1 2 3; do whole 2; done | median)
s2=$(for i in 1 2 3; do slices 2; done | median)
same=$(q -c "SELECT count(*) FILTER (WHERE s.t::text = w.t::text) || ' of ' || (SELECT count(*) FROM whole) FROM sliced s JOIN whole w USING (tx, ty)")
tiles=$(q -c "SELECT count(*) FROM whole")
echo
echo "slices: the DEM x8 (7.6 Mpixels) in 64-pixel tiles, $tiles tins, 5 levels; median of 3"
echo "| build | wall time |"
echo "|---|---:|"
printf '| one backend, tinmerge.threads = 1 | %.2f s |\n' "$w1"
printf '| one backend, tinmerge.threads = 2 | %.2f s |\n' "$w2"
printf '| two backends at once, one slice each, tinmerge.threads = 1 | %.2f s |\n' "$s2"
echo "slices' tiles byte for byte the whole build's: $same"
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE $db"
