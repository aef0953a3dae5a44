#!/usr/bin/env bash
# Extension upgrade path: install the previous release (0.1.0, its frozen
# install script in sql/versions/), store tin values with it, ALTER EXTENSION
# tinmerge UPDATE, and check that (1) the stored values read the same and
# answer the same, (2) what 0.2.0 added works on them, and (3) the upgraded
# catalog (every function with its flags, source and comment, every
# operator, operator class, type and cast of the extension) is exactly what
# a fresh CREATE EXTENSION of the new version makes. Needs the running test
# cluster and the installed extension.
set -euo pipefail
cd "$(dirname "$0")/.."
q() { scripts/cluster.sh psql -qAtX -v ON_ERROR_STOP=1 "$@"; }
old=0.1.0
new=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -1)

q -d postgres -c "DROP DATABASE IF EXISTS tinmerge_upgrade" -c "DROP DATABASE IF EXISTS tinmerge_fresh"
q -d postgres -c "CREATE DATABASE tinmerge_upgrade" -c "CREATE DATABASE tinmerge_fresh"
q -d tinmerge_upgrade -c "CREATE EXTENSION tinmerge VERSION '$old' CASCADE" 2>/dev/null
q -d tinmerge_fresh -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
[ "$(q -d tinmerge_upgrade -c "SELECT extversion FROM pg_extension WHERE extname = 'tinmerge'")" = "$old" ] \
  || { echo "could not install tinmerge $old"; exit 1; }

# values stored by the old version: a tin built from a synthetic terrain and
# a linetree
q -d tinmerge_upgrade <<'SQL'
CREATE TABLE terrain AS
SELECT tin_from_points(ST_SetSRID(ST_Collect(ST_MakePoint(x * 10.0, y * 10.0,
         50 * sin(x / 9.0) * cos(y / 7.0) + x * 0.3)), 32616), 0.5, 4) AS t
FROM generate_series(0, 120) x, generate_series(0, 120) y;
CREATE TABLE lines AS
SELECT tin_linetree('SRID=32616;LINESTRING(5 5, 600 300, 1150 1190)'::geometry) AS lt;
SQL
answers() {
  q -d tinmerge_upgrade <<'SQL'
SELECT md5(t::text), tin_info(t)::text FROM terrain;
SELECT round(tin_height(t, ST_SetSRID(ST_MakePoint(i * 11.3, i * 9.7), 32616))::numeric, 9)
FROM terrain, generate_series(1, 100, 9) i;
SELECT count(*), round(sum(ST_Length(geom))::numeric, 6) FROM terrain, lines, tin_line_segments(t, lt, 2);
SELECT * FROM terrain, tin_area_stats(t, 'SRID=32616;POLYGON((100 100, 900 150, 700 1000, 100 100))'::geometry, 3);
SQL
}
before=$(answers)

q -d tinmerge_upgrade -c "ALTER EXTENSION tinmerge UPDATE"
[ "$(q -d tinmerge_upgrade -c "SELECT extversion FROM pg_extension WHERE extname = 'tinmerge'")" = "$new" ] \
  || { echo "ALTER EXTENSION tinmerge UPDATE did not reach $new"; exit 1; }
after=$(answers)
[ "$before" = "$after" ] || { echo "values stored by $old answer differently after the update"; diff <(echo "$before") <(echo "$after"); exit 1; }

# what the new version added works on the old values
eq=$(q -d tinmerge_upgrade -c "SELECT t = t, t <> t, (SELECT count(*) FROM (SELECT DISTINCT t FROM (SELECT t FROM terrain UNION ALL SELECT t FROM terrain) u) d) FROM terrain")
[ "$eq" = "t|f|1" ] || { echo "= on values stored by $old gave '$eq'"; exit 1; }

# the upgraded catalog is the fresh one
catalog() {
  q -d "$1" <<'SQL'
WITH ext AS (SELECT oid FROM pg_extension WHERE extname = 'tinmerge'),
members AS (
  SELECT classid, objid FROM pg_depend, ext
  WHERE refclassid = 'pg_extension'::regclass AND refobjid = ext.oid AND deptype = 'e')
SELECT 'function ' || p.oid::regprocedure || ' returns ' || pg_get_function_result(p.oid)
       || ' args ' || pg_get_function_arguments(p.oid)
       || ' ' || p.provolatile::text || p.proisstrict::text || p.proparallel::text || ' cost ' || p.procost || ' rows ' || p.prorows
       || ' lang ' || l.lanname || ' src ' || md5(p.prosrc) || ' bin ' || coalesce(p.probin, '-')
       || ' config ' || coalesce(array_to_string(p.proconfig, ';'), '-')
       || ' comment ' || coalesce(md5(obj_description(p.oid, 'pg_proc')), 'NONE')
FROM members m JOIN pg_proc p ON m.classid = 'pg_proc'::regclass AND p.oid = m.objid
JOIN pg_language l ON l.oid = p.prolang
UNION ALL
SELECT 'operator ' || o.oid::regoperator || ' ' || o.oprcode::regproc || ' ' || o.oprcom::regoperator
       || ' ' || o.oprnegate::regoperator || ' ' || o.oprcanhash || ' ' || o.oprrest || ' ' || o.oprjoin
       || ' comment ' || coalesce(obj_description(o.oid, 'pg_operator'), 'NONE')
FROM members m JOIN pg_operator o ON m.classid = 'pg_operator'::regclass AND o.oid = m.objid
UNION ALL
SELECT 'opclass ' || c.opcname || ' ' || c.opcdefault || ' ' || c.opcintype::regtype
FROM members m JOIN pg_opclass c ON m.classid = 'pg_opclass'::regclass AND c.oid = m.objid
UNION ALL
SELECT 'type ' || t.typname || ' ' || t.typinput || ' ' || t.typoutput || ' ' || t.typreceive || ' '
       || t.typsend || ' ' || t.typstorage::text || ' ' || t.typalign::text || ' comment ' || coalesce(obj_description(t.oid, 'pg_type'), 'NONE')
FROM members m JOIN pg_type t ON m.classid = 'pg_type'::regclass AND t.oid = m.objid
UNION ALL
SELECT 'cast ' || c.castsource::regtype || ' -> ' || c.casttarget::regtype || ' ' || c.castcontext::text || ' ' || c.castmethod::text
FROM members m JOIN pg_cast c ON m.classid = 'pg_cast'::regclass AND c.oid = m.objid
UNION ALL
SELECT 'other ' || pg_describe_object(m.classid, m.objid, 0)
FROM members m WHERE m.classid NOT IN ('pg_proc'::regclass, 'pg_operator'::regclass,
  'pg_opclass'::regclass, 'pg_type'::regclass, 'pg_cast'::regclass)
ORDER BY 1;
SQL
}
catalog tinmerge_fresh > target/catalog-fresh.txt
catalog tinmerge_upgrade > target/catalog-upgraded.txt
if ! diff target/catalog-fresh.txt target/catalog-upgraded.txt; then
  echo "the catalog after ALTER EXTENSION UPDATE ($old -> $new) differs from a fresh install of $new (< fresh, > upgraded)"
  exit 1
fi
n=$(wc -l < target/catalog-fresh.txt)
q -d postgres -c "DROP DATABASE tinmerge_upgrade" -c "DROP DATABASE tinmerge_fresh"
echo "upgrade $old -> $new: stored values answer the same, = works on them, catalog identical to a fresh install ($n objects)"
