#!/usr/bin/env python3
"""docs/sql-reference.md against the catalog: every public function of the
installed extension (pg_proc, names not starting with "_", the type's I/O and
the operators' support functions aside) has an entry whose signature is the
one PostgreSQL reports, argument names, types and defaults
(pg_get_function_arguments) and result (pg_get_function_result) included,
and nothing is documented that does not exist.

An entry is a heading (### `name(args) RETURNS result`) or the first cell of
a table row (| `name(args) RETURNS result` | ...). `line geometry|linetree|text`
stands for one signature per type. Types are compared as PostgreSQL names
them (float8 = double precision, int = integer); defaults without their
casts (DEFAULT NULL::integer = DEFAULT NULL).

Usage: tests/docs_signatures.py DATABASE (the test cluster running:
scripts/cluster.sh psql).
"""
import re
import subprocess
import sys

ALIASES = {
    "float8": "double precision",
    "int": "integer",
    "int4": "integer",
    "int8": "bigint",
    "bool": "boolean",
}


def split_top(s):
    """Split at commas outside parentheses and quotes."""
    out, depth, quote, cur = [], 0, False, ""
    for ch in s:
        if ch == "'":
            quote = not quote
        elif not quote and ch == "(":
            depth += 1
        elif not quote and ch == ")":
            depth -= 1
        if ch == "," and depth == 0 and not quote:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        out.append(cur.strip())
    return out


def norm_type(t):
    t = t.strip()
    arr = ""
    while t.endswith("[]"):
        t, arr = t[:-2].strip(), arr + "[]"
    return ALIASES.get(t, t) + arr


def norm_default(d):
    d = d.strip()
    # casts PostgreSQL adds: NULL::integer, 'rast'::name, (0)::double precision
    d = re.sub(r"::[a-z ]+(\[\])*$", "", d)
    if d.startswith("(") and d.endswith(")"):
        d = d[1:-1]
    # a negative number comes back quoted: '-9999'::double precision
    if re.fullmatch(r"'-[0-9.]+'", d):
        d = d[1:-1]
    return d


def norm_arg(a):
    """'name type DEFAULT x' (name optional, quoted names unquoted)."""
    a = a.strip()
    default = None
    m = re.match(r"(.*?)\s+DEFAULT\s+(.*)$", a, re.S)
    if m:
        a, default = m.group(1).strip(), norm_default(m.group(2))
    a = a.replace('"', "")
    words = a.split()
    types = {"double", "precision", "character", "varying"}
    if len(words) >= 2 and words[0] not in types:
        name, typ = words[0], " ".join(words[1:])
    else:
        name, typ = "", " ".join(words)
    s = (name + " " if name else "") + norm_type(typ)
    return s + (" DEFAULT " + default if default is not None else "")


def norm_result(r):
    r = r.strip()
    m = re.match(r"TABLE\((.*)\)$", r, re.S)
    if m:
        return "TABLE(" + ", ".join(norm_arg(a) for a in split_top(m.group(1))) + ")"
    if r.startswith("SETOF "):
        return "SETOF " + norm_type(r[6:])
    return norm_type(r)


def signature(name, args, result):
    return "%s(%s) RETURNS %s" % (
        name,
        ", ".join(norm_arg(a) for a in split_top(args)),
        norm_result(result),
    )


def documented(text):
    found = []
    pat = re.compile(r"^(?:### |\| )`([a-z_0-9]+)\((.*?)\) RETURNS ([^`]*)`", re.M)
    for m in pat.finditer(text):
        name, args, result = m.group(1), m.group(2), m.group(3)
        # one alternation per entry: `line geometry|linetree|text`
        alt = re.search(r"(\w+) ([a-z_0-9\[\]]+(?:\|[a-z_0-9\[\]]+)+)", args)
        if alt:
            for t in alt.group(2).split("|"):
                found.append(signature(name, args.replace(alt.group(0), alt.group(1) + " " + t), result))
        else:
            found.append(signature(name, args, result))
    return found


# the extension's public functions in pg_proc (p): names not starting with
# "_", the type's I/O and the operators' support functions aside (also
# used by tests/function_coverage.py)
PUBLIC_FUNCTIONS = """
FROM pg_proc p
JOIN pg_depend d ON d.classid = 'pg_proc'::regclass AND d.objid = p.oid AND d.deptype = 'e'
JOIN pg_extension e ON e.oid = d.refobjid AND e.extname = 'tinmerge'
WHERE p.proname !~ '^_'
  AND NOT EXISTS (SELECT FROM pg_type t WHERE p.oid IN (t.typinput, t.typoutput, t.typreceive, t.typsend))
  AND NOT EXISTS (SELECT FROM pg_operator o WHERE o.oprcode = p.oid)
  AND NOT EXISTS (SELECT FROM pg_amproc a WHERE a.amproc = p.oid)"""


def catalog(db):
    q = ("SELECT p.proname, pg_get_function_arguments(p.oid), pg_get_function_result(p.oid)"
         + PUBLIC_FUNCTIONS + "\nORDER BY 1, 2")
    out = subprocess.run(
        ["scripts/cluster.sh", "psql", "-X", "-q", "-A", "-t", "-F", "\t", "-d", db, "-c", q],
        check=True, capture_output=True, text=True,
    ).stdout
    rows = [line.split("\t") for line in out.splitlines() if line.strip()]
    return [signature(n, a, r) for n, a, r in rows]


def main():
    db = sys.argv[1] if len(sys.argv) > 1 else "tinmerge_regress"
    docs = documented(open("docs/sql-reference.md").read())
    cat = catalog(db)
    missing = sorted(set(cat) - set(docs))
    extra = sorted(set(docs) - set(cat))
    for s in missing:
        print("not documented as it is:  " + s)
    for s in extra:
        print("documented, not in pg_proc: " + s)
    if missing or extra:
        print("docs/sql-reference.md differs from the catalog: %d missing, %d that do not exist" % (len(missing), len(extra)))
        sys.exit(1)
    print("docs/sql-reference.md: %d signatures, every public function, as pg_proc has them" % len(cat))


if __name__ == "__main__":
    main()
