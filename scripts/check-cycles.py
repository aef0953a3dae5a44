#!/usr/bin/env python3
"""Fails if a Rust module uses another module that uses it back (directly or
through others), or if a module of the core uses one of a higher layer
(`LAYERS`: docs/architecture.md's order, lowest first). Reads `use crate::...`, `use super::...`, `use self::...` (a child's items
taken, or re-exported with `pub use`: a module that re-exports a child
uses it) and inline
`crate::a::b` paths of every .rs file under the given crate roots; a module is
a file (`a/b.rs` is `a::b`, `a/mod.rs` is `a`). Declaring a child (`mod x;`)
is not a use; `#[cfg(test)] mod tests` blocks are skipped.

    scripts/check-cycles.py src crates/tinmerge-core/src
"""
import re
import sys
from pathlib import Path


# The core's layers, lowest first: a module may use its own layer's and the
# layers below, never above (the crate root, which declares them all, aside).
LAYERS = [
    {"error", "geom", "interrupt", "memory", "progress", "par", "polygon"},
    {"io"},
    {"tin"},
    {"merge", "analysis"},
    {"serve", "render"},
]
CORE = "crates/tinmerge-core/src"


def layer_of(module: str):
    top = module.split("::")[0] if module else ""
    for k, names in enumerate(LAYERS):
        if top in names:
            return k
    return None


def module_of(root: Path, f: Path) -> str:
    parts = list(f.relative_to(root).with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts = parts[:-1]
    return "::".join(parts)


def expand(path: str):
    """`a::{b, c::{d, e}}` -> a::b, a::c::d, a::c::e (enough for our code)."""
    m = re.match(r"^(.*?)\{(.*)\}$", path, re.S)
    if not m:
        yield path.strip()
        return
    head, body = m.group(1), m.group(2)
    depth, cur, items = 0, "", []
    for ch in body:
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        if ch == "," and depth == 0:
            items.append(cur)
            cur = ""
        else:
            cur += ch
    items.append(cur)
    for it in items:
        it = it.strip()
        if it:
            yield from expand(head + it)


def strip(src: str) -> str:
    src = re.sub(r"//[^\n]*", "", src)
    i = src.find("#[cfg(test)]\nmod tests")
    return src[:i] if i >= 0 else src


def main(roots):
    graph = {}
    upward = []
    for root in map(Path, roots):
        mods = {module_of(root, f): f for f in root.rglob("*.rs")}
        for name, f in mods.items():
            src = strip(f.read_text())
            here = name.split("::") if name else []
            deps = set()
            paths = [p for u in re.findall(r"\buse\s+([^;]+);", src) for p in expand(u)]
            paths += re.findall(r"(?<![:\w])((?:crate|super)(?:::\w+)+)", src)
            for p in paths:
                p = re.sub(r"\s+as\s+\w+$", "", p.strip())
                segs = p.split("::")
                if segs[0] == "crate":
                    segs = segs[1:]
                elif segs[0] == "super":
                    segs = here[:-1] + segs[1:]
                elif segs[0] == "self":
                    # `use self::x::{..}` and `pub use self::x::..`: a
                    # child's items taken or re-exported
                    segs = here + segs[1:]
                else:
                    continue
                # the longest prefix that is a module of this crate
                for k in range(len(segs), 0, -1):
                    cand = "::".join(segs[:k])
                    if cand in mods:
                        if cand != name:
                            deps.add(cand)
                        break
            # paths through a child module (`faces::overlay_faces(..)` in `overlay`)
            prefix = name + "::" if name else ""
            for m in mods:
                if m.startswith(prefix) and m != name and "::" not in m[len(prefix):]:
                    child = m[len(prefix):]
                    if re.search(r"(?<![:\w])(?:self::)?" + child + r"::\w", src):
                        deps.add(m)
            graph[(str(root), name)] = {(str(root), d) for d in deps}
            if Path(root) == Path(CORE) and name:
                here_layer = layer_of(name)
                if here_layer is None:
                    upward.append(f"{name}: not in any layer of LAYERS")
                for d in sorted(deps):
                    there = layer_of(d)
                    if here_layer is not None and there is not None and there > here_layer:
                        upward.append(f"{name} (layer {here_layer}) uses {d} (layer {there})")
    # cycles: strongly connected components with more than one module
    index, low, stack, on, sccs, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                sccs.append(comp)

    sys.setrecursionlimit(10000)
    for v in list(graph):
        if v not in index:
            visit(v)
    if sccs:
        for comp in sccs:
            names = sorted(n or "<root>" for _, n in comp)
            print(f"import cycle in {comp[0][0]}: " + " <-> ".join(names))
            for _, n in sorted(comp):
                back = sorted(d for _, d in graph[(comp[0][0], n)] if (comp[0][0], d) in comp)
                print(f"    {n or '<root>'} uses {', '.join(back)}")
        sys.exit(1)
    if upward:
        print("upward imports in the core (layers: " + " < ".join("/".join(sorted(l)) for l in LAYERS) + "):")
        for u in upward:
            print("    " + u)
        sys.exit(1)
    print(f"no import cycles among {len(graph)} modules, and no upward import among the core's layers")


if __name__ == "__main__":
    main(sys.argv[1:] or ["src", "crates/tinmerge-core/src"])
