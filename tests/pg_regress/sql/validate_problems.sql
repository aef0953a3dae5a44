-- tin_validate names each problem it knows, on a value made to have it
-- (tests/data/problems/, written by crates/tinmerge-core/tests/validate.rs):
-- a sliver (a triangle of zero area up to rounding whose corner lies on the
-- opposite edge at the edge's height), a crack (that corner at another
-- height: a wall) and a hole (one triangle uses a second centre vertex 3
-- ulps from the first). The oracle is PostGIS on tin_triangles: the
-- triangle of zero area up to rounding, its height range, and the edges
-- used by one triangle that are not on the outer boundary.
\getenv abs_srcdir PG_ABS_SRCDIR
\set sliver :abs_srcdir '/../data/problems/sliver.tin'
\set crack :abs_srcdir '/../data/problems/crack.tin'
\set hole :abs_srcdir '/../data/problems/hole.tin'
CREATE TABLE vp AS
SELECT 'sliver' AS name, encode(pg_read_binary_file(:'sliver'), 'hex')::tin AS t
UNION ALL SELECT 'crack', encode(pg_read_binary_file(:'crack'), 'hex')::tin
UNION ALL SELECT 'hole', encode(pg_read_binary_file(:'hole'), 'hex')::tin;
-- what tin_validate reports: one problem of the value's own kind
SELECT name, v.level, v.problem, count(*) AS rows
FROM vp, tin_validate(t) v GROUP BY 1, 2, 3 ORDER BY 1, 2, 3;
-- sliver and crack: the triangle named is the one PostGIS finds of zero
-- area (2 x 2 square: under 1e-15), a crack where it is not flat
WITH named AS (SELECT name, t, v.triangle, v.problem FROM vp, tin_validate(t) v WHERE name <> 'hole'),
pg AS (SELECT name, tr.id, ST_ZMax(tr.geom) - ST_ZMin(tr.geom) AS jump
       FROM vp, tin_triangles(t) tr WHERE name <> 'hole' AND ST_Area(tr.geom) < 1e-15)
SELECT n.name, n.triangle = p.id AS same_triangle,
       n.problem = CASE WHEN p.jump > 0 THEN 'crack' ELSE 'sliver' END AS same_kind
FROM named n JOIN pg p USING (name) ORDER BY 1;
-- hole: PostGIS's edges used by one triangle only that are not on the
-- outer boundary (the unit square's sides); every triangle on one is named
WITH tr AS (SELECT id, geom FROM vp, tin_triangles(t) WHERE name = 'hole'),
edge AS (SELECT id, ST_MakeLine(ST_PointN(ST_ExteriorRing(geom), k), ST_PointN(ST_ExteriorRing(geom), k + 1)) AS e
         FROM tr, generate_series(1, 3) k),
canon AS (SELECT id, CASE WHEN (ST_X(ST_StartPoint(e)), ST_Y(ST_StartPoint(e))) < (ST_X(ST_EndPoint(e)), ST_Y(ST_EndPoint(e)))
                          THEN e ELSE ST_Reverse(e) END AS e FROM edge),
-- (edges keyed by their exact coordinates: WKB, not text, which rounds)
used AS (SELECT ST_AsBinary(e) AS k, array_agg(id) AS ids, (array_agg(e))[1] AS e FROM canon GROUP BY 1),
inner_gap AS (SELECT unnest(ids) AS id FROM used
              WHERE cardinality(ids) = 1
                AND NOT ST_Covers(ST_Boundary(ST_MakeEnvelope(0, 0, 1, 1, 32616)), e)),
want AS (SELECT DISTINCT id FROM inner_gap),
got AS (SELECT DISTINCT v.triangle AS id FROM vp, tin_validate(t) v WHERE name = 'hole')
SELECT (SELECT count(*) FROM want) AS postgis_triangles_on_a_gap,
       (SELECT count(*) FROM got) AS named,
       NOT EXISTS (SELECT id FROM want EXCEPT SELECT id FROM got)
       AND NOT EXISTS (SELECT id FROM got EXCEPT SELECT id FROM want) AS same;
-- they still answer: the values read, and the sound parts work
SELECT name, tin_num_triangles(t) AS triangles, round(tin_height(t, 'SRID=32616;POINT(0.9 0.3)')::numeric, 6) AS z
FROM vp ORDER BY 1;
DROP TABLE vp;
