-- Every function of the extension has a COMMENT (the comment is its
-- one-line documentation in \df+ and in GUI tools): must list nothing.
SELECT p.oid::regprocedure AS function_without_comment
FROM pg_proc p
JOIN pg_depend d ON d.classid = 'pg_proc'::regclass AND d.objid = p.oid AND d.deptype = 'e'
JOIN pg_extension e ON e.oid = d.refobjid AND e.extname = 'tinmerge'
WHERE obj_description(p.oid, 'pg_proc') IS NULL
ORDER BY 1;
-- and the count is not vacuous: the extension has functions
SELECT count(*) > 50 AS has_functions
FROM pg_depend d JOIN pg_extension e ON e.oid = d.refobjid AND e.extname = 'tinmerge'
WHERE d.classid = 'pg_proc'::regclass AND d.deptype = 'e';
