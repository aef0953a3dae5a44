-- = , <> and the hash opclass (tin_eq, tin_ne, tin_hash) on several values,
-- against the oracle of their bytes: the text form of a tin is the hex of
-- its value, so two tins are equal exactly when their texts are.
SET extra_float_digits = 0;
-- six values: four different tins (two tolerances of one window, another
-- window, the terrain), a copy of one made from its text (a value that was
-- never in a table), and one of them stored again in a table of another
-- storage (MAIN against EXTERNAL: read back through another path)
CREATE TABLE op_vals (id int, t tin);
ALTER TABLE op_vals ALTER COLUMN t SET STORAGE EXTERNAL;
INSERT INTO op_vals
  SELECT 1, tin_from_raster(rast, 4.0, 2) FROM dem_window
  UNION ALL SELECT 2, tin_from_raster(rast, 2.0, 2) FROM dem_window
  UNION ALL SELECT 3, tin_from_raster(ST_Clip(rast, ST_Buffer(ST_Centroid(ST_Envelope(rast)), 2000)), 4.0, 2) FROM dem_window
  UNION ALL SELECT 4, t FROM terrain;
INSERT INTO op_vals SELECT 5, (SELECT t::text FROM op_vals WHERE id = 1)::tin;
CREATE TABLE op_main (id int, t tin);
ALTER TABLE op_main ALTER COLUMN t SET STORAGE MAIN;
INSERT INTO op_main SELECT 6, t FROM op_vals WHERE id = 2;
INSERT INTO op_vals SELECT id, t FROM op_main;
-- every pair: = and <> against the texts, hashes equal for equal values
SELECT count(*) AS pairs,
       count(*) FILTER (WHERE (a.t = b.t) IS DISTINCT FROM (a.t::text = b.t::text)) AS eq_wrong,
       count(*) FILTER (WHERE (a.t <> b.t) IS DISTINCT FROM (a.t::text <> b.t::text)) AS ne_wrong,
       count(*) FILTER (WHERE a.t::text = b.t::text AND tin_hash(a.t) <> tin_hash(b.t)) AS equal_hash_differs,
       count(*) FILTER (WHERE a.t::text = b.t::text) AS equal_pairs
FROM op_vals a, op_vals b;
-- the four different values hash differently (a 32-bit hash: a collision
-- among four is possible in principle, at odds of about 1 in 700 million)
SELECT count(DISTINCT tin_hash(t)) AS hashes, count(DISTINCT t::text) AS values FROM op_vals;
-- what the planner does with the opclass: a hash aggregate and a hash join
-- give the texts' groups and matches
SET enable_sort = off;
SET enable_mergejoin = off;
SET enable_nestloop = off;
EXPLAIN (COSTS OFF) SELECT t, count(*) FROM op_vals GROUP BY t;
EXPLAIN (COSTS OFF) SELECT count(*) FROM op_vals a JOIN op_vals b ON a.t = b.t;
SELECT count(*) AS groups, sum(n) AS rows FROM (SELECT t, count(*) AS n FROM op_vals GROUP BY t) g;
SELECT array_agg(n ORDER BY n) AS group_sizes FROM (SELECT count(*) AS n FROM op_vals GROUP BY t) g;
SELECT count(*) AS hash_join_matches,
       (SELECT count(*) FROM op_vals a, op_vals b WHERE a.t::text = b.t::text) AS text_matches
FROM op_vals a JOIN op_vals b ON a.t = b.t;
SELECT count(*) AS distinct_values FROM (SELECT DISTINCT t FROM op_vals) d;
SELECT count(*) AS in_list FROM op_vals WHERE t IN (SELECT t FROM op_vals WHERE id IN (1, 4));
RESET enable_sort;
RESET enable_mergejoin;
RESET enable_nestloop;
-- NULLs: the operators are STRICT
SELECT (NULL::tin = t) IS NULL AS eq_null, (t <> NULL::tin) IS NULL AS ne_null, tin_hash(NULL) IS NULL AS hash_null
FROM op_vals WHERE id = 1;
DROP TABLE op_vals, op_main;
