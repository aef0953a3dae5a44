-- tinmerge 0.18.0 -> 0.19.0. Stored values read and answer as before.
-- New: tin_viewshed, the viewshed of one observer (or, counted, of a
-- MULTIPOINT's) over a level as a raster (two forms: at a cell size, or
-- on the grid of a reference raster); tin_viewshed_polygon, the ground
-- seen as a MULTIPOLYGON.
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
CREATE  FUNCTION "_tin_viewshed"(
	"t" tin,
	"observer" geometry,
	"radius" double precision,
	"cell_size" double precision,
	"observer_height" double precision,
	"target_height" double precision,
	"level" INT,
	"curvature" bool,
	"refraction" double precision,
	"gridx" double precision,
	"gridy" double precision
) RETURNS bytea
IMMUTABLE PARALLEL SAFE COST 100000 
LANGUAGE c
AS 'MODULE_PATHNAME', '_tin_viewshed_wrapper';
CREATE  FUNCTION "_tin_viewshed_ref"(
	"t" tin,
	"observer" geometry,
	"radius" double precision,
	"rast" bytea,
	"observer_height" double precision,
	"target_height" double precision,
	"level" INT,
	"curvature" bool,
	"refraction" double precision
) RETURNS bytea
IMMUTABLE PARALLEL SAFE COST 100000 
LANGUAGE c
AS 'MODULE_PATHNAME', '_tin_viewshed_ref_wrapper';
COMMENT ON FUNCTION _tin_viewshed(tin, geometry, float8, float8, float8, float8, int, boolean, float8, float8, float8) IS 'Internal: use tin_viewshed(tin, geometry, float8, float8, ...).';
COMMENT ON FUNCTION _tin_viewshed_ref(tin, geometry, float8, bytea, float8, float8, int, boolean, float8) IS 'Internal: use tin_viewshed(tin, geometry, float8, raster, ...).';

CREATE FUNCTION tin_viewshed(t tin, observer geometry, radius float8, cell_size float8, observer_height float8 DEFAULT 1.7, target_height float8 DEFAULT 0, level int DEFAULT NULL, curvature boolean DEFAULT false, refraction float8 DEFAULT 0.13, gridx float8 DEFAULT 0, gridy float8 DEFAULT 0)
RETURNS raster AS
$$ SELECT ST_RastFromWKB(@extschema@._tin_viewshed($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11)) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 100000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_viewshed(tin, geometry, float8, float8, float8, float8, int, boolean, float8, float8, float8) IS
'The viewshed of an observer over the surface of a level (NULL = finest) as a one-band raster of square cells cell_size across, pixel edges on the lines gridx + k * cell_size and gridy + k * cell_size (as gdalwarp -tap; pass the DEM''s ST_UpperLeftX/Y and pixel size to get gdal_viewshed''s grid), covering the observer''s radius within the tin''s extent, with the tin''s SRID. A cell is 1 (visible) when the sight line from the observer''s eye (a POINT: observer_height above the surface; a POINT Z: at that absolute height) to the point target_height above the surface at the cell''s centre does not go below the surface, tin_line_of_sight''s verdict; 0 (hidden) otherwise; nodata (255) off the domain or farther than radius (horizontal, in the tin''s units) from the observer. A MULTIPOINT observes from each of its points and counts: each cell holds how many see it (8BUI up to 254 observers, else 16BUI with nodata 65535), a cumulative viewshed. curvature and refraction as tin_line_of_sight. By a fan of rays walked once through the hierarchy (coarse triangles that cannot rise into view are skipped whole), each cell decided by the two rays around it and its own ray''s last cells walked exactly; a cell whose two rays disagree is walked exactly from the observer. The observer must be over the tin''s hull and have its SRID. At most 65535 cells a side. NULL for a NULL argument other than level.';

CREATE FUNCTION tin_viewshed(t tin, observer geometry, radius float8, ref raster, observer_height float8 DEFAULT 1.7, target_height float8 DEFAULT 0, level int DEFAULT NULL, curvature boolean DEFAULT false, refraction float8 DEFAULT 0.13)
RETURNS raster AS
$$ SELECT ST_RastFromWKB(@extschema@._tin_viewshed_ref($1, $2, $3, $4::bytea, $5, $6, $7, $8, $9)) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 100000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_viewshed(tin, geometry, float8, raster, float8, float8, int, boolean, float8) IS
'The viewshed of tin_viewshed(tin, geometry, float8, float8, ...) on the grid of ref (its size, georeference and SRID; its bands are ignored), for example the DEM the tin was built from or a tile of ST_MakeEmptyCoverage: 1 visible, 0 hidden, nodata (255) off the domain or past radius; a MULTIPOINT observer counts. ref must be north-up and have the tin''s SRID. NULL for a NULL argument other than level.';

CREATE FUNCTION tin_viewshed_polygon(t tin, observer geometry, radius float8, cell_size float8, observer_height float8 DEFAULT 1.7, target_height float8 DEFAULT 0, level int DEFAULT NULL, curvature boolean DEFAULT false, refraction float8 DEFAULT 0.13, gridx float8 DEFAULT 0, gridy float8 DEFAULT 0)
RETURNS geometry AS
$$ SELECT COALESCE(ST_Multi(ST_Union(d.geom)), ST_SetSRID('MULTIPOLYGON EMPTY'::geometry, ST_SRID($2)))
   FROM ST_DumpAsPolygons(@extschema@.tin_viewshed($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11)) AS d
   WHERE d.val >= 1 $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 100000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_viewshed_polygon(tin, geometry, float8, float8, float8, float8, int, boolean, float8, float8, float8) IS
'The ground seen from the observer (from at least one point of a MULTIPOINT) as a MULTIPOLYGON: the union of the visible cells of tin_viewshed with the same arguments, each cell its square (ST_DumpAsPolygons); an empty MULTIPOLYGON when nothing is seen. NULL for a NULL argument other than level.';
