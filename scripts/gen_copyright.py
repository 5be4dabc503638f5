#!/usr/bin/env python3
"""Write the Debian package's copyright file (DEP-5, machine-readable) from the build itself.

Names every Rust crate compiled into `/usr/bin/telerehab` -- the graph of the `telerehab`
package's normal dependencies as `cargo metadata --filter-platform <host>` resolves it (so
dev-dependencies, build-only tools and the Python extension's crates are left out) -- with its
licence expression and authors, the console's vendored browser libraries
(crates/hub/console/vendor/*/LICENSE), and our own licence (the workspace's `license`).

    python3 scripts/gen_copyright.py [--metadata FILE] [--out FILE]

Without --metadata it runs `cargo metadata` itself (offline when the sources are present).
Nothing here is hand-kept: a crate added to the build appears at the next package build.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VENDOR = ROOT / "crates" / "hub" / "console" / "vendor"
COMMON_LICENSES = Path("/usr/share/common-licenses")
FORMAT = "https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/"

# A phrase each licence's text carries, to find that text among a crate's licence files.
SIGNATURES = {
    "MIT": "Permission is hereby granted, free of charge",
    "BSD-3-Clause": "Neither the name",
    "BSD-2-Clause": "Redistributions in binary form must reproduce",
    "ISC": "Permission to use, copy, modify, and",
    "Zlib": "This software is provided 'as-is'",
    "Unicode-3.0": "UNICODE LICENSE V3",
    "Unlicense": "This is free and unencumbered software",
    "0BSD": "Permission to use, copy, modify, and/or distribute this software for any",
    "BSL-1.0": "Boost Software License",
    "OFL-1.1": "SIL OPEN FONT LICENSE",
    "Ubuntu-font-1.0": "UBUNTU FONT LICENCE",
    "LLVM-exception": "LLVM Exceptions to the Apache 2.0 License",
}
# SPDX identifier -> the file under /usr/share/common-licenses holding its text on Debian.
IN_COMMON = {
    "Apache-2.0": "Apache-2.0",
    "MPL-2.0": "MPL-2.0",
    "GPL-2.0-only": "GPL-2",
    "CC0-1.0": "CC0-1.0",
}


def host_triple() -> str:
    out = subprocess.run(["rustc", "-vV"], capture_output=True, text=True, check=True).stdout
    return next(line.split(": ", 1)[1] for line in out.splitlines() if line.startswith("host: "))


def cargo_metadata() -> dict:
    cmd = ["cargo", "metadata", "--format-version", "1", "--filter-platform", host_triple()]
    for extra in (["--offline"], []):
        run = subprocess.run(cmd + extra, cwd=ROOT, capture_output=True, text=True)
        if run.returncode == 0:
            return json.loads(run.stdout)
    sys.exit(f"gen_copyright: cargo metadata failed:\n{run.stderr}")


def compiled_crates(meta: dict, root_name: str = "telerehab") -> list[dict]:
    """Every package in the binary: the root's normal dependencies, transitively."""
    packages = {p["id"]: p for p in meta["packages"]}
    nodes = {n["id"]: n for n in meta["resolve"]["nodes"]}
    roots = [p["id"] for p in meta["packages"] if p["name"] == root_name and p["source"] is None]
    if len(roots) != 1:
        sys.exit(f"gen_copyright: no workspace package named {root_name!r}")
    seen: set[str] = set()
    todo = list(roots)
    while todo:
        pid = todo.pop()
        if pid in seen:
            continue
        seen.add(pid)
        for dep in nodes[pid]["deps"]:
            if any(kind["kind"] is None for kind in dep["dep_kinds"]):
                todo.append(dep["pkg"])
    return sorted((packages[i] for i in seen), key=lambda p: (p["name"], p["version"]))


def dep5_license(spdx: str) -> str:
    """An SPDX expression as DEP-5 writes it: `or`/`and`, a comma before a lower-precedence
    `and` that follows a parenthesised group, `/` (the old Cargo form) as `or`."""
    expr = re.sub(r"\s*/\s*", " OR ", spdx.strip())
    parts = [p.strip() for p in re.split(r"\s+AND\s+(?![^(]*\))", expr)]
    grouped = any(p.startswith("(") for p in parts)
    words = []
    for part in parts:
        inner = part[1:-1] if part.startswith("(") and part.endswith(")") else part
        words.append(re.sub(r"\s+OR\s+", " or ", re.sub(r"\s+WITH\s+", " with ", inner)))
    return (", and " if grouped else " and ").join(words)


def license_ids(spdx: str) -> set[str]:
    """The licence identifiers in an SPDX expression (exceptions included)."""
    words = re.findall(r"[A-Za-z0-9.+-]+", spdx.replace("/", " "))
    return {w for w in words if w not in ("OR", "AND", "WITH")}


def crate_dir(pkg: dict) -> Path:
    return Path(pkg["manifest_path"]).parent


def squash(text: str) -> str:
    """Lower case, every run of white space as one space (licence files wrap differently)."""
    return " ".join(text.lower().split())


def licence_files(directory: Path) -> list[Path]:
    """A crate's licence files: LICENSE*/COPYING* at its top, text files one level down
    (fonts carry theirs beside them, e.g. fonts/OFL.txt)."""
    top = [
        p for p in sorted(directory.glob("*"))
        if p.is_file() and p.name.upper().startswith(("LICEN", "COPYING", "UNLICENSE"))
    ]
    return top + sorted(directory.glob("*/*.txt"))


def only_the(ident: str, text: str) -> str:
    """An exception's own words, without the licence it amends: the LLVM exception's file also
    holds Apache-2.0's full text, which common-licenses has (policy 12.5)."""
    if ident == "LLVM-exception":
        start = text.find("--- LLVM Exceptions")
        return text[start:] if start >= 0 else text
    return text


def licence_text(ident: str, crates: list[dict]) -> str:
    """The text of a licence: a pointer into common-licenses, else the first crate's copy."""
    if ident in IN_COMMON:
        return (
            f"On Debian systems the full text of {ident} is in "
            f"{COMMON_LICENSES / IN_COMMON[ident]}."
        )
    signature = SIGNATURES.get(ident)
    if signature:
        for pkg in crates:
            if ident not in license_ids(pkg.get("license") or ""):
                continue
            for path in licence_files(crate_dir(pkg)):
                text = path.read_text(errors="replace")
                if squash(signature) in squash(text):
                    return only_the(ident, text)
    return f"The text of {ident}: https://spdx.org/licenses/{ident}.html"


def field(text: str) -> str:
    """A multi-line DEP-5 field value: continuation lines indented, blank ones as ` .`."""
    lines = text.strip("\n").splitlines() or [""]
    out = [lines[0].strip()]
    for line in lines[1:]:
        line = line.rstrip().replace("\t", "    ")
        out.append(" " + line if line.strip() else " .")
    return "\n".join(out)


def vendored_console_libraries() -> list[dict]:
    """Each vendored console library: name, version, copyright lines, licence id."""
    libs = []
    for d in sorted(p for p in VENDOR.iterdir() if p.is_dir()):
        text = (d / "LICENSE").read_text()
        ident = next((i for i, s in SIGNATURES.items() if s.lower() in text.lower()), None)
        if ident is None and "apache license" in text.lower() and "version 2.0" in text.lower():
            ident = "Apache-2.0"  # its text is in common-licenses (licence_text points there)
        if ident is None:
            sys.exit(f"gen_copyright: cannot tell the licence of {d / 'LICENSE'}")
        name, _, version = d.name.rpartition("-")
        notices = [ln.strip() for ln in text.splitlines() if ln.strip().startswith("Copyright")]
        libs.append(
            {"dir": d.name, "name": name, "version": version, "copyright": notices,
             "license": ident, "files": sorted(f.name for f in d.iterdir())}
        )
    return libs


def own_workspace() -> dict:
    with open(ROOT / "Cargo.toml", "rb") as f:
        ws = tomllib.load(f)["workspace"]["package"]
    return ws


def render(meta: dict) -> str:
    crates = compiled_crates(meta)
    ours = [p for p in crates if p["source"] is None]
    theirs = [p for p in crates if p["source"] is not None]
    ws = own_workspace()
    libs = vendored_console_libraries()
    used: set[str] = license_ids(ws["license"])
    out = [
        f"Format: {FORMAT}\nUpstream-Name: telerehab\n"
        f"Comment: Generated by scripts/gen_copyright.py from `cargo metadata` of this build.\n"
        f" /usr/bin/telerehab is one executable compiled from {len(crates)} Rust crates:\n"
        f" {len(ours)} of this project's workspace and {len(theirs)} from crates.io, each\n"
        f" below as `Files: vendor/rust/<crate>-<version>/*` (where `cargo vendor` puts its\n"
        f" source), and embeds the therapist console's browser libraries\n"
        f" (crates/hub/console/vendor/)."
    ]
    authors = ", ".join(ws.get("authors", [])) or "the telerehab developers"
    out.append(
        f"Files: *\nCopyright: 2026 {authors}\nLicense: {dep5_license(ws['license'])}\n"
        f"Comment: this project's crates: {', '.join(p['name'] for p in ours)}."
    )
    for pkg in theirs:
        spdx = pkg.get("license") or ""
        if not spdx:
            sys.exit(f"gen_copyright: {pkg['name']} {pkg['version']} states no licence")
        used |= license_ids(spdx)
        who = "\n".join(pkg.get("authors") or [f"the {pkg['name']} authors"])
        where = pkg.get("repository") or pkg.get("homepage") or "crates.io"
        out.append(
            f"Files: vendor/rust/{pkg['name']}-{pkg['version']}/*\n"
            f"Copyright: {field(who)}\nLicense: {dep5_license(spdx)}\n"
            f"Comment: Rust crate {pkg['name']} {pkg['version']}, {where}"
        )
    for lib in libs:
        used.add(lib["license"])
        files = " ".join(f"crates/hub/console/vendor/{lib['dir']}/{f}" for f in lib["files"])
        notices = "\n".join(lib["copyright"]) or f"the {lib['name']} authors"
        out.append(
            f"Files: {files}\nCopyright: {field(notices)}\nLicense: {lib['license']}\n"
            f"Comment: {lib['name']} {lib['version']}, vendored console library (npm)"
        )
    for ident in sorted(used):
        out.append(f"License: {ident}\n {field(licence_text(ident, theirs))}")
    return "\n\n".join(out) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--metadata", help="a saved `cargo metadata --format-version 1` (JSON)")
    ap.add_argument("--out", help="where to write it (default: standard output)")
    args = ap.parse_args()
    meta = json.loads(Path(args.metadata).read_text()) if args.metadata else cargo_metadata()
    text = render(meta)
    if args.out:
        Path(args.out).write_text(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
