-- Line merge against an independent oracle in PostGIS: the real contour lines
-- of the DEM (gdal_contour, every 50 m; loaded by the runner as table
-- contours) intersected with every triangle of tin_triangles in a
-- GiST-indexed table (ST_Intersection), at a coarse and the finest level.
SET extra_float_digits = 0;
SELECT count(*) AS contours, sum(ST_NPoints(geom)) AS vertices, min(elev), max(elev) FROM contours;
CREATE TABLE line_tris AS
  SELECT l AS level, tr.id, tr.geom FROM terrain, unnest(ARRAY[1, 4]) l, tin_triangles(t, l) tr;
CREATE INDEX ON line_tris USING gist (geom);
ANALYZE line_tris;
-- ours: planar length per (contour, level, triangle)
-- (every third contour: 208 lines, 22,000 vertices, ~65,000 line/triangle pairs)
CREATE TABLE line_ours AS
SELECT c.id, l AS level, s.triangle, sum(s.length2d) AS len, count(*) AS pieces
FROM contours c, terrain, unnest(ARRAY[1, 4]) l, tin_line_segments(t, c.geom, l) s
WHERE c.id % 3 = 0
GROUP BY 1, 2, 3;
-- oracle: length of the intersection with each triangle polygon
CREATE TABLE line_oracle AS
SELECT c.id, tr.level, tr.id AS triangle, ST_Length(ST_Intersection(c.geom, tr.geom)) AS len
FROM contours c JOIN line_tris tr ON ST_Intersects(c.geom, tr.geom)
WHERE c.id % 3 = 0;
-- same triangle sets: every triangle the oracle finds a stretch of the line
-- in (longer than 1 micrometre, below GEOS's rounding of crossing points) is
-- ours, and every triangle of ours is the oracle's
SELECT o.level, count(*) AS oracle_triangles,
       count(*) FILTER (WHERE o.len > 1e-6 AND u.triangle IS NULL) AS missed
FROM line_oracle o LEFT JOIN line_ours u USING (id, level, triangle)
GROUP BY 1 ORDER BY 1;
SELECT u.level, count(*) AS our_triangles,
       count(*) FILTER (WHERE o.triangle IS NULL OR o.len = 0) AS not_in_oracle,
       count(*) FILTER (WHERE abs(u.len - o.len) > 1e-6) AS length_differs
FROM line_ours u LEFT JOIN line_oracle o USING (id, level, triangle)
GROUP BY 1 ORDER BY 1;
-- sum of length2d = the length of the line inside the domain (by PostGIS:
-- the valid pixels' squares within the hull of their centres); to 1e-9
-- relative
CREATE TABLE line_hull AS SELECT ST_Intersection((SELECT ST_Polygon(rast) FROM dem),
                       (SELECT ST_ConvexHull(ST_Collect(p.geom)) FROM dem, ST_PixelAsCentroids(rast, 1, true) p)) AS h;
SELECT level,
       count(*) FILTER (WHERE ST_Within(c.geom, h)) AS contours_inside,
       count(*) FILTER (WHERE ST_Within(c.geom, h)
                          AND abs(s.len - ST_Length(c.geom)) > 1e-9 * ST_Length(c.geom)) AS inside_length_wrong,
       count(*) FILTER (WHERE NOT ST_Within(c.geom, h)
                          AND abs(s.len - ST_Length(ST_Intersection(c.geom, h))) > 1e-6 * ST_Length(c.geom)) AS partly_outside_length_wrong
FROM contours c, line_hull,
     (SELECT id, level, sum(len) AS len FROM line_ours GROUP BY 1, 2) s
WHERE s.id = c.id
GROUP BY 1 ORDER BY 1;
-- draped vertices lie on the surface (tin_height), and the contour drapes to
-- its own height within the level's tolerance (measured at the contour's
-- own vertices, which gdal_contour interpolates between pixel centres)
CREATE TABLE line_draped AS
SELECT c.id, c.elev, l AS level, (ST_DumpPoints(tin_drape(t, c.geom, l))).geom AS p
FROM contours c, terrain, unnest(ARRAY[1, 4]) l WHERE c.id % 3 = 0;
-- (crossing points computed on a hull edge may round to just outside it:
-- tin_height is NULL there when farther than 16 units in the last place;
-- 26 such points before 0.21.1, which answers the nearer ones)
SELECT level, count(*) AS draped_vertices,
       count(*) FILTER (WHERE abs(ST_Z(p) - tin_height(t, p, level)) > 1e-6) AS off_surface,
       count(*) FILTER (WHERE tin_height(t, p, level) IS NULL
                          AND ST_DWithin(p, ST_Boundary((SELECT h FROM line_hull)), 1e-6)) AS rounded_off_the_hull,
       count(*) FILTER (WHERE tin_height(t, p, level) IS NULL
                          AND NOT ST_DWithin(p, ST_Boundary((SELECT h FROM line_hull)), 1e-6)) AS outside
FROM line_draped, terrain GROUP BY 1 ORDER BY 1;
-- gdal_contour places each contour vertex on the segment between two
-- neighbouring pixel centres A and B, at the height interpolated linearly
-- between them. A level is within its tolerance of every sample, so where A,
-- B and the vertex lie in one triangle (the surface is linear along AB) the
-- draped vertex is within tolerance of the contour's value: checked at every
-- such vertex. Elsewhere the surface may bend between samples; the spread is
-- shown, not bounded (the tolerance holds at samples, not between them).
CREATE TABLE line_cv AS
SELECT c.id, c.elev, l AS level, v.geom AS v,
       (ST_X(v.geom) - ST_X(o)) / 90 AS cx, (ST_Y(o) - ST_Y(v.geom)) / 90 AS cy, o
FROM contours c, unnest(ARRAY[1, 4]) l, ST_DumpPoints(c.geom) v,
     (SELECT ST_PixelAsCentroid(rast, 1, 1) o FROM dem) d
WHERE c.id % 3 = 0;
CREATE TABLE line_ab AS
SELECT id, elev, level, v,
       ST_MakeLine(ST_Translate(o, 90 * a1, -90 * b1), ST_Translate(o, 90 * a2, -90 * b2)) AS ab
FROM (SELECT *, CASE WHEN abs(cx - round(cx)) < 1e-6 THEN round(cx) ELSE floor(cx) END a1,
                CASE WHEN abs(cx - round(cx)) < 1e-6 THEN round(cx) ELSE ceil(cx) END a2,
                CASE WHEN abs(cx - round(cx)) < 1e-6 THEN floor(cy) ELSE round(cy) END b1,
                CASE WHEN abs(cx - round(cx)) < 1e-6 THEN ceil(cy) ELSE round(cy) END b2
      FROM line_cv) s;
SELECT l.level, tin_tolerance(t, l.level) AS tolerance, count(*) AS vertices_with_ab_in_one_triangle,
       count(*) FILTER (WHERE abs(tin_height(t, l.v, l.level) - l.elev) > tin_tolerance(t, l.level) + 1e-9) AS beyond_tolerance
FROM line_ab l, terrain, line_tris tr
WHERE tr.level = l.level AND tr.id = tin_locate(t, l.v, l.level) AND ST_Covers(tr.geom, l.ab)
GROUP BY 1, 2 ORDER BY 1;
SELECT level, round(percentile_cont(0.5) WITHIN GROUP (ORDER BY abs(tin_height(t, v, level) - elev))::numeric, 1) AS median_dev,
       round(percentile_cont(0.9) WITHIN GROUP (ORDER BY abs(tin_height(t, v, level) - elev))::numeric, 1) AS p90_dev
FROM line_ab, terrain WHERE tin_height(t, v, level) IS NOT NULL GROUP BY 1 ORDER BY 1;
-- tin_line_triangles is the sequence of tin_line_segments' triangles
SELECT count(*) AS sequences_differ FROM contours c, terrain
WHERE ARRAY(SELECT triangle FROM tin_line_triangles(t, c.geom, 4) ORDER BY seq)
   IS DISTINCT FROM ARRAY(SELECT triangle FROM tin_line_segments(t, c.geom, 4) ORDER BY seq);
-- profile against PostGIS (every third contour): the point at `distance`
-- along the line (ST_LineInterpolatePoint), and the height there of the
-- finest level's triangle holding it (plane_z); distances from 0 up to
-- the line's length, never decreasing
CREATE TABLE lt_profile AS
SELECT c.id, p.distance, p.z, ST_Length(c.geom) AS len,
       ST_LineInterpolatePoint(c.geom, least(1, p.distance / ST_Length(c.geom))) AS pt,
       lag(p.distance) OVER (PARTITION BY c.id ORDER BY p.distance) AS prev
FROM contours c, terrain, tin_line_profile(t, c.geom) p WHERE c.id % 3 = 0;
-- (the triangle nearest the point: a point on the domain's edge can lie
-- a rounding outside it)
ALTER TABLE lt_profile ADD COLUMN oz float8, ADD COLUMN off float8;
UPDATE lt_profile p SET oz = o.z, off = o.d
FROM (SELECT q.id, q.distance, n.z, n.d FROM lt_profile q,
      LATERAL (SELECT plane_z(tr.geom, q.pt) AS z, ST_Distance(tr.geom, q.pt) AS d FROM line_tris tr
               WHERE tr.level = 4 ORDER BY tr.geom <-> q.pt LIMIT 1) n) o
WHERE o.id = p.id AND o.distance = p.distance;
SELECT count(*) > 50000 AS many_points, count(DISTINCT id) AS lines,
       count(*) FILTER (WHERE off > 1e-6) AS off_the_terrain,
       count(*) FILTER (WHERE abs(oz - z) > 1e-6) AS z_differs,
       count(*) FILTER (WHERE distance < 0 OR distance > len * (1 + 1e-12) OR distance < prev) AS distance_wrong
FROM lt_profile;
-- a line inside the domain: the profile runs from 0 to its whole length
SELECT count(*) AS inside_lines,
       count(*) FILTER (WHERE abs(first - 0) > 1e-9 OR abs(last - len) > 1e-6 * len) AS ends_wrong
FROM (SELECT id, min(distance) AS first, max(distance) AS last, max(len) AS len FROM lt_profile GROUP BY id) s
JOIN contours c USING (id), line_hull WHERE ST_Within(c.geom, h);
-- climb: the sum of the positive steps between consecutive profile heights
-- taken from PostGIS (plane_z, above), along every ninth contour
SELECT count(*) AS lines, count(*) FILTER (WHERE abs(coalesce(o.climb, 0) - coalesce(tin_line_climb(t, c.geom), 0)) > 1e-5) AS climb_wrong
FROM contours c, terrain,
  LATERAL (SELECT sum(greatest(0, oz - lag)) AS climb
           FROM (SELECT oz, lag(oz) OVER (ORDER BY distance) FROM lt_profile p WHERE p.id = c.id) s) o
WHERE c.id % 9 = 0;
-- tin_line_segments' rise and 3D length against PostGIS (every ninth
-- contour): the heights at the piece's points from the plane of its
-- triangle (plane_z), the lengths summed from them
SELECT count(*) AS pieces,
       count(*) FILTER (WHERE abs(s.rise - (plane_z(tr.geom, ST_EndPoint(s.geom)) - plane_z(tr.geom, ST_StartPoint(s.geom)))) > 1e-6) AS rise_differs,
       count(*) FILTER (WHERE abs(s.length2d - ST_Length(s.geom)) > 1e-6) AS length2d_differs,
       count(*) FILTER (WHERE abs(s.length3d - o.len3d) > 1e-6) AS length3d_differs
FROM contours c, terrain, tin_line_segments(t, c.geom) s
JOIN line_tris tr ON tr.level = 4 AND tr.id = s.triangle,
LATERAL (SELECT sum(sqrt((ST_X(q) - ST_X(pq)) ^ 2 + (ST_Y(q) - ST_Y(pq)) ^ 2 + (plane_z(tr.geom, q) - plane_z(tr.geom, pq)) ^ 2)) AS len3d
         FROM (SELECT d.geom AS q, lag(d.geom) OVER (ORDER BY d.path) AS pq FROM ST_DumpPoints(s.geom) d) x
         WHERE pq IS NOT NULL) o
WHERE c.id % 9 = 0;
-- river running uphill? a line drawn downhill along the steepest contour
-- crossing climbs less than it falls
SELECT tin_line_climb(t, ST_MakeLine(a, b)) < tin_line_climb(t, ST_MakeLine(b, a)) AS downhill_climbs_less
FROM terrain,
     (SELECT ST_SetSRID(ST_MakePoint(745000, 4045000), 32616) a, ST_SetSRID(ST_MakePoint(750000, 4050000), 32616) b) p
WHERE tin_height(t, a) > tin_height(t, b);

-- Edge cases, each against PostGIS on the triangles of level 1 ('along an
-- edge' has one miss by design: of the two triangles holding it, the larger id)
CREATE TABLE edge_cases(name text, geom geometry);
INSERT INTO edge_cases
SELECT 'along an edge', ST_MakeLine(ST_PointN(ST_ExteriorRing(geom), 1), ST_PointN(ST_ExteriorRing(geom), 2))
FROM line_tris WHERE level = 1 AND id = 1234
UNION ALL
SELECT 'through a vertex', ST_MakeLine(ARRAY[
  ST_Translate(ST_PointN(ST_ExteriorRing(geom), 1), -300, -170), ST_PointN(ST_ExteriorRing(geom), 1),
  ST_Translate(ST_PointN(ST_ExteriorRing(geom), 1), 300, 170)])
FROM line_tris WHERE level = 1 AND id = 2345
UNION ALL
SELECT 'starts and ends on edges', ST_MakeLine(
  ST_LineInterpolatePoint(ST_MakeLine(ST_PointN(ST_ExteriorRing(geom), 1), ST_PointN(ST_ExteriorRing(geom), 2)), 0.5),
  ST_LineInterpolatePoint(ST_MakeLine(ST_PointN(ST_ExteriorRing(geom), 2), ST_PointN(ST_ExteriorRing(geom), 3)), 0.25))
FROM line_tris WHERE level = 1 AND id = 3456
UNION ALL
SELECT 'zero-length segments and repeated points',
  'SRID=32616;LINESTRING(745000 4050000, 745000 4050000, 746000 4051500, 746000 4051500, 746000 4051500, 747500 4050500)'::geometry
UNION ALL
SELECT 'closed ring', ST_ExteriorRing(ST_Buffer('SRID=32616;POINT(747000 4052000)'::geometry, 900, 8))
UNION ALL
SELECT 'partly outside', ST_MakeLine(ST_Centroid(tin_envelope(t)), ST_Translate(ST_Centroid(tin_envelope(t)), 40000, 3000))
FROM terrain
UNION ALL
SELECT 'entirely outside', 'SRID=32616;LINESTRING(0 0, 10 10)'::geometry
UNION ALL
SELECT 'multilinestring', 'SRID=32616;MULTILINESTRING((745000 4050000, 746000 4051000), (747000 4052000, 748000 4051000))'::geometry;
SELECT e.name,
       (SELECT count(*) FROM tin_line_segments(t, e.geom, 1)) AS pieces,
       abs(coalesce((SELECT sum(length2d) FROM tin_line_segments(t, e.geom, 1)), 0)
           - ST_Length(ST_Intersection(e.geom, h))) < 1e-6 AS length_inside_is_postgis,
       (SELECT count(*) FROM line_tris tr WHERE tr.level = 1 AND ST_Length(ST_Intersection(e.geom, tr.geom)) > 1e-6
          AND tr.id NOT IN (SELECT triangle FROM tin_line_segments(t, e.geom, 1))) AS missed,
       (SELECT count(*) FROM tin_line_segments(t, e.geom, 1) u
          WHERE NOT EXISTS (SELECT FROM line_tris tr WHERE tr.level = 1 AND tr.id = u.triangle
                              AND ST_Length(ST_Intersection(e.geom, tr.geom)) > 1e-6)) AS extra
FROM edge_cases e, terrain, line_hull ORDER BY e.name;
-- along an edge: two triangles hold it, the smaller id gets it, once
SELECT array_agg(triangle) AS along_edge_triangles,
       (SELECT min(id) FROM line_tris tr, edge_cases e WHERE e.name = 'along an edge' AND tr.level = 1
          AND ST_Length(ST_Intersection(e.geom, tr.geom)) > 0) AS smallest_holder
FROM edge_cases e, terrain, tin_line_segments(t, e.geom, 1) WHERE e.name = 'along an edge';
-- repeated points change nothing
SELECT ARRAY(SELECT triangle FROM tin_line_triangles(t, geom, 1)) =
       ARRAY(SELECT triangle FROM tin_line_triangles(t, ST_RemoveRepeatedPoints(geom), 1)) AS repeated_points_ignored
FROM edge_cases, terrain WHERE name = 'zero-length segments and repeated points';
-- a closed ring ends in the triangle it started in
SELECT (SELECT triangle FROM tin_line_segments(t, geom) ORDER BY seq LIMIT 1) =
       (SELECT triangle FROM tin_line_segments(t, geom) ORDER BY seq DESC LIMIT 1) AS ring_closes
FROM edge_cases, terrain WHERE name = 'closed ring';
-- tin_drape of lines: a vertex at every crossing, the line's own vertices
-- kept; parts outside dropped; polygons and collections
SELECT ST_NPoints(tin_drape(t, geom, 1)) = (SELECT count(*) + 1 FROM tin_line_segments(t, geom, 1)) +
         (SELECT sum(ST_NPoints(geom) - 2) FROM tin_line_segments(t, geom, 1)) AS drape_vertex_count,
       abs(ST_Length(tin_drape(t, geom, 1)) - ST_Length(geom)) < 1e-9 * ST_Length(geom) AS draped_length2d_is_line_length
FROM edge_cases, terrain WHERE name = 'through a vertex';
SELECT name, GeometryType(tin_drape(t, geom)), ST_NumGeometries(tin_drape(t, geom)), ST_Zmflag(tin_drape(t, geom)) AS zm
FROM edge_cases, terrain ORDER BY name;
SELECT GeometryType(d), ST_NPoints(d) > 5 AS densified, ST_IsClosed(ST_ExteriorRing(d)) AS closed,
       abs(ST_Area(d) - ST_Area(g)) < 1e-6 AS same_area
FROM (SELECT tin_drape(t, g) d, g FROM terrain,
      (SELECT ST_Buffer('SRID=32616;POINT(747000 4052000)'::geometry, 900, 2) g) s) s;
SELECT ST_AsText(tin_drape(t, 'SRID=32616;GEOMETRYCOLLECTION(POINT(747000 4052000), POINT(0 0), LINESTRING(0 0, 1 1))'::geometry), 3)
FROM terrain;
-- a polygon partly off the terrain keeps its intersection with the domain
-- (0.9 refused it): against PostGIS's ST_Intersection with the data domain
-- (line_hull), the same area to 1e-6 and the same number of parts; every
-- vertex on the surface, or on the domain's edge within 1 mm where the cut
-- rounds it just off; wholly off: NULL
SELECT name, GeometryType(d) AS type, ST_NumGeometries(d) = ST_NumGeometries(o) AS same_parts,
       ST_Area(ST_SymDifference(ST_Force2D(d), o)) < 1e-6 * ST_Area(o) AS same_area,
       (SELECT bool_and(coalesce(abs(ST_Z(v.geom) - tin_height(t, v.geom)) < 1e-6,
                                 ST_DWithin(ST_Boundary(h), v.geom, 1e-3)))
        FROM ST_DumpPoints(d) v) AS on_surface
FROM terrain, line_hull, (VALUES
  ('triangle past the east edge', 'SRID=32616;POLYGON((740000 4060000, 900000 4060000, 740000 4061000, 740000 4060000))'::geometry),
  ('holed square across the south edge', ST_Difference(ST_Buffer(ST_Centroid((SELECT ST_Envelope(rast) FROM dem)), 20000, 'quad_segs=1'),
                                                       ST_Buffer(ST_Centroid((SELECT ST_Envelope(rast) FROM dem)), 3000))),
  ('off the terrain', 'SRID=32616;POLYGON((0 0, 10 0, 10 10, 0 0))')
) v(name, g), LATERAL (SELECT tin_drape(t, g) AS d, ST_Intersection(g, h) AS o) x
ORDER BY 1;
-- tin_drape writes PostGIS's own serialisation (no EWKB on the way): byte
-- for byte what PostGIS makes of the same geometry when it parses it
-- (bounding box, its float4 rounding, polygon padding), read from the heap
-- page with pageinspect; every row small enough to sit on page 0 uncompressed
CREATE EXTENSION IF NOT EXISTS pageinspect;
CREATE TEMP TABLE drape_bytes AS
SELECT name, d AS ours, ST_GeomFromEWKB(ST_AsEWKB(d)) AS postgis
FROM (SELECT name, tin_drape(t, g, 0) AS d FROM terrain, (VALUES
  ('point', 'SRID=32616;POINT(747000.3 4052000.7)'::geometry),
  ('point z', 'SRID=32616;POINT Z(747000.3 4052000.7 99)'),
  ('two-point line', 'SRID=32616;LINESTRING(747000 4052000, 747010 4052003)'),
  ('line', 'SRID=32616;LINESTRING(746000 4051000, 747500 4052400, 748000 4052000)'),
  ('polygon with hole', 'SRID=32616;POLYGON((746000 4051000, 748000 4051000, 748000 4053000, 746000 4051000), (747000 4051500, 747500 4051500, 747500 4052000, 747000 4051500))'),
  ('one-point multipoint', 'SRID=32616;MULTIPOINT(747000 4052000)'),
  ('multipoint', 'SRID=32616;MULTIPOINT(747000 4052000, 746000 4051000)'),
  ('one short multiline', 'SRID=32616;MULTILINESTRING((747000 4052000, 747001 4052001))'),
  ('multipolygon', 'SRID=32616;MULTIPOLYGON(((746000 4051000, 746500 4051000, 746500 4051500, 746000 4051000)), ((747000 4052000, 747300 4052000, 747300 4052300, 747000 4052000)))'),
  ('collection', 'SRID=32616;GEOMETRYCOLLECTION(POINT(747000 4052000), LINESTRING(746000 4051000, 746100 4051050), GEOMETRYCOLLECTION(POINT(746500 4051500)))')
) v(name, g)) s;
SELECT v.name, ST_AsEWKT(v.ours) = ST_AsEWKT(v.postgis) AS same_geometry,
       i.t_attrs[2] = i.t_attrs[3] AS same_bytes, length(i.t_attrs[2]) AS bytes
FROM (SELECT row_number() OVER () AS lp, name, ours, postgis FROM drape_bytes) v
JOIN heap_page_item_attrs(get_raw_page('drape_bytes', 0), 'drape_bytes'::regclass) i ON i.lp = v.lp
ORDER BY v.lp;
SELECT count(*) AS rows_on_page_0 FROM heap_page_items(get_raw_page('drape_bytes', 0));
-- per row on points: the point with the height of tin_height at every
-- level, NULL outside the domain; the same for a point with Z or an EMPTY one
SELECT count(*) AS points,
       count(*) FILTER (WHERE tin_drape(t, p, l) IS NOT DISTINCT FROM
         CASE WHEN tin_height(t, p, l) IS NOT NULL
              THEN ST_SetSRID(ST_MakePoint(ST_X(p), ST_Y(p), tin_height(t, p, l)), 32616) END) AS same_as_tin_height,
       count(*) FILTER (WHERE tin_drape(t, p, l) IS NULL) AS outside
FROM terrain, generate_series(0, 4) l,
     (SELECT ST_SetSRID(ST_MakePoint(740000 + 300.7 * i, 4045000 + 211.3 * i), 32616) p FROM generate_series(0, 99) i) s;
SELECT tin_drape(t, 'SRID=32616;POINT EMPTY'::geometry) IS NULL AS empty_is_null,
       ST_Z(tin_drape(t, 'SRID=32616;POINT Z(747000 4052000 -5)'::geometry)) = tin_height(t, 'SRID=32616;POINT(747000 4052000)'::geometry) AS own_z_replaced,
       tin_drape(t, NULL::geometry) IS NULL AS null_geometry, tin_drape(NULL::tin, 'POINT(0 0)'::geometry) IS NULL AS null_tin
FROM terrain;
-- widened lines: every triangle within width/2 (oracle: ST_DWithin), once each
SELECT e.name,
       (SELECT count(*) FROM tin_line_triangles(t, e.geom, 1, 500)) AS near_triangles,
       (SELECT count(DISTINCT triangle) = count(*) FROM tin_line_triangles(t, e.geom, 1, 500)) AS each_once,
       (SELECT count(*) FROM line_tris tr WHERE tr.level = 1 AND ST_DWithin(tr.geom, e.geom, 250)
          AND tr.id NOT IN (SELECT triangle FROM tin_line_triangles(t, e.geom, 1, 500))) AS missed,
       (SELECT count(*) FROM tin_line_triangles(t, e.geom, 1, 500) w JOIN line_tris tr ON tr.level = 1 AND tr.id = w.triangle
          WHERE NOT ST_DWithin(tr.geom, e.geom, 250 + 1e-6)) AS too_far
FROM edge_cases e, terrain ORDER BY e.name;
-- first approach order: every triangle within width/2 of the start (all
-- first approached at the start; oracle ST_DWithin) comes before the others,
-- the one under the start among them
WITH w AS (SELECT seq, triangle FROM contours c, terrain, tin_line_triangles(t, c.geom, 4, 100) WHERE c.id = 100),
near AS (SELECT tr.id FROM line_tris tr, contours c
         WHERE c.id = 100 AND tr.level = 4 AND ST_DWithin(tr.geom, ST_StartPoint(c.geom), 50))
SELECT (SELECT count(*) FROM near) AS near_the_start,
       (SELECT array_agg(triangle ORDER BY triangle) FROM w WHERE seq <= (SELECT count(*) FROM near))
         = (SELECT array_agg(id ORDER BY id) FROM near) AS near_ones_first,
       (SELECT tin_locate(t, ST_StartPoint(geom), 4) FROM contours, terrain WHERE id = 100) IN (SELECT id FROM near)
         AS under_the_start_among_them;

-- The stored line tree gives the same rows as the geometry, for every
-- contour and every function (the tree only skips work)
CREATE TABLE line_trees AS SELECT id, geom, tin_linetree(geom) AS lt FROM contours;
SELECT count(*) AS trees, sum((tin_linetree_info(lt)->>'points')::int) = (SELECT sum(ST_NPoints(geom)) FROM contours) AS all_points,
       count(*) FILTER (WHERE abs((tin_linetree_info(lt)->>'length')::float8 - ST_Length(geom)) > 1e-9 * ST_Length(geom)) AS length_wrong
FROM line_trees;
SELECT l AS level,
       count(*) FILTER (WHERE ARRAY(SELECT row(s.*)::text FROM tin_line_segments(t, c.geom, l) s)
                IS DISTINCT FROM ARRAY(SELECT row(s.*)::text FROM tin_line_segments(t, c.lt, l) s)) AS segments_differ,
       count(*) FILTER (WHERE ARRAY(SELECT row(s.*)::text FROM tin_line_triangles(t, c.geom, l) s)
                IS DISTINCT FROM ARRAY(SELECT row(s.*)::text FROM tin_line_triangles(t, c.lt, l) s)) AS triangles_differ,
       count(*) FILTER (WHERE ARRAY(SELECT row(s.*)::text FROM tin_line_profile(t, c.geom, l) s)
                IS DISTINCT FROM ARRAY(SELECT row(s.*)::text FROM tin_line_profile(t, c.lt, l) s)) AS profiles_differ,
       count(*) FILTER (WHERE tin_line_climb(t, c.geom, l) IS DISTINCT FROM tin_line_climb(t, c.lt, l)) AS climbs_differ
FROM line_trees c, terrain, unnest(ARRAY[0, 2, 4]) l GROUP BY 1 ORDER BY 1;
SELECT count(*) FILTER (WHERE ARRAY(SELECT row(s.*)::text FROM tin_line_triangles(t, c.geom, 2, 120) s)
                IS DISTINCT FROM ARRAY(SELECT row(s.*)::text FROM tin_line_triangles(t, c.lt, 2, 120) s)) AS widened_differ
FROM line_trees c, terrain WHERE id % 5 = 0;
-- edge cases through the tree as well
SELECT count(*) FILTER (WHERE ARRAY(SELECT row(s.*)::text FROM tin_line_segments(t, e.geom, 1) s)
                IS DISTINCT FROM ARRAY(SELECT row(s.*)::text FROM tin_line_segments(t, tin_linetree(e.geom), 1) s)) AS edge_cases_differ
FROM edge_cases e, terrain;
-- the text form round-trips exactly (binary: tests/dump_restore.sh)
SELECT count(*) FILTER (WHERE (lt::text::linetree)::text <> lt::text) AS text_roundtrip_wrong FROM line_trees;
SELECT tin_linetree('SRID=32616;LINESTRING EMPTY'::geometry) IS NULL AS empty_is_null,
       (SELECT count(*) FROM tin_line_triangles((SELECT t FROM terrain), NULL::linetree)) AS null_no_rows;
