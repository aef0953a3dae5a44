#!/usr/bin/env bash
# Runs docs/tutorial.md: every ```sh and ```sql block, in order, against a
# fresh database on the running test cluster (libpq environment variables,
# as the tutorial says), stopping at the first error. Output goes to
# target/tutorial.log; the test fails if any block fails, so the tutorial
# cannot drift from the code.
set -euo pipefail
cd "$(dirname "$0")/.."
db=tinmerge_tutorial
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
export PGHOST="$PWD/target/pg" PGPORT="${TINMERGE_PORT:-28815}" PGUSER=postgres PGDATABASE=$db
log=target/tutorial.log
: > "$log"
blocks=$(mktemp -d)
python3 - docs/tutorial.md "$blocks" <<'PY'
import re, sys
src, out = sys.argv[1], sys.argv[2]
text = open(src).read()
n = 0
for m in re.finditer(r"^```(sh|sql)\n(.*?)^```", text, re.S | re.M):
    n += 1
    open(f"{out}/{n:03d}.{m.group(1)}", "w").write(m.group(2))
print(f"{n} blocks")
PY
count=0
for f in "$blocks"/*; do
  count=$((count + 1))
  echo "== block $(basename "$f")" >> "$log"
  case "$f" in
    *.sql) psql -X -v ON_ERROR_STOP=1 -f "$f" >> "$log" 2>&1 || { echo "tutorial: SQL block $(basename "$f") failed:"; cat "$f"; tail -20 "$log"; exit 1; } ;;
    *.sh) bash -euo pipefail "$f" >> "$log" 2>&1 || { echo "tutorial: shell block $(basename "$f") failed:"; cat "$f"; tail -20 "$log"; exit 1; } ;;
  esac
done
rm -rf "$blocks"
# the clean-up at the end left nothing of the tutorial behind
left=$(psql -XAtc "SELECT count(*) FROM pg_class WHERE relname LIKE 'tut\_%' AND relkind IN ('r', 'v')")
[ "$left" = 0 ] || { echo "tutorial: $left tables/views left after the clean-up"; exit 1; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE $db"
echo "tutorial: $count blocks of docs/tutorial.md ran (output in $log)"
