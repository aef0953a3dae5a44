#!/usr/bin/env bash
# A throw-away PostgreSQL 15 cluster under target/pg (run as `postgres` when
# we are root, since PostgreSQL refuses to run as root).
# usage: scripts/cluster.sh start|stop|psql [args]
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=/usr/lib/postgresql/15/bin
DIR="$PWD/target/pg"
DATA="$DIR/data"
PORT="${TINMERGE_PORT:-28815}"
export PGHOST="$DIR" PGPORT="$PORT"
as_pg() {
  if [ "$(id -u)" -eq 0 ]; then runuser -u postgres -- "$@"; else "$@"; fi
}
case "${1:-}" in
  start)
    mkdir -p "$DIR"
    [ "$(id -u)" -eq 0 ] && chown postgres "$DIR"
    if [ ! -f "$DATA/PG_VERSION" ]; then
      as_pg "$BIN/initdb" -D "$DATA" -A trust -U postgres --no-sync >/dev/null
    fi
    if ! as_pg "$BIN/pg_ctl" -D "$DATA" status >/dev/null 2>&1; then
      as_pg "$BIN/pg_ctl" -D "$DATA" -l "$DIR/log" -w \
        -o "-p $PORT -k $DIR -c listen_addresses='' -c fsync=off" start >/dev/null
    fi
    echo "PostgreSQL running: psql -h $DIR -p $PORT -U postgres"
    ;;
  stop)
    if [ -f "$DATA/PG_VERSION" ]; then
      as_pg "$BIN/pg_ctl" -D "$DATA" -w -m fast stop >/dev/null 2>&1 || true
    fi
    ;;
  psql)
    shift
    exec psql -h "$DIR" -p "$PORT" -U postgres -v ON_ERROR_STOP=1 "$@"
    ;;
  *) echo "usage: $0 start|stop|psql" >&2; exit 2 ;;
esac
