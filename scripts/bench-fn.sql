-- bench(label, query, n): runs `query` n times and gives the median in ms
-- (2 decimals). Loaded by scripts/bench.sh and scripts/bench-serve.sh.
CREATE FUNCTION bench(label text, query text, n int) RETURNS TABLE(what text, median_ms numeric, runs int)
LANGUAGE plpgsql AS $$
DECLARE t0 timestamptz; ms float8[] := '{}';
BEGIN
  FOR i IN 1..n LOOP
    t0 := clock_timestamp();
    EXECUTE query;
    ms := ms || extract(epoch FROM clock_timestamp() - t0) * 1000;
  END LOOP;
  RETURN QUERY SELECT label, round((SELECT percentile_cont(0.5) WITHIN GROUP (ORDER BY x) FROM unnest(ms) x)::numeric, 2), n;
END $$;
