#!/usr/bin/env python3
"""Dependencies a crate declares and never names (in the spirit of cargo-machete).

For every workspace crate, each dependency's library name (dashes as underscores, renames
honoured) must appear as a word in the Rust sources that can use it: `src/`, `build.rs` and the
crate's targets for normal and build dependencies; also `tests/`, `benches/` and `examples/`
for dev-dependencies. A dependency named nowhere is dead weight (build time, the SOUP list,
the attack surface) and fails, unless ALLOWED says why it is declared without being named.

    python3 scripts/unused_deps.py          # exit 1 naming each unused dependency
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# (crate, dependency) → why it is declared although no source names it.
ALLOWED: dict[tuple[str, str], str] = {}


def sources(crate_dir: Path, dev: bool) -> str:
    roots = ["src", "build.rs"] + (["tests", "benches", "examples"] if dev else [])
    text = []
    for root in roots:
        path = crate_dir / root
        files = [path] if path.is_file() else sorted(path.rglob("*.rs")) if path.is_dir() else []
        text += [f.read_text(encoding="utf-8", errors="replace") for f in files]
    return "\n".join(text)


def unused() -> list[str]:
    meta = json.loads(
        subprocess.run(
            ["cargo", "metadata", "--format-version", "1", "--offline"],
            cwd=ROOT, check=True, capture_output=True, text=True,
        ).stdout
    )
    # A package's library name as sources write it (rustls-webpki is `webpki`).
    lib_names = {
        p["name"]: t["name"].replace("-", "_")
        for p in meta["packages"]
        for t in p["targets"]
        if {"lib", "rlib", "proc-macro"} & set(t["kind"])
    }
    members = set(meta["workspace_members"])
    found = []
    for package in meta["packages"]:
        if package["id"] not in members:
            continue
        crate_dir = Path(package["manifest_path"]).parent
        # A package whose targets live outside src/ (the workspace tests' package keeps them and
        # the modules its library includes at its root): every Rust file of it counts.
        outside = [t for t in package["targets"] if not Path(t["src_path"]).is_relative_to(crate_dir / "src")]
        extra = "\n".join(
            f.read_text(encoding="utf-8", errors="replace")
            for f in (sorted(crate_dir.rglob("*.rs")) if outside else [])
            if "target" not in f.relative_to(crate_dir).parts
        )
        normal_text = sources(crate_dir, dev=False) + extra
        dev_text = normal_text + sources(crate_dir, dev=True)
        for dep in package["dependencies"]:
            ident = (dep.get("rename") or lib_names.get(dep["name"], dep["name"])).replace("-", "_")
            text = dev_text if dep.get("kind") == "dev" else normal_text
            if re.search(rf"\b{re.escape(ident)}\b", text):
                continue
            if (package["name"], dep["name"]) in ALLOWED:
                continue
            kind = dep.get("kind") or "normal"
            found.append(f"{package['name']}: {kind} dependency `{dep['name']}` is named by no source")
    return found


def main() -> int:
    problems = unused()
    for p in problems:
        print(f"unused dependency: {p}")
    if problems:
        print(f"unused dependencies: {len(problems)} (remove them, or say why in ALLOWED)")
        return 1
    print("unused dependencies: none")
    return 0


if __name__ == "__main__":
    sys.exit(main())
