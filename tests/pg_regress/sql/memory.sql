-- tinmerge.max_memory: a request whose size is known is refused before it
-- allocates, one whose output grows is stopped as it passes the limit; both
-- with SQLSTATE 53400 and a message saying what to raise. MB figures depend
-- on the backend's state, so they are masked here. tinmerge.cache_size
-- bounds the decoded-value cache.
CREATE FUNCTION try_mem(q text) RETURNS text LANGUAGE sql AS
$$ SELECT regexp_replace(try(q), '[0-9]+ ?MB', 'N MB', 'g') $$;
-- the settings exist once the library is loaded (any tinmerge call, or
-- shared_preload_libraries / session_preload_libraries)
SELECT tin_num_levels(t) FROM terrain;
SHOW tinmerge.max_memory;
SET tinmerge.max_memory = '8MB';
-- build from the DEM's 118,130 samples at 5 levels (about 100 MB)
SELECT try_mem($$SELECT tin_from_raster(rast, 2.0, 5) FROM dem$$);
SELECT try_mem($$SELECT tin_from_points(ST_Collect(ST_MakePoint(ST_X(geom), ST_Y(geom), val)), 1.0) FROM (SELECT (ST_PixelAsCentroids(rast)).* FROM dem) p$$);
-- a point reads the stored 2.9 MB tin in slices: no decode, it fits; so
-- does level 0 (a small part of the value, read on its own)
SELECT try_mem($$SELECT tin_height(t, 'SRID=32616;POINT(740000 4060000)'::geometry) FROM terrain$$);
SELECT try_mem($$SELECT ST_NPoints(tin_as_geometry(t, 0)) > 0 FROM terrain$$);
-- decoding it whole (the finest level) does not
SELECT try_mem($$SELECT ST_NPoints(tin_as_geometry(t)) FROM terrain$$);
SELECT try_mem($$SELECT (SELECT t FROM terrain)::text::tin IS NOT NULL$$);
-- with the tin decoded and cached (cached values do not count):
RESET tinmerge.max_memory;
SELECT ST_NPoints(tin_as_geometry(t)) > 0 FROM terrain;
SET tinmerge.max_memory = '16MB';
-- reading a 1376 x 1452 raster band (about 18 MB)
CREATE TEMP TABLE dem4 AS SELECT ST_Rescale(rast, ST_ScaleX(rast) / 4, ST_ScaleY(rast) / 4) AS rast FROM dem;
SELECT try_mem($$SELECT count(*) FROM terrain, dem4, tin_raster_stats(t, rast, 0)$$);
-- an overlay whose least output is over the limit, and the store of one
SELECT try_mem($$SELECT count(*) FROM terrain a, tin_overlay(a.t, a.t, 4, 4)$$);
SET tinmerge.max_memory = '64MB';
-- refused before the store, or stopped while the overlay runs by the
-- backend's private resident memory (0.20.1): which comes first depends on
-- what the session's allocator already holds
SELECT try_mem($$SELECT tin_num_triangles(tin_overlay_tin(a.t, a.t, 4, 4)) FROM terrain a$$)
       ~ '^53400: (tin_overlay_tin: storing 278383 triangles as a tin needs about N MB, more than|this call has used N MB of heap and grown the backend by N MB \(private resident memory\), past seven eighths of) tinmerge\.max_memory \(N MB\)'
       AS refused;
-- an overlay whose output passes the limit while it runs: a copy shifted
-- by half a pixel crosses every edge (least estimate 12 MB, output ~100 MB)
RESET tinmerge.max_memory;
CREATE TEMP TABLE shifted AS
SELECT tin_from_raster(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 15, ST_UpperLeftY(rast) - 15), 2.0, 5) AS t FROM dem;
SELECT ST_NPoints(tin_as_geometry(t)) > 0 FROM shifted;
SET tinmerge.max_memory = '24MB';
-- stopped by the heap check or by the backend's private resident memory
-- (0.20.1), whichever check sees it first
SELECT try_mem($$SELECT count(*) FROM terrain a, shifted b, tin_overlay(a.t, b.t, 2, 2)$$)
       ~ '^53400: this call has used N MB(, more than| of heap and grown the backend by N MB \(private resident memory\), past seven eighths of) tinmerge\.max_memory \(N MB\)'
       AS stopped_while_running;
-- what fits still works in the same session
SELECT count(*) FROM terrain a, tin_overlay(a.t, a.t, 0, 0);
SELECT round(tin_height(t, 'SRID=32616;POINT(741000 4061000)'::geometry)::numeric, 6) FROM terrain;
-- no limit, and the limits of the setting itself
SET tinmerge.max_memory = -1;
SELECT count(*) FROM terrain a, tin_overlay(a.t, a.t, 2, 2);
SELECT try($$SET tinmerge.max_memory = -2$$);
SELECT try($$SET tinmerge.max_memory = 'lots'$$);
RESET tinmerge.max_memory;
SHOW tinmerge.max_memory;
SELECT count(*) > 0 FROM terrain, tin_from_raster((SELECT rast FROM dem), 2.0, 5) n, tin_triangles(n, 0);
-- tinmerge.cache_size: a value larger than the cache is never kept; the
-- point functions read it in slices instead of decoding it every time
SET tinmerge.cache_size = '8MB';
CREATE TEMP TABLE c0 AS SELECT * FROM tin_cache_stats();
SELECT count(tin_num_vertices(t, 0)) FROM terrain, generate_series(1, 3);
SELECT count(tin_height(t, 'SRID=32616;POINT(741000 4061000)'::geometry)) FROM terrain;
SELECT count(tin_height(t, 'SRID=32616;POINT(741000 4061000)'::geometry)) FROM terrain;
SELECT s.misses - c0.misses AS misses, s.bytes <= 8 * 1024 * 1024 AS within_cache_size FROM tin_cache_stats() s, c0;
RESET tinmerge.cache_size;
CREATE TEMP TABLE c1 AS SELECT * FROM tin_cache_stats();
-- past 2,000 point calls the value is decoded once and kept
SELECT count(tin_height(t, 'SRID=32616;POINT(741000 4061000)'::geometry)) FROM terrain, generate_series(1, 2100);
SELECT s.misses - c1.misses AS misses, s.entries >= 1 AS cached FROM tin_cache_stats() s, c1;
