-- Issue 26: a build's boundary (POLYGON / MULTIPOLYGON with holes). On the
-- UTM DEM (nodata border) and the geographic one, a concave shell reaching
-- past the data with a hole, and a separate square, built over the data
-- alone (fill_gaps => false: boundary ∩ valid cells). Oracles are PostGIS
-- alone, from tin_triangles' output and the rasters' own pixels:
-- - the triangles of every level cover boundary ∩ the data (the valid
--   pixels' squares, ST_Polygon, within the convex hull of their centres):
--   same area (to 1e-9) and nothing outside it;
-- - tin_height and tin_locate are NULL at every pixel centre off that
--   region and within each level's tolerance on it;
-- - the merges on the non-convex holed domain agree with PostGIS on the
--   same region: lines (tin_line_segments vs ST_Intersection), areas
--   (tin_area_triangles' coverage vs ST_Intersection), rasters
--   (tin_raster_stats' pixel count vs the centres in the region),
--   footprints (tin_footprint vs ST_Intersects), polygons draped
--   (tin_drape vs ST_Intersection) and the overlay with a plain tin (area
--   of the common domain);
-- - bad boundaries one per line.
\set VERBOSITY terse
SET extra_float_digits = 0;
-- a point at fractions (fx, fy) of a raster's extent
CREATE FUNCTION bd_pt(r raster, fx float8, fy float8) RETURNS geometry
LANGUAGE sql IMMUTABLE AS $$
  SELECT ST_SetSRID(ST_MakePoint(ST_XMin(e) + fx * (ST_XMax(e) - ST_XMin(e)),
                                 ST_YMax(e) - fy * (ST_YMax(e) - ST_YMin(e))), ST_SRID(r))
  FROM (SELECT ST_Envelope(r) AS e) s $$;
CREATE FUNCTION bd_ring(r raster, VARIADIC f float8[]) RETURNS geometry
LANGUAGE sql IMMUTABLE AS $$
  SELECT ST_MakeLine(array_agg(bd_pt(r, f[i], f[i + 1]) ORDER BY i) || bd_pt(r, f[1], f[2]))
  FROM generate_series(1, array_length(f, 1), 2) i $$;
CREATE TABLE bd AS
SELECT d.name, d.rast, ST_PixelWidth(d.rast) AS px,
       ST_Collect(
         ST_MakePolygon(bd_ring(d.rast, 0.08,0.10, 0.70,0.06, 0.52,0.43, 1.30,0.50, 0.81,0.77, 0.17,0.70),
                        ARRAY[bd_ring(d.rast, 0.30,0.33, 0.42,0.37, 0.40,0.48, 0.27,0.45)]),
         ST_MakePolygon(bd_ring(d.rast, 0.10,0.82, 0.25,0.82, 0.25,0.95, 0.10,0.95))) AS boundary
FROM (SELECT 'utm' AS name, rast FROM dem UNION ALL SELECT 'geo', rast FROM dem_geo) d;
ALTER TABLE bd ADD COLUMN t tin, ADD COLUMN region geometry;
UPDATE bd SET t = tin_from_raster(rast, 2.0, 4, boundary => boundary, fill_gaps => false),
  region = ST_Intersection(boundary, ST_Intersection(ST_Polygon(rast),
    (SELECT ST_ConvexHull(ST_Collect(geom)) FROM ST_PixelAsCentroids(rast))));
SELECT name, GeometryType(boundary) AS boundary, ST_NumInteriorRings(ST_GeometryN(region, 1)) AS holes,
       NOT ST_Contains(ST_ConvexHull(region), region) IS NULL AS concave FROM bd ORDER BY name;
-- every level covers the region: the same area, and no triangle sticks out
-- (GEOS's difference of a small triangle along the rings leaves up to
-- about 1e-8 of it)
SELECT b.name, l AS level,
       abs(sum(ST_Area(tr.geom)) / ST_Area(b.region) - 1) < 1e-9 AS same_area,
       bool_and(ST_Area(ST_Difference(ST_Force2D(tr.geom), b.region)) < 1e-6 * ST_Area(tr.geom)) AS inside,
       count(*) = tin_num_triangles(b.t, l) AS counted
FROM bd b, generate_series(0, 3) l, tin_triangles(b.t, l) tr
GROUP BY b.name, l, b.region, b.t ORDER BY 1, 2;
-- pixel centres: NULL off the region, within each level's tolerance on it
-- (centres within 1e-6 pixel of the region's boundary are left out)
SELECT b.name, l AS level,
       count(*) FILTER (WHERE ST_Intersects(b.region, c.geom)) AS centres_in,
       count(*) FILTER (WHERE NOT ST_Intersects(b.region, c.geom)) AS centres_out,
       bool_and((tin_height(b.t, c.geom, l) IS NULL) = NOT ST_Intersects(b.region, c.geom)) AS null_off_the_region,
       bool_and((tin_locate(b.t, c.geom, l) IS NULL) = NOT ST_Intersects(b.region, c.geom)) AS located,
       max(abs(tin_height(b.t, c.geom, l) - c.val)) <= 2.0 * 2 ^ (3 - l) + 1e-6 AS within_tolerance
FROM bd b, generate_series(0, 3) l, ST_PixelAsCentroids(b.rast) c
WHERE NOT ST_DWithin(ST_Boundary(b.region), c.geom, 1e-6 * b.px)
GROUP BY b.name, l ORDER BY 1, 2;
-- lines through the hole, the notch and off the data: the pieces add up to
-- the lines clipped to the region, and each piece lies in it
CREATE TABLE bd_lines AS
SELECT b.name, ST_Collect(ARRAY[
  ST_MakeLine(bd_pt(b.rast, -0.1, 0.41), bd_pt(b.rast, 1.1, 0.39)),
  ST_MakeLine(ARRAY[bd_pt(b.rast, 0.2, 0.02), bd_pt(b.rast, 0.6, 0.6), bd_pt(b.rast, 0.15, 0.98)]),
  ST_MakeLine(bd_pt(b.rast, 0.9, 0.1), bd_pt(b.rast, 0.45, 0.35))]) AS geom
FROM bd b;
SELECT b.name, l AS level,
       abs(sum(s.length2d) / ST_Length(ST_Intersection(ln.geom, b.region)) - 1) < 1e-9 AS same_length,
       bool_and(ST_DWithin(b.region, ST_Force2D(s.geom), 1e-6 * b.px)) AS inside
FROM bd b JOIN bd_lines ln USING (name), generate_series(0, 3) l, tin_line_segments(b.t, ln.geom, l) s
GROUP BY b.name, l, ln.geom, b.region ORDER BY 1, 2;
-- tin_line_triangles: the triangles crossed, none of them outside
SELECT b.name, count(*) > 0 AS crossed,
       bool_and(tr.triangle < tin_num_triangles(b.t)) AS in_the_domain
FROM bd b JOIN bd_lines ln USING (name), tin_line_triangles(b.t, ln.geom) tr
GROUP BY b.name ORDER BY 1;
-- tin_footprint (level 2): the triangles meeting a rectangle 40 x 120 pixels turned
-- 30 degrees, centred in the hole, beside it and in the notch, are those
-- of tin_triangles PostGIS finds meeting it (ST_Intersects): none void
WITH r AS MATERIALIZED (
  SELECT b.name, b.t, k, c, 40 * b.px AS wd, 120 * b.px AS ln,
             ST_Rotate(ST_MakeEnvelope(ST_X(c) - 20 * b.px, ST_Y(c) - 60 * b.px, ST_X(c) + 20 * b.px, ST_Y(c) + 60 * b.px,
                                       ST_SRID(c)), -radians(30), c) AS rect
      FROM bd b, (VALUES ('in the hole', 0.36, 0.40), ('beside it', 0.22, 0.40), ('in the notch', 0.62, 0.40)) v(k, fx, fy),
           LATERAL (SELECT bd_pt(b.rast, fx, fy) AS c) x)
SELECT r.name, r.k, ours = theirs AS same_triangles, cardinality(ours) > 0 AS some
FROM r,
LATERAL (SELECT array_agg(id ORDER BY id) AS ours FROM tin_footprint(r.t, r.c, r.wd, r.ln, 30, 2) id) o,
LATERAL (SELECT array_agg(id ORDER BY id) AS theirs FROM tin_triangles(r.t, 2) tr WHERE ST_Intersects(tr.geom, r.rect)) p
ORDER BY 1, 2;
-- an area over the hole, the notch and off the data: coverage times area
-- adds up to the polygon clipped to the region, at every level
SELECT b.name, l AS level,
       abs(sum(a.coverage * ST_Area(tr.geom)) / ST_Area(ST_Intersection(p.geom, b.region)) - 1) < 1e-9 AS same_area
FROM bd b, generate_series(0, 3) l,
     LATERAL (SELECT ST_MakePolygon(bd_ring(b.rast, 0.2,0.2, 1.2,0.3, 0.6,0.9)) AS geom) p,
     tin_area_triangles(b.t, p.geom, l) a
     JOIN tin_triangles(b.t, l) tr ON tr.id = a.triangle
GROUP BY b.name, l, p.geom, b.region ORDER BY 1, 2;
-- the raster merge: the pixels handed to triangles are the valid centres
-- in the region (none is within 1e-6 pixel of its boundary here)
-- (the centres within 1e-6 pixel of its boundary may go either way)
SELECT name, handed BETWEEN clearly_in AND clearly_in + on_its_boundary AS same_pixels, on_its_boundary > 0 AS some_on_it
FROM (SELECT b.name,
        (SELECT sum(count) FROM tin_raster_stats(b.t, b.rast)) AS handed,
        (SELECT count(*) FROM ST_PixelAsCentroids(b.rast) c WHERE ST_Intersects(b.region, c.geom)
           AND NOT ST_DWithin(ST_Boundary(b.region), c.geom, 1e-6 * b.px)) AS clearly_in,
        (SELECT count(*) FROM ST_PixelAsCentroids(b.rast) c
         WHERE ST_DWithin(ST_Boundary(b.region), c.geom, 1e-6 * b.px)) AS on_its_boundary
      FROM bd b) s ORDER BY 1;
-- the overlay with a tin of the same raster over its data alone (on the
-- UTM DEM its outer boundary bends in by an ulp where the valid cells'
-- outline is cut at the hull, which the overlay refused as "not convex"):
-- the common domain is the region
SELECT b.name, abs(sum(ST_Area(o.geom_a)) / ST_Area(b.region) - 1) < 1e-9 AS same_area,
       count(*) > 0 AS triangles
FROM bd b, tin_overlay(b.t, tin_from_raster(b.rast, 8.0, 1, fill_gaps => false), 1, 0) o
GROUP BY b.name, b.region ORDER BY 1;
-- tin_drape of a polygon keeps its intersection with the domain (PostGIS:
-- ST_Intersection with the region, the same area to 1e-6; every vertex on
-- the surface, or on the region's edge within 1e-6 pixel where the cut
-- rounds it just off): a strip whose corners are all on the terrain but
-- which crosses the hole (cut silently to one of its runs in 0.9.0), the
-- strip left of the hole (draped whole: the same ring), one leaving the
-- raster and one off it (NULL)
CREATE TABLE bd_strips AS
SELECT b.name, k, ST_MakeEnvelope(ST_X(p), ST_Y(p), ST_X(q), ST_Y(q) + 2 * b.px, ST_SRID(b.rast)) AS g
FROM bd b, (VALUES ('across', 0.22, 0.48, 0.40), ('beside', 0.22, 0.26, 0.40),
                   ('leaving', 0.9, 1.3, 0.55), ('off', 1.2, 1.3, 0.55)) v(k, x0, x1, y),
     LATERAL (SELECT bd_pt(b.rast, x0, y) AS p, bd_pt(b.rast, x1, y) AS q) s;
SELECT s.name, s.k, GeometryType(d) AS type, ST_NumGeometries(d) AS parts,
       ST_NumGeometries(ST_Intersection(s.g, b.region)) AS postgis_parts,
       ST_Area(ST_SymDifference(ST_Force2D(d), ST_Intersection(s.g, b.region))) < 1e-6 * ST_Area(s.g) AS same_area,
       ST_NPoints(d) > 5 * ST_NumGeometries(d) AS vertices_added,
       (SELECT bool_and(coalesce(abs(ST_Z(v.geom) - tin_height(b.t, v.geom)) < 1e-6,
                                 ST_DWithin(ST_Boundary(b.region), v.geom, 1e-6 * b.px)))
        FROM ST_DumpPoints(d) v) AS on_surface
FROM bd_strips s JOIN bd b USING (name), LATERAL (SELECT tin_drape(b.t, s.g) AS d) x
ORDER BY 1, 2;
-- the strip beside the hole comes back as itself
SELECT s.name, ST_Area(ST_SymDifference(ST_Force2D(d), s.g)) < 1e-9 * ST_Area(s.g) AS same_ring
FROM bd_strips s JOIN bd b USING (name), LATERAL (SELECT tin_drape(b.t, s.g) AS d) x
WHERE k = 'beside' ORDER BY 1;
DROP TABLE bd_strips;
-- a boundary holding the whole raster gives the plain build, byte for byte
SELECT name, tin_from_raster(rast, 2.0, 4, boundary => ST_Expand(ST_Envelope(rast), px))
             = tin_from_raster(rast, 2.0, 4) AS plain FROM bd ORDER BY 1;
-- tin_from_points with a boundary: the boundary within the points' hull
-- (points have no pixels: no data squares)
SELECT b.name, abs(sum(ST_Area(tr.geom)) / ST_Area(ST_Intersection(b.boundary, p.hull)) - 1) < 1e-9 AS same_area
FROM bd b,
     LATERAL (SELECT tin_from_points(ST_SetSRID(ST_Collect(ST_MakePoint(ST_X(geom), ST_Y(geom), val)), ST_SRID(b.rast)), 4.0, 2,
                                     boundary => b.boundary) AS t,
                     ST_ConvexHull(ST_Collect(geom)) AS hull
              FROM ST_PixelAsCentroids(b.rast)) p,
     tin_triangles(p.t) tr
GROUP BY b.name, b.boundary, p.hull ORDER BY 1;
-- fill_gaps => false: the terrain is where the raster has data. The UTM
-- DEM (nodata on its rotated border) and the geographic one with a lake
-- and a single pixel set to nodata. Oracles: ST_Polygon (the valid
-- pixels' squares) clipped to the hull of the valid centres has the
-- triangles' area; tin_height is NULL wherever ST_Value is NULL (every
-- pixel centre, and points a third of a pixel off them); every valid
-- centre is within each level's tolerance; a line over the lake is cut
-- where the data stops.
CREATE TABLE gaps AS
SELECT 'utm' AS name, rast, ST_PixelWidth(rast) AS px FROM dem
UNION ALL
SELECT 'geo', ST_SetValues(ST_SetBandNoDataValue(rast, -9999), 1, ARRAY[
         ROW(ST_Buffer(bd_pt(rast, 0.6, 0.4), 0.05 * (ST_XMax(ST_Envelope(rast)) - ST_XMin(ST_Envelope(rast)))), -9999),
         ROW(ST_PixelAsCentroid(rast, 100, 200), -9999)]::geomval[]), ST_PixelWidth(rast)
FROM dem_geo;
ALTER TABLE gaps ADD COLUMN t tin, ADD COLUMN region geometry, ADD COLUMN nd float8;
UPDATE gaps SET t = tin_from_raster(rast, 2.0, 4, fill_gaps => false), nd = ST_BandNoDataValue(rast),
  region = ST_Intersection(ST_Polygon(rast), (SELECT ST_ConvexHull(ST_Collect(geom)) FROM ST_PixelAsCentroids(rast)));
SELECT name, ST_NumInteriorRings(ST_GeometryN(region, 1)) AS holes,
       ST_Area(ST_ConvexHull(region)) > ST_Area(region) AS not_the_hull FROM gaps ORDER BY name;
SELECT g.name, l AS level, abs(sum(ST_Area(tr.geom)) / ST_Area(g.region) - 1) < 1e-9 AS same_area
FROM gaps g, generate_series(0, 3) l, tin_triangles(g.t, l) tr
GROUP BY g.name, l, g.region ORDER BY 1, 2;
-- (a point a third of a pixel off a centre is in that pixel: ST_Value
-- there is the pixel's value, NULL on nodata; checked with ST_Value itself
-- at 60 pixels, since ST_Value reads the whole raster each call)
CREATE TABLE gap_pts AS
SELECT g.name, NULLIF(c.val, g.nd) AS val, s.off, c.x, c.y,
       ST_Translate(c.geom, s.off * g.px, -0.5 * s.off * g.px) AS geom
FROM gaps g, (VALUES (0.0), (0.33)) s(off), ST_PixelAsCentroids(g.rast, 1, false) c;
SELECT p.name, bool_and(ST_Value(g.rast, p.geom) IS NOT DISTINCT FROM p.val) AS value_of_the_pixel,
       count(*) FILTER (WHERE p.val IS NULL) > 0 AS some_nodata
FROM gap_pts p JOIN gaps g USING (name)
WHERE (p.x * 31 + p.y) % 4001 = 0 OR (p.val IS NULL AND (p.x + p.y) % 997 = 0) GROUP BY p.name ORDER BY 1;
SELECT g.name, l AS level,
       count(*) FILTER (WHERE p.val IS NULL) AS nodata_points,
       bool_and(tin_height(g.t, p.geom, l) IS NULL) FILTER (WHERE p.val IS NULL) AS null_where_st_value_is,
       max(abs(tin_height(g.t, p.geom, l) - p.val)) FILTER (WHERE p.off = 0) <= 2.0 * 2 ^ (3 - l) + 1e-6 AS within_tolerance
FROM gaps g JOIN gap_pts p USING (name), generate_series(0, 3) l
GROUP BY g.name, l ORDER BY 1, 2;
SELECT g.name, abs(sum(s.length2d) / ST_Length(ST_Intersection(ln.geom, g.region)) - 1) < 1e-9 AS same_length,
       count(*) > 1 AS pieces
FROM gaps g, LATERAL (SELECT ST_MakeLine(bd_pt(g.rast, 0.05, 0.4), bd_pt(g.rast, 0.95, 0.42)) AS geom) ln,
     tin_line_segments(g.t, ln.geom) s
GROUP BY g.name, ln.geom, g.region ORDER BY 1;
-- a raster without nodata has no gaps: fill_gaps changes nothing
SELECT tin_from_raster(rast, 2.0, 4, fill_gaps => true) = tin_from_raster(rast, 2.0, 4, fill_gaps => false) AS no_gaps_to_fill FROM dem_geo;
-- fill_gaps => true on the UTM DEM (nodata on its rotated border): the
-- terrain is the hull of the valid pixel centres (PostGIS's ST_ConvexHull
-- has the triangles' area at every level), every valid centre is within
-- each level's tolerance of its ST_PixelAsCentroids value, and the points
-- a third of a pixel off the nodata centres inside the hull have heights
CREATE TABLE gaps_filled AS
SELECT tin_from_raster(rast, 2.0, 4, fill_gaps => true) AS t,
       (SELECT ST_ConvexHull(ST_Collect(geom)) FROM ST_PixelAsCentroids(rast)) AS hull
FROM dem;
SELECT l AS level, abs(sum(ST_Area(tr.geom)) / ST_Area(g.hull) - 1) < 1e-9 AS hull_area
FROM gaps_filled g, generate_series(0, 3) l, tin_triangles(g.t, l) tr GROUP BY l, g.hull ORDER BY 1;
SELECT l AS level, count(*) AS valid_centres,
       max(abs(tin_height(g.t, c.geom, l) - c.val)) <= 2.0 * 2 ^ (3 - l) + 1e-6 AS within_tolerance
FROM gaps_filled g, dem, ST_PixelAsCentroids(dem.rast) c, generate_series(0, 3) l GROUP BY l ORDER BY 1;
SELECT count(*) > 0 AS nodata_centres_in_the_hull,
       bool_and(tin_height(g.t, ST_Translate(c.geom, 0.33 * ST_PixelWidth(dem.rast), 0)) IS NOT NULL) AS heights_there
FROM gaps_filled g, dem, ST_PixelAsCentroids(dem.rast, 1, false) c
WHERE c.val = ST_BandNoDataValue(dem.rast) AND ST_Contains(g.hull, ST_Translate(c.geom, 0.33 * ST_PixelWidth(dem.rast), 0));
DROP TABLE gaps_filled;
SELECT tin_from_raster(rast, 2.0, 4, fill_gaps => NULL) IS NULL AS null_fill_gaps FROM dem_geo;
DROP TABLE gap_pts;
DROP TABLE gaps;
-- NULLs and bad boundaries, one per line
SELECT tin_from_raster(NULL::raster, 2.0, 4, boundary => (SELECT boundary FROM bd WHERE name = 'geo')) IS NULL AS null_raster;
SELECT tin_from_raster(rast, 2.0, 2, boundary => ST_SetSRID(ST_MakePolygon(ST_MakeLine(ARRAY[bd_pt(rast, 0.1, 0.1), bd_pt(rast, 0.9, 0.9), bd_pt(rast, 0.9, 0.1), bd_pt(rast, 0.1, 0.9), bd_pt(rast, 0.1, 0.1)])), 4326)) FROM bd WHERE name = 'geo';
SELECT tin_from_raster(rast, 2.0, 2, boundary => ST_Boundary(boundary)) FROM bd WHERE name = 'geo';
SELECT tin_from_raster(rast, 2.0, 2, boundary => ST_Transform(boundary, 3857)) FROM bd WHERE name = 'geo';
SELECT tin_from_raster(rast, 2.0, 2, boundary => ST_Translate(boundary, 10, 0)) FROM bd WHERE name = 'geo';
SELECT tin_from_raster(rast, 2.0, 2, keep_border => true, boundary => boundary) FROM bd WHERE name = 'geo';
-- keep_border over the valid pixels only: a raster without nodata builds
-- the same tile with or without fill_gaps; nodata cutting into the hull
-- (the UTM DEM's border) builds the tile over its data (0.21.1 refused it):
-- the valid squares within the hull of the centres, as without keep_border
SELECT tin_from_raster(rast, 2.0, 2, keep_border => true, fill_gaps => false)
       = tin_from_raster(rast, 2.0, 2, keep_border => true, fill_gaps => true) AS tiles_as_before FROM dem_geo;
SELECT abs(a.area / ST_Area(ST_Intersection(ST_Polygon(rast), (SELECT ST_ConvexHull(ST_Collect(geom)) FROM ST_PixelAsCentroids(rast)))) - 1) < 1e-9 AS tile_over_its_data
FROM dem, LATERAL (SELECT sum(ST_Area(geom)) AS area FROM tin_triangles(tin_from_raster(rast, 2.0, 2, keep_border => true), 1)) a;
DROP TABLE bd_lines;
DROP TABLE bd;
DROP FUNCTION bd_ring(raster, float8[]);
DROP FUNCTION bd_pt(raster, float8, float8);
