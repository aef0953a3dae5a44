-- tin_tiles(..., fill_gaps => false), the default since 0.22.0 (issue 48):
-- tiles over the valid pixels' squares only. Two DEMs: the UTM one (nodata
-- on its rotated border: a ragged staircase through many tiles) and the
-- geographic one with nodata put across the seams of 64-pixel tiles (a disc
-- around the corner where four tiles meet, a pixel on a seam column, a
-- pixel on a seam row). Oracles are PostGIS's: each tile's domain (its
-- triangles' area at every level) is ST_Polygon (the valid pixels' squares)
-- within ST_ConvexHull of the tile's valid ST_PixelAsCentroids; along every
-- seam, points a quarter pixel apart get a height from both tiles or from
-- neither, the same one; both tiles have the same vertices on a seam;
-- tin_height is NULL a third of a pixel off every nodata centre.
CREATE TABLE od AS
SELECT 'utm' AS name, rast FROM dem
UNION ALL
SELECT 'geo', ST_SetValues(ST_SetBandNoDataValue(rast, -9999), 1, ARRAY[
         ROW(ST_Buffer(ST_PixelAsCentroid(rast, 129, 129), 12.5 * ST_PixelWidth(rast)), -9999),
         ROW(ST_PixelAsCentroid(rast, 65, 40), -9999),
         ROW(ST_PixelAsCentroid(rast, 30, 129), -9999)]::geomval[])
FROM dem_geo;
ALTER TABLE od ADD COLUMN nd float8, ADD COLUMN poly geometry;
UPDATE od SET nd = ST_BandNoDataValue(rast), poly = ST_Polygon(rast);
CREATE TABLE od_tiles AS
SELECT o.name, t.tx, t.ty, t.t FROM od o, tin_tiles(o.rast, 64, 2.0, 3) t;
-- every pixel (0-based column and row), and the tiles whose window holds it
CREATE TABLE od_cells AS
SELECT o.name, c.x - 1 AS c, c.y - 1 AS r, c.val IS DISTINCT FROM o.nd AS valid, c.geom
FROM od o, ST_PixelAsCentroids(o.rast, 1, false) c;
CREATE TABLE od_hulls AS
SELECT t.name, t.tx, t.ty, ST_ConvexHull(ST_Collect(c.geom)) AS hull
FROM od_tiles t JOIN od_cells c ON c.name = t.name AND c.valid
 AND c.c BETWEEN t.tx * 64 AND t.tx * 64 + 64 AND c.r BETWEEN t.ty * 64 AND t.ty * 64 + 64
GROUP BY 1, 2, 3;
ALTER TABLE od_hulls ADD COLUMN region geometry;
UPDATE od_hulls h SET region = ST_Intersection(ST_ClipByBox2D(o.poly, h.hull), h.hull)
FROM od o WHERE o.name = h.name;
-- the tiles, those whose valid squares do not fill their hull, and the
-- domain at every level
SELECT name, count(*) AS tiles, count(*) FILTER (WHERE ST_Area(region) < ST_Area(hull) * (1 - 1e-9)) AS with_nodata_in_the_hull
FROM od_hulls GROUP BY 1 ORDER BY 1;
SELECT h.name, l AS level, max(abs(a.area / ST_Area(h.region) - 1)) < 1e-9 AS domain_is_the_valid_squares
FROM od_hulls h JOIN od_tiles t USING (name, tx, ty), generate_series(0, 2) l,
     LATERAL (SELECT sum(ST_Area(geom)) AS area FROM tin_triangles(t.t, l)) a
GROUP BY 1, 2 ORDER BY 1, 2;
-- a third of a pixel off each nodata centre of a tile's window: no height
SELECT c.name, count(*) > 100 AS nodata_points,
       bool_and(tin_height(t.t, ST_Translate(c.geom, 0.33 * ST_PixelWidth(o.rast), 0.17 * ST_PixelHeight(o.rast))) IS NULL) AS null_there
FROM od_cells c JOIN od o USING (name) JOIN od_tiles t ON t.name = c.name
 AND c.c BETWEEN t.tx * 64 AND t.tx * 64 + 63 AND c.r BETWEEN t.ty * 64 AND t.ty * 64 + 63
WHERE NOT c.valid GROUP BY 1 ORDER BY 1;
-- seams: points a quarter pixel apart along every shared column and row
CREATE TABLE od_seam_pts AS
SELECT a.name, a.t AS ta, b.t AS tb, ST_Translate(c.geom, 0, q * ST_ScaleY(o.rast)) AS p
FROM od_tiles a JOIN od_tiles b ON b.name = a.name AND b.tx = a.tx + 1 AND b.ty = a.ty
JOIN od o ON o.name = a.name
JOIN od_cells c ON c.name = a.name AND c.c = b.tx * 64 AND c.r BETWEEN a.ty * 64 AND a.ty * 64 + 63,
(VALUES (0.0), (0.25), (0.75)) v(q)
UNION ALL
SELECT a.name, a.t, b.t, ST_Translate(c.geom, q * ST_ScaleX(o.rast), 0)
FROM od_tiles a JOIN od_tiles b ON b.name = a.name AND b.tx = a.tx AND b.ty = a.ty + 1
JOIN od o ON o.name = a.name
JOIN od_cells c ON c.name = a.name AND c.r = b.ty * 64 AND c.c BETWEEN a.tx * 64 AND a.tx * 64 + 63,
(VALUES (0.0), (0.25), (0.75)) v(q);
SELECT name, l AS level,
       count(*) FILTER (WHERE ha IS NOT NULL AND hb IS NOT NULL) > 1000 AS answered_by_both,
       count(*) FILTER (WHERE (ha IS NULL) <> (hb IS NULL)) AS answered_by_one_only,
       count(*) FILTER (WHERE ha IS NULL AND hb IS NULL) > 0 AS some_off_the_data,
       max(abs(ha - hb)) < 1e-9 AS same_heights
FROM od_seam_pts, generate_series(0, 2) l,
     LATERAL (SELECT tin_height(ta, p, l) AS ha, tin_height(tb, p, l) AS hb) h
GROUP BY 1, 2 ORDER BY 1, 2;
-- the vertices on each seam, from both tiles: the same
CREATE TABLE od_verts AS
SELECT DISTINCT t.name, t.tx, t.ty, l, ST_X(d.geom) AS x, ST_Y(d.geom) AS y
FROM od_tiles t, generate_series(0, 2) l, tin_triangles(t.t, l) tr, ST_DumpPoints(tr.geom) d;
CREATE TABLE od_seams AS
SELECT a.name, a.tx, a.ty, b.tx AS bx, b.ty AS by, ST_X(c.geom) AS sx, NULL::float8 AS sy,
       ST_PixelWidth(o.rast) * 1e-6 AS eps
FROM od_tiles a JOIN od_tiles b ON b.name = a.name AND b.tx = a.tx + 1 AND b.ty = a.ty
JOIN od o ON o.name = a.name
JOIN od_cells c ON c.name = a.name AND c.c = b.tx * 64 AND c.r = a.ty * 64
UNION ALL
SELECT a.name, a.tx, a.ty, b.tx, b.ty, NULL, ST_Y(c.geom), ST_PixelWidth(o.rast) * 1e-6
FROM od_tiles a JOIN od_tiles b ON b.name = a.name AND b.tx = a.tx AND b.ty = a.ty + 1
JOIN od o ON o.name = a.name
JOIN od_cells c ON c.name = a.name AND c.r = b.ty * 64 AND c.c = a.tx * 64;
WITH on_seam AS (
  SELECT s.name, s.tx, s.ty, v.l, v.tx = s.tx AND v.ty = s.ty AS in_a, v.x, v.y
  FROM od_seams s JOIN od_verts v ON v.name = s.name
   AND ((v.tx, v.ty) = (s.tx, s.ty) OR (v.tx, v.ty) = (s.bx, s.by))
   AND (abs(v.x - s.sx) < s.eps OR abs(v.y - s.sy) < s.eps)
)
SELECT name, l AS level, count(a.x) > 1000 AS seam_vertices,
       count(*) FILTER (WHERE b.x IS NULL) AS only_in_one,
       count(*) FILTER (WHERE a.x IS NULL) AS only_in_the_other
FROM (SELECT * FROM on_seam WHERE in_a) a FULL JOIN (SELECT * FROM on_seam WHERE NOT in_a) b
  USING (name, tx, ty, l, x, y)
GROUP BY 1, 2 ORDER BY 1, 2;
-- tin_tiles_from_table over the same raster cut by ST_Tile: the same tiles
CREATE TABLE od_rt_utm AS SELECT ST_Tile(rast, 64, 64) AS rast FROM od WHERE name = 'utm';
CREATE TABLE od_rt_geo AS SELECT ST_Tile(rast, 64, 64) AS rast FROM od WHERE name = 'geo';
SELECT 'utm' AS name, count(*) AS tiles, bool_and(f.t = t.t) AS same_as_tin_tiles
FROM tin_tiles_from_table('od_rt_utm', 2.0, 3) f JOIN od_tiles t ON t.name = 'utm' AND (t.tx, t.ty) = (f.tx, f.ty)
UNION ALL
SELECT 'geo', count(*), bool_and(f.t = t.t)
FROM tin_tiles_from_table('od_rt_geo', 2.0, 3) f JOIN od_tiles t ON t.name = 'geo' AND (t.tx, t.ty) = (f.tx, f.ty);
-- the pattern of docs/scaling.md: each window of the UTM DEM cut out in
-- SQL (its pixels plus the first column and row of its neighbours) and
-- built alone with keep_border => true: over its data too (0.21.1 refused
-- it), the same domain, and the seams answered alike from both sides
CREATE TABLE od_cut AS
SELECT t.tx, t.ty, tin_from_raster(ST_Clip(o.rast, ST_MakeEnvelope(
         ST_UpperLeftX(o.rast) + t.tx * 64 * ST_ScaleX(o.rast),
         ST_UpperLeftY(o.rast) + (t.ty * 64 + 65) * ST_ScaleY(o.rast),
         ST_UpperLeftX(o.rast) + (t.tx * 64 + 65) * ST_ScaleX(o.rast),
         ST_UpperLeftY(o.rast) + t.ty * 64 * ST_ScaleY(o.rast), ST_SRID(o.rast))),
       2.0, 3, keep_border => true) AS t
FROM od o JOIN od_tiles t USING (name) WHERE o.name = 'utm';
SELECT count(*) AS tiles, bool_and(abs(a.area / ST_Area(h.region) - 1) < 1e-9) AS domain_is_the_valid_squares
FROM od_cut c JOIN od_hulls h ON h.name = 'utm' AND (h.tx, h.ty) = (c.tx, c.ty),
     LATERAL (SELECT sum(ST_Area(geom)) AS area FROM tin_triangles(c.t, 2)) a;
SELECT l AS level, count(*) FILTER (WHERE (ha IS NULL) <> (hb IS NULL)) AS answered_by_one_only,
       max(abs(ha - hb)) < 1e-9 AS same_heights
FROM od_seam_pts s
JOIN od_tiles a ON a.name = s.name AND a.t = s.ta JOIN od_cut ca ON (ca.tx, ca.ty) = (a.tx, a.ty)
JOIN od_tiles b ON b.name = s.name AND b.t = s.tb JOIN od_cut cb ON (cb.tx, cb.ty) = (b.tx, b.ty),
     generate_series(0, 2) l,
     LATERAL (SELECT tin_height(ca.t, s.p, l) AS ha, tin_height(cb.t, s.p, l) AS hb) h
WHERE s.name = 'utm' GROUP BY 1 ORDER BY 1;
-- fill_gaps => true: each tile the hull of its valid centres, as before
-- 0.22.0; NULL: no rows
WITH f AS MATERIALIZED (
  SELECT o.name, t.tx, t.ty, t.t FROM od o, tin_tiles(o.rast, 64, 2.0, 3, fill_gaps => true) t)
SELECT f.name, count(*) AS tiles, bool_and(abs(a.area / ST_Area(h.hull) - 1) < 1e-9) AS each_tile_its_hull
FROM f JOIN od_hulls h USING (name, tx, ty),
     LATERAL (SELECT sum(ST_Area(geom)) AS area FROM tin_triangles(f.t, 0)) a
GROUP BY 1 ORDER BY 1;
SELECT count(*) AS rows_for_null_fill_gaps FROM dem, tin_tiles(rast, 64, 2.0, 3, fill_gaps => NULL);
DROP TABLE od_cut, od_rt_utm, od_rt_geo, od_seams, od_verts, od_seam_pts, od_hulls, od_cells, od_tiles, od;
