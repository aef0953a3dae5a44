#!/usr/bin/env bash
# Build (release) and install tinmerge into the system PostgreSQL 15
# (as root directly, otherwise through sudo), with the install scripts of
# earlier releases and the upgrade scripts from them (sql/versions/), so
# CREATE EXTENSION tinmerge VERSION '<old>' and ALTER EXTENSION tinmerge
# UPDATE work. TINMERGE_FEATURES=bench adds the benchmark-only SQL entry
# points (`make bench` does; `make install` never).
set -euo pipefail
cd "$(dirname "$0")/.."
PG_CONFIG=/usr/lib/postgresql/15/bin/pg_config
SUDO=""
if [ "$(id -u)" -eq 0 ]; then
  cargo pgrx install --release --pg-config "$PG_CONFIG" ${TINMERGE_FEATURES:+--features "$TINMERGE_FEATURES"}
else
  SUDO="sudo"
  cargo pgrx install --release --sudo --pg-config "$PG_CONFIG" ${TINMERGE_FEATURES:+--features "$TINMERGE_FEATURES"}
fi
$SUDO install -m 644 sql/versions/tinmerge--*.sql "$("$PG_CONFIG" --sharedir)/extension/"
