#!/usr/bin/env python3
"""Every public function of the installed extension is tested against an
oracle that is not tinmerge: a textual rule over the test files.

A function counts as covered when its name appears in a test file (the
pg_regress SQL, the property and browser checks, the shell tests) within
WINDOW lines of an oracle marker in that file: a PostGIS or raster
measurement (ST_Area, ST_Intersection, ST_Value, ...), the tests' own SQL
oracles (plane_z, slope_factor from 00_setup.sql), or an outside library
(shapely, numpy, scipy, matplotlib, exactextract, gdal). The names of pg_proc
are those docs_signatures.py checks (names not starting with "_", the type's
I/O and the operators' support functions aside).

ALLOWED lists the functions whose oracle is elsewhere (at most five, each
with its reason). The rule is textual: it is a floor, not a proof, and it
fails when a new function has no oracle test near its name.

Usage: tests/function_coverage.py DATABASE (the test cluster running).
"""
import glob
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import docs_signatures  # noqa: E402

WINDOW = 12

MARKERS = re.compile(
    r"\b(ST_(Area|Intersection|Intersects|Value|Length|3DLength|Covers|Contains|Within|Equals|Extent|"
    r"Distance|DWithin|ConvexHull|Polygon|PixelAs\w+|Z|ZMax|ZMin|X|Y|Union|Difference|Buffer|"
    r"LineInterpolatePoint|DumpSegments|DumpPoints|Points|NPoints|Centroid|ClosestPoint|Summary\w*|MapAlgebra|"
    r"Slope|Aspect|HillShade|Resample|Transform|MakeEnvelope|Collect|Boundary|IsValid)|"
    r"plane_z|slope_factor|shapely|numpy|np\.|scipy|matplotlib|exactextract|gdal|osgeo|oracle|brute)\b",
    re.IGNORECASE,
)

# function -> why its oracle is not in a test file near its name
ALLOWED = {
    # reports this backend's cache counters; nothing outside tinmerge knows them
    "tin_cache_stats": "cache counters of this backend: no outside oracle exists",
}

FILES = (
    glob.glob("tests/pg_regress/sql/*.sql")
    + glob.glob("tests/properties/*.py")
    + glob.glob("tests/properties/*.mjs")
    + glob.glob("tests/*.sh")
    + glob.glob("tests/*.mjs")
    + glob.glob("tests/*.py")
)


def catalog(db):
    q = "SELECT DISTINCT p.proname" + docs_signatures.PUBLIC_FUNCTIONS + "\nORDER BY 1"
    out = subprocess.run(
        ["scripts/cluster.sh", "psql", "-X", "-q", "-A", "-t", "-d", db, "-c", q],
        check=True, capture_output=True, text=True,
    ).stdout
    return [line.strip() for line in out.splitlines() if line.strip()]


def covered_in(name, lines, marked):
    pat = re.compile(r"\b" + re.escape(name) + r"\s*\(")
    for i, line in enumerate(lines):
        if pat.search(line) and any(marked[max(0, i - WINDOW):i + WINDOW + 1]):
            return True
    return False


def main():
    db = sys.argv[1] if len(sys.argv) > 1 else "tinmerge_regress"
    names = catalog(db)
    if len(ALLOWED) > 5:
        sys.exit("more than five allowed functions")
    texts = {}
    for f in sorted(FILES):
        if f.endswith("function_coverage.py"):
            continue
        lines = open(f, encoding="utf-8").read().splitlines()
        texts[f] = (lines, [bool(MARKERS.search(l)) for l in lines])
    missing = []
    for n in names:
        if n in ALLOWED:
            continue
        where = [f for f, (lines, marked) in texts.items() if covered_in(n, lines, marked)]
        if not where:
            missing.append(n)
    stale = sorted(set(ALLOWED) - set(names))
    for n in stale:
        print("allowed but not in pg_proc: " + n)
    for n in missing:
        print("no test file compares %s with an oracle near its name" % n)
    if missing or stale:
        sys.exit(1)
    print("%d public functions, each near an oracle in a test file (%d allowed: %s)"
          % (len(names), len(ALLOWED), ", ".join(sorted(ALLOWED))))


if __name__ == "__main__":
    main()
