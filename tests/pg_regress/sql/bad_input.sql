-- Bad input: each case gives an ERROR with an SQLSTATE and a clear message.
SELECT try($$SELECT tin_from_raster(rast, 2.0, 0) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 17) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 1000000) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, -1.0, 3) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, 'NaN'::float8, 3) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, 'Infinity'::float8, 3) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, ARRAY[4, 8]::float8[]) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, ARRAY[4, 4]::float8[]) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, ARRAY[]::float8[]) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, ARRAY[4, NULL]::float8[]) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, ARRAY[8, 'NaN']::float8[]) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, 2) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, 0) FROM dem$$);
SELECT try($$SELECT tin_from_raster(ST_MakeEmptyRaster(0, 0, 0, 0, 1), 2.0)$$);
SELECT try($$SELECT tin_from_raster(ST_MakeEmptyRaster(10, 10, 0, 0, 1), 2.0)$$);
SELECT try($$SELECT tin_from_raster(ST_AddBand(ST_MakeEmptyRaster(10, 10, 0, 0, 1), 1, '32BF'::text, -9999::float8, -9999::float8), 2.0)$$);
SELECT try($$SELECT tin_from_raster(ST_AddBand(ST_MakeEmptyRaster(1, 1, 0, 0, 1), 1, '32BF'::text, 5::float8, -9999::float8), 2.0)$$);
SELECT try($$SELECT tin_from_raster(ST_AddBand(ST_MakeEmptyRaster(3, 1, 0, 0, 1), 1, '32BF'::text, 5::float8, -9999::float8), 2.0)$$);
SELECT try($$SELECT tin_from_points('MULTIPOINT(0 0, 1 1, 2 0)'::geometry, 1)$$);
SELECT try($$SELECT tin_from_points('MULTIPOINT Z (0 0 1, 1 1 1, 2 2 1)'::geometry, 1)$$);
SELECT try($$SELECT tin_from_points('MULTIPOINT Z (0 0 1, 1 1 1)'::geometry, 1)$$);
SELECT try($$SELECT tin_from_points('MULTIPOINT Z (0 0 1, 0 0 2, 0 0 3)'::geometry, 1)$$);
SELECT try($$SELECT tin_from_points('MULTIPOINT Z EMPTY'::geometry, 1)$$);
SELECT try($$SELECT tin_from_points('MULTIPOINT ZM (0 0 1 1, 1 0 1 1, 0 1 1 1)'::geometry, 1)$$);
SELECT try($$SELECT tin_from_points(ST_Collect(ARRAY[ST_MakePoint(0, 0, 1), ST_MakePoint(1, 0, 'NaN'::float8), ST_MakePoint(0, 1, 1)]), 1)$$);
SELECT try($$SELECT tin_from_points(ST_Collect(ARRAY[ST_MakePoint(0, 0, 1), ST_MakePoint('Infinity'::float8, 0, 1), ST_MakePoint(0, 1, 1)]), 1)$$);
SELECT try($$SELECT tin_from_points('MULTIPOINT Z (0 0 1, 1 0 1, 0 1 1)'::geometry, 'NaN'::float8)$$);
SELECT try($$SELECT tin_from_points('MULTIPOINT Z (0 0 1, 1 0 1, 0 1 1)'::geometry, 1, 0)$$);
SELECT try($$SELECT tin_num_triangles(t, 5) FROM terrain$$);
SELECT try($$SELECT tin_num_triangles(t, -1) FROM terrain$$);
SELECT try($$SELECT tin_tolerance(t, 99) FROM terrain$$);
SELECT try($$SELECT count(*) FROM terrain, tin_triangles(t, 5)$$);
SELECT try($$SELECT tin_as_geometry(t, -2) FROM terrain$$);
-- hostile values: truncated, wrong magic, bit flips, huge counts
SELECT try($$SELECT ''::tin$$);
SELECT try($$SELECT 'zz'::tin$$);
SELECT try($$SELECT 'ABC'::tin$$);
SELECT try($$SELECT '00FF'::tin$$);
SELECT try($$SELECT left(t::text, 100)::tin FROM terrain$$);
SELECT try($$SELECT left(t::text, length(t::text) - 2)::tin FROM terrain$$);
SELECT try($$SELECT ('58' || substr(t::text, 3))::tin FROM terrain$$);
SELECT try($$SELECT (left(t::text, 8) || '0200' || substr(t::text, 13))::tin FROM terrain$$);
SELECT try($$SELECT (left(t::text, 32) || 'FF' || substr(t::text, 35))::tin FROM terrain$$);
SELECT try($$SELECT (left(t::text, 40) || 'FFFFFF7F' || substr(t::text, 49))::tin FROM terrain$$);
SELECT try($$SELECT (left(t::text, 4000) || 'FF' || substr(t::text, 4003))::tin FROM terrain$$);
SELECT try($$SELECT (left(t::text, 20000) || '7F' || substr(t::text, 20003))::tin FROM terrain$$);
-- nothing above broke the backend
SELECT tin_num_levels(t) FROM terrain;
-- point merge
SELECT try($$SELECT tin_height(t, 'SRID=4326;POINT(-84 36)'::geometry) FROM terrain$$);
SELECT try($$SELECT tin_locate(t, 'SRID=32616;LINESTRING(0 0, 1 1)'::geometry) FROM terrain$$);
SELECT try($$SELECT tin_height(t, 'SRID=32616;MULTIPOINT(0 0, 1 1)'::geometry) FROM terrain$$);
SELECT try($$SELECT tin_height(t, 'SRID=32616;POLYGON EMPTY'::geometry) FROM terrain$$);
SELECT try($$SELECT tin_height(t, 'SRID=32616;POINT(740000 4060000)'::geometry, 5) FROM terrain$$);
SELECT try($$SELECT tin_locate(t, 'SRID=32616;POINT(740000 4060000)'::geometry, -1) FROM terrain$$);
SELECT try($$SELECT tin_height(t, 'SRID=32616;POINT M (740000 4060000 1)'::geometry) FROM terrain$$);
SELECT try($$SELECT tin_drape(t, 'SRID=4326;MULTIPOINT(-84 36)'::geometry) FROM terrain$$);
SELECT try($$SELECT tin_footprint(t, 'SRID=32616;POINT(740000 4060000)'::geometry, -1, 10, 0) FROM terrain$$);
SELECT try($$SELECT tin_footprint(t, 'SRID=32616;POINT(740000 4060000)'::geometry, 10, 'NaN', 0) FROM terrain$$);
SELECT try($$SELECT tin_footprint(t, 'SRID=32616;POINT(740000 4060000)'::geometry, 10, 10, 'Infinity') FROM terrain$$);
-- line merge: wrong type, SRID, width; linetree values
SELECT try($$SELECT * FROM terrain, tin_line_triangles(t, 'SRID=32616;POINT(740000 4060000)'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_line_segments(t, 'SRID=32616;POLYGON((740000 4060000, 741000 4060000, 740000 4061000, 740000 4060000))'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_line_profile(t, 'SRID=4326;LINESTRING(-84 36, -84.1 36.1)'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_line_triangles(t, 'SRID=32616;LINESTRING(740000 4060000, 741000 4061000)'::geometry, NULL, -5)$$);
SELECT try($$SELECT * FROM terrain, tin_line_triangles(t, 'SRID=32616;LINESTRING(740000 4060000, 741000 4061000)'::geometry, NULL, 'NaN')$$);
SELECT try($$SELECT * FROM terrain, tin_line_triangles(t, 'SRID=32616;LINESTRING(740000 4060000, 741000 4061000)'::geometry, 9)$$);
SELECT try($$SELECT tin_line_climb(t, 'SRID=32616;LINESTRING M (740000 4060000 1, 741000 4061000 2)'::geometry) FROM terrain$$);
SELECT try($$SELECT tin_linetree('SRID=32616;POINT(740000 4060000)'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_line_triangles(t, tin_linetree('SRID=4326;LINESTRING(-84 36, -84.1 36.1)'::geometry))$$);
SELECT try($$SELECT 'zz'::linetree$$);
SELECT try($$SELECT '00'::linetree$$);
SELECT try($$SELECT overlay(tin_linetree('LINESTRING(0 0, 1 1, 2 0)'::geometry)::text placing 'FF' from 200 for 2)::linetree$$);
SELECT try($$SELECT left(tin_linetree('LINESTRING(0 0, 1 1, 2 0)'::geometry)::text, 150)::linetree$$);
SELECT try($$SELECT tin_footprint(t, 'SRID=32616;LINESTRING(0 0, 1 1)'::geometry, 10, 10, 0) FROM terrain$$);
SELECT try($$SELECT tin_footprint(t, 'SRID=4326;POINT(-84 36)'::geometry, 10, 10, 0) FROM terrain$$);
-- area merge
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, 'SRID=32616;POINT(740000 4060000)'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, 'SRID=32616;LINESTRING(740000 4060000, 741000 4061000)'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, 'SRID=32616;GEOMETRYCOLLECTION(POLYGON((740000 4060000, 741000 4060000, 741000 4061000, 740000 4060000)))'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, 'SRID=4326;POLYGON((-84 36, -84.1 36, -84.1 36.1, -84 36))'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, 'SRID=32616;POLYGON((740000 4060000, 741000 4061000, 741000 4060000, 740000 4061000, 740000 4060000))'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, 'SRID=32616;POLYGON((740000 4060000, 741000 4060000, 742000 4060000, 740000 4060000))'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, 'SRID=32616;MULTIPOLYGON(((740000 4060000, 742000 4060000, 742000 4062000, 740000 4060000)), ((741000 4060000, 743000 4060000, 743000 4062000, 741000 4060000)))'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, 'SRID=32616;POLYGON((740000 4060000, 741000 4060000, 741000 4061000, 740000 4060000), (745000 4060000, 746000 4060000, 746000 4061000, 745000 4060000))'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, ST_SetSRID(ST_MakePolygon(ST_MakeLine(ARRAY[ST_MakePoint(740000, 4060000), ST_MakePoint('NaN', 4061000), ST_MakePoint(741000, 4060000), ST_MakePoint(740000, 4060000)])), 32616))$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, 'SRID=32616;POLYGON M ((740000 4060000 1, 741000 4060000 1, 741000 4061000 1, 740000 4060000 1))'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, ST_Expand(tin_envelope(t), -10), 5)$$);
SELECT try($$SELECT * FROM terrain, tin_area_triangles(t, ST_Expand(tin_envelope(t), -10), -1)$$);
SELECT try($$SELECT * FROM terrain, tin_area_stats(t, 'SRID=32616;POLYGON((740000 4060000, 741000 4061000, 741000 4060000, 740000 4061000, 740000 4060000))'::geometry)$$);
SELECT try($$SELECT * FROM terrain, tin_volume(t, ST_Expand(tin_envelope(t), -10), 'NaN')$$);
SELECT try($$SELECT * FROM terrain, tin_volume(t, ST_Expand(tin_envelope(t), -10), 'Infinity')$$);
SELECT try($$SELECT * FROM terrain, tin_volume(t, 'SRID=32616;POINT(740000 4060000)'::geometry, 0)$$);
-- raster merge
SELECT try($$SELECT * FROM terrain, dem, tin_raster_stats(t, ST_SetSRID(rast, 4326))$$);
SELECT try($$SELECT * FROM terrain, dem, tin_raster_stats(t, ST_SetSRID(rast, 0))$$);
SELECT try($$SELECT * FROM terrain, dem, tin_raster_pixels(t, ST_SetSkew(rast, 0.5, 0))$$);
SELECT try($$SELECT * FROM terrain, dem, tin_raster_stats(t, ST_SetScale(rast, 0, -90), weighted => true)$$);
SELECT try($$SELECT * FROM terrain, dem, tin_raster_stats(t, rast, 0, 2)$$);
SELECT try($$SELECT * FROM terrain, dem, tin_raster_stats(t, rast, 0, 0)$$);
SELECT try($$SELECT * FROM terrain, dem, tin_raster_pixels(t, rast, 0, -1)$$);
SELECT try($$SELECT * FROM terrain, dem, tin_raster_stats(t, rast, 9)$$);
SELECT try($$SELECT * FROM terrain, dem, tin_paint(t, rast)$$);
SELECT try($$SELECT * FROM terrain, dem, tin_paint(t, ST_SetSRID(ST_ColorMap(rast, 'bluered'), 4326))$$);
SELECT try($$SELECT * FROM terrain, tin_raster_stats(t, '0100000100000000000080564000000000008056c0000000004095264100000000b0f94e4100000000000000000000000000000000687f00000a000a008a003c1cc6002f746d702f616273656e742e74696600'::raster)$$);
SELECT try($$SELECT * FROM terrain, tin_paint(t, '0100000100000000000080564000000000008056c0000000004095264100000000b0f94e4100000000000000000000000000000000687f00000a000a008a003c1cc6002f746d702f616273656e742e74696600'::raster)$$);
SELECT try($$SELECT count(*) FROM terrain a, tin_overlay(a.t, tin_from_points('SRID=4326;MULTIPOINT Z (0 0 1, 1 0 1, 0 1 1)'::geometry, 1))$$);
SELECT try($$SELECT count(*) FROM terrain a, tin_overlay(a.t, a.t, -1, 0)$$);
SELECT try($$SELECT count(*) FROM terrain a, tin_overlay(a.t, a.t, 0, 5)$$);
SELECT try($$SELECT tin_overlay_tin(a.t, a.t, 5, 0) FROM terrain a$$);
SELECT try($$SELECT * FROM terrain a, tin_difference(a.t, a.t, 0, -2)$$);
SELECT try($$SELECT count(*) FROM terrain a, tin_overlay(a.t, overlay(a.t::text placing 'FF' from 900 for 2)::tin)$$);
-- more hostile coordinates and degenerate inputs (issue 8): coordinates
-- beyond 1e100 are refused (exact predicates would overflow); huge sizes
-- and degenerate lines work
SELECT try($$SELECT tin_height(t, ST_SetSRID(ST_MakePoint('NaN', 4060000), 32616)) FROM terrain$$);
SELECT try($$SELECT tin_height(t, ST_SetSRID(ST_MakePoint('Infinity', 4060000), 32616)) FROM terrain$$);
SELECT try($$SELECT tin_locate(t, ST_SetSRID(ST_MakePoint(1e308, -1e308), 32616)) FROM terrain$$);
SELECT try($$SELECT tin_drape(t, ST_SetSRID(ST_MakeLine(ST_MakePoint(740000, 4060000), ST_MakePoint('NaN', 4061000)), 32616)) FROM terrain$$);
SELECT try($$SELECT count(*) FROM terrain, tin_line_segments(t, ST_SetSRID(ST_MakeLine(ST_MakePoint(740000, 4060000), ST_MakePoint(741000, 'Infinity')), 32616))$$);
SELECT count(*) FROM terrain, tin_line_segments(t, 'SRID=32616;LINESTRING(740000 4060000, 740000 4060000)'::geometry);
SELECT count(*) FROM terrain, tin_line_triangles(t, 'SRID=32616;LINESTRING(740000 4060000, 740000 4060000)'::geometry, 0, 1e308);
SELECT try($$SELECT count(*) FROM terrain, tin_line_triangles(t, 'SRID=32616;GEOMETRYCOLLECTION EMPTY'::geometry)$$);
SELECT try($$SELECT count(*) FROM terrain, tin_line_triangles(t, tin_linetree('SRID=32616;LINESTRING(1e300 1e300, -1e300 -1e300)'::geometry), 0)$$);
SELECT try($$SELECT tin_linetree(ST_SetSRID(ST_MakeLine(ST_MakePoint(0, 0), ST_MakePoint('NaN', 1)), 32616))$$);
SELECT count(*) FROM terrain, tin_footprint(t, 'SRID=32616;POINT(740000 4060000)'::geometry, 1e308, 1e308, 0, 0);
SELECT try($$SELECT count(*) FROM terrain, tin_area_triangles(t, 'SRID=32616;POLYGON((740000 4060000, 740000 4060000, 740000 4060000, 740000 4060000))'::geometry)$$);
SELECT try($$SELECT count(*) FROM terrain, tin_area_triangles(t, 'SRID=32616;POLYGON((-1e300 -1e300, 1e300 -1e300, 1e300 1e300, -1e300 -1e300))'::geometry, 0)$$);
SELECT count(*) FROM terrain, tin_volume(t, 'SRID=32616;POLYGON((740000 4060000, 741000 4060000, 741000 4061000, 740000 4060000))'::geometry, 1e308);
-- rasters for every raster function: empty and all-nodata give no rows, a
-- single pixel works (its triangle gets it), a band of NaN has no valid pixels
SELECT count(*) FROM terrain, tin_raster_stats(t, ST_MakeEmptyRaster(0, 0, 740000, 4060000, 30, -30, 0, 0, 32616));
SELECT count(*) FROM terrain, tin_raster_pixels(t, ST_MakeEmptyRaster(0, 0, 740000, 4060000, 30, -30, 0, 0, 32616));
SELECT count(*) FROM terrain, tin_paint(t, ST_MakeEmptyRaster(0, 0, 740000, 4060000, 30, -30, 0, 0, 32616));
SELECT try($$SELECT count(*) FROM terrain, tin_raster_stats(t, ST_MakeEmptyRaster(10, 10, 740000, 4060000, 30, -30, 0, 0, 32616))$$);
SELECT count(*) FROM terrain, tin_raster_stats(t, ST_AddBand(ST_MakeEmptyRaster(10, 10, 740000, 4060000, 30, -30, 0, 0, 32616), '32BF'::text, -9999, -9999));
SELECT count(*) FROM terrain, tin_raster_stats(t, ST_AddBand(ST_MakeEmptyRaster(10, 10, 740000, 4060000, 30, -30, 0, 0, 32616), '32BF'::text, -9999, -9999), weighted => true);
SELECT count(*) FROM terrain, tin_raster_pixels(t, ST_AddBand(ST_MakeEmptyRaster(10, 10, 740000, 4060000, 30, -30, 0, 0, 32616), '32BF'::text, -9999, -9999));
SELECT string_agg(count::text || ':' || mean::text, ',') FROM terrain, tin_raster_stats(t, ST_AddBand(ST_MakeEmptyRaster(1, 1, 741000, 4061000, 30, -30, 0, 0, 32616), '32BF'::text, 7, -9999), 0);
SELECT count(*) FROM terrain, tin_raster_stats(t, ST_AddBand(ST_MakeEmptyRaster(1, 1, 741000, 4061000, 30, -30, 0, 0, 32616), '32BF'::text, 7, -9999), 0, 1, true);
SELECT try($$SELECT count(*) FROM terrain, tin_raster_pixels(t, ST_MakeEmptyRaster(10, 10, 740000, 4060000, 30, -30, 0, 0, 32616), 0, 3)$$);
SELECT try($$SELECT count(*) FROM terrain, tin_paint(t, ST_AddBand(ST_MakeEmptyRaster(10, 10, 740000, 4060000, 30, -30, 0, 0, 32616), '8BUI'::text, 1, 0))$$);
SELECT count(*) FROM terrain, tin_raster_stats(t, ST_AddBand(ST_MakeEmptyRaster(10, 10, 740000, 4060000, 30, -30, 0, 0, 32616), '32BF'::text, 'NaN'::float8, -9999));
-- tin equality on damaged values never gets past the header check
SELECT try($$SELECT t = overlay(t::text placing 'FF' from 900 for 2)::tin FROM terrain$$);
-- NULL and empty inputs give NULL (or no rows), never an error
SELECT tin_height(NULL::tin, 'POINT(0 0)'::geometry) IS NULL AS null_tin,
       tin_height(t, NULL::geometry) IS NULL AS null_geom,
       tin_height(t, 'SRID=32616;POINT EMPTY'::geometry) IS NULL AS empty_point,
       tin_locate(t, 'SRID=32616;POINT EMPTY'::geometry) IS NULL AS empty_locate,
       tin_drape(t, 'SRID=32616;MULTIPOINT EMPTY'::geometry) IS NULL AS empty_drape,
       (SELECT count(*) FROM tin_footprint(t, NULL, 1, 1, 0)) AS null_footprint,
       (SELECT count(*) FROM tin_footprint(t, 'SRID=32616;POINT EMPTY'::geometry, 1, 1, 0)) AS empty_footprint,
       (SELECT count(*) FROM tin_raster_stats(NULL, NULL)) AS null_raster_stats,
       (SELECT count(*) FROM dem, tin_raster_stats(t, rast, 0, 1, NULL)) AS null_weighted,
       (SELECT count(*) FROM dem, tin_paint(NULL, rast)) AS null_paint
FROM terrain;

-- What PostGIS users type (issue 44), one mistake per line: each an ERROR
-- whose message or HINT names the fix.
-- a point without an SRID on a tin with one (PostGIS refuses mixed SRIDs,
-- 0 included; it used to be taken as if in the tin's SRID)
SELECT tin_height(t, 'POINT(740000 4060000)'::geometry) FROM terrain;
-- longitude/latitude without an SRID on a UTM tin (it answered NULL)
SELECT tin_height(t, 'POINT(-84.2 36.4)'::geometry) FROM terrain;
-- a line without an SRID, as an untyped literal
SELECT count(*) FROM terrain, tin_line_segments(t, 'LINESTRING(740000 4060000, 741000 4061000)');
-- a tin without an SRID queried with a geometry that has one
SELECT tin_height(tin_from_points('MULTIPOINT Z (0 0 1, 10 0 2, 0 10 3)'::geometry, 1, 1), 'SRID=32616;POINT(1 1)'::geometry);
-- breaklines or a boundary without an SRID
SELECT tin_from_raster(rast, 2.0, 3, soft_breaklines => 'LINESTRING(740000 4060000, 741000 4061000)'::geometry) FROM dem;
SELECT tin_from_raster(rast, 2.0, 3, boundary => 'POLYGON((740000 4060000, 741000 4060000, 741000 4061000, 740000 4060000))'::geometry) FROM dem;
-- a geography (PostgreSQL has no implicit cast to geometry; the error was
-- "function does not exist")
SELECT tin_height(t, 'SRID=4326;POINT(-84.2 36.4)'::geography) FROM terrain;
SELECT count(*) FROM terrain, tin_area_stats(t, 'SRID=4326;POLYGON((-84.2 36.4, -84.1 36.4, -84.1 36.5, -84.2 36.4))'::geography);
-- a 2D polygon as breaklines: named as the wrong type (it used to be told
-- it has no Z, then refused as soft_breaklines as a polygon)
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, breaklines => ST_MakeEnvelope(740000, 4060000, 741000, 4061000, 32616)) FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, soft_breaklines => ST_MakeEnvelope(740000, 4060000, 741000, 4061000, 32616)) FROM dem$$);
-- untyped literals where a function has two forms: the line functions
-- (geometry and linetree) and tin_from_raster's tolerance (float8 and
-- float8[]) take them as a geometry and as one float8
SELECT count(*) AS segments, round(sum(length2d)::numeric, 3) AS length2d,
       (SELECT count(*) FROM terrain, tin_line_triangles(t, 'SRID=32616;LINESTRING(740000 4060000, 741000 4061000)')) AS triangles,
       (SELECT count(*) FROM terrain, tin_line_profile(t, 'SRID=32616;LINESTRING(740000 4060000, 741000 4061000)')) AS profile_points,
       (SELECT tin_line_climb(t, 'SRID=32616;LINESTRING(740000 4060000, 741000 4061000)') FROM terrain)
         = (SELECT tin_line_climb(t, 'SRID=32616;LINESTRING(740000 4060000, 741000 4061000)'::geometry) FROM terrain) AS climb_same
FROM terrain, tin_line_segments(t, 'SRID=32616;LINESTRING(740000 4060000, 741000 4061000)');
SELECT tin_height(t, 'SRID=32616;POINT(740000 4060000)') = tin_height(t, 'SRID=32616;POINT(740000 4060000)'::geometry) AS point_literal,
       (SELECT count(*) FROM tin_footprint(t, 'SRID=32616;POINT(740000 4060000)', 30, 80, 45)) > 0 AS footprint_literal,
       (SELECT round(area2d) FROM tin_area_stats(t, 'SRID=32616;POLYGON((740000 4060000, 740600 4060000, 740600 4060400, 740000 4060000))')) AS area_literal
FROM terrain;
SELECT tin_from_raster(rast, NULL, 3) IS NULL AS null_tolerance_gives_null FROM dem;
SELECT tin_num_levels(tin_from_raster(rast, '8', 2)) AS text_tolerance_levels FROM dem;
SELECT try($$SELECT tin_from_raster(rast, 'Infinity', 3) FROM dem$$);
SELECT tin_num_levels(tin_from_raster(rast, '{16,8,4}')) AS array_literal_levels FROM dem;
