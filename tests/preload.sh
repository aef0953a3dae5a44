#!/usr/bin/env bash
# tinmerge in shared_preload_libraries (docs/sql-reference.md, Settings):
# the postmaster loads the library and runs _PG_init once, every backend
# inherits it. Restarts the running test cluster preloaded, runs the
# pg_regress tests of the point and area merges and of sliced reads against
# their expected outputs (the same files as the plain run) in a database of
# their own, then restores the setting. Needs the running test cluster.
set -euo pipefail
cd "$(dirname "$0")/.."
q() { scripts/cluster.sh psql -qAtX -v ON_ERROR_STOP=1 "$@"; }
restart() { scripts/cluster.sh stop; scripts/cluster.sh start >/dev/null; }
q -d postgres -c "ALTER SYSTEM SET shared_preload_libraries = 'tinmerge'"
trap 'q -d postgres -c "ALTER SYSTEM RESET shared_preload_libraries"; restart' EXIT
restart
[ "$(q -d postgres -c "SHOW shared_preload_libraries")" = "tinmerge" ] \
  || { echo "tinmerge is not preloaded"; exit 1; }
# the settings exist before any tinmerge call: _PG_init ran in the postmaster
q -d postgres -c "SELECT current_setting('tinmerge.cache_size'), current_setting('tinmerge.threads')::int > 0" >/dev/null
q -d postgres -c "DROP DATABASE IF EXISTS tinmerge_preload" -c "CREATE DATABASE tinmerge_preload"
q -d tinmerge_preload -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh tinmerge_preload >/dev/null
mkdir -p target/regress-preload
/usr/lib/postgresql/15/lib/pgxs/src/test/regress/pg_regress \
  --host="$PWD/target/pg" --port="${TINMERGE_PORT:-28815}" --user=postgres \
  --use-existing --dbname=tinmerge_preload \
  --inputdir=tests/pg_regress --outputdir=target/regress-preload 00_setup point area storage \
  || { cat target/regress-preload/regression.diffs 2>/dev/null | head -100; exit 1; }
echo "preloaded: point, area and storage regress tests pass"
