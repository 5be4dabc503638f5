#!/usr/bin/env python3
"""Writes docs/SCREENS.md: every patient screen and every console screen, one row a screen and
one column a language, each cell a link to its screenshot in docs/screenshots/{patient,console}/
<language>/. `--check` fails (exit 1) when the file is not what the screenshots make it, or
when a screen lacks a language.

The screenshots themselves are made on purpose, not in CI:
  TELEREHAB_SCREENSHOTS=docs/screenshots/patient cargo test -p station --test every_screen
  TELEREHAB_SCREENSHOTS=docs/screenshots/console TELEREHAB_BIN=target/debug/telerehab \\
    xvfb-run -a .venv/bin/python -m pytest -q tests/python/test_console_axe.py \\
    tests/python/test_console_screens_languages.py
"""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHOTS = ROOT / "docs" / "screenshots"
OUT = ROOT / "docs" / "SCREENS.md"
LANGUAGES = ["en", "en-XA", "de", "es", "zh"]
# Screens shown once in a clinic's life, drawn in English only: the forced change of the
# one-time password at the very first sign-in (the same form as "password" after it).
ONCE = {"password-forced"}

HEAD = """# Every screen in every language

The patient's screens (the station's window, 1280×720, drawn offscreen by the window's own
code) and the therapist console's screens (headless Chromium's window, the station settings and a
live session at 1366×768), in English, the pseudo-locale
`en-XA` (accented and 40 % longer, to find clipped text and words left outside the
catalogues), German, Spanish and Chinese. Each was looked at as a one-handed patient with a
neglected side, and as a therapist between two patients. Made by the commands in
`scripts/screens_index.py`, which writes this page (`python3 scripts/screens_index.py`).
"""


def table(area, title):
    """The markdown table of `area` (patient or console): (lines, problems)."""
    folder = SHOTS / area
    screens = sorted({p.stem for lang in LANGUAGES for p in (folder / lang).glob("*.png")})
    lines = [f"## {title}", "", "| Screen | " + " | ".join(LANGUAGES) + " |",
             "|---|" + "---|" * len(LANGUAGES)]
    problems = []
    for screen in screens:
        cells = []
        for lang in LANGUAGES:
            shot = folder / lang / f"{screen}.png"
            if shot.exists():
                cells.append(f"[{lang}](screenshots/{area}/{lang}/{screen}.png)")
            else:
                cells.append("—")
                if screen not in ONCE:
                    problems.append(f"{area}/{lang}/{screen}.png is missing")
        name = screen.split("-", 1)[1] if screen[:2].isdigit() else screen
        lines.append(f"| {name.replace('-', ' ')} | " + " | ".join(cells) + " |")
    if not screens:
        problems.append(f"no screenshots in {folder}")
    return lines, problems


def main():
    lines, problems = [HEAD], []
    for area, title in (("patient", "The patient's station"), ("console", "The therapist console")):
        rows, missing = table(area, title)
        lines += rows + [""]
        problems += missing
    text = "\n".join(lines)
    if "--check" in sys.argv:
        if problems:
            sys.exit("screens: " + "; ".join(problems))
        if not OUT.exists() or OUT.read_text() != text:
            sys.exit("screens: docs/SCREENS.md is out of date: run python3 scripts/screens_index.py")
        print(f"screens: docs/SCREENS.md lists every screen in {len(LANGUAGES)} languages")
        return
    OUT.write_text(text)
    for p in problems:
        print("screens:", p)


if __name__ == "__main__":
    main()
