-- tinmerge 0.23.1 -> 0.23.2. Stored values read and answer as before; no
-- function is added or removed. tin_overviews makes every overview layer
-- cover all the table's own layer covers: an overview pixel with no data
-- under it but data under a neighbour takes the mean of the data under
-- the 3 x 3 pixels around it (tin::cover), and the tiles on an overview's
-- frame are grown by a pixel where the table's outer pixel centres lie
-- past the overview's (tin::tiles::pad_samples). Its comment says so.
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
COMMENT ON FUNCTION tin_overviews(regclass, float8, int, name, int, int, int, boolean) IS
'Builds one terrain from zoom 0 to the finest as a pyramid of tiled terrains: the table of raster tiles (factor 1) and each overview PostGIS lists for its raster column in raster_overviews (raster2pgsql -l 4,16,64, ST_CreateOverview), each built as tin_tiles_from_table(overview, tolerance * factor, levels, ...) builds it (an overview of factor f, its pixels f times larger, with f times the tolerance: the same error for its pixel size) (tx, ty in that layer''s grid of tiles; seams agree at every level), except that an overview pixel left nodata by PostGIS''s resampling takes the mean of the table''s valid pixels under it, or when there are none under it, of those under it and its eight neighbours, and the tiles on an overview''s frame are grown by a pixel (copies of their outer pixels) where the table''s outer pixel centres lie past the overview''s, so every layer covers all the table''s layer covers (an overview reaching past the data''s edge by up to about two of its pixels), each row carrying the zooms its layer serves (minzoom..maxzoom): a zoom is served by the coarsest layer whose pixels are no larger than the detail Cesium expects of it (a tile of zoom z is 65 x 65 heights, 180 / 2^z / 64 degrees apart), the finest layer up to zoom 24, the coarsest from 0; so a tile reads the tins of one layer only, at most 2 x 2 of them when the tiles are 128 pixels a side or more; a layer whose pixels are no coarser than the next finer one''s gives no rows. Serve a tile from the rows with z BETWEEN minzoom AND maxzoom whose extent meets it (docs/serving.md). slice, slices and fill_gaps as for tin_tiles_from_table, for every layer. The layers must share the table''s SRID (22023), which must be set (the zooms are measured in degrees).';
