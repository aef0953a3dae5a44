-- tinmerge 0.15.0 -> 0.16.0. No stored value and no answer changes. The
-- functions that take a tin gain a planner support function: calling it
-- loads tinmerge while PostgreSQL simplifies a query, before it sizes the
-- query's tables, so a table with a tin column that no VACUUM or ANALYZE
-- has seen is sized by its rows (src/pg/planner.rs; docs/scaling.md, "Join
-- forms and parallel plans").
CREATE FUNCTION "_tin_plan_support"("_request" internal) RETURNS internal
IMMUTABLE STRICT PARALLEL SAFE
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_plan_support_wrapper';
COMMENT ON FUNCTION _tin_plan_support(internal) IS 'Planner support of the functions taking a tin: answers no request; calling it loads tinmerge before the planner sizes the query''s tables, so a terrain table never analyzed is sized by its rows (docs/scaling.md).';
ALTER FUNCTION tin_area_stats(tin,geography,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_area_stats(tin,geometry,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_area_stats(tin,text,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_area_triangles(tin,geography,integer,boolean) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_area_triangles(tin,geometry,integer,boolean) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_area_triangles(tin,text,integer,boolean) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_as_geometry(tin,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_as_gltf(tin,integer,raster,double precision) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_as_svg(tin,integer,integer[],double precision[],text[],geometry,text,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_contours(tin,double precision,integer,double precision) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_difference(tin,tin,integer,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_drape(tin,geography,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_drape(tin,geometry,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_drape(tin,text,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_envelope(tin) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_footprint(tin,geography,double precision,double precision,double precision,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_footprint(tin,geometry,double precision,double precision,double precision,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_footprint(tin,text,double precision,double precision,double precision,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_height(tin,geography,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_height(tin,geometry,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_height(tin,text,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_info(tin) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_climb(tin,geography,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_climb(tin,geometry,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_climb(tin,linetree,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_climb(tin,text,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_profile(tin,geography,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_profile(tin,geometry,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_profile(tin,linetree,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_profile(tin,text,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_segments(tin,geography,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_segments(tin,geometry,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_segments(tin,linetree,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_segments(tin,text,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_triangles(tin,geography,integer,double precision) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_triangles(tin,geometry,integer,double precision) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_triangles(tin,linetree,integer,double precision) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_line_triangles(tin,text,integer,double precision) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_locate(tin,geography,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_locate(tin,geometry,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_locate(tin,text,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_num_levels(tin) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_num_triangles(tin,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_num_vertices(tin,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_overlay(tin,tin,integer,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_overlay_tin(tin,tin,integer,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_paint(tin,raster,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_quantized_mesh(tin,integer,integer,integer,boolean,double precision) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_quantized_mesh(tin,integer,integer,integer,integer,boolean,double precision) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_quantized_mesh(tin[],integer,integer,integer,boolean,double precision) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_quantized_mesh_layer(tin,boolean,boolean,text) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_quantized_mesh_layer(tin[],boolean,boolean,text) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_raster_pixels(tin,raster,integer,integer,boolean) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_raster_stats(tin,raster,integer,integer,boolean,boolean) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_rewrite(tin) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_slope_aspect(tin,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_srid(tin) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_surface_area(tin,geography,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_surface_area(tin,geometry,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_surface_area(tin,text,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_tolerance(tin,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_triangles(tin,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_validate(tin) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_validate(tin,raster,integer,geometry) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_volume(tin,geography,double precision,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_volume(tin,geometry,double precision,integer) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_volume(tin,text,double precision,integer) SUPPORT _tin_plan_support;
