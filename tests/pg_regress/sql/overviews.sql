-- tin_overviews: a table of raster tiles and its PostGIS overviews built as
-- one pyramid. window_tiles is the DEM window as 100 x 100 tiles (4 x 4);
-- ST_CreateOverview adds factors 2 (2 x 2 tiles) and 4 (one tile).
SET client_min_messages = warning;
SELECT AddRasterConstraints('window_tiles'::name, 'rast'::name) AS constrained;
SELECT ST_CreateOverview('window_tiles'::regclass, 'rast', 2) AS o2,
       ST_CreateOverview('window_tiles'::regclass, 'rast', 4) AS o4;
CREATE TABLE pyramid AS SELECT * FROM tin_overviews('window_tiles', 2.0, 3);
-- one layer per table, coarser pixels serving lower zooms, the zooms 0..24
-- each served by exactly one layer
SELECT factor, minzoom, maxzoom, count(*) AS tins, min(tx) AS tx0, max(tx) AS tx1, min(ty) AS ty0, max(ty) AS ty1
FROM pyramid GROUP BY 1, 2, 3 ORDER BY 1;
SELECT count(*) AS zooms, bool_and(n = 1) AS one_layer_each
FROM (SELECT z, count(DISTINCT factor) AS n FROM generate_series(0, 24) z LEFT JOIN pyramid ON z BETWEEN minzoom AND maxzoom GROUP BY z) s;
-- the rule, from PostGIS's own numbers: a layer serves a zoom when its
-- pixels (in degrees) are no larger than the zoom's 65 x 65 heightmap
-- spacing, 180 / 2^z / 64; the next coarser layer's are larger
WITH px AS (SELECT f, greatest((ST_XMax(e) - ST_XMin(e)) / w, (ST_YMax(e) - ST_YMin(e)) / h) AS deg
            FROM (VALUES (1, 'window_tiles'), (2, 'o_2_window_tiles'), (4, 'o_4_window_tiles')) v(f, tab),
                 LATERAL (SELECT ST_Transform(ST_Segmentize(ST_Envelope(ST_Union(ST_Envelope(rast))), 500), 4326) AS e,
                                 (ST_XMax(ST_Union(ST_Envelope(rast))) - ST_XMin(ST_Union(ST_Envelope(rast)))) / max(abs(ST_ScaleX(rast))) AS w,
                                 (ST_YMax(ST_Union(ST_Envelope(rast))) - ST_YMin(ST_Union(ST_Envelope(rast)))) / max(abs(ST_ScaleY(rast))) AS h
                          FROM (SELECT rast FROM window_tiles WHERE tab = 'window_tiles'
                                UNION ALL SELECT rast FROM o_2_window_tiles WHERE tab = 'o_2_window_tiles'
                                UNION ALL SELECT rast FROM o_4_window_tiles WHERE tab = 'o_4_window_tiles') r) m)
SELECT bool_and(CASE WHEN p.factor = 1 THEN true ELSE px.deg <= 180 / 2 ^ z / 64 END
                AND coalesce((SELECT c.deg > 180 / 2 ^ z / 64 FROM px c WHERE c.f = p.factor * 2), true)) AS rule_holds
FROM generate_series(0, 24) z JOIN (SELECT DISTINCT factor, minzoom, maxzoom FROM pyramid) p ON z BETWEEN minzoom AND maxzoom
JOIN px ON px.f = p.factor;
-- each layer is tin_tiles_from_table of its table with the tolerance times
-- its factor, byte for byte, but for the tiles of an overview with nodata
-- pixels over data of the table (given it) and those on its frame (grown
-- to reach the table's outer pixel centres, as every overview tile is
-- here): below
SELECT p.factor, count(*) AS tins, count(*) FILTER (WHERE p.t::text = f.t::text) AS identical
FROM pyramid p JOIN (SELECT 1 AS factor, * FROM tin_tiles_from_table('window_tiles', 2.0, 3)
                     UNION ALL SELECT 2, * FROM tin_tiles_from_table('o_2_window_tiles', 4.0, 3)
                     UNION ALL SELECT 4, * FROM tin_tiles_from_table('o_4_window_tiles', 8.0, 3)) f USING (factor, tx, ty)
GROUP BY 1 ORDER BY 1;
-- slices: every layer's rows of slice k of 2, together the whole pyramid
SELECT count(*) AS rows, count(*) FILTER (WHERE s.t::text = p.t::text) AS identical
FROM pyramid p FULL JOIN (SELECT * FROM tin_overviews('window_tiles', 2.0, 3, slice => 0, slices => 2)
                          UNION ALL SELECT * FROM tin_overviews('window_tiles', 2.0, 3, slice => 1, slices => 2)) s USING (factor, tx, ty);
-- a table without overviews is one layer serving every zoom
CREATE TABLE lone_tiles AS SELECT rast FROM window_tiles;
SELECT factor, minzoom, maxzoom, count(*) FROM tin_overviews('lone_tiles', 2.0, 2) GROUP BY 1, 2, 3;
-- overviews cover the data, exactly. Oracle, PostGIS: each layer's
-- domain (the union of its triangles) against the base layer's, built the
-- same way. On the UTM DEM (nodata along its rotated border) and the
-- geographic one (data to its frame), as 128-px tiles with factors 2 and
-- 4, over the hull (fill_gaps) and over the valid squares (the default).
-- Two gaps close: PostGIS's nearest neighbour leaves an overview pixel
-- nodata where the finer pixel it takes is nodata, though others under it
-- hold data (tin_overviews gives such a pixel the mean of those, and any
-- pixel beside one the mean of those around it); and an overview's outer pixel centres
-- lie (f - 1) / 2 base pixels inside the base's (tin_overviews grows the
-- frame's tiles by a pixel, copies of their outer ones). What the base
-- covers and an overview does not: none (the share below 1e-9, for the
-- rounding of the two lattices' coordinates). The overviews built as they
-- are, by tin_tiles_from_table, leave a ring, shown with its depth (in
-- base pixels); and how far each layer reaches past the base's domain.
CREATE FUNCTION pg_temp.cover_check(dem regclass, fill boolean)
RETURNS TABLE(how text, factor int, uncovered_share numeric, covered boolean, deepest_px numeric, reach_px numeric)
LANGUAGE plpgsql AS $$
DECLARE px float8;
BEGIN
  EXECUTE format('SELECT ST_PixelWidth(rast) FROM %s', dem) INTO px;
  EXECUTE format('CREATE TEMP TABLE cover_tiles AS SELECT ST_Tile(rast, 128, 128) AS rast FROM %s', dem);
  PERFORM AddRasterConstraints('cover_tiles'::name, 'rast'::name);
  PERFORM ST_CreateOverview('cover_tiles'::regclass, 'rast', 2), ST_CreateOverview('cover_tiles'::regclass, 'rast', 4);
  CREATE TEMP TABLE cover_dom AS
    SELECT 'tin_overviews' AS how, p.factor, ST_Union(geom) AS g
    FROM tin_overviews('cover_tiles', 4.0, 2, fill_gaps => fill) p, tin_triangles(p.t, 0) GROUP BY p.factor
    UNION ALL SELECT 'tin_tiles_from_table', 2, ST_Union(geom) FROM tin_tiles_from_table('o_2_cover_tiles', 8.0, 2, fill_gaps => fill) f, tin_triangles(f.t, 0)
    UNION ALL SELECT 'tin_tiles_from_table', 4, ST_Union(geom) FROM tin_tiles_from_table('o_4_cover_tiles', 16.0, 2, fill_gaps => fill) f, tin_triangles(f.t, 0);
  RETURN QUERY
    SELECT s.how, s.factor, round(s.share::numeric, 4), s.share < 1e-9,
           round(coalesce(s.deepest, 0)::numeric, 2), round(s.reach::numeric, 2)
    FROM (SELECT d.how, d.factor, ST_Area(ST_Difference(b.g, d.g)) / ST_Area(b.g) AS share,
                 (SELECT max(ST_Distance((q).geom, ST_Boundary(b.g))) / px
                  FROM ST_DumpPoints(ST_Difference(b.g, d.g)) q) AS deepest,
                 (SELECT max(ST_Distance((q).geom, b.g)) / px FROM ST_DumpPoints(d.g) q) AS reach
          FROM cover_dom d, cover_dom b WHERE b.factor = 1 AND d.factor > 1) s
    ORDER BY 1 DESC, 2;
  DROP TABLE cover_dom;
  PERFORM DropOverviewConstraints('o_2_cover_tiles'::name, 'rast'::name), DropOverviewConstraints('o_4_cover_tiles'::name, 'rast'::name);
  DROP TABLE o_2_cover_tiles, o_4_cover_tiles;
  PERFORM DropRasterConstraints('cover_tiles'::name, 'rast'::name);
  DROP TABLE cover_tiles;
END $$;
SELECT 'utm' AS dem, 'hull' AS over, * FROM pg_temp.cover_check('dem', true);
SELECT 'utm' AS dem, 'valid squares' AS over, * FROM pg_temp.cover_check('dem', false);
SELECT 'geographic' AS dem, 'hull' AS over, * FROM pg_temp.cover_check('dem_geo', true);
SELECT 'geographic' AS dem, 'valid squares' AS over, * FROM pg_temp.cover_check('dem_geo', false);
-- errors
CREATE TABLE nosrid_tiles AS SELECT ST_SetSRID(rast, 0) AS rast FROM window_tiles;
SELECT count(*) FROM tin_overviews('nosrid_tiles', 2.0, 2);
SELECT count(*) FROM tin_overviews('window_tiles', 2.0, 2, rast_column => 'nope');
SELECT count(*) FROM tin_overviews('window_tiles', 2.0, 2, slice => 2, slices => 2);
DROP TABLE pyramid, lone_tiles, nosrid_tiles;
SELECT DropOverviewConstraints('o_2_window_tiles'::name, 'rast'::name), DropOverviewConstraints('o_4_window_tiles'::name, 'rast'::name);
DROP TABLE o_2_window_tiles, o_4_window_tiles;
SELECT DropRasterConstraints('window_tiles'::name, 'rast'::name) AS unconstrained;
