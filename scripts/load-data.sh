#!/usr/bin/env bash
# Load the bundled DEMs into database $1 as tables dem (UTM 16N) and dem_geo.
set -euo pipefail
cd "$(dirname "$0")/.."
db="$1"
# psql of another cluster (tests/sharding.sh): TINMERGE_PSQL="psql -h ... -p ..."
psqlc() {
  if [ -n "${TINMERGE_PSQL:-}" ]; then $TINMERGE_PSQL -v ON_ERROR_STOP=1 "$@"; else scripts/cluster.sh psql "$@"; fi
}
{
  raster2pgsql -s 32616 -N -9999 tests/data/jacksboro_fault_dem_utm16n.tif public.dem
  raster2pgsql -s 4326 tests/data/jacksboro_fault_dem.tif public.dem_geo
} 2>/dev/null | psqlc -q -d "$db" >/dev/null
# A window of the UTM DEM without nodata (10 pixels in from every side), as
# one raster (dem_window) and as raster2pgsql -t 100x100 tiles (window_tiles):
# the tiled-terrain fixtures (docs/scaling.md).
win=$(mktemp -d)
gdal_translate -q -srcwin 10 10 324 343 tests/data/jacksboro_fault_dem_utm16n.tif "$win/window.tif"
{
  raster2pgsql -s 32616 -N -9999 "$win/window.tif" public.dem_window
  raster2pgsql -s 32616 -N -9999 -t 100x100 "$win/window.tif" public.window_tiles
} 2>/dev/null | psqlc -q -d "$db" >/dev/null
# a third grid for metric measures: the geographic DEM warped to CONUS
# Albers (EPSG:5070) by gdalwarp, bilinear, 97.3 x 88.9 m pixels from the
# fractional origin gdalwarp picks, nodata on the rotated border
gdalwarp -q -t_srs EPSG:5070 -tr 97.3 88.9 -r bilinear -dstnodata -9999 tests/data/jacksboro_fault_dem.tif "$win/albers.tif"
raster2pgsql -s 5070 -N -9999 "$win/albers.tif" public.dem_albers 2>/dev/null | psqlc -q -d "$db" >/dev/null
rm -rf "$win"
# Contour lines every 50 m (gdal_contour), as tables contours (the UTM DEM)
# and contours_geo (the geographic one).
tmp=$(mktemp -d)
contours() { # table, srid, DEM file
  gdal_contour -q -f CSV -lco GEOMETRY=AS_WKT -a elev -i 50 "$3" "$tmp/$1.csv"
  chmod -R a+rX "$tmp"
  psqlc -q -d "$db" >/dev/null <<SQL
CREATE TABLE contours_raw(wkt text, id int, elev float8);
\copy contours_raw FROM '$tmp/$1.csv' CSV HEADER
CREATE TABLE $1 AS
  SELECT id, elev, ST_GeomFromText(wkt, $2)::geometry(LineString, $2) AS geom FROM contours_raw;
DROP TABLE contours_raw;
SQL
}
contours contours 32616 tests/data/jacksboro_fault_dem_utm16n.tif
contours contours_geo 4326 tests/data/jacksboro_fault_dem.tif
# Areas between contours every 50 m (gdal_contour -p: multipolygons with
# holes), as table contour_bands.
gdal_contour -q -p -f CSV -lco GEOMETRY=AS_WKT -amin lo -amax hi -i 50 \
  tests/data/jacksboro_fault_dem_utm16n.tif "$tmp/bands.csv"
chmod -R a+rX "$tmp"
psqlc -q -d "$db" >/dev/null <<SQL
CREATE TABLE bands_raw(wkt text, id int, lo float8, hi float8);
\copy bands_raw FROM '$tmp/bands.csv' CSV HEADER
CREATE TABLE contour_bands AS
  SELECT id, lo, hi, ST_GeomFromText(wkt, 32616)::geometry(MultiPolygon, 32616) AS geom FROM bands_raw;
DROP TABLE bands_raw;
SQL
rm -rf "$tmp"
