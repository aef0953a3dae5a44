#!/usr/bin/env bash
# Progress of long builds (issue 75): one session runs tin_tiles_from_table
# over a table of tiles big enough to take about ten seconds, with
# tinmerge.progress_interval = 1, while a second session reads the view
# tin_progress every half second. Checked: the second session sees the
# first's pid, function and phases, done rising to the total, done never
# past it, and in the phase that builds every tile ("building tiles") the total is the
# number of tiles the table has (counted by PostGIS, the oracle); the
# first session got NOTICE lines in that form; after it ends, no row and
# no file of it is left. Then the same build cancelled (pg_cancel_backend)
# halfway leaves no file either, a tin_from_raster build reports its
# levels (the old engine's over the valid squares, engine 2's over the
# hull), and with tinmerge.progress_interval = 0 no NOTICE comes. Needs
# the running test cluster and tinmerge_regress (table dem).
set -euo pipefail
cd "$(dirname "$0")/.."
out=target/progress
rm -rf "$out"; mkdir -p "$out"
q() { scripts/cluster.sh psql -qAtX -v ON_ERROR_STOP=1 -d tinmerge_regress "$@"; }
# the DEM 8 times finer (bilinear), as 48 x 48 tiles (4 times finer took
# 4 s once build engine 2 built tiles: too short for 3 NOTICE lines at 2 s)
q <<'SQL'
DROP TABLE IF EXISTS progress_tiles;
CREATE TABLE progress_tiles AS
SELECT ST_Tile(ST_Rescale(rast, ST_ScaleX(rast) / 8, ST_ScaleY(rast) / 8, 'Bilinear'), 1, 48, 48) AS rast FROM dem;
SQL
tiles=$(q -c "SELECT count(*) FROM progress_tiles")
echo "progress_tiles: $tiles tiles"

# the build: session A (its pid first), NOTICE lines to $out/a.err
run_a() { # progress_interval, then the build's SQL
  {
    echo "SET tinmerge.progress_interval = $1;"
    echo "SELECT pg_backend_pid();"
    echo "$2"
  } | scripts/cluster.sh psql -qAtX -d tinmerge_regress > "$out/a.out" 2> "$out/a.err"
}
build="SELECT count(*) FROM tin_tiles_from_table('progress_tiles', 0.25, 4);"
run_a 1 "$build" & a=$!
# session B: tin_progress every half second while A runs
: > "$out/seen"
while kill -0 "$a" 2>/dev/null; do
  q -F '|' -c "SELECT pid, function, phase, done, total, unit, percent, time_left IS NOT NULL FROM tin_progress" >> "$out/seen" || true
  sleep 0.5
done
wait "$a"
pid=$(head -1 "$out/a.out")
echo "session A (pid $pid) built $(sed -n 2p "$out/a.out") tiles; session B saw $(wc -l < "$out/seen") rows"
scripts/python.sh - "$out/seen" "$pid" "$tiles" "$out/a.err" <<'PY'
import re, sys
seen, pid, tiles, err = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
rows = [l.rstrip('\n').split('|') for l in open(seen) if l.strip()]
rows = [r for r in rows if r[0] == pid]
assert len(rows) >= 5, f"session B saw {len(rows)} progress rows of session A, not 5 or more"
assert all(r[1] == 'tin_tiles_from_table' and r[5] == 'tiles' for r in rows), rows[:3]
phases = []
for r in rows:
    if not phases or phases[-1] != r[2]:
        phases.append(r[2])
last = {}
for r in rows:
    done, total = int(r[3]), int(r[4])
    assert 0 <= done <= total, f"done {done} of total {total}"
    assert done >= last.get(r[2], 0), f"done went down in {r[2]}: {last.get(r[2])} -> {done}"
    last[r[2]] = done
final = [r for r in rows if r[2] == 'building tiles']
assert final, f"no row of the phase 'building tiles' (phases seen: {phases})"
assert all(int(r[4]) == tiles for r in final), f"the phase 'building tiles' has not the table's {tiles} tiles for total: {final[-1]}"
assert any(r[7] == 't' for r in rows), "no row had a time left"
rising = sum(1 for a, b in zip(final, final[1:]) if int(b[3]) > int(a[3]))
assert rising >= 2, f"done rose {rising} times in the phase 'building tiles'"
notices = [l for l in open(err) if l.startswith('NOTICE:')]
form = re.compile(r"NOTICE:  tin_tiles_from_table: (.+): (\d+) of (\d+) tiles \(\d+ %\), [\d.]+ tiles/s(, .+ left)? \(.+ so far\)$")
assert len(notices) >= 3, f"{len(notices)} NOTICE lines, not 3 or more: {open(err).read()[:500]}"
for n in notices:
    assert form.match(n.rstrip('\n')), f"a NOTICE line not of the form: {n!r}"
print(f"ok: {len(rows)} rows of session A seen in {len(phases)} phases ({', '.join(phases)}), "
      f"'building tiles' {final[0][3]} -> {final[-1][3]} of {tiles} tiles; {len(notices)} NOTICE lines, e.g.")
print("  " + notices[len(notices) // 2].rstrip('\n'))
PY
left=$(q -c "SELECT count(*) FROM _tin_progress() WHERE pid = $pid")
[ "$left" = 0 ] || { echo "progress: session A ended, its progress file is still there"; exit 1; }

# cancelled halfway: no file left
run_a 0 "$build" & a=$!
pid=""
for _ in $(seq 1 120); do
  sleep 0.5
  pid=$(q -c "SELECT pid FROM tin_progress WHERE phase = 'building tiles' AND percent > 20" | head -1)
  [ -n "$pid" ] && break
done
[ -n "$pid" ] || { echo "progress: the second build's phase 'building tiles' was never seen past 20 %"; exit 1; }
q -c "SELECT pg_cancel_backend($pid)" > /dev/null
wait "$a" || true
grep -q "canceling statement due to user request" "$out/a.err" ||
  { echo "progress: the build was not cancelled:"; cat "$out/a.err"; exit 1; }
sleep 0.5
left=$(q -c "SELECT count(*) FROM _tin_progress() WHERE pid = $pid")
[ "$left" = 0 ] || { echo "progress: the cancelled build left its progress file"; exit 1; }
if grep -q '^NOTICE:' "$out/a.err"; then
  echo "progress: NOTICE lines with tinmerge.progress_interval = 0"; exit 1
fi
echo "ok: a build cancelled past 20 % left no progress file; no NOTICE with the interval 0"

# one build of a whole raster reports its levels
run_a 1 "SELECT tin_num_vertices(tin_from_raster(ST_Rescale(rast, ST_ScaleX(rast) / 4, ST_ScaleY(rast) / 4, 'Bilinear'), 0.25, 4)) FROM dem;"
grep -m2 -E '^NOTICE:  tin_from_raster: refining a level parent by parent \([0-9] of [0-9]\): [0-9]+ of [0-9]+ triangles' "$out/a.err" ||
  { echo "progress: tin_from_raster gave no NOTICE of its levels:"; cat "$out/a.err"; exit 1; }
# and so does one built by build engine 2 (over the valid centres' hull):
# its levels as they are refined, then assembled and checked
run_a 1 "SELECT tin_num_vertices(tin_from_raster(ST_Rescale(rast, ST_ScaleX(rast) / 4, ST_ScaleY(rast) / 4, 'Bilinear'), 0.25, 4, fill_gaps => true)) FROM dem;"
grep -m2 -E '^NOTICE:  tin_from_raster: (building level [0-9] of [0-9]: [0-9]+ vertices|(assembling|checking) the levels: [0-9] of [0-9] levels)' "$out/a.err" ||
  { echo "progress: tin_from_raster (engine 2) gave no NOTICE of its levels:"; cat "$out/a.err"; exit 1; }
q -c "DROP TABLE progress_tiles"
echo "progress: all checks passed"
