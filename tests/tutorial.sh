#!/usr/bin/env bash
# Runs docs/tutorial.md: every ```sh and ```sql block, in order, against a
# fresh database on the running test cluster (libpq environment variables,
# as the tutorial says), stopping at the first error, and compares each
# block's output (stdout) with tests/tutorial/NNN.out, so neither the
# tutorial nor the answers it shows can drift from the code. Everything
# (stderr too) also goes to target/tutorial.log.
#
#   tests/tutorial.sh            run and compare
#   tests/tutorial.sh --accept   run and write the expected files (after
#                                editing the tutorial: review the git diff)
set -euo pipefail
cd "$(dirname "$0")/.."
db=tinmerge_tutorial
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
export PGHOST="$PWD/target/pg" PGPORT="${TINMERGE_PORT:-28815}" PGUSER=postgres PGDATABASE=$db
log=target/tutorial.log
: > "$log"
accept=false
[ "${1:-}" = "--accept" ] && accept=true
expected=tests/tutorial
out=target/tutorial
rm -rf "$out" && mkdir -p "$out" "$expected"
blocks=$(mktemp -d)
scripts/python.sh - docs/tutorial.md "$blocks" <<'PY'
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
failed=0
for f in "$blocks"/*; do
  count=$((count + 1))
  b=$(basename "$f"); n=${b%.*}
  echo "== block $b" >> "$log"
  case "$f" in
    *.sql) run=(psql -X -v ON_ERROR_STOP=1) ;;
    *.sh) run=(bash -euo pipefail) ;;
  esac
  # the block on stdin, so messages name <stdin>, not a temporary path
  "${run[@]}" < "$f" > "$out/$n.out" 2> "$out/$n.err" || {
    cat "$out/$n.out" "$out/$n.err" >> "$log"
    echo "tutorial: block $b failed:"; cat "$f"; tail -20 "$out/$n.err"; exit 1; }
  cat "$out/$n.out" "$out/$n.err" >> "$log"
  if $accept; then
    cp "$out/$n.out" "$expected/$n.out"
  elif [ ! -f "$expected/$n.out" ]; then
    echo "tutorial: no expected output $expected/$n.out for block $b (tests/tutorial.sh --accept writes it)"; failed=1
  elif ! diff -u "$expected/$n.out" "$out/$n.out" > "$out/$n.diff"; then
    echo "tutorial: block $b gave a different output:"; cat "$f"; cat "$out/$n.diff"; failed=1
  fi
done
# an expected file for a block the tutorial no longer has is stale
for e in "$expected"/*.out; do
  n=$(basename "$e" .out)
  if [ ! -f "$out/$n.out" ]; then
    if $accept; then rm "$e"; else echo "tutorial: $e has no block (the tutorial has $count)"; failed=1; fi
  fi
done
[ "$failed" = 0 ] || exit 1
rm -rf "$blocks"
# the clean-up at the end left nothing of the tutorial behind
left=$(psql -XAtc "SELECT count(*) FROM pg_class WHERE relname LIKE 'tut\_%' AND relkind IN ('r', 'v')")
[ "$left" = 0 ] || { echo "tutorial: $left tables/views left after the clean-up"; exit 1; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE $db"
echo "tutorial: $count blocks of docs/tutorial.md ran, every output as in $expected/ (log in $log)"
