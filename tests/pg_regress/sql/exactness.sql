-- Issue 22: exact hierarchy. tinmerge 0.2.0 built 700 / 2,424 / 5,037 /
-- 7,329 slivers at levels 1-4 of the geographic DEM (EPSG:4326, 1/1200
-- degree pixels): pixel centres on one lattice line are not exactly
-- collinear as doubles, so a sample on a coarse edge did not split it.
-- Counted here by PostGIS from tin_triangles alone.
\set VERBOSITY terse
CREATE TABLE exact_geo AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem_geo;
CREATE TABLE exact_tris AS
SELECT l, id, geom FROM exact_geo, generate_series(0, 4) l, tin_triangles(t, l);
-- slivers: smallest altitude (2 area / longest side) under 1e-3 pixel
WITH side AS (
  SELECT l, id, geom, max(ST_Length((d).geom)) AS longest
  FROM (SELECT l, id, geom, ST_DumpSegments(geom) d FROM exact_tris) s GROUP BY l, id, geom)
SELECT l, count(*) AS triangles,
       count(*) FILTER (WHERE 2 * ST_Area(geom) / longest < 1e-3 / 1200) AS slivers
FROM side GROUP BY l ORDER BY l;
-- every edge used by two triangles with the same two end vertices, or by
-- one on the domain's boundary (the pixels' hull): no T-junction
WITH seg AS (
  SELECT l, id, ST_PointN((d).geom, 1) AS p, ST_PointN((d).geom, 2) AS q
  FROM (SELECT l, id, ST_DumpSegments(ST_Force2D(geom)) d FROM exact_tris) s),
edge AS (
  SELECT l, least(ST_AsEWKB(p), ST_AsEWKB(q)) AS a, greatest(ST_AsEWKB(p), ST_AsEWKB(q)) AS b, count(*) AS uses
  FROM seg GROUP BY 1, 2, 3),
hull AS (SELECT ST_ExteriorRing(ST_ConvexHull(ST_Collect(geom))) AS ring
         FROM dem_geo, ST_PixelAsCentroids(rast, 1, true))
SELECT l, count(*) AS edges,
       count(*) FILTER (WHERE uses = 2) AS shared,
       count(*) FILTER (WHERE uses = 1) AS on_boundary,
       count(*) FILTER (WHERE uses > 2
                           OR (uses = 1 AND NOT ST_DWithin(ST_MakeLine(a::geometry, b::geometry), ring, 1e-9)
                               OR uses = 1 AND ST_Distance(ST_Centroid(ST_MakeLine(a::geometry, b::geometry)), ring) > 1e-9)) AS t_junctions
FROM edge, hull GROUP BY l ORDER BY l;
-- the checker agrees: no problems in the new tin
SELECT count(*) AS problems FROM exact_geo, tin_validate(t);
-- a tin built by tinmerge 0.2.0 from an 80 x 80 window of the same DEM
-- (tests/data/format-v1/geo-0.2.0.tin): tin_validate finds its cracks,
-- and the rebuild from the raster has none
\getenv abs_srcdir PG_ABS_SRCDIR
\set fixture :abs_srcdir '/../data/format-v1/geo-0.2.0.tin'
CREATE TABLE exact_old AS SELECT encode(pg_read_binary_file(:'fixture'), 'hex')::tin AS t;
SELECT level, problem, count(*) FROM exact_old, tin_validate(t) GROUP BY 1, 2 ORDER BY 1, 2;
-- PostGIS finds the same triangles: those of zero area up to rounding
-- (ST_Area under 1e-15 square degrees; a pixel's is 7.7e-8)
SELECT level, v.n AS named, p.n AS postgis_zero_area, v.ids = p.ids AS same_triangles
FROM (SELECT level, count(*) AS n, array_agg(triangle ORDER BY triangle) AS ids
      FROM exact_old, tin_validate(t) WHERE problem IN ('crack', 'sliver') GROUP BY 1) v
FULL JOIN (SELECT l AS level, count(*) AS n, array_agg(tr.id ORDER BY tr.id) AS ids
           FROM exact_old, generate_series(0, tin_num_levels(t) - 1) l, tin_triangles(t, l) tr
           WHERE ST_Area(tr.geom) < 1e-15 GROUP BY 1) p USING (level) ORDER BY 1;
SELECT tin_num_triangles(t, 3) > 0 AS still_reads, tin_height(t, ST_Centroid(tin_envelope(t))) IS NOT NULL AS answers
FROM exact_old;
-- the rebuild of docs/upgrading.md: same source pixels, the tolerances the
-- old tin was built with (from tin_info)
CREATE TABLE exact_src AS SELECT ST_Clip(rast, tin_envelope(o.t)) AS rast FROM dem_geo, exact_old o;
UPDATE exact_old SET t = tin_from_raster(d.rast,
         ARRAY(SELECT (l->>'tolerance')::float8 FROM jsonb_array_elements(tin_info(t)->'levels') l))
FROM exact_src d
WHERE EXISTS (SELECT FROM tin_validate(exact_old.t));
SELECT tin_info(t)->'levels'->3->>'tolerance' AS finest_tolerance, tin_num_levels(t) AS levels,
       (SELECT count(*) FROM tin_validate(t)) AS problems_after_rebuild
FROM exact_old;
-- issue 73: a window of the UTM DEM put on a geographic grid of
-- 1/32400-degree pixels (1/9 arc-second), built over its valid pixels
-- (there is nodata on its left): level 1 had a gap of 4 edges, a grid
-- crossing kept as a vertex 4.4e-9 pixel from the sample on the parent's
-- side it was. The oracle is PostGIS's: every edge (ST_DumpSegments of
-- the triangles) used by at most two triangles, and every edge used once
-- on the boundary of the union of the level's triangles
CREATE TABLE exact_73 AS
WITH w AS (SELECT ST_Clip(rast, ST_MakeEnvelope(731209.22, 4048256.16, 745609.22, 4063196.16, 32616)) r FROM dem)
SELECT ST_SetSRID(ST_SetScale(ST_SetUpperLeft(r, 162.8386382115849, 52.87551690288227), 1/32400.0, -1/32400.0), 4326) AS r,
       tin_from_raster(ST_SetSRID(ST_SetScale(ST_SetUpperLeft(r, 162.8386382115849, 52.87551690288227), 1/32400.0, -1/32400.0), 4326), 5.0, 2) AS t
FROM w;
SELECT ST_Width(r) AS width, ST_Height(r) AS height, (ST_SummaryStats(r)).count < ST_Width(r) * ST_Height(r) AS has_nodata FROM exact_73;
SELECT level, problem, count(*) FROM exact_73, tin_validate(t, r) GROUP BY 1, 2 ORDER BY 1, 2;
WITH tr AS (SELECT l, tr.geom FROM exact_73, generate_series(0, 1) l, tin_triangles(t, l) tr),
u AS (SELECT l, ST_Boundary(ST_Union(ST_Force2D(geom))) AS b FROM tr GROUP BY l),
seg AS (SELECT l, ST_Force2D((ST_DumpSegments(geom)).geom) AS s FROM tr),
e AS (SELECT l, ST_AsBinary(CASE WHEN ST_X(ST_StartPoint(s)) < ST_X(ST_EndPoint(s))
                               OR (ST_X(ST_StartPoint(s)) = ST_X(ST_EndPoint(s)) AND ST_Y(ST_StartPoint(s)) < ST_Y(ST_EndPoint(s)))
                              THEN s ELSE ST_Reverse(s) END) AS k, (array_agg(s))[1] AS s, count(*) AS n
      FROM seg GROUP BY 1, 2)
SELECT e.l AS level, bool_and(n <= 2) AS no_edge_used_thrice,
       count(*) FILTER (WHERE n = 1 AND NOT ST_Covers(u.b, e.s)) AS edges_used_once_inside
FROM e JOIN u USING (l) GROUP BY 1 ORDER BY 1;
-- STRICT: NULL gives no rows
SELECT count(*) FROM tin_validate(NULL::tin);
DROP TABLE exact_geo, exact_tris, exact_old, exact_src, exact_73;
