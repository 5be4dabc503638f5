#!/usr/bin/env python3
"""The safety file's trace, checked against one test run (docs/safety/README.md).

Every test the hazard table names as `path::test_function` must
  1. exist: the file is in the tree and defines the function (`fn name` in Rust, `def name` in
     Python), and
  2. have passed in this run: `test <...>name ... ok` in the cargo log, inside the section of a
     test binary built from that file's crate or test file; or a JUnit test case of that file
     and name with no failure, error or skip in pytest's XML.
A renamed, removed, ignored, failed or unrun test breaks the trace and this exits 1, naming
each one and what is wrong with it.

    python3 scripts/check_safety_trace.py --cargo-log LOG [--junit XML] [--table FILE ...]
    python3 scripts/check_safety_trace.py --exists-only     # only step 1 (no run needed)
"""

from __future__ import annotations

import argparse
import re
import sys
import tomllib
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_TABLES = [ROOT / "docs" / "safety" / "hazards.md"]

ENTRY = re.compile(r"`((?:crates|tests|pyext)/[\w./-]+\.(?:rs|py))::(\w+)`")
RUNNING = re.compile(r"^\s*Running (?:unittests )?(\S+) \((?:\S*/)?deps/([\w]+)-[0-9a-f]+(?:\.exe)?\)")
RESULT = re.compile(r"\btest (\S+) \.\.\. (ok|FAILED|ignored)\b")
# A test whose result another test's output (`--nocapture`) pushed off its line.
STARTED = re.compile(r"\btest (\S+) \.\.\. (?!(?:ok|FAILED|ignored)\b)")
# The binary's summary: a test started above without its result on its line took the binary's.
SUMMARY = re.compile(r"^test result: (ok|FAILED)\. \d+ passed; (\d+) failed")


@dataclass(frozen=True)
class Entry:
    path: str
    name: str
    where: str  # the table file and line, for the message

    def __str__(self) -> str:
        return f"{self.path}::{self.name}"


def entries_of(tables: list[Path]) -> list[Entry]:
    found: list[Entry] = []
    for table in tables:
        shown = table.relative_to(ROOT) if table.is_relative_to(ROOT) else table
        for number, line in enumerate(table.read_text(encoding="utf-8").splitlines(), 1):
            for m in ENTRY.finditer(line):
                found.append(Entry(m.group(1), m.group(2), f"{shown}:{number}"))
    return found


def defines(entry: Entry, root: Path) -> str | None:
    """None when the file defines the function, else what is wrong."""
    file = root / entry.path
    if not file.is_file():
        return f"{entry.path} does not exist"
    keyword = "def" if entry.path.endswith(".py") else "fn"
    pattern = re.compile(rf"\b{keyword}\s+{re.escape(entry.name)}\s*[(<]")
    if not pattern.search(file.read_text(encoding="utf-8")):
        return f"{entry.path} defines no `{keyword} {entry.name}`"
    return None


def lib_target_of(crate_dir: Path) -> str:
    """The crate's library target name as cargo names its test binary (dashes as underscores)."""
    manifest = tomllib.loads((crate_dir / "Cargo.toml").read_text(encoding="utf-8"))
    name = manifest.get("lib", {}).get("name") or manifest["package"]["name"]
    return name.replace("-", "_")


def binaries_for(entry: Entry, root: Path) -> tuple[str, str | None]:
    """(the Running line's source path, the deps stem or None for any) of the binary that runs
    the entry's test: a crate's unit tests for a file under src/, the test file otherwise."""
    parts = Path(entry.path).parts
    if parts[0] == "crates" and len(parts) > 3 and parts[2] == "src":
        crate_dir = root / parts[0] / parts[1]
        return ("src/", lib_target_of(crate_dir))
    if parts[0] == "crates" and len(parts) > 3 and parts[2] == "tests":
        return ("tests/" + parts[3], Path(parts[3]).stem)
    if parts[0] == "tests" and entry.path.endswith(".rs"):
        # The workspace-level tests are a package rooted at tests/ (tests/Cargo.toml).
        return ("/".join(parts[1:]), Path(parts[-1]).stem)
    return ("", None)


def cargo_results(log: str) -> list[tuple[str, str, str, str]]:
    """(source path, deps stem, test name, result) for every test result line of the log."""
    results = []
    source, stem = "", ""
    unfinished: list[str] = []
    for line in log.splitlines():
        m = RUNNING.match(line)
        if m:
            source, stem = m.group(1), m.group(2)
            unfinished = []
            continue
        for r in RESULT.finditer(line):
            results.append((source, stem, r.group(1), r.group(2)))
        unfinished += [r.group(1) for r in STARTED.finditer(line)]
        summary = SUMMARY.match(line)
        if summary:
            # libtest ends a binary with `ok` only when none of its tests failed: a test whose
            # `... ok` was interleaved away passed; under `FAILED` it cannot be told, so it
            # counts as failed.
            passed = summary.group(1) == "ok" and summary.group(2) == "0"
            results += [(source, stem, name, "ok" if passed else "FAILED") for name in unfinished]
            unfinished = []
    return results


def cargo_verdict(entry: Entry, results, root: Path) -> str | None:
    source_prefix, stem = binaries_for(entry, root)
    seen = []
    for source, binary, name, result in results:
        # A test's path in its binary: `module::name`, or `name::backend` for a test a macro
        # runs once a backend (the hub's SQLite and PostgreSQL): the name is one of its parts.
        if entry.name not in name.split("::"):
            continue
        if stem is not None and binary != stem:
            continue
        if source_prefix.endswith("/") and not source.startswith(source_prefix):
            continue
        if not source_prefix.endswith("/") and source != source_prefix:
            continue
        seen.append(result)
    if not seen:
        return "did not run in this cargo test log"
    if "FAILED" in seen:
        return "FAILED in this run"
    if "ok" not in seen:
        return "was ignored in this run"
    return None


def junit_verdict(entry: Entry, xml_text: str) -> str | None:
    module = entry.path[: -len(".py")].replace("/", ".")
    seen = []
    for case in ET.fromstring(xml_text).iter("testcase"):
        name = case.get("name", "").split("[", 1)[0]
        classname = case.get("classname", "")
        # pytest names the module from its rootdir (`tests.python.test_x`) or from the test
        # folder itself (`test_x`): the module's own name must match either way.
        same_module = classname == module or classname.split(".")[-1] == module.split(".")[-1]
        if name != entry.name or not same_module:
            continue
        bad = [child.tag for child in case if child.tag in ("failure", "error", "skipped")]
        seen.append(bad[0] if bad else "ok")
    if not seen:
        return "did not run in this pytest run"
    if "ok" not in seen or any(s in ("failure", "error") for s in seen):
        return f"{[s for s in seen if s != 'ok'][0]} in this run"
    return None


def check(tables, cargo_log, junit_xml, exists_only, root=ROOT) -> list[str]:
    problems = []
    entries = entries_of(tables)
    if not entries:
        return [f"no `path::test` entries found in {', '.join(str(t) for t in tables)}"]
    results = cargo_results(cargo_log) if cargo_log is not None else []
    for entry in entries:
        wrong = defines(entry, root)
        if wrong is None and not exists_only:
            if entry.path.endswith(".py"):
                wrong = (
                    junit_verdict(entry, junit_xml)
                    if junit_xml is not None
                    else "is a Python test and no pytest JUnit XML was given"
                )
            else:
                wrong = (
                    cargo_verdict(entry, results, root)
                    if cargo_log is not None
                    else "is a Rust test and no cargo log was given"
                )
        if wrong:
            problems.append(f"{entry.where}: {entry} {wrong}")
    return problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cargo-log", type=Path)
    parser.add_argument("--junit", type=Path)
    parser.add_argument("--table", type=Path, action="append")
    parser.add_argument("--exists-only", action="store_true")
    args = parser.parse_args(argv)
    tables = args.table or DEFAULT_TABLES
    cargo_log = args.cargo_log.read_text(encoding="utf-8", errors="replace") if args.cargo_log else None
    junit = args.junit.read_text(encoding="utf-8") if args.junit else None
    problems = check(tables, cargo_log, junit, args.exists_only)
    count = len(entries_of(tables))
    if problems:
        print(f"safety trace: {len(problems)} of {count} named tests break the trace:")
        for p in problems:
            print(f"  {p}")
        return 1
    what = "exist" if args.exists_only else "exist and passed in this run"
    print(f"safety trace: all {count} tests named by the hazard table {what}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
