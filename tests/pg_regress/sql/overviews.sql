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
-- pixels over data of the table (given it: below)
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
-- overviews cover the data: the UTM DEM (nodata along its rotated
-- border) as 128-px tiles, with factors 2 and 4. PostGIS's nearest
-- neighbour leaves an overview pixel nodata where the finer pixel it takes
-- is nodata, though others under it hold data; tin_overviews gives such a
-- pixel the mean of those. Oracle, PostGIS: each layer's domain (the union
-- of its triangles) against the base layer's. A tin covers its samples'
-- hull, so an overview's domain stops at its outer pixel centres, up to
-- (f - 1) / 2 base pixels (of 90 m) short of the base's: what the base
-- covers and an overview does not must lie within half an overview pixel
-- (f / 2 base pixels) of the base domain's edge. The same overviews built
-- by tin_tiles_from_table leave a ring deeper than that.
CREATE TABLE cover_tiles AS SELECT ST_Tile(rast, 128, 128) AS rast FROM dem;
SELECT AddRasterConstraints('cover_tiles'::name, 'rast'::name) AS constrained;
SELECT ST_CreateOverview('cover_tiles'::regclass, 'rast', 2) AS o2,
       ST_CreateOverview('cover_tiles'::regclass, 'rast', 4) AS o4;
CREATE TABLE cover_pyr AS SELECT * FROM tin_overviews('cover_tiles', 4.0, 2);
CREATE TABLE cover_dom AS
  SELECT 'tin_overviews' AS how, factor, ST_Union(geom) AS g FROM cover_pyr, tin_triangles(t, 0) GROUP BY factor
  UNION ALL SELECT 'tin_tiles_from_table', 2, ST_Union(geom) FROM tin_tiles_from_table('o_2_cover_tiles', 8.0, 2), tin_triangles(t, 0)
  UNION ALL SELECT 'tin_tiles_from_table', 4, ST_Union(geom) FROM tin_tiles_from_table('o_4_cover_tiles', 16.0, 2), tin_triangles(t, 0);
SELECT how, factor, round(share::numeric, 4) AS uncovered_share, round(deepest::numeric, 2) AS deepest_px, deepest <= factor / 2.0 AS within_half_an_overview_pixel
FROM (SELECT d.how, d.factor, ST_Area(ST_Difference(b.g, d.g)) / ST_Area(b.g) AS share,
             (SELECT max(ST_Distance((p).geom, ST_Boundary(b.g))) / 90 FROM ST_DumpPoints(ST_Difference(b.g, d.g)) p) AS deepest
      FROM cover_dom d, cover_dom b WHERE b.factor = 1 AND d.factor > 1) s
ORDER BY 1 DESC, 2;
DROP TABLE cover_pyr, cover_dom;
SELECT DropOverviewConstraints('o_2_cover_tiles'::name, 'rast'::name), DropOverviewConstraints('o_4_cover_tiles'::name, 'rast'::name);
DROP TABLE o_2_cover_tiles, o_4_cover_tiles;
SELECT DropRasterConstraints('cover_tiles'::name, 'rast'::name) AS unconstrained;
DROP TABLE cover_tiles;
-- errors
CREATE TABLE nosrid_tiles AS SELECT ST_SetSRID(rast, 0) AS rast FROM window_tiles;
SELECT count(*) FROM tin_overviews('nosrid_tiles', 2.0, 2);
SELECT count(*) FROM tin_overviews('window_tiles', 2.0, 2, rast_column => 'nope');
SELECT count(*) FROM tin_overviews('window_tiles', 2.0, 2, slice => 2, slices => 2);
DROP TABLE pyramid, lone_tiles, nosrid_tiles;
SELECT DropOverviewConstraints('o_2_window_tiles'::name, 'rast'::name), DropOverviewConstraints('o_4_window_tiles'::name, 'rast'::name);
DROP TABLE o_2_window_tiles, o_4_window_tiles;
SELECT DropRasterConstraints('window_tiles'::name, 'rast'::name) AS unconstrained;
