-- Shared fixtures: the runner loaded the bundled DEMs with raster2pgsql as
-- tables dem (UTM 16N, nodata -9999) and dem_geo (EPSG:4326).
SET extra_float_digits = 0;
SELECT extname FROM pg_extension WHERE extname IN ('postgis', 'postgis_raster', 'tinmerge') ORDER BY 1;
SELECT ST_Width(rast), ST_Height(rast), ST_SRID(rast), ST_BandNoDataValue(rast) FROM dem;
CREATE TABLE terrain AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem;
-- error-catching helper: one bad input per line, SQLSTATE and message
CREATE FUNCTION try(q text) RETURNS text LANGUAGE plpgsql AS $$
BEGIN
  EXECUTE q;
  RETURN 'ok';
EXCEPTION WHEN others THEN
  RETURN SQLSTATE || ': ' || SQLERRM;
END $$;
-- The height of a triangle's plane at a point: the triangle's corners as
-- PostGIS reads them (a POLYGON Z of tin_triangles), the plane by Cramer's
-- rule. The tests' own interpolation, no tinmerge function: an oracle.
CREATE FUNCTION plane_z(tri geometry, p geometry) RETURNS float8 LANGUAGE sql IMMUTABLE AS $$
  SELECT za + ((ST_X(p) - xa) * (uz * vy - uy * vz) + (ST_Y(p) - ya) * (ux * vz - uz * vx)) / (ux * vy - uy * vx)
  FROM (SELECT ST_X(a) xa, ST_Y(a) ya, ST_Z(a) za,
               ST_X(b) - ST_X(a) ux, ST_Y(b) - ST_Y(a) uy, ST_Z(b) - ST_Z(a) uz,
               ST_X(c) - ST_X(a) vx, ST_Y(c) - ST_Y(a) vy, ST_Z(c) - ST_Z(a) vz
        FROM (SELECT ST_PointN(r, 1) a, ST_PointN(r, 2) b, ST_PointN(r, 3) c
              FROM (SELECT ST_ExteriorRing(tri) r) r) v) w $$;
-- A triangle's surface area over its planar area (|n| / |n_z| of the
-- normal of its corners as PostGIS reads them): a planar area inside it
-- times this is the surface area above it.
CREATE FUNCTION slope_factor(tri geometry) RETURNS float8 LANGUAGE sql IMMUTABLE AS $$
  SELECT sqrt((uy * vz - uz * vy) ^ 2 + (uz * vx - ux * vz) ^ 2 + (ux * vy - uy * vx) ^ 2) / abs(ux * vy - uy * vx)
  FROM (SELECT ST_X(b) - ST_X(a) ux, ST_Y(b) - ST_Y(a) uy, ST_Z(b) - ST_Z(a) uz,
               ST_X(c) - ST_X(a) vx, ST_Y(c) - ST_Y(a) vy, ST_Z(c) - ST_Z(a) vz
        FROM (SELECT ST_PointN(r, 1) a, ST_PointN(r, 2) b, ST_PointN(r, 3) c
              FROM (SELECT ST_ExteriorRing(tri) r) r) v) w $$;
