#!/usr/bin/env bash
# Build engine 2 (issue 74) in the core, beside the build it is to replace
# and pydelatin in the same run: `cargo bench --bench engine` (both
# bundled DEMs, 2 m and 5 m, one level and five; wall time, finest
# triangles and vertices, peak heap a pixel), then
# scripts/bench-delatin.py (pydelatin 0.4, one level, error at the pixel
# centres only, on the geographic DEM, which has no nodata); then both
# again on terraces (each pixel made 8 x 8 pixels). Not a test:
# timings are noisy.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
echo "## engine 2 and the old engine ($(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores)"
cargo bench -q -p tinmerge-core --bench engine 2>/dev/null | grep '^|'
echo
echo "## pydelatin"
scripts/python.sh scripts/bench-delatin.py tests/data/jacksboro_fault_dem.tif
echo
echo "## engine 2 and pydelatin on terraces (each pixel 8 x 8 pixels: the UTM DEM at 11.25 m, 7.56 M valid pixels), 2 m, one run each"
TERRACES=8 cargo bench -q -p tinmerge-core --bench engine 2>/dev/null | grep '^|'
echo
scripts/python.sh scripts/bench-delatin.py tests/data/jacksboro_fault_dem.tif 8
