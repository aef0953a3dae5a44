-- Cesium quantized-mesh tiles (issue 27): the layer, the level a zoom
-- chooses, tiles off the terrain, fill, NULLs and bad addresses. The
-- decoded tiles are checked against PostGIS by
-- tests/properties/check_quantized_mesh.mjs (loaders.gl's decoder) and
-- drawn by CesiumJS in tests/globe.sh.
SET extra_float_digits = 0;
CREATE TABLE qm_layer AS SELECT tin_quantized_mesh_layer(t, normals => true, fill => true) AS j FROM terrain;
SELECT j->>'format' AS format, j->>'scheme' AS scheme, j->>'projection' AS projection, j->'tiles' AS tiles,
       j->'minzoom' AS minzoom, j->'maxzoom' AS maxzoom, j->'extensions' AS extensions,
       j->'available'->0 AS zoom0, json_array_length(j->'available') AS zooms
FROM qm_layer;
-- the bounds hold the terrain: every vertex of the finest level, through PostGIS
SELECT ST_XMin(g::box3d) >= w AND ST_YMin(g::box3d) >= s AND ST_XMax(g::box3d) <= e AND ST_YMax(g::box3d) <= n AS bounds_hold,
       round(w::numeric, 4) AS west, round(n::numeric, 4) AS north
FROM (SELECT (j->'bounds'->>0)::float8 w, (j->'bounds'->>1)::float8 s, (j->'bounds'->>2)::float8 e, (j->'bounds'->>3)::float8 n FROM qm_layer) b,
     (SELECT ST_Transform(ST_Collect(geom), 4326) AS g FROM terrain, tin_triangles(t)) v;
-- the available tiles of each zoom are the tiles over those bounds
SELECT z, (a->0->>'startX')::int AS x0, (a->0->>'endX')::int AS x1, (a->0->>'startY')::int AS y0, (a->0->>'endY')::int AS y1
FROM qm_layer, json_array_elements(j->'available') WITH ORDINALITY e(a, n), LATERAL (SELECT n - 1 AS z) zz
WHERE z IN (1, 8, 12);
-- the level a zoom chooses: the coarsest whose error bound (its tolerance,
-- or its measured error where larger) is at most the tile's geometric
-- error, 77067.34 m / 2^z
WITH lv AS (SELECT (l->>'level')::int AS level, greatest((l->>'tolerance')::float8, (l->>'max_error')::float8) AS e FROM terrain, jsonb_array_elements(tin_info(t)->'levels') l),
     z AS (SELECT z, coalesce((SELECT min(level) FROM lv WHERE e <= 6378137 * 2 * pi() * 0.25 / 130 / 2 ^ z), (SELECT max(level) FROM lv)) AS level
           FROM generate_series(10, 15) z),
     tile AS (SELECT z.z, z.level, x, y FROM z, qm_layer,
                LATERAL (SELECT ((j->'available'->z.z->0->>'startX')::int + (j->'available'->z.z->0->>'endX')::int) / 2 AS x,
                                ((j->'available'->z.z->0->>'startY')::int + (j->'available'->z.z->0->>'endY')::int) / 2 AS y) c)
SELECT tile.z, tile.level,
       tin_quantized_mesh(t, tile.z, x, y) = tin_quantized_mesh(t, tile.level, tile.z, x, y) AS same_as_its_level,
       tin_quantized_mesh(t, tile.z, x, y) <> tin_quantized_mesh(t, CASE WHEN tile.level = 0 THEN 1 ELSE tile.level - 1 END, tile.z, x, y) AS differs_from_another
FROM tile, terrain ORDER BY 1;
-- off the terrain: NULL; with fill, a flat tile of 4 vertices and 2 triangles
-- (88-byte header, 4 x 6 bytes of vertices, 2 x 3 indices, 4 edge lists of 2)
SELECT tin_quantized_mesh(t, 0, 1, 0) IS NULL AS east_root_null,
       length(tin_quantized_mesh(t, 0, 1, 0, fill => 0)) AS filled_bytes,
       length(tin_quantized_mesh(t, 3, 0, 0, fill => -10)) AS filled_far_bytes,
       length(tin_quantized_mesh(t, 0, 0, 0, fill => 0)) > length(tin_quantized_mesh(t, 0, 0, 0)) AS fill_adds
FROM terrain;
-- normals: one extension of 2 bytes per vertex after the edge lists
SELECT length(n) - length(b) = 5 + 2 * (get_byte(b, 88) + 256 * get_byte(b, 89) + 65536 * get_byte(b, 90)) AS normals_extension,
       get_byte(n, length(b)) AS extension_id
FROM terrain, LATERAL (SELECT tin_quantized_mesh(t, 13, 4357, 5760) AS b, tin_quantized_mesh(t, 13, 4357, 5760, normals => true) AS n) q;
-- NULLs: no tile; a NULL level is the finest
SELECT tin_quantized_mesh(NULL::tin, 0, 0, 0) IS NULL AS null_tin, tin_quantized_mesh(t, NULL, 0, 0) IS NULL AS null_z,
       tin_quantized_mesh(t, NULL::int, 15, 17431, 23044) = tin_quantized_mesh(t, 4, 15, 17431, 23044) AS null_level_finest,
       -- a NULL fill is no fill: the eastern root tile stays NULL, as it
       -- does not with fill => 0, and the western one is not filled around
       -- the terrain
       tin_quantized_mesh(t, 0, 1, 0, fill => NULL) IS NULL AND tin_quantized_mesh(t, 0, 1, 0, fill => 0) IS NOT NULL
         AND length(tin_quantized_mesh(t, 0, 0, 0, fill => NULL)) < length(tin_quantized_mesh(t, 0, 0, 0, fill => 0)) AS null_fill_none,
       tin_quantized_mesh_layer(NULL::tin) IS NULL AS null_layer
FROM terrain;
-- the geographic tin needs no transform; the same rules
SELECT (tin_quantized_mesh_layer(tin_from_raster(rast, 2.0, 4))->>'maxzoom')::int AS geo_maxzoom FROM dem_geo;
-- the array form (a terrain stored as tiles) of one tin is the single form
SELECT z, tin_quantized_mesh(ARRAY[t], z, x, y, normals => true, fill => 240) = tin_quantized_mesh(t, z, x, y, normals => true, fill => 240) AS same
FROM terrain, qm_layer,
     LATERAL (SELECT z, ((j->'available'->z->0->>'startX')::int + (j->'available'->z->0->>'endX')::int) / 2 AS x,
                        ((j->'available'->z->0->>'startY')::int + (j->'available'->z->0->>'endY')::int) / 2 AS y
              FROM generate_series(8, 15, 7) z) c ORDER BY z;
SELECT tin_quantized_mesh_layer(ARRAY[t])::text = tin_quantized_mesh_layer(t)::text AS same_layer FROM terrain;
-- tiles of tin_tiles as one terrain: the tiles over the bounds that meet the
-- window answer (4 corners of the box are off the window, rotated in degrees)

CREATE TABLE qm_win AS SELECT tx, ty, t FROM dem_window, tin_tiles(rast, 100, 2.0, 3);
WITH l AS (SELECT tin_quantized_mesh_layer(array_agg(t)) AS j FROM qm_win),
     r AS (SELECT (j->'available'->13->0) AS a FROM l)
SELECT count(*) AS tiles, count(*) FILTER (WHERE b IS NOT NULL) AS answered
FROM r, generate_series((a->>'startX')::int, (a->>'endX')::int) x, generate_series((a->>'startY')::int, (a->>'endY')::int) y,
     LATERAL (SELECT tin_quantized_mesh(array_agg(t), 13, x, y) AS b FROM qm_win) m;
SELECT tin_quantized_mesh('{}'::tin[], 13, 4357, 5760) IS NULL AS empty_is_off, length(tin_quantized_mesh('{}'::tin[], 13, 4357, 5760, fill => 0)) AS empty_filled,
       tin_quantized_mesh(NULL::tin[], 13, 4357, 5760) IS NULL AS null_array, tin_quantized_mesh_layer('{}'::tin[]) IS NULL AS empty_layer;
SELECT try($$SELECT tin_quantized_mesh(ARRAY[(SELECT t FROM terrain), (SELECT t FROM qm_win LIMIT 1)], 13, 4357, 5760)$$);
DROP TABLE qm_win;
-- the water mask and metadata extensions (tests/properties/check_quantized_mesh.mjs
-- checks the mask against PostGIS cell by cell and the metadata against
-- layer.json): the tile without them is the start of the tile with them,
-- then the extension's id and the mask (65,536 cells, or one byte when the
-- tile is all land or all water); NULL water and false metadata are none;
-- the polygons in the tin's SRID or in degrees give the same bytes
CREATE TABLE qm_water AS
SELECT ST_Buffer(ST_Centroid(tin_envelope(t)), 2500, 32) AS g, ST_Transform(ST_Centroid(tin_envelope(t)), 4326) AS c FROM terrain;
WITH k AS (SELECT z, floor((ST_X(c) + 180) / (180 / 2 ^ z))::int AS x, floor((ST_Y(c) + 90) / (180 / 2 ^ z))::int AS y
           FROM qm_water, generate_series(12, 15) z)
SELECT z, substr(w, 1, length(p)) = p AS prefix, get_byte(w, length(p)) AS ext_id, length(w) - length(p) - 5 AS mask_bytes,
       get_byte(w, length(w) - 1) AS last_cell,
       tin_quantized_mesh(t, z, x, y, water => NULL, metadata => false) = p AS none_is_none,
       tin_quantized_mesh(t, z, x, y, water => (SELECT ST_Transform(g, 4326) FROM qm_water)) = w AS degrees_same,
       length(tin_quantized_mesh(t, z, x, y, water => 'POLYGON EMPTY')) - length(p) AS empty_water_bytes,
       convert_from(substr(m, length(p) + 10), 'UTF8')::json->'available'->0 AS metadata_next_zoom
FROM terrain, k,
     LATERAL (SELECT tin_quantized_mesh(t, z, x, y) AS p, tin_quantized_mesh(t, z, x, y, water => (SELECT g FROM qm_water)) AS w,
                     tin_quantized_mesh(t, z, x, y, metadata => true) AS m) q
ORDER BY z;
SELECT tin_quantized_mesh_layer(t, normals => true, water => true, metadata => true)->'extensions' AS all_three,
       tin_quantized_mesh_layer(t, metadata => true)->'extensions' AS metadata_only,
       (tin_quantized_mesh_layer(t, metadata => true)->'available')::jsonb = (tin_quantized_mesh_layer(t)->'available')::jsonb AS same_available
FROM terrain;
-- bad input, one per line
SELECT try($$SELECT tin_quantized_mesh(t, 25, 0, 0) FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, -1, 0, 0) FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 3, 16, 0) FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 3, 0, 8) FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 3, -1, 0) FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 9, 3, 0, 0) FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 0, 0, 0, fill => 'NaN') FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 0, 0, 0, fill => 'Infinity') FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(tin_from_points('MULTIPOINT Z (0 0 1, 10 0 2, 0 10 3, 10 10 4)'::geometry, 1.0, 1), 0, 0, 0)$$);
SELECT try($$SELECT tin_quantized_mesh_layer(tin_from_points('MULTIPOINT Z (0 0 1, 10 0 2, 0 10 3, 10 10 4)'::geometry, 1.0, 1))$$);
SELECT try($$SELECT tin_quantized_mesh(t, 12, 2178, 2880, water => 'LINESTRING(0 0, 1 1)') FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 12, 2178, 2880, water => 'POLYGON((0 0, 1 0, 1 1, 0 0))') FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 12, 2178, 2880, water => 'SRID=4326;GEOMETRYCOLLECTION(POLYGON((0 0, 1 0, 1 1, 0 0)), POINT(0 0))') FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 12, 2178, 2880, water => 'SRID=4326;POLYGON((0 0, 1e300 0, 1 1, 0 0))') FROM terrain$$);
SELECT try($$SELECT tin_quantized_mesh(t, 12, 2178, 2880, water => 'SRID=32616;POLYGON((0 0, 1e30 0, 1 1e30, 0 0))') FROM terrain$$);
DROP TABLE qm_layer, qm_water;
