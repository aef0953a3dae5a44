#!/usr/bin/env bash
# make installcheck: the pg_regress suite and every SQL example of
# README.md and docs/sql-reference.md against tinmerge as installed in a
# running cluster, the one libpq's PGHOST, PGPORT and PGUSER name (as
# PGXS's installcheck does; the user must be able to create databases and
# extensions). Each run makes its own databases (tinmerge_installcheck and
# tinmerge_examples, from the bundled DEMs) and drops them after; the
# outputs are under target/installcheck/.
# e.g. PGHOST=/var/run/postgresql PGUSER=postgres make installcheck
set -euo pipefail
cd "$(dirname "$0")/.."
db=tinmerge_installcheck
P=(psql -X -q -v ON_ERROR_STOP=1)
export TINMERGE_PSQL="psql -X"
# outputs are compared: no progress NOTICE lines from a slow statement
export PGOPTIONS="${PGOPTIONS:-} -c tinmerge.progress_interval=0"
echo "== installcheck against ${PGHOST:-the default host}:${PGPORT:-5432} as ${PGUSER:-$(id -un)}: tinmerge $("${P[@]}" -Atd postgres -c "SELECT default_version FROM pg_available_extensions WHERE name = 'tinmerge'")"
"${P[@]}" -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
trap '"${P[@]}" -d postgres -c "DROP DATABASE IF EXISTS $db" -c "DROP DATABASE IF EXISTS tinmerge_examples" >/dev/null 2>&1 || true' EXIT
"${P[@]}" -d "$db" -c "SET client_min_messages = warning" -c "CREATE EXTENSION tinmerge CASCADE"
scripts/load-data.sh "$db"
out=target/installcheck
rm -rf "$out"; mkdir -p "$out"
tests=$(ls tests/pg_regress/sql/*.sql | xargs -n1 basename | sed 's/\.sql$//' | grep -v '^00_setup$' | sort)
rc=0
/usr/lib/postgresql/15/lib/pgxs/src/test/regress/pg_regress \
  --use-existing --dbname="$db" --inputdir=tests/pg_regress --outputdir="$out" \
  00_setup $tests || rc=$?
if [ "$rc" -ne 0 ]; then
  head -200 "$out/regression.diffs" 2>/dev/null || true
  exit "$rc"
fi
echo "== the SQL examples of README.md and docs/sql-reference.md"
tests/doc_examples.sh
echo "== installcheck passed"
