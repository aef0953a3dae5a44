#!/usr/bin/env bash
# Build tinmerge (release) and stage the files an install puts in the
# system PostgreSQL 15 under target/package/<their path>: the library, the
# control file, this release's install script (what `cargo pgrx package`
# makes) and the install and upgrade scripts of earlier releases
# (sql/versions/), so CREATE EXTENSION tinmerge VERSION '<old>' and ALTER
# EXTENSION tinmerge UPDATE work. What scripts/install.sh installs and
# scripts/package.sh puts in the .deb. TINMERGE_FEATURES=bench adds the
# benchmark-only SQL entry points (`make bench` does; never a package).
set -euo pipefail
cd "$(dirname "$0")/.."
PG_CONFIG=/usr/lib/postgresql/15/bin/pg_config
OUT="$PWD/target/package"
rm -rf "$OUT"
cargo pgrx package --pg-config "$PG_CONFIG" --out-dir "$OUT" \
  ${TINMERGE_FEATURES:+--features "$TINMERGE_FEATURES"}
ext="$OUT$("$PG_CONFIG" --sharedir)/extension"
install -m 644 sql/versions/tinmerge--*.sql "$ext/"
echo "staged $(find "$OUT" -type f | wc -l) files in $OUT"
