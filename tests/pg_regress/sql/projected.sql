-- Metric measures on a third grid, against PostGIS on the triangles of
-- tin_triangles: the geographic DEM warped to CONUS Albers (EPSG:5070) by
-- gdalwarp (scripts/load-data.sh): 97.3 x 88.9 m pixels (not square) from a
-- fractional origin, nodata on its rotated border, and a hole of 20 x 15
-- pixels punched in here. Planar and surface areas, heights, slopes and
-- volumes inside polygons, exactly: PostGIS cuts each polygon by every
-- triangle it meets (ST_Intersection), and on each piece the surface is the
-- triangle's plane (plane_z, slope_factor, cut_fill of 00_setup.sql).
SET extra_float_digits = 0;
CREATE TABLE pj_rast AS
  SELECT ST_MapAlgebra(rast, 1, NULL, 'CASE WHEN [rast.x] BETWEEN 150 AND 169 AND [rast.y] BETWEEN 200 AND 214 THEN NULL ELSE [rast] END') AS rast
  FROM dem_albers;
SELECT ST_Width(rast) AS width, ST_Height(rast) AS height, ST_SRID(rast) AS srid, round(ST_ScaleX(rast)::numeric, 6) AS dx,
       round(ST_ScaleY(rast)::numeric, 6) AS dy, ST_UpperLeftX(rast) <> round(ST_UpperLeftX(rast)) AS fractional_origin,
       (ST_SummaryStats(rast)).count AS valid, ST_Width(rast) * ST_Height(rast) - (ST_SummaryStats(rast)).count AS nodata
FROM pj_rast;
CREATE TABLE pj AS SELECT tin_from_raster(rast, 2.0, 4) AS t FROM pj_rast;
CREATE TABLE pj_tris AS SELECT l AS level, tr.id, tr.geom FROM pj, generate_series(0, 3) l, tin_triangles(t, l) tr;
CREATE INDEX ON pj_tris USING gist (geom);
ANALYZE pj_tris;
-- the domain (PostGIS): the valid pixels' squares within the hull of their
-- centres; every level's triangles cover its area (the border and the hole
-- left out), and the surface area of the whole terrain is the sum of the
-- triangles' planar areas times their slope factors
CREATE TABLE pj_domain AS
  SELECT ST_Intersection((SELECT ST_Polygon(rast) FROM pj_rast),
                         (SELECT ST_ConvexHull(ST_Collect(p.geom)) FROM pj_rast, ST_PixelAsCentroids(rast, 1, true) p)) AS geom;
SELECT l.level, l.triangles,
       abs(l.area - ST_Area(d.geom)) <= 1e-9 * ST_Area(d.geom) AS area_is_domain,
       l.degenerate,
       abs(tin_surface_area(pj.t, (SELECT ST_Envelope(rast) FROM pj_rast), l.level) - l.area3d) <= 1e-9 * l.area3d AS surface_area
FROM (SELECT level, count(*) AS triangles, sum(ST_Area(geom)) AS area, sum(ST_Area(geom) * slope_factor(geom)) AS area3d,
             count(*) FILTER (WHERE ST_Area(geom) <= 0) AS degenerate
      FROM pj_tris GROUP BY 1) l, pj_domain d, pj
ORDER BY 1;
-- polygons: 8 circles of 1.5 km (seeded points), a square over the hole,
-- and one across the nodata border
CREATE TABLE pj_polys AS
  SELECT row_number() OVER ()::int AS id, ST_Buffer(g, 1500, 16) AS geom
  FROM (SELECT (ST_Dump(ST_GeneratePoints(ST_Buffer(geom, -2000), 8, 5070))).geom AS g FROM pj_domain) p
  UNION ALL SELECT 100, ST_Expand(ST_Centroid(ST_PixelAsPolygon(rast, 160, 207)), 1500) FROM pj_rast
  UNION ALL SELECT 101, ST_Expand(ST_PointN(ST_ExteriorRing(ST_ConvexHull(geom)), 1), 2000) FROM pj_domain;
SELECT count(*) AS polygons,
       count(*) FILTER (WHERE NOT ST_Covers(d.geom, p.geom)) AS partly_off_the_domain
FROM pj_polys p, pj_domain d;
CREATE TABLE pj_pieces AS
  SELECT p.id, t.level, t.geom AS tri, x.piece
  FROM pj_polys p JOIN pj_tris t ON t.level IN (0, 3) AND t.geom && p.geom AND ST_Intersects(t.geom, p.geom),
  LATERAL (SELECT (ST_Dump(ST_CollectionExtract(ST_Intersection(ST_Force2D(t.geom), p.geom), 3))).geom AS piece) x;
-- per piece: planar area, surface area, the integral of z (area times z at
-- the centroid: z is linear), its slope in degrees, its corners' heights,
-- the volume above and below 600 m
CREATE TABLE pj_oracle AS
  SELECT id, level, sum(a) AS area2d, sum(a * sf) AS area3d, min(zlo) AS min_z, max(zhi) AS max_z,
         sum(a * zc) / sum(a) AS mean_z, sum(a * slope) / sum(a) AS mean_slope,
         max(slope) FILTER (WHERE a > 1e-3) AS max_slope_big, max(slope) AS max_slope_any,
         sum(cut) AS cut, sum(fill) AS fill
  FROM (SELECT id, level, ST_Area(piece) AS a, slope_factor(tri) AS sf,
               plane_z(tri, ST_Centroid(piece)) AS zc,
               degrees(atan(sqrt(greatest(slope_factor(tri) ^ 2 - 1, 0)))) AS slope,
               (SELECT min(plane_z(tri, (dp).geom)) FROM ST_DumpPoints(piece) dp) AS zlo,
               (SELECT max(plane_z(tri, (dp).geom)) FROM ST_DumpPoints(piece) dp) AS zhi,
               cf.cut, cf.fill
        FROM pj_pieces, cut_fill(piece, tri, NULL, 600) cf) x
  GROUP BY 1, 2;
SELECT o.level, count(*) AS polygons,
       count(*) FILTER (WHERE abs(s.area2d - o.area2d) > 1e-9 * o.area2d OR abs(s.area3d - o.area3d) > 1e-9 * o.area3d) AS areas_differ,
       count(*) FILTER (WHERE abs(s.mean_z - o.mean_z) > 1e-9 OR abs(s.min_z - o.min_z) > 1e-9 OR abs(s.max_z - o.max_z) > 1e-9) AS heights_differ,
       count(*) FILTER (WHERE abs(s.mean_slope - o.mean_slope) > 1e-9
                          OR s.max_slope < o.max_slope_big - 1e-9 OR s.max_slope > o.max_slope_any + 1e-9) AS slopes_differ,
       count(*) FILTER (WHERE abs(v.cut - o.cut) > 1e-9 * (o.cut + o.fill) OR abs(v.fill - o.fill) > 1e-9 * (o.cut + o.fill)) AS volumes_differ,
       count(*) FILTER (WHERE o.cut > 0 AND o.fill > 0) AS both_ways
FROM pj_oracle o JOIN pj_polys p USING (id), pj,
     tin_area_stats(pj.t, p.geom, o.level) s, tin_volume(pj.t, p.geom, 600, o.level) v
GROUP BY 1 ORDER BY 1;
