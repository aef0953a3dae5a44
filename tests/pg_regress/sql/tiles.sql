-- Tiled terrains (docs/scaling.md): a window of the DEM without nodata,
-- loaded by the runner both whole (dem_window) and as raster2pgsql -t
-- 100x100 tiles (window_tiles, 16 tiles). Each tile's tin is built from its
-- pixels plus the first column and row of its right and lower neighbours
-- (one shared column/row of samples per seam) with keep_border => true.
SET extra_float_digits = 0;
SELECT count(*) AS tiles, sum(ST_Width(rast) * ST_Height(rast)) AS pixels FROM window_tiles;

-- the build pattern: tile extent grown by one pixel right and down, filled
-- from the neighbours, one tin per tile
CREATE TABLE tin_tiles AS
SELECT a.rid AS id,
       tin_from_raster(ST_Clip(ST_Union(b.rast), e.env), 2.0, 3, keep_border => true, fill_gaps => true) AS t
FROM window_tiles a
CROSS JOIN LATERAL (SELECT ST_MakeEnvelope(
    ST_UpperLeftX(a.rast), ST_UpperLeftY(a.rast) + (ST_Height(a.rast) + 1) * ST_ScaleY(a.rast),
    ST_UpperLeftX(a.rast) + (ST_Width(a.rast) + 1) * ST_ScaleX(a.rast), ST_UpperLeftY(a.rast),
    ST_SRID(a.rast)) AS env) e
JOIN window_tiles b ON b.rast && e.env
GROUP BY a.rid, e.env;
CREATE INDEX tin_tiles_envelope ON tin_tiles USING gist (tin_envelope(t));
ANALYZE tin_tiles;
CREATE TABLE window_tin AS SELECT tin_from_raster(rast, 2.0, 3) AS t FROM dem_window;

-- the tiles cover the window's pixel centres exactly, envelopes meeting on
-- the seams (shared columns/rows of pixel centres)
SELECT ST_Equals(ST_Union(tin_envelope(t)), (SELECT tin_envelope(t) FROM window_tin)) AS tiles_cover_window,
       sum(ST_Area(tin_envelope(t))) = ST_Area((SELECT tin_envelope(t) FROM window_tin)) AS no_overlap
FROM tin_tiles;

-- the index answers the join predicate
SET enable_seqscan = off;
EXPLAIN (COSTS OFF)
SELECT id FROM tin_tiles WHERE tin_envelope(t) && 'SRID=32616;POINT(745000 4055000)'::geometry;
RESET enable_seqscan;

-- seam samples: pixel centres of the window on the shared columns and rows
-- (and midpoints between consecutive ones along the seam). Every tile
-- covering one answers it, at every level, with the same height (up to
-- rounding: each tile interpolates the seam from its own triangle); at a
-- sample that height is within the level's tolerance of the pixel value
-- (ST_Value is the oracle), at a midpoint of the mean of the two pixel
-- values (the surface is straight between consecutive seam samples).
CREATE TABLE tile_seam AS
WITH c AS (
  SELECT p.x, p.y, p.val, p.geom FROM dem_window, ST_PixelAsCentroids(rast) p
  WHERE (p.x > 1 AND (p.x - 1) % 100 = 0) OR (p.y > 1 AND (p.y - 1) % 100 = 0)
)
SELECT c.geom, c.val AS expect FROM c
UNION ALL
SELECT ST_LineInterpolatePoint(ST_MakeLine(c.geom, n.geom), 0.5), (c.val + n.val) / 2
FROM c JOIN c n ON (n.x = c.x AND n.y = c.y + 1 AND (c.x - 1) % 100 = 0)
                OR (n.y = c.y AND n.x = c.x + 1 AND (c.y - 1) % 100 = 0);
WITH h AS (
  SELECT s.geom, s.expect, l, k.id, tin_height(k.t, s.geom, l) AS z
  FROM tile_seam s JOIN tin_tiles k ON tin_envelope(k.t) && s.geom, generate_series(0, 2) l
), per AS (
  SELECT geom, expect, l, count(*) AS tiles, count(z) AS answered, max(z) - min(z) AS spread, max(abs(z - expect)) AS off
  FROM h GROUP BY geom, expect, l
)
SELECT l AS level, count(*) AS seam_points, min(tiles) AS min_tiles, max(tiles) AS max_tiles,
       sum(tiles - answered) AS unanswered, count(*) FILTER (WHERE spread > 1e-9) AS tiles_disagree,
       count(*) FILTER (WHERE off > 2.0 * 2 ^ (2 - l) + 1e-9) AS beyond_tolerance
FROM per GROUP BY l ORDER BY l;

-- the tiles against one tin of the window: both built by build engine 2
-- (after 0.27.0; the tiles by the old engine before, 0.7 to 1.1); 1.0 at
-- every level
-- (until 0.7.0 keep_border made every border pixel a vertex of
-- every level: fans of slivers at the coarse levels that persisted into
-- the finest; on the 3.1 m tiles of scripts/bench-big.sh, 3.6x the
-- triangles of free builds and draped lines up to 2.8x too long)
SELECT l AS level, round((SELECT sum(tin_num_triangles(t, l)) FROM tin_tiles)::numeric / tin_num_triangles(w.t, l), 1) AS tiles_over_single
FROM window_tin w, generate_series(0, 2) l ORDER BY l;

-- points against the tile table: the join through the index, one row per
-- point kept by DISTINCT ON (on a seam either tile gives the same height). Every pixel centre of the
-- window in a sample of ~1/7 gets a height from the tiles and from the
-- single tin, each within the level's tolerance of the pixel value.
CREATE TABLE tile_pts AS
SELECT row_number() OVER () AS id, p.geom, p.val
FROM dem_window, ST_PixelAsCentroids(rast) p WHERE (p.x + 3 * p.y) % 7 = 0;
WITH tiled AS (
  SELECT DISTINCT ON (p.id, l) p.id, p.val, l, tin_height(k.t, p.geom, l) AS z
  FROM tile_pts p JOIN tin_tiles k ON tin_envelope(k.t) && p.geom, generate_series(0, 2) l
  ORDER BY p.id, l, k.id
), single AS (
  SELECT p.id, l, tin_height(w.t, p.geom, l) AS z FROM tile_pts p, window_tin w, generate_series(0, 2) l
)
SELECT tiled.l AS level, count(*) AS points, count(tiled.z) AS tiled_answers, count(single.z) AS single_answers,
       count(*) FILTER (WHERE abs(tiled.z - tiled.val) > 2.0 * 2 ^ (2 - tiled.l) + 1e-9) AS tiled_beyond_tolerance,
       count(*) FILTER (WHERE abs(single.z - tiled.val) > 2.0 * 2 ^ (2 - tiled.l) + 1e-9) AS single_beyond_tolerance
FROM tiled JOIN single USING (id, l) GROUP BY tiled.l ORDER BY 1;

-- lines against the tile table: each contour cut by the tile envelopes with
-- PostGIS, each piece merged with its tile, then summed per contour. Planar
-- lengths equal the single tin's (and ST_Length of the contour in the
-- window); draped pieces meet on the seams at the same height.
CREATE TABLE tile_contours AS
SELECT c.id, ST_Intersection(c.geom, w.env) AS geom
FROM contours c, (SELECT tin_envelope(t) AS env FROM window_tin) w
WHERE ST_Intersects(c.geom, w.env) AND ST_Length(ST_Intersection(c.geom, w.env)) > 0;
CREATE TABLE tile_pieces AS
SELECT c.id AS contour, k.id AS tile, k.t,
       ST_CollectionExtract(ST_Intersection(c.geom, tin_envelope(k.t)), 2) AS geom
FROM tile_contours c JOIN tin_tiles k ON tin_envelope(k.t) && c.geom;
DELETE FROM tile_pieces WHERE ST_IsEmpty(geom);
-- the oracles below cut pieces by their tile's triangles (level 1 and the
-- finest), made once by tin_triangles and found through a GiST index
CREATE TEMP TABLE tile_tris AS
SELECT k.id AS tile, l AS level, tr.geom
FROM tin_tiles k, generate_series(1, 2) l, tin_triangles(k.t, l) tr;
CREATE INDEX ON tile_tris USING gist (geom);
ANALYZE tile_tris;
WITH tiled AS (
  SELECT p.contour AS id, sum(s.length2d) AS len2d, sum(s.length3d) AS len3d
  FROM tile_pieces p, tin_line_segments(p.t, p.geom, 1) s GROUP BY p.contour
), single AS (
  SELECT c.id, sum(s.length2d) AS len2d, sum(s.length3d) AS len3d
  FROM tile_contours c, window_tin w, tin_line_segments(w.t, c.geom, 1) s GROUP BY c.id
), oracle AS (
  -- PostGIS: each piece cut by every triangle of its tile (level 1), each
  -- segment's rise from the plane of its triangle (plane_z)
  SELECT p.contour AS id,
         sum(sqrt(ST_Length(g.geom) ^ 2 + (plane_z(tr.geom, ST_EndPoint(g.geom)) - plane_z(tr.geom, ST_StartPoint(g.geom))) ^ 2)) AS len3d
  FROM tile_pieces p JOIN tile_tris tr ON tr.tile = p.tile AND tr.level = 1 AND tr.geom && p.geom,
       ST_DumpSegments(ST_CollectionExtract(ST_Intersection(p.geom, tr.geom), 2)) g
  GROUP BY p.contour
)
SELECT count(*) AS contours,
       count(*) FILTER (WHERE abs(tiled.len2d - single.len2d) > 1e-9 * single.len2d) AS len2d_differ,
       count(*) FILTER (WHERE abs(tiled.len2d - ST_Length(c.geom)) > 1e-9 * tiled.len2d) AS len2d_not_st_length,
       count(*) FILTER (WHERE abs(tiled.len3d - oracle.len3d) > 1e-6 * oracle.len3d) AS len3d_not_postgis
FROM tiled JOIN single USING (id) JOIN oracle USING (id) JOIN tile_contours c USING (id);
WITH ends AS (
  SELECT p.contour, p.tile, e.geom
  FROM tile_pieces p, ST_Dump(tin_drape(p.t, p.geom, 1)) d,
       LATERAL (VALUES (ST_StartPoint(d.geom)), (ST_EndPoint(d.geom))) e(geom)
)
SELECT count(*) AS seam_crossings,
       count(*) FILTER (WHERE abs(ST_Z(a.geom) - ST_Z(b.geom)) > 1e-9) AS heights_differ
FROM ends a JOIN ends b ON a.contour = b.contour AND a.tile < b.tile AND ST_DWithin(a.geom, b.geom, 1e-6);

-- areas against the tile table: contour bands cut by the tile envelopes,
-- merged per tile, summed per band. Planar areas equal the single tin's;
-- surface areas are PostGIS's: each piece cut by every triangle of its
-- tile, each part's planar area times its triangle's slope factor.
WITH wbands AS (
  SELECT b.id, ST_Intersection(b.geom, w.env) AS geom
  FROM contour_bands b, (SELECT tin_envelope(t) AS env FROM window_tin) w
  WHERE ST_Intersects(b.geom, w.env)
), tiled AS (
  SELECT b.id, sum(s.area2d) AS a2, sum(s.area3d) AS a3
  FROM wbands b JOIN tin_tiles k ON tin_envelope(k.t) && b.geom,
       tin_area_stats(k.t, ST_CollectionExtract(ST_Intersection(b.geom, tin_envelope(k.t)), 3), 1) s
  GROUP BY b.id
), single AS (
  SELECT b.id, s.area2d AS a2, s.area3d AS a3 FROM wbands b, window_tin w, tin_area_stats(w.t, b.geom, 1) s
), parts AS (
  -- each band's piece in each tile cut into parts of at most 64 vertices
  -- (ST_Subdivide: they partition it), so that each triangle is cut by a
  -- few small parts
  SELECT b.id, k.id AS tile, ST_Subdivide(ST_CollectionExtract(ST_Intersection(b.geom, tin_envelope(k.t)), 3), 64) AS geom
  FROM wbands b JOIN tin_tiles k ON tin_envelope(k.t) && b.geom
), oracle AS (
  SELECT p.id, sum(ST_Area(ST_Intersection(tr.geom, p.geom)) * slope_factor(tr.geom)) AS a3
  FROM parts p JOIN tile_tris tr ON tr.tile = p.tile AND tr.level = 1 AND tr.geom && p.geom
  GROUP BY p.id
)
SELECT count(*) AS bands,
       count(*) FILTER (WHERE abs(tiled.a2 - single.a2) > 1e-9 * single.a2) AS area2d_differ,
       count(*) FILTER (WHERE abs(tiled.a3 - oracle.a3) > 1e-6 * oracle.a3) AS area3d_not_postgis
FROM tiled JOIN single USING (id) JOIN oracle USING (id);

-- volumes against the tile table: cut and fill of each band against the
-- window's median height, per tile piece, summed. The tiles and the single
-- tin are different surfaces within 2 m of every pixel, so their net
-- volumes (cut - fill) differ by less than 2 x 2 m x the band's area; the
-- tiles' net volume is PostGIS's: each piece cut by every triangle of its
-- tile's finest level (tin_volume's level here), each part's area times its
-- triangle's plane height at its centroid above the base (the integral of
-- a linear function over a polygon).
WITH wbands AS (
  SELECT b.id, ST_Intersection(b.geom, w.env) AS geom
  FROM contour_bands b, (SELECT tin_envelope(t) AS env FROM window_tin) w
  WHERE ST_Intersects(b.geom, w.env)
), base AS (
  SELECT percentile_cont(0.5) WITHIN GROUP (ORDER BY val) AS z FROM dem_window, ST_PixelAsPoints(rast) p
), tiled AS (
  SELECT b.id, sum(v.cut) AS cut, sum(v.fill) AS fill
  FROM wbands b JOIN tin_tiles k ON tin_envelope(k.t) && b.geom, base,
       tin_volume(k.t, ST_CollectionExtract(ST_Intersection(b.geom, tin_envelope(k.t)), 3), base.z) v
  GROUP BY b.id
), single AS (
  SELECT b.id, v.cut, v.fill, ST_Area(b.geom) AS area FROM wbands b, window_tin w, base, tin_volume(w.t, b.geom, base.z) v
), parts AS (
  -- (every third band: the finest level's triangles are many)
  SELECT b.id, k.id AS tile, ST_Subdivide(ST_CollectionExtract(ST_Intersection(b.geom, tin_envelope(k.t)), 3), 64) AS geom
  FROM wbands b JOIN tin_tiles k ON tin_envelope(k.t) && b.geom WHERE b.id % 3 = 0
), oracle AS (
  SELECT p.id, sum(ST_Area(i.geom) * (plane_z(tr.geom, ST_Centroid(i.geom)) - base.z)) AS net
  FROM parts p JOIN tile_tris tr ON tr.tile = p.tile AND tr.level = 2 AND tr.geom && p.geom, base,
       LATERAL (SELECT ST_CollectionExtract(ST_Intersection(tr.geom, p.geom), 3) AS geom) i
  WHERE NOT ST_IsEmpty(i.geom)
  GROUP BY p.id
)
SELECT count(*) AS bands, count(*) FILTER (WHERE single.cut + single.fill > 0) AS with_volume,
       count(*) FILTER (WHERE abs((tiled.cut - tiled.fill) - (single.cut - single.fill)) > 2 * 2.0 * area) AS net_volume_beyond_bound,
       count(oracle.net) AS against_postgis,
       count(*) FILTER (WHERE abs((tiled.cut - tiled.fill) - oracle.net) > 1e-6 * (tiled.cut + tiled.fill) + 1e-6) AS net_volume_not_postgis
FROM tiled JOIN single USING (id) LEFT JOIN oracle USING (id);

-- drapes against the tile table: the draped pieces merged back into one
-- line per contour (ST_LineMerge joins them where they meet on a seam;
-- their heights there agree, as the seam crossings above show): as many
-- parts as the contour in the window, and its planar length
WITH draped AS (
  SELECT p.contour AS id, ST_LineMerge(ST_Collect(d.geom)) AS geom
  FROM tile_pieces p, ST_Dump(tin_drape(p.t, p.geom)) d GROUP BY p.contour
)
SELECT count(*) AS contours,
       count(*) FILTER (WHERE ST_NumGeometries(d.geom) <> ST_NumGeometries(ST_LineMerge(c.geom))) AS parts_differ,
       count(*) FILTER (WHERE abs(ST_Length(d.geom) - ST_Length(c.geom)) > 1e-6 * ST_Length(c.geom)) AS length_differs,
       bool_and(ST_Zmflag(d.geom) = 2) AS all_3d
FROM draped d JOIN tile_contours c USING (id);

-- tin_tiles: the same pattern in one call, from the window raster itself
-- (no ST_Union, no ST_Clip). Each tile covers the pixels of the tile the
-- SQL pattern built (the same envelope), the seams agree and hold the
-- pixel values, and the tiles cover the window without overlap
CREATE TABLE one_call AS SELECT tx, ty, t FROM dem_window, tin_tiles(rast, 100, 2.0, 3);
SELECT count(*) AS tiles, min(tx) AS min_tx, max(tx) AS max_tx, min(ty) AS min_ty, max(ty) AS max_ty,
       bool_and(tin_num_levels(t) = 3) AS three_levels FROM one_call;
SELECT count(*) AS matched FROM one_call o JOIN tin_tiles k ON ST_Equals(tin_envelope(o.t), tin_envelope(k.t));
-- tin_tiles' tiles hold their tolerance in the one-pixel strips along
-- their seams too (since 0.14.0: both tiles of a seam keep the seam pixels
-- a strip needs): tin_validate against the window raster, where the grid
-- segments beyond a tile's seams are its neighbours'. The SQL pattern's
-- tiles need not (a tile alone cannot put a vertex on a seam its neighbour
-- does not know of): 46 levels over before the seams were planned at
-- half the tolerance (after 0.27.0), 20 with that; none since build
-- engine 2 builds the tiles and mends a strip from inside (after 0.27.0),
-- on this window
SELECT 'tin_tiles' AS build, count(DISTINCT (o.tx, o.ty)) AS tiles, count(v.level) AS levels_over
FROM one_call o CROSS JOIN dem_window d LEFT JOIN LATERAL tin_validate(o.t, d.rast) v ON true
UNION ALL
SELECT 'keep_border per tile', count(DISTINCT k.id), count(v.level)
FROM tin_tiles k CROSS JOIN dem_window d LEFT JOIN LATERAL tin_validate(k.t, d.rast) v ON true
ORDER BY 1 DESC;
SELECT ST_Equals(ST_Union(tin_envelope(t)), (SELECT tin_envelope(t) FROM window_tin)) AS tiles_cover_window,
       sum(ST_Area(tin_envelope(t))) = ST_Area((SELECT tin_envelope(t) FROM window_tin)) AS no_overlap
FROM one_call;
WITH h AS (
  SELECT s.geom, s.expect, l, tin_height(k.t, s.geom, l) AS z
  FROM tile_seam s JOIN one_call k ON tin_envelope(k.t) && s.geom, generate_series(0, 2) l
), per AS (
  SELECT geom, expect, l, count(*) AS tiles, count(z) AS answered, max(z) - min(z) AS spread, max(abs(z - expect)) AS off
  FROM h GROUP BY geom, expect, l
)
SELECT l AS level, count(*) AS seam_points, min(tiles) AS min_tiles, max(tiles) AS max_tiles,
       sum(tiles - answered) AS unanswered, count(*) FILTER (WHERE spread > 1e-9) AS tiles_disagree,
       count(*) FILTER (WHERE off > 2.0 * 2 ^ (2 - l) + 1e-9) AS beyond_tolerance
FROM per GROUP BY l ORDER BY l;
-- raster statistics against the tile table: with half_open => true a pixel
-- centre on a tin's outer boundary counts only where the domain goes on
-- east (north) of it, as on a shared edge, so every seam centre is counted
-- by exactly one tile. The oracle: PostGIS's pixel centres of the window
-- inside the half-open envelope [xmin, xmax) x [ymin, ymax) of the single
-- tin (the window has no nodata: its domain is that rectangle). The tiles
-- and the single tin (with the flag) count exactly those, each once, with
-- the same sums; without the flag the tiles count every seam centre twice.
-- Weighted (coverage) statistics need no flag: fractions add up across
-- seams to the single tin's.
CREATE TABLE oracle_px AS
SELECT p.x, p.y, p.val
FROM dem_window d, ST_PixelAsCentroids(d.rast, 1) c, LATERAL (SELECT ST_X(c.geom) AS x, ST_Y(c.geom) AS y, c.val) p,
     (SELECT tin_envelope(t) AS e FROM window_tin) w
WHERE p.x >= ST_XMin(w.e) AND p.x < ST_XMax(w.e) AND p.y >= ST_YMin(w.e) AND p.y < ST_YMax(w.e);
WITH tiles AS (
  SELECT l, sum(s.count) AS n, sum(s.sum) AS total
  FROM one_call k, dem_window d, generate_series(0, 2) l, tin_raster_stats(k.t, d.rast, l, half_open => true) s GROUP BY l
), single AS (
  SELECT l, sum(s.count) AS n, sum(s.sum) AS total
  FROM window_tin w, dem_window d, generate_series(0, 2) l, tin_raster_stats(w.t, d.rast, l, half_open => true) s GROUP BY l
), closed AS (
  SELECT l, sum(s.count) AS n FROM one_call k, dem_window d, generate_series(0, 2) l, tin_raster_stats(k.t, d.rast, l) s GROUP BY l
), closed_single AS (
  SELECT l, sum(s.count) AS n FROM window_tin w, dem_window d, generate_series(0, 2) l, tin_raster_stats(w.t, d.rast, l) s GROUP BY l
)
SELECT t.l AS level, (SELECT count(*) FROM oracle_px) AS oracle_pixels, t.n AS tiles_half_open, s.n AS single_half_open,
       abs(t.total - (SELECT sum(val) FROM oracle_px)) < 1e-9 * abs(t.total) AS tiles_sum_is_oracle,
       abs(s.total - (SELECT sum(val) FROM oracle_px)) < 1e-9 * abs(s.total) AS single_sum_is_oracle,
       c.n - cs.n AS closed_tiles_count_seams_twice
FROM tiles t JOIN single s USING (l) JOIN closed c USING (l) JOIN closed_single cs USING (l) ORDER BY 1;
-- pixel by pixel: each oracle centre owned by one tile, the tile whose
-- half-open envelope holds it (the east / north tile on a seam)
WITH owned AS (
  SELECT ST_X(ST_PixelAsCentroid(d.rast, p.col, p.row)) AS x, ST_Y(ST_PixelAsCentroid(d.rast, p.col, p.row)) AS y,
         tin_envelope(k.t) AS e
  FROM one_call k, dem_window d, tin_raster_pixels(k.t, d.rast, 1, half_open => true) p
), per AS (SELECT x, y, count(*) AS n, bool_and(x < ST_XMax(e) AND y < ST_YMax(e)) AS east_north FROM owned GROUP BY x, y)
SELECT count(*) AS owned_pixels, count(*) FILTER (WHERE n > 1) AS owned_twice,
       count(*) FILTER (WHERE NOT east_north) AS by_the_west_or_south_tile,
       (SELECT count(*) FROM oracle_px o LEFT JOIN per p ON (p.x, p.y) = (o.x, o.y) WHERE p.x IS NULL) AS oracle_pixels_missed
FROM per;
WITH tiles AS (SELECT sum(s.sum) AS total FROM one_call k, dem_window d, tin_raster_stats(k.t, d.rast, 1, weighted => true) s),
     single AS (SELECT sum(s.sum) AS total FROM window_tin w, dem_window d, tin_raster_stats(w.t, d.rast, 1, weighted => true) s)
SELECT abs(t.total - s.total) < 1e-9 * abs(s.total) AS weighted_sums_agree FROM tiles t, single s;
DROP TABLE oracle_px;
-- bad arguments
SELECT count(*) FROM dem_window, tin_tiles(rast, 1, 2.0, 3);
SELECT count(*) FROM dem_window, tin_tiles(rast, 100, 2.0, 3, band => 2);
SELECT count(*) FROM dem_window, tin_tiles(rast, 100, -1.0, 3);

-- tin_tiles_from_table: a table of tiles (the raster2pgsql -t 100x100 table of the
-- same window): bit for bit the tins tin_tiles builds from the window
-- raster itself, tile for tile
CREATE TABLE from_table AS SELECT * FROM tin_tiles_from_table('window_tiles', 2.0, 3);
SELECT count(*) AS tiles, count(o.t) AS matched, count(*) FILTER (WHERE f.t::text = o.t::text) AS same_bytes
FROM from_table f LEFT JOIN one_call o USING (tx, ty);
-- and against the table's own pixels (PostGIS's ST_PixelAsCentroids of
-- its rasters): every valid centre within each level's tolerance on a
-- tile holding it
SELECT l AS level, count(*) AS centres, count(h.z) AS answered,
       count(*) FILTER (WHERE abs(h.z - c.val) > 2.0 * 2 ^ (2 - l) + 1e-6) AS beyond_tolerance
FROM window_tiles w, ST_PixelAsCentroids(w.rast) c, generate_series(0, 2) l,
     LATERAL (SELECT tin_height(f.t, c.geom, l) AS z FROM from_table f
              WHERE tin_envelope(f.t) && c.geom ORDER BY tin_height(f.t, c.geom, l) IS NULL LIMIT 1) h
GROUP BY l ORDER BY l;
-- ST_Tile of the whole DEM (nodata corners, last tiles narrower) in 64 x 64
-- tiles, the rows in a shuffled order, against tin_tiles of the DEM raster;
-- and the geographic DEM in 90 x 90 tiles
CREATE TABLE dem_cut AS SELECT t AS rast FROM dem, ST_Tile(rast, 64, 64) t ORDER BY md5(ST_AsText(ST_Envelope(t)));
CREATE TABLE geo_cut AS SELECT t AS rast FROM dem_geo, ST_Tile(rast, 90, 90) t ORDER BY md5(ST_AsText(ST_Envelope(t)));
-- (each table built once, kept for the checks below)
CREATE TEMP TABLE plain AS SELECT * FROM tin_tiles_from_table('dem_cut', 4.0, 2);
CREATE TEMP TABLE geo_tins AS SELECT * FROM tin_tiles_from_table('geo_cut', 4.0, 2);
SELECT 'utm' AS dem, count(*) AS tiles, count(w.t) AS matched, count(*) FILTER (WHERE f.t::text = w.t::text) AS same_bytes
FROM plain f
LEFT JOIN (SELECT w.* FROM dem, tin_tiles(rast, 64, 4.0, 2) w) w USING (tx, ty)
UNION ALL
SELECT 'geographic', count(*), count(w.t), count(*) FILTER (WHERE f.t::text = w.t::text)
FROM geo_tins f
LEFT JOIN (SELECT w.* FROM dem_geo, tin_tiles(rast, 90, 4.0, 2) w) w USING (tx, ty);
-- every valid pixel centre of the geographic DEM's 90 x 90 tiles, as
-- ST_PixelAsCentroids gives it (from its own raster tile's corner), gets a
-- height from a tin holding it: on the edge of the data such a centre can
-- lie an ulp off the tin's hull, which the tins place on the table's
-- lattice (0.21.0 gave some no height: 344 of the same DEM's centres in
-- 97-pixel tiles, core test tiles::pixel_centres...)
SELECT count(*) AS centres, count(*) FILTER (WHERE s.h IS NULL) AS unanswered,
       count(*) FILTER (WHERE abs(s.h - c.val) > 4.0 + 1e-9) AS beyond_tolerance
FROM geo_cut g, ST_PixelAsCentroids(g.rast, 1, true) c,
     LATERAL (SELECT max(tin_height(k.t, c.geom)) AS h FROM geo_tins k WHERE tin_envelope(k.t) && c.geom) s;
DROP TABLE geo_tins;
-- the same tiles from a partitioned table (the tiles dealt to two partitions
-- in turn, so the ctids repeat between them), a table with an inheritance
-- child, and a view: they are read by their tiles' places, not by ctid;
-- byte for byte the plain table's tiles
CREATE TABLE dem_parts (half int, rast raster) PARTITION BY LIST (half);
CREATE TABLE dem_parts_0 PARTITION OF dem_parts FOR VALUES IN (0);
CREATE TABLE dem_parts_1 PARTITION OF dem_parts FOR VALUES IN (1);
INSERT INTO dem_parts SELECT (row_number() OVER () % 2)::int, rast FROM dem_cut;
CREATE TABLE dem_inh (rast raster);
CREATE TABLE dem_inh_child () INHERITS (dem_inh);
INSERT INTO dem_inh SELECT rast FROM dem_cut WHERE ST_UpperLeftY(rast) > (SELECT ST_UpperLeftY(rast) FROM dem) + 128 * ST_ScaleY(rast);
INSERT INTO dem_inh_child SELECT rast FROM dem_cut WHERE ST_UpperLeftY(rast) <= (SELECT ST_UpperLeftY(rast) FROM dem) + 128 * ST_ScaleY(rast);
CREATE VIEW dem_view AS SELECT rast FROM dem_cut;
SELECT 'partitioned' AS source, (SELECT count(*) FROM dem_parts_0) AS first_part, (SELECT count(*) FROM dem_parts_1) AS second_part,
       count(*) AS tiles, count(*) FILTER (WHERE f.t::text = p.t::text) AS same_bytes
FROM tin_tiles_from_table('dem_parts', 4.0, 2) f LEFT JOIN plain p USING (tx, ty)
UNION ALL
SELECT 'inheritance', (SELECT count(*) FROM ONLY dem_inh), (SELECT count(*) FROM dem_inh_child), count(*), count(*) FILTER (WHERE f.t::text = p.t::text)
FROM tin_tiles_from_table('dem_inh', 4.0, 2) f LEFT JOIN plain p USING (tx, ty)
UNION ALL
SELECT 'view', (SELECT count(*) FROM dem_view), NULL, count(*), count(*) FILTER (WHERE f.t::text = p.t::text)
FROM tin_tiles_from_table('dem_view', 4.0, 2) f LEFT JOIN plain p USING (tx, ty);
SELECT (SELECT count(*) FROM plain) AS plain_tiles;
DROP VIEW dem_view;
DROP TABLE dem_parts, dem_inh_child, dem_inh, plain;
-- slices (0.21.0): the DEM in 8 x 8 tiles (43 x 46, nodata corners) built
-- whole and as three slices of tile rows, each planned with its halo: every
-- tile once, byte for byte the whole build's
CREATE TEMP TABLE dem_cut8 AS SELECT t AS rast FROM dem, ST_Tile(rast, 8, 8) t;
CREATE TEMP TABLE whole8 AS SELECT * FROM tin_tiles_from_table('dem_cut8', 4.0, 2);
CREATE TEMP TABLE sliced8 AS
SELECT k, f.* FROM generate_series(0, 2) k, tin_tiles_from_table('dem_cut8', 4.0, 2, slice => k, slices => 3) f;
SELECT (SELECT count(*) FROM whole8) AS tiles, count(*) AS sliced, count(DISTINCT (tx, ty)) AS distinct_tiles,
       count(*) FILTER (WHERE s.t::text = w.t::text) AS same_bytes,
       array_agg(DISTINCT k ORDER BY k) AS slices_with_tiles,
       bool_and(s.ty >= k * 46 / 3 AND s.ty < (k + 1) * 46 / 3) AS rows_of_their_slice
FROM sliced8 s LEFT JOIN whole8 w USING (tx, ty);
SELECT count(*) FROM tin_tiles_from_table('dem_cut8', 4.0, 2, slice => 3, slices => 3);
SELECT count(*) FROM tin_tiles_from_table('dem_cut8', 4.0, 2, slice => 0, slices => 0);
SELECT count(*) FROM tin_tiles_from_table('dem_cut8', 4.0, 2, slice => -1, slices => 2);
-- a tile missing: every other tile is still built, its neighbours without
-- its border pixels (the left neighbour's tin spans its own 64 columns,
-- 63 pixels from first to last centre)
DELETE FROM dem_cut WHERE ST_UpperLeftX(rast) = (SELECT ST_UpperLeftX(rast) FROM dem) + 128 * ST_ScaleX(rast)
                      AND ST_UpperLeftY(rast) = (SELECT ST_UpperLeftY(rast) FROM dem) + 64 * ST_ScaleY(rast);
WITH missing AS MATERIALIZED (SELECT * FROM tin_tiles_from_table('dem_cut', 4.0, 2))
SELECT count(*) AS tiles, count(*) FILTER (WHERE (tx, ty) = (2, 1)) AS the_missing_one,
       (SELECT round(((ST_XMax(tin_envelope(t)) - ST_XMin(tin_envelope(t))) / (SELECT ST_ScaleX(rast) FROM dem))::numeric, 6)
        FROM missing WHERE (tx, ty) = (1, 1)) AS left_neighbour_columns_apart
FROM missing;
-- bad tables, one per line
SELECT count(*) FROM tin_tiles_from_table('window_tiles', 2.0, 3, rast_column => 'rid');
SELECT count(*) FROM tin_tiles_from_table('window_tiles', 2.0, 3, rast_column => 'nope');
SELECT count(*) FROM tin_tiles_from_table('no_such_table', 2.0, 3);
SELECT count(*) FROM tin_tiles_from_table('window_tiles', 2.0, 3, band => 2);
SELECT count(*) FROM tin_tiles_from_table('window_tiles', 2.0, 0);
CREATE TEMP TABLE bad_tiles AS SELECT rast FROM window_tiles;
INSERT INTO bad_tiles SELECT ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + ST_ScaleX(rast) / 2, ST_UpperLeftY(rast)) FROM window_tiles LIMIT 1;
SELECT count(*) FROM tin_tiles_from_table('bad_tiles', 2.0, 3);
TRUNCATE bad_tiles;
INSERT INTO bad_tiles SELECT rast FROM window_tiles UNION ALL SELECT ST_SetScale(rast, ST_ScaleX(rast) * 2, ST_ScaleY(rast)) FROM window_tiles LIMIT 17;
SELECT count(*) FROM tin_tiles_from_table('bad_tiles', 2.0, 3);
TRUNCATE bad_tiles;
INSERT INTO bad_tiles SELECT CASE WHEN rid = 1 THEN ST_SetSRID(rast, 4326) ELSE rast END FROM window_tiles;
SELECT count(*) FROM tin_tiles_from_table('bad_tiles', 2.0, 3);
TRUNCATE bad_tiles;
INSERT INTO bad_tiles SELECT rast FROM window_tiles UNION ALL SELECT rast FROM window_tiles WHERE rid = 5;
SELECT count(*) FROM tin_tiles_from_table('bad_tiles', 2.0, 3);
TRUNCATE bad_tiles;
SELECT count(*) AS empty_table FROM tin_tiles_from_table('bad_tiles', 2.0, 3);
DROP TABLE from_table, dem_cut, geo_cut;
DROP TABLE one_call;
