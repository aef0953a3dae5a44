#!/usr/bin/env bash
# Load the bundled DEMs into database $1 as tables dem (UTM 16N) and dem_geo.
set -euo pipefail
cd "$(dirname "$0")/.."
db="$1"
{
  raster2pgsql -s 32616 -N -9999 tests/data/jacksboro_fault_dem_utm16n.tif public.dem
  raster2pgsql -s 4326 tests/data/jacksboro_fault_dem.tif public.dem_geo
} 2>/dev/null | scripts/cluster.sh psql -q -d "$db" >/dev/null
