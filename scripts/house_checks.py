#!/usr/bin/env python3
"""The house rules a reader can check mechanically; exits 1 when one is broken:

1. no source file under crates/*/src longer than 700 lines;
2. no import circle between the source files of a crate (below);
3. no line of docs/BENCHMARKS.md over 200 characters outside tables, and at most 800 lines;
4. no non-test function under crates/*/src over 100 lines unless a comment just above it says
   why ("long because …");
5. the repository stands alone: no citation of the source documents by file number
   (the word seed and a three-digit number), of the project's issues (issue and a number) or of its design brief, and no absolute
   path of this machine, in crates/, docs/, scripts/, examples/, tests/ or README.md.

Import circles are read from the `use` lines and from paths written inline in the code
(`crate::a::b(…)`, `super::x::f(…)`, a child module's `x::f(…)`). A file imports another when
one of those paths resolves to the module that file defines. A child importing from one of
its ancestors (`use super::System` in a module's own folder) is how a module shares its types
with its parts and is not counted; every other pair of files that import each other, directly or
around a longer loop, is printed. Exits 1 when there is one.

Usage: scripts/house_checks.py   (from anywhere; checks the repository it is in)
"""

import re
import sys
from pathlib import Path

USE = re.compile(r"^\s*(?:pub(?:\([^)]*\))?\s+)?use\s+([^;]+);", re.M)
# A path written in code: `a::b` or longer, its first segment a name (module paths are snake case).
INLINE = re.compile(r"(?<![\w:])[a-z_][a-z0-9_]*(?:::[A-Za-z_][A-Za-z0-9_]*)+")


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
        trees = [segs for tree in USE.findall(text) for segs in paths_of(tree)]
        inline = [p.split("::") for p in INLINE.findall(USE.sub("", text))]
        for segs in trees + inline:
            if True:
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
MAX_DOC_LINES = 800
MAX_FN_LINES = 100
FN = re.compile(r"^(\s*)(?:pub(?:\([^)]*\))?\s+)?(?:const\s+)?(?:unsafe\s+)?fn\s+(\w+)")
# What the repository must not cite or name (rule 5); this file is exempt, it spells them.
NOT_ALONE = r"seeds? 00[0-4]|issues? \"?[0-9]+|issue \"core\"|DESIGN\.md|/work/|\.\./shared"


def long_functions(f):
    """(name, first line, length) of the non-test functions of a file over MAX_FN_LINES lines
    without a "long because" comment in the comment lines just above them."""
    lines = f.read_text().split("\n")
    out = []
    for i, line in enumerate(lines):
        if re.match(r"\s*#\[cfg\(test\)\]", line) and re.match(
            r"\s*(pub\s+)?mod\s+\w+\s*\{", lines[i + 1] if i + 1 < len(lines) else ""
        ):
            break  # an inline tests module closes the file
        m = FN.match(line)
        if not m:
            continue
        indent = len(m.group(1))
        j = i
        while j < len(lines) and not lines[j].rstrip().endswith(("{", ";")):
            j += 1
        if j == len(lines) or lines[j].rstrip().endswith(";"):
            continue
        k = j + 1
        while k < len(lines) and not (
            lines[k].startswith(" " * indent + "}") and len(lines[k]) - len(lines[k].lstrip()) == indent
        ):
            k += 1
        length = k - i + 1
        above = []
        a = i - 1
        while a >= 0 and lines[a].strip().startswith(("//", "#[")):
            above.append(lines[a])
            a -= 1
        if length > MAX_FN_LINES and "long because" not in " ".join(above).lower():
            out.append((m.group(2), i + 1, length))
    return out


def not_alone(repo):
    """`file:line: text` of each place that breaks rule 5 (from git's tracked files)."""
    import subprocess

    me = Path(__file__).resolve().relative_to(repo)
    r = subprocess.run(
        ["git", "grep", "-n", "-I", "-i", "-E", NOT_ALONE, "--", "crates", "docs", "scripts",
         "examples", "tests", "README.md", f":!{me}"],
        cwd=repo, capture_output=True, text=True,
    )
    return [l for l in r.stdout.splitlines() if l]


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
    for f in sorted(repo.glob("crates/*/src/**/*.rs")):
        if f.name == "tests.rs" or "tests" in f.relative_to(repo).parts[3:-1]:
            continue
        for name, line, length in long_functions(f):
            broken += 1
            print(f"long function: {f.relative_to(repo)}:{line} `{name}` has {length} lines "
                  f"(at most {MAX_FN_LINES} without a \"long because\" comment above it)")
    for place in not_alone(repo):
        broken += 1
        print(f"does not stand alone: {place}")
    bench = repo / "docs" / "BENCHMARKS.md"
    text = bench.read_text()
    if text.count("\n") > MAX_DOC_LINES:
        broken += 1
        print(f"too long: docs/BENCHMARKS.md has {text.count(chr(10))} lines (at most {MAX_DOC_LINES})")
    for no, line in enumerate(text.split("\n"), 1):
        if len(line) > MAX_DOC_LINE and not line.startswith("|"):
            broken += 1
            print(f"long line: docs/BENCHMARKS.md:{no} has {len(line)} characters (at most {MAX_DOC_LINE})")
    print(f"house checks: {broken} broken")
    sys.exit(1 if broken else 0)


if __name__ == "__main__":
    main()
