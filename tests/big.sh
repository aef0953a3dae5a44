#!/usr/bin/env bash
# The large-terrain benchmark at test size: the bundled DEM 6x finer with
# fractal detail (2,064 x 2,178 = 4.5 million pixels of 15 m, the source's
# nodata holes kept), loaded with raster2pgsql -t 256x256 and built with
# tin_tiles_from_table; fails when a check against PostGIS fails (sampled
# pixel centres within the tolerance, seam points agreeing, line pieces
# keeping their planar length inside the domains) or when the tiles differ,
# bit for bit, from tin_tiles on the raster as one value, or when the
# pyramid tin_overviews builds with PostGIS's overviews (raster2pgsql -l
# 4,16,64) differs in its table's layer from the tiles. Timings print but
# are not checked. Needs the running test cluster and the installed extension.
set -euo pipefail
cd "$(dirname "$0")/.."
TINMERGE_BIG_WHOLE=1 TINMERGE_BIG_SERVE=1 TINMERGE_BIG_OVERVIEWS=1 scripts/bench-big.sh 6 20000 50 50
