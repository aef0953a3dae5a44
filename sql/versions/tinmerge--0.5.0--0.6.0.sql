-- tinmerge 0.5.0 -> 0.6.0: no answer changes. New values are stored in
-- format 4 (each array cut into groups of 1,024 elements, each coded,
-- compressed with zstd and checksummed: about a fifth of format 3, and
-- still read in slices). Values stored in formats 1 and 3 keep reading as
-- they are; tin_rewrite converts them.
COMMENT ON FUNCTION tin_rewrite(tin) IS 'The same tin in the current storage format (format 4: compressed groups with their own checksums, about a fifth of format 3, read in slices by the point, line and area functions); a value already in it is returned as it is. Answers do not change. UPDATE terrain SET t = tin_rewrite(t) converts stored values (docs/upgrading.md).';
