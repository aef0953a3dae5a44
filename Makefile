# tinmerge: the two commands are `make demo` and `make test`.
.PHONY: demo test install installcheck package start stop psql bench clean

demo:
	scripts/demo.sh

test:
	scripts/test.sh

install:
	scripts/setup.sh
	scripts/install.sh

# the pg_regress suite and the docs' SQL examples against tinmerge installed
# in the running cluster PGHOST/PGPORT/PGUSER name
installcheck:
	scripts/installcheck.sh

# target/postgresql-15-tinmerge_<version>_amd64.deb (lintian-checked)
package:
	scripts/setup.sh
	scripts/package.sh

start:
	scripts/cluster.sh start

stop:
	scripts/cluster.sh stop

psql:
	scripts/cluster.sh psql -d tinmerge_demo

bench:
	scripts/bench.sh
	scripts/bench-joins.sh
	scripts/bench-build.sh
	scripts/bench-slices.sh
	scripts/bench-big.sh
	scripts/bench-zonal.sh
	scripts/bench-overviews.sh
	scripts/bench-giga.sh
	scripts/bench-area.sh
	scripts/bench-engine.sh

clean:
	scripts/cluster.sh stop
	cargo clean
