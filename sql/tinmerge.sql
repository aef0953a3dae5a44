-- tinmerge's SQL-language functions: PostGIS geometry/raster signatures
-- over the internal Rust functions (_tin_*, which take EWKB/raster bytes),
-- and the operators on tin. Each function carries its flags, COST and ROWS
-- in its definition and its COMMENT right after it; the Rust functions carry
-- theirs next to their #[pg_extern] in src/pg/ (cost = ...; an
-- extension_sql! block with ROWS and the COMMENT). pgrx places this file
-- after every Rust function.
--
-- Levels are 0-based: 0 = coarsest; a NULL or omitted level = finest.
--
-- Costs are in PostGIS's tiers (COST 1 default, 50 low, 500 medium, 10000
-- high; measured per call on the DEM: a height ~1.5 us, a footprint or a
-- linetree well under 1 ms, a contour line or polygon merge 0.5-5 ms, builds
-- and whole-raster merges 10 ms and up); ROWS on set-returning functions.
-- They let a join of a large feature table with a terrain use parallel
-- workers (docs/scaling.md).
--
-- search_path: every function below is defined with SET search_path FROM
-- CURRENT, so it runs with the setting pinned here, once: this extension's
-- schema, PostGIS's schema (each once), then pg_temp last. The wrappers then
-- work from sessions whose search_path lacks them (postgres_fdw's remote
-- sessions, pg_restore, SET search_path = ''). PostgreSQL 15 has no
-- @extschema:postgis@ to qualify PostGIS names with; the price is that the
-- planner does not inline these wrappers, so the per-row functions (points)
-- are Rust functions instead. CREATE EXTENSION restores the session's own
-- search_path after this script.
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);

CREATE FUNCTION tin_from_raster(rast raster, tolerance float8, levels int DEFAULT 5, band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL, fill_gaps boolean DEFAULT false)
RETURNS tin AS $$ SELECT CASE WHEN $6 IS NULL AND $7 IS NULL AND $8 IS NULL AND $9
  THEN @extschema@._tin_from_raster($1::bytea, $2, $3, $4, $5)
  ELSE @extschema@._tin_from_raster_domain($1::bytea, $2, $3, $4, $5, $6::bytea, $7::bytea, $8::bytea, $9) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, float8, int, int, boolean, geometry, geometry, geometry, boolean) IS
'Builds a tin from the valid pixel centres of one band (nodata skipped). Level i is within tolerance * 2^(levels-1-i) of every sample and of the raster''s surface between the samples too (with a boundary or soft breaklines too; hard breaklines keep their own heights, and the grid segments they cut are left out): on every grid line between two valid pixel centres (their straight line, what gdal_contour and bilinear ST_Value use), a vertex being put where an edge over the tolerance crosses one; with keep_border everywhere but the one-pixel strip along the hull, whose vertices are its own samples so that tiles agree (tin_validate(tin, raster) checks a value); levels 1..16. keep_border => true decides the vertices on each side of the convex hull from that side''s samples alone, simplified to each level''s tolerance, so tiles that share a border row or column of pixels have the same vertices and the same surface along it at every level (see docs/scaling.md, tiled terrains). breaklines (LINESTRING Z / MULTILINESTRING Z, the raster''s SRID) are hard: the surface follows their own heights along them; soft_breaklines (any lines, Z ignored) are edges whose heights follow the samples along them, simplified to each level''s tolerance. Every breakline is a union of edges at every level, level 0 included; crossing lines split each other; samples on a line (up to rounding) are left out and every other sample is within each level''s tolerance. Parts of breaklines outside the samples'' convex hull are cut off; hard lines crossing at different heights raise an ERROR (docs/breaklines.md). boundary (POLYGON / MULTIPOLYGON, holes allowed, valid, the same SRID) limits the terrain to its area within the samples'' convex hull, concave parts and holes included: its rings there are edges at every level with heights from the samples, the samples outside it are left out, and every merge answers NULL or no rows outside it (the triangles there are void, not returned by tin_triangles; docs/breaklines.md). Breaklines outside the boundary shape nothing that is returned. The terrain is where the raster has data: the domain is the union of the valid pixels'' squares (what ST_Value answers on) within the convex hull of their centres, nodata around and inside the data left out, so tin_height is NULL wherever ST_Value is NULL (a build with a boundary of those squares; a raster without nodata in that hull builds on its pixel lattice as before). fill_gaps => true fills the nodata gaps instead, the domain being the hull of the valid centres (the default until 0.9.0). With keep_border => true and nodata cutting into that hull, the tile is built over its data as tin_tiles builds it (since 0.22.0): the valid squares within the hull, clipped to its outer pixel centres, the outline''s pieces there chosen from their own samples so that the tile beside it agrees. NULL for a NULL raster, tolerance, levels, band, keep_border or fill_gaps.';

-- An untyped tolerance (NULL, 'Infinity', '{8,4,2}') matches both the
-- float8 and the float8[] forms; this text form, which PostgreSQL prefers
-- for it, reads it as one float8, or as the tolerances per level when it
-- is an array literal.
CREATE FUNCTION tin_from_raster(rast raster, tolerance text, levels int DEFAULT 5, band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL, fill_gaps boolean DEFAULT false)
RETURNS tin AS $$ SELECT CASE WHEN pg_catalog.btrim($2) LIKE '{%'
  THEN @extschema@.tin_from_raster($1, $2::float8[], $4, $5, $6, $7, $8, $9)
  ELSE @extschema@.tin_from_raster($1, $2::float8, $3, $4, $5, $6, $7, $8, $9) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, text, int, int, boolean, geometry, geometry, geometry, boolean) IS
'tin_from_raster with the tolerance given as text (e.g. an untyped literal: NULL, ''Infinity'', ''2.5''): tin_from_raster(rast, tolerance::float8, levels, ...); an array literal (''{8,4,2}'') is the tolerances per level, coarsest first: tin_from_raster(rast, tolerance::float8[], band, ...), levels unused.';

CREATE FUNCTION tin_from_raster(rast raster, tolerances float8[], band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL, fill_gaps boolean DEFAULT false)
RETURNS tin AS $$ SELECT CASE WHEN $5 IS NULL AND $6 IS NULL AND $7 IS NULL AND $8
  THEN @extschema@._tin_from_raster_tolerances($1::bytea, $2, $3, $4)
  ELSE @extschema@._tin_from_raster_tolerances_domain($1::bytea, $2, $3, $4, $5::bytea, $6::bytea, $7::bytea, $8) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, float8[], int, boolean, geometry, geometry, geometry, boolean) IS
'Builds a tin from the valid pixel centres of one band with explicit per-level tolerances (coarsest first, strictly decreasing). keep_border, breaklines, soft_breaklines, boundary and fill_gaps as for tin_from_raster(raster, float8, int, int, boolean, geometry, geometry, geometry, boolean).';

CREATE FUNCTION tin_tiles(rast raster, tile_px int, tolerance float8, levels int DEFAULT 5, band int DEFAULT 1, fill_gaps boolean DEFAULT false)
RETURNS TABLE(tx int, ty int, t tin) AS
$$ SELECT * FROM @extschema@._tin_tiles($1::bytea, $2, $3, $4, $5, $6) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_tiles(raster, int, float8, int, int, boolean) IS
'Builds one band of a raster as a grid of tins in one call: tile (tx, ty) (numbered from 0, west to east and north to south) holds tile_px x tile_px pixels plus the first column of its right neighbour and the first row of the one below, and is built as tin_from_raster(..., keep_border => true) does, so neighbouring tiles have the same vertices on their shared seam at every level and their surfaces agree along it. As for tin_from_raster, the terrain is where the raster has data (fill_gaps => false, the default): a tile whose nodata pixels reach into the hull of its valid centres has for domain the valid pixels'' squares within that hull, clipped to its seams (the centre lines of its shared column and row), so tin_height is NULL wherever ST_Value is; the outline''s pieces on a seam have the same vertices and heights seen from both tiles, so the tiles'' domains meet without gap or overlap. fill_gaps => true fills the gaps: each tile is the hull of its valid centres (the only form until 0.22.0). Tiles are built on tinmerge.threads threads; a tile without three non-collinear valid pixels gives no row. NULL arguments give no rows. Index the result with CREATE INDEX ON tiles USING gist (tin_envelope(t)) (docs/scaling.md).';
CREATE FUNCTION tin_tiles_from_table(tiles regclass, tolerance float8, levels int DEFAULT 5, rast_column name DEFAULT 'rast', band int DEFAULT 1, slice int DEFAULT 0, slices int DEFAULT 1, fill_gaps boolean DEFAULT false)
RETURNS TABLE(tx int, ty int, t tin) AS
$$ SELECT * FROM @extschema@._tin_tiles_table($1::oid, $4::text, $2, $3, $5, $6, $7, $8) $$
LANGUAGE sql STABLE STRICT PARALLEL RESTRICTED COST 100000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_tiles_from_table(regclass, float8, int, name, int, int, int, boolean) IS
'Builds one band (of the raster column rast_column) of a table of raster tiles (raster2pgsql -t, ST_Tile: one pixel grid, tiles cut at multiples of one size) as a grid of tins in one call: tile (tx, ty) (numbered from 0 from the top-left tile, west to east and north to south) is built from its own pixels plus the first column of the tile to its right, the first row of the one below and the first pixel of the one below-right, as tin_tiles(raster, ...) builds the tiles of one raster, so seams agree at every level. Tiles are read a row at a time and built on tinmerge.threads threads, so memory stays bounded by two rows of tiles whatever the table''s size. Tiles whose pixel size, skew or SRID differ, or that are not a whole number of pixels apart, raise an ERROR (22023). slice => k, slices => n (0 <= k < n) returns only the k-th of n bands of tile rows (ty from k * rows / n up to the next band''s), each tile byte for byte what the whole build gives it: the seams are planned with 10 more rows of tiles on each side, so n sessions can each build and insert one slice at the same time (docs/scaling.md); a slice out of range raises 22023. fill_gaps as for tin_tiles: by default each tile is over its valid pixels'' squares only; fill_gaps => true fills the gaps (the only form until 0.22.0). Index the result with CREATE INDEX ON tiles USING gist (tin_envelope(t)) (docs/scaling.md).';

CREATE FUNCTION tin_overviews(tiles regclass, tolerance float8, levels int DEFAULT 5, rast_column name DEFAULT 'rast', band int DEFAULT 1, slice int DEFAULT 0, slices int DEFAULT 1, fill_gaps boolean DEFAULT false)
RETURNS TABLE(factor int, minzoom int, maxzoom int, tx int, ty int, t tin) AS
$$ SELECT * FROM @extschema@._tin_overviews($1::oid, $4::text, $2, $3, $5, $6, $7, $8) $$
LANGUAGE sql STABLE STRICT PARALLEL RESTRICTED COST 100000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_overviews(regclass, float8, int, name, int, int, int, boolean) IS
'Builds one terrain from zoom 0 to the finest as a pyramid of tiled terrains: the table of raster tiles (factor 1) and each overview PostGIS lists for its raster column in raster_overviews (raster2pgsql -l 4,16,64, ST_CreateOverview), each built as tin_tiles_from_table(overview, tolerance * factor, levels, ...) builds it (an overview of factor f, its pixels f times larger, with f times the tolerance: the same error for its pixel size) (tx, ty in that layer''s grid of tiles; seams agree at every level), except that an overview pixel left nodata by PostGIS''s resampling takes the mean of the table''s valid pixels under it, or when there are none under it, of those under it and its eight neighbours, and the tiles on an overview''s frame are grown by a pixel (copies of their outer pixels) where the table''s outer pixel centres lie past the overview''s, so every layer covers all the table''s layer covers (an overview reaching past the data''s edge by up to about two of its pixels), each row carrying the zooms its layer serves (minzoom..maxzoom): a zoom is served by the coarsest layer whose pixels are no larger than the detail Cesium expects of it (a tile of zoom z is 65 x 65 heights, 180 / 2^z / 64 degrees apart), the finest layer up to zoom 24, the coarsest from 0; so a tile reads the tins of one layer only, at most 2 x 2 of them when the tiles are 128 pixels a side or more; a layer whose pixels are no coarser than the next finer one''s gives no rows. Serve a tile from the rows with z BETWEEN minzoom AND maxzoom whose extent meets it (docs/serving.md). slice, slices and fill_gaps as for tin_tiles_from_table, for every layer. The layers must share the table''s SRID (22023), which must be set (the zooms are measured in degrees).';

CREATE FUNCTION tin_from_points(pts geometry, tolerance float8, levels int DEFAULT 5, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL)
RETURNS tin AS $$ SELECT CASE WHEN $4 IS NULL AND $5 IS NULL AND $6 IS NULL
  THEN @extschema@._tin_from_points($1::bytea, $2, $3)
  ELSE @extschema@._tin_from_points_domain($1::bytea, $2, $3, $4::bytea, $5::bytea, $6::bytea) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_points(geometry, float8, int, geometry, geometry, geometry) IS
'Builds a tin from every vertex of a geometry with Z (typically MULTIPOINT Z); points with equal x,y are merged (mean z). Level i is within tolerance * 2^(levels-1-i) of every sample and of the samples'' Delaunay triangulation everywhere (since 0.12.0; with breaklines or a boundary since 0.13.0, soft lines and rings taking its heights and its edges a hard line cuts left out; measured at its vertices and where edges cross its edges, a vertex being put at such a crossing where no sample mends it). breaklines (LINESTRING Z / MULTILINESTRING Z, the points'' SRID) are hard: the surface follows their own heights along them; soft_breaklines (any lines, Z ignored) are edges whose heights follow the samples along them, simplified to each level''s tolerance. Every breakline is a union of edges at every level, level 0 included; crossing lines split each other; samples on a line (up to rounding) are left out and every other sample is within each level''s tolerance. Parts of breaklines outside the samples'' convex hull are cut off; hard lines crossing at different heights raise an ERROR (docs/breaklines.md). boundary (POLYGON / MULTIPOLYGON, holes allowed, valid, the same SRID) limits the terrain to its area within the samples'' convex hull, concave parts and holes included: its rings there are edges at every level with heights from the samples, the samples outside it are left out, and every merge answers NULL or no rows outside it (the triangles there are void, not returned by tin_triangles; docs/breaklines.md). Breaklines outside the boundary shape nothing that is returned. NULL for NULL points, tolerance or levels.';

CREATE FUNCTION tin_envelope(t tin)
RETURNS geometry AS $$ SELECT @extschema@._tin_envelope($1)::geometry $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_envelope(tin) IS
'Bounding box of the tin as a POLYGON with its SRID (read from the header only).';

CREATE FUNCTION tin_triangles(t tin, level int DEFAULT NULL)
RETURNS TABLE(id int, parent int, geom geometry) AS
$$ SELECT id, parent, geom::geometry FROM @extschema@._tin_triangles($1, $2) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_triangles(tin, int) IS
'Triangles of one level (NULL = finest) as POLYGON Z with the tin''s SRID; parent is the containing triangle of the previous level (NULL at level 0).';

CREATE FUNCTION tin_as_svg(t tin, level int DEFAULT NULL, triangles int[] DEFAULT NULL,
                           vals float8[] DEFAULT NULL, classes text[] DEFAULT NULL,
                           features geometry DEFAULT NULL, legend text DEFAULT NULL, width int DEFAULT 800)
RETURNS text AS $$ SELECT @extschema@._tin_as_svg($1, $2, $3, $4, $5, $6::bytea, $7, $8) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_as_svg(tin, int, int[], float8[], text[], geometry, text, int) IS
'An SVG picture of one level (NULL = finest), width pixels wide, with a legend: triangles coloured by height; or, with triangles => ids and vals => values (e.g. array_agg of a merge''s output), by value (others grey); or with classes => labels, one colour per class (at most 20); triangles alone highlights them. features (a geometry in the tin''s SRID) is drawn on top. NULL when t is NULL.';

CREATE FUNCTION tin_as_gltf(t tin, level int DEFAULT NULL, texture raster DEFAULT NULL, z_factor float8 DEFAULT 1.0)
RETURNS bytea AS $$ SELECT @extschema@._tin_as_gltf($1, $2, $3::bytea, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_as_gltf(tin, int, raster, float8) IS
'One level (NULL = finest) as a binary glTF 2.0 (.glb) mesh, y up, centred on the bounding box (the centre and SRID are in the node extras), heights times z_factor. With texture (a north-up raster in the tin''s SRID: 1 band grey, 3 RGB, 4 RGBA; at most 8192 pixels a side) the image is painted on the surface; without, vertices are coloured by height. NULL when t is NULL.';

CREATE FUNCTION tin_as_geometry(t tin, level int DEFAULT NULL)
RETURNS geometry AS $$ SELECT @extschema@._tin_as_geometry($1, $2)::geometry $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_as_geometry(tin, int) IS
'One level (NULL = finest) as a PostGIS TIN Z geometry.';

-- Point merge (seed 6.3): tin_locate, tin_height, tin_footprint and
-- tin_drape are Rust functions reading PostGIS's serialisation directly
-- (src/pg/point.rs, src/pg/line.rs).

-- Line merge (seed 6.4). Lines travel as EWKB to the _tin_line_* functions.
CREATE FUNCTION tin_line_triangles(t tin, line geometry, level int DEFAULT NULL, width float8 DEFAULT 0)
RETURNS TABLE(seq int, triangle int) AS
$$ SELECT * FROM @extschema@._tin_line_triangles($1, $2::bytea, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_triangles(tin, geometry, int, float8) IS
'Triangles of a level (NULL = finest) a LINESTRING or MULTILINESTRING passes through, in travel order (seq from 1; a triangle entered again appears again). With width > 0: every triangle within width/2 of the line, each once, ordered by where the line first comes that close. Stretches outside the domain are skipped; along a shared edge the smaller triangle id holds the stretch.';

CREATE FUNCTION tin_line_segments(t tin, line geometry, level int DEFAULT NULL)
RETURNS TABLE(seq int, triangle int, geom geometry, length2d float8, length3d float8, rise float8) AS
$$ SELECT seq, triangle, geom::geometry, length2d, length3d, rise FROM @extschema@._tin_line_segments($1, $2::bytea, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_segments(tin, geometry, int) IS
'The line cut at every triangle edge of a level (NULL = finest): one LINESTRING Z on the surface per triangle crossed, in travel order, with its planar length, surface length and rise (end height minus start height). Stretches outside the domain are skipped.';

CREATE FUNCTION tin_line_profile(t tin, line geometry, level int DEFAULT NULL)
RETURNS TABLE(distance float8, z float8) AS
$$ SELECT * FROM @extschema@._tin_line_profile($1, $2::bytea, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_profile(tin, geometry, int) IS
'Height profile along a line: every vertex of the draped line (the line''s vertices and its triangle-edge crossings) with its planar distance from the start (parts of a MULTILINESTRING follow each other). Stretches outside the domain give no points.';

CREATE FUNCTION tin_line_climb(t tin, line geometry, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@._tin_line_climb($1, $2::bytea, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_climb(tin, geometry, int) IS
'Total ascent along the direction of the line on the surface of a level (NULL = finest): the sum of the positive height differences along the draped line (0 for a line running only downhill; NULL when no part is in the domain).';

-- The multi-scale line tree: build once (e.g. in a generated column), merge
-- many times. The linetree overloads give the same rows as the geometry ones.
CREATE FUNCTION tin_linetree(line geometry)
RETURNS linetree AS $$ SELECT @extschema@._tin_linetree($1::bytea) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE COST 500 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_linetree(geometry) IS
'Multi-scale line tree of a LINESTRING or MULTILINESTRING (Douglas-Peucker generalisations, each child level within a quarter of its parent''s error, an error bound per segment): merges with a tin through it skip the stretches that cannot leave a triangle. NULL for an empty line.';
CREATE FUNCTION tin_line_segments(t tin, line linetree, level int DEFAULT NULL)
RETURNS TABLE(seq int, triangle int, geom geometry, length2d float8, length3d float8, rise float8) AS
$$ SELECT seq, triangle, geom::geometry, length2d, length3d, rise FROM @extschema@._tin_line_segments_tree($1, $2, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_segments(tin, linetree, int) IS
'tin_line_segments through a stored line tree: the same rows as for its geometry.';

-- Untyped literals: a quoted line ('SRID=32616;LINESTRING(...)', as
-- PostGIS users write them) matches both the geometry and the linetree
-- forms, and PostgreSQL refused it as "not unique". PostgreSQL prefers a
-- text form for an untyped literal, so these take the text as a geometry
-- (PostGIS's own text forms, ST_AsText(text) and others, do the same).
CREATE FUNCTION tin_line_triangles(t tin, line text, level int DEFAULT NULL, width float8 DEFAULT 0)
RETURNS TABLE(seq int, triangle int) AS
$$ SELECT * FROM @extschema@.tin_line_triangles($1, $2::geometry, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_triangles(tin, text, int, float8) IS
'tin_line_triangles of a line given as text (WKT or EWKT, e.g. an untyped literal): the rows of line::geometry.';
CREATE FUNCTION tin_line_segments(t tin, line text, level int DEFAULT NULL)
RETURNS TABLE(seq int, triangle int, geom geometry, length2d float8, length3d float8, rise float8) AS
$$ SELECT * FROM @extschema@.tin_line_segments($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_segments(tin, text, int) IS
'tin_line_segments of a line given as text (WKT or EWKT, e.g. an untyped literal): the rows of line::geometry.';
CREATE FUNCTION tin_line_profile(t tin, line text, level int DEFAULT NULL)
RETURNS TABLE(distance float8, z float8) AS
$$ SELECT * FROM @extschema@.tin_line_profile($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_profile(tin, text, int) IS
'tin_line_profile of a line given as text (WKT or EWKT, e.g. an untyped literal): the rows of line::geometry.';
CREATE FUNCTION tin_line_climb(t tin, line text, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_line_climb($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_climb(tin, text, int) IS
'tin_line_climb of a line given as text (WKT or EWKT, e.g. an untyped literal): the value for line::geometry.';

-- The Rust functions that call PostGIS (tin_area_triangles, tin_area_stats,
-- tin_surface_area, tin_volume: ST_IsValidReason, their validity verdict,
-- called by OID; the quantized-mesh functions: ST_Transform) or read its
-- spatial_ref_sys (the area functions, tin_slope_aspect and
-- tin_line_of_sight, for a tin whose extent could be in degrees) find them
-- in PostGIS's schema, looked up in pg_extension once per backend
-- (src/pg/args.rs, postgis()), so they work whatever the session's
-- search_path and pin none: a function with a SET clause pays a
-- configuration change on every call (0.27.0; until 0.26.0 they pinned this
-- search_path, 6 % of a zonal join's time).

-- raster merge
CREATE FUNCTION tin_raster_stats(t tin, rast raster, level int DEFAULT NULL, band int DEFAULT 1, weighted boolean DEFAULT false, half_open boolean DEFAULT false)
RETURNS TABLE(triangle int, count bigint, sum float8, mean float8, min float8, max float8, mode float8) AS
$$ SELECT * FROM @extschema@._tin_raster_zonal($1, $2::bytea, $3, $4, $5, $6) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_raster_stats(tin, raster, int, int, boolean, boolean) IS
'Zonal statistics of a raster band per triangle of a level (NULL = finest). By default (scanline sweep) a pixel belongs to the triangle containing its centre (a centre on a shared edge goes to the triangle east of it, north of an east-west edge; on a vertex to the triangle just east-north-east of it; on the outer boundary to the triangle it lies on). With weighted => true every pixel a triangle overlaps counts by the exact fraction of its area inside the triangle, as exactextract does: count = pixels overlapped, sum = sum of value x fraction, mean = sum / sum of fractions, mode = value of greatest total coverage. With half_open => true a centre on the domain''s outer boundary counts only where the domain continues east of it (north of an east-west side), the rule of shared edges: over a table of tiles sharing their seams (tin_tiles) every seam centre is then counted by exactly one tile, the one a single tin of their union gives it to, and centres on the union''s west and south sides are not counted (weighted statistics need no such option: coverage fractions add up across seams). Nodata pixels are skipped; triangles receiving no pixel are not returned; mode ties go to the smallest value. The raster must be north-up, in-db, with the tin''s SRID.';

CREATE FUNCTION tin_raster_pixels(t tin, rast raster, level int DEFAULT NULL, band int DEFAULT 1, half_open boolean DEFAULT false)
RETURNS TABLE(triangle int, col int, "row" int, value float8) AS
$$ SELECT * FROM @extschema@._tin_raster_owners($1, $2::bytea, $3, $4, $5) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_raster_pixels(tin, raster, int, int, boolean) IS
'Every valid pixel of a raster band with the triangle of a level (NULL = finest) containing its centre (the rule of tin_raster_stats, half_open included), in raster order; col and row numbered from 1 as in ST_Value. Nodata pixels and pixels outside the tin are left out.';

CREATE FUNCTION tin_validate(t tin, rast raster, band int DEFAULT 1, breaklines geometry DEFAULT NULL)
RETURNS TABLE(level int, problem text, triangle int, detail text) AS
$$ SELECT * FROM @extschema@._tin_validate_raster($1, $2::bytea, $3, COALESCE($4::bytea, ''::bytea)) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 100000 ROWS 10 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_validate(tin, raster, int, geometry) IS
'The rows of tin_validate(tin), and one row per level further from a raster band''s surface than its tolerance (problem ''over tolerance''): the surface is the band''s value at each valid pixel centre and, on every grid line between two valid pixel centres, the straight line between them (what gdal_contour and bilinear ST_Value use); a level is linear in each triangle, so its error there is largest at a pixel centre or where an edge crosses a grid line, and both are measured. triangle holds the worst place, detail its error, position and how many crossings and centres are over. Values built by 0.10.0 and earlier kept coarse heights along coarse edges into finer levels and show here; rebuild them (docs/upgrading.md). A tile (keep_border) can show for the one-pixel strip along its hull, whose vertices are its own samples so that neighbouring tiles agree. breaklines: the hard breaklines the tin was built with (tin_from_raster''s breaklines); the surface holds their own heights along them, so the grid segments they cut (within 1e-6 pixel) and the pixel centres on them are left out, as the build leaves them out. No rows for a sound value within its tolerances. The raster and the breaklines must have the tin''s SRID; nodata pixels are skipped. No rows for a NULL tin, raster or band.';

CREATE FUNCTION tin_paint(t tin, rast raster, level int DEFAULT NULL)
RETURNS TABLE(triangle int, r float8, g float8, b float8) AS
$$ SELECT * FROM @extschema@._tin_paint($1, $2::bytea, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_paint(tin, raster, int) IS
'An image painted on the surface: the mean colour (bands 1, 2, 3 as red, green, blue) of the pixels whose centres each triangle of a level (NULL = finest) contains (the rule of tin_raster_stats); a pixel counts when all three bands are valid. Triangles receiving no pixel are not returned.';

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
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 100000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_viewshed_polygon(tin, geometry, float8, float8, float8, float8, int, boolean, float8, float8, float8) IS
'The ground seen from the observer (from at least one point of a MULTIPOINT) as a MULTIPOLYGON: the union of the visible cells of tin_viewshed with the same arguments, each cell its square (ST_DumpAsPolygons); an empty MULTIPOLYGON when nothing is seen. NULL for a NULL argument other than level.';

-- TIN/TIN overlay
CREATE FUNCTION tin_overlay(a tin, b tin, level_a int DEFAULT NULL, level_b int DEFAULT NULL)
RETURNS TABLE(id int, triangle_a int, triangle_b int, geom_a geometry, geom_b geometry) AS
$$ SELECT id, triangle_a, triangle_b, geom_a::geometry, geom_b::geometry FROM @extschema@._tin_overlay($1, $2, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_overlay(tin, tin, int, int) IS
'Overlay of two tins at their levels (NULL = finest): a triangulation of the common domain holding every vertex and every edge of both (edges cut where they cross). Each output triangle with the triangle of a and of b containing it (ids as in tin_triangles) and twice as POLYGON Z: heights from surface a, then from surface b. Both tins must have the same SRID; disjoint domains give no rows.';

CREATE FUNCTION tin_overlay_tin(a tin, b tin, level_a int DEFAULT NULL, level_b int DEFAULT NULL)
RETURNS tin AS
$$ SELECT @extschema@._tin_overlay_tin($1, $2, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_overlay_tin(tin, tin, int, int) IS
'The overlay of tin_overlay as a single-level tin with heights from a (tolerance 0), so every other merge works on it. NULL when the domains do not overlap.';

CREATE FUNCTION tin_difference(a tin, b tin, level_a int DEFAULT NULL, level_b int DEFAULT NULL)
RETURNS TABLE(cut float8, fill float8, area_changed float8) AS
$$ SELECT * FROM @extschema@._tin_difference($1, $2, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_difference(tin, tin, int, int) IS
'Surface difference of a against b over their common domain (as ArcGIS Surface Difference): cut = volume where a is above b, fill = volume where a is below b, area_changed = planar area where they differ. Exact for the linear surfaces: computed on the overlay, each triangle split at the line where a = b. No row when the domains do not overlap.';

-- Equality (0.2.0): the same stored bytes; hashable, so GROUP BY, DISTINCT
-- and hash joins work on tin columns.

CREATE OPERATOR = (
    LEFTARG = tin, RIGHTARG = tin, FUNCTION = tin_eq,
    COMMUTATOR = =, NEGATOR = <>,
    RESTRICT = eqsel, JOIN = eqjoinsel, HASHES
);
COMMENT ON OPERATOR =(tin, tin) IS 'same tin value (the same bytes)';

CREATE OPERATOR <> (
    LEFTARG = tin, RIGHTARG = tin, FUNCTION = tin_ne,
    COMMUTATOR = <>, NEGATOR = =,
    RESTRICT = neqsel, JOIN = neqjoinsel
);
COMMENT ON OPERATOR <>(tin, tin) IS 'different tin values';

CREATE OPERATOR CLASS tin_hash_ops DEFAULT FOR TYPE tin USING hash AS
    OPERATOR 1 = (tin, tin),
    FUNCTION 1 tin_hash(tin);

-- Untyped literals for the point and area merges too: with the geography
-- forms below, a quoted geometry matched both, so each has a text form,
-- which PostgreSQL prefers for an untyped literal and reads as a geometry.
CREATE FUNCTION tin_area_stats(t tin, area text, level int DEFAULT NULL)
RETURNS TABLE(area2d float8, area3d float8, min_z float8, max_z float8, mean_z float8, mean_slope float8, max_slope float8) AS $$ SELECT * FROM @extschema@.tin_area_stats($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_area_stats(tin, text, int) IS
'tin_area_stats of an area given as text (WKT or EWKT, e.g. an untyped literal): the answer for area::geometry.';
CREATE FUNCTION tin_area_triangles(t tin, area text, level int DEFAULT NULL, compact boolean DEFAULT false)
RETURNS TABLE(triangle int, level int, relation text, coverage float8) AS $$ SELECT * FROM @extschema@.tin_area_triangles($1, $2::geometry, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_area_triangles(tin, text, int, boolean) IS
'tin_area_triangles of an area given as text (WKT or EWKT, e.g. an untyped literal): the answer for area::geometry.';
CREATE FUNCTION tin_drape(t tin, geom text, level int DEFAULT NULL)
RETURNS geometry AS $$ SELECT @extschema@.tin_drape($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_drape(tin, text, int) IS
'tin_drape of a geom given as text (WKT or EWKT, e.g. an untyped literal): the answer for geom::geometry.';
CREATE FUNCTION tin_footprint(t tin, pt text, width float8, length float8, angle float8, level int DEFAULT NULL)
RETURNS SETOF int AS $$ SELECT * FROM @extschema@.tin_footprint($1, $2::geometry, $3, $4, $5, $6) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 20 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_footprint(tin, text, float8, float8, float8, int) IS
'tin_footprint of a pt given as text (WKT or EWKT, e.g. an untyped literal): the answer for pt::geometry.';
CREATE FUNCTION tin_height(t tin, pt text, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_height($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_height(tin, text, int) IS
'tin_height of a pt given as text (WKT or EWKT, e.g. an untyped literal): the answer for pt::geometry.';
CREATE FUNCTION tin_locate(t tin, pt text, level int DEFAULT NULL)
RETURNS int AS $$ SELECT @extschema@.tin_locate($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_locate(tin, text, int) IS
'tin_locate of a pt given as text (WKT or EWKT, e.g. an untyped literal): the answer for pt::geometry.';
CREATE FUNCTION tin_surface_area(t tin, area text, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_surface_area($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_surface_area(tin, text, int) IS
'tin_surface_area of an area given as text (WKT or EWKT, e.g. an untyped literal): the answer for area::geometry.';
CREATE FUNCTION tin_volume(t tin, area text, base_z float8, level int DEFAULT NULL)
RETURNS TABLE(cut float8, fill float8) AS $$ SELECT * FROM @extschema@.tin_volume($1, $2::geometry, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_volume(tin, text, float8, int) IS
'tin_volume of an area given as text (WKT or EWKT, e.g. an untyped literal): the answer for area::geometry.';

-- A geography argument: PostgreSQL has no implicit cast to geometry, and
-- without these forms the error was "function ... does not exist". They
-- raise 22023 with a hint that names the cast and the transform (the
-- geometry form called with an argument that raises it).
CREATE FUNCTION _tin_refuse_geography(func text, arg text, t tin) RETURNS geometry AS $$
BEGIN
  RAISE EXCEPTION '%: % is a geography; tinmerge merges geometry in the tin''s SRID', func, arg
    USING ERRCODE = '22023',
          HINT = format('cast it to geometry and transform it: ST_Transform(%s::geometry, %s)', arg,
                        COALESCE(@extschema@.tin_srid(t)::text, 'tin_srid(t)'));
END $$ LANGUAGE plpgsql IMMUTABLE PARALLEL SAFE
SET search_path FROM CURRENT;
COMMENT ON FUNCTION _tin_refuse_geography(text, text, tin) IS 'Internal: the error of the geography forms.';
CREATE FUNCTION tin_area_stats(t tin, area geography, level int DEFAULT NULL)
RETURNS TABLE(area2d float8, area3d float8, min_z float8, max_z float8, mean_z float8, mean_slope float8, max_slope float8) AS $$ SELECT * FROM @extschema@.tin_area_stats($1, @extschema@._tin_refuse_geography('tin_area_stats', 'area', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_area_stats(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(area::geometry, tin_srid(t)).';
CREATE FUNCTION tin_area_triangles(t tin, area geography, level int DEFAULT NULL, compact boolean DEFAULT false)
RETURNS TABLE(triangle int, level int, relation text, coverage float8) AS $$ SELECT * FROM @extschema@.tin_area_triangles($1, @extschema@._tin_refuse_geography('tin_area_triangles', 'area', $1), $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_area_triangles(tin, geography, int, boolean) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(area::geometry, tin_srid(t)).';
CREATE FUNCTION tin_drape(t tin, geom geography, level int DEFAULT NULL)
RETURNS geometry AS $$ SELECT @extschema@.tin_drape($1, @extschema@._tin_refuse_geography('tin_drape', 'geom', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_drape(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(geom::geometry, tin_srid(t)).';
CREATE FUNCTION tin_footprint(t tin, pt geography, width float8, length float8, angle float8, level int DEFAULT NULL)
RETURNS SETOF int AS $$ SELECT * FROM @extschema@.tin_footprint($1, @extschema@._tin_refuse_geography('tin_footprint', 'pt', $1), $3, $4, $5, $6) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 20 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_footprint(tin, geography, float8, float8, float8, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(pt::geometry, tin_srid(t)).';
CREATE FUNCTION tin_height(t tin, pt geography, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_height($1, @extschema@._tin_refuse_geography('tin_height', 'pt', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_height(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(pt::geometry, tin_srid(t)).';
CREATE FUNCTION tin_line_climb(t tin, line geography, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_line_climb($1, @extschema@._tin_refuse_geography('tin_line_climb', 'line', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_climb(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(line::geometry, tin_srid(t)).';
CREATE FUNCTION tin_line_profile(t tin, line geography, level int DEFAULT NULL)
RETURNS TABLE(distance float8, z float8) AS $$ SELECT * FROM @extschema@.tin_line_profile($1, @extschema@._tin_refuse_geography('tin_line_profile', 'line', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_profile(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(line::geometry, tin_srid(t)).';
CREATE FUNCTION tin_line_segments(t tin, line geography, level int DEFAULT NULL)
RETURNS TABLE(seq int, triangle int, geom geometry, length2d float8, length3d float8, rise float8) AS $$ SELECT * FROM @extschema@.tin_line_segments($1, @extschema@._tin_refuse_geography('tin_line_segments', 'line', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_segments(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(line::geometry, tin_srid(t)).';
CREATE FUNCTION tin_line_triangles(t tin, line geography, level int DEFAULT NULL, width float8 DEFAULT 0)
RETURNS TABLE(seq int, triangle int) AS $$ SELECT * FROM @extschema@.tin_line_triangles($1, @extschema@._tin_refuse_geography('tin_line_triangles', 'line', $1), $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_triangles(tin, geography, int, float8) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(line::geometry, tin_srid(t)).';
CREATE FUNCTION tin_locate(t tin, pt geography, level int DEFAULT NULL)
RETURNS int AS $$ SELECT @extschema@.tin_locate($1, @extschema@._tin_refuse_geography('tin_locate', 'pt', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_locate(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(pt::geometry, tin_srid(t)).';
CREATE FUNCTION tin_surface_area(t tin, area geography, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_surface_area($1, @extschema@._tin_refuse_geography('tin_surface_area', 'area', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_surface_area(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(area::geometry, tin_srid(t)).';
CREATE FUNCTION tin_volume(t tin, area geography, base_z float8, level int DEFAULT NULL)
RETURNS TABLE(cut float8, fill float8) AS $$ SELECT * FROM @extschema@.tin_volume($1, @extschema@._tin_refuse_geography('tin_volume', 'area', $1), $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1 SUPPORT _tin_plan_support
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_volume(tin, geography, float8, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(area::geometry, tin_srid(t)).';
