-- tin_line_of_sight (issue 49) against PostGIS: the sight line's ground
-- track cut by every triangle of the level it meets (ST_Intersection over a
-- GiST join of tin_triangles), and at each cut's ends the sight line's
-- height minus plane_z (00_setup.sql) of that triangle: blocked where it
-- is below 0 strictly between the two points. 300 random pairs on the UTM
-- DEM at levels 1 and 4, and 300 on the geographic DEM at level 2.
SET extra_float_digits = 0;
SELECT setseed(0.49);
CREATE TABLE los_tins AS
SELECT 'utm' AS name, t, 1 AS level FROM terrain
UNION ALL SELECT 'utm', t, 4 FROM terrain
UNION ALL SELECT 'geographic', tin_from_raster(rast, 2.0, 3), 2 FROM dem_geo;
CREATE TABLE los_tris AS SELECT a.name, a.level, tr.geom FROM los_tins a, tin_triangles(a.t, a.level) tr;
CREATE INDEX ON los_tris USING gist (geom);
ANALYZE los_tris;
-- pairs inside the middle of each DEM's extent (where it has data), eyes
-- 0-30 m above the ground, targets 0-10 m, every other one on the ground
-- (target_height 0, the default: it touches the sight line)
CREATE TABLE los_pairs AS
SELECT a.name, a.level, i, o, g, tin_height(a.t, o, a.level) + oh AS zo, tin_height(a.t, g, a.level) + th AS zt, oh, th
-- (the tins in a fixed order and the pairs LATERAL to them: random() is
-- drawn in the same order whatever plan the statistics give)
FROM (SELECT * FROM los_tins ORDER BY name, level) a, LATERAL generate_series(1, 300) i,
     LATERAL (SELECT ST_XMin(e) + (0.15 + 0.7 * random()) * (ST_XMax(e) - ST_XMin(e)) AS x1, ST_YMin(e) + (0.15 + 0.7 * random()) * (ST_YMax(e) - ST_YMin(e)) AS y1,
                     ST_XMin(e) + (0.15 + 0.7 * random()) * (ST_XMax(e) - ST_XMin(e)) AS x2, ST_YMin(e) + (0.15 + 0.7 * random()) * (ST_YMax(e) - ST_YMin(e)) AS y2,
                     30 * random() AS oh, CASE WHEN i % 2 = 0 THEN 0 ELSE 10 * random() END AS th, i AS k
              FROM (SELECT tin_envelope(a.t) AS e) e) r,
     LATERAL (SELECT ST_SetSRID(ST_MakePoint(x1, y1), ST_SRID(tin_envelope(a.t))) AS o, ST_SetSRID(ST_MakePoint(x2, y2), ST_SRID(tin_envelope(a.t))) AS g) p;
CREATE TABLE los_oracle AS
SELECT p.name, p.level, p.i,
       min(p.zo + (p.zt - p.zo) * ST_Distance(p.o, e.pt) / ST_Distance(p.o, p.g) - plane_z(c.tri, e.pt))
         FILTER (WHERE ST_Distance(p.o, e.pt) > 1e-9 * ST_Distance(p.o, p.g) AND ST_Distance(p.g, e.pt) > 1e-9 * ST_Distance(p.o, p.g)) AS clearance
FROM los_pairs p
CROSS JOIN LATERAL (SELECT tr.geom AS tri, (ST_Dump(ST_Intersection(ST_MakeLine(p.o, p.g), ST_Force2D(tr.geom)))).geom AS piece
                    FROM los_tris tr WHERE tr.name = p.name AND tr.level = p.level AND ST_Intersects(tr.geom, ST_MakeLine(p.o, p.g))) c
CROSS JOIN LATERAL (SELECT ST_PointN(c.piece, k) AS pt FROM generate_series(1, 2) k WHERE GeometryType(c.piece) = 'LINESTRING') e
GROUP BY 1, 2, 3;
CREATE TABLE los_got AS
SELECT p.name, p.level, p.i, s.*
FROM los_pairs p JOIN los_tins a ON a.name = p.name AND a.level = p.level,
     tin_line_of_sight(a.t, p.o, p.g, p.oh, p.th, p.level) s;
-- the same verdicts (pairs grazing within 1e-6 m left out, none expected),
-- the same clearance, the obstruction on the surface and on the sight line
SELECT o.name, o.level, count(*) AS pairs, count(*) FILTER (WHERE NOT g.visible) AS blocked,
       count(*) FILTER (WHERE abs(o.clearance) < 1e-6) AS grazing,
       count(*) FILTER (WHERE abs(o.clearance) >= 1e-6 AND g.visible <> (o.clearance > 0)) AS verdicts_differ,
       count(*) FILTER (WHERE abs(g.clearance - o.clearance) > 1e-6) AS clearances_differ,
       count(*) FILTER (WHERE NOT g.visible AND abs(ST_Z(g.obstruction) - tin_height(a.t, g.obstruction, o.level)) > 1e-6) AS obstruction_off_surface,
       count(*) FILTER (WHERE NOT g.visible AND abs(ST_Z(g.obstruction) - (p.zo + (p.zt - p.zo) * g.distance / ST_Distance(p.o, p.g))) > 1e-6) AS obstruction_off_sight_line,
       count(*) FILTER (WHERE NOT g.visible AND abs(g.distance - ST_Distance(p.o, g.obstruction)) > 1e-9 * ST_Distance(p.o, p.g)) AS distance_wrong
FROM los_oracle o JOIN los_got g USING (name, level, i) JOIN los_pairs p USING (name, level, i)
     JOIN los_tins a ON a.name = o.name AND a.level = o.level
GROUP BY 1, 2 ORDER BY 1, 2;
-- the earth's curvature: over flat ground, an eye 100 m up sees the ground
-- up to sqrt(2 R h / (1 - k)) = 38,270 m away (k = 0.13), and an eye 1.7 m
-- up (with k = 0) 4,654 m
CREATE TABLE los_flat AS
SELECT tin_from_points(ST_SetSRID('MULTIPOINT Z ((-100000 -100000 0), (100000 -100000 0), (100000 100000 0), (-100000 100000 0), (0 0 0))'::geometry, 32616), 0.0, 1) AS t;
SELECT d, h, k, (SELECT visible FROM tin_line_of_sight(t, ST_SetSRID(ST_MakePoint(-d / 2, 1), 32616), ST_SetSRID(ST_MakePoint(d / 2, 1), 32616), h, 0, curvature => true, refraction => k)) AS with_curvature,
       (SELECT visible FROM tin_line_of_sight(t, ST_SetSRID(ST_MakePoint(-d / 2, 1), 32616), ST_SetSRID(ST_MakePoint(d / 2, 1), 32616), h, 0)) AS flat
FROM los_flat, (VALUES (38000.0, 100.0, 0.13), (38600.0, 100.0, 0.13), (4600.0, 1.7, 0.0), (4700.0, 1.7, 0.0)) v(d, h, k) ORDER BY h DESC, d;
-- a POINT Z is an absolute height; untyped literals; defaults
SELECT s.visible, round(s.distance) AS distance, ST_AsText(ST_SnapToGrid(s.obstruction, 1)) AS obstruction
FROM terrain, tin_line_of_sight(t, 'SRID=32616;POINT Z (741000 4055000 200)', 'SRID=32616;POINT(744000 4059000)') s;
SELECT s.visible FROM terrain, tin_line_of_sight(t, 'SRID=32616;POINT Z (741000 4055000 5000)', 'SRID=32616;POINT(744000 4059000)') s;
-- NULLs: no row; bad input, one per line
SELECT count(*) AS null_observer FROM terrain, tin_line_of_sight(t, NULL, 'SRID=32616;POINT(744000 4059000)');
SELECT count(*) AS null_height FROM terrain, tin_line_of_sight(t, 'SRID=32616;POINT(741000 4055000)', 'SRID=32616;POINT(744000 4059000)', NULL);
SELECT try($$SELECT * FROM terrain, tin_line_of_sight(t, 'SRID=4326;POINT(-84 36)', 'SRID=32616;POINT(744000 4059000)')$$);
SELECT try($$SELECT * FROM terrain, tin_line_of_sight(t, 'SRID=32616;LINESTRING(741000 4055000, 741001 4055000)', 'SRID=32616;POINT(744000 4059000)')$$);
SELECT try($$SELECT * FROM terrain, tin_line_of_sight(t, 'SRID=32616;POINT(1000 1000)', 'SRID=32616;POINT(744000 4059000)')$$);
SELECT try($$SELECT * FROM terrain, tin_line_of_sight(t, 'SRID=32616;POINT(741000 4055000)', 'SRID=32616;POINT(744000 4059000)', 'Infinity')$$);
SELECT try($$SELECT * FROM terrain, tin_line_of_sight(t, 'SRID=32616;POINT(741000 4055000)', 'SRID=32616;POINT(744000 4059000)', level => 7)$$);
SELECT try($$SELECT * FROM terrain, tin_line_of_sight(t, 'SRID=32616;POINT EMPTY', 'SRID=32616;POINT(744000 4059000)')$$);
DROP TABLE los_tins, los_tris, los_pairs, los_oracle, los_got, los_flat;
