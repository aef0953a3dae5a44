#!/usr/bin/env bash
# Installs what tinmerge needs, only when missing: Debian packages,
# cargo-pgrx 0.18.0, the pgrx PostgreSQL 15 configuration, Python test libs
# (in the project's own virtualenv, target/venv: Debian 12's python3
# refuses pip installs, PEP 668). Works as root (CI) and as a user with sudo.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
PG_CONFIG=/usr/lib/postgresql/15/bin/pg_config
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"

# Rust: the build needs the rust-version of Cargo.toml or newer
need=$(sed -n 's/^rust-version = "\(.*\)"/\1/p' "$root/Cargo.toml" | head -1)
rust_hint="install Rust $need or newer with rustup (https://rustup.rs: curl --proto '=https' -sSf https://sh.rustup.rs | sh), then open a new shell"
if ! command -v cargo >/dev/null || ! command -v rustc >/dev/null; then
  echo "tinmerge needs Rust $need or newer, and cargo is not on PATH: $rust_hint" >&2
  exit 1
fi
have=$(rustc --version | sed -n 's/^rustc \([0-9][0-9.]*\).*/\1/p')
if [ "$(printf '%s\n%s\n' "$need" "$have" | sort -V | head -1)" != "$need" ]; then
  echo "tinmerge needs Rust $need or newer, this is rustc $have: $rust_hint (rustup update)" >&2
  exit 1
fi

pkgs="postgresql-15 postgresql-server-dev-15 postgresql-15-postgis-3 postgresql-15-pointcloud postgis libclang-dev clang sudo gdal-bin chromium python3-venv"
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
# benchmark (exactextract: the coverage-weighted oracle for raster stats),
# in target/venv from Debian's python3 (scripts/python.sh runs it)
venv="$root/target/venv"
if ! "$venv/bin/python3" -c "import numpy, matplotlib, shapely, exactextract, pydelatin, tifffile" 2>/dev/null; then
  echo "== installing Python test libraries into target/venv"
  base=/usr/bin/python3
  [ -x "$base" ] || base=python3
  "$base" -m venv "$venv"
  "$venv/bin/python3" -m pip install -q --disable-pip-version-check numpy matplotlib shapely exactextract pydelatin tifffile
fi
