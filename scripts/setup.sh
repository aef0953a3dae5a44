#!/usr/bin/env bash
# Installs what tinmerge needs, only when missing: Debian packages,
# cargo-pgrx 0.18.0, the pgrx PostgreSQL 15 configuration, Python test libs.
# Works as root (CI) and as a user with sudo.
set -euo pipefail
PG_CONFIG=/usr/lib/postgresql/15/bin/pg_config
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"

pkgs="postgresql-15 postgresql-server-dev-15 postgresql-15-postgis-3 postgresql-15-pointcloud postgis libclang-dev clang sudo gdal-bin chromium"
missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "== installing Debian packages:$missing"
  $SUDO apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing
fi

if ! cargo pgrx --version 2>/dev/null | grep -q "0.18.0"; then
  echo "== installing cargo-pgrx 0.18.0 (about 5 minutes)"
  cargo install --locked cargo-pgrx --version =0.18.0
fi

if ! grep -qs "pg15" "${PGRX_HOME:-$HOME/.pgrx}/config.toml"; then
  echo "== cargo pgrx init (uses the system PostgreSQL 15, downloads nothing)"
  cargo pgrx init --pg15 "$PG_CONFIG"
fi

# The web pages' JavaScript (CesiumJS, node-postgres, loaders.gl,
# puppeteer-core), pinned by web/package-lock.json, from the npm registry
web="$(cd "$(dirname "$0")/.." && pwd)/web"
if [ ! -d "$web/node_modules/cesium" ] || [ "$web/package-lock.json" -nt "$web/node_modules/.package-lock.json" ]; then
  command -v npm >/dev/null || $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nodejs npm
  echo "== npm ci --prefix web"
  npm ci --prefix "$web" --no-audit --no-fund --loglevel=error
fi

# Python libraries used by the independent property tests and the
# benchmark (exactextract: the coverage-weighted oracle for raster stats)
if ! python3 -c "import numpy, matplotlib, shapely, exactextract" 2>/dev/null; then
  echo "== installing Python test libraries"
  python3 -m pip install -q numpy matplotlib shapely exactextract
fi
