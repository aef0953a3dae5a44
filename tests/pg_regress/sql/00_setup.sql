-- Shared fixtures: the runner loaded the bundled DEMs with raster2pgsql as
-- tables dem (UTM 16N, nodata -9999) and dem_geo (EPSG:4326), and the
-- geographic one warped to CONUS Albers as dem_albers (scripts/load-data.sh).
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
-- The integral over a triangle of planar area a of the positive part of a
-- linear function with corner values d, in closed form: with one corner
-- above zero, a p^3 / (3 (p - q1) (p - q2)); with two, the mean of the
-- corners times a plus the part below zero, a (-q)^3 / (3 (p1 - q) (p2 - q)).
CREATE FUNCTION pos_part(a float8, d float8[]) RETURNS float8 LANGUAGE plpgsql IMMUTABLE AS $$
DECLARE
  p float8[] := ARRAY(SELECT x FROM unnest(d) x WHERE x > 0 ORDER BY x);
  q float8[] := ARRAY(SELECT x FROM unnest(d) x WHERE x <= 0 ORDER BY x);
BEGIN
  IF cardinality(p) = 3 THEN RETURN a * (d[1] + d[2] + d[3]) / 3;
  ELSIF cardinality(p) = 0 THEN RETURN 0;
  ELSIF cardinality(p) = 1 THEN RETURN a * p[1] ^ 3 / (3 * (p[1] - q[1]) * (p[1] - q[2]));
  ELSE RETURN a * (d[1] + d[2] + d[3]) / 3 + a * (-q[1]) ^ 3 / (3 * (p[1] - q[1]) * (p[2] - q[1]));
  END IF;
END $$;
-- Over a convex polygon piece inside triangle ta (and tb): the integrals of
-- max(d, 0) (cut) and max(-d, 0) (fill) for d = plane_z(ta) - plane_z(tb),
-- or plane_z(ta) - base when tb is NULL, over a fan of the piece.
CREATE FUNCTION cut_fill(piece geometry, ta geometry, tb geometry, base float8 DEFAULT NULL, OUT cut float8, OUT fill float8)
LANGUAGE plpgsql IMMUTABLE AS $$
DECLARE
  r geometry := ST_ExteriorRing(piece);
  n int := ST_NPoints(r) - 1;
  x float8[]; y float8[]; d float8[];
  a float8;
BEGIN
  cut := 0; fill := 0;
  FOR i IN 1..n LOOP
    x[i] := ST_X(ST_PointN(r, i)); y[i] := ST_Y(ST_PointN(r, i));
    d[i] := plane_z(ta, ST_PointN(r, i)) - CASE WHEN tb IS NULL THEN base ELSE plane_z(tb, ST_PointN(r, i)) END;
  END LOOP;
  FOR i IN 2..n - 1 LOOP
    a := abs((x[i] - x[1]) * (y[i + 1] - y[1]) - (x[i + 1] - x[1]) * (y[i] - y[1])) / 2;
    cut := cut + pos_part(a, ARRAY[d[1], d[i], d[i + 1]]);
    fill := fill + pos_part(a, ARRAY[-d[1], -d[i], -d[i + 1]]);
  END LOOP;
END $$;
