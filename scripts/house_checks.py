#!/usr/bin/env python3
"""The house rules a reader can check mechanically; exits 1 when one is broken:

1. no source file under crates/*/src longer than 700 lines;
2. no import circle between the source files of a crate (below);
3. no line of docs/BENCHMARKS.md over 200 characters outside tables.

Import circles are read from the `use` lines. A file imports another when one of its `use` paths (`crate::a::b`, `super::x`, `self::x`, or a
child module's name) resolves to the module that file defines. A child importing from one of
its ancestors (`use super::System` in a module's own folder) is how a module shares its types
with its parts and is not counted; every other pair of files that import each other, directly or
around a longer loop, is printed. Exits 1 when there is one.

Usage: scripts/house_checks.py   (from anywhere; checks the repository it is in)
"""

import re
import sys
from pathlib import Path

USE = re.compile(r"^\s*(?:pub(?:\([^)]*\))?\s+)?use\s+([^;]+);", re.M)


def module_files(src):
    """{module path tuple: file} for a crate's src directory."""
    mods = {}
    for f in src.rglob("*.rs"):
        rel = f.relative_to(src).with_suffix("")
        parts = list(rel.parts)
        if parts in (["lib"], ["main"]):
            parts = []
        elif parts[-1] == "mod":
            parts = parts[:-1]
        mods[tuple(parts)] = f
    return mods


def paths_of(tree):
    """The paths a `use` tree names, as lists of segments (`a::{b, c::d}` → a::b, a::c::d)."""
    tree = re.sub(r"\s+", "", tree)
    depth, start, parts = 0, 0, []
    brace = tree.find("{")
    if brace < 0:
        return [tree.split(" as ")[0].split("::")]
    prefix, inner = tree[:brace], tree[brace + 1:tree.rfind("}")]
    for i, ch in enumerate(inner + ","):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == "," and depth == 0:
            if inner[start:i]:
                parts.append(inner[start:i])
            start = i + 1
    out = []
    for p in parts:
        for sub in paths_of(p):
            out.append([s for s in prefix.rstrip(":").split("::") if s] + sub)
    return out


def resolve(segments, here, mods):
    """The longest module prefix of `segments` seen from module `here`, or None."""
    if not segments:
        return None
    if segments[0] == "crate":
        base, rest = (), segments[1:]
    elif segments[0] in ("super", "self"):
        base = here
        while segments and segments[0] in ("super", "self"):
            if segments[0] == "super":
                base = base[:-1]
            segments = segments[1:]
        rest = segments
    elif here + (segments[0],) in mods:
        base, rest = here, segments
    else:
        return None
    best = base if base in mods else None
    for i in range(1, len(rest) + 1):
        if base + tuple(rest[:i]) in mods:
            best = base + tuple(rest[:i])
    return best


def cycles(mods):
    here_of = {f: m for m, f in mods.items()}
    edges = {m: set() for m in mods}
    for m, f in mods.items():
        text = re.sub(r"//.*", "", f.read_text())
        for tree in USE.findall(text):
            for segs in paths_of(tree):
                t = resolve(segs, m, mods)
                # A module importing its own ancestor shares that ancestor's types: allowed.
                if t is not None and t != m and m[:len(t)] != t:
                    edges[m].add(t)
    # Tarjan's strongly connected components.
    index, low, stack, on, comps, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
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
                comps.append(comp)

    sys.setrecursionlimit(10000)
    for v in mods:
        if v not in index:
            visit(v)
    return [[mods[m] for m in c] for c in comps]


MAX_LINES = 700
MAX_DOC_LINE = 200


def main():
    repo = Path(__file__).resolve().parent.parent
    broken = 0
    for f in sorted(repo.glob("crates/*/src/**/*.rs")):
        lines = f.read_text().count("\n")
        if lines > MAX_LINES:
            broken += 1
            print(f"too long: {f.relative_to(repo)} has {lines} lines (at most {MAX_LINES})")
    for src in sorted(repo.glob("crates/*/src")):
        for comp in cycles(module_files(src)):
            broken += 1
            print("import circle: " + " ↔ ".join(str(f.relative_to(repo)) for f in sorted(comp)))
    bench = repo / "docs" / "BENCHMARKS.md"
    for no, line in enumerate(bench.read_text().split("\n"), 1):
        if len(line) > MAX_DOC_LINE and not line.startswith("|"):
            broken += 1
            print(f"long line: docs/BENCHMARKS.md:{no} has {len(line)} characters (at most {MAX_DOC_LINE})")
    print(f"house checks: {broken} broken")
    sys.exit(1 if broken else 0)


if __name__ == "__main__":
    main()
