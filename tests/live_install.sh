#!/usr/bin/env bash
# Installing tinmerge on a live server crashes nothing (issue 75): one
# session with the library loaded keeps running merges (point, line, area,
# raster, build) while scripts/install.sh installs the packaged files again
# (every file renamed into place, a new inode, so the session keeps the old
# mapping); then that session still answers, a new session loads the new
# file, and the server log has no "terminated by signal" since the start.
# The same install by a plain copy over the library (as `cargo pgrx
# install` does) truncates the mapped file and brought the cluster down
# with SIGBUS (signal 7): tried by hand, not in the suite (it drops every
# session of the test cluster). Needs the running test cluster and the
# tinmerge_regress database (tables terrain and dem from pg_regress), and
# a package from scripts/install.sh (target/package).
set -euo pipefail
cd "$(dirname "$0")/.."
LOG="$PWD/target/pg/log"
q() { scripts/cluster.sh psql -qAt -v ON_ERROR_STOP=1 -d tinmerge_regress "$@"; }
[ -d target/package ] || { echo "live_install: no target/package (scripts/install.sh makes it)" >&2; exit 1; }
start_bytes=$(stat -c %s "$LOG")
lib="$(/usr/lib/postgresql/15/bin/pg_config --pkglibdir)/tinmerge.so"
inode_before=$(stat -c %i "$lib")

# the session: 400 rounds of five merges and a small build, a short sleep
# between, as one psql connection (one backend, the library loaded once)
rounds=400
{
  echo "SET client_min_messages = warning;"
  echo "SELECT pg_backend_pid();"
  for i in $(seq 1 "$rounds"); do
    cat <<SQL
SELECT 'round $i', round(sum(tin_height(t, ST_SetSRID(ST_MakePoint(ST_XMin(e) + (ST_XMax(e) - ST_XMin(e)) * k / 50.0, ST_YMin(e) + (ST_YMax(e) - ST_YMin(e)) * ((k * 7) % 50) / 50.0), 32616)))::numeric, 6)
  FROM terrain, tin_envelope(t) e, generate_series(1, 49) k;
SELECT round(sum(length3d)::numeric, 6) FROM terrain, tin_envelope(t) e,
  tin_line_segments(t, ST_SetSRID(ST_MakeLine(ST_MakePoint(ST_XMin(e), ST_YMin(e)), ST_MakePoint(ST_XMax(e), ST_YMax(e))), 32616), 2);
SELECT round(s.area3d::numeric, 3) FROM terrain, tin_envelope(t) e, tin_area_stats(t, ST_Buffer(ST_Centroid(e), (ST_XMax(e) - ST_XMin(e)) / 5, 16)) s;
SELECT count(*) FROM terrain, dem, tin_raster_stats(t, rast, 1) s;
SELECT tin_num_triangles(tin_from_raster(ST_Clip(rast, ST_Buffer(ST_Centroid(ST_Envelope(rast)), 600)), 8.0, 2), 1) FROM dem;
SELECT pg_sleep(0.02);
SQL
  done
  echo "SELECT 'session done';"
} > target/live_install.sql
q -f target/live_install.sql > target/live_install.out 2>&1 & session=$!

# let the session get going, then install while it runs (twice, a second
# apart, so one lands while a query is in flight whatever the timing)
sleep 3
for k in 1 2; do
  if [ "${TINMERGE_LIVE_INSTALL_BY_COPY:-}" = 1 ]; then
    # the counter-test: the library copied over in place, as cp and
    # `cargo pgrx install` do (this test must fail then)
    cp target/package"$lib" "$lib"
  else
    TINMERGE_INSTALL_NO_BUILD=1 scripts/install.sh > /dev/null
  fi
  sleep 1
done
inode_after=$(stat -c %i "$lib")
rc=0
wait $session || rc=$?
if [ "$rc" -ne 0 ] || ! grep -q "session done" target/live_install.out; then
  echo "live_install: the session running during the install failed (exit $rc):" >&2
  tail -5 target/live_install.out >&2
  exit 1
fi
answered=$(grep -c "^round " target/live_install.out)
# a new session loads the file now in place
new=$(q -c "SELECT tin_num_triangles(t, 0) > 0 FROM terrain")
crashes=$(tail -c +"$((start_bytes + 1))" "$LOG" | grep -c "terminated by signal" || true)
echo "live install: $answered of $rounds rounds answered by the session running through two installs;"
echo "  library inode $inode_before -> $inode_after (renamed into place); a new session: $new;"
echo "  'terminated by signal' in the server log since the start: $crashes"
[ "$answered" -eq "$rounds" ] && [ "$new" = t ] && [ "$crashes" -eq 0 ] && [ "$inode_before" != "$inode_after" ] || {
  echo "live_install: FAILED" >&2
  exit 1
}
echo "== live install crashed nothing"
