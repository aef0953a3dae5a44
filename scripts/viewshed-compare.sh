#!/usr/bin/env bash
# tin_viewshed against gdal_viewshed (and GRASS r.viewshed when installed)
# on the bundled UTM DEM: the same observers (1.7 m above the ground), the
# same radius (10 km) and the DEM's own 90 m grid, targets on the ground.
# Prints each tool's median time and how many cells in reach agree with
# tin_viewshed at the finest level. They are expected to differ where the
# tin (a surface within 2 m of the DEM, linear in each triangle) and the
# raster tools' cell model differ: the agreement is a figure, not a test.
# Usage: scripts/viewshed-compare.sh DATABASE (with the data of
# scripts/load-data.sh and a table terrain(t) built from dem).
set -euo pipefail
cd "$(dirname "$0")/.."
db=${1:?database}
q() { scripts/cluster.sh psql -qAt -d "$db" "$@"; }
dem=tests/data/jacksboro_fault_dem_utm16n.tif
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# observers: the centre, a valley and a ridge of the DEM
observers="746419.5,4052891.3 741210.2,4058003.7 752500.0,4061000.0"
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
have_grass=false
if command -v grass >/dev/null 2>&1; then have_grass=true; fi
if $have_grass; then
  grass -c "$dem" "$tmp/grassdb/loc" -e >/dev/null 2>&1
  grass "$tmp/grassdb/loc/PERMANENT" --exec r.in.gdal input="$dem" output=dem >/dev/null 2>&1
fi
q -c "DROP TABLE IF EXISTS vs_tools; CREATE TABLE vs_tools (tool text, k int, rast raster)"
k=0
printf 'observer | tin_viewshed_ms | gdal_viewshed_ms | agree_gdal_pct | cells'
$have_grass && printf ' | r_viewshed_ms | agree_grass_pct | gdal_agrees_grass_pct'
printf '\n'
for o in $observers; do
  k=$((k + 1))
  x=${o%,*}; y=${o#*,}
  g=()
  for i in 1 2 3; do
    s=$(date +%s%N)
    gdal_viewshed -q -ox "$x" -oy "$y" -oz 1.7 -tz 0 -md 10000 -vv 1 -iv 0 -ov 255 -a_nodata 255 "$dem" "$tmp/gdal$k.tif"
    g+=($(( ($(date +%s%N) - s) / 1000000 )))
  done
  gdal_ms=$(printf '%s\n' "${g[@]}" | median)
  raster2pgsql -s 32616 -a "$tmp/gdal$k.tif" vs_gdal_tmp 2>/dev/null | sed "s/INSERT INTO \"vs_gdal_tmp\" (\"rast\") VALUES (/INSERT INTO vs_tools (tool, k, rast) VALUES ('gdal', $k, /" | q >/dev/null
  grass_cols=""
  if $have_grass; then
    r=()
    for i in 1 2 3; do
      s=$(date +%s%N)
      grass "$tmp/grassdb/loc/PERMANENT" --exec r.viewshed -b --overwrite input=dem output=vs coordinates="$x,$y" observer_elevation=1.7 target_elevation=0 max_distance=10000 >/dev/null 2>&1
      r+=($(( ($(date +%s%N) - s) / 1000000 )))
    done
    grass "$tmp/grassdb/loc/PERMANENT" --exec r.out.gdal input=vs output="$tmp/grass$k.tif" type=Byte nodata=255 >/dev/null 2>&1
    raster2pgsql -s 32616 -a "$tmp/grass$k.tif" vs_gdal_tmp 2>/dev/null | sed "s/INSERT INTO \"vs_gdal_tmp\" (\"rast\") VALUES (/INSERT INTO vs_tools (tool, k, rast) VALUES ('grass', $k, /" | q >/dev/null
    grass_cols=$(printf '%s\n' "${r[@]}" | median)
  fi
  q -F ' | ' <<SQL
SELECT '$x $y', b.median_ms, $gdal_ms,
       round(100.0 * count(*) FILTER (WHERE t.v = g.v) / count(*), 2), count(*)
       $($have_grass && echo ", $grass_cols, round(100.0 * count(*) FILTER (WHERE t.v = r.v AND r.v IS NOT NULL) / count(*) FILTER (WHERE r.v IS NOT NULL), 2), round(100.0 * count(*) FILTER (WHERE g.v = r.v AND r.v IS NOT NULL) / count(*) FILTER (WHERE r.v IS NOT NULL), 2)")
FROM (SELECT tin_viewshed(t, ST_SetSRID(ST_MakePoint($x, $y), 32616), 10000, d.rast) AS vs FROM terrain, dem d) a,
     LATERAL bench('vs', 'SELECT octet_length(_tin_viewshed_ref(t, ST_SetSRID(ST_MakePoint($x, $y), 32616), 10000, d.rast::bytea, 1.7, 0, NULL, false, 0.13)) FROM terrain, dem d', 5) b,
     (SELECT rast FROM vs_tools WHERE tool = 'gdal' AND k = $k) gd,
     $($have_grass && echo "(SELECT rast FROM vs_tools WHERE tool = 'grass' AND k = $k) gr,")
     LATERAL (SELECT (ST_PixelAsCentroids(a.vs, 1, true)).*) c
     CROSS JOIN LATERAL (SELECT c.val AS v) t
     CROSS JOIN LATERAL (SELECT ST_Value(gd.rast, 1, c.geom) AS v) g
     $($have_grass && echo "CROSS JOIN LATERAL (SELECT CASE WHEN ST_Value(gr.rast, 1, c.geom) > 0 THEN 1 WHEN ST_Value(gr.rast, 1, c.geom) = 0 THEN 0 END AS v) r")
GROUP BY b.median_ms;
SQL
done
q -c "DROP TABLE vs_tools"
