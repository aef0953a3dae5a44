-- tin_as_raster (issue 49): the surface of a level as a raster. Every pixel
-- centre (upper left + (col - 0.5) * scale, as GDAL and ST_Value place it:
-- ar_centre; ST_PixelAsCentroids's points are the centroids of the pixels'
-- polygons, a rounding away on fractional grids) against tin_height (bit for bit, nodata exactly where it has no
-- height) on three grids (the UTM DEM; the geographic DEM; the DEM warped
-- to Albers, 97.3 x 88.9 m pixels from a fractional origin with a nodata
-- border: void triangles), every level; against the triangles' planes as
-- PostGIS reads them (plane_z of 00_setup) at a sample of centres; the
-- pixel-size form's grid against floor/ceil of the extent; bad input.
SET extra_float_digits = 0;
CREATE FUNCTION ar_centre(ulx float8, uly float8, sx float8, sy float8, srid int, col int, "row" int) RETURNS geometry
LANGUAGE sql IMMUTABLE AS $$
  SELECT ST_SetSRID(ST_MakePoint(ulx + (col - 0.5::float8) * sx, uly + ("row" - 0.5::float8) * sy), srid) $$;
CREATE TABLE ar_terrains AS
SELECT 'utm' AS name, t, (SELECT rast FROM dem) AS rast FROM terrain
UNION ALL SELECT 'geographic', tin_from_raster(rast, 2.0, 4), rast FROM dem_geo
UNION ALL SELECT 'albers', tin_from_raster(rast, 2.0, 4), rast FROM dem_albers;
CREATE TABLE ar_pixels AS
SELECT name, level, x, y, val, tin_height(t, geom, level) AS h, geom
FROM (SELECT a.name, a.t, l.level, x, y, val, ar_centre(m.upperleftx, m.upperlefty, m.scalex, m.scaley, m.srid, x, y) AS geom
      FROM ar_terrains a, ST_MetaData(a.rast) m, generate_series(0, tin_num_levels(a.t) - 1) l(level),
           LATERAL unnest(ST_DumpValues(tin_as_raster(a.t, a.rast, l.level), 1, false)) WITH ORDINALITY v(val, i),
           LATERAL (SELECT ((i - 1) % m.width)::int + 1 AS x, ((i - 1) / m.width)::int + 1 AS y) xy) s;
-- every centre: the raster's value is tin_height's, nodata where it is NULL
SELECT name, count(DISTINCT level) AS levels, count(*) AS pixels,
       count(*) FILTER (WHERE h IS NOT NULL) AS on_domain,
       count(*) FILTER (WHERE h IS NULL AND val <> -9999) AS value_off_domain,
       count(*) FILTER (WHERE h IS NOT NULL AND val IS DISTINCT FROM h) AS differ
FROM ar_pixels GROUP BY name ORDER BY name;
-- the albers grid has nodata on its border: pixels off the domain
SELECT name, count(*) FILTER (WHERE h IS NULL) > 0 AS some_off_domain FROM ar_pixels GROUP BY name ORDER BY name;
-- the oracle: the planes of the triangles of level 1 holding a centre
-- (tin_triangles as PostGIS reads them, found by a GiST join), at every
-- 13th centre; and no centre off the domain inside a domain triangle
CREATE TABLE ar_tris AS SELECT name, tr.geom FROM ar_terrains a, tin_triangles(a.t, 1) tr;
CREATE INDEX ON ar_tris USING gist (geom);
ANALYZE ar_tris;
WITH s AS (SELECT * FROM ar_pixels WHERE level = 1 AND (x * 7 + y) % 13 = 0 AND h IS NOT NULL)
SELECT s.name, count(DISTINCT (s.x, s.y)) AS centres,
       max(abs(s.val - plane_z(tr.geom, s.geom))) < 1e-6 AS planes_agree
FROM s JOIN ar_tris tr ON tr.name = s.name AND ST_Intersects(tr.geom, s.geom)
GROUP BY s.name ORDER BY s.name;
SELECT s.name, count(*) FILTER (WHERE EXISTS (
         SELECT 1 FROM ar_tris tr WHERE tr.name = s.name AND ST_Intersects(tr.geom, s.geom))) AS off_domain_but_covered
FROM ar_pixels s WHERE level = 1 AND h IS NULL GROUP BY s.name ORDER BY s.name;
-- the pixel-size form: the grid through (gridx, gridy), the fewest pixels
-- covering the tin's extent (floor and ceil of the extent's edges), the
-- tin's SRID, 32BF holding float4 of tin_height
WITH g AS (SELECT name, t, s, gx, gy, tin_as_raster(t, s, 1, '32BF', gridx => gx, gridy => gy) AS r
           FROM ar_terrains, (VALUES (23.7, 0.25, -0.5)) v(s, gx, gy) WHERE name <> 'geographic'
           UNION ALL
           SELECT name, t, 0.00097, 0.0001, 0, tin_as_raster(t, 0.00097, 1, '32BF', gridx => 0.0001) FROM ar_terrains WHERE name = 'geographic')
SELECT name, ST_SRID(r) = ST_SRID(tin_envelope(t)) AS srid, ST_BandPixelType(r) AS type,
       ST_UpperLeftX(r) = gx + floor((ST_XMin(tin_envelope(t)) - gx) / s) * s AS left_edge,
       ST_UpperLeftY(r) = gy + ceil((ST_YMax(tin_envelope(t)) - gy) / s) * s AS top_edge,
       ST_Width(r) = ceil((ST_XMax(tin_envelope(t)) - gx) / s) - floor((ST_XMin(tin_envelope(t)) - gx) / s) AS width,
       ST_Height(r) = ceil((ST_YMax(tin_envelope(t)) - gy) / s) - floor((ST_YMin(tin_envelope(t)) - gy) / s) AS height,
       (SELECT count(*) FILTER (WHERE p.val IS DISTINCT FROM tin_height(g.t, ar_centre(m.upperleftx, m.upperlefty, m.scalex, m.scaley, m.srid, p.x, p.y), 1)::float4::float8)
        FROM ST_MetaData(r) m, ST_PixelAsCentroids(r, 1, true) p) AS differ,
       (SELECT count(*) FILTER (WHERE tin_height(g.t, ar_centre(m.upperleftx, m.upperlefty, m.scalex, m.scaley, m.srid, p.x, p.y), 1) IS NOT NULL)
        FROM ST_MetaData(r) m, ST_PixelAsCentroids(r, 1, false) p WHERE p.val = -9999) AS nodata_on_domain
FROM g ORDER BY name;
-- the raster tools work on it: hillshade and slope of level 2 over the DEM's grid
SELECT (ST_SummaryStats(ST_HillShade(tin_as_raster(t, rast, 2)))).count > 100000 AS hillshade,
       (ST_SummaryStats(ST_Slope(tin_as_raster(t, rast, 2), 1, '32BF', 'DEGREES'))).max BETWEEN 10 AND 90 AS slope
FROM ar_terrains WHERE name = 'utm';
-- a tile of ST_MakeEmptyCoverage: each tile's pixels as the whole raster's
WITH whole AS (SELECT tin_as_raster(t, 60.0, 3) AS r, t FROM terrain),
     tiles AS (SELECT tin_as_raster(w.t, c, 3) AS r FROM whole w,
                 ST_MakeEmptyCoverage(50, 50, ST_Width(w.r), ST_Height(w.r), ST_UpperLeftX(w.r), ST_UpperLeftY(w.r), 60, -60, 0, 0, 32616) c)
SELECT count(*) AS tiles,
       (SELECT count(*) FROM whole, ST_PixelAsCentroids(whole.r, 1, false)) AS whole_pixels,
       (SELECT count(*) FROM (SELECT ST_AsText(ar_centre(m.upperleftx, m.upperlefty, m.scalex, m.scaley, m.srid, p.x, p.y)), p.val
                              FROM tiles, ST_MetaData(tiles.r) m, ST_PixelAsCentroids(tiles.r, 1, false) p
                              EXCEPT SELECT ST_AsText(ar_centre(m.upperleftx, m.upperlefty, m.scalex, m.scaley, m.srid, p.x, p.y)), p.val
                              FROM whole, ST_MetaData(whole.r) m, ST_PixelAsCentroids(whole.r, 1, false) p) d) AS tile_pixels_not_in_whole
FROM tiles;
-- untyped literals and positional forms
SELECT ST_BandPixelType(tin_as_raster(t, 50, 0, '32bf')) AS untyped_type, ST_Width(tin_as_raster(t, 50, 0)) AS int_size,
       ST_Width(tin_as_raster(t, rast, 0)) AS ref_form FROM terrain, dem;
-- an empty reference raster: an empty raster back
SELECT ST_IsEmpty(tin_as_raster(t, ST_MakeEmptyRaster(0, 0, 0, 0, 1, -1, 0, 0, 32616))) FROM terrain;
-- NULLs: a NULL level is the finest; any other NULL gives NULL
SELECT tin_as_raster(t, d.rast, NULL)::bytea = tin_as_raster(t, d.rast, 4)::bytea AS null_level_is_finest,
       tin_as_raster(NULL::tin, d.rast) IS NULL AS null_tin, tin_as_raster(t, NULL::raster) IS NULL AS null_raster,
       tin_as_raster(t, NULL::float8) IS NULL AS null_size, tin_as_raster(t, d.rast, 0, NULL) IS NULL AS null_type,
       tin_as_raster(t, 50.0, 0, '64BF', NULL) IS NULL AS null_nodata, tin_as_raster(t, 50.0, gridx => NULL) IS NULL AS null_grid
FROM terrain, dem d;
-- bad input, one per line
SELECT try($$SELECT tin_as_raster(t, ST_SetSRID(rast, 4326)) FROM terrain, dem$$);
SELECT try($$SELECT tin_as_raster(t, ST_SetSRID(rast, 0)) FROM terrain, dem$$);
SELECT try($$SELECT tin_as_raster(t, ST_SetSkew(rast, 0.5, 0)) FROM terrain, dem$$);
SELECT try($$SELECT tin_as_raster(t, rast, 9) FROM terrain, dem$$);
SELECT try($$SELECT tin_as_raster(t, rast, -1) FROM terrain, dem$$);
SELECT try($$SELECT tin_as_raster(t, rast, 0, '16BSI') FROM terrain, dem$$);
SELECT try($$SELECT tin_as_raster(t, rast, 0, '64BF', 'NaN') FROM terrain, dem$$);
SELECT try($$SELECT tin_as_raster(t, 0) FROM terrain$$);
SELECT try($$SELECT tin_as_raster(t, -5) FROM terrain$$);
SELECT try($$SELECT tin_as_raster(t, 'Infinity'::float8) FROM terrain$$);
SELECT try($$SELECT tin_as_raster(t, 10, gridx => 'NaN') FROM terrain$$);
SELECT try($$SELECT tin_as_raster(t, 0.1) FROM terrain$$);
SELECT try($$SELECT tin_as_raster(t, 1.2) FROM terrain$$);
SELECT try($$SELECT tin_as_raster(t, ST_MakeEmptyRaster(20000, 20000, 0, 0, 1, -1, 0, 0, 32616)) FROM terrain$$);
SET tinmerge.max_memory = '64MB';
SELECT try($$SELECT tin_as_raster(t, 5.0) FROM terrain$$);
RESET tinmerge.max_memory;
DROP TABLE ar_terrains, ar_pixels, ar_tris;
DROP FUNCTION ar_centre(float8, float8, float8, float8, int, int, int);
