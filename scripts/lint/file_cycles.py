#!/usr/bin/env python3
"""File-level import cycles in the workspace's Rust crates (STYLE: no import cycles between files).

Each `.rs` file under a crate's `src/` is one module. File A depends on file B when A names a
path that resolves to B's module: `use crate::x::y`, `use super::z`, an inline `crate::x::f()`,
or a `use` of a sibling module (`use self::…`). Each path is resolved to the longest module
prefix that is a file. Not edges: a module's `mod` lines and `pub use` re-exports (a parent
showing its children's items is the module's face, not a use), and a child naming its
ancestor's own items (`super::Frontend` in frontend/builder.rs) — those are the file tree's
parent/child structure. What is left is a cycle between files that are not one another's
ancestor: two siblings, or files in different folders, each using the other.

Usage: file_cycles.py [CRATE_SRC_DIR...]   (default: every crates/*/src and src/)
Exit status 1 when a cycle is found; each cycle is printed with its files.
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]

USE_RE = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?use\s+([^;]+);", re.M | re.S)
INLINE_RE = re.compile(r"\b((?:crate|super)(?:::(?:super|[A-Za-z_][A-Za-z0-9_]*))+)")
MOD_RE = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?mod\s+([a-z_0-9]+)\s*;", re.M)


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r'"(\\.|[^"\\])*"', '""', text)
    return text


def modules(src):
    """{module path tuple: file} of one crate, following `mod x;` from lib.rs/main.rs."""
    out = {}

    def visit(path, file):
        out[path] = file
        text = strip_comments(file.read_text())
        folder = file.parent if file.name in ("mod.rs", "lib.rs", "main.rs") else file.with_suffix("")
        for m in MOD_RE.finditer(text):
            name = m.group(3)
            for cand in (folder / f"{name}.rs", folder / name / "mod.rs"):
                if cand.is_file():
                    visit(path + (name,), cand)
                    break

    for root in ("lib.rs", "main.rs"):
        if (src / root).is_file():
            visit((), src / root)
    return out


def expand(tree):
    """The paths a `use` tree names: `a::{b, c::d}` -> [a::b, a::c::d]."""
    tree = re.sub(r"\s+", "", re.sub(r"\s+as\s+\w+", "", tree))
    if "{" not in tree:
        return [tree]
    i = tree.index("{")
    head, body = tree[:i], tree[i + 1:tree.rindex("}")]
    parts, depth, cur = [], 0, ""
    for ch in body:
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
            continue
        depth += ch == "{"
        depth -= ch == "}"
        cur += ch
    parts.append(cur)
    return [p for part in parts if part for p in expand(head + part)]


def resolve(path, here, mods):
    """The module (tuple) a `crate::`/`super::`/`self::` path lands in, or None."""
    segs = [s for s in path.split("::") if s]
    if not segs:
        return None
    if segs[0] == "crate":
        base, segs = (), segs[1:]
    elif segs[0] in ("super", "self"):
        base = here
        while segs and segs[0] in ("super", "self"):
            if segs[0] == "super":
                base = base[:-1]
            segs = segs[1:]
    elif (here + (segs[0],)) in mods:  # `use child::X` inside a module
        base = here
    else:
        return None
    best = base
    cur = base
    for s in segs:
        cur = cur + (s,)
        if cur in mods:
            best = cur
        else:
            break
    return best


def edges(mods):
    out = {m: set() for m in mods}
    for here, file in mods.items():
        text = strip_comments(file.read_text())
        paths = []
        for m in USE_RE.finditer(text):
            if m.group(1) and m.group(1).strip().startswith("pub"):
                continue  # a re-export
            paths.extend(expand(m.group(3)))
        body = USE_RE.sub("", text)
        paths.extend(m.group(1) for m in INLINE_RE.finditer(body))
        for p in paths:
            target = resolve(p, here, mods)
            if target is None or target == here:
                continue
            # Parent/child structure: a file and its ancestors.
            if here[: len(target)] == target or target[: len(here)] == here:
                continue
            out[here].add(target)
    return out


def cycles(graph):
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, comps, n = {}, {}, [], set(), [], [0]

    def strong(v):
        index[v] = low[v] = n[0]
        n[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                strong(w)
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
                comps.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in graph:
        if v not in index:
            strong(v)
    return comps


def main(argv):
    srcs = [pathlib.Path(a) for a in argv] or (
        sorted(ROOT.glob("crates/*/src")) + sorted(ROOT.glob("plugins/*/src")) + [ROOT / "src"])
    found = 0
    for src in srcs:
        mods = modules(src)
        for comp in cycles(edges(mods)):
            found += 1
            files = [str(mods[m].relative_to(ROOT)) for m in comp]
            print(f"cycle of {len(files)} files: " + " ".join(files))
    if found:
        print(f"{found} cycle(s) between files; move the shared piece down (STYLE: no import cycles)")
        return 1
    print(f"no import cycle between files in {len(srcs)} crate source folders")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
