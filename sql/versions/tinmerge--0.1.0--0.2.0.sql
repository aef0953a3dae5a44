-- tinmerge 0.1.0 -> 0.2.0: equality on tin (=, <>, hash operator class).
-- The stored value format is unchanged (format version 1), so stored
-- values need no rewrite. tests/upgrade.sh checks that this script makes
-- exactly the catalog of a fresh 0.2.0 install.
\echo Use "ALTER EXTENSION tinmerge UPDATE TO '0.2.0'" to load this file. \quit

CREATE FUNCTION tin_eq(a tin, b tin) RETURNS bool
IMMUTABLE STRICT PARALLEL SAFE LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_eq_wrapper';

CREATE FUNCTION tin_ne(a tin, b tin) RETURNS bool
IMMUTABLE STRICT PARALLEL SAFE LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_ne_wrapper';

CREATE FUNCTION tin_hash(t tin) RETURNS int
IMMUTABLE STRICT PARALLEL SAFE LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_hash_wrapper';

COMMENT ON FUNCTION tin_eq(tin, tin) IS
'True when two tins are the same value (the same bytes; header hashes and lengths compared first). The function behind the = operator.';
COMMENT ON FUNCTION tin_ne(tin, tin) IS
'True when two tins are different values. The function behind the <> operator.';
COMMENT ON FUNCTION tin_hash(tin) IS
'32-bit hash of a tin (its stored content hash): hash operator class support for =.';

CREATE OPERATOR = (
    LEFTARG = tin, RIGHTARG = tin, FUNCTION = tin_eq,
    COMMUTATOR = =, NEGATOR = <>,
    RESTRICT = eqsel, JOIN = eqjoinsel, HASHES
);
COMMENT ON OPERATOR =(tin, tin) IS 'same tin value (the same bytes)';

CREATE OPERATOR <> (
    LEFTARG = tin, RIGHTARG = tin, FUNCTION = tin_ne,
    COMMUTATOR = <>, NEGATOR = =,
    RESTRICT = neqsel, JOIN = neqjoinsel
);
COMMENT ON OPERATOR <>(tin, tin) IS 'different tin values';

CREATE OPERATOR CLASS tin_hash_ops DEFAULT FOR TYPE tin USING hash AS
    OPERATOR 1 = (tin, tin),
    FUNCTION 1 tin_hash(tin);
