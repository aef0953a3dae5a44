-- tinmerge public SQL API: PostGIS geometry/raster signatures over the
-- internal bytea functions (_tin_*), plus a comment on every function.
-- Levels are 0-based: 0 = coarsest; a NULL or omitted level = finest.

CREATE FUNCTION tin_from_raster(rast raster, tolerance float8, levels int DEFAULT 5, band int DEFAULT 1, keep_border boolean DEFAULT false)
RETURNS tin AS $$ SELECT @extschema@._tin_from_raster($1::bytea, $2, $3, $4, $5) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE;
COMMENT ON FUNCTION tin_from_raster(raster, float8, int, int, boolean) IS
'Builds a tin from the valid pixel centres of one band (nodata skipped). Level i is within tolerance * 2^(levels-1-i) of every sample; levels 1..16. keep_border => true makes every sample on the edges of the convex hull a vertex of every level, so tiles that share a border row or column of pixels have the same surface along it (see docs/scaling.md, tiled terrains).';

CREATE FUNCTION tin_from_raster(rast raster, tolerances float8[], band int DEFAULT 1, keep_border boolean DEFAULT false)
RETURNS tin AS $$ SELECT @extschema@._tin_from_raster_tolerances($1::bytea, $2, $3, $4) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE;
COMMENT ON FUNCTION tin_from_raster(raster, float8[], int, boolean) IS
'Builds a tin from the valid pixel centres of one band with explicit per-level tolerances (coarsest first, strictly decreasing). keep_border as for tin_from_raster(raster, float8, int, int, boolean).';

CREATE FUNCTION tin_from_points(pts geometry, tolerance float8, levels int DEFAULT 5)
RETURNS tin AS $$ SELECT @extschema@._tin_from_points($1::bytea, $2, $3) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE;
COMMENT ON FUNCTION tin_from_points(geometry, float8, int) IS
'Builds a tin from every vertex of a geometry with Z (typically MULTIPOINT Z); points with equal x,y are merged (mean z). Error is measured at the samples.';

CREATE FUNCTION tin_envelope(t tin)
RETURNS geometry AS $$ SELECT @extschema@._tin_envelope($1)::geometry $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE;
COMMENT ON FUNCTION tin_envelope(tin) IS
'Bounding box of the tin as a POLYGON with its SRID (read from the header only).';

CREATE FUNCTION tin_triangles(t tin, level int DEFAULT NULL)
RETURNS TABLE(id int, parent int, geom geometry) AS
$$ SELECT id, parent, geom::geometry FROM @extschema@._tin_triangles($1, $2) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_triangles(tin, int) IS
'Triangles of one level (NULL = finest) as POLYGON Z with the tin''s SRID; parent is the containing triangle of the previous level (NULL at level 0).';

CREATE FUNCTION tin_as_svg(t tin, level int DEFAULT NULL, triangles int[] DEFAULT NULL,
                           vals float8[] DEFAULT NULL, classes text[] DEFAULT NULL,
                           features geometry DEFAULT NULL, legend text DEFAULT NULL, width int DEFAULT 800)
RETURNS text AS $$ SELECT @extschema@._tin_as_svg($1, $2, $3, $4, $5, $6::bytea, $7, $8) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000;
COMMENT ON FUNCTION tin_as_svg(tin, int, int[], float8[], text[], geometry, text, int) IS
'An SVG picture of one level (NULL = finest), width pixels wide, with a legend: triangles coloured by height; or, with triangles => ids and vals => values (e.g. array_agg of a merge''s output), by value (others grey); or with classes => labels, one colour per class (at most 20); triangles alone highlights them. features (a geometry in the tin''s SRID) is drawn on top. NULL when t is NULL.';

CREATE FUNCTION tin_as_gltf(t tin, level int DEFAULT NULL, texture raster DEFAULT NULL, z_factor float8 DEFAULT 1.0)
RETURNS bytea AS $$ SELECT @extschema@._tin_as_gltf($1, $2, $3::bytea, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000;
COMMENT ON FUNCTION tin_as_gltf(tin, int, raster, float8) IS
'One level (NULL = finest) as a binary glTF 2.0 (.glb) mesh, y up, centred on the bounding box (the centre and SRID are in the node extras), heights times z_factor. With texture (a north-up raster in the tin''s SRID: 1 band grey, 3 RGB, 4 RGBA; at most 8192 pixels a side) the image is painted on the surface; without, vertices are coloured by height. NULL when t is NULL.';

CREATE FUNCTION tin_as_geometry(t tin, level int DEFAULT NULL)
RETURNS geometry AS $$ SELECT @extschema@._tin_as_geometry($1, $2)::geometry $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_as_geometry(tin, int) IS
'One level (NULL = finest) as a PostGIS TIN Z geometry.';

-- Point merge (seed 6.3). tin_locate, tin_height and tin_footprint are Rust
-- functions taking geometry directly (read without a WKB conversion). Not
-- STRICT (a NULL level means finest); a NULL tin or geometry gives NULL, an
-- empty geometry gives NULL.
COMMENT ON FUNCTION tin_locate(tin, geometry, int) IS
'Id (as in tin_triangles) of the triangle of a level (NULL = finest) containing a POINT; on a shared edge or vertex, the smallest id; NULL outside the domain. Grid index + exact walk: constant time per point.';

COMMENT ON FUNCTION tin_height(tin, geometry, int) IS
'Height of the surface of a level (NULL = finest) at a POINT, by linear interpolation on the triangle containing it; NULL outside the domain. The point''s own Z, if any, is ignored.';

COMMENT ON FUNCTION tin_footprint(tin, geometry, float8, float8, float8, int) IS
'Ids of the triangles of a level (NULL = finest) meeting the closed rectangle centred on a POINT, width across and length along angle (degrees clockwise from north), in increasing id order. Width and length >= 0 (0 gives a segment or a point).';

-- Line merge (seed 6.4). Lines travel as EWKB to the _tin_line_* functions.
CREATE FUNCTION tin_line_triangles(t tin, line geometry, level int DEFAULT NULL, width float8 DEFAULT 0)
RETURNS TABLE(seq int, triangle int) AS
$$ SELECT * FROM @extschema@._tin_line_triangles($1, $2::bytea, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_line_triangles(tin, geometry, int, float8) IS
'Triangles of a level (NULL = finest) a LINESTRING or MULTILINESTRING passes through, in travel order (seq from 1; a triangle entered again appears again). With width > 0: every triangle within width/2 of the line, each once, ordered by where the line first comes that close. Stretches outside the domain are skipped; along a shared edge the smaller triangle id holds the stretch.';

CREATE FUNCTION tin_line_segments(t tin, line geometry, level int DEFAULT NULL)
RETURNS TABLE(seq int, triangle int, geom geometry, length2d float8, length3d float8, rise float8) AS
$$ SELECT seq, triangle, geom::geometry, length2d, length3d, rise FROM @extschema@._tin_line_segments($1, $2::bytea, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_line_segments(tin, geometry, int) IS
'The line cut at every triangle edge of a level (NULL = finest): one LINESTRING Z on the surface per triangle crossed, in travel order, with its planar length, surface length and rise (end height minus start height). Stretches outside the domain are skipped.';

CREATE FUNCTION tin_line_profile(t tin, line geometry, level int DEFAULT NULL)
RETURNS TABLE(distance float8, z float8) AS
$$ SELECT * FROM @extschema@._tin_line_profile($1, $2::bytea, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_line_profile(tin, geometry, int) IS
'Height profile along a line: every vertex of the draped line (the line''s vertices and its triangle-edge crossings) with its planar distance from the start (parts of a MULTILINESTRING follow each other). Stretches outside the domain give no points.';

CREATE FUNCTION tin_line_climb(t tin, line geometry, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@._tin_line_climb($1, $2::bytea, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_line_climb(tin, geometry, int) IS
'Total ascent along the direction of the line on the surface of a level (NULL = finest): the sum of the positive height differences along the draped line (0 for a line running only downhill; NULL when no part is in the domain).';

-- The multi-scale line tree: build once (e.g. in a generated column), merge
-- many times. The linetree overloads give the same rows as the geometry ones.
CREATE FUNCTION tin_linetree(line geometry)
RETURNS linetree AS $$ SELECT @extschema@._tin_linetree($1::bytea) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE;
COMMENT ON FUNCTION tin_linetree(geometry) IS
'Multi-scale line tree of a LINESTRING or MULTILINESTRING (Douglas-Peucker generalisations, each child level within a quarter of its parent''s error, an error bound per segment): merges with a tin through it skip the stretches that cannot leave a triangle. NULL for an empty line.';
COMMENT ON FUNCTION tin_linetree_info(linetree) IS
'SRID, parts, points, tree nodes, planar length and size in bytes of a linetree.';
COMMENT ON FUNCTION tin_line_triangles(tin, linetree, int, float8) IS
'tin_line_triangles through a stored line tree: the same rows as for its geometry, visiting only the stretches near triangle edges.';
CREATE FUNCTION tin_line_segments(t tin, line linetree, level int DEFAULT NULL)
RETURNS TABLE(seq int, triangle int, geom geometry, length2d float8, length3d float8, rise float8) AS
$$ SELECT seq, triangle, geom::geometry, length2d, length3d, rise FROM @extschema@._tin_line_segments_tree($1, $2, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_line_segments(tin, linetree, int) IS
'tin_line_segments through a stored line tree: the same rows as for its geometry.';
COMMENT ON FUNCTION tin_line_profile(tin, linetree, int) IS
'tin_line_profile through a stored line tree: the same rows as for its geometry.';
COMMENT ON FUNCTION tin_line_climb(tin, linetree, int) IS
'tin_line_climb through a stored line tree: the same value as for its geometry.';

CREATE FUNCTION tin_drape(t tin, geom geometry, level int DEFAULT NULL)
RETURNS geometry AS $$ SELECT @extschema@._tin_drape($1, $2::bytea, $3)::geometry $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_drape(tin, geometry, int) IS
'The geometry with Z from the surface of a level (NULL = finest) and a vertex added wherever a line or ring crosses a triangle edge (as ArcGIS Interpolate Shape or H2GIS ST_Drape). Any type, multi* and collections included. Points outside the domain are dropped; lines keep their stretches inside (a line leaving and coming back becomes a MULTILINESTRING); a polygon with a vertex outside is an error. NULL when nothing is left.';

-- Area merge. PostGIS decides validity (ST_IsValidReason); the functions
-- that measure in the SRID's units are told whether it is geographic.
CREATE FUNCTION @extschema@._tin_srid_is_geographic(srid int) RETURNS boolean AS
$$ SELECT EXISTS (SELECT 1 FROM spatial_ref_sys s WHERE s.srid = $1
     AND (s.proj4text LIKE '%+proj=longlat%' OR s.srtext LIKE 'GEOGCS%' OR s.srtext LIKE 'GEOGCRS%')) $$
LANGUAGE sql STABLE STRICT PARALLEL SAFE;
COMMENT ON FUNCTION _tin_srid_is_geographic(int) IS 'Internal: whether spatial_ref_sys describes the SRID as geographic (longitude/latitude).';

CREATE FUNCTION tin_area_triangles(t tin, area geometry, level int DEFAULT NULL, compact boolean DEFAULT false)
RETURNS TABLE(triangle int, level int, relation text, coverage float8) AS
$$ SELECT * FROM @extschema@._tin_area_triangles($1, $2::bytea, $3, $4, ST_IsValidReason($2)) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_area_triangles(tin, geometry, int, boolean) IS
'Triangles of a level (NULL = finest) on and inside a POLYGON or MULTIPOLYGON, by the hierarchical polygonal sweep: relation ''inside'' (wholly inside, touching the boundary allowed; coverage 1) or ''boundary'' (the polygon''s boundary crosses the triangle; coverage = fraction of the triangle''s area inside). With compact => true, inside triangles are reported at the coarsest level whose triangle is wholly inside (the level column says which), covering the same region. Parts outside the domain are ignored; an invalid polygon is an error (repair it with ST_MakeValid).';

CREATE FUNCTION tin_area_stats(t tin, area geometry, level int DEFAULT NULL)
RETURNS TABLE(area2d float8, area3d float8, min_z float8, max_z float8, mean_z float8, mean_slope float8, max_slope float8) AS
$$ SELECT * FROM @extschema@._tin_area_stats($1, $2::bytea, $3, ST_IsValidReason($2), @extschema@._tin_srid_is_geographic(@extschema@.tin_srid($1))) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_area_stats(tin, geometry, int) IS
'Statistics of the surface of a level (NULL = finest) clipped exactly to a POLYGON or MULTIPOLYGON: planar area, surface area, min/max height, area-weighted mean height and slope (degrees), steepest slope. Heights are NULL when the polygon misses the domain. Planar SRIDs only: a geographic tin is an error.';

CREATE FUNCTION tin_surface_area(t tin, area geometry, level int DEFAULT NULL)
RETURNS float8 AS
$$ SELECT s.area3d FROM @extschema@.tin_area_stats($1, $2, $3) s $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000;
COMMENT ON FUNCTION tin_surface_area(tin, geometry, int) IS
'Surface (3D) area of a level (NULL = finest) clipped exactly to a POLYGON or MULTIPOLYGON: the area3d of tin_area_stats as a scalar (0 when the polygon misses the domain; NULL when an argument other than level is NULL), so it can be used where a set-returning call cannot, e.g. pushed down to a postgres_fdw shard. Planar SRIDs only.';

CREATE FUNCTION tin_volume(t tin, area geometry, base_z float8, level int DEFAULT NULL)
RETURNS TABLE(cut float8, fill float8) AS
$$ SELECT * FROM @extschema@._tin_volume($1, $2::bytea, $3, $4, ST_IsValidReason($2), @extschema@._tin_srid_is_geographic(@extschema@.tin_srid($1))) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_volume(tin, geometry, float8, int) IS
'Volumes inside a POLYGON or MULTIPOLYGON between the surface of a level (NULL = finest) and the height base_z: cut = volume of surface above base_z, fill = volume of the space below base_z down to the surface (as a cut-and-fill or ArcGIS Surface Volume), exact for the linear surface. Planar SRIDs only.';

COMMENT ON FUNCTION tin_srid(tin) IS 'SRID of the tin (header only).';
COMMENT ON FUNCTION tin_num_levels(tin) IS 'Number of levels of detail (header only).';
COMMENT ON FUNCTION tin_num_triangles(tin, int) IS 'Triangles at a level (NULL = finest; header only).';
COMMENT ON FUNCTION tin_num_vertices(tin, int) IS 'Vertices used by a level (NULL = finest; header only).';
COMMENT ON FUNCTION tin_tolerance(tin, int) IS 'Vertical error bound a level was built to (NULL = finest; header only).';
COMMENT ON FUNCTION tin_validate(tin) IS
'Problems of a stored tin, one row each: level, problem (''crack'': a triangle of zero area up to rounding whose corner lies on the opposite edge while the surfaces on the two sides disagree there, a vertical wall; ''sliver'': the same where they agree), triangle id (as in tin_triangles) and a detail. No rows for a sound tin. Tins built by tinmerge 0.2.0 from rasters whose pixel centres do not round exactly (geographic grids, fractional origins) have them: rebuild those (docs/upgrading.md).';
ALTER FUNCTION tin_validate(tin) ROWS 10;
COMMENT ON FUNCTION tin_info(tin) IS 'SRID, bounding box, size in bytes and per level: tolerance, triangles, vertices and the max error measured at the source samples (header only).';
COMMENT ON FUNCTION tin_cache_stats() IS 'This backend''s decoded-tin cache: hits, misses, entries and bytes (see tinmerge.cache_size).';

COMMENT ON FUNCTION _tin_from_raster(bytea, float8, int, int, boolean) IS 'Internal: use tin_from_raster(raster, ...).';
COMMENT ON FUNCTION _tin_from_raster_tolerances(bytea, float8[], int, boolean) IS 'Internal: use tin_from_raster(raster, float8[], ...).';
COMMENT ON FUNCTION _tin_from_points(bytea, float8, int) IS 'Internal: use tin_from_points(geometry, ...).';
COMMENT ON FUNCTION _tin_envelope(tin) IS 'Internal: use tin_envelope(tin).';
COMMENT ON FUNCTION _tin_triangles(tin, int) IS 'Internal: use tin_triangles(tin, int).';
COMMENT ON FUNCTION _tin_as_geometry(tin, int) IS 'Internal: use tin_as_geometry(tin, int).';
COMMENT ON FUNCTION _tin_as_svg(tin, int, int[], float8[], text[], bytea, text, int) IS 'Internal: use tin_as_svg(tin, ...).';
COMMENT ON FUNCTION _tin_as_gltf(tin, int, bytea, float8) IS 'Internal: use tin_as_gltf(tin, ...).';
ALTER FUNCTION _tin_as_svg(tin, int, int[], float8[], text[], bytea, text, int) COST 10000;
ALTER FUNCTION _tin_as_gltf(tin, int, bytea, float8) COST 10000;
COMMENT ON FUNCTION _tin_drape(tin, bytea, int) IS 'Internal: use tin_drape(tin, geometry, int).';
COMMENT ON FUNCTION _tin_line_triangles(tin, bytea, int, float8) IS 'Internal: use tin_line_triangles(tin, geometry, int, float8).';
COMMENT ON FUNCTION _tin_line_segments(tin, bytea, int) IS 'Internal: use tin_line_segments(tin, geometry, int).';
COMMENT ON FUNCTION _tin_line_profile(tin, bytea, int) IS 'Internal: use tin_line_profile(tin, geometry, int).';
COMMENT ON FUNCTION _tin_line_climb(tin, bytea, int) IS 'Internal: use tin_line_climb(tin, geometry, int).';
COMMENT ON FUNCTION _tin_area_triangles(tin, bytea, int, boolean, text) IS 'Internal: use tin_area_triangles(tin, geometry, int, boolean).';
COMMENT ON FUNCTION _tin_area_stats(tin, bytea, int, text, boolean) IS 'Internal: use tin_area_stats(tin, geometry, int).';
COMMENT ON FUNCTION _tin_volume(tin, bytea, float8, int, text, boolean) IS 'Internal: use tin_volume(tin, geometry, float8, int).';
COMMENT ON FUNCTION _tin_raster_stats(tin, bytea, int, int, boolean) IS 'Internal: use tin_raster_stats(tin, raster, int, int, boolean).';
COMMENT ON FUNCTION _tin_paint(tin, bytea, int) IS 'Internal: use tin_paint(tin, raster, int).';
COMMENT ON FUNCTION _tin_raster_pixels(tin, bytea, int, int) IS 'Internal: use tin_raster_pixels(tin, raster, int, int).';
COMMENT ON FUNCTION _tin_overlay(tin, tin, int, int) IS 'Internal: use tin_overlay(tin, tin, int, int).';
COMMENT ON FUNCTION _tin_overlay_tin(tin, tin, int, int) IS 'Internal: use tin_overlay_tin(tin, tin, int, int).';
COMMENT ON FUNCTION _tin_difference(tin, tin, int, int) IS 'Internal: use tin_difference(tin, tin, int, int).';
COMMENT ON FUNCTION _tin_linetree(bytea) IS 'Internal: use tin_linetree(geometry).';
COMMENT ON FUNCTION _tin_line_segments_tree(tin, linetree, int) IS 'Internal: use tin_line_segments(tin, linetree, int).';
COMMENT ON FUNCTION linetree_in(cstring) IS 'Text input of linetree: hex of the binary form, fully validated (every error bound recomputed).';
COMMENT ON FUNCTION linetree_out(linetree) IS 'Text output of linetree: hex of the binary form.';
COMMENT ON FUNCTION linetree_recv(internal) IS 'Binary input of linetree, fully validated.';
COMMENT ON FUNCTION linetree_send(linetree) IS 'Binary output of linetree.';
COMMENT ON FUNCTION tin_in(cstring) IS 'Text input of tin: hex of the binary form, fully validated.';
COMMENT ON FUNCTION tin_out(tin) IS 'Text output of tin: hex of the binary form.';
COMMENT ON FUNCTION tin_recv(internal) IS 'Binary input of tin, fully validated.';
COMMENT ON FUNCTION tin_send(tin) IS 'Binary output of tin.';

-- raster merge
CREATE FUNCTION tin_raster_stats(t tin, rast raster, level int DEFAULT NULL, band int DEFAULT 1, weighted boolean DEFAULT false)
RETURNS TABLE(triangle int, count bigint, sum float8, mean float8, min float8, max float8, mode float8) AS
$$ SELECT * FROM @extschema@._tin_raster_stats($1, $2::bytea, $3, $4, $5) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_raster_stats(tin, raster, int, int, boolean) IS
'Zonal statistics of a raster band per triangle of a level (NULL = finest). By default (scanline sweep) a pixel belongs to the triangle containing its centre (a centre on a shared edge goes to the triangle east of it, north of an east-west edge; on a vertex to the triangle just east-north-east of it; on the outer boundary to the triangle it lies on). With weighted => true every pixel a triangle overlaps counts by the exact fraction of its area inside the triangle, as exactextract does: count = pixels overlapped, sum = sum of value x fraction, mean = sum / sum of fractions, mode = value of greatest total coverage. Nodata pixels are skipped; triangles receiving no pixel are not returned; mode ties go to the smallest value. The raster must be north-up, in-db, with the tin''s SRID.';

CREATE FUNCTION tin_raster_pixels(t tin, rast raster, level int DEFAULT NULL, band int DEFAULT 1)
RETURNS TABLE(triangle int, col int, "row" int, value float8) AS
$$ SELECT * FROM @extschema@._tin_raster_pixels($1, $2::bytea, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_raster_pixels(tin, raster, int, int) IS
'Every valid pixel of a raster band with the triangle of a level (NULL = finest) containing its centre (the rule of tin_raster_stats), in raster order; col and row numbered from 1 as in ST_Value. Nodata pixels and pixels outside the tin are left out.';

CREATE FUNCTION tin_paint(t tin, rast raster, level int DEFAULT NULL)
RETURNS TABLE(triangle int, r float8, g float8, b float8) AS
$$ SELECT * FROM @extschema@._tin_paint($1, $2::bytea, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_paint(tin, raster, int) IS
'An image painted on the surface: the mean colour (bands 1, 2, 3 as red, green, blue) of the pixels whose centres each triangle of a level (NULL = finest) contains (the rule of tin_raster_stats); a pixel counts when all three bands are valid. Triangles receiving no pixel are not returned.';

-- TIN/TIN overlay
CREATE FUNCTION tin_overlay(a tin, b tin, level_a int DEFAULT NULL, level_b int DEFAULT NULL)
RETURNS TABLE(id int, triangle_a int, triangle_b int, geom_a geometry, geom_b geometry) AS
$$ SELECT id, triangle_a, triangle_b, geom_a::geometry, geom_b::geometry FROM @extschema@._tin_overlay($1, $2, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_overlay(tin, tin, int, int) IS
'Overlay of two tins at their levels (NULL = finest): a triangulation of the common domain holding every vertex and every edge of both (edges cut where they cross). Each output triangle with the triangle of a and of b containing it (ids as in tin_triangles) and twice as POLYGON Z: heights from surface a, then from surface b. Both tins must have the same SRID; disjoint domains give no rows.';

CREATE FUNCTION tin_overlay_tin(a tin, b tin, level_a int DEFAULT NULL, level_b int DEFAULT NULL)
RETURNS tin AS
$$ SELECT @extschema@._tin_overlay_tin($1, $2, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_overlay_tin(tin, tin, int, int) IS
'The overlay of tin_overlay as a single-level tin with heights from a (tolerance 0), so every other merge works on it. NULL when the domains do not overlap.';

CREATE FUNCTION tin_difference(a tin, b tin, level_a int DEFAULT NULL, level_b int DEFAULT NULL)
RETURNS TABLE(cut float8, fill float8, area_changed float8) AS
$$ SELECT * FROM @extschema@._tin_difference($1, $2, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE;
COMMENT ON FUNCTION tin_difference(tin, tin, int, int) IS
'Surface difference of a against b over their common domain (as ArcGIS Surface Difference): cut = volume where a is above b, fill = volume where a is below b, area_changed = planar area where they differ. Exact for the linear surfaces: computed on the overlay, each triangle split at the line where a = b. No row when the domains do not overlap.';

-- Equality (0.2.0): the same stored bytes; hashable, so GROUP BY, DISTINCT
-- and hash joins work on tin columns.
COMMENT ON FUNCTION tin_eq(tin, tin) IS
'True when two tins are the same value (the same bytes; header hashes and lengths compared first). The function behind the = operator.';
COMMENT ON FUNCTION tin_ne(tin, tin) IS
'True when two tins are different values. The function behind the <> operator.';
COMMENT ON FUNCTION tin_hash(tin) IS
'32-bit hash of a tin (its stored content hash): hash operator class support for =.';

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

-- Planner costs (0.2.0; 0.1.0 had the defaults), in PostGIS's tiers (COST 1 default, 50 low, 500
-- medium, 10000 high; measured per call on the DEM: a height ~1.5 us, a
-- footprint or a linetree well under 1 ms, a contour line or polygon merge
-- 0.5-5 ms, builds and whole-raster merges 10 ms and up), on the public functions and on the internal ones the
-- SQL wrappers call (the wrappers are not inlined: see the search_path block below); ROWS for set-returning
-- functions. They let a join of a large feature table with a terrain use
-- parallel workers (docs/scaling.md).
ALTER FUNCTION tin_height(tin, geometry, integer) COST 50;
ALTER FUNCTION tin_locate(tin, geometry, integer) COST 50;
ALTER FUNCTION tin_footprint(tin, geometry, float8, float8, float8, integer) COST 500 ROWS 20;
ALTER FUNCTION tin_drape(tin, geometry, integer) COST 10000;
ALTER FUNCTION _tin_drape(tin, bytea, integer) COST 10000;
ALTER FUNCTION tin_as_geometry(tin, integer) COST 10000;
ALTER FUNCTION _tin_as_geometry(tin, integer) COST 10000;
ALTER FUNCTION tin_triangles(tin, integer) COST 10000 ROWS 10000;
ALTER FUNCTION _tin_triangles(tin, integer) COST 10000 ROWS 10000;
ALTER FUNCTION tin_linetree(geometry) COST 500;
ALTER FUNCTION _tin_linetree(bytea) COST 500;
ALTER FUNCTION tin_line_triangles(tin, geometry, integer, float8) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_triangles(tin, linetree, integer, float8) COST 10000 ROWS 100;
ALTER FUNCTION _tin_line_triangles(tin, bytea, integer, float8) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_segments(tin, geometry, integer) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_segments(tin, linetree, integer) COST 10000 ROWS 100;
ALTER FUNCTION _tin_line_segments(tin, bytea, integer) COST 10000 ROWS 100;
ALTER FUNCTION _tin_line_segments_tree(tin, linetree, integer) COST 500 ROWS 100;
ALTER FUNCTION tin_line_profile(tin, geometry, integer) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_profile(tin, linetree, integer) COST 10000 ROWS 100;
ALTER FUNCTION _tin_line_profile(tin, bytea, integer) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_climb(tin, geometry, integer) COST 10000;
ALTER FUNCTION tin_line_climb(tin, linetree, integer) COST 10000;
ALTER FUNCTION _tin_line_climb(tin, bytea, integer) COST 10000;
ALTER FUNCTION tin_area_triangles(tin, geometry, integer, boolean) COST 10000 ROWS 1000;
ALTER FUNCTION _tin_area_triangles(tin, bytea, integer, boolean, text) COST 10000 ROWS 1000;
ALTER FUNCTION tin_area_stats(tin, geometry, integer) COST 10000 ROWS 1;
ALTER FUNCTION _tin_area_stats(tin, bytea, integer, text, boolean) COST 10000 ROWS 1;
ALTER FUNCTION tin_volume(tin, geometry, float8, integer) COST 10000 ROWS 1;
ALTER FUNCTION _tin_volume(tin, bytea, float8, integer, text, boolean) COST 10000 ROWS 1;
ALTER FUNCTION tin_from_raster(raster, float8, integer, integer, boolean) COST 10000;
ALTER FUNCTION tin_from_raster(raster, float8[], integer, boolean) COST 10000;
ALTER FUNCTION _tin_from_raster(bytea, float8, integer, integer, boolean) COST 10000;
ALTER FUNCTION _tin_from_raster_tolerances(bytea, float8[], integer, boolean) COST 10000;
ALTER FUNCTION tin_from_points(geometry, float8, integer) COST 10000;
ALTER FUNCTION _tin_from_points(bytea, float8, integer) COST 10000;
ALTER FUNCTION tin_raster_stats(tin, raster, integer, integer, boolean) COST 10000 ROWS 10000;
ALTER FUNCTION _tin_raster_stats(tin, bytea, integer, integer, boolean) COST 10000 ROWS 10000;
ALTER FUNCTION tin_raster_pixels(tin, raster, integer, integer) COST 10000 ROWS 100000;
ALTER FUNCTION _tin_raster_pixels(tin, bytea, integer, integer) COST 10000 ROWS 100000;
ALTER FUNCTION tin_paint(tin, raster, integer) COST 10000 ROWS 10000;
ALTER FUNCTION _tin_paint(tin, bytea, integer) COST 10000 ROWS 10000;
ALTER FUNCTION tin_overlay(tin, tin, integer, integer) COST 10000 ROWS 100000;
ALTER FUNCTION _tin_overlay(tin, tin, integer, integer) COST 10000 ROWS 100000;
ALTER FUNCTION tin_overlay_tin(tin, tin, integer, integer) COST 10000;
ALTER FUNCTION _tin_overlay_tin(tin, tin, integer, integer) COST 10000;
ALTER FUNCTION tin_difference(tin, tin, integer, integer) COST 10000 ROWS 1;
ALTER FUNCTION _tin_difference(tin, tin, integer, integer) COST 10000 ROWS 1;
ALTER FUNCTION tin_cache_stats() ROWS 1;

-- search_path safety (0.2.0): every SQL-language wrapper runs with the
-- search_path of the install (this extension's schema, then PostGIS's), so
-- it works from sessions whose search_path lacks them: postgres_fdw's remote
-- sessions (pg_catalog only), pg_restore, SET search_path = ''. (PostgreSQL
-- 15 has no @extschema:postgis@ to qualify PostGIS names with; the price is
-- that the planner no longer inlines these wrappers.)
DO $$
DECLARE f regprocedure;
BEGIN
  FOR f IN
    SELECT p.oid::regprocedure
    FROM pg_proc p
    JOIN pg_depend d ON d.classid = 'pg_proc'::regclass AND d.objid = p.oid AND d.deptype = 'e'
    JOIN pg_extension e ON d.refclassid = 'pg_extension'::regclass AND d.refobjid = e.oid
    WHERE e.extname = 'tinmerge' AND p.prolang = (SELECT oid FROM pg_language WHERE lanname = 'sql')
  LOOP
    EXECUTE format('ALTER FUNCTION %s SET search_path FROM CURRENT', f);
  END LOOP;
END $$;
