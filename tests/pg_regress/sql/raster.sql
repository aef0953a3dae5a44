-- Raster merge against an independent oracle in PostGIS: every valid pixel
-- centre (ST_PixelAsCentroids) against the triangles of tin_triangles at
-- every level (GiST). A centre strictly inside a triangle (ST_Contains)
-- must go to that triangle; every centre on edges or vertices goes to
-- exactly one triangle whose closed polygon holds it; statistics equal
-- PostgreSQL's own aggregates over that assignment (mode() WITHIN GROUP
-- picks the smallest of equally frequent values).
SET extra_float_digits = 0;
CREATE TABLE r_tris AS
  SELECT l AS level, tr.id AS triangle, tr.geom FROM terrain, unnest(ARRAY[0, 2, 4]) l, tin_triangles(t, l) tr;
CREATE INDEX ON r_tris USING gist (geom);
ANALYZE r_tris;
-- rasters: the DEM (every tin vertex is a pixel centre: ties everywhere),
-- a 3x finer grid shifted by a third of a pixel over the middle of the
-- domain (ST_Rescale, nearest; partial cover), and
-- tiles of the DEM (100 x 100, partial cover) with every 5th pixel nodata
CREATE TABLE r_rasters AS
  SELECT 'dem' AS name, 1 AS part, rast FROM dem
  UNION ALL
  SELECT 'finer', 1, ST_Rescale(ST_Clip(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + ST_ScaleX(rast) / 3, ST_UpperLeftY(rast)),
                                        ST_Expand(ST_Centroid(ST_Envelope(rast)), 6000)),
                                ST_ScaleX(rast) / 3, ST_ScaleY(rast) / 3, 'NearestNeighbor') FROM dem
  UNION ALL
  SELECT 'tiles', row_number() OVER ()::int,
         ST_MapAlgebra(tile, 1, NULL, 'CASE WHEN [rast.x] % 5 = 0 THEN -9999 ELSE [rast] END', -9999)
  FROM (SELECT ST_Tile(rast, 100, 100, true, -9999) AS tile FROM dem) t
  WHERE ST_Intersects(tile, (SELECT tin_as_geometry(t, 0) FROM terrain)) ;
SELECT name, count(*) AS parts, sum(ST_Width(rast) * ST_Height(rast)) AS pixels, min(ST_SRID(rast)) AS srid
FROM r_rasters GROUP BY 1 ORDER BY 1;
-- the domain (by PostGIS): the valid pixels' squares within the hull of
-- their centres (GEOS rounds the vertices of the intersection: a centre on
-- the hull is in it within a micrometre)
CREATE TABLE r_domain AS SELECT ST_Intersection((SELECT ST_Polygon(rast) FROM dem),
                       (SELECT ST_ConvexHull(ST_Collect(p.geom)) FROM dem, ST_PixelAsCentroids(rast, 1, true) p)) AS geom;
CREATE TABLE r_px AS
  SELECT name, part, p.x AS col, p.y AS "row", p.val, p.geom, ST_DWithin(d.geom, p.geom, 1e-6) AS in_domain
  FROM r_rasters, ST_PixelAsCentroids(rast, 1, true) p, r_domain d;
CREATE TABLE r_ours AS
  SELECT name, part, l AS level, p.*
  FROM r_rasters, terrain, generate_series(0, 4) l, tin_raster_pixels(t, rast, l) p
  WHERE l IN (0, 4) OR (name = 'dem' AND l = 2);
-- each valid centre in the closed domain exactly once, none outside
SELECT o.name, o.level,
       count(*) AS handed,
       count(*) - count(DISTINCT (o.part, o.col, o.row)) AS twice,
       (SELECT count(*) FROM r_px p WHERE p.name = o.name AND p.in_domain) AS valid_in_domain,
       count(*) FILTER (WHERE p.col IS NULL) AS not_valid
FROM r_ours o LEFT JOIN r_px p USING (name, part, col, "row")
GROUP BY 1, 2 ORDER BY 1, 2;
-- strictly inside: the containing triangle; on an edge or vertex: one of
-- the triangles holding it
SELECT o.name, o.level,
       count(*) FILTER (WHERE c.triangle IS NOT NULL AND c.triangle <> o.triangle) AS wrong_inside,
       count(*) FILTER (WHERE c.triangle IS NULL) > 0 AS some_on_edges,
       count(*) FILTER (WHERE NOT ST_Intersects(t.geom, p.geom)) AS owner_misses
FROM r_ours o JOIN r_px p USING (name, part, col, "row")
JOIN r_tris t ON t.level = o.level AND t.triangle = o.triangle
LEFT JOIN LATERAL (SELECT triangle FROM r_tris x WHERE x.level = o.level AND ST_Contains(x.geom, p.geom) LIMIT 1) c ON true
GROUP BY 1, 2 ORDER BY 1, 2;
-- statistics: whole rasters at every level, and the tiles
CREATE TABLE r_stats AS
  SELECT name, part, l AS level, s.*
  FROM r_rasters, terrain, generate_series(0, 4) l, tin_raster_stats(t, rast, l) s
  WHERE l IN (0, 4) OR (name = 'dem' AND l = 2);
SELECT s.name, s.level, count(*) AS triangles,
       count(*) FILTER (WHERE a.triangle IS NULL) AS extra,
       (SELECT count(DISTINCT (part, triangle)) FROM r_ours o WHERE o.name = s.name AND o.level = s.level) AS with_pixels,
       count(*) FILTER (WHERE s.count <> a.n OR s.min <> a.lo OR s.max <> a.hi OR s.mode <> a.mo
                         OR abs(s.sum - a.total) > 1e-9 * abs(a.total) OR abs(s.mean - a.total / a.n) > 1e-9 * abs(a.total / a.n)) AS differ
FROM r_stats s
LEFT JOIN (SELECT name, part, level, triangle, count(*) AS n, sum(value) AS total, min(value) AS lo, max(value) AS hi,
                  mode() WITHIN GROUP (ORDER BY value) AS mo
           FROM r_ours GROUP BY 1, 2, 3, 4) a USING (name, part, level, triangle)
GROUP BY 1, 2 ORDER BY 1, 2;
-- small cases: a single pixel on a tin vertex, an empty raster, an
-- all-nodata band, a raster beside the domain, a NULL band or level
SELECT count(*), min(count), min(mean) FROM terrain, dem,
  tin_raster_stats(t, ST_AddBand(ST_MakeEmptyRaster(1, 1, ST_UpperLeftX(rast) + 100 * ST_ScaleX(rast), ST_UpperLeftY(rast) + 100 * ST_ScaleY(rast),
                                                   ST_ScaleX(rast), ST_ScaleY(rast), 0, 0, 32616), '32BF'::text, 7, -9999), 0);
SELECT count(*) FROM terrain, tin_raster_stats(t, ST_MakeEmptyRaster(0, 0, 0, 0, 1, -1, 0, 0, 32616));
SELECT count(*) FROM terrain, dem, tin_raster_stats(t, ST_AddBand(ST_MakeEmptyRaster(rast), '32BF'::text, -9999, -9999));
SELECT count(*) FROM terrain, dem, tin_raster_pixels(t, ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 1e6, ST_UpperLeftY(rast)));
SELECT count(*) FROM terrain, dem, tin_raster_stats(t, rast, 0, NULL);
SELECT (SELECT count(*) FROM terrain, dem, tin_raster_stats(t, rast, NULL)) = (SELECT count(*) FROM terrain, dem, tin_raster_stats(t, rast, 4)) AS null_level_is_finest;
-- coverage-weighted statistics against PostGIS: every pixel polygon
-- (ST_PixelAsPolygons) intersected with every triangle it meets
-- (ST_Intersection, ST_Area), on one 100 x 100 tile with nodata, at
-- levels 0 and 4
CREATE TABLE r_cells AS
  SELECT r.part, p.x AS col, p.y AS "row", p.val, p.geom
  FROM r_rasters r, ST_PixelAsPolygons(r.rast, 1, true) p WHERE r.name = 'tiles' AND r.part = 7;
CREATE TABLE r_wsql AS
  SELECT t.level, t.triangle, count(*) AS n, sum(c.val * f) / sum(f) AS mean, sum(c.val * f) AS total, min(c.val) AS lo, max(c.val) AS hi
  FROM r_cells c JOIN r_tris t ON t.level IN (0, 4) AND ST_Intersects(t.geom, c.geom),
  LATERAL (SELECT ST_Area(ST_Intersection(t.geom, c.geom)) / ST_Area(c.geom) AS f) a
  WHERE f > 1e-9 GROUP BY 1, 2;
CREATE TABLE r_wours AS
  SELECT l AS level, s.* FROM r_rasters r, terrain, unnest(ARRAY[0, 4]) l, tin_raster_stats(t, r.rast, l, weighted => true) s
  WHERE r.name = 'tiles' AND r.part = 7;
SELECT level, count(*) AS triangles,
       count(*) FILTER (WHERE o.triangle IS NULL OR w.triangle IS NULL) AS not_in_both,
       count(*) FILTER (WHERE o.count <> w.n) AS count_differs,
       count(*) FILTER (WHERE abs(o.mean - w.mean) > 1e-6 * abs(w.mean) OR abs(o.sum - w.total) > 1e-6 * abs(w.total)
                         OR o.min <> w.lo OR o.max <> w.hi) AS stats_differ
FROM r_wours o FULL JOIN r_wsql w USING (level, triangle)
GROUP BY 1 ORDER BY 1;
-- a small triangle owning no pixel centre still gets a weighted value:
-- with pixels 4x the DEM's, triangles of level 4 without a centre; the
-- triangles without a weighted value overlap no valid pixel polygon
CREATE TABLE r_coarse AS SELECT ST_Rescale(rast, 4 * ST_ScaleX(rast), 4 * ST_ScaleY(rast)) AS rast FROM dem;
CREATE TABLE r_coarse_cells AS SELECT p.geom FROM r_coarse, ST_PixelAsPolygons(rast, 1, true) p;
CREATE INDEX ON r_coarse_cells USING gist (geom);
CREATE TABLE r_coarse_w AS SELECT s.triangle FROM terrain, r_coarse, tin_raster_stats(t, rast, 4, weighted => true) s;
SELECT count(*) FILTER (WHERE c.triangle IS NULL) > 0 AS some_only_weighted
FROM r_coarse_w w
LEFT JOIN (SELECT s.triangle FROM terrain, r_coarse, tin_raster_stats(t, rast, 4) s) c USING (triangle);
SELECT count(*) > 0 AS some_without_value,
       count(*) FILTER (WHERE EXISTS (SELECT 1 FROM r_coarse_cells c WHERE ST_Intersects(c.geom, tr.geom)
                                      AND ST_Area(ST_Intersection(c.geom, tr.geom)) > 1e-9 * ST_Area(c.geom))) AS but_overlapped
FROM terrain, tin_triangles(t, 4) tr WHERE NOT EXISTS (SELECT 1 FROM r_coarse_w w WHERE w.triangle = tr.id);
-- weighted over a band of ones without nodata: the fractions add up to the
-- domain's area in pixels, and every mean is 1
SELECT round((sum(s.sum) * 90 * 90 / ST_Area(d.geom))::numeric, 9) AS weight_over_area,
       count(*) FILTER (WHERE abs(s.mean - 1) > 1e-12) AS mean_not_1
FROM terrain, dem, r_domain d,
     tin_raster_stats(t, ST_AddBand(ST_MakeEmptyRaster(rast), '32BF'::text, 1, NULL), 2, weighted => true) s
GROUP BY d.geom;
-- tin_paint against PostGIS: the mean of each band over the valid pixel
-- centres (ST_PixelAsCentroids) that ST_Contains puts in the triangle.
-- The colour map of the DEM (bands 1-3 of RGBA) shifted by (0.37, 0.61) of
-- a pixel, so that no centre lies on an edge (counted: on_edges) and the
-- owner of every centre is the one triangle containing it
CREATE TABLE r_rgb AS
  SELECT ST_ColorMap(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 0.37 * ST_ScaleX(rast), ST_UpperLeftY(rast) + 0.61 * ST_ScaleY(rast)), 'bluered') AS rast
  FROM dem;
CREATE TABLE r_rgb_px AS
  SELECT b1.geom, b1.val AS r, b2.val AS g, b3.val AS b
  FROM r_rgb, ST_PixelAsCentroids(rast, 1, true) b1
  JOIN ST_PixelAsCentroids(rast, 2, true) b2 USING (x, y)
  JOIN ST_PixelAsCentroids(rast, 3, true) b3 USING (x, y);
CREATE TABLE r_rgb_owner AS
  SELECT t.triangle, avg(p.r) AS r, avg(p.g) AS g, avg(p.b) AS b, count(*) AS n
  FROM r_rgb_px p JOIN r_tris t ON t.level = 2 AND ST_Contains(t.geom, p.geom) GROUP BY 1;
SELECT (SELECT count(*) FROM r_rgb_px p
        WHERE EXISTS (SELECT 1 FROM r_tris t WHERE t.level = 2 AND ST_Intersects(t.geom, p.geom))
          AND NOT EXISTS (SELECT 1 FROM r_tris t WHERE t.level = 2 AND ST_Contains(t.geom, p.geom))) AS on_edges,
       count(*) AS triangles,
       count(*) FILTER (WHERE p.triangle IS NULL OR m.triangle IS NULL) AS not_in_both,
       count(*) FILTER (WHERE abs(p.r - m.r) > 1e-9 OR abs(p.g - m.g) > 1e-9 OR abs(p.b - m.b) > 1e-9) AS differ
FROM (SELECT p.* FROM terrain, r_rgb, tin_paint(t, rast, 2) p) p
FULL JOIN r_rgb_owner m USING (triangle);
