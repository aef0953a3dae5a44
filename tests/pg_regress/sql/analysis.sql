-- Surface analyses (issue 27): exact contours and slope/aspect of a level,
-- against oracles computed here in SQL from tin_triangles (each triangle's
-- corners: the isoline piece where the height crosses its edges, a corner
-- at the height counting as above; the plane's gradient).
SET extra_float_digits = 0;
CREATE TABLE an_tris AS
SELECT tr.id, ST_X(a) ax, ST_Y(a) ay, ST_Z(a) az, ST_X(b) bx, ST_Y(b) by_, ST_Z(b) bz, ST_X(c) cx, ST_Y(c) cy, ST_Z(c) cz
FROM terrain, tin_triangles(t, 1) tr,
     LATERAL (SELECT ST_PointN(ST_ExteriorRing(tr.geom), 1) a, ST_PointN(ST_ExteriorRing(tr.geom), 2) b,
                     ST_PointN(ST_ExteriorRing(tr.geom), 3) c) p;
CREATE TABLE an_lines AS SELECT z, geom FROM terrain, tin_contours(t, 25, 1);
SELECT count(*) AS lines, count(DISTINCT z) AS heights, min(z), max(z),
       count(*) FILTER (WHERE ST_IsClosed(geom)) AS rings, bool_and(ST_SRID(geom) = 32616) AS srid,
       bool_and(GeometryType(geom) = 'LINESTRING') AS linestrings
FROM an_lines;
-- per height: the same number of pieces and the same total length; the
-- heights are the oracle's (every multiple of 25 m within the level's
-- height range), not taken from tin_contours' output
WITH heights AS (
  SELECT generate_series((ceil(min(least(az, bz, cz)) / 25) * 25)::int,
                         (floor(max(greatest(az, bz, cz)) / 25) * 25)::int, 25)::float8 AS z
  FROM an_tris
), cross_pts AS (
  SELECT z.z, t.id, e.k,
         CASE WHEN e.z1 = z.z THEN e.x1 WHEN e.z2 = z.z THEN e.x2 ELSE e.x1 + (z.z - e.z1) / (e.z2 - e.z1) * (e.x2 - e.x1) END AS x,
         CASE WHEN e.z1 = z.z THEN e.y1 WHEN e.z2 = z.z THEN e.y2 ELSE e.y1 + (z.z - e.z1) / (e.z2 - e.z1) * (e.y2 - e.y1) END AS y
  FROM heights z, an_tris t,
       LATERAL (VALUES (1, ax, ay, az, bx, by_, bz), (2, bx, by_, bz, cx, cy, cz), (3, cx, cy, cz, ax, ay, az)) e(k, x1, y1, z1, x2, y2, z2)
  WHERE (e.z1 >= z.z) <> (e.z2 >= z.z)
), oracle AS (
  SELECT z, count(*) FILTER (WHERE len > 0) AS pieces, sum(len) AS len
  FROM (SELECT z, id,
               sqrt(((array_agg(x ORDER BY k))[1] - (array_agg(x ORDER BY k))[2])^2 + ((array_agg(y ORDER BY k))[1] - (array_agg(y ORDER BY k))[2])^2) AS len
        FROM cross_pts GROUP BY z, id) p
  GROUP BY z
), got AS (
  SELECT z, sum(ST_NPoints(geom) - 1) AS pieces, sum(ST_Length(geom)) AS len FROM an_lines GROUP BY z
)
SELECT count(*) AS heights, count(*) FILTER (WHERE o.pieces = g.pieces) AS same_pieces,
       count(*) FILTER (WHERE abs(o.len - g.len) <= 1e-9 * o.len) AS same_length,
       count(*) FILTER (WHERE o.z IS NULL OR g.z IS NULL) AS height_missing
FROM (SELECT * FROM oracle WHERE pieces > 0) o FULL JOIN got g USING (z);
-- open lines end on the domain's edge (the boundary of the level's union)
SELECT count(*) AS open_lines,
       count(*) FILTER (WHERE ST_DWithin(ST_StartPoint(l.geom), ST_Boundary(d.u), 1e-6)
                          AND ST_DWithin(ST_EndPoint(l.geom), ST_Boundary(d.u), 1e-6)) AS ending_on_the_edge
FROM an_lines l, (SELECT ST_Union(tr.geom) AS u FROM terrain, tin_triangles(t, 1) tr) d
WHERE NOT ST_IsClosed(l.geom);
-- slope and aspect against the gradient of each triangle's plane
WITH g AS (
  SELECT id, ((bz - az) * (cy - ay) - (by_ - ay) * (cz - az)) / ((bx - ax) * (cy - ay) - (by_ - ay) * (cx - ax)) AS a,
             ((bx - ax) * (cz - az) - (bz - az) * (cx - ax)) / ((bx - ax) * (cy - ay) - (by_ - ay) * (cx - ax)) AS b
  FROM an_tris
)
SELECT count(*) AS triangles,
       count(*) FILTER (WHERE abs(s.slope - degrees(atan(sqrt(g.a ^ 2 + g.b ^ 2)))) < 1e-9) AS same_slope,
       count(*) FILTER (WHERE s.aspect IS NULL AND g.a = 0 AND g.b = 0
                           OR least(abs(s.aspect::numeric - (degrees(atan2(-g.a, -g.b)) + 360)::numeric % 360),
                                    360 - abs(s.aspect::numeric - (degrees(atan2(-g.a, -g.b)) + 360)::numeric % 360)) < 1e-7) AS same_aspect
FROM terrain, tin_slope_aspect(t, 1) s JOIN g ON g.id = s.triangle;
-- contours as vector tiles: one Mapbox vector tile of the 25 m contours
SELECT length(ST_AsMVT(q, 'contours')) > 1000 AS mvt
FROM (SELECT z, ST_AsMVTGeom(ST_Transform(geom, 3857), ST_TileEnvelope(12, 1089, 1599)) AS geom
      FROM an_lines WHERE ST_Transform(geom, 3857) && ST_TileEnvelope(12, 1089, 1599)) q;
-- NULLs and bad arguments
SELECT count(*) AS null_interval FROM terrain, tin_contours(t, NULL);
SELECT count(*) AS null_tin FROM tin_contours(NULL, 10);
SELECT count(*) FROM terrain, tin_contours(t, 0);
SELECT count(*) FROM terrain, tin_contours(t, -5, 0);
SELECT count(*) FROM terrain, tin_contours(t, 1e-6, 0);
SELECT count(*) FROM terrain, tin_contours(t, 25, 9);
-- a geographic tin (0.25.0): each triangle in the east and north metres
-- of its centroid's tangent plane (the three points: 10 m over 8.97 km
-- east, 20 m over 11.09 km north; computed apart in Python from the WGS84
-- earth-centred coordinates: slope 0.10029321520, aspect 219.43581355)
SELECT round(slope::numeric, 6) AS slope, round(aspect::numeric, 4) AS aspect
FROM tin_slope_aspect(tin_from_points('SRID=4326;MULTIPOINT Z ((-84.1 36.2 300), (-84.0 36.2 310), (-84.05 36.3 320))'::geometry, 1.0, 1));
-- and the geographic DEM's tin: the mean of its triangles' slopes weighted
-- by PostGIS's geodesic area of each is tin_area_stats' mean slope
CREATE TABLE an_geo AS SELECT tin_from_raster(rast, 8.0, 2) AS t FROM dem_geo;
SELECT abs(sum(s.slope * ST_Area(tr.geom::geography)) / sum(ST_Area(tr.geom::geography)) - st.mean_slope) < 1e-6 * st.mean_slope AS weighted_mean
FROM an_geo, tin_slope_aspect(t) s JOIN tin_triangles(t) tr ON tr.id = s.triangle,
     tin_area_stats(t, ST_Expand(tin_envelope(t), 1)) st
GROUP BY st.mean_slope;
DROP TABLE an_geo;
DROP TABLE an_tris, an_lines;
