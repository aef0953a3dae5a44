#!/usr/bin/env bash
# A billion pixels (issue 48): scripts/bench-big.sh on the bundled DEM 89x
# finer with fractal detail (scripts/make-big-dem.py 89: 30,616 x 32,307 =
# 989 million pixels of 1.01 m, the source's nodata holes kept), loaded with
# raster2pgsql -t 256x256 and built with tin_tiles_from_table, first in one
# backend, then in 2 slices on 2 backends at once (byte-identical, checked),
# then with PostGIS's overviews (raster2pgsql -l 4,16,64) as one pyramid by
# tin_overviews; then one quantized-mesh tile at zoom 0, 8 and the finest,
# from the tiles alone and from the pyramid, and 10^6 points,
# 10^3 lines and 10^3 polygons against PostGIS, cold and warm. Prints its
# tables and the disk it used. In make bench only (hours on 2 cores).
#
# What it needs (2026-11-29, this 2-core 24 GB machine): docs/performance.md.
# usage: scripts/bench-giga.sh [FACTOR [SLICES]]
set -euo pipefail
cd "$(dirname "$0")/.."
FACTOR="${1:-89}"
export TINMERGE_BIG_SLICES="${2:-2}" TINMERGE_BIG_SERVE=1 TINMERGE_BIG_OVERVIEWS=1
t0=$(date +%s)
rc=0
scripts/bench-big.sh "$FACTOR" 1000000 1000 1000 || rc=$?
echo "== disk: the generated raster and the cluster after the run"
du -sh "target/big/dem$FACTOR.raw" target/pg 2>/dev/null || true
scripts/cluster.sh psql -qAt -d "${TINMERGE_BIG_DB:-tinmerge_big}" -F ' | ' -c "SELECT 'database', pg_size_pretty(pg_database_size(current_database()))"
echo "== bench-giga: $(( $(date +%s) - t0 )) s in all"
exit "$rc"
