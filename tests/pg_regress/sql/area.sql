-- Area merge against an independent oracle in PostGIS: real areas between
-- contours of the DEM (gdal_contour -p, loaded by the runner as table
-- contour_bands: multipolygons with holes), and a box with a hole reaching
-- outside the domain, against every triangle of tin_triangles at every
-- level in a GiST-indexed table (ST_Within, ST_Relate, ST_Intersection).
SET extra_float_digits = 0;
CREATE TABLE area_polys AS
  SELECT id, geom FROM contour_bands WHERE id IN (1, 13, 16)
  UNION ALL
  SELECT 100, ST_Difference(ST_Expand(ST_MakeEnvelope(ST_XMin(e), ST_YMin(e), ST_XMin(e) + 4000, ST_YMin(e) + 5000, 32616), 1500),
                            ST_MakeEnvelope(ST_XMin(e) + 1000, ST_YMin(e) + 1000, ST_XMin(e) + 2500, ST_YMin(e) + 3000, 32616))
  FROM (SELECT tin_envelope(t) AS e FROM terrain) x;
SELECT id, ST_GeometryType(geom), ST_NumGeometries(geom) AS parts, ST_NPoints(geom) AS vertices,
       (SELECT sum(ST_NumInteriorRings(g.geom)) FROM ST_Dump(geom) g) AS holes, ST_IsValid(geom)
FROM area_polys ORDER BY id;
CREATE TABLE area_tris AS
  SELECT l AS level, tr.id AS triangle, tr.geom FROM terrain, generate_series(0, 4) l, tin_triangles(t, l) tr;
CREATE INDEX ON area_tris USING gist (geom);
CREATE INDEX ON area_tris (level, triangle);
ANALYZE area_tris;
-- oracle: triangles whose inside meets the polygon's inside; inside when
-- ST_Within, else boundary with the ST_Intersection area. The polygons are
-- cut into pieces of at most 64 vertices (ST_Subdivide) for the
-- intersections: the pieces tile the polygon, so areas add up.
CREATE TABLE area_pieces AS SELECT id, ST_Subdivide(geom, 64) AS geom FROM area_polys;
CREATE INDEX ON area_pieces USING gist (geom);
CREATE TABLE area_oracle AS
SELECT id, level, triangle, CASE WHEN within THEN 'inside' ELSE 'boundary' END AS relation,
       CASE WHEN within THEN 1.0 ELSE
         (SELECT sum(ST_Area(ST_Intersection(x.geom, s.geom))) FROM area_pieces s
          WHERE s.id = x.id AND s.geom && x.geom) / ST_Area(x.geom) END AS coverage
FROM (
  SELECT p.id, a.level, a.triangle, a.geom, ST_Within(a.geom, p.geom) AS within
  FROM area_polys p JOIN area_tris a ON ST_Intersects(a.geom, p.geom)) x
WHERE within OR EXISTS (SELECT 1 FROM area_pieces s
                        WHERE s.id = x.id AND s.geom && x.geom AND ST_Relate(x.geom, s.geom, 'T********'));
CREATE TABLE area_ours AS
SELECT p.id, l AS at_level, r.*
FROM area_polys p, terrain, generate_series(0, 4) l, tin_area_triangles(t, p.geom, l) r;
-- every row at the level asked for
SELECT count(*) FILTER (WHERE level <> at_level) AS wrong_level FROM area_ours;
-- same triangles, same relation, coverage within 1e-9, at every level
SELECT coalesce(o.id, u.id) AS id, coalesce(o.level, u.level) AS level,
       count(*) FILTER (WHERE o.relation = 'inside') AS inside,
       count(*) FILTER (WHERE o.relation = 'boundary') AS boundary,
       count(*) FILTER (WHERE u.triangle IS NULL) AS missed,
       count(*) FILTER (WHERE o.triangle IS NULL) AS extra,
       count(*) FILTER (WHERE o.relation <> u.relation) AS wrong_relation,
       max(abs(o.coverage - u.coverage)) < 1e-9 AS coverage_within_1e9
FROM area_oracle o FULL JOIN area_ours u USING (id, level, triangle)
GROUP BY 1, 2 ORDER BY 1, 2;
-- compact: inside triangles at the coarsest level wholly inside; expanded
-- (every full-list inside triangle lies in exactly one compact one: its
-- centroid in exactly one, its corners in that one up to 1e-6 m, the
-- rounding of a vertex put where a coarse edge crosses a grid line) they
-- give the full list, and cover the same area
CREATE TABLE area_compact AS
SELECT p.id, r.*
FROM area_polys p, terrain, tin_area_triangles(t, p.geom, compact => true) r;
SELECT c.id, count(*) FILTER (WHERE c.relation = 'inside') AS compact_inside,
       count(DISTINCT c.level) FILTER (WHERE c.relation = 'inside') AS levels_used,
       count(*) FILTER (WHERE c.relation = 'boundary') AS compact_boundary
FROM area_compact c GROUP BY 1 ORDER BY 1;
CREATE TABLE compact_geoms AS
  SELECT c.id, c.level, c.triangle, a.geom
  FROM area_compact c JOIN area_tris a USING (level, triangle) WHERE c.relation = 'inside';
CREATE INDEX ON compact_geoms USING gist (geom);
SELECT f.id, count(*) AS full_inside,
       count(*) FILTER (WHERE h.n <> 1) AS not_in_exactly_one,
       count(*) FILTER (WHERE h.n = 1 AND NOT ST_Covers(ST_Buffer(h.g, 1e-6, 'join=mitre'), b.geom))
         AS corner_outside
FROM area_ours f JOIN area_tris b ON b.level = 4 AND b.triangle = f.triangle,
     LATERAL (SELECT count(*) AS n, (array_agg(g.geom))[1] AS g FROM compact_geoms g
              WHERE g.id = f.id AND g.geom && b.geom AND ST_Covers(g.geom, ST_Centroid(b.geom))) h
WHERE f.at_level = 4 AND f.relation = 'inside'
GROUP BY 1 ORDER BY 1;
SELECT g.id, abs(sum(ST_Area(g.geom)) - min(fa.a)) / sum(ST_Area(g.geom)) < 1e-12 AS same_area
FROM compact_geoms g
JOIN (SELECT f.id, sum(ST_Area(b.geom)) AS a FROM area_ours f JOIN area_tris b ON b.level = 4 AND b.triangle = f.triangle
      WHERE f.at_level = 4 AND f.relation = 'inside' GROUP BY 1) fa USING (id)
GROUP BY 1 ORDER BY 1;
-- the boundary rows of the compact list are the full list's
SELECT count(*) AS boundary_rows_differing FROM (
  (SELECT id, triangle, coverage FROM area_compact WHERE relation = 'boundary'
   EXCEPT SELECT id, triangle, coverage FROM area_ours WHERE at_level = 4 AND relation = 'boundary')
  UNION ALL
  (SELECT id, triangle, coverage FROM area_ours WHERE at_level = 4 AND relation = 'boundary'
   EXCEPT SELECT id, triangle, coverage FROM area_compact WHERE relation = 'boundary')) d;
-- statistics against the clipped triangles (oracle: the triangle when
-- ST_Within, else its ST_Intersection with the polygon; heights from each
-- triangle's plane through its corners, at the clipped centroid)
CREATE TABLE area_clipped AS
SELECT id, level, area, z1 + gx * (cx - x1) + gy * (cy - y1) AS zc, degrees(atan(sqrt(gx * gx + gy * gy))) AS slope
FROM (
  SELECT id, level, area, cx, cy, x1, y1, z1,
         ((z2 - z1) * (y3 - y1) - (z3 - z1) * (y2 - y1)) / d AS gx,
         ((x2 - x1) * (z3 - z1) - (x3 - x1) * (z2 - z1)) / d AS gy
  FROM (
    SELECT o.id, o.level, ST_Area(c.g) AS area, ST_X(ST_Centroid(c.g)) AS cx, ST_Y(ST_Centroid(c.g)) AS cy,
           ST_X(q.p1) x1, ST_Y(q.p1) y1, ST_Z(q.p1) z1, ST_X(q.p2) x2, ST_Y(q.p2) y2, ST_Z(q.p2) z2,
           ST_X(q.p3) x3, ST_Y(q.p3) y3, ST_Z(q.p3) z3,
           (ST_X(q.p2) - ST_X(q.p1)) * (ST_Y(q.p3) - ST_Y(q.p1)) - (ST_X(q.p3) - ST_X(q.p1)) * (ST_Y(q.p2) - ST_Y(q.p1)) AS d
    FROM area_oracle o JOIN area_tris a USING (level, triangle),
    LATERAL (SELECT a.geom AS g WHERE o.relation = 'inside'
             UNION ALL
             SELECT ST_CollectionExtract(ST_Intersection(a.geom, s.geom), 3) FROM area_pieces s
             WHERE o.relation = 'boundary' AND s.id = o.id AND s.geom && a.geom) c,
    LATERAL (SELECT ST_PointN(ST_ExteriorRing(a.geom), 1) p1, ST_PointN(ST_ExteriorRing(a.geom), 2) p2,
                    ST_PointN(ST_ExteriorRing(a.geom), 3) p3) q
    WHERE o.level IN (0, 4)) r
  WHERE area > 0) s;
SELECT s.id, s.level,
       abs(st.area2d - s.a) / s.a < 1e-9 AS area2d_ok,
       abs(st.area3d - s.a3) / s.a3 < 1e-9 AS area3d_ok,
       abs(st.mean_z - s.mz) < 1e-9 * s.mz AS mean_z_ok,
       abs(st.mean_slope - s.ms) < 1e-7 AS mean_slope_ok,
       abs(st.max_slope - s.xs) < 1e-7 AS max_slope_ok,
       st.min_z >= (SELECT min(ST_ZMin(geom)) FROM area_tris WHERE level = s.level) AND st.min_z <= st.mean_z
         AND st.mean_z <= st.max_z AS z_range_ok,
       abs((v.cut - v.fill) - (s.mz - 500) * s.a) < 1e-9 * s.mz * s.a AS net_volume_ok
FROM (SELECT id, level, sum(area) AS a, sum(area / cos(radians(slope))) AS a3,
             sum(area * zc) / sum(area) AS mz, sum(area * slope) / sum(area) AS ms, max(slope) AS xs
      FROM area_clipped GROUP BY 1, 2) s
JOIN area_polys p USING (id), terrain,
LATERAL tin_area_stats(t, p.geom, s.level) st,
LATERAL tin_volume(t, p.geom, 500, s.level) v
ORDER BY 1, 2;
-- the same statistics once each level's subtree sums are made (a whole-
-- domain polygon per level does as much flat work as the level has
-- triangles, which makes them: docs/sql-reference.md, area merge; it has a
-- small hole, or the header's sums would answer it): coarse triangles
-- wholly inside now count in O(1); the same values up to rounding
CREATE TEMP TABLE area_flat AS
SELECT p.id, s.level, st.*, v.cut, v.fill
FROM (SELECT DISTINCT id, level FROM area_clipped) s JOIN area_polys p USING (id), terrain,
LATERAL tin_area_stats(t, p.geom, s.level) st, LATERAL tin_volume(t, p.geom, 500, s.level) v;
SELECT count(*) FROM terrain, generate_series(0, 4) l,
  tin_area_stats(t, ST_Difference(ST_Expand(tin_envelope(t), 100), ST_Buffer(ST_Centroid(tin_envelope(t)), 1)), l);
SELECT f.id, f.level,
       abs(st.area2d - f.area2d) <= 1e-12 * f.area2d AND abs(st.area3d - f.area3d) <= 1e-12 * f.area3d AS areas_same,
       abs(st.mean_z - f.mean_z) <= 1e-12 * f.mean_z AND abs(st.mean_slope - f.mean_slope) <= 1e-10 AS means_same,
       (st.min_z, st.max_z, st.max_slope) = (f.min_z, f.max_z, f.max_slope) AS extremes_same,
       abs(v.cut - f.cut) <= 1e-12 * (f.cut + f.fill) AND abs(v.fill - f.fill) <= 1e-12 * (f.cut + f.fill) AS volumes_same
FROM area_flat f JOIN area_polys p USING (id), terrain,
LATERAL tin_area_stats(t, p.geom, f.level) st, LATERAL tin_volume(t, p.geom, 500, f.level) v
ORDER BY 1, 2;
-- a box around the whole domain: the volume above a base under the lowest
-- point is the prism sum over the triangles (area times mean corner height)
SELECT l AS level,
       abs(v.cut - pr.prisms) / pr.prisms < 1e-12 AS prism_sum, v.fill
FROM terrain, generate_series(0, 4) l,
LATERAL tin_volume(t, ST_Expand(tin_envelope(t), 100), 0, l) v,
LATERAL (SELECT sum(ST_Area(geom) * (ST_Z(ST_PointN(ST_ExteriorRing(geom), 1)) + ST_Z(ST_PointN(ST_ExteriorRing(geom), 2))
                                     + ST_Z(ST_PointN(ST_ExteriorRing(geom), 3))) / 3) AS prisms
         FROM area_tris WHERE level = l) pr
ORDER BY 1;
-- a polygon wholly outside the domain: no rows, zero area, zero volume
SELECT count(*) FROM terrain, tin_area_triangles(t, ST_Translate(ST_Expand(tin_envelope(t), -10), 1e6, 0));
SELECT area2d, area3d, min_z, mean_z FROM terrain, tin_area_stats(t, ST_Translate(ST_Expand(tin_envelope(t), -10), 1e6, 0));
SELECT * FROM tin_volume((SELECT t FROM terrain), ST_Translate(ST_Expand((SELECT tin_envelope(t) FROM terrain), -10), 1e6, 0), 0);
-- empty polygon and NULLs
SELECT count(*) FROM terrain, tin_area_triangles(t, 'SRID=32616;POLYGON EMPTY'::geometry);
SELECT count(*) FROM terrain, tin_area_triangles(t, NULL::geometry);
SELECT count(*) FROM tin_area_triangles(NULL::tin, 'SRID=32616;POLYGON((0 0,1 0,1 1,0 0))');
SELECT count(*) FROM terrain, tin_volume(t, ST_Expand(tin_envelope(t), 1), NULL);
-- a geographic tin (0.25.0): areas in square metres on the spheroid, as
-- PostGIS's ST_Area(geography) of the polygon (its edges segmentized in
-- degrees, so that geodesics follow the straight lines in degrees the tin
-- clips along); cut - fill is the integral of (z - base), mean_z times area
CREATE TABLE terrain_geo AS SELECT tin_from_raster(rast, 8.0, 2) AS t FROM dem_geo;
SELECT count(*) > 0 FROM terrain_geo, tin_area_triangles(t, ST_Expand(tin_envelope(t), -0.01));
WITH p AS (SELECT t, ST_Expand(tin_envelope(t), -0.01) AS p FROM terrain_geo),
s AS (SELECT p, s.*, v.* FROM p, tin_area_stats(t, p) s, tin_volume(t, p, 300) v)
SELECT abs(area2d / ST_Area(ST_Segmentize(p, 0.0005)::geography) - 1) < 1e-6 AS area_as_postgis,
       area2d > 5e8 AS square_metres,
       area3d > area2d AND area3d < 1.1 * area2d AS surface_area,
       mean_slope BETWEEN 1 AND 30 AS slope_in_degrees,
       abs((cut - fill) - (mean_z - 300) * area2d) < 1e-9 * (cut + fill) AS volumes
FROM s;
-- the same for a polygon across the edge of the terrain, and tin_surface_area
WITH p AS (SELECT t, ST_Buffer(ST_Centroid(tin_envelope(t)), 0.2, 64) AS p FROM terrain_geo),
s AS (SELECT p, t, s.* FROM p, tin_area_stats(t, p) s)
SELECT abs(area2d / ST_Area(ST_Segmentize(ST_Intersection(p, tin_envelope(t)), 0.0005)::geography) - 1) < 1e-6 AS clipped_area_as_postgis,
       tin_surface_area(t, p) = area3d AS scalar_form
FROM s;
-- Tiles wholly inside a polygon answer from the whole-level sums in their
-- header (format 6, since 0.26.0): no triangle is read. The oracle is
-- PostGIS over each tile's triangles (tin_triangles): planar area, the
-- area-weighted mean of the corner heights (a linear surface's mean over
-- a triangle), min and max height; and the decoded/sliced counters of
-- tin_cache_stats do not move.
CREATE TABLE area_tiles AS SELECT tx, ty, t FROM dem_window, tin_tiles(rast, 50, 2.0, 3);
SELECT DISTINCT tin_info(t)->>'format' AS format FROM area_tiles;
CREATE TABLE area_circle AS
  SELECT ST_Buffer(ST_Centroid(ST_Envelope(rast::geometry)), 0.4 * ST_Width(rast) * ST_PixelWidth(rast), 64) AS geom
  FROM dem_window;
CREATE TEMP TABLE c_before AS SELECT * FROM tin_cache_stats();
CREATE TABLE area_whole AS
SELECT tx, ty, l, s.*
FROM area_tiles, area_circle c, generate_series(0, 2) l, tin_area_stats(t, c.geom, l) s
WHERE ST_Covers(c.geom, tin_envelope(t));
SELECT s.misses - b.misses AS decoded, s.sliced_blocks - b.sliced_blocks AS blocks_read
FROM tin_cache_stats() s, c_before b;
SELECT count(DISTINCT (tx, ty)) AS tiles_inside, count(*) AS rows FROM area_whole;
WITH o AS (
  SELECT tx, ty, l, sum(ST_Area(tr.geom)) AS area2d,
         sum(ST_Area(tr.geom) * (ST_Z(ST_PointN(ST_ExteriorRing(tr.geom), 1)) + ST_Z(ST_PointN(ST_ExteriorRing(tr.geom), 2))
                                 + ST_Z(ST_PointN(ST_ExteriorRing(tr.geom), 3))) / 3) / sum(ST_Area(tr.geom)) AS mean_z,
         min(ST_ZMin(tr.geom)) AS min_z, max(ST_ZMax(tr.geom)) AS max_z
  FROM area_tiles, generate_series(0, 2) l, tin_triangles(t, l) tr
  GROUP BY tx, ty, l)
SELECT count(*) AS compared,
       max(abs(w.area2d - o.area2d) / o.area2d) < 1e-12 AS area2d_ok,
       max(abs(w.mean_z - o.mean_z)) < 1e-9 AS mean_z_ok,
       bool_and(w.min_z = o.min_z AND w.max_z = o.max_z) AS extremes_ok,
       bool_and(w.area3d >= w.area2d AND w.mean_slope BETWEEN 0 AND w.max_slope) AS slopes_ok
FROM area_whole w JOIN o USING (tx, ty, l);
-- the same over every tile the circle meets, the usual query (no
-- ST_Intersection with the tiles: their domains meet on the seams): tiles
-- inside from their headers, the others through their triangles; the
-- planar area is PostGIS's of the tiles' triangles clipped to the circle,
-- and most of it lies in triangles wholly inside
WITH ours AS (
  SELECT sum(s.area2d) AS area2d, sum(s.mean_z * s.area2d) / sum(s.area2d) AS mean_z
  FROM area_tiles, area_circle c, tin_area_stats(t, c.geom) s
  WHERE tin_envelope(t) && c.geom),
clipped AS (
  SELECT ST_Area(ST_Intersection(tr.geom, c.geom)) AS a,
         (ST_Z(ST_PointN(ST_ExteriorRing(tr.geom), 1)) + ST_Z(ST_PointN(ST_ExteriorRing(tr.geom), 2))
          + ST_Z(ST_PointN(ST_ExteriorRing(tr.geom), 3))) / 3 AS zc, tr.geom, c.geom AS cg
  FROM area_tiles, area_circle c, tin_triangles(t) tr
  WHERE tr.geom && c.geom AND ST_Intersects(tr.geom, c.geom))
SELECT abs(ours.area2d - (SELECT sum(a) FROM clipped)) / ours.area2d < 1e-9 AS area2d_ok,
       (SELECT sum(a) FROM clipped WHERE ST_Within(geom, cg)) > 0.5 * ours.area2d AS mostly_inside
FROM ours;
-- a plan that takes the tiles in the outer loop meets three polygons in
-- turn for each tile (their rows interleaved): each row is its own
-- polygon's (the backend keeps the polygons it read last, by their
-- bytes); the oracle is PostGIS's area of each circle clipped to the
-- tiles' triangles
CREATE TABLE area_three AS
  SELECT i, ST_Buffer(ST_Translate(ST_Centroid(geom), 2000 * i, -1500 * i), 3000 + 1000 * i, 16) AS geom
  FROM area_circle, generate_series(1, 3) i;
WITH ours AS (
  SELECT c.i, sum(s.area2d) AS area2d, count(*) AS rows
  FROM area_tiles k
  CROSS JOIN LATERAL (SELECT i, geom FROM area_three c WHERE tin_envelope(k.t) && c.geom OFFSET 0) c,
  LATERAL tin_area_stats(k.t, c.geom) s
  GROUP BY c.i),
oracle AS (
  SELECT c.i, sum(ST_Area(ST_Intersection(tr.geom, c.geom))) AS area2d
  FROM area_tiles, area_three c, tin_triangles(t) tr
  WHERE tr.geom && c.geom
  GROUP BY c.i)
SELECT i, rows > 1 AS several_tiles, abs(ours.area2d - oracle.area2d) / oracle.area2d < 1e-9 AS area2d_ok
FROM ours JOIN oracle USING (i) ORDER BY i;
