#!/usr/bin/env bash
# Cesium quantized-mesh tiles from SQL, seen by what users run: the tiles
# decoded by loaders.gl and checked against PostGIS
# (tests/properties/check_quantized_mesh.mjs), then CesiumJS in headless
# Chromium drawing the terrain served by web/terrain-server.mjs and
# sampling heights (tests/globe.mjs). Needs the running test cluster after
# pg_regress (its terrain and dem_geo tables) and web/node_modules
# (scripts/setup.sh: npm ci --prefix web).
set -euo pipefail
cd "$(dirname "$0")/.."
[ -d web/node_modules/cesium ] || { echo "globe test: web/node_modules is missing (scripts/setup.sh runs npm ci --prefix web)"; exit 1; }
export PGHOST="$PWD/target/pg" PGPORT="${TINMERGE_PORT:-28815}" PGUSER=postgres PGDATABASE="${TINMERGE_DB:-tinmerge_regress}"
node tests/properties/check_quantized_mesh.mjs
CHROMIUM="$(command -v chromium || command -v chromium-browser)" node tests/globe.mjs
