#!/usr/bin/env python3
"""Count the skipped tests of a test run and, in CI, fail on any not on the allow-list.

Reads the logs given (the output of `cargo test -- --nocapture` and of `pytest -rs`) and finds
every line with `SKIPPED` (a Rust test's `SKIPPED: <reason>`, pytest's `SKIPPED [n] file: reason`,
`scripts/with-postgres.sh`'s own). Prints each once with its count. When the environment has
`CI` set, exits 1 if any such line matches none of the substrings in `.ci/skip-allowlist`
(a PostgreSQL that would not start, a missing display or GPU: a visible failure, not a pass).

Python 3 standard library only.
"""

from __future__ import annotations

import collections
import os
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
ALLOWLIST = ROOT / ".ci" / "skip-allowlist"
SKIP = re.compile(r"SKIPPED\b[: \[]")


def allowed_reasons(path: pathlib.Path = ALLOWLIST) -> list[str]:
    """The allow-list's substrings (comments and blank lines left out)."""
    lines = path.read_text(encoding="utf-8").splitlines()
    return [line.strip() for line in lines if line.strip() and not line.lstrip().startswith("#")]


def skips(texts: list[str]) -> collections.Counter[str]:
    """Every SKIPPED line of the logs, stripped, with how often it occurs."""
    found: collections.Counter[str] = collections.Counter()
    for text in texts:
        for line in text.splitlines():
            if SKIP.search(line) and "check_skips" not in line:
                found[line.strip()] += 1
    return found


def main(argv: list[str]) -> int:
    if not argv:
        print("usage: check_skips.py LOG [LOG...]", file=sys.stderr)
        return 2
    texts = [pathlib.Path(p).read_text(encoding="utf-8", errors="replace") for p in argv]
    found = skips(texts)
    reasons = allowed_reasons()
    refused = [line for line in found if not any(r in line for r in reasons)]
    total = sum(found.values())
    print(f"== skipped tests: {total} ({total - sum(found[r] for r in refused)} allowed)")
    for line, n in sorted(found.items()):
        mark = "NOT ALLOWED" if line in refused else "allowed"
        print(f"   {n}x [{mark}] {line}")
    if refused and os.environ.get("CI"):
        print(
            f"check_skips: {len(refused)} kind(s) of skip not on .ci/skip-allowlist; in CI a "
            "skipped test is a failure (install what it needs in scripts/setup.sh)",
            file=sys.stderr,
        )
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
