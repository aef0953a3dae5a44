-- A table with a tin column that no VACUUM or ANALYZE has seen is planned
-- with its real rows, not PostgreSQL's ten-page guess (1,270 rows for a
-- one-row terrain table, which autovacuum never analyzes): the comma join
-- users write then scans the terrain once, outside, with no Materialize,
-- and no JIT compiles a join of a few points. (Found measuring the
-- README's join form: 1,000 points took 2.8 ms against 0.3 ms once the
-- terrain table was analyzed; src/pg/planner.rs.)
SET extra_float_digits = 0;
SET max_parallel_workers_per_gather = 0;
-- nothing below calls tinmerge before the first EXPLAIN: this session's
-- first query that names a tinmerge function is planned right too (its
-- support function loads tinmerge before the tables are sized)
CREATE TABLE pl_terrain AS SELECT t FROM terrain;
SELECT setseed(0.5);
CREATE TABLE pl_pts AS
SELECT i AS id, ST_SetSRID(ST_MakePoint(740500 + random() * 5000, 4059000 + random() * 5000), 32616) AS geom
FROM generate_series(1, 1000) i;
ANALYZE pl_pts;
EXPLAIN (COSTS OFF) SELECT sum(tin_height(t.t, p.geom)) FROM pl_pts p, pl_terrain t;
-- the planner's row estimate for a relation of a query
CREATE FUNCTION plan_rows(q text, rel text) RETURNS float8 LANGUAGE plpgsql AS $$
DECLARE j jsonb;
BEGIN
  EXECUTE 'EXPLAIN (FORMAT JSON) ' || q INTO j;
  RETURN jsonb_path_query_first(j, '$.**?(@."Relation Name" == $r)."Plan Rows"',
                                jsonb_build_object('r', rel))::float8;
END $$;
CREATE TABLE pl_plain AS SELECT 1 AS id, 'no tin here'::text AS note;
-- never analyzed; the estimate is count(*)'s answer
SELECT c.reltuples AS reltuples, (SELECT count(*) FROM pl_terrain) AS rows,
       plan_rows('SELECT * FROM pl_terrain', 'pl_terrain') AS estimate
FROM pg_class c WHERE c.relname = 'pl_terrain';
-- a table without a tin column keeps PostgreSQL's guess
SELECT plan_rows('SELECT * FROM pl_plain', 'pl_plain') > 100 AS plain_keeps_the_guess;
-- rows added and deleted: the rows the query's snapshot sees
INSERT INTO pl_terrain SELECT t FROM terrain;
INSERT INTO pl_terrain SELECT t FROM terrain;
DELETE FROM pl_terrain WHERE ctid = (SELECT min(ctid) FROM pl_terrain);
SELECT (SELECT count(*) FROM pl_terrain) AS rows,
       plan_rows('SELECT * FROM pl_terrain', 'pl_terrain') AS estimate;
-- inside a transaction that has not committed its rows yet
BEGIN;
INSERT INTO pl_terrain SELECT t FROM terrain;
SELECT (SELECT count(*) FROM pl_terrain) AS rows,
       plan_rows('SELECT * FROM pl_terrain', 'pl_terrain') AS estimate;
ROLLBACK;
-- two terrain rows now: the points outside and the two terrains
-- materialized (two scans of the points would cost more), the plan
-- PostgreSQL makes once the table is analyzed (below)
EXPLAIN (COSTS OFF) SELECT sum(tin_height(t.t, p.geom)) FROM pl_pts p, pl_terrain t;
-- (its answer: each point's height once per terrain row, as the
-- scalar-subquery form gives it once)
SELECT (SELECT count(tin_height(t.t, p.geom)) FROM pl_pts p, pl_terrain t)
     = 2 * (SELECT count(tin_height((SELECT t FROM terrain), p.geom)) FROM pl_pts p) AS same_answer;
-- an empty terrain table: one row, as PostgreSQL clamps every estimate
CREATE TABLE pl_empty (t tin);
SELECT plan_rows('SELECT * FROM pl_empty', 'pl_empty') AS estimate_empty;
-- a materialized view of tins too
CREATE MATERIALIZED VIEW pl_view AS SELECT t FROM terrain;
SELECT plan_rows('SELECT * FROM pl_view', 'pl_view') AS estimate_view;
-- analyzed, PostgreSQL's own statistics answer, as they did without us
ANALYZE pl_terrain;
SELECT plan_rows('SELECT * FROM pl_terrain', 'pl_terrain') AS estimate_analyzed;
EXPLAIN (COSTS OFF) SELECT sum(tin_height(t.t, p.geom)) FROM pl_pts p, pl_terrain t;
DROP MATERIALIZED VIEW pl_view;
DROP TABLE pl_terrain, pl_plain, pl_pts, pl_empty;
DROP FUNCTION plan_rows(text, text);
