-- tinmerge 0.3.0 -> 0.4.0: the code's new shape (a core crate, one folder per
-- merge) changes no answer. Benchmark entry points are no longer part of an
-- install (they are built only with the `bench` feature, `make bench`).
DROP FUNCTION IF EXISTS _tin_area_examined(tin, bytea, integer, text);
