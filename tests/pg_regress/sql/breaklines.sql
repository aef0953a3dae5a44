-- Issue 26: breaklines. A hard road (LINESTRING Z, its own heights), a
-- soft ridge crossing it (heights from the pixels) and a dam crest at one
-- height, on the UTM DEM and on the geographic one. Oracles are PostGIS
-- alone, on tin_triangles' output:
-- - every breakline is a union of edges at every level: the distinct edges
--   whose two ends and middle lie within 1e-7 pixel of the line add up to
--   its length (an edge cutting a bend of the line, or a gap, would not;
--   a pixel centre a few cm off a line is a vertex of its own, so the
--   distance must be far below a pixel);
-- - along a hard line the surface is the line: tin_height equals
--   ST_LineInterpolatePoint's Z (interpolated along each segment);
-- - every pixel centre off the lines is within each level's tolerance;
-- - tin_validate finds no crack or sliver.
\set VERBOSITY terse
SET extra_float_digits = 0;
-- a point at fractions (fx, fy) of a raster's extent, at height z
CREATE FUNCTION bl_pt(r raster, fx float8, fy float8, z float8) RETURNS geometry
LANGUAGE sql IMMUTABLE AS $$
  SELECT ST_SetSRID(ST_MakePoint(ST_XMin(e) + fx * (ST_XMax(e) - ST_XMin(e)),
                                 ST_YMin(e) + fy * (ST_YMax(e) - ST_YMin(e)), z), ST_SRID(r))
  FROM (SELECT ST_Envelope(r) AS e) s $$;
CREATE TABLE bl_lines AS
SELECT d.name, 1e-7 * ST_PixelWidth(d.rast) AS eps, l.kind, l.geom
FROM (SELECT 'utm' AS name, rast FROM dem UNION ALL SELECT 'geo', rast FROM dem_geo) d,
LATERAL (VALUES
  ('road', ST_MakeLine(ARRAY[bl_pt(d.rast, 0.15, 0.30, 310), bl_pt(d.rast, 0.40, 0.42, 318),
                             bl_pt(d.rast, 0.62, 0.35, 321), bl_pt(d.rast, 0.85, 0.55, 330)])),
  ('ridge', ST_Force2D(ST_MakeLine(ARRAY[bl_pt(d.rast, 0.30, 0.10, 0), bl_pt(d.rast, 0.45, 0.50, 0),
                                         bl_pt(d.rast, 0.50, 0.90, 0)]))),
  ('dam', ST_MakeLine(bl_pt(d.rast, 0.20, 0.75, 305), bl_pt(d.rast, 0.70, 0.80, 305)))
) l(kind, geom);
CREATE TABLE bl_tins AS
SELECT d.name,
       tin_from_raster(d.rast, 2.0, 4,
         breaklines => (SELECT ST_Collect(geom) FROM bl_lines l WHERE l.name = d.name AND kind <> 'ridge'),
         soft_breaklines => (SELECT geom FROM bl_lines l WHERE l.name = d.name AND kind = 'ridge')) AS t
FROM (SELECT 'utm' AS name, rast FROM dem UNION ALL SELECT 'geo', rast FROM dem_geo) d;
SELECT name, tin_num_levels(t) AS levels, tin_num_triangles(t, 0) > 0 AS built FROM bl_tins ORDER BY name;
-- distinct edges of every level
CREATE TABLE bl_edges AS
SELECT DISTINCT b.name, l AS level,
       least(ST_AsEWKB((s).geom), ST_AsEWKB(ST_Reverse((s).geom)))::geometry AS e
FROM bl_tins b, generate_series(0, 3) l, tin_triangles(b.t, l) tr,
     ST_DumpSegments(ST_Force2D(tr.geom)) s;
-- each line, at each level: the length of the edges on it / its length
SELECT l.name, l.kind, e.level,
       round((sum(ST_Length(e.e)) / ST_Length(l.geom))::numeric, 9) AS covered,
       count(*) AS edges
FROM bl_lines l JOIN bl_edges e ON e.name = l.name
 AND ST_DWithin(ST_StartPoint(e.e), l.geom, l.eps) AND ST_DWithin(ST_EndPoint(e.e), l.geom, l.eps)
 AND ST_DWithin(ST_LineInterpolatePoint(e.e, 0.5), l.geom, l.eps)
GROUP BY l.name, l.kind, e.level, l.geom ORDER BY 1, 2, 3;
-- along the hard lines the surface is the line, at every level
SELECT l.name, l.kind, count(*) AS points,
       max(abs(tin_height(b.t, ST_Force2D(p), lv) - ST_Z(p))) < 1e-6 AS on_the_line
FROM bl_lines l JOIN bl_tins b USING (name), generate_series(0, 3) lv,
     generate_series(1, 99) f, ST_LineInterpolatePoint(l.geom, f / 100.0) p
WHERE l.kind <> 'ridge'
GROUP BY 1, 2 ORDER BY 1, 2;
-- every pixel centre off the lines within each level's tolerance (8, 4,
-- 2, 1 ... : 2.0 at the finest of 4 levels is 16 / 8 / 4 / 2)
WITH px AS (
  SELECT 'utm' AS name, (c).geom, (c).val FROM dem, ST_PixelAsCentroids(rast, 1, true) c
  UNION ALL
  SELECT 'geo', (c).geom, (c).val FROM dem_geo, ST_PixelAsCentroids(rast, 1, true) c),
off AS (
  SELECT px.* FROM px
  WHERE NOT EXISTS (SELECT FROM bl_lines l WHERE l.name = px.name AND ST_DWithin(l.geom, px.geom, l.eps)))
SELECT o.name, lv, count(*) AS pixels,
       count(*) FILTER (WHERE abs(tin_height(b.t, o.geom, lv) - o.val) > 2.0 * 2 ^ (3 - lv) + 1e-9) AS beyond_tolerance
FROM off o JOIN bl_tins b USING (name), generate_series(0, 3) lv
GROUP BY 1, 2 ORDER BY 1, 2;
-- no crack, no sliver
SELECT name, count(v.*) AS problems FROM bl_tins LEFT JOIN LATERAL tin_validate(t) v ON true GROUP BY 1 ORDER BY 1;
-- along the soft ridge the surface follows the pixels: at every level it
-- is within the level's tolerance of the range of the pixels in the 5 x 5
-- window around each point (ST_Neighborhood), away from where the ridge
-- meets the hard road and dam (there it takes their heights). A surface
-- running straight between the ridge's own three vertices missed by up to
-- 335 m.
WITH pt AS (
  SELECT l.name, lv, ST_LineInterpolatePoint(l.geom, f / 400.0) AS p
  FROM bl_lines l, generate_series(1, 399) f, generate_series(0, 3) lv
  WHERE l.kind = 'ridge'),
win AS (
  SELECT pt.name, lv, p,
         (SELECT min(v) FROM unnest(ST_Neighborhood(d.rast, 1, p, 2, 2)) v) AS lo,
         (SELECT max(v) FROM unnest(ST_Neighborhood(d.rast, 1, p, 2, 2)) v) AS hi
  FROM pt JOIN (SELECT 'utm' AS name, rast FROM dem UNION ALL SELECT 'geo', rast FROM dem_geo) d USING (name)
  WHERE NOT EXISTS (SELECT FROM bl_lines h WHERE h.name = pt.name AND h.kind <> 'ridge'
                      AND ST_DWithin(h.geom, p, 3 * ST_PixelWidth(d.rast))))
SELECT w.name, count(*) AS points,
       count(*) FILTER (WHERE tin_height(b.t, w.p, w.lv) NOT BETWEEN w.lo - 2.0 * 2 ^ (3 - w.lv) - 1e-9
                                                             AND w.hi + 2.0 * 2 ^ (3 - w.lv) + 1e-9) AS off_the_pixels
FROM win w JOIN bl_tins b USING (name)
GROUP BY 1 ORDER BY 1;
CREATE TABLE bl_plain AS SELECT tin_from_raster(rast, 2.0, 4) AS t FROM dem;
-- the same bytes on one thread as on two
SET tinmerge.threads = 1;
SELECT tin_from_raster(rast, 2.0, 4, breaklines => (SELECT ST_Collect(geom) FROM bl_lines l WHERE l.name = 'utm' AND kind <> 'ridge'),
         soft_breaklines => (SELECT geom FROM bl_lines l WHERE l.name = 'utm' AND kind = 'ridge')) = b.t AS one_thread_same
FROM dem, bl_tins b WHERE b.name = 'utm';
RESET tinmerge.threads;
-- no breaklines is the plain build, byte for byte: empty ones, and lines
-- wholly off the terrain
SELECT tin_from_raster(rast, 2.0, 4, breaklines => 'SRID=32616;MULTILINESTRING Z EMPTY'::geometry) = p.t AS empty_same,
       tin_from_raster(rast, 2.0, 4, breaklines => 'SRID=32616;LINESTRING Z(0 0 0, 10 10 0)'::geometry) = p.t AS off_terrain_same
FROM dem, bl_plain p;
-- NULL for any other NULL argument
SELECT tin_from_raster(NULL::raster, 2.0, 4, breaklines => geom) IS NULL AS null_raster,
       tin_from_raster(rast, NULL::float8, 4, breaklines => geom) IS NULL AS null_tolerance,
       tin_from_raster(rast, 2.0, NULL, breaklines => geom) IS NULL AS null_levels
FROM dem, bl_lines WHERE name = 'utm' AND kind = 'dam';
-- explicit tolerances take breaklines too
SELECT tin_num_levels(tin_from_raster(rast, ARRAY[8.0, 2.0], breaklines => geom)) AS levels
FROM dem, bl_lines WHERE name = 'utm' AND kind = 'road';
-- tin_from_points: the dam crest through scattered points
CREATE TABLE bl_pts AS
SELECT tin_from_points(ST_SetSRID(ST_Collect(ST_MakePoint(ST_X((c).geom), ST_Y((c).geom), (c).val)), 32616), 2.0, 3,
                       breaklines => (SELECT geom FROM bl_lines WHERE name = 'utm' AND kind = 'dam')) AS t
FROM dem, ST_PixelAsCentroids(rast, 1, true) c;
SELECT ST_SRID(tin_envelope(t)) AS srid,
       (SELECT max(abs(tin_height(t, ST_LineInterpolatePoint(geom, f / 10.0), lv) - 305))
        FROM bl_lines, generate_series(1, 9) f, generate_series(0, 2) lv
        WHERE name = 'utm' AND kind = 'dam') < 1e-6 AS on_the_crest
FROM bl_pts;
-- the flat lake of docs/breaklines.md: the pixels inside a ring set to
-- nodata, the ring a hard breakline at the water level; inside it the
-- surface is the water level at every level
CREATE TABLE bl_lake AS
SELECT ST_Buffer(bl_pt(rast, 0.55, 0.6, 0), 25 * ST_PixelWidth(rast), 8) AS geom, 280.0::float8 AS level FROM dem;
CREATE TABLE bl_lake_tin AS
SELECT tin_from_raster(ST_SetValues(d.rast, 1, ARRAY[ROW(l.geom, ST_BandNoDataValue(d.rast))]::geomval[]), 2.0, 4,
         breaklines => ST_Force3D(ST_Boundary(l.geom), l.level)) AS t
FROM dem d, bl_lake l;
SELECT count(*) AS pixels_inside,
       count(*) FILTER (WHERE abs(tin_height(b.t, (c).geom, lv) - l.level) > 1e-9) AS off_the_water
FROM dem, bl_lake l, bl_lake_tin b, ST_PixelAsCentroids(rast, 1, false) c, generate_series(0, 3) lv
WHERE ST_Contains(l.geom, (c).geom);
-- breaklines reaching outside the pixel centres' hull are cut at it:
-- gdal_contour's 50 m contours (table contours) end on pixel edges, half a
-- pixel outside. As hard breaklines at their own elevation: at points along
-- them inside the hull (ST_ConvexHull of ST_PixelAsCentroids, a millimetre
-- in), the surface is the contour's elevation at every level. A line
-- wholly outside is left out.
CREATE TABLE bl_hull AS SELECT ST_ConvexHull(ST_Collect((c).geom)) AS geom FROM dem, ST_PixelAsCentroids(rast, 1, true) c;
CREATE TABLE bl_contour_tin AS
SELECT tin_from_raster(rast, 2.0, 3,
         breaklines => (SELECT ST_Collect(ST_Force3D(geom, elev)) FROM contours),
         soft_breaklines => ST_MakeLine(bl_pt(rast, 1.5, 0.5, 0), bl_pt(rast, 1.7, 0.6, 0))) AS t
FROM dem;
SELECT count(DISTINCT c.id) AS contours, count(*) AS points,
       count(*) FILTER (WHERE abs(tin_height(b.t, p, lv) - c.elev) > 1e-6) AS off_the_contour
FROM contours c, bl_contour_tin b, bl_hull h, generate_series(0, 2) lv,
     generate_series(1, 9) f, ST_LineInterpolatePoint(c.geom, f / 10.0) p
WHERE ST_Contains(ST_Buffer(h.geom, -1e-3), p);
-- bad input, one per line
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, breaklines => 'SRID=4326;LINESTRING Z (0 0 1, 1 1 1)') FROM dem$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, breaklines => ST_Force2D(geom)) FROM dem, bl_lines WHERE name = 'utm' AND kind = 'road'$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, breaklines => ST_MakePolygon(ST_AddPoint(geom, ST_StartPoint(geom)))) FROM dem, bl_lines WHERE name = 'utm' AND kind = 'road'$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, breaklines => ST_Collect(l.geom, ST_SetSRID(ST_MakeLine(bl_pt(rast, 0.3, 0.2, 400), bl_pt(rast, 0.5, 0.6, 400)), 32616))) FROM dem, bl_lines l WHERE name = 'utm' AND kind = 'road'$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, keep_border => true, breaklines => geom) FROM dem, bl_lines WHERE name = 'utm' AND kind = 'road'$$);
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, breaklines => ST_MakeLine(geom, geom)) FROM dem, (SELECT ST_StartPoint(geom) AS geom FROM bl_lines WHERE name = 'utm' AND kind = 'road') p$$);
SELECT try($$SELECT tin_from_points('SRID=32616;MULTIPOINT Z (0 0 1, 10 0 2, 0 10 3, 10 10 4)', 1.0, 2, soft_breaklines => 'SRID=32616;POINT(5 5)')$$);
DROP TABLE bl_lines, bl_tins, bl_edges, bl_plain, bl_pts, bl_lake, bl_lake_tin, bl_hull, bl_contour_tin;
DROP FUNCTION bl_pt(raster, float8, float8, float8);
