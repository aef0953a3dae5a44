-- Point clouds (issue 25): tin_from_points_agg over point rows and over
-- pgpointcloud patches exploded to points, keeping the ground (ASPRS class
-- 2). No real LAS file is at hand offline, so the cloud is made from the
-- DEM window: one ground return per pixel centre of a 120 x 120 corner,
-- moved by a deterministic jitter (up to a fifth of a pixel) and at the
-- pixel's value, and next to every third ground return away from the
-- cloud's edge (where slivers between jittered samples are steep) a
-- vegetation or building return (class 3 to 6) 4 to 19 m above it.
SET extra_float_digits = 0;
CREATE TABLE cloud AS
SELECT (p.y * 1000 + p.x)::int AS id, 2 AS class,
       ST_SetSRID(ST_MakePoint(ST_X(p.geom) + ((p.x * 7919 + p.y * 104729) % 101 - 50) * 0.004 * ST_PixelWidth(rast),
                               ST_Y(p.geom) + ((p.x * 104729 + p.y * 7919) % 101 - 50) * 0.004 * ST_PixelHeight(rast),
                               p.val), ST_SRID(rast)) AS pt
FROM dem_window, ST_PixelAsCentroids(rast) p WHERE p.x <= 120 AND p.y <= 120;
INSERT INTO cloud
SELECT 1000000 + id, 3 + id % 4,
       ST_SetSRID(ST_MakePoint(ST_X(pt) + 0.31, ST_Y(pt) - 0.17, ST_Z(pt) + 4 + id % 16), ST_SRID(pt))
FROM cloud WHERE id % 3 = 0 AND id % 1000 BETWEEN 2 AND 119 AND id / 1000 BETWEEN 2 AND 119;
SELECT class, count(*) FROM cloud GROUP BY class ORDER BY class;

-- the aggregate over the ground rows is the tin tin_from_points builds from
-- their collection (the same samples in the same order)
CREATE TABLE cloud_tins AS
SELECT tin_from_points_agg(pt, 1.0, 3 ORDER BY id) FILTER (WHERE class = 2) AS ground,
       tin_from_points_agg(pt, 1.0, 3 ORDER BY id) AS everything,
       tin_from_points(ST_Collect(pt ORDER BY id) FILTER (WHERE class = 2), 1.0, 3) AS collected
FROM cloud;
-- (held to the samples' Delaunay surface between them too since 0.12.0,
-- the finest level of this jittered grid of 90 m pixels at 1 m has
-- vertices at crossings besides the samples, more vertices than samples;
-- the coarsest, at 4 m, fewer)
SELECT ground = collected AS same_as_collect, tin_num_levels(ground) AS levels, tin_srid(ground) AS srid,
       (tin_info(ground) -> 'levels' -> 0 ->> 'vertices')::int < (SELECT count(*) FROM cloud WHERE class = 2)
         AS coarsest_has_fewer_vertices_than_samples
FROM cloud_tins;
-- oracles: every ground return is within the finest tolerance of the
-- ground tin (the build's bound, at the samples themselves); no vegetation
-- return is on its surface, while the tin of all returns goes up to them
SELECT count(*) AS ground_returns,
       count(*) FILTER (WHERE abs(tin_height(ground, pt) - ST_Z(pt)) > 1.0 + 1e-9) AS ground_beyond_tolerance,
       count(*) FILTER (WHERE tin_height(ground, pt) IS NULL) AS ground_outside
FROM cloud, cloud_tins WHERE class = 2;
SELECT count(*) AS other_returns,
       count(*) FILTER (WHERE abs(tin_height(ground, pt) - ST_Z(pt)) <= 1.0) AS on_the_ground_tin,
       count(*) FILTER (WHERE abs(tin_height(everything, pt) - ST_Z(pt)) <= 1.0) AS on_the_tin_of_everything
FROM cloud, cloud_tins WHERE class <> 2;

-- the six-argument form: the ground with a soft breakline (a diagonal of
-- the cloud) and a boundary (the cloud's hull less a square in its middle),
-- taken from the first row: the tin tin_from_points builds from the
-- collection with them; three NULLs: the three-argument form. Oracles: the
-- triangles cover boundary ∩ hull (PostGIS areas, to 1e-9) and the
-- breakline is a union of edges of the finest level (PostGIS: its length
-- within the boundary is, to 1e-6, the length of tin_triangles' edges
-- within 1e-6 of it)
CREATE TABLE cloud_domain AS
SELECT ST_Difference(h, ST_Expand(ST_Centroid(h), 300)) AS boundary,
       ST_MakeLine(ST_PointN(ST_ExteriorRing(ST_OrientedEnvelope(h)), 1), ST_PointN(ST_ExteriorRing(ST_OrientedEnvelope(h)), 3)) AS line,
       h
FROM (SELECT ST_ConvexHull(ST_Collect(pt)) AS h FROM cloud WHERE class = 2) s;
CREATE TABLE cloud_domain_tins AS
SELECT tin_from_points_agg(pt, 1.0, 3, NULL, (SELECT line FROM cloud_domain), (SELECT boundary FROM cloud_domain) ORDER BY id) FILTER (WHERE class = 2) AS agg,
       tin_from_points(ST_Collect(pt ORDER BY id) FILTER (WHERE class = 2), 1.0, 3,
                       soft_breaklines => (SELECT line FROM cloud_domain), boundary => (SELECT boundary FROM cloud_domain)) AS collected,
       tin_from_points_agg(pt, 1.0, 3, NULL, NULL, NULL ORDER BY id) FILTER (WHERE class = 2) AS nulls
FROM cloud;
SELECT agg = collected AS same_as_collect, nulls = (SELECT ground FROM cloud_tins) AS nulls_are_three_arguments,
       abs((SELECT sum(ST_Area(geom)) FROM tin_triangles(agg)) / ST_Area(ST_Intersection(boundary, h)) - 1) < 1e-9 AS domain_is_boundary,
       abs((SELECT ST_Length(ST_Intersection(ST_Union(ST_Boundary(geom)), ST_Buffer(line, 1e-6))) FROM tin_triangles(agg))
           / ST_Length(ST_Intersection(line, boundary)) - 1) < 1e-6 AS line_is_edges
FROM cloud_domain_tins, cloud_domain;
DROP TABLE cloud_domain, cloud_domain_tins;

-- no rows, only NULL or empty rows: NULL; bad rows: errors
SELECT tin_from_points_agg(pt, 1.0, 3) IS NULL AS no_rows FROM cloud WHERE false;
SELECT tin_from_points_agg(NULL::geometry, 1.0, 3) IS NULL AS null_rows FROM generate_series(1, 3);
SELECT tin_from_points_agg(pt, 1.0, 3) FROM (SELECT ST_SetSRID(ST_MakePoint(1, 2), 32616) AS pt) x;
SELECT tin_from_points_agg(pt, 1.0, 3) FROM (VALUES ('SRID=32616;POINT Z (1 2 3)'::geometry), ('SRID=4326;POINT Z (1 2 3)')) v(pt);
SELECT tin_from_points_agg(pt, g, 3) FROM cloud, generate_series(1, 2) g WHERE id < 3000;
SELECT tin_from_points_agg(pt, NULL, 3) FROM cloud;
SELECT tin_from_points_agg(pt, -1.0, 3) FROM cloud;

-- the same cloud in pgpointcloud: X, Y, Z in centimetres, Classification;
-- patches of 400 points; ground kept with PC_Get on the exploded points
CREATE EXTENSION IF NOT EXISTS pointcloud;
CREATE EXTENSION IF NOT EXISTS pointcloud_postgis;
INSERT INTO pointcloud_formats (pcid, srid, schema) VALUES (77, 32616,
'<?xml version="1.0" encoding="UTF-8"?>
<pc:PointCloudSchema xmlns:pc="http://pointcloud.org/schemas/PC/1.1" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
  <pc:dimension><pc:position>1</pc:position><pc:size>4</pc:size><pc:name>X</pc:name><pc:interpretation>int32_t</pc:interpretation><pc:scale>0.01</pc:scale></pc:dimension>
  <pc:dimension><pc:position>2</pc:position><pc:size>4</pc:size><pc:name>Y</pc:name><pc:interpretation>int32_t</pc:interpretation><pc:scale>0.01</pc:scale></pc:dimension>
  <pc:dimension><pc:position>3</pc:position><pc:size>4</pc:size><pc:name>Z</pc:name><pc:interpretation>int32_t</pc:interpretation><pc:scale>0.01</pc:scale></pc:dimension>
  <pc:dimension><pc:position>4</pc:position><pc:size>1</pc:size><pc:name>Classification</pc:name><pc:interpretation>uint8_t</pc:interpretation></pc:dimension>
  <pc:metadata><Metadata name="compression">dimensional</Metadata></pc:metadata>
</pc:PointCloudSchema>');
CREATE TABLE cloud_patches AS
SELECT id / 400 AS patch, PC_Patch(PC_MakePoint(77, ARRAY[ST_X(pt), ST_Y(pt), ST_Z(pt), class]) ORDER BY id) AS pa
FROM cloud GROUP BY id / 400;
SELECT count(*) AS patches, sum(PC_NumPoints(pa)) AS points FROM cloud_patches;
CREATE TABLE cloud_pc AS
SELECT tin_from_points_agg(geometry(pt), 1.0, 3) FILTER (WHERE PC_Get(pt, 'Classification') = 2) AS ground
FROM cloud_patches, PC_Explode(pa) pt;
-- the ground returns, as stored (to the centimetre), are within the
-- tolerance of the tin; the other returns are not on it
SELECT count(*) AS ground_returns,
       count(*) FILTER (WHERE abs(tin_height(ground, geometry(pt)) - PC_Get(pt, 'Z')) > 1.0 + 1e-9) AS ground_beyond_tolerance
FROM cloud_patches, PC_Explode(pa) pt, cloud_pc WHERE PC_Get(pt, 'Classification') = 2;
SELECT count(*) AS other_returns,
       count(*) FILTER (WHERE abs(tin_height(ground, geometry(pt)) - PC_Get(pt, 'Z')) <= 1.0) AS on_the_ground_tin
FROM cloud_patches, PC_Explode(pa) pt, cloud_pc WHERE PC_Get(pt, 'Classification') <> 2;
DROP TABLE cloud, cloud_tins, cloud_patches, cloud_pc;
DELETE FROM pointcloud_formats WHERE pcid = 77;
DROP EXTENSION pointcloud_postgis;
DROP EXTENSION pointcloud;
