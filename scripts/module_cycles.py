#!/usr/bin/env python3
"""Cycles among a crate's top-level modules: `use crate::X` / `crate::X::` edges between the
first-level modules of each crate under crates/ (a file or folder under src/), strongly
connected components of more than one module reported."""
import re, sys, os
from pathlib import Path

root = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
total = 0
for crate in sorted((root / "crates").iterdir()):
    src = crate / "src"
    if not src.is_dir():
        continue
    mods = {p.stem if p.is_file() else p.name for p in src.iterdir()
            if (p.suffix == ".rs" and p.stem not in ("lib", "main")) or (p.is_dir() and p.name != "snapshots")}
    edges = {m: set() for m in mods}
    for m in mods:
        paths = [src / f"{m}.rs"] if (src / f"{m}.rs").exists() else []
        if (src / m).is_dir():
            paths += list((src / m).rglob("*.rs"))
        for p in paths:
            if p.stem == "tests" or "tests" in p.parts[len(src.parts):]:
                continue
            # Code only: doc links and comments are not dependencies; nor are tests.
            text = re.sub(r"//[^\n]*", "", p.read_text())
            text = text.split("#[cfg(test)]")[0]
            for t in re.findall(r"crate::([a-z_0-9]+)", text):
                if t in mods and t != m:
                    edges[m].add(t)
            for block in re.findall(r"use crate::\{([^;]*)\}", text, re.S):
                for t in re.findall(r"(?:^|[\s,{])([a-z_0-9]+)(?=::|\s*[,}]|$)", block):
                    if t in mods and t != m:
                        edges[m].add(t)
    # Tarjan
    index, low, stack, on, sccs, i = {}, {}, [], set(), [], [0]
    def strong(v):
        index[v] = low[v] = i[0]; i[0] += 1; stack.append(v); on.add(v)
        for w in edges[v]:
            if w not in index:
                strong(w); low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop(); on.discard(w); comp.append(w)
                if w == v: break
            if len(comp) > 1:
                sccs.append(sorted(comp))
    sys.setrecursionlimit(10000)
    for v in sorted(mods):
        if v not in index:
            strong(v)
    for c in sccs:
        total += 1
        print(f"{crate.name}: cycle among {', '.join(c)}")
print(f"{total} cycle(s)")
