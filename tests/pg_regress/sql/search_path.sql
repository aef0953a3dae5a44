-- The SQL-language wrappers work in sessions whose search_path lacks the
-- extension's and PostGIS's schemas: postgres_fdw's remote sessions run with
-- search_path = pg_catalog, pg_restore with ''. (Found by tests/sharding.sh:
-- tin_surface_area on a shard failed with "function st_isvalidreason does
-- not exist", tin_drape with "type geometry does not exist".)
SET extra_float_digits = 0;
CREATE TABLE sp_feat AS SELECT
  'SRID=32616;LINESTRING(740000 4060000, 741000 4061000, 742500 4060500)'::geometry AS line,
  ST_Buffer('SRID=32616;POINT(741000 4060500)'::geometry, 400) AS area,
  'SRID=32616;POINT(741234 4060777)'::geometry AS pt;
CREATE FUNCTION sp_answers() RETURNS text LANGUAGE sql AS $$
  SELECT concat_ws(' | ',
    public.tin_height(t, pt),
    public.ST_AsText(public.tin_envelope(t)),
    public.ST_NPoints(public.tin_drape(t, line)),
    round(public.tin_line_climb(t, line)::numeric, 6),
    (SELECT count(*) FROM public.tin_line_segments(t, line)),
    (SELECT count(*) FROM public.tin_line_triangles(t, line, NULL, 50.0)),
    (SELECT count(*) FROM public.tin_line_profile(t, line)),
    (SELECT count(*) FROM public.tin_area_triangles(t, area)),
    (SELECT round(area3d::numeric, 3) FROM public.tin_area_stats(t, area)),
    round(public.tin_surface_area(t, area)::numeric, 3),
    (SELECT round(cut::numeric, 1) FROM public.tin_volume(t, area, 500)),
    (SELECT count(*) FROM public.tin_triangles(t, 0)),
    public.ST_NumGeometries(public.tin_as_geometry(t, 0)),
    (SELECT count(*) FROM public.dem d, public.tin_raster_stats(t, d.rast, 0)),
    public.tin_num_triangles(public.tin_from_raster((SELECT d.rast FROM public.dem d), 16.0, 2)))
  FROM public.terrain, public.sp_feat
$$;
SELECT public.sp_answers() AS answers_default_path \gset
SET search_path = pg_catalog;
SELECT public.sp_answers() = :'answers_default_path' AS same_with_pg_catalog;
SET search_path = '';
SELECT public.sp_answers() = :'answers_default_path' AS same_with_empty_path;
RESET search_path;
SELECT :'answers_default_path' <> '' AS answered;
DROP FUNCTION sp_answers();
DROP TABLE sp_feat;
