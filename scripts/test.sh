#!/usr/bin/env bash
# The whole test suite: formatting, the core crate's cargo tests on real data
# (no PostgreSQL), #[pg_test]s, the pg_regress suite, and the independent
# property tests.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh

echo "== no module imports one that imports it back"
scripts/python.sh scripts/check-cycles.py src crates/tinmerge-core/src
echo "== cargo fmt --check"
cargo fmt --check
echo "== cargo test -p tinmerge-core (the pure core, real DEMs, no PostgreSQL)"
cargo test --release -p tinmerge-core

echo "== cargo pgrx test (#[pg_test] only: the integration tests ran above in release)"
if [ "$(id -u)" -eq 0 ]; then
  mkdir -p target/pgrx-test && chown postgres target/pgrx-test
  cargo pgrx test pg15 pg::tests:: --runas postgres --pgdata "$PWD/target/pgrx-test/data"
else
  cargo pgrx test pg15 pg::tests::
fi

echo "== install the extension"
scripts/install.sh

echo "== pg_regress"
scripts/cluster.sh stop
rm -rf target/pg
scripts/cluster.sh start
trap 'scripts/cluster.sh stop' EXIT
scripts/cluster.sh psql -q -d postgres -c "CREATE DATABASE tinmerge_regress"
scripts/cluster.sh psql -q -d tinmerge_regress -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh tinmerge_regress
mkdir -p target/regress
tests=$(ls tests/pg_regress/sql/*.sql | xargs -n1 basename | sed 's/\.sql$//' | sort)
/usr/lib/postgresql/15/lib/pgxs/src/test/regress/pg_regress \
  --host="$PWD/target/pg" --port="${TINMERGE_PORT:-28815}" --user=postgres \
  --use-existing --dbname=tinmerge_regress \
  --inputdir=tests/pg_regress --outputdir=target/regress $tests \
  || { cat target/regress/regression.diffs 2>/dev/null | head -200; exit 1; }

echo "== docs/sql-reference.md against pg_proc: every public function, its arguments, defaults and result"
scripts/python.sh tests/docs_signatures.py tinmerge_regress

echo "== shared_preload_libraries: point, area and storage regress tests on a preloaded server"
tests/preload.sh

echo "== browser: the demo page's pictures and 3D views in headless Chromium"
tests/browser.sh

echo "== globe: quantized-mesh tiles decoded by loaders.gl against PostGIS, CesiumJS drawing the served terrain"
tests/globe.sh

echo "== tutorial: every block of docs/tutorial.md, in order"
tests/tutorial.sh

echo "== every SQL block of README.md and docs/sql-reference.md, as written"
tests/doc_examples.sh

echo "== COPY, pg_dump, pg_restore"
tests/dump_restore.sh

echo "== extension upgrade from the previous release"
tests/upgrade.sh

echo "== concurrency: 8 clients, mixed merges, results against a single client"
tests/concurrency.sh

echo "== sharding: 3 clusters, postgres_fdw, merges pushed to the shards, answers against one node"
tests/sharding.sh

echo "== a terrain bigger than one value at test size: 4.5 million pixels as tiles, checked against PostGIS"
tests/big.sh

echo "== hierarchy properties against every pixel (independent oracle: PostGIS + numpy/matplotlib/shapely)"
scripts/python.sh tests/properties/check_hierarchy.py
echo "== point builds between their samples against their Delaunay triangulation (independent oracle: matplotlib's qhull)"
scripts/python.sh tests/properties/check_points_between.py
echo "== coverage-weighted raster statistics against exactextract"
scripts/python.sh tests/properties/check_raster_exactextract.py
echo "== all tests passed"
