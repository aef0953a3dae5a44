#!/usr/bin/env bash
# tin values survive COPY (text and binary), pg_dump -Fc and pg_restore, and
# queries on the restored value give the same answers. Needs the running test
# cluster and the tinmerge_regress database with table terrain (pg_regress).
set -euo pipefail
cd "$(dirname "$0")/.."
DIR="$PWD/target/pg"; PORT="${TINMERGE_PORT:-28815}"
q() { scripts/cluster.sh psql -qAt "$@"; }
work="$PWD/target/dump"; rm -rf "$work"; mkdir -p "$work"; chmod 777 "$work"

# COPY text and binary round trips
q -d tinmerge_regress -c "DROP TABLE IF EXISTS copy_txt, copy_bin; CREATE TABLE copy_txt (t tin); CREATE TABLE copy_bin (t tin)"
q -d tinmerge_regress -c "\\copy terrain TO '$work/terrain.txt'"
q -d tinmerge_regress -c "\\copy copy_txt FROM '$work/terrain.txt'"
q -d tinmerge_regress -c "\\copy terrain TO '$work/terrain.bin' WITH (FORMAT binary)"
q -d tinmerge_regress -c "\\copy copy_bin FROM '$work/terrain.bin' WITH (FORMAT binary)"
same=$(q -d tinmerge_regress -c "SELECT (SELECT t::text FROM copy_txt) = (SELECT t::text FROM terrain) AND (SELECT t::text FROM copy_bin) = (SELECT t::text FROM terrain)")
[ "$same" = "t" ] || { echo "COPY round trip changed the value"; exit 1; }

# linetree values: COPY binary round trip (line_trees from pg_regress)
q -d tinmerge_regress -c "DROP TABLE IF EXISTS copy_lt; CREATE TABLE copy_lt (id int, lt linetree)"
q -d tinmerge_regress -c "\\copy (SELECT id, lt FROM line_trees) TO '$work/lt.bin' WITH (FORMAT binary)"
q -d tinmerge_regress -c "\\copy copy_lt FROM '$work/lt.bin' WITH (FORMAT binary)"
bad=$(q -d tinmerge_regress -c "SELECT count(*) FROM line_trees a LEFT JOIN copy_lt b USING (id) WHERE b.lt IS NULL OR a.lt::text <> b.lt::text")
[ "$bad" = "0" ] || { echo "COPY binary changed $bad linetree values"; exit 1; }

# pg_dump -Fc / pg_restore into a fresh database
pg_dump -h "$DIR" -p "$PORT" -U postgres -Fc -t terrain -f "$work/terrain.dump" tinmerge_regress
q -d postgres -c "DROP DATABASE IF EXISTS tinmerge_restore" -c "CREATE DATABASE tinmerge_restore"
q -d tinmerge_restore -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
pg_restore -h "$DIR" -p "$PORT" -U postgres -d tinmerge_restore "$work/terrain.dump"
a=$(q -d tinmerge_regress -c "SELECT md5(t::text), tin_info(t)::text FROM terrain")
b=$(q -d tinmerge_restore -c "SELECT md5(t::text), tin_info(t)::text FROM terrain")
[ "$a" = "$b" ] || { echo "pg_dump/pg_restore changed the value"; exit 1; }
c=$(q -d tinmerge_restore -c "SELECT count(*) FROM terrain, tin_triangles(t, 2)")
d=$(q -d tinmerge_regress -c "SELECT count(*) FROM terrain, tin_triangles(t, 2)")
[ "$c" = "$d" ] || { echo "restored value answers differently"; exit 1; }
storage=$(q -d tinmerge_restore -c "SELECT attstorage FROM pg_attribute WHERE attrelid = 'terrain'::regclass AND attname = 't'")
[ "$storage" = "e" ] || { echo "tin column storage is '$storage', expected external"; exit 1; }
q -d postgres -c "DROP DATABASE tinmerge_restore"
echo "COPY (text, binary) and pg_dump/pg_restore keep tin values exactly ($(du -h "$work/terrain.dump" | cut -f1) dump)"
