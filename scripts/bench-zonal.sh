#!/usr/bin/env bash
# Zonal statistics over a tiled terrain at the cost of the boundary (issue
# 76), side by side with the PostGIS way in one run: on the terrain of
# scripts/bench-big.sh (FACTOR 29: 105 million pixels of 3.1 m as 1,582
# tins of 256 x 256 pixels, 1 m at the finest of 5 levels; built first
# when its database is missing), circles of 100 m, 500 m and 5 km radius
# and a county-sized polygon (about 300 km², 4,000 vertices), each summed
# over the tiles it meets as users write it:
#   tinmerge: sum of tin_area_stats(tile, polygon) over the tiles whose
#             envelope meets it (a tile wholly inside answers from the
#             sums in its header; the others through their triangles)
#   PostGIS:  ST_SummaryStatsAgg(ST_Clip(rast, polygon)) over the raster
#             tiles it meets
# and cut and fill of 1 km² polygons against the height at their centre:
# tin_volume against ST_Clip + ST_MapAlgebra (GREATEST([rast] - base, 0)
# and the reverse) summed times the pixel area. Cold: the first query of a
# new connection; warm: the median of the next runs (one core, no parallel
# workers). The answers are compared too (mean height against PostGIS's
# pixel mean; areas against ST_Area of the polygon within the raster's
# footprint). Prints tables; timings are not asserted (noisy machine).
#
# usage: [TINMERGE_BIG_DB=database] [TINMERGE_ZONAL_KM=n] scripts/bench-zonal.sh [FACTOR]
#   (scripts/bench-big.sh takes TINMERGE_BIG_DB too: the billion-pixel
#   terrain in a database of its own beside the 105-Mpixel one)
set -euo pipefail
cd "$(dirname "$0")/.."
FACTOR="${1:-29}"
DB="${TINMERGE_BIG_DB:-tinmerge_big}"
scripts/cluster.sh start >/dev/null
q() { scripts/cluster.sh psql -v ON_ERROR_STOP=1 -qAtX -d "$DB" "$@"; }
if ! q -c "SELECT count(*) FROM big_tins" >/dev/null 2>&1; then
  echo "== no terrain in $DB: scripts/bench-big.sh $FACTOR (its features few)"
  TINMERGE_BIG_REUSE=1 scripts/bench-big.sh "$FACTOR" 1000 10 10 >/dev/null
fi
q -c "SELECT 1 FROM pg_proc WHERE proname = 'bench'" | grep -q 1 || q -f scripts/bench-fn.sql
echo "== zonal statistics over tiles; $(date -u '+%Y-%m-%d %H:%M') UTC, $(nproc) cores, tinmerge $(q -c "SELECT extversion FROM pg_extension WHERE extname = 'tinmerge'")"
q -F ' | ' -c "SELECT 'terrain' AS what, count(*) AS tins, sum(tin_num_triangles(t)) AS finest_triangles,
  string_agg(DISTINCT tin_info(t)->>'format', ',') AS formats,
  (SELECT count(*) FROM big_tiles) AS raster_tiles,
  (SELECT round(max(ST_ScaleX(rast))::numeric, 3) FROM big_tiles) AS pixel_m FROM big_tins"
q <<'SQL'
SET client_min_messages = warning;
DROP TABLE IF EXISTS zones, zones_km;
SELECT setseed(0.76);
CREATE TEMP TABLE ext AS SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h
FROM (SELECT ST_Extent(tin_envelope(t))::geometry e FROM big_tins) s;
-- circles well inside the terrain (quad_segs 32: 128 vertices)
CREATE TABLE zones AS
SELECT r || ' m' AS kind, i AS id,
       ST_Buffer(ST_SetSRID(ST_MakePoint(x0 + 1.2 * r + random() * (w - 2.4 * r), y0 + 1.2 * r + random() * (h - 2.4 * r)), 32616), r, 32) AS geom
FROM ext, (VALUES (100, 1000), (500, 100), (5000, 10)) v(r, n), generate_series(1, n) i;
-- a county: 4,000 vertices, radius about 10 km with lobes and a rough edge
INSERT INTO zones
SELECT 'county', 1, ST_MakePolygon(ST_AddPoint(l, ST_StartPoint(l)))
FROM (SELECT ST_MakeLine(ST_SetSRID(ST_MakePoint(
               x0 + w / 2 + rr * cos(a), y0 + h / 2 + rr * sin(a)), 32616) ORDER BY k) AS l
      FROM ext, LATERAL (SELECT k, 2 * pi() * k / 4000 AS a FROM generate_series(0, 3999) k) g,
      LATERAL (SELECT 10000 * (1 + 0.12 * sin(7 * a) + 0.04 * sin(53 * a) + 0.01 * random()) AS rr) r
      GROUP BY x0, y0, w, h) s;
-- 1 km² for cut and fill, against PostGIS's pixel height at the centre
CREATE TABLE zones_km AS
SELECT i AS id, ST_Buffer(c, 564.19, 32) AS geom,
       (SELECT ST_Value(r.rast, 1, c) FROM big_tiles r WHERE ST_Intersects(r.rast, c) LIMIT 1) AS base
FROM (SELECT i, ST_SetSRID(ST_MakePoint(x0 + 700 + random() * (w - 1400), y0 + 700 + random() * (h - 1400)), 32616) c
      FROM ext, generate_series(1, 100) i) s;
DELETE FROM zones_km WHERE base IS NULL;
ANALYZE zones; ANALYZE zones_km;
SQL
# TINMERGE_ZONAL_KM=n: only the first n of the 1 km² polygons (the
# billion-pixel terrain: PostGIS's cut and fill of 100 takes minutes a run)
q -c "DELETE FROM zones_km WHERE id > ${TINMERGE_ZONAL_KM:-100}"
q -F ' | ' -c "SELECT kind, count(*) AS polygons, round((avg(ST_Area(geom)) / 1e6)::numeric, 3) AS km2_each, max(ST_NPoints(geom)) AS vertices,
  round(avg((SELECT count(*) FROM big_tins k WHERE tin_envelope(k.t) && z.geom)), 1) AS tiles_met_each,
  round(avg((SELECT count(*) FROM big_tins k WHERE ST_Covers(z.geom, tin_envelope(k.t)))), 1) AS tiles_inside_each
FROM zones z GROUP BY kind ORDER BY min(ST_Area(geom))"

tin_q() { echo "SELECT z.id, sum(s.area2d) AS area2d, sum(s.area3d) AS area3d, sum(s.mean_z * s.area2d) / nullif(sum(s.area2d), 0) AS mean_z, min(s.min_z) AS min_z, max(s.max_z) AS max_z FROM zones z JOIN big_tins k ON tin_envelope(k.t) && z.geom, LATERAL tin_area_stats(k.t, z.geom) s WHERE z.kind = '$1' GROUP BY z.id"; }
pg_q() { echo "SELECT z.id, (ST_SummaryStatsAgg(ST_Clip(r.rast, z.geom), 1, true)).mean AS mean_z FROM zones z JOIN big_tiles r ON ST_Intersects(r.rast, z.geom) WHERE z.kind = '$1' GROUP BY z.id"; }
px2=$(q -c "SELECT abs(ST_ScaleX(rast) * ST_ScaleY(rast)) FROM big_tiles LIMIT 1")
CUT_TIN="SELECT z.id, sum(v.cut) AS cut, sum(v.fill) AS fill FROM zones_km z JOIN big_tins k ON tin_envelope(k.t) && z.geom, LATERAL tin_volume(k.t, z.geom, z.base) v GROUP BY z.id"
CUT_PG="SELECT z.id, $px2 * sum(coalesce((ST_SummaryStats(ST_MapAlgebra(c.r, 1, '32BF', 'GREATEST([rast] - ' || z.base || ', 0)'))).sum, 0)) AS cut, $px2 * sum(coalesce((ST_SummaryStats(ST_MapAlgebra(c.r, 1, '32BF', 'GREATEST(' || z.base || ' - [rast], 0)'))).sum, 0)) AS fill FROM zones_km z JOIN big_tiles t ON ST_Intersects(t.rast, z.geom), LATERAL (SELECT ST_Clip(t.rast, z.geom) AS r) c GROUP BY z.id"

# ms per query: cold (first of a connection) and the warm median (after
# one more run: a tile read in slices on its first call is decoded whole on
# its second, and kept)
timed() { # query warm_runs -> "cold warm"
  scripts/cluster.sh psql -qAtX -d "$DB" \
    -c "SET max_parallel_workers_per_gather = 0" -c "SET client_min_messages = warning" \
    -c "CREATE TEMP TABLE c AS SELECT median_ms FROM bench('', \$q\$SELECT count(s::text) FROM ($1) s\$q\$, 1)" \
    -c "CREATE TEMP TABLE w AS SELECT median_ms FROM bench('', \$q\$SELECT count(s::text) FROM ($1) s\$q\$, 1)" \
    -c "SELECT (SELECT median_ms FROM c) || ' ' || median_ms FROM bench('', \$q\$SELECT count(s::text) FROM ($1) s\$q\$, $2)"
}
echo "== time (ms; one core): polygons | tinmerge cold | warm | PostGIS cold | warm | PostGIS / tinmerge (warm) | tinmerge per polygon"
declare -A per
for kind in "100 m" "500 m" "5000 m" "county"; do
  n=$(q -c "SELECT count(*) FROM zones WHERE kind = '$kind'")
  read -r tc tw <<<"$(timed "$(tin_q "$kind")" 3)"
  read -r pc pw <<<"$(timed "$(pg_q "$kind")" 1)"
  per[$kind]=$(awk -v t="$tw" -v n="$n" 'BEGIN { printf "%.4f", t / n }')
  awk -v k="$kind" -v n="$n" -v tc="$tc" -v tw="$tw" -v pc="$pc" -v pw="$pw" \
    'BEGIN { printf "%s (%d) | %.1f | %.1f | %.1f | %.1f | %.1fx | %.3f\n", k, n, tc, tw, pc, pw, pw / tw, tw / n }'
done
read -r tc tw <<<"$(timed "$CUT_TIN" 3)"
read -r pc pw <<<"$(timed "$CUT_PG" 1)"
awk -v n="$(q -c "SELECT count(*) FROM zones_km")" -v tc="$tc" -v tw="$tw" -v pc="$pc" -v pw="$pw" \
  'BEGIN { printf "cut and fill of 1 km² (%d) | %.1f | %.1f | %.1f | %.1f | %.1fx | %.3f\n", n, tc, tw, pc, pw, pw / tw, tw / n }'
awk -v a="${per[500 m]}" -v b="${per[5000 m]}" 'BEGIN { printf "== 10x the radius (500 m -> 5 km) costs %.1fx the time per polygon (the area 100x, the perimeter 10x)\n", b / a }'

echo "== answers: tinmerge against PostGIS (the tin is within 1 m of every pixel; PostGIS counts the pixels whose centre is in the polygon, each at its value)"
q <<SQL
SET client_min_messages = warning;
SET max_parallel_workers_per_gather = 0;
DROP TABLE IF EXISTS zonal_tin, zonal_pg, zonal_cut_tin, zonal_cut_pg;
CREATE TABLE zonal_tin AS $(tin_q "%" | sed "s/z.kind = '%'/true/; s/SELECT z.id,/SELECT z.kind, z.id,/; s/GROUP BY z.id/GROUP BY z.kind, z.id/");
CREATE TABLE zonal_pg AS $(pg_q "%" | sed "s/z.kind = '%'/true/; s/SELECT z.id,/SELECT z.kind, z.id, (ST_SummaryStatsAgg(ST_Clip(r.rast, z.geom), 1, true)).count AS valid,/; s/GROUP BY z.id/GROUP BY z.kind, z.id/");
CREATE TABLE zonal_cut_tin AS $CUT_TIN;
CREATE TABLE zonal_cut_pg AS $CUT_PG;
SQL
q -F ' | ' <<SQL
SELECT kind, count(*) AS compared,
       round(percentile_cont(0.5) WITHIN GROUP (ORDER BY abs(a.mean_z - b.mean_z))::numeric, 3) AS median_abs_mean_z_diff_m,
       round(max(abs(a.mean_z - b.mean_z))::numeric, 3) AS max_abs_mean_z_diff_m,
       count(*) FILTER (WHERE b.valid * $px2 < 0.99 * ST_Area(z.geom)) AS over_nodata_by_postgis_pixels,
       count(*) FILTER (WHERE a.area2d < 0.99 * ST_Area(z.geom)) AS over_nodata_by_tinmerge_area,
       max(abs(a.area2d - ST_Area(z.geom)) / ST_Area(z.geom)) FILTER (WHERE b.valid * $px2 >= 0.99 * ST_Area(z.geom)) AS max_rel_area_diff_from_st_area_elsewhere
FROM zonal_tin a JOIN zonal_pg b USING (kind, id) JOIN zones z USING (kind, id)
GROUP BY kind ORDER BY min(ST_Area(z.geom));
SELECT 'cut and fill of 1 km²' AS what, count(*) AS compared,
       round(percentile_cont(0.5) WITHIN GROUP (ORDER BY abs(a.cut - b.cut) / nullif(a.cut + a.fill, 0))::numeric, 4) AS median_rel_cut_diff,
       round(percentile_cont(0.5) WITHIN GROUP (ORDER BY abs(a.fill - b.fill) / nullif(a.cut + a.fill, 0))::numeric, 4) AS median_rel_fill_diff,
       round(avg(a.cut + a.fill)::numeric) AS mean_cut_plus_fill_m3
FROM zonal_cut_tin a JOIN zonal_cut_pg b USING (id);
SQL
