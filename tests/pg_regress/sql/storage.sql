-- Storage (format 7 here: compact groups with void triangles and each
-- level's whole sums in the header; 6 without void triangles; 5 and 4,
-- without the sums, before 0.26.0): the per-row point functions read a stored terrain in slices (a
-- few blocks, each checked against its own checksum) until they have been
-- called often enough on it to decode it whole. Answers are the same
-- either way; format 1 values still read and tin_rewrite converts them.
SET extra_float_digits = 0;
CREATE TABLE store_terrain (id int, t tin);
INSERT INTO store_terrain SELECT 1, t FROM terrain;
SELECT tin_info(t)->>'format' AS format, pg_column_size(t) = (tin_info(t)->>'bytes')::int AS stored_uncompressed
FROM store_terrain;
-- points and their heights from the decoded value (this session decodes it:
-- more calls than the slicing limit)
CREATE TABLE store_pts AS
SELECT i, ST_SetSRID(ST_MakePoint(740000 + (i * 7919) % 20000 + 0.37, 4045000 + (i * 104729) % 20000 + 0.61), 32616) AS p
FROM generate_series(1, 3000) i;
CREATE TABLE store_want AS
SELECT i, l, tin_height(t, p, l) AS z, tin_locate(t, p, l) AS tri
FROM store_pts, store_terrain, generate_series(0, 4) l;
SELECT count(*) AS answers, count(z) AS inside FROM store_want;
-- and lines: a 2 km line and a contour cut per triangle, with profile and climb
CREATE TABLE store_lines AS
SELECT 1 AS id, 'SRID=32616;LINESTRING(757000 4052000, 759000 4052100)'::geometry AS geom
UNION ALL SELECT 2, geom FROM contours WHERE id = 100;
CREATE TABLE store_cut AS
SELECT sl.id, g.l, s.* FROM store_lines sl, store_terrain st, generate_series(0, 4) g(l), tin_line_segments(st.t, sl.geom, g.l) s;
CREATE TABLE store_prof AS
SELECT sl.id, g.l, (SELECT array_agg(array[distance, z] ORDER BY distance, z) FROM tin_line_profile(st.t, sl.geom, g.l)) AS prof,
       tin_line_climb(st.t, sl.geom, g.l) AS climb,
       (SELECT array_agg(triangle ORDER BY seq) FROM tin_line_triangles(st.t, sl.geom, g.l)) AS tris
FROM store_lines sl, store_terrain st, generate_series(0, 4) g(l);
-- and areas: a 1 km square and a contour band with holes
CREATE TABLE store_polys AS
SELECT 1 AS id, 'SRID=32616;POLYGON((757500 4051500, 758500 4051500, 758500 4052500, 757500 4052500, 757500 4051500))'::geometry AS geom
UNION ALL (SELECT 2, geom FROM contour_bands WHERE lo = 400);
CREATE TABLE store_area AS
SELECT p.id, g.l, (SELECT array_agg(array[triangle, level] ORDER BY level, triangle) FROM tin_area_triangles(st.t, p.geom, g.l, true)) AS tris,
       (SELECT array_agg(coverage ORDER BY triangle) FROM tin_area_triangles(st.t, p.geom, g.l)) AS cov,
       (SELECT row(a.*)::text FROM tin_area_stats(st.t, p.geom, g.l) a) AS stats,
       (SELECT row(v.*)::text FROM tin_volume(st.t, p.geom, 500, g.l) v) AS vol
FROM store_polys p, store_terrain st, generate_series(0, 4) g(l);
SELECT sliced_values, entries >= 1 AS decoded FROM tin_cache_stats();
-- a new session: a few points read the value in slices, decoding nothing
\c
SET extra_float_digits = 0;
SELECT count(*) FILTER (WHERE tin_height(t, p, l) IS NOT DISTINCT FROM w.z
                          AND tin_locate(t, p, l) IS NOT DISTINCT FROM w.tri) AS same_answers,
       count(*) AS asked
FROM store_want w JOIN store_pts USING (i), store_terrain WHERE i <= 5;
SELECT entries AS decoded_values, sliced_values, sliced_blocks > 0 AS read_blocks,
       -- (held groups are decoded: against the arrays a whole decode holds)
       sliced_bytes * 10 < (SELECT sum((l->>'triangles')::bigint * 28) + max((l->>'vertices')::bigint) * 24
                            FROM store_terrain, jsonb_array_elements(tin_info(t)->'levels') l) AS read_under_10_percent
FROM tin_cache_stats();
-- a new session: the same lines read in slices
\c
SET extra_float_digits = 0;
WITH now AS (SELECT sl.id, g.l, s.* FROM store_lines sl, store_terrain st, generate_series(0, 4) g(l),
               tin_line_segments(st.t, sl.geom, g.l) s WHERE sl.id = 1)
SELECT (SELECT count(*) FROM now) AS pieces, (SELECT count(*) FROM store_cut WHERE id = 1) AS pieces_decoded,
       count(*) AS same_pieces
FROM now n JOIN store_cut c USING (id, l, seq)
WHERE n.triangle = c.triangle AND ST_AsEWKB(n.geom) = ST_AsEWKB(c.geom) AND n.length3d = c.length3d AND n.rise = c.rise;
SELECT count(*) FILTER (WHERE (SELECT array_agg(array[distance, z] ORDER BY distance, z) FROM tin_line_profile(st.t, sl.geom, p.l)) = p.prof
                          AND tin_line_climb(st.t, sl.geom, p.l) IS NOT DISTINCT FROM p.climb
                          AND (SELECT array_agg(triangle ORDER BY seq) FROM tin_line_triangles(st.t, sl.geom, p.l)) = p.tris) AS same_profiles,
       count(*) AS asked
FROM store_prof p JOIN store_lines sl USING (id), store_terrain st WHERE p.id = 1;
SELECT entries AS decoded_values, sliced_values FROM tin_cache_stats();
-- the square read in slices: the same rows, coverages, statistics and volumes
SELECT count(*) FILTER (WHERE (SELECT array_agg(array[triangle, level] ORDER BY level, triangle) FROM tin_area_triangles(st.t, p.geom, a.l, true)) = a.tris
                          AND (SELECT array_agg(coverage ORDER BY triangle) FROM tin_area_triangles(st.t, p.geom, a.l)) = a.cov
                          AND (SELECT row(x.*)::text FROM tin_area_stats(st.t, p.geom, a.l) x) = a.stats
                          AND (SELECT row(v.*)::text FROM tin_volume(st.t, p.geom, 500, a.l) v) = a.vol) AS same_areas,
       count(*) AS asked
FROM store_area a JOIN store_polys p USING (id), store_terrain st WHERE a.id = 1;
SELECT entries AS decoded_values, sliced_values FROM tin_cache_stats();
-- a contour band with holes (large: read in slices until an eighth of the
-- blocks are held, then decoded): the same answers
SELECT count(*) FILTER (WHERE (SELECT array_agg(array[triangle, level] ORDER BY level, triangle) FROM tin_area_triangles(st.t, p.geom, a.l, true)) = a.tris
                          AND (SELECT array_agg(coverage ORDER BY triangle) FROM tin_area_triangles(st.t, p.geom, a.l)) = a.cov
                          AND (SELECT row(x.*)::text FROM tin_area_stats(st.t, p.geom, a.l) x) = a.stats
                          AND (SELECT row(v.*)::text FROM tin_volume(st.t, p.geom, 500, a.l) v) = a.vol) AS same_areas,
       count(*) AS asked
FROM store_area a JOIN store_polys p USING (id), store_terrain st WHERE a.id = 2;
-- tin_drape of a point takes the same path
SELECT ST_Z(tin_drape(t, p, 2)) = w.z AS drape_same
FROM store_want w JOIN store_pts USING (i), store_terrain WHERE i = 7 AND l = 2;
-- past the slicing limit the value is decoded whole and answers stay the same
SELECT count(*) FILTER (WHERE tin_height(t, p, l) IS NOT DISTINCT FROM w.z) AS same_answers, count(*) AS asked
FROM store_want w JOIN store_pts USING (i), store_terrain;
SELECT entries AS decoded_values, sliced_values FROM tin_cache_stats();
-- a value already in the current format: tin_rewrite returns it as it is
SELECT tin_rewrite(t) = t AS current_unchanged, tin_info(tin_rewrite(t))->>'format' AS format FROM store_terrain;
-- a value stored in format 1 (a fixture written by 0.2.0): read whole, the
-- same answers after tin_rewrite, which gives the current format
\getenv abs_srcdir PG_ABS_SRCDIR
\set fixture :abs_srcdir '/../data/format-v1/geo-0.2.0.tin'
CREATE TABLE store_old AS SELECT encode(pg_read_binary_file(:'fixture'), 'hex')::tin AS t;
SELECT tin_info(t)->>'format' AS old_format, tin_info(tin_rewrite(t))->>'format' AS new_format,
       tin_rewrite(t) = t AS same_bytes, tin_rewrite(tin_rewrite(t)) = tin_rewrite(t) AS rewrite_is_idempotent,
       tin_info(tin_rewrite(t)) - 'bytes' - 'format' = tin_info(t) - 'bytes' - 'format' AS same_header
FROM store_old;
INSERT INTO store_old SELECT tin_rewrite(t) FROM store_old;
\c
-- one point on each: the format-1 value is decoded whole, the rewritten one
-- read in slices
SELECT count(tin_height(t, ST_Centroid(tin_envelope(t)))) FROM store_old;
SELECT entries AS decoded_values, sliced_values FROM tin_cache_stats();
SELECT count(DISTINCT (SELECT array_agg(tin_height(o.t, ST_SetSRID(ST_MakePoint(ST_XMin(e) + (ST_XMax(e) - ST_XMin(e)) * k / 37.0,
                                                                          ST_YMin(e) + (ST_YMax(e) - ST_YMin(e)) * ((k * 17) % 37) / 37.0), 4326)) ORDER BY k)
                       FROM generate_series(0, 36) k)) AS distinct_height_lists,
       count(DISTINCT (SELECT array_agg(geom ORDER BY id) FROM tin_triangles(o.t, 2))) AS distinct_triangle_lists
FROM store_old o, LATERAL (SELECT tin_envelope(o.t)::box2d AS e) b;
SELECT tin_rewrite(NULL::tin) IS NULL AS strict;
-- a coarse level of a stored value read on its own (tin_triangles,
-- tin_as_geometry): in a fresh backend, levels 0 and 1 are read in slices
-- (the value is not decoded) and give the rows of the decoded value
\c
CREATE TABLE store_levels AS
SELECT l, (SELECT md5(string_agg(id || ':' || coalesce(parent, -1) || ':' || ST_AsEWKT(geom), ',' ORDER BY id)) FROM tin_triangles(t, l)) AS rows,
       md5(ST_AsEWKB(tin_as_geometry(t, l))::text) AS tin_geom
FROM store_terrain, generate_series(0, 1) l;
SELECT entries AS decoded_values, sliced_values FROM tin_cache_stats();
SET tinmerge.cache_size = 0;
SELECT l, rows = (SELECT md5(string_agg(id || ':' || coalesce(parent, -1) || ':' || ST_AsEWKT(geom), ',' ORDER BY id)) FROM tin_triangles(t, l)) AS same_rows,
       tin_geom = md5(ST_AsEWKB(tin_as_geometry(t, l))::text) AS same_tin_geometry
FROM store_levels, store_terrain ORDER BY l;
RESET tinmerge.cache_size;
DROP TABLE store_levels;
-- raster merges on a stored value: a 1 km clip of the DEM (a tile of the
-- terrain) and a 2.5 km corner of it resampled to odd pixels (over the
-- domain's hull). Statistics, coverage-weighted statistics and pixels at
-- every level from the decoded value (tinmerge.cache_size = 0 decodes it on
-- every call); then, each raster in a fresh backend, the same rows read in
-- slices (the triangles under the raster). The clip leaves the value
-- undecoded. The corner's window crosses the domain's edge, and the walk
-- along it then finds the level's hull, which reads every neighbour group
-- of the level (as tin_area_stats of that window does): past an eighth of
-- the groups the backend decodes the value whole, with the same rows
\c
SET extra_float_digits = 0;
CREATE TABLE store_rasters AS
SELECT 1 AS id, ST_Clip(rast, ST_MakeEnvelope(757000, 4051000, 758000, 4052000, 32616)) AS rast FROM dem
UNION ALL
SELECT 2, ST_Rescale(ST_Clip(rast, ST_MakeEnvelope(731000, 4036600, 733500, 4039000, 32616)), 37.3, -41.1) FROM dem;
CREATE FUNCTION store_raster_rows(t tin, r raster, l int) RETURNS text[] LANGUAGE sql AS $$
  SELECT ARRAY[(SELECT md5(string_agg(row(s.*)::text, ',' ORDER BY s.triangle)) FROM tin_raster_stats(t, r, l) s),
               (SELECT md5(string_agg(row(s.*)::text, ',' ORDER BY s.triangle)) FROM tin_raster_stats(t, r, l, weighted => true) s),
               (SELECT md5(string_agg(row(p.*)::text, ',' ORDER BY p.row, p.col)) FROM tin_raster_pixels(t, r, l) p),
               (SELECT count(*)::text FROM tin_raster_pixels(t, r, l))] $$;
SET tinmerge.cache_size = 0;
CREATE TABLE store_rstats AS
SELECT r.id, g.l, store_raster_rows(st.t, r.rast, g.l) AS rows
FROM store_rasters r, store_terrain st, generate_series(0, 4) g(l);
RESET tinmerge.cache_size;
SELECT id, min(rows[4]::int) AS pixels, max(rows[4]::int) FROM store_rstats GROUP BY id ORDER BY id;
\c
SET extra_float_digits = 0;
SELECT count(*) FILTER (WHERE store_raster_rows(st.t, r.rast, x.l) = x.rows) AS same_as_decoded, count(*) AS asked
FROM store_rstats x JOIN store_rasters r USING (id), store_terrain st WHERE x.id = 1;
SELECT entries AS decoded_values, sliced_values FROM tin_cache_stats();
\c
SET extra_float_digits = 0;
SELECT count(*) FILTER (WHERE store_raster_rows(st.t, r.rast, x.l) = x.rows) AS same_as_decoded, count(*) AS asked
FROM store_rstats x JOIN store_rasters r USING (id), store_terrain st WHERE x.id = 2;
SELECT entries AS decoded_values, sliced_values FROM tin_cache_stats();
DROP TABLE store_rasters, store_rstats;
DROP FUNCTION store_raster_rows(tin, raster, int);
DROP TABLE store_terrain, store_pts, store_want, store_old, store_lines, store_cut, store_prof, store_polys, store_area;
