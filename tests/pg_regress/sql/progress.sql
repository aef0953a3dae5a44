-- Progress of long builds (docs/sql-reference.md, Settings): the setting
-- tinmerge.progress_interval, its bounds, and the view tin_progress (what
-- tests/progress.sh reads from a second session while a build runs; here
-- no build of this session runs while it is read).
SELECT tin_num_levels(t) FROM terrain;  -- loads the library
SELECT name, boot_val, unit, min_val, max_val, context FROM pg_settings WHERE name = 'tinmerge.progress_interval';
SET tinmerge.progress_interval = -1;
SET tinmerge.progress_interval = 3601;
SET tinmerge.progress_interval = 'often';
SET tinmerge.progress_interval = '1min';
SELECT current_setting('tinmerge.progress_interval');
RESET tinmerge.progress_interval;
-- the view's columns
SELECT attname, format_type(atttypid, atttypmod) FROM pg_attribute
WHERE attrelid = 'tin_progress'::regclass AND attnum > 0 ORDER BY attnum;
SELECT count(*) FROM tin_progress WHERE pid = pg_backend_pid();
