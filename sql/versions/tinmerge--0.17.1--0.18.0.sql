-- tinmerge 0.17.1 -> 0.18.0. Stored values read and answer as before.
-- New: tin_as_raster, the surface of a level as a PostGIS raster (two
-- forms: on the grid of a reference raster, or at a pixel size); and
-- tin_volume(a, b, area), cut and fill between two surfaces inside a
-- polygon; and tin_line_of_sight.
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
CREATE  FUNCTION "_tin_as_raster"(
	"t" tin,
	"rast" bytea,
	"level" INT,
	"pixel_type" TEXT,
	"nodata" double precision
) RETURNS bytea
IMMUTABLE PARALLEL SAFE COST 10000 
LANGUAGE c
AS 'MODULE_PATHNAME', '_tin_as_raster_wrapper';
COMMENT ON FUNCTION _tin_as_raster(tin, bytea, int, text, float8) IS 'Internal: use tin_as_raster(tin, raster, int, text, float8).';
CREATE  FUNCTION "_tin_as_raster_sized"(
	"t" tin,
	"pixel_size" double precision,
	"level" INT,
	"pixel_type" TEXT,
	"nodata" double precision,
	"gridx" double precision,
	"gridy" double precision
) RETURNS bytea
IMMUTABLE PARALLEL SAFE COST 10000 
LANGUAGE c
AS 'MODULE_PATHNAME', '_tin_as_raster_sized_wrapper';
COMMENT ON FUNCTION _tin_as_raster_sized(tin, float8, int, text, float8, float8, float8) IS 'Internal: use tin_as_raster(tin, float8, int, text, float8, float8, float8).';

CREATE FUNCTION tin_as_raster(t tin, ref raster, level int DEFAULT NULL, pixel_type text DEFAULT '64BF', nodata float8 DEFAULT -9999)
RETURNS raster AS
$$ SELECT ST_RastFromWKB(@extschema@._tin_as_raster($1, $2::bytea, $3, $4, $5)) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_as_raster(tin, raster, int, text, float8) IS
'The surface of a level (NULL = finest) as a one-band raster on the grid of ref (its size, georeference and SRID; its bands are ignored): the height at every pixel centre, bit for bit what tin_height gives at ST_PixelAsCentroid of that pixel, by one scanline sweep over the triangles (no point location per pixel). Pixels whose centre is off the domain (off the hull, in a hole or outside a build''s boundary) get nodata. pixel_type ''64BF'' (exact) or ''32BF''; nodata is the band''s nodata value. ST_HillShade, ST_Slope, ST_Aspect, ST_AsGDALRaster and gdaldem then work on the tin. ref must be north-up and have the tin''s SRID; for a large extent, one call per tile of ST_MakeEmptyCoverage. NULL for a NULL tin, raster, pixel_type or nodata.';
CREATE FUNCTION tin_as_raster(t tin, pixel_size float8, level int DEFAULT NULL, pixel_type text DEFAULT '64BF', nodata float8 DEFAULT -9999, gridx float8 DEFAULT 0, gridy float8 DEFAULT 0)
RETURNS raster AS
$$ SELECT ST_RastFromWKB(@extschema@._tin_as_raster_sized($1, $2, $3, $4, $5, $6, $7)) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_as_raster(tin, float8, int, text, float8, float8, float8) IS
'The surface of a level (NULL = finest) as a one-band north-up raster of square pixels pixel_size across (in the tin''s units), with the tin''s SRID: pixel edges on the lines gridx + k * pixel_size and gridy + k * pixel_size (as gdalwarp -tap), the fewest pixels covering the tin''s extent. Heights at pixel centres, nodata off the domain, as tin_as_raster(tin, raster). At most 65535 pixels a side and 1 GB; for the grid of an existing raster (the DEM the tin was built from), pass that raster instead. NULL for a NULL tin, pixel_size, pixel_type, nodata, gridx or gridy.';

CREATE  FUNCTION "tin_volume"(
	"a" tin,
	"b" tin,
	"area" geometry,
	"level_a" INT DEFAULT NULL,
	"level_b" INT DEFAULT NULL
) RETURNS TABLE (
	"cut" double precision, 
	"fill" double precision, 
	"area_cut" double precision, 
	"area_fill" double precision, 
	"area_unchanged" double precision 
)
IMMUTABLE PARALLEL SAFE SUPPORT "_tin_plan_support"  COST 10000 
LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_volume_between_wrapper';
ALTER FUNCTION tin_volume(tin, tin, geometry, int, int) ROWS 1;
COMMENT ON FUNCTION tin_volume(tin, tin, geometry, int, int) IS
'Cut and fill between two surfaces inside a POLYGON or MULTIPOLYGON (holes count out), each at a level (NULL = finest): two epochs of a survey, or a design against the ground, as ArcGIS Surface Difference and Cut Fill. cut = volume where a is above b, fill = volume where a is below b, area_cut and area_fill the planar areas where it is so, area_unchanged where the two are one plane (their triangles'' planes agree within 1e-9 of the height, as tin_difference); exact for the linear surfaces, over the overlay of the two (tin_overlay) clipped to the polygon. Only the common domain counts: the three areas sum to the polygon''s part of it. The tins must share their SRID, a projected one; the polygon must have it too. No row for a NULL tin or polygon.';
ALTER FUNCTION tin_volume(tin, tin, geometry, int, int) SET search_path FROM CURRENT;

CREATE  FUNCTION "tin_line_of_sight"(
	"t" tin,
	"observer" geometry,
	"target" geometry,
	"observer_height" double precision DEFAULT 1.7,
	"target_height" double precision DEFAULT 0,
	"level" INT DEFAULT NULL,
	"curvature" bool DEFAULT false,
	"refraction" double precision DEFAULT 0.13
) RETURNS TABLE (
	"visible" bool, 
	"obstruction" geometry, 
	"distance" double precision, 
	"clearance" double precision 
)
IMMUTABLE PARALLEL SAFE SUPPORT "_tin_plan_support" COST 500 
LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_line_of_sight_wrapper';
ALTER FUNCTION tin_line_of_sight(tin, geometry, geometry, float8, float8, int, boolean, float8) ROWS 1;
COMMENT ON FUNCTION tin_line_of_sight(tin, geometry, geometry, float8, float8, int, boolean, float8) IS
'Whether a target can be seen from an observer over the surface of a level (NULL = finest), exactly for its triangles: the straight sight line from the observer''s eye (a POINT: observer_height above the surface; a POINT Z: at that absolute height) to the target (target_height above the surface, or its Z) is cut at every triangle edge, and blocked where the surface rises above it. visible; obstruction, the first point where the surface meets the sight line, as a POINT Z on the surface (NULL when visible); distance, its horizontal distance from the observer in the tin''s units; clearance, the least height of the sight line above the surface strictly between the two (negative when blocked; NULL when the line crosses no edge). curvature: distant ground lowered by (1 - refraction) d^2 / (2 R), R = 6,371 km (as gdal_viewshed and r.viewshed), with d in metres (geographic tins: degrees converted along the line). Where the line leaves the domain nothing blocks. Points must have the tin''s SRID; a POINT off the surface needs a Z. No row for a NULL argument other than level.';
ALTER FUNCTION tin_line_of_sight(tin, geometry, geometry, float8, float8, int, boolean, float8) SET search_path FROM CURRENT;
