-- The SQL-language wrappers work in sessions whose search_path lacks the
-- extension's and PostGIS's schemas: postgres_fdw's remote sessions run with
-- search_path = pg_catalog, pg_restore with ''. (Found by tests/sharding.sh:
-- tin_surface_area on a shard failed with "function st_isvalidreason does
-- not exist", tin_drape with "type geometry does not exist".)
SET extra_float_digits = 0;
CREATE TABLE sp_feat AS SELECT
  'SRID=32616;LINESTRING(740000 4060000, 741000 4061000, 742500 4060500)'::geometry AS line,
  ST_Buffer('SRID=32616;POINT(741000 4060500)'::geometry, 400) AS area,
  'SRID=32616;POINT(741234 4060777)'::geometry AS pt,
  -- not convex: its validity is PostGIS's verdict (ST_IsValidReason)
  'SRID=32616;POLYGON((740500 4060000, 741500 4060000, 741500 4061000, 741000 4060400, 740500 4061000, 740500 4060000))'::geometry AS concave;
-- a geographic tin: the area functions read its spheroid in spatial_ref_sys
CREATE TABLE sp_geo AS SELECT tin_from_raster(rast, 8.0, 2) AS t FROM dem_geo;
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
    (SELECT round(area3d::numeric, 3) FROM public.tin_area_stats(t, concave)),
    (SELECT round(s.area2d::numeric, 0) FROM public.sp_geo g, public.tin_area_stats(g.t, public.ST_Expand(public.tin_envelope(g.t), -0.002)) s),
    round(public.tin_surface_area(t, area)::numeric, 3),
    (SELECT round(cut::numeric, 1) FROM public.tin_volume(t, area, 500)),
    (SELECT count(*) FROM public.tin_triangles(t, 0)),
    public.ST_NumGeometries(public.tin_as_geometry(t, 0)),
    coalesce(pg_catalog.length(public.tin_quantized_mesh(t, 0, 0, 0)), -1),
    (SELECT count(*) FROM public.dem d, public.tin_raster_stats(t, d.rast, 0)),
    public.tin_num_triangles(public.tin_from_raster((SELECT d.rast FROM public.dem d), 16.0, 2)))
  FROM public.terrain, public.sp_feat
$$;
-- the first calls of this backend run without PostGIS on the path: what
-- the Rust functions look up once per backend (PostGIS's schema, the OID of
-- ST_IsValidReason, an SRID's spheroid) is looked up there
SET search_path = '';
SELECT public.sp_answers() AS answers_empty_path \gset
RESET search_path;
SELECT public.sp_answers() = :'answers_empty_path' AS same_with_default_path;
SET search_path = pg_catalog;
SELECT public.sp_answers() = :'answers_empty_path' AS same_with_pg_catalog;
RESET search_path;
SELECT :'answers_empty_path' <> '' AS answered;
DROP FUNCTION sp_answers();
DROP TABLE sp_feat, sp_geo;
