-- TIN/TIN overlay against PostGIS: the common domain from ST_ConvexHull and
-- ST_Intersection, overlap by ST_Union, containment by ST_Covers, input
-- vertices and edges from tin_triangles with ST_DumpPoints/ST_DumpSegments,
-- heights from tin_height on the inputs.
SET extra_float_digits = 0;
-- two epochs of a 60 x 60 pixel window: b shifted by a fraction of a pixel
-- and built at other tolerances, c the same samples as a at other
-- tolerances (shared vertices, overlapping edges), raised = a + 1 m, and
-- far = a window that does not meet a
CREATE TABLE o_win AS
  SELECT ST_Clip(rast, ST_MakeEnvelope(ST_UpperLeftX(rast) + 100 * ST_ScaleX(rast), ST_UpperLeftY(rast) + 160 * ST_ScaleY(rast),
                                       ST_UpperLeftX(rast) + 160 * ST_ScaleX(rast), ST_UpperLeftY(rast) + 100 * ST_ScaleY(rast), 32616)) AS rast
  FROM dem;
CREATE TABLE o_tins AS
  SELECT 'a' AS name, tin_from_raster(rast, 4.0, 2) AS t FROM o_win
  UNION ALL SELECT 'b', tin_from_raster(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 0.37 * ST_ScaleX(rast), ST_UpperLeftY(rast) + 0.61 * ST_ScaleY(rast)), 2.5, 2) FROM o_win
  UNION ALL SELECT 'c', tin_from_raster(rast, 1.5, 2) FROM o_win
  UNION ALL SELECT 'raised', tin_from_raster(ST_MapAlgebra(rast, 1, NULL, '[rast] + 1'), 4.0, 2) FROM o_win
  UNION ALL SELECT 'far', tin_from_raster(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 1e5, ST_UpperLeftY(rast)), 4.0, 2) FROM o_win;
CREATE TABLE o_pairs AS
  SELECT a.name || '/' || b.name || '@' || la AS pair, a.t AS ta, b.t AS tb, la AS level
  FROM o_tins a, o_tins b, unnest(ARRAY[0, 1]) la
  WHERE a.name = 'a' AND b.name IN ('a', 'b', 'c');
CREATE TABLE o_out AS
  SELECT pair, o.* FROM o_pairs, tin_overlay(ta, tb, level, level) o;
CREATE INDEX ON o_out USING gist (geom_a);
CREATE TABLE o_dom AS
  SELECT pair, ST_Intersection(ST_ConvexHull(tin_as_geometry(ta, level)), ST_ConvexHull(tin_as_geometry(tb, level))) AS geom
  FROM o_pairs;
-- area of the common domain, no overlaps (area of the union), every
-- triangle non-degenerate
SELECT p.pair, count(*) > 0 AS some,
       abs(sum(ST_Area(o.geom_a)) - ST_Area(d.geom)) <= 1e-9 * ST_Area(d.geom) AS area_is_domain,
       abs(ST_Area(ST_Union(o.geom_a)) - sum(ST_Area(o.geom_a))) <= 1e-9 * ST_Area(d.geom) AS no_overlap,
       count(*) FILTER (WHERE ST_Area(o.geom_a) <= 0) AS degenerate,
       count(*) FILTER (WHERE NOT ST_Equals(ST_Force2D(o.geom_a), ST_Force2D(o.geom_b))) AS geoms_differ
FROM o_pairs p JOIN o_out o USING (pair) JOIN o_dom d USING (pair)
GROUP BY p.pair, d.geom ORDER BY 1;
-- each output triangle inside its triangle of a and of b
CREATE TABLE o_tri AS
  SELECT p.pair, 'a' AS side, tr.id, tr.geom FROM o_pairs p, tin_triangles(p.ta, p.level) tr
  UNION ALL SELECT p.pair, 'b', tr.id, tr.geom FROM o_pairs p, tin_triangles(p.tb, p.level) tr;
CREATE INDEX ON o_tri (pair, side, id);
ANALYZE o_tri;
SELECT o.pair,
       count(*) FILTER (WHERE NOT ST_Covers(ST_Buffer(ta.geom, 1e-6), o.geom_a)) AS outside_a,
       count(*) FILTER (WHERE NOT ST_Covers(ST_Buffer(tb.geom, 1e-6), o.geom_a)) AS outside_b
FROM o_out o
JOIN o_tri ta ON ta.pair = o.pair AND ta.side = 'a' AND ta.id = o.triangle_a
JOIN o_tri tb ON tb.pair = o.pair AND tb.side = 'b' AND tb.id = o.triangle_b
GROUP BY 1 ORDER BY 1;
-- every input vertex in the common domain is an output vertex
CREATE TABLE o_outpts AS
  SELECT DISTINCT pair, ST_AsBinary(ST_Force2D((ST_DumpPoints(geom_a)).geom)) AS k FROM o_out;
CREATE TABLE o_inpts AS
  SELECT p.pair, (ST_DumpPoints(tr.geom)).geom AS g FROM o_pairs p, tin_triangles(p.ta, p.level) tr
  UNION SELECT p.pair, (ST_DumpPoints(tr.geom)).geom FROM o_pairs p, tin_triangles(p.tb, p.level) tr;
ALTER TABLE o_inpts ADD COLUMN k bytea;
UPDATE o_inpts SET k = ST_AsBinary(ST_Force2D(g));
ANALYZE o_inpts;
ANALYZE o_outpts;
SELECT v.pair, count(*) AS input_vertices, count(*) FILTER (WHERE op.k IS NULL) AS missing
FROM o_inpts v JOIN o_dom d USING (pair)
LEFT JOIN o_outpts op ON op.pair = v.pair AND op.k = v.k
WHERE ST_Covers(d.geom, v.g)
GROUP BY 1 ORDER BY 1;
-- every input edge, clipped to the common domain, is covered by output
-- edges: their lengths along it add up to its length
CREATE TABLE o_outsegs AS
  SELECT DISTINCT pair, ST_Normalize(ST_Force2D((ST_DumpSegments(geom_a)).geom)) AS geom FROM o_out;
CREATE INDEX ON o_outsegs USING gist (geom);
CREATE TABLE o_insegs AS
  SELECT DISTINCT p.pair, ST_Intersection(ST_Normalize(ST_Force2D(s.geom)), d.geom) AS geom
  FROM o_pairs p JOIN o_dom d USING (pair),
       LATERAL (SELECT (ST_DumpSegments(tr.geom)).geom FROM tin_triangles(p.ta, p.level) tr
                UNION ALL SELECT (ST_DumpSegments(tr.geom)).geom FROM tin_triangles(p.tb, p.level) tr) s;
-- (the union of the stretches of the input edge they lie on: two input
-- vertices a rounding apart, a grid-line crossing of one tin on the
-- outline of the other, are both output vertices, and the output edges
-- from them run side by side within 1e-10 m)
SELECT i.pair, count(*) AS input_edges,
       count(*) FILTER (WHERE abs(coalesce(c.len, 0) - 1) > 1e-6) AS not_covered
FROM o_insegs i
LEFT JOIN LATERAL (
  SELECT sum(upper(r) - lower(r)) AS len
  FROM unnest((SELECT range_agg(numrange(least(t0, t1)::numeric, greatest(t0, t1)::numeric))
               FROM o_outsegs s,
                    LATERAL (SELECT ST_LineLocatePoint(i.geom, ST_StartPoint(s.geom)) AS t0,
                                    ST_LineLocatePoint(i.geom, ST_EndPoint(s.geom)) AS t1) t
               WHERE s.pair = i.pair AND ST_Covers(ST_Buffer(i.geom, 1e-6), s.geom))) r) c ON true
WHERE ST_Length(i.geom) > 1e-3
GROUP BY 1 ORDER BY 1;
-- heights: the corners of geom_a on surface a, of geom_b on surface b
SELECT o.pair,
       max(abs(ST_Z(v.g) - tin_height(p.ta, ST_Force2D(v.g), p.level))) < 1e-6 AS a_heights,
       max(abs(ST_Z(w.g) - tin_height(p.tb, ST_Force2D(w.g), p.level))) < 1e-6 AS b_heights
FROM o_out o JOIN o_pairs p USING (pair),
     LATERAL (SELECT (ST_DumpPoints(o.geom_a)).geom AS g) v,
     LATERAL (SELECT (ST_DumpPoints(o.geom_b)).geom AS g) w
GROUP BY 1 ORDER BY 1;
-- surface difference: with itself nothing; a + 1 m against a: the
-- domain's area in cut (to 1e-8: the overlay's slivers between the two
-- tins' vertices at grid-line crossings, a rounding apart)
SELECT d.cut, d.fill, d.area_changed FROM o_tins a, tin_difference(a.t, a.t) d WHERE a.name = 'a';
SELECT abs(d.cut - ST_Area(ST_ConvexHull(tin_as_geometry(a.t)))) <= 1e-8 * ST_Area(ST_ConvexHull(tin_as_geometry(a.t))) AS cut_is_area,
       d.fill = 0 AS no_fill,
       abs(d.area_changed - ST_Area(ST_ConvexHull(tin_as_geometry(a.t)))) <= 1e-9 * ST_Area(ST_ConvexHull(tin_as_geometry(a.t))) AS all_changed
FROM o_tins r, o_tins a, tin_difference(r.t, a.t) d WHERE r.name = 'raised' AND a.name = 'a';
-- b and c against a, exactly: PostGIS cuts every triangle of a by every
-- triangle of b it meets (ST_Intersection: convex pieces), and cut_fill
-- (00_setup.sql) integrates max(z_a - z_b, 0) and max(z_b - z_a, 0) over
-- each piece in closed form
CREATE TABLE o_exact AS
  SELECT p.pair, sum(cf.cut) AS cut, sum(cf.fill) AS fill, count(*) AS pieces
  FROM o_pairs p
  JOIN o_tri ta ON ta.pair = p.pair AND ta.side = 'a'
  JOIN o_tri tb ON tb.pair = p.pair AND tb.side = 'b' AND ST_Intersects(ta.geom, tb.geom),
  LATERAL (SELECT (ST_Dump(ST_CollectionExtract(ST_Intersection(ST_Force2D(ta.geom), ST_Force2D(tb.geom)), 3))).geom AS piece) x,
  cut_fill(x.piece, ta.geom, tb.geom) cf
  WHERE p.pair IN ('a/b@1', 'a/c@0')
  GROUP BY 1;
SELECT e.pair, e.pieces > 1000 AS many_pieces, e.cut > 0 AND e.fill > 0 AS both_ways,
       abs(d.cut - e.cut) <= 1e-9 * (e.cut + e.fill) AS cut_exact,
       abs(d.fill - e.fill) <= 1e-9 * (e.cut + e.fill) AS fill_exact
FROM o_exact e JOIN o_pairs p USING (pair), tin_difference(p.ta, p.tb, p.level, p.level) d
ORDER BY 1;
-- the overlay as a tin (tin_overlay_tin): one level whose triangles PostGIS
-- finds tile the common domain (area and union), each inside a triangle of
-- a and of b (ST_Covers), holding every vertex of both in the domain, with
-- the heights of a's plane there (plane_z of a triangle of a covering the
-- corner)
CREATE TABLE o_ot AS
  SELECT tr.id, tr.geom FROM o_tins a, o_tins b, tin_triangles(tin_overlay_tin(a.t, b.t, 1, 1)) tr
  WHERE a.name = 'a' AND b.name = 'b';
CREATE INDEX ON o_ot USING gist (geom);
CREATE INDEX ON o_tri USING gist (geom);
ANALYZE o_ot;
ANALYZE o_tri;
SELECT (SELECT tin_num_levels(tin_overlay_tin(a.t, b.t, 1, 1)) FROM o_tins a, o_tins b WHERE a.name = 'a' AND b.name = 'b') AS levels,
       count(*) > 0 AS some,
       abs(sum(ST_Area(o.geom)) - ST_Area(d.geom)) <= 1e-9 * ST_Area(d.geom) AS area_is_domain,
       abs(ST_Area(ST_Union(o.geom)) - sum(ST_Area(o.geom))) <= 1e-9 * ST_Area(d.geom) AS no_overlap,
       count(*) FILTER (WHERE NOT EXISTS (SELECT 1 FROM o_tri t WHERE t.pair = 'a/b@1' AND t.side = 'a' AND t.geom && o.geom
                                          AND ST_Covers(ST_Buffer(t.geom, 1e-6), o.geom))) AS outside_a,
       count(*) FILTER (WHERE NOT EXISTS (SELECT 1 FROM o_tri t WHERE t.pair = 'a/b@1' AND t.side = 'b' AND t.geom && o.geom
                                          AND ST_Covers(ST_Buffer(t.geom, 1e-6), o.geom))) AS outside_b
FROM o_ot o, o_dom d WHERE d.pair = 'a/b@1' GROUP BY d.geom;
CREATE TABLE o_otpts AS
  SELECT DISTINCT ST_AsBinary(ST_Force2D(g)) AS k, g FROM (SELECT (ST_DumpPoints(geom)).geom AS g FROM o_ot) x;
ANALYZE o_otpts;
SELECT count(*) AS vertices,
       count(*) FILTER (WHERE abs(ST_Z(v.g) - h.z) > 1e-6) AS heights_not_a,
       count(*) FILTER (WHERE h.z IS NULL) AS not_on_a,
       (SELECT count(*) FROM o_inpts i JOIN o_dom d USING (pair) LEFT JOIN o_otpts w USING (k)
        WHERE i.pair = 'a/b@1' AND ST_Covers(d.geom, i.g) AND w.k IS NULL) AS input_vertices_missing
FROM o_otpts v
LEFT JOIN LATERAL (SELECT plane_z(t.geom, v.g) AS z FROM o_tri t WHERE t.pair = 'a/b@1' AND t.side = 'a'
                   AND t.geom && ST_Expand(v.g, 1e-6) AND ST_DWithin(t.geom, v.g, 1e-6) LIMIT 1) h ON true;
-- disjoint domains, NULLs, SRIDs
SELECT (SELECT count(*) FROM tin_overlay(a.t, f.t)) AS disjoint_rows,
       tin_overlay_tin(a.t, f.t) IS NULL AS disjoint_tin,
       (SELECT count(*) FROM tin_difference(a.t, f.t)) AS disjoint_difference,
       (SELECT count(*) FROM tin_overlay(NULL, a.t)) AS null_rows,
       tin_overlay_tin(a.t, NULL) IS NULL AS null_tin,
       (SELECT count(*) FROM tin_overlay(a.t, a.t, NULL, 0)) = (SELECT count(*) FROM tin_overlay(a.t, a.t, 1, 0)) AS null_level_is_finest_a
FROM o_tins a, o_tins f WHERE a.name = 'a' AND f.name = 'far';
SELECT try($$SELECT count(*) FROM o_win w, o_tins a, tin_overlay(a.t, tin_from_raster(ST_SetSRID(w.rast, 32617), 4.0, 2)) WHERE a.name = 'a'$$);
SELECT try($$SELECT count(*) FROM o_tins a, tin_overlay(a.t, a.t, 2) WHERE a.name = 'a'$$);
SELECT try($$SELECT count(*) FROM o_tins a, tin_difference(a.t, a.t, 0, -1) WHERE a.name = 'a'$$);
-- tin_volume(a, b, polygon) (issue 49): cut and fill between two surfaces
-- inside polygons, against PostGIS: the polygon cut into triangles
-- (ST_TriangulatePolygon: convex pieces), each cut by every triangle of a
-- and of b it meets (ST_Intersection), and cut_fill (00_setup.sql) over
-- each piece. The polygons, in the window's extent: an L with a hole, a
-- rectangle reaching past the window, two pieces
CREATE INDEX ON o_tri USING gist (geom);
ANALYZE o_tri;
CREATE TABLE o_polys AS
SELECT name, ST_SetSRID(ST_Affine(g, ST_XMax(e) - ST_XMin(e), 0, 0, ST_YMax(e) - ST_YMin(e), ST_XMin(e), ST_YMin(e)), 32616) AS geom
FROM (SELECT ST_Envelope(rast) AS e FROM o_win) w,
     (VALUES ('L with a hole', ST_Difference('POLYGON((0.1 0.1, 0.8 0.1, 0.8 0.4, 0.45 0.4, 0.45 0.9, 0.1 0.9, 0.1 0.1))'::geometry,
                                             'POLYGON((0.2 0.2, 0.35 0.2, 0.35 0.6, 0.2 0.6, 0.2 0.2))'::geometry)),
             ('past the window', 'POLYGON((0.5 0.5, 1.3 0.5, 1.3 1.2, 0.5 1.2, 0.5 0.5))'::geometry),
             ('two pieces', 'MULTIPOLYGON(((0.05 0.6, 0.3 0.6, 0.3 0.95, 0.05 0.95, 0.05 0.6)), ((0.6 0.05, 0.95 0.05, 0.7 0.3, 0.6 0.05)))'::geometry)) v(name, g);
CREATE TABLE o_vol_exact AS
  SELECT p.pair, q.name, sum(cf.cut) AS cut, sum(cf.fill) AS fill, count(*) AS pieces
  FROM o_pairs p CROSS JOIN o_polys q
  CROSS JOIN LATERAL (SELECT (ST_Dump(ST_TriangulatePolygon(q.geom))).geom AS tri) pt
  JOIN o_tri ta ON ta.pair = p.pair AND ta.side = 'a' AND ST_Intersects(ta.geom, pt.tri)
  JOIN o_tri tb ON tb.pair = p.pair AND tb.side = 'b' AND ST_Intersects(tb.geom, ta.geom) AND ST_Intersects(tb.geom, pt.tri)
  CROSS JOIN LATERAL (SELECT (ST_Dump(ST_CollectionExtract(ST_Intersection(ST_Intersection(ST_Force2D(ta.geom), ST_Force2D(tb.geom)), pt.tri), 3))).geom AS piece) x
  CROSS JOIN LATERAL cut_fill(x.piece, ta.geom, tb.geom) cf
  WHERE p.pair IN ('a/b@1', 'a/c@0')
  GROUP BY 1, 2;
SELECT e.pair, e.name, e.pieces > 100 AS many_pieces, e.cut > 0 AND e.fill > 0 AS both_ways,
       abs(v.cut - e.cut) <= 1e-9 * (e.cut + e.fill) AS cut_exact,
       abs(v.fill - e.fill) <= 1e-9 * (e.cut + e.fill) AS fill_exact,
       abs(v.area_cut + v.area_fill + v.area_unchanged - ST_Area(ST_Intersection(q.geom, d.geom))) <= 1e-9 * ST_Area(q.geom) AS areas_sum_to_the_domain_inside
FROM o_vol_exact e JOIN o_pairs p USING (pair) JOIN o_polys q USING (name) JOIN o_dom d USING (pair),
     tin_volume(p.ta, p.tb, q.geom, p.level, p.level) v
ORDER BY 1, 2;
-- a surface 1 m above another: cut is the area inside, all of it area_cut;
-- a surface against itself: all of it unchanged
SELECT q.name,
       abs(v.cut - ST_Area(ST_Intersection(q.geom, ST_ConvexHull(tin_as_geometry(a.t))))) <= 1e-8 * ST_Area(q.geom) AS cut_is_area,
       v.fill = 0 AS no_fill, abs(v.area_cut - v.cut) <= 1e-8 * v.cut AS area_cut_is_area,
       s.cut = 0 AND s.fill = 0 AND s.area_cut = 0 AND s.area_fill = 0 AS itself_no_change,
       abs(s.area_unchanged - v.area_cut) <= 1e-9 * v.area_cut AS itself_unchanged
FROM o_polys q, o_tins r, o_tins a, tin_volume(r.t, a.t, q.geom) v, tin_volume(a.t, a.t, q.geom) s
WHERE r.name = 'raised' AND a.name = 'a' ORDER BY 1;
-- the whole common domain: tin_difference's cut, fill and changed area
SELECT abs(v.cut - d.cut) <= 1e-9 * (d.cut + d.fill) AS cut_as_difference, abs(v.fill - d.fill) <= 1e-9 * (d.cut + d.fill) AS fill_as_difference,
       abs(v.area_cut + v.area_fill - d.area_changed) <= 1e-9 * d.area_changed AS changed_as_difference
FROM o_pairs p, tin_difference(p.ta, p.tb, p.level, p.level) d,
     tin_volume(p.ta, p.tb, ST_Expand(tin_envelope(p.ta), 100), p.level, p.level) v
WHERE p.pair = 'a/b@1';
-- untyped literal, NULLs, bad input
SELECT round(v.cut + v.fill) > 0 AS untyped
FROM o_tins a, o_tins b, o_win w,
     tin_volume(a.t, b.t, 'SRID=32616;POLYGON((741000 4056000, 743600 4056000, 743600 4058600, 741000 4056000))') v
WHERE a.name = 'a' AND b.name = 'b';
SELECT count(*) AS rows_for_null_polygon FROM o_tins a, tin_volume(a.t, a.t, NULL::geometry) WHERE a.name = 'a';
SELECT count(*) AS rows_for_null_tin FROM o_polys q, tin_volume(NULL::tin, NULL::tin, q.geom);
SELECT try($$SELECT * FROM o_tins a, o_polys q, tin_volume(a.t, a.t, ST_SetSRID(q.geom, 4326)) WHERE a.name = 'a' AND q.name = 'two pieces'$$);
SELECT try($$SELECT * FROM o_tins a, o_polys q, tin_volume(a.t, a.t, ST_Boundary(q.geom)) WHERE a.name = 'a' AND q.name = 'two pieces'$$);
SELECT try($$SELECT * FROM o_tins a, o_polys q, tin_volume(a.t, a.t, q.geom, 5) WHERE a.name = 'a' AND q.name = 'two pieces'$$);
SELECT try($$SELECT * FROM o_win w, o_tins a, o_polys q, tin_volume(a.t, tin_from_raster(ST_SetSRID(w.rast, 32617), 4.0, 2), q.geom) WHERE a.name = 'a' AND q.name = 'two pieces'$$);
-- two geographic tins (0.25.0): metres on the spheroid; cut - fill is the
-- difference of the two surfaces' integrals (tin_area_stats; each part is
-- measured at its centroid's latitude, so the two sums over different
-- triangles agree to 1e-7 of the integral of z, here 4e-9), and the three
-- areas add up to PostGIS's geodesic area of the (segmentized) polygon
WITH g AS (SELECT tin_from_raster(rast, 8.0, 1) AS a, tin_from_raster(rast, 2.0, 1) AS b,
                  ST_Expand(ST_Centroid(ST_Envelope(rast)), 0.05) AS p FROM dem_geo),
v AS (SELECT g.*, v.* FROM g, tin_volume(a, b, p) v)
SELECT cut > 0 AND fill > 0 AS both_ways,
       abs((cut - fill) - ((sa.mean_z - sb.mean_z) * sa.area2d)) < 1e-7 * sa.mean_z * sa.area2d AS difference_of_integrals,
       abs((area_cut + area_fill + area_unchanged) / ST_Area(ST_Segmentize(p, 0.0005)::geography) - 1) < 1e-6 AS areas_as_postgis
FROM v, tin_area_stats(a, p) sa, tin_area_stats(b, p) sb;
-- tin_overlay_tin keeps the holes of either tin (0.19.0 and before filled
-- them: the overlay's triangles inside a void triangle were stored as
-- surface, so tin_height answered in the hole): a tin with a square hole
-- over one without, shifted; the area against PostGIS's intersection of
-- the two domains, NULL in the hole, a's heights elsewhere
CREATE TABLE o_hole AS
WITH p AS (SELECT ST_SetSRID(ST_Collect(ST_MakePoint(x, y, (x * 7 + y * 3) % 11)), 32616) AS g
           FROM generate_series(0, 100, 10) x, generate_series(0, 100, 10) y)
SELECT tin_from_points(g, 0.0, 1, boundary => ST_SetSRID('POLYGON((0 0, 100 0, 100 100, 0 100, 0 0), (40 40, 60 40, 60 60, 40 60, 40 40))'::geometry, 32616)) AS a,
       tin_from_points(ST_Translate(g, 5, 3), 0.0, 1) AS b FROM p;
SELECT round((SELECT sum(ST_Area(geom)) FROM tin_triangles(o))::numeric, 6) AS overlay_area,
       ST_Area(ST_Intersection(ST_SetSRID('POLYGON((0 0, 100 0, 100 100, 0 100, 0 0), (40 40, 60 40, 60 60, 40 60, 40 40))'::geometry, 32616),
                               ST_SetSRID('POLYGON((5 3, 105 3, 105 103, 5 103, 5 3))'::geometry, 32616))) AS postgis_area,
       tin_height(o, 'SRID=32616;POINT(50 50)') IS NULL AS hole_is_null,
       abs(tin_height(o, 'SRID=32616;POINT(21 33)') - tin_height(a, 'SRID=32616;POINT(21 33)')) < 1e-9 AS height_of_a,
       (SELECT round(sum(ST_Area(geom))::numeric, 6) FROM tin_triangles(tin_overlay_tin(a, a))) AS itself_area
FROM o_hole, tin_overlay_tin(a, b) o;
