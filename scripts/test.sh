#!/usr/bin/env bash
# The whole test suite: formatting, the core crate's cargo tests on real data
# (no PostgreSQL), #[pg_test]s, the pg_regress suite, and the independent
# property tests.
set -euo pipefail
cd "$(dirname "$0")/.."
# each step's wall time, printed as a table at the end
STEP_NAME="setup"
STEP_T0=$SECONDS
TIMES=""
step() {
  TIMES+="$(printf '%6d s  %s' $((SECONDS - STEP_T0)) "$STEP_NAME")"$'\n'
  STEP_NAME="$1"
  STEP_T0=$SECONDS
  echo "== $1"
}
scripts/setup.sh
# tests compare outputs: no progress NOTICE lines however long a statement
# runs (tests/progress.sh sets the interval it tests)
export PGOPTIONS="${PGOPTIONS:-} -c tinmerge.progress_interval=0"

step "no module imports one that imports it back"
scripts/python.sh scripts/check-cycles.py src crates/tinmerge-core/src
step "cargo fmt --check"
cargo fmt --check
step "cargo clippy (every target of both crates, warnings denied; unsafe blocks need a SAFETY comment)"
cargo clippy --workspace --all-targets -- -D warnings
step "cargo doc (both crates, private items too; broken intra-doc links denied)"
RUSTDOCFLAGS="-D warnings -A rustdoc::private_intra_doc_links" \
  cargo doc --workspace --no-deps --document-private-items
step "cargo test -p tinmerge-core (the pure core, real DEMs, no PostgreSQL)"
cargo test --release -p tinmerge-core

step "cargo pgrx test (#[pg_test] only: the integration tests ran above in release)"
if [ "$(id -u)" -eq 0 ]; then
  mkdir -p target/pgrx-test && chown postgres target/pgrx-test
  cargo pgrx test pg15 pg::tests:: --runas postgres --pgdata "$PWD/target/pgrx-test/data"
else
  # pgrx's test framework installs the extension into the system PostgreSQL
  # (/usr/share/postgresql, /usr/lib/postgresql) and has no --sudo, so as a
  # user this step runs as root through sudo, with the user's toolchain and
  # its test server as postgres (its data outside the home, which postgres
  # may not enter); what root wrote is given back to the user afterwards
  pgdata="/tmp/tinmerge-pgrx-test-$(id -u)"
  sudo rm -rf "$pgdata"
  sudo install -d -o postgres "$pgdata"
  rc=0
  sudo env PATH="$PATH" HOME="$HOME" \
    CARGO_HOME="${CARGO_HOME:-$HOME/.cargo}" RUSTUP_HOME="${RUSTUP_HOME:-$HOME/.rustup}" \
    PGRX_HOME="${PGRX_HOME:-$HOME/.pgrx}" ${CARGO_TARGET_DIR:+CARGO_TARGET_DIR="$CARGO_TARGET_DIR"} \
    cargo pgrx test pg15 pg::tests:: --runas postgres --pgdata "$pgdata/data" || rc=$?
  sudo find target "${CARGO_TARGET_DIR:-target}" "${CARGO_HOME:-$HOME/.cargo}" "${PGRX_HOME:-$HOME/.pgrx}" \
    -user root -exec chown "$(id -u):$(id -g)" {} +
  sudo rm -rf "$pgdata"
  [ "$rc" -eq 0 ] || exit "$rc"
fi

step "the Debian package: release build staged, .deb built and checked by lintian, installed with apt-get in place of any development install"
scripts/stage.sh
TINMERGE_PACKAGE_NO_BUILD=1 scripts/package.sh
tests/package.sh install

step "pg_regress against the installed package, as an installcheck (two halves at once, each in its own database)"
scripts/cluster.sh stop
rm -rf target/pg
scripts/cluster.sh start
trap 'scripts/cluster.sh stop' EXIT
# The suite in two halves of about equal time, run at the same time on two
# databases (each with 00_setup and the same data), so the queries of one
# half use the core the other's single-threaded queries leave idle: the
# five longest tests and overviews (after tiles: it constrains
# window_tiles) on tinmerge_regress2, every other test on tinmerge_regress
# (the later steps read its tables). On 2026-12-07 the step took 894 s
# with overviews in the second half; by the tests' times then, about
# 770 s and 750 s a half now.
first="tiles boundary overlay between_samples breaklines overviews"
for db in tinmerge_regress tinmerge_regress2; do
  scripts/cluster.sh psql -q -d postgres -c "CREATE DATABASE $db"
  scripts/cluster.sh psql -q -d $db -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
  scripts/load-data.sh $db
done
all=$(ls tests/pg_regress/sql/*.sql | xargs -n1 basename | sed 's/\.sql$//' | grep -v '^00_setup$' | sort)
second=$(for t in $all; do case " $first " in *" $t "*) ;; *) echo "$t" ;; esac; done)
regress() { # database, output directory, tests
  local db=$1 out=$2; shift 2
  mkdir -p "$out"
  /usr/lib/postgresql/15/lib/pgxs/src/test/regress/pg_regress \
    --host="$PWD/target/pg" --port="${TINMERGE_PORT:-28815}" --user=postgres \
    --use-existing --dbname="$db" \
    --inputdir=tests/pg_regress --outputdir="$out" 00_setup "$@" > "$out/summary.txt" 2>&1
}
rm -rf target/regress target/regress2
rc1=0 rc2=0
regress tinmerge_regress2 target/regress2 $first & p1=$!
regress tinmerge_regress target/regress $second & p2=$!
wait $p1 || rc1=$?
wait $p2 || rc2=$?
cat target/regress2/summary.txt target/regress/summary.txt
if [ "$rc1" -ne 0 ] || [ "$rc2" -ne 0 ]; then
  cat target/regress/regression.diffs target/regress2/regression.diffs 2>/dev/null | head -200
  exit 1
fi

step "docs/sql-reference.md against pg_proc: every public function, its arguments, defaults and result"
scripts/python.sh tests/docs_signatures.py tinmerge_regress

step "every name the docs give in backticks (paths, SQL functions, settings, Rust paths, other names) exists (tests/docs_names.py)"
scripts/python.sh tests/docs_names.py tinmerge_regress

step "every public function near an oracle in a test file (tests/function_coverage.py)"
scripts/python.sh tests/function_coverage.py tinmerge_regress

step "shared_preload_libraries: point, area and storage regress tests on a preloaded server"
tests/preload.sh

step "two lanes at once: the pictures and globes in Chromium | tutorial, doc examples, dump/restore, upgrade, concurrency, live install, progress, sharding, big terrain"
# Chromium's software rendering beside the SQL tests, which leave a core
# idle; each test has its own databases, ports and files. A lane stops at
# its first failure; both logs are printed, then the failures.
lane_sh() { # log file, then "description|command" in order
  local log=$1 c; shift
  for c in "$@"; do
    echo "== ${c%%|*}"
    local t0=$SECONDS
    ${c#*|} || { echo "FAILED: ${c%%|*}"; return 1; }
    echo "   ($((SECONDS - t0)) s)"
  done > "$log" 2>&1
}
lane_sh target/lane-1.log \
  "browser: the demo page's pictures and 3D views in headless Chromium|tests/browser.sh" \
  "globe: quantized-mesh tiles decoded by loaders.gl against PostGIS, CesiumJS drawing the served terrain|tests/globe.sh" & l1=$!
lane_sh target/lane-2.log \
  "tutorial: every block of docs/tutorial.md, in order|tests/tutorial.sh" \
  "every SQL block of README.md and docs/sql-reference.md, as written|tests/doc_examples.sh" \
  "COPY, pg_dump, pg_restore|tests/dump_restore.sh" \
  "extension upgrade from the previous release|tests/upgrade.sh" \
  "concurrency: 8 clients, mixed merges, results against a single client|tests/concurrency.sh" \
  "live install: a session keeps answering through two installs of the extension (files renamed into place)|tests/live_install.sh" \
  "progress: a build's progress read from a second session, NOTICE lines, cancel|tests/progress.sh" \
  "sharding: 3 clusters, postgres_fdw, merges pushed to the shards, answers against one node|tests/sharding.sh" \
  "a terrain bigger than one value at test size: 4.5 million pixels as tiles, checked against PostGIS|tests/big.sh" & l2=$!
r1=0 r2=0
wait $l1 || r1=$?
wait $l2 || r2=$?
cat target/lane-1.log target/lane-2.log
[ "$r1" -eq 0 ] && [ "$r2" -eq 0 ] || { echo "a test of the two lanes failed (above)"; exit 1; }

step "tinmerge.max_memory from outside: the DEM 8x finer builds under the defaults, a build past the limit stopped (backend VmHWM)"
tests/memory.sh

step "property checks in two lanes at once (independent oracles: PostGIS, numpy/matplotlib/shapely, matplotlib's qhull, exactextract)"
# hierarchy properties against every pixel, then coverage-weighted raster
# statistics against exactextract; beside them, point builds between their
# samples against their Delaunay triangulation (qhull), then 100,000 sight
# lines against an oracle from tin_triangles. Each check makes and drops
# tables of its own names in tinmerge_regress.
lane() { # log file, then the checks in order
  local log=$1 c; shift
  for c in "$@"; do
    echo "== $c"
    scripts/python.sh "tests/properties/$c" || return 1
  done > "$log" 2>&1
}
lane target/properties-1.log check_hierarchy.py check_raster_exactextract.py & l1=$!
lane target/properties-2.log check_points_between.py check_line_of_sight.py & l2=$!
r1=0 r2=0
wait $l1 || r1=$?
wait $l2 || r2=$?
cat target/properties-1.log target/properties-2.log
[ "$r1" -eq 0 ] && [ "$r2" -eq 0 ] || { echo "a property check failed (above)"; exit 1; }

step "the package removed with apt-get: no tinmerge file left"
scripts/cluster.sh stop
trap - EXIT
tests/package.sh remove
step "done"
echo "== step times"
printf '%s' "$TIMES"
echo "total: $SECONDS s"
echo "== all tests passed"
