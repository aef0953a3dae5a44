#!/usr/bin/env bash
# Extension upgrade paths. First: install the first release (0.1.0, its frozen
# install script in sql/versions/), store tin values with it, ALTER EXTENSION
# tinmerge UPDATE, and check that (1) the stored values read the same and
# answer the same, (2) what 0.2.0 added works on them, and (3) the upgraded
# catalog (every function with its flags, source, support function and comment, every
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
       || ' support ' || p.prosupport::regproc::text
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
q -d postgres -c "DROP DATABASE tinmerge_upgrade"
echo "upgrade $old -> $new: stored values answer the same, = works on them, catalog identical to a fresh install ($n objects)"

# Values written by tinmerge 0.2.0 itself (format 1, the bytes 0.2.0 wrote:
# tests/data/format-v1): the geographic DEM window with 0.2.0's cracks, a
# UTM DEM window and a linetree, stored in a database at 0.2.0 (created as
# 0.1.0 + the 0.1.0--0.2.0 script) and copied out with COPY BINARY. After
# ALTER EXTENSION UPDATE they read and answer the same, tin_validate finds
# the cracks 0.2.0 stored, tin_rewrite gives format 6 values that answer
# the same (read in slices), and COPY BINARY of the 0.2.0 table loads into a
# fresh install of the new version with the same bytes.
old2=0.2.0
data="$PWD/tests/data/format-v1"
q -d postgres -c "DROP DATABASE IF EXISTS tinmerge_upgrade2"
q -d postgres -c "CREATE DATABASE tinmerge_upgrade2"
q -d tinmerge_upgrade2 -c "CREATE EXTENSION tinmerge VERSION '$old2' CASCADE" 2>/dev/null
[ "$(q -d tinmerge_upgrade2 -c "SELECT extversion FROM pg_extension WHERE extname = 'tinmerge'")" = "$old2" ] \
  || { echo "could not install tinmerge $old2"; exit 1; }
q -d tinmerge_upgrade2 -v geo="$data/geo-0.2.0.tin" -v win="$data/window.tin" -v lt="$data/line.linetree" <<'SQL'
CREATE TABLE old_tins AS
SELECT 'geo' AS name, encode(pg_read_binary_file(:'geo'), 'hex')::tin AS t
UNION ALL SELECT 'window', encode(pg_read_binary_file(:'win'), 'hex')::tin;
CREATE TABLE old_lines AS SELECT encode(pg_read_binary_file(:'lt'), 'hex')::linetree AS lt;
-- a terrain under the stored linetree (which lies outside both tins)
CREATE TABLE cover AS
SELECT tin_from_points(ST_SetSRID(ST_Collect(ST_MakePoint(740000 + x * 100.0, 4059000 + y * 100.0,
         300 + 40 * sin(x / 5.0) * cos(y / 4.0))), 32616), 0.5, 3) AS t
FROM generate_series(0, 40) x, generate_series(0, 40) y;
SQL
mkdir -p target
q -d tinmerge_upgrade2 -c "\copy old_tins TO 'target/old_tins.bin' (FORMAT binary)"
# heights on a 17 x 17 lattice over each tin's box at every level, a line
# across each box (cut at every level), the same through the stored
# linetree, and the triangles in a triangle in each box with their
# statistics (projected only): functions 0.2.0
# had, with the signatures it had
answers2() { # database, table
  q -d "$1" <<SQL
SELECT name, md5(t::text), tin_num_levels(t), tin_num_triangles(t), tin_num_vertices(t) FROM $2 ORDER BY name;
WITH b AS (SELECT name, t, tin_envelope(t) AS e FROM $2),
p AS (SELECT name, t, i, ST_SetSRID(ST_MakePoint(ST_XMin(e) + (ST_XMax(e) - ST_XMin(e)) * (i % 17) / 16.0,
                                                 ST_YMin(e) + (ST_YMax(e) - ST_YMin(e)) * (i / 17) / 16.0), tin_srid(t)) AS pt
      FROM b, generate_series(0, 288) i)
SELECT name, l, md5(string_agg(coalesce(tin_height(t, pt, l)::text, '-'), ',' ORDER BY i))
FROM p, generate_series(0, tin_num_levels(t) - 1) l GROUP BY name, l ORDER BY name, l;
WITH b AS (SELECT name, t, tin_envelope(t) AS e FROM $2),
ln AS (SELECT name, t, ST_SetSRID(ST_MakeLine(ST_MakePoint(ST_XMin(e) + 0.1 * (ST_XMax(e) - ST_XMin(e)), ST_YMin(e) + 0.2 * (ST_YMax(e) - ST_YMin(e))),
                                              ST_MakePoint(ST_XMin(e) + 0.9 * (ST_XMax(e) - ST_XMin(e)), ST_YMin(e) + 0.7 * (ST_YMax(e) - ST_YMin(e)))), tin_srid(t)) AS g,
              ST_SetSRID(ST_MakePolygon(ST_MakeLine(ARRAY[
                ST_MakePoint(ST_XMin(e) + 0.2 * (ST_XMax(e) - ST_XMin(e)), ST_YMin(e) + 0.1 * (ST_YMax(e) - ST_YMin(e))),
                ST_MakePoint(ST_XMin(e) + 0.8 * (ST_XMax(e) - ST_XMin(e)), ST_YMin(e) + 0.3 * (ST_YMax(e) - ST_YMin(e))),
                ST_MakePoint(ST_XMin(e) + 0.5 * (ST_XMax(e) - ST_XMin(e)), ST_YMin(e) + 0.9 * (ST_YMax(e) - ST_YMin(e))),
                ST_MakePoint(ST_XMin(e) + 0.2 * (ST_XMax(e) - ST_XMin(e)), ST_YMin(e) + 0.1 * (ST_YMax(e) - ST_YMin(e)))])), tin_srid(t)) AS a
       FROM b)
SELECT name, l,
       (SELECT md5(string_agg(s.triangle || ':' || ST_AsText(s.geom) || ':' || s.length3d, ',' ORDER BY s.seq)) FROM tin_line_segments(t, g, l) s),
       (SELECT md5(string_agg(row(x.*)::text, ',' ORDER BY row(x.*)::text)) FROM tin_area_triangles(t, a, l) x),
       CASE WHEN tin_srid(t) <> 4326 THEN (SELECT row(x.*)::text FROM tin_area_stats(t, a, l) x) END,
       -- a polygon holding the whole terrain: answered from the header's
       -- sums once rewritten (format 6), from the triangles before
       CASE WHEN tin_srid(t) <> 4326 THEN (SELECT row(x.*)::text FROM tin_area_stats(t, ST_Expand(e, 1), l) x) END
FROM ln JOIN (SELECT name, e FROM b) b USING (name), generate_series(0, tin_num_levels(t) - 1) l ORDER BY name, l;
SELECT count(*), md5(string_agg(ST_AsText(s.geom), ',' ORDER BY s.seq))
FROM cover, old_lines, tin_line_segments(cover.t, lt, 1) s;
SQL
}
before2=$(answers2 tinmerge_upgrade2 old_tins)
echo "$before2" > target/upgrade-$old2-answers.txt
[ "$(echo "$before2" | grep -c '|')" -ge 14 ] && ! echo "$before2" | grep -q '^0|' \
  || { echo "too few answers from the $old2 values: $before2"; exit 1; }
q -d tinmerge_upgrade2 -c "ALTER EXTENSION tinmerge UPDATE"
[ "$(q -d tinmerge_upgrade2 -c "SELECT extversion FROM pg_extension WHERE extname = 'tinmerge'")" = "$new" ] \
  || { echo "ALTER EXTENSION tinmerge UPDATE from $old2 did not reach $new"; exit 1; }
after2=$(answers2 tinmerge_upgrade2 old_tins)
[ "$before2" = "$after2" ] || { echo "values stored by $old2 answer differently after the update"; diff <(echo "$before2") <(echo "$after2"); exit 1; }
# the 0.2.0 value's cracks are found; both values are format 1
found=$(q -d tinmerge_upgrade2 -c "SELECT string_agg(name || '=' || (tin_info(t)->>'format') || '/' || (SELECT count(*) FROM tin_validate(t)), ' ' ORDER BY name) FROM old_tins")
case "$found" in
  "geo=1/"[1-9]*" window=1/"*) ;;
  *) echo "tin_validate on the values $old2 stored gave '$found' (expected format 1 and cracks in geo)"; exit 1 ;;
esac
# rewritten in the current format, in a new table (so the functions read
# the stored rewritten value, in slices): the same answers apart from the
# bytes
q -d tinmerge_upgrade2 -c "CREATE TABLE new_tins AS SELECT name, tin_rewrite(t) AS t FROM old_tins"
fmt=$(q -d tinmerge_upgrade2 -c "SELECT string_agg(DISTINCT tin_info(t)->>'format', ',') FROM new_tins")
[ "$fmt" = "6" ] || { echo "tin_rewrite gave format '$fmt'"; exit 1; }
rewritten=$(answers2 tinmerge_upgrade2 new_tins)
[ "$(echo "$before2" | sed 1,2d)" = "$(echo "$rewritten" | sed 1,2d)" ] \
  || { echo "values of $old2 rewritten in format $fmt answer differently"; diff <(echo "$before2") <(echo "$rewritten"); exit 1; }
# COPY BINARY of the 0.2.0 table into a fresh install of the new version
q -d tinmerge_fresh -c "CREATE TABLE old_tins (name text, t tin)" \
  -c "\copy old_tins FROM 'target/old_tins.bin' (FORMAT binary)"
same=$(q -d tinmerge_fresh -c "SELECT string_agg(name || '=' || md5(t::text), ' ' ORDER BY name) FROM old_tins")
want=$(q -d tinmerge_upgrade2 -c "SELECT string_agg(name || '=' || md5(t::text), ' ' ORDER BY name) FROM old_tins")
[ "$same" = "$want" ] || { echo "COPY BINARY of $old2 values into $new changed them: $same vs $want"; exit 1; }
q -d postgres -c "DROP DATABASE tinmerge_upgrade2" -c "DROP DATABASE tinmerge_fresh"
rm -f target/old_tins.bin
echo "upgrade $old2 -> $new: values 0.2.0 wrote (format 1) answer the same, its cracks are found, tin_rewrite to format $fmt answers the same, COPY BINARY into $new keeps them"
