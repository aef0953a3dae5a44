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
