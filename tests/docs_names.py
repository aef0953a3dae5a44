#!/usr/bin/env python3
"""Every name the docs give in backticks that the code must have, it has
(issue 75: the docs named modules, functions and sizes that had moved).

Read: README.md and docs/*.md. Checked, each span in backticks that is
 - a path of the repository (starting with crates/, src/, scripts/, tests/,
   docs/, sql/ or .ci/; a `*` in it is a glob): it exists;
 - a SQL function (`tin_...`, alone or called): the installed extension
   has it (pg_proc, or a view of that name: pg_views), unless the span is a table or column the docs make;
 - a setting (`tinmerge.name`): pg_settings has it once the library is
   loaded;
 - a bare name with an underscore (`refine_parent_general`, `max_error`):
   some source, script, SQL file or code block of the project says it, or
   it is PostgreSQL's or a dependency's (`PG_NAMES`);
 - a Rust path (`module::item`, `Type::method`, a chain of them): its first
   part is a module (a file or folder of that name under the core's or the
   extension's src/) or a type (a struct, enum or trait defined there), and
   its last part is defined (fn, struct, enum, trait, type, const, static,
   mod, macro or a file of that name) within that module's files, or within
   the file defining that type; a path of a crate the project uses
   (`spade::`, `pgrx::`, ...) is not checked.

Usage: tests/docs_names.py DATABASE (the test cluster running:
scripts/cluster.sh psql). Exit 1 on any name not found, each printed with
its file and line.
"""
import glob
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORE = os.path.join(ROOT, "crates", "tinmerge-core")
SRC = [os.path.join(CORE, d) for d in ("src", "tests", "benches")] + [os.path.join(ROOT, "src")]
PATH_ROOTS = ("crates/", "src/", "scripts/", "tests/", "docs/", "sql/", ".ci/")
# crates and std paths the docs quote: not the project's to check
FOREIGN = {"spade", "pgrx", "geo", "wkb", "robust", "rayon", "serde", "std", "core", "gltf",
           "tiff", "png", "zstd", "xxhash_rust", "rustc_hash", "delaunator", "rand", "libc",
           "postgis", "pg_sys", "cargo", "liblwgeom", "thiserror", "alloc", "geo_traits",
           "MultiPoint"}
# names of PostgreSQL and of dependencies the docs quote bare
PG_NAMES = {"cpu_tuple_cost", "seq_page_cost", "parallel_setup_cost", "pg_dump", "dblink_send_query",
            "async_capable", "locate_with_hint_option_core"}
# SQL types: `raster::bytea` is a cast, not a Rust path
SQL_TYPES = {"bytea", "geometry", "geography", "raster", "text", "regclass", "int", "integer",
             "float8", "double", "numeric", "tin", "linetree", "json", "jsonb", "boolean", "bigint"}


def psql(db, sql):
    out = subprocess.run(["scripts/cluster.sh", "psql", "-qAt", "-d", db, "-c", sql],
                         cwd=ROOT, check=True, capture_output=True, text=True).stdout
    return set(out.split())


def rust_files():
    out = []
    for s in SRC:
        for d, _, fs in os.walk(s):
            out += [os.path.join(d, f) for f in fs if f.endswith(".rs")]
    return out


DEF = re.compile(r"\b(?:fn|struct|enum|trait|type|const|static|mod|macro_rules!)\s+([A-Za-z_][A-Za-z0-9_]*)")


def definitions(files, members):
    """Items defined in `files` (and, with `members`, the fields and
    variants of their types)."""
    names = set()
    for f in files:
        names.add(os.path.splitext(os.path.basename(f))[0])
        with open(f, encoding="utf-8") as h:
            text = h.read()
        names.update(DEF.findall(text))
        # re-exports: `pub use a::b::{c, d as e};`, `pub use a::name;`
        for body in re.findall(r"\bpub(?:\([a-z]+\))?\s+use\s+([^;]+);", text):
            names.update(re.findall(r"(?:\bas\s+)?([A-Za-z_][A-Za-z0-9_]*)\s*(?=[,}]|$)", body.strip()))
        if members:
            # enum variants (`Name,` `Name(` `Name {`) and fields (`name:`)
            names.update(re.findall(r"^\s*([A-Z][A-Za-z0-9_]*)\s*[({,]", text, re.M))
            names.update(re.findall(r"^\s*(?:pub(?:\([a-z]+\))?\s+)?([a-z_][a-z0-9_]*)\s*:(?!:)", text, re.M))
    return names


def main():
    db = sys.argv[1] if len(sys.argv) > 1 else "tinmerge_regress"
    funcs = psql(db, "SELECT DISTINCT proname FROM pg_proc WHERE proname LIKE 'tin%' "
                     "UNION SELECT opcname FROM pg_opclass WHERE opcname LIKE 'tin%' "
                     "UNION SELECT viewname FROM pg_views WHERE viewname LIKE 'tin%'")
    settings = psql(db, "LOAD 'tinmerge'; SELECT name FROM pg_settings WHERE name LIKE 'tinmerge.%'")
    files = rust_files()
    # modules: files and folders by name; types: the files defining them
    modules = {}
    for f in files:
        rel = os.path.relpath(f, ROOT)
        parts = rel.split(os.sep)
        for k, p in enumerate(parts):
            name = os.path.splitext(p)[0]
            if name in ("mod", "lib", "main"):
                continue
            base = os.path.join(ROOT, *parts[:k + 1])
            modules.setdefault(name, set()).update(
                [base] if base.endswith(".rs") else [x for x in files if x.startswith(base + os.sep)])
    types = {}
    for f in files:
        with open(f, encoding="utf-8") as h:
            text = h.read()
            found = re.findall(r"\b(?:struct|enum|trait|type)\s+([A-Z][A-Za-z0-9_]*)", text)
            # and the files with its methods: `impl Name`, `impl<..> Name<..>`, `impl X for Name`
            found += re.findall(r"\bimpl(?:<[^>]*>)?\s+(?:[A-Za-z0-9_:<>, ']+\s+for\s+)?([A-Z][A-Za-z0-9_]*)", text)
            for t in found:
                types.setdefault(t, set()).add(f)
    defs_cache = {}

    def defined_in(fs, name, members=False):
        key = (tuple(sorted(fs)), members)
        if key not in defs_cache:
            defs_cache[key] = definitions(fs, members)
        return name in defs_cache[key]

    # tables and columns the docs create are not functions
    made = set()
    docs = [os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "docs", "*.md")))
    for d in docs:
        with open(d, encoding="utf-8") as h:
            made.update(re.findall(r"(?i)create\s+(?:temp\s+|unlogged\s+)?(?:table|view|index)\s+(?:if not exists\s+)?([a-z_][a-z0-9_]*)", h.read()))
    # every identifier the project's sources, scripts and SQL say, and
    # the docs' own code blocks
    said = set(PG_NAMES)
    others = glob.glob(os.path.join(ROOT, "sql", "**", "*.sql"), recursive=True)
    others += glob.glob(os.path.join(ROOT, "tests", "**", "*.*"), recursive=True)
    others += glob.glob(os.path.join(ROOT, "scripts", "*"))
    for f in files + [x for x in others if os.path.isfile(x) and not x.endswith((".tif", ".png", ".gz"))]:
        with open(f, encoding="utf-8", errors="replace") as h:
            said.update(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", h.read()))
    # and the names of its files (a pg_regress test: `tiles_over_data`)
    said.update(os.path.splitext(os.path.basename(f))[0] for f in files + others)
    for d in docs:
        with open(d, encoding="utf-8") as h:
            for block in re.findall(r"```.*?```", h.read(), re.S):
                said.update(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", block))
    bad = []
    checked = {"path": 0, "function": 0, "setting": 0, "rust": 0, "name": 0}
    for d in docs:
        rel = os.path.relpath(d, ROOT)
        in_code = False
        with open(d, encoding="utf-8") as h:
            lines = h.read().split("\n")
        for n, line in enumerate(lines, 1):
            if line.lstrip().startswith("```"):
                in_code = not in_code
                continue
            if in_code:
                continue
            for span in re.findall(r"`([^`\n]+)`", line):
                s = span.strip()
                if s.startswith(PATH_ROOTS) and re.fullmatch(r"[\w./*+-]+", s):
                    checked["path"] += 1
                    p = s.rstrip("/")
                    # tests/ and benches/ of the core are named from its folder too
                    if not (glob.glob(os.path.join(ROOT, p)) or glob.glob(os.path.join(CORE, p))):
                        bad.append(f"{rel}:{n}: no file {s}")
                    continue
                m = re.fullmatch(r"(tin_[a-z0-9_]+)(\(.*\))?(\s.*)?", s)
                if m:
                    name = m.group(1)
                    checked["function"] += 1
                    # else a table the docs make, or a Rust item or module
                    # of that name (`tin_type`, `tin_level`)
                    if name not in funcs and not (name in made or name in modules
                                                  or defined_in(files, name)):
                        bad.append(f"{rel}:{n}: no SQL function {name}")
                    continue
                m = re.fullmatch(r"(tinmerge\.[a-z_]+)(\s*=.*)?", s)
                if m and not s.endswith(".so"):
                    checked["setting"] += 1
                    if m.group(1) not in settings:
                        bad.append(f"{rel}:{n}: no setting {m.group(1)}")
                    continue
                m = re.fullmatch(r"([a-z][a-z0-9]*_[a-z0-9_]+)(\(\))?", s)
                if m:
                    checked["name"] += 1
                    if m.group(1) not in said:
                        bad.append(f"{rel}:{n}: {s}: nothing in the project says it")
                    continue
                m = re.fullmatch(r"([A-Za-z_][A-Za-z0-9_]*(?:::[A-Za-z_][A-Za-z0-9_]*)+)(\(.*\))?(!)?", s)
                if m:
                    parts = m.group(1).split("::")
                    if parts[0] in FOREIGN or parts[0] in ("crate", "super", "self", "tinmerge_core", "tinmerge"):
                        parts = parts[1:] if parts[0] in ("crate", "tinmerge_core", "tinmerge") else []
                    if len(parts) < 2 or parts[-1] in SQL_TYPES:
                        continue
                    first, last = parts[0], parts[-1]
                    members = first not in modules and first in types
                    if first in modules:
                        scope = modules[first]
                    elif first in types:
                        scope = types[first]
                    else:
                        checked["rust"] += 1
                        bad.append(f"{rel}:{n}: {s}: no module or type {first}")
                        continue
                    checked["rust"] += 1
                    if not defined_in(scope, last, members):
                        bad.append(f"{rel}:{n}: {s}: {last} is not defined in {first}")
    for b in bad:
        print(b)
    print(f"docs names: {checked['path']} paths, {checked['function']} SQL functions, "
          f"{checked['setting']} settings, {checked['rust']} Rust paths, {checked['name']} other names "
          f"checked; {len(bad)} not found")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
