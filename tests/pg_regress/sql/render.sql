-- Pictures: tin_as_svg and tin_as_gltf on the DEM's tin (table terrain from
-- 00_setup), checked against what the tin says of itself and PostGIS.
SET extra_float_digits = 0;

-- one <polygon> per triangle, ids 0..n-1, at every level
SELECT l, (SELECT count(*) FROM regexp_matches(tin_as_svg(t, l), '<polygon data-t="', 'g')) = tin_num_triangles(t, l) AS every_triangle
FROM terrain, generate_series(0, 4) l ORDER BY l;
-- NULL level = finest; width sets the picture's size
SELECT tin_as_svg(t) = tin_as_svg(t, 4) AS null_is_finest,
       substring(tin_as_svg(t, 0, width => 300) FROM '<svg [^>]*width="([0-9]+)"') AS width
FROM terrain;
-- values: the triangles with the smallest and largest mean slope get the
-- two ends of the ramp, triangles without a value are grey
WITH s AS (SELECT s.triangle, s.mean FROM terrain, dem, tin_raster_stats(t, ST_Slope(dem.rast, 1, '32BF', 'DEGREES'), 0) s),
     svg AS (SELECT tin_as_svg(t, 0, triangles => (SELECT array_agg(triangle) FROM s WHERE triangle % 2 = 0),
                               vals => (SELECT array_agg(mean) FROM s WHERE triangle % 2 = 0)) AS doc FROM terrain)
SELECT (SELECT count(*) FROM regexp_matches(doc, 'fill="#e1e1e1"', 'g'))
         = (SELECT tin_num_triangles(t, 0) FROM terrain) - (SELECT count(mean) FROM s WHERE triangle % 2 = 0) AS grey_without_value,
       doc LIKE '%data-t="' || (SELECT triangle FROM s WHERE triangle % 2 = 0 ORDER BY mean LIMIT 1) || '" points="%" fill="#440154"%' AS lowest_is_first_colour,
       doc LIKE '%data-t="' || (SELECT triangle FROM s WHERE triangle % 2 = 0 ORDER BY mean DESC LIMIT 1) || '" points="%" fill="#fde725"%' AS highest_is_last_colour
FROM svg;
-- classes from an area merge, the polygon on top, legend in order
WITH b AS (SELECT ST_Buffer(ST_Centroid(tin_envelope(t)), 3000) AS g FROM terrain),
     a AS (SELECT array_agg(x.triangle) AS ids, array_agg(x.relation) AS rel FROM terrain, b, tin_area_triangles(t, b.g, 1) x),
     svg AS (SELECT tin_as_svg(t, 1, triangles => a.ids, classes => a.rel, features => b.g, legend => 'relation') AS doc FROM terrain, a, b)
SELECT doc LIKE '%class="features"><path d="M%' AS polygon_drawn,
       substring(doc FROM '<g class="legend".*') ~ 'relation.*inside.*boundary|relation.*boundary.*inside' AS legend_lists_classes,
       xml_is_well_formed_document(doc) AS well_formed
FROM svg;

-- glTF: magic, version, length as written; vertex and index counts as the
-- level has; the centre in the extras
WITH g AS (SELECT t, tin_as_gltf(t, 2) AS glb FROM terrain),
     j AS (SELECT t, glb, convert_from(substring(glb FROM 21 FOR
             (get_byte(glb, 12) + get_byte(glb, 13) * 256 + get_byte(glb, 14) * 65536)), 'UTF8')::jsonb AS doc FROM g)
SELECT substring(glb FROM 1 FOR 4) = 'glTF'::bytea AS magic,
       get_byte(glb, 4) AS version,
       get_byte(glb, 8) + get_byte(glb, 9) * 256 + get_byte(glb, 10) * 65536 + get_byte(glb, 11) * 16777216 = octet_length(glb) AS length_ok,
       (doc->'accessors'->((doc->'meshes'->0->'primitives'->0->'attributes'->>'POSITION')::int)->>'count')::int = tin_num_vertices(t, 2) AS vertices,
       (doc->'accessors'->((doc->'meshes'->0->'primitives'->0->>'indices')::int)->>'count')::int = 3 * tin_num_triangles(t, 2) AS indices,
       doc->'nodes'->0->'extras'->>'srid' AS srid,
       abs((doc->'nodes'->0->'extras'->'origin'->>0)::float8 - ST_X(ST_Centroid(tin_envelope(t)))) < 1e-6 AS origin_x
FROM j;
-- with a texture: an image, texture coordinates, no vertex colours
WITH j AS (SELECT convert_from(substring(glb FROM 21 FOR (get_byte(glb, 12) + get_byte(glb, 13) * 256 + get_byte(glb, 14) * 65536)), 'UTF8')::jsonb AS doc
           FROM (SELECT tin_as_gltf(t, 1, ST_HillShade(dem.rast)) AS glb FROM terrain, dem) g)
SELECT doc->'images'->0->>'mimeType' AS image, doc->'meshes'->0->'primitives'->0->'attributes' ? 'TEXCOORD_0' AS uv,
       doc->'meshes'->0->'primitives'->0->'attributes' ? 'COLOR_0' AS colours
FROM j;

-- NULLs and bad arguments
SELECT tin_as_svg(NULL) IS NULL AS svg_null, tin_as_gltf(NULL) IS NULL AS gltf_null;
SELECT try($$SELECT tin_as_svg(t, 5) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, width => 0) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, width => 100000) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, triangles => ARRAY[0, 1], vals => ARRAY[1.0]) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, triangles => ARRAY[0, 100000], vals => ARRAY[1.0, 2.0]) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, triangles => ARRAY[3, 3], vals => ARRAY[1.0, 2.0]) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, triangles => ARRAY[3, NULL], vals => ARRAY[1.0, 2.0]) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, vals => ARRAY[1.0]) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, triangles => ARRAY[1], vals => ARRAY[1.0], classes => ARRAY['a']) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, triangles => (SELECT array_agg(i) FROM generate_series(0, 20) i), classes => (SELECT array_agg('c' || i) FROM generate_series(0, 20) i)) FROM terrain$$);
SELECT try($$SELECT tin_as_svg(t, 0, features => 'SRID=4326;POINT(0 0)'::geometry) FROM terrain$$);
SELECT try($$SELECT tin_as_gltf(t, 9) FROM terrain$$);
SELECT try($$SELECT tin_as_gltf(t, 0, z_factor => 0) FROM terrain$$);
SELECT try($$SELECT tin_as_gltf(t, 0, z_factor => 'NaN') FROM terrain$$);
SELECT try($$SELECT tin_as_gltf(t, 0, rast) FROM terrain, dem_geo$$);
SELECT try($$SELECT tin_as_gltf(t, 0, ST_SetSkew(rast, 1, 0)) FROM terrain, dem$$);
SELECT try($$SELECT tin_as_gltf(t, 0, ST_AddBand(rast, rast)) FROM terrain, dem$$);
SELECT try($$SELECT tin_as_gltf(t, 0, ST_MakeEmptyRaster(9000, 10, 0, 0, 1, -1, 0, 0, 32616)) FROM terrain$$);
SELECT try($$SELECT tin_as_gltf(t, 0, ST_AddBand(ST_MakeEmptyRaster(9000, 10, 0, 0, 1, -1, 0, 0, 32616), '8BUI'::text, 7)) FROM terrain$$);
SELECT try($$SELECT tin_as_gltf(t, 0, ST_SetSRID(rast, 0)) FROM terrain, dem$$);
