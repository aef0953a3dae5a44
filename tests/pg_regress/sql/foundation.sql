-- The foundation functions on the real Jacksboro DEM (UTM, tolerance 2 m, 5 levels).
SET extra_float_digits = 0;
SELECT tin_srid(t), tin_num_levels(t) FROM terrain;
-- per-level triangle counts, vertices and tolerances; the vertices are
-- PostGIS's distinct corners of the level's triangles
SELECT l AS level, tin_num_triangles(t, l) AS triangles, tin_num_vertices(t, l) AS vertices,
       tin_num_vertices(t, l) = (SELECT count(DISTINCT (ST_X(d.geom), ST_Y(d.geom)))
                                 FROM tin_triangles(t, l) tr, ST_DumpPoints(tr.geom) d) AS vertices_are_postgis,
       tin_tolerance(t, l) AS tolerance
FROM terrain, generate_series(0, 4) l ORDER BY l;
-- NULL level = finest
SELECT tin_num_triangles(t) = tin_num_triangles(t, 4), tin_tolerance(t) FROM terrain;
-- header-only functions agree with the triangles
SELECT l, (SELECT count(*) FROM tin_triangles(t, l)) = tin_num_triangles(t, l) AS same
FROM terrain, generate_series(0, 4) l ORDER BY l;
-- envelope: the box of the valid pixel centres (PostGIS's ST_Extent of
-- ST_PixelAsCentroids) and of every level's triangles, with the SRID
SELECT ST_SRID(e), round(ST_XMin(e)::numeric, 3), round(ST_YMin(e)::numeric, 3),
       round(ST_XMax(e)::numeric, 3), round(ST_YMax(e)::numeric, 3),
       ST_Equals(e, (SELECT ST_SetSRID(ST_Extent(geom)::geometry, 32616) FROM dem, ST_PixelAsCentroids(rast))) AS centres_extent,
       (SELECT bool_and(ST_Equals(e, (SELECT ST_SetSRID(ST_Extent(geom)::geometry, 32616) FROM tin_triangles(t, l))))
        FROM generate_series(0, 4) l) AS triangles_extent
FROM (SELECT t, tin_envelope(t) e FROM terrain) s;
-- tin_info: levels, measured errors within tolerance
SELECT i->>'srid' AS srid, jsonb_array_length(i->'levels') AS levels,
       (SELECT bool_and((x->>'max_error')::float8 <= (x->>'tolerance')::float8) FROM jsonb_array_elements(i->'levels') x) AS within,
       (i->>'bytes')::bigint * 2 = length(t::text) AS bytes_match
FROM (SELECT t, tin_info(t) i FROM terrain) s;
-- every level covers the valid pixels' squares inside the hull of their
-- centres (tin_from_raster's default domain; PostGIS's ST_Polygon and
-- ST_ConvexHull), to 1e-9; that is less than the hull itself
WITH region AS MATERIALIZED (
  SELECT ST_Intersection(ST_Polygon(rast), (SELECT ST_ConvexHull(ST_Collect(geom)) FROM ST_PixelAsCentroids(rast))) AS r,
         (SELECT ST_ConvexHull(ST_Collect(geom)) FROM ST_PixelAsCentroids(rast)) AS hull
  FROM dem
)
SELECT l, round(sum(ST_Area(geom))::numeric / 1e6, 3) AS km2,
       abs(sum(ST_Area(geom)) / ST_Area(r) - 1) < 1e-9 AS valid_region_area,
       sum(ST_Area(geom)) < ST_Area(hull) AS less_than_hull
FROM terrain, region, generate_series(0, 4) l, LATERAL tin_triangles(t, l) GROUP BY l, r, hull ORDER BY l;
-- surface area: PostGIS's planar area of each triangle times its slope
-- factor (slope_factor, from its corners), over the whole terrain and over
-- a polygon cutting triangles (ST_Intersection with each), to 1e-9
WITH a AS MATERIALIZED (SELECT ST_Buffer(ST_Centroid(tin_envelope(t)), 4000, 5) AS g FROM terrain)
SELECT l,
       abs(tin_surface_area(t, tin_envelope(t), l) / (SELECT sum(ST_Area(tr.geom) * slope_factor(tr.geom)) FROM tin_triangles(t, l) tr) - 1) < 1e-9 AS whole,
       abs(tin_surface_area(t, a.g, l) / (SELECT sum(ST_Area(ST_Intersection(tr.geom, a.g)) * slope_factor(tr.geom))
                                          FROM tin_triangles(t, l) tr WHERE tr.geom && a.g) - 1) < 1e-9 AS polygon
FROM terrain, a, generate_series(0, 4, 2) l ORDER BY l;
-- triangles: POLYGON Z with the SRID, parents NULL only at level 0
SELECT DISTINCT ST_GeometryType(geom), ST_SRID(geom), ST_NDims(geom), ST_NPoints(geom) FROM terrain, tin_triangles(t, 2);
SELECT count(*) FILTER (WHERE parent IS NULL) AS level0_null FROM terrain, tin_triangles(t, 0);
SELECT count(*) FILTER (WHERE parent IS NULL) AS level3_null FROM terrain, tin_triangles(t, 3);
-- every child lies in its parent (PostGIS predicate, small buffer for rounding)
SELECT bool_and(ST_Covers(ST_Buffer(p.geom, 1e-6), c.geom)) AS children_in_parents
FROM terrain, tin_triangles(t, 1) c JOIN tin_triangles(t, 0) p ON p.id = c.parent;
-- as a PostGIS TIN: one patch per triangle of the level, the same
-- corners as tin_triangles' polygons (PostGIS's ST_Points of each, sorted)
SELECT ST_GeometryType(g), ST_NumGeometries(g), ST_SRID(g),
       ARRAY(SELECT ST_AsText(ST_Points(d.geom)) FROM ST_Dump(g) d ORDER BY 1)
         = ARRAY(SELECT ST_AsText(ST_Points(tr.geom)) FROM tin_triangles(t, 0) tr ORDER BY 1) AS same_triangles
FROM (SELECT t, tin_as_geometry(t, 0) g FROM terrain) s;
-- text I/O round-trips exactly; header of the text form starts with the magic
SELECT (t::text)::tin::text = t::text AS text_roundtrip, left(t::text, 8) AS magic FROM terrain;
-- from points: vertices with Z, equal x,y merged
SELECT tin_num_vertices(tin_from_points('SRID=32616;MULTIPOINT Z (0 0 1, 10 0 2, 0 10 3, 10 10 9, 5 5 20, 5 5 40)'::geometry, 0.5, 2));
-- a bump of 10 on the diagonal: within level 0's tolerance 10, inserted at level 1
-- (tolerance 5), splitting the persisted diagonal edge: 2 triangles, then 4 children
SELECT l, id, parent, ST_AsText(geom) FROM generate_series(0, 1) l, tin_triangles(
  tin_from_points('SRID=32616;MULTIPOINT Z (0 0 0, 10 0 0, 0 10 0, 10 10 0, 5 5 10)'::geometry, 5, 2), l) ORDER BY l, id;
-- explicit tolerances
SELECT tin_tolerance(t, 0), tin_tolerance(t, 1), tin_tolerance(t, 2)
FROM (SELECT tin_from_raster(rast, ARRAY[40, 20, 10]::float8[]) t FROM dem) s;
-- geographic DEM keeps its SRID
SELECT tin_srid(t), tin_num_levels(t) FROM (SELECT tin_from_raster(rast, 8, 2) t FROM dem_geo) s;
-- NULL handling: level functions are not STRICT; a NULL tin gives NULL
SELECT tin_num_triangles(NULL::tin, 0) IS NULL, tin_tolerance(NULL::tin) IS NULL,
       (SELECT count(*) FROM tin_triangles(NULL::tin)) AS no_rows, tin_as_geometry(NULL::tin) IS NULL;
-- decoded once per backend: repeated calls on the same value hit the cache
CREATE TEMP TABLE before AS SELECT * FROM tin_cache_stats();
SELECT count(tin_as_geometry(t, 0)) FROM terrain, generate_series(1, 20);
SELECT s.hits - b.hits >= 19 AS hits, s.misses - b.misses <= 1 AS at_most_one_decode
FROM tin_cache_stats() s, before b;
