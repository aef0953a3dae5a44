-- Issue 43: the tolerance holds on the whole surface, not only at the pixel
-- centres. Along a grid line between two valid pixel centres the DEM is the
-- straight line between them; gdal_contour puts its contour vertices on
-- those lines at their contour's height (GDAL's own interpolation, the
-- independent oracle here). Up to 0.10.0 a coarse edge kept its coarse
-- heights into every finer level: contour vertices were up to 7.8x the
-- finest tolerance off.
SET extra_float_digits = 0;
-- The UTM DEM has nodata: built over its valid pixels (the default) and
-- on its lattice with the gaps filled; the geographic DEM has none. Both
-- also within a boundary (boundary.sql's: a concave shell reaching past
-- the data, a hole, a second square; until 0.12.0 such builds were held
-- at the samples only, and between samples they left holes and cracks
-- along the rings), and with soft breaklines (a zigzag, a line along a
-- pixel row, one running off the raster).
CREATE FUNCTION bs_pt(r raster, fx float8, fy float8) RETURNS geometry
LANGUAGE sql IMMUTABLE AS $$
  SELECT ST_SetSRID(ST_MakePoint(ST_XMin(e) + fx * (ST_XMax(e) - ST_XMin(e)),
                                 ST_YMax(e) - fy * (ST_YMax(e) - ST_YMin(e))), ST_SRID(r))
  FROM (SELECT ST_Envelope(r) AS e) s $$;
CREATE FUNCTION bs_line(r raster, VARIADIC f float8[]) RETURNS geometry
LANGUAGE sql IMMUTABLE AS $$
  SELECT ST_MakeLine(array_agg(bs_pt(r, f[i], f[i + 1]) ORDER BY i))
  FROM generate_series(1, array_length(f, 1), 2) i $$;
CREATE FUNCTION bs_ring(r raster, VARIADIC f float8[]) RETURNS geometry
LANGUAGE sql IMMUTABLE AS $$ SELECT ST_AddPoint(bs_line(r, VARIADIC f), bs_pt(r, f[1], f[2])) $$;
-- hard breaklines (heights of their own: an embankment 4 m over the DEM,
-- a level cut at 300 m, one running off the raster at the DEM's height):
-- held between samples too since 0.13.0, but on the grid segments the
-- lines cut, where the surface is the lines' own
CREATE FUNCTION bs_line_z(r raster, dz float8, VARIADIC f float8[]) RETURNS geometry
LANGUAGE sql IMMUTABLE AS $$
  SELECT ST_MakeLine(array_agg(ST_SetSRID(ST_MakePoint(ST_X(p), ST_Y(p),
           CASE WHEN ST_Intersects(ST_Envelope(r), p) THEN ST_Value(r, 1, p) + dz ELSE 300 END), ST_SRID(r)) ORDER BY i))
  FROM generate_series(1, array_length(f, 1), 2) i, LATERAL bs_pt(r, f[i], f[i + 1]) p $$;
CREATE TABLE bs_hard AS
  SELECT d.dem, ST_Collect(ARRAY[
           bs_line_z(d.rast, 4.0, 0.11,0.23, 0.37,0.41, 0.52,0.18, 0.83,0.57),
           ST_Force3D(bs_line(d.rast, 0.2013,0.7511, 0.6,0.7), 300),
           bs_line_z(d.rast, 0.0, 0.7,0.8, 1.3,0.93)]) AS lines
  FROM (SELECT 'utm' AS dem, rast FROM dem UNION ALL SELECT 'geographic', rast FROM dem_geo) d;
CREATE TABLE bs_terrain AS
  SELECT 'utm' AS dem, 'valid pixels' AS build, tin_from_raster(rast, 2.0, 5) AS t FROM dem
  UNION ALL
  SELECT 'utm', 'gaps filled', tin_from_raster(rast, 2.0, 5, fill_gaps => true) FROM dem
  UNION ALL
  SELECT 'geographic', 'lattice', tin_from_raster(rast, 2.0, 5) FROM dem_geo
  UNION ALL
  SELECT d.dem, 'boundary',
         tin_from_raster(d.rast, 2.0, 5, boundary => ST_Collect(
           ST_MakePolygon(bs_ring(d.rast, 0.08,0.10, 0.70,0.06, 0.52,0.43, 1.30,0.50, 0.81,0.77, 0.17,0.70),
                          ARRAY[bs_ring(d.rast, 0.30,0.33, 0.42,0.37, 0.40,0.48, 0.27,0.45)]),
           ST_MakePolygon(bs_ring(d.rast, 0.10,0.82, 0.25,0.82, 0.25,0.95, 0.10,0.95))))
  FROM (SELECT 'utm' AS dem, rast FROM dem UNION ALL SELECT 'geographic', rast FROM dem_geo) d
  UNION ALL
  SELECT d.dem, 'soft breaklines',
         tin_from_raster(d.rast, 2.0, 5, soft_breaklines => ST_Collect(ARRAY[
           bs_line(d.rast, 0.11,0.23, 0.37,0.41, 0.52,0.18, 0.83,0.57),
           ST_MakeLine(ST_PixelAsCentroid(d.rast, ST_Width(d.rast) / 5, ST_Height(d.rast) * 3 / 4),
                       ST_PixelAsCentroid(d.rast, ST_Width(d.rast) * 3 / 5, ST_Height(d.rast) * 3 / 4)),
           bs_line(d.rast, 0.7,0.8, 1.3,0.93)]))
  FROM (SELECT 'utm' AS dem, rast FROM dem UNION ALL SELECT 'geographic', rast FROM dem_geo) d
  UNION ALL
  SELECT d.dem, 'hard breaklines', tin_from_raster(d.rast, 2.0, 5, breaklines => h.lines)
  FROM (SELECT 'utm' AS dem, rast FROM dem UNION ALL SELECT 'geographic', rast FROM dem_geo) d
       JOIN bs_hard h USING (dem);
-- the contour vertices on a grid line between two valid pixel centres
-- (those gdal_contour puts on the half-pixel lines beside nodata follow
-- its own rule there, not the raster's surface)
CREATE TABLE bs_valid AS
  SELECT d.dem, p.x - 1 AS col, p.y - 1 AS "row"
  FROM (SELECT 'utm' AS dem, rast FROM dem UNION ALL SELECT 'geographic', rast FROM dem_geo) d,
       ST_PixelAsPoints(d.rast, 1, true) p;
CREATE UNIQUE INDEX ON bs_valid (dem, col, "row");
CREATE TABLE bs_vertices AS
  WITH v AS (
    SELECT 'utm' AS dem, elev, (ST_DumpPoints(geom)).geom AS p FROM contours
    UNION ALL
    SELECT 'geographic', elev, (ST_DumpPoints(geom)).geom FROM contours_geo),
  g AS (SELECT 'utm' AS dem, ST_UpperLeftX(rast) AS ulx, ST_UpperLeftY(rast) AS uly,
               ST_ScaleX(rast) AS sx, ST_ScaleY(rast) AS sy FROM dem
        UNION ALL
        SELECT 'geographic', ST_UpperLeftX(rast), ST_UpperLeftY(rast), ST_ScaleX(rast), ST_ScaleY(rast) FROM dem_geo)
  SELECT v.dem, elev, p,
         (abs(c - round(c)) < 1e-6
          AND EXISTS (SELECT 1 FROM bs_valid a WHERE a.dem = v.dem AND a.col = round(c)::int AND a."row" = floor(r)::int)
          AND EXISTS (SELECT 1 FROM bs_valid a WHERE a.dem = v.dem AND a.col = round(c)::int AND a."row" = floor(r)::int + 1))
         OR (abs(r - round(r)) < 1e-6
          AND EXISTS (SELECT 1 FROM bs_valid a WHERE a.dem = v.dem AND a.col = floor(c)::int AND a."row" = round(r)::int)
          AND EXISTS (SELECT 1 FROM bs_valid a WHERE a.dem = v.dem AND a.col = floor(c)::int + 1 AND a."row" = round(r)::int)) AS on_grid
  FROM v JOIN g USING (dem),
       LATERAL (SELECT (ST_X(p) - ulx) / sx - 0.5 AS c, (ST_Y(p) - uly) / sy - 0.5 AS r) q;
SELECT dem, count(*) AS vertices, count(*) FILTER (WHERE on_grid) > 0.95 * count(*) AS nearly_all_on_grid_lines
FROM bs_vertices GROUP BY dem ORDER BY dem DESC;
DELETE FROM bs_vertices WHERE NOT on_grid;
-- vertices outside the surface (tin_height NULL): on its outline up to
-- the rounding of gdal_contour's text output (1e-6 pixel), but for builds
-- within a boundary; none since 0.21.1, where tin_height answers a point
-- off the domain by a rounding (5 of the UTM DEM's vertices and 65 of the
-- geographic DEM's were outside before, all on the outline)
SELECT b.dem, b.build, count(*) AS outside,
       bool_and(ST_DWithin(v.p, ST_Boundary(fp), 1e-6 * ST_PixelWidth(d.rast))) AS on_the_outline
FROM bs_terrain b JOIN bs_vertices v USING (dem)
     JOIN (SELECT 'utm' AS dem, rast FROM dem UNION ALL SELECT 'geographic', rast FROM dem_geo) d USING (dem),
     LATERAL (SELECT ST_Union(geom) AS fp FROM tin_triangles(b.t, 0)) f
WHERE tin_height(b.t, v.p) IS NULL AND b.build <> 'boundary'
GROUP BY b.dem, b.build ORDER BY b.dem DESC, b.build;
-- every build a valid hierarchy (no holes, cracks, slivers)
SELECT dem, build, (SELECT count(*) FROM tin_validate(t)) AS problems FROM bs_terrain ORDER BY 1 DESC, 2;
CREATE TABLE bs_levels AS
  SELECT b.dem, b.build, l AS level, tin_tolerance(t, l) AS tolerance,
         (tin_info(t) -> 'levels' -> l ->> 'max_error')::float8 AS max_error,
         (SELECT array_agg(tin_height(b.t, v.p, l) - v.elev) FROM bs_vertices v
          WHERE v.dem = b.dem
            -- beside a hard line (within a pixel: every grid segment it
            -- cuts) the surface is the line's
            AND NOT (b.build = 'hard breaklines'
                     AND ST_DWithin(v.p, (SELECT lines FROM bs_hard h WHERE h.dem = b.dem), px))) AS err
  FROM bs_terrain b
       JOIN (SELECT 'utm' AS dem, ST_PixelWidth(rast) * 1.5 AS px FROM dem
             UNION ALL SELECT 'geographic', ST_PixelWidth(rast) * 1.5 FROM dem_geo) d USING (dem),
       generate_series(0, 4) l;
-- every contour vertex at every level: none further from its contour's
-- height than the level's tolerance. The slack is GDAL's: a pixel whose
-- value equals a contour's is nudged by about 1e-6 m, so a contour vertex
-- there is that far from the raster's surface (a sample at exactly the
-- tolerance shows as 2.000001 m)
SELECT dem, build, level, tolerance, cardinality(err) AS vertices,
       (SELECT count(e) FROM unnest(err) e) AS inside,
       (SELECT count(*) FROM unnest(err) e WHERE abs(e) > tolerance + 1e-5) AS over
FROM bs_levels ORDER BY dem DESC, build, level;
-- tin_info's max_error is the surface's: at least the contours' worst
-- (they lie on grid lines), at most the tolerance
SELECT dem, build, level,
       (SELECT max(abs(e)) FROM unnest(err) e) <= max_error + 1e-5 AS max_error_covers_contours,
       max_error <= tolerance AS max_error_within_tolerance
FROM bs_levels ORDER BY dem DESC, build, level;
-- two such tins overlaid (vertices at grid-line crossings of two grids
-- 0.48 pixel apart): every face, the area of the common domain
WITH a AS MATERIALIZED (SELECT t FROM bs_terrain WHERE dem = 'geographic' AND build = 'lattice'),
b AS MATERIALIZED (
  SELECT tin_from_raster(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 0.0004, ST_UpperLeftY(rast)), 8.0, 2) AS t FROM dem_geo),
d AS MATERIALIZED (
  SELECT ST_Area(ST_Intersection(ST_ConvexHull(tin_as_geometry(a.t, 0)), ST_ConvexHull(tin_as_geometry(b.t, 0)))) AS area
  FROM a, b)
SELECT count(*) > 100000 AS faces, abs(sum(ST_Area(o.geom_a)) / min(d.area) - 1) < 1e-9 AS area_is_domain
FROM a, b, d, tin_overlay(a.t, b.t, 4, 1) o;
-- the same over the UTM DEM's valid pixels, against the grid moved by 4
-- pixels at other tolerances: both tins' vertices lie on the same grid
-- lines, their crossings round onto each other; that overlay failed with
-- "edges crossing too near each other" until such points were merged.
-- Every pair of levels covers the common domain (the level-0 triangles'
-- unions intersected, PostGIS)
WITH a AS MATERIALIZED (SELECT t FROM bs_terrain WHERE build = 'valid pixels'),
b AS MATERIALIZED (
  SELECT tin_from_raster(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 40, ST_UpperLeftY(rast) - 40), 8.0, 2) AS t FROM dem),
d AS MATERIALIZED (
  SELECT ST_Area(ST_Intersection((SELECT ST_Union(geom) FROM tin_triangles(a.t, 0)),
                                 (SELECT ST_Union(geom) FROM tin_triangles(b.t, 0)))) AS area
  FROM a, b)
SELECT la, lb, count(*) > 50000 AS faces,
       abs(sum(ST_Area(o.geom_a)) / min(d.area) - 1) < 1e-9 AS area_is_domain
FROM a, b, d, generate_series(0, 4) la, generate_series(0, 1) lb, tin_overlay(a.t, b.t, la, lb) o
GROUP BY 1, 2 ORDER BY 1, 2;
-- tin_validate(tin, raster): nothing over the tolerance on these builds
SELECT b.dem, b.build, count(v.*) AS problems
FROM bs_terrain b
     JOIN (SELECT 'utm' AS dem, rast FROM dem UNION ALL SELECT 'geographic', rast FROM dem_geo) d USING (dem)
     LEFT JOIN bs_hard h ON h.dem = b.dem AND b.build = 'hard breaklines'
     LEFT JOIN LATERAL tin_validate(b.t, d.rast, breaklines => h.lines) v ON true
GROUP BY 1, 2 ORDER BY 1 DESC, 2;
-- without its lines, tin_validate sees their own heights on the grid
-- segments they cut: every level over
SELECT b.dem, count(v.*) AS levels_over
FROM bs_terrain b
     JOIN (SELECT 'utm' AS dem, rast FROM dem UNION ALL SELECT 'geographic', rast FROM dem_geo) d USING (dem),
     tin_validate(b.t, d.rast) v
WHERE b.build = 'hard breaklines' GROUP BY 1 ORDER BY 1 DESC;
-- where tin_validate names a place, PostGIS agrees there (bilinear
-- ST_Value, as below): the places it names for the hard-breakline build
-- judged without its lines, between pixel centres, where the lines cut
-- the grid segments
SELECT v.level, v.problem, x.err > tin_tolerance(b.t, v.level) AS over,
       abs(abs(tin_height(b.t, x.p, v.level) - ST_Value(ST_SetBandNoDataValue(d.rast, 1, -32768), 1, x.p, resample => 'bilinear'))
           - x.err) < 1e-6 AS postgis_agrees,
       v.triangle = tin_locate(b.t, x.p, v.level)
         OR ST_DWithin((SELECT geom FROM tin_triangles(b.t, v.level) WHERE id = v.triangle), x.p, 1e-9) AS triangle_holds_it,
       v.detail LIKE '%between pixel centres%' AS between_centres
FROM bs_terrain b, dem_geo d, tin_validate(b.t, d.rast) v,
     LATERAL (SELECT substring(v.detail FROM '^error ([-0-9.e+]+) ')::float8 AS err,
                     ST_SetSRID(ST_GeomFromText(substring(v.detail FROM '(POINT\([^)]*\))')), 4326) AS p) x
WHERE b.dem = 'geographic' AND b.build = 'hard breaklines' ORDER BY 1;
-- a tile's build (keep_border) chooses the seam's vertices from its own
-- samples (so that the tile beside it agrees); the one-pixel strip along
-- its hull was held at the samples only, and tin_validate named the levels
-- over their tolerance there (every level until 0.27.0, 3 and 4 of 0-4
-- with the seams at half the tolerance); build engine 2 mends the strip
-- from inside (after 0.27.0): none on this DEM. Where it names one,
-- PostGIS agrees at the place (bilinear ST_Value
-- on a grid line is the two pixels' line; the geographic DEM has no
-- nodata, so every neighbour is there; PostGIS's bilinear ST_Value needs
-- a nodata value set all the same)
CREATE TABLE bs_tile AS SELECT tin_from_raster(rast, 2.0, 5, keep_border => true) AS t FROM dem_geo;
CREATE TABLE bs_found AS
  SELECT v.*, substring(v.detail FROM '^error ([-0-9.e+]+) ')::float8 AS err,
         ST_SetSRID(ST_GeomFromText(substring(v.detail FROM '(POINT\([^)]*\))')), 4326) AS p
  FROM bs_tile b, dem_geo d, tin_validate(b.t, d.rast) v;
SELECT f.level, f.problem, tin_tolerance(b.t, f.level) AS tolerance,
       f.err > tin_tolerance(b.t, f.level) AS over,
       abs(abs(tin_height(b.t, f.p, f.level) - ST_Value(ST_SetBandNoDataValue(d.rast, 1, -32768), 1, f.p, resample => 'bilinear'))
           - f.err) < 1e-6 AS postgis_agrees,
       f.triangle = tin_locate(b.t, f.p, f.level)
         OR ST_DWithin((SELECT geom FROM tin_triangles(b.t, f.level) WHERE id = f.triangle), f.p, 1e-9) AS triangle_holds_it,
       f.detail LIKE '%between pixel centres%' AS between_centres
FROM bs_found f, bs_tile b, dem_geo d ORDER BY 1;
-- tin_tiles holds the strips too (since 0.14.0): a tile asks for the seam
-- pixels a strip needs and both tiles of the seam keep them. Every tile of
-- both DEMs against the whole raster (the grid segments beyond a tile's
-- seams are its neighbours'): no problem, no level over its tolerance
-- (tin_tiles_from_table gives these tiles bit for bit, tiles.sql)
CREATE TABLE bs_tiles AS
  SELECT 'utm, 64 px' AS grid, k.tx, k.ty, k.t, d.rast FROM dem d, tin_tiles(d.rast, 64, 2.0, 3) k
  UNION ALL
  SELECT 'geographic, 97 px', k.tx, k.ty, k.t, d.rast FROM dem_geo d, tin_tiles(d.rast, 97, 2.0, 3) k;
SELECT b.grid, count(DISTINCT (b.tx, b.ty)) AS tiles, count(v.level) AS problems
FROM bs_tiles b LEFT JOIN LATERAL tin_validate(b.t, b.rast) v ON true
GROUP BY 1 ORDER BY 1;
DROP TABLE bs_tiles;
-- bad input
SELECT try($$SELECT count(*) FROM bs_tile b, dem_geo d, tin_validate(b.t, d.rast, 0)$$);
SELECT try($$SELECT count(*) FROM bs_tile b, dem_geo d, tin_validate(b.t, d.rast, 2)$$);
SELECT try($$SELECT count(*) FROM bs_tile b, dem d, tin_validate(b.t, d.rast)$$);
SELECT try($$SELECT count(*) FROM bs_tile b, dem_geo d, tin_validate(b.t, d.rast, breaklines => 'SRID=4326;POINT Z(0 0 0)'::geometry)$$);
SELECT try($$SELECT count(*) FROM bs_tile b, dem_geo d, tin_validate(b.t, d.rast, breaklines => 'SRID=32616;LINESTRING Z(0 0 1, 1 1 1)'::geometry)$$);
SELECT count(*) AS null_rows FROM bs_tile b, tin_validate(b.t, NULL::raster);
SELECT count(*) AS null_rows FROM bs_tile b, dem_geo d, tin_validate(b.t, d.rast, NULL::int);
DROP TABLE bs_found, bs_tile, bs_levels, bs_vertices, bs_valid, bs_terrain, bs_hard;
DROP FUNCTION bs_ring, bs_line_z, bs_line, bs_pt;
