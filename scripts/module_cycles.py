#!/usr/bin/env python3
"""Cycles among the modules of each crate (issue 43: "no module cycle anywhere").

A crate's modules are its files (`src/a.rs` or `src/a/mod.rs` is `a`, `src/a/b.rs` is `a::b`)
and the inline `mod x { … }` blocks are part of their file. Module A depends on its sibling B
(two children of the same parent) when any code inside A names something inside B through
`crate::…`, `super::…` or `self::…` paths, `use` trees included (`use crate::{b::X, c}`),
and a name a module re-exports counts where it is defined: `crate::render::Picture`, when
`render` has `pub use scene::Picture`, names `render::scene` (every `use` of a module is
followed, so a child naming its parent's import of a sibling's item depends on that sibling).
Each parent's children then form a graph; a strongly connected component of two or more is a
cycle, reported as `crate: parent: a <-> b <-> …`.

    python3 scripts/module_cycles.py    # list every cycle; exit 1 on any

The tree has none (issue 43: the last were broken on 2026-12-07); a new one fails CI.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
PATH_START = re.compile(rf"\b(crate|super|self)((?:::(?:super|{IDENT}))*)::(\{{|{IDENT})")


def crates() -> list[tuple[str, Path]]:
    found = []
    for manifest in sorted(ROOT.glob("crates/*/Cargo.toml")) + [ROOT / "pyext" / "Cargo.toml"]:
        src = manifest.parent / "src"
        name = re.search(r'^name\s*=\s*"([^"]+)"', manifest.read_text(encoding="utf-8"), re.M)
        if src.is_dir() and name:
            found.append((name.group(1), src))
    return found


def module_of(src: Path, file: Path) -> tuple[str, ...]:
    rel = file.relative_to(src).with_suffix("")
    parts = rel.parts
    if parts in (("lib",), ("main",)):
        return ()
    if parts[-1] == "mod":
        parts = parts[:-1]
    return tuple(parts)


def strip_comments(text: str) -> str:
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return "\n".join(line.split("//", 1)[0] for line in text.splitlines())


def use_tree_heads(text: str, start: int) -> list[list[str]]:
    """The paths inside a `{…}` use tree beginning at text[start] == '{': each item's leading
    path segments (`{b::X, c, d::{e, f}}` → [b, X], [c], [d])."""
    depth, item, items, i = 0, "", [], start
    while i < len(text):
        ch = text[i]
        if ch == "{":
            depth += 1
            if depth > 1:
                item += ch
        elif ch == "}":
            depth -= 1
            if depth == 0:
                items.append(item)
                break
            item += ch
        elif ch == "," and depth == 1:
            items.append(item)
            item = ""
        else:
            item += ch
        i += 1
    heads = []
    for it in items:
        segs = re.findall(rf"{IDENT}|\{{", it.strip())
        path = []
        for s in segs:
            if s == "{" or s == "as":
                break
            path.append(s)
        if path:
            heads.append(path)
    return heads


def references(text: str, here: tuple[str, ...], is_dir_module: bool) -> list[tuple[str, ...]]:
    """Absolute module paths (as segment tuples, possibly ending in an item name) `text` names."""
    found = []
    # The module `self::` and `super::` are relative to: a file is its own module.
    for m in PATH_START.finditer(text):
        root, middle, tail = m.group(1), m.group(2), m.group(3)
        segs = [s for s in middle.split("::") if s]
        if root == "crate":
            base: list[str] = []
        else:
            base = list(here)
            if root == "super":
                base = base[:-1]
        for s in segs:
            if s == "super":
                base = base[:-1]
            else:
                base.append(s)
        if tail == "{":
            for head in use_tree_heads(text, m.end() - 1):
                found.append(tuple(base + head))
        else:
            found.append(tuple(base + [tail]))
    return found


USE = re.compile(r"\buse\s+([^;]+);")


def use_leaves(tree: str) -> list[tuple[list[str], str]]:
    """The leaves of a use tree as (path segments, name it is known by): `a::{b as c, d::e}`
    → ([a, b], c), ([a, d, e], e); globs and `self` leaves are left out."""
    tree = re.sub(r"\s+", " ", tree).strip()
    depth, start = 0, 0
    brace = tree.find("{")
    if brace < 0:
        m = re.fullmatch(rf"((?:{IDENT}::)*{IDENT})(?: as ({IDENT}))?", tree)
        if not m:
            return []
        segs = m.group(1).split("::")
        name = m.group(2) or segs[-1]
        return [] if segs[-1] == "self" or name == "_" else [(segs, name)]
    prefix = [s for s in tree[:brace].strip().rstrip(":").split("::") if s]
    inner, out = tree[brace + 1 : tree.rfind("}")], []
    for i, ch in enumerate(inner + ","):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == "," and depth == 0:
            item = inner[start:i].strip()
            start = i + 1
            if item == "self":
                out.append((prefix, prefix[-1]))
            elif item and item != "*":
                out.extend((prefix + segs, name) for segs, name in use_leaves(item))
    return out


def imports_of(text: str, here: tuple[str, ...], modules) -> dict[str, tuple[str, ...]]:
    """The names a module's `use` declarations bring in, each to the absolute path it stands
    for (external crates left out)."""
    found = {}
    for m in USE.finditer(text):
        for segs, name in use_leaves(m.group(1)):
            root, rest = segs[0], segs[1:]
            if root == "crate":
                base: list[str] = []
            elif root in ("self", "super"):
                base = list(here) if root == "self" else list(here[:-1])
            elif here + (root,) in modules:
                base, rest = list(here), segs
            else:
                continue
            for s in rest:
                base = base[:-1] if s == "super" else base + [s]
            found[name] = tuple(base)
    return found


def graph_of(src: Path) -> dict[tuple[str, ...], set[tuple[str, ...]]]:
    modules: dict[tuple[str, ...], Path] = {}
    for f in sorted(src.rglob("*.rs")):
        # `lib.rs` is the crate's root; a `main.rs` beside it is another crate (the binary).
        modules.setdefault(module_of(src, f), f)
    texts = {
        m: strip_comments(f.read_text(encoding="utf-8", errors="replace")) for m, f in modules.items()
    }
    imports = {m: imports_of(t, m, modules) for m, t in texts.items()}

    def resolve(ref: tuple[str, ...]) -> tuple[str, ...] | None:
        """The module a path names: the longest prefix that is a module, followed through
        that module's own `use` of the next segment (a re-export) to where it is defined."""
        for _ in range(16):
            target = next((ref[:n] for n in range(len(ref), -1, -1) if ref[:n] in modules), None)
            if target is None or len(ref) == len(target):
                return target
            via = imports[target].get(ref[len(target)])
            if via is None:
                return target
            ref = via + ref[len(target) + 1 :]
        return None

    edges: dict[tuple[str, ...], set[tuple[str, ...]]] = {}
    for module, file in modules.items():
        text = texts[module]
        for ref in references(text, module, file.name == "mod.rs"):
            # The module the reference names, through re-exports.
            target = resolve(ref)
            if target is None or target == module:
                continue
            # The sibling pair under their deepest common parent.
            common = 0
            while common < min(len(module), len(target)) and module[common] == target[common]:
                common += 1
            if common >= len(module) or common >= len(target):
                continue  # one contains the other: a parent and its own child
            a, b = module[: common + 1], target[: common + 1]
            edges.setdefault(a, set()).add(b)
    return edges


def cycles(edges: dict[tuple[str, ...], set[tuple[str, ...]]]) -> list[list[tuple[str, ...]]]:
    """Strongly connected components of two or more (Tarjan)."""
    index: dict = {}
    low: dict = {}
    stack: list = []
    on: set = set()
    out = []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
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
                out.append(sorted(comp))

    sys.setrecursionlimit(10_000)
    for v in sorted(set(edges) | {w for ws in edges.values() for w in ws}):
        if v not in index:
            visit(v)
    return out


def all_cycles() -> list[str]:
    found = []
    for name, src in crates():
        for comp in cycles(graph_of(src)):
            parent = "::".join(comp[0][:-1]) or "crate"
            found.append(f"{name}: {parent}: " + " <-> ".join(c[-1] for c in comp))
    return sorted(found)


def main(argv: list[str] | None = None) -> int:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    found = all_cycles()
    for c in found:
        print(f"module cycle: {c}")
    print(f"module cycles: {len(found)}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
