-- Point merge against independent oracles in PostGIS: for each level, every
-- triangle of tin_triangles in a GiST-indexed table, tested with
-- ST_Intersects (smallest id wins on shared edges and vertices); heights from
-- the plane through that triangle's corners computed here in SQL; footprints
-- against ST_Intersects with the rectangle built by ST_Rotate.
SET extra_float_digits = 0;
CREATE TABLE tris AS
  SELECT l AS level, tr.id, tr.geom FROM terrain, generate_series(0, 4) l, tin_triangles(t, l) tr;
CREATE INDEX ON tris USING gist (geom);
ANALYZE tris;
SELECT level, count(*) FROM tris GROUP BY level ORDER BY level;
-- test points per level: 10,000 uniform over the bbox grown by 5 % (some
-- outside the domain), 2,000 exact vertices, 2,000 edge midpoints, 500 far away
SELECT setseed(0.42);
CREATE TABLE pts AS
WITH b AS (SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h
           FROM (SELECT tin_envelope(t)::box2d e FROM terrain) s)
SELECT l AS level, 'random' AS kind,
       ST_SetSRID(ST_MakePoint(x0 - 0.05 * w + random() * 1.1 * w, y0 - 0.05 * h + random() * 1.1 * h), 32616) AS geom
FROM b, generate_series(0, 4) l, generate_series(1, 10000)
UNION ALL
SELECT level, 'far outside', ST_SetSRID(ST_MakePoint(x0 + w / 2 + cos(a) * w, y0 + h / 2 + sin(a) * h), 32616)
FROM b, generate_series(0, 4) level, LATERAL (SELECT random() * 2 * pi() AS a, g FROM generate_series(1, 500) g) r;
INSERT INTO pts
SELECT level, 'vertex', ST_SetSRID(ST_PointN(ST_ExteriorRing(geom), 1 + (id % 3)), 32616)
FROM (SELECT level, id, geom, row_number() OVER (PARTITION BY level ORDER BY md5(id::text)) rn FROM tris) z
WHERE rn <= 2000;
INSERT INTO pts
SELECT level, 'edge midpoint', ST_SetSRID(ST_MakePoint((ST_X(a) + ST_X(b)) / 2, (ST_Y(a) + ST_Y(b)) / 2), 32616)
FROM (SELECT level, ST_PointN(ST_ExteriorRing(geom), 1 + (id % 3)) a, ST_PointN(ST_ExteriorRing(geom), 2 + (id % 3)) b,
             row_number() OVER (PARTITION BY level ORDER BY md5(id::text || 'e')) rn FROM tris) z
WHERE rn <= 2000;
SELECT level, kind, count(*) FROM pts GROUP BY 1, 2 ORDER BY 1, 2;
-- the oracle's answer for every point
CREATE TABLE oracle AS
SELECT p.level, p.kind, p.geom,
       (SELECT min(id) FROM tris t WHERE t.level = p.level AND ST_Intersects(t.geom, p.geom)) AS id
FROM pts p;
-- height on the oracle's triangle: plane through its three corners
-- (plane_z: 00_setup.sql, the height of a triangle's plane by Cramer's rule)
-- per level and kind: points inside/outside, and disagreements (must be 0)
SELECT o.level, o.kind,
       count(*) FILTER (WHERE o.id IS NOT NULL) AS inside,
       count(*) FILTER (WHERE o.id IS NULL) AS outside,
       count(*) FILTER (WHERE tin_locate(t, o.geom, o.level) IS DISTINCT FROM o.id) AS locate_wrong,
       count(*) FILTER (WHERE (o.id IS NULL) <> (tin_height(t, o.geom, o.level) IS NULL)
                          OR abs(tin_height(t, o.geom, o.level) - plane_z(tr.geom, o.geom)) > 1e-6) AS height_wrong
FROM oracle o CROSS JOIN terrain LEFT JOIN tris tr ON tr.level = o.level AND tr.id = o.id
GROUP BY 1, 2 ORDER BY 1, 2;
-- NULL level = finest; the point's own Z is ignored; vertices give their own Z
SELECT count(*) FILTER (WHERE tin_locate(t, geom) IS DISTINCT FROM tin_locate(t, geom, 4)) AS finest_differs,
       count(*) FILTER (WHERE tin_height(t, ST_Force3DZ(geom)) IS DISTINCT FROM tin_height(t, geom)) AS z_matters
FROM pts, terrain WHERE level = 4;
SELECT count(*) AS vertex_heights_wrong
FROM (SELECT (ST_DumpPoints(geom)).geom AS v FROM tris WHERE level = 4 AND id % 50 = 0) s, terrain
WHERE abs(tin_height(t, v) - ST_Z(v)) > 1e-9;
-- tin_drape of points and multipoints: same x, y, Z = tin_height; outside dropped
SELECT count(*) AS drape_wrong FROM pts p, terrain
WHERE level = 4 AND tin_height(t, geom) IS NOT NULL
  AND NOT (ST_X(tin_drape(t, geom)) = ST_X(geom) AND ST_Y(tin_drape(t, geom)) = ST_Y(geom)
           AND ST_Z(tin_drape(t, geom)) = tin_height(t, geom));
SELECT count(*) AS drape_outside_not_null FROM pts p, terrain
WHERE level = 4 AND tin_height(t, geom) IS NULL AND tin_drape(t, geom) IS NOT NULL;
SELECT ST_NumGeometries(d) = (SELECT count(*) FROM pts, terrain WHERE level = 2 AND kind = 'random' AND tin_height(t, geom, 2) IS NOT NULL) AS multipoint_keeps_inside,
       ST_SRID(d), ST_CoordDim(d)
FROM (SELECT tin_drape(t, (SELECT ST_Collect(geom) FROM pts WHERE level = 2 AND kind = 'random'), 2) d FROM terrain) s;
SELECT ST_AsText(tin_drape(t, 'SRID=32616;POINT(700000 4000000)'::geometry)) FROM terrain;
-- footprints against ST_Intersects with the rotated rectangle
SELECT setseed(0.7);
CREATE TABLE rects AS
WITH b AS (SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h
           FROM (SELECT tin_envelope(t)::box2d e FROM terrain) s)
-- (random() drawn in (level, i) order whatever order the planner joins in)
SELECT l AS level, i, x0 - 0.1 * w + random() * 1.2 * w AS x, y0 - 0.1 * h + random() * 1.2 * h AS y,
       random() * (ARRAY[20, 500, 5000])[1 + i % 3] AS width, random() * (ARRAY[20, 500, 5000])[1 + i % 3] AS length,
       random() * 720 - 360 AS angle
FROM (SELECT * FROM b, generate_series(0, 4) l, generate_series(1, 100) i ORDER BY l, i OFFSET 0) s;
SELECT r.level,
       count(*) AS footprints,
       sum(cardinality(got)) AS triangles,
       count(*) FILTER (WHERE got IS DISTINCT FROM want) AS wrong
FROM rects r, terrain,
     LATERAL (SELECT coalesce(array_agg(f ORDER BY f), '{}') AS got
              FROM tin_footprint(t, ST_SetSRID(ST_MakePoint(r.x, r.y), 32616), r.width, r.length, r.angle, r.level) f) g,
     LATERAL (SELECT coalesce(array_agg(id ORDER BY id), '{}') AS want FROM tris
              WHERE tris.level = r.level AND ST_Intersects(tris.geom,
                ST_Rotate(ST_MakeEnvelope(r.x - r.width / 2, r.y - r.length / 2, r.x + r.width / 2, r.y + r.length / 2, 32616),
                          -radians(r.angle), r.x, r.y))) w
GROUP BY 1 ORDER BY 1;
-- a zero-size footprint is the point: the same triangles as ST_Intersects
SELECT count(*) AS point_footprint_wrong FROM pts p, terrain
WHERE level = 3 AND kind IN ('vertex', 'edge midpoint')
  AND ARRAY(SELECT tin_footprint(t, p.geom, 0, 0, 0, 3))
      IS DISTINCT FROM ARRAY(SELECT id FROM tris WHERE level = 3 AND ST_Intersects(tris.geom, p.geom) ORDER BY id);
-- per-row calls on one stored tin decode it once (hits, no new misses)
SELECT misses AS misses_before FROM tin_cache_stats() \gset
SELECT count(tin_height(t, geom)) > 0 FROM pts, terrain;
SELECT misses - :misses_before AS new_misses FROM tin_cache_stats();
