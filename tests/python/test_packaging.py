"""The clinic's hub as a service (packaging/telerehab-hub.service): systemd accepts the unit
and rates its exposure 2.0 or lower (systemd-analyze works offline, without systemd running)."""

import os
import re
import shutil
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
UNIT = ROOT / "packaging" / "telerehab-hub.service"
BIN = os.environ.get("TELEREHAB_BIN", str(ROOT / "target" / "debug" / "telerehab"))


def analyze(*args: str) -> subprocess.CompletedProcess:
    # scripts/setup.sh installs systemd; without it this test fails rather than skips.
    assert shutil.which("systemd-analyze"), "systemd-analyze missing: run scripts/setup.sh"
    return subprocess.run(["systemd-analyze", *args], capture_output=True, text=True)


def test_the_hub_service_is_rated_2_or_lower_by_systemd():
    out = analyze("security", "--offline=true", str(UNIT))
    found = re.search(r"Overall exposure level for telerehab-hub\.service: ([0-9.]+)", out.stdout)
    assert found, out.stdout + out.stderr
    assert float(found.group(1)) <= 2.0, out.stdout


def test_the_hub_service_unit_verifies(tmp_path):
    # verify checks that ExecStart's program exists: point it at the binary under test.
    unit = tmp_path / "telerehab-hub.service"
    unit.write_text(UNIT.read_text().replace("/usr/bin/telerehab", BIN))
    out = analyze("verify", str(unit))
    assert out.returncode == 0, out.stdout + out.stderr


def test_the_hub_service_runs_hub_serve_on_its_state_directory_as_its_own_user():
    text = UNIT.read_text()
    assert "ExecStart=/usr/bin/telerehab hub serve --data /var/lib/telerehab-hub" in text
    assert "StateDirectory=telerehab-hub" in text and "User=telerehab-hub" in text
    assert "EnvironmentFile=-/etc/telerehab/hub.env" in text
    sysusers = (ROOT / "packaging" / "telerehab-hub.sysusers").read_text()
    assert re.search(r"^u telerehab-hub ", sysusers, re.M)


# --- The Debian package's generated parts (scripts/package.sh), checked without root. ---

import importlib.util
import json
import xml.etree.ElementTree as ET

SCRIPTS = ROOT / "scripts"


def load_gen_copyright():
    spec = importlib.util.spec_from_file_location("gen_copyright", SCRIPTS / "gen_copyright.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def cargo_metadata() -> dict:
    out = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--filter-platform",
         "x86_64-unknown-linux-gnu", "--offline"],
        cwd=ROOT, capture_output=True, text=True, check=True,
    )
    return json.loads(out.stdout)


def binary_graph(meta: dict) -> set[tuple[str, str]]:
    """(name, version) of every crate the `telerehab` binary links: the `telerehab` package's
    normal dependencies, transitively (walked here independently of the generator)."""
    nodes = {n["id"]: n for n in meta["resolve"]["nodes"]}
    packages = {p["id"]: p for p in meta["packages"]}
    todo = [p["id"] for p in meta["packages"] if p["name"] == "telerehab" and p["source"] is None]
    seen = set()
    while todo:
        pid = todo.pop()
        if pid not in seen:
            seen.add(pid)
            todo += [d["pkg"] for d in nodes[pid]["deps"]
                     if any(k["kind"] is None for k in d["dep_kinds"])]
    return {(packages[i]["name"], packages[i]["version"]) for i in seen
            if packages[i]["source"] is not None}


def paragraphs(copyright_text: str) -> list[dict[str, str]]:
    """DEP-5 paragraphs as {field: first line of its value}."""
    out = []
    for block in copyright_text.strip().split("\n\n"):
        fields = {}
        for line in block.splitlines():
            if line and not line[0].isspace():
                key, _, value = line.partition(":")
                fields[key] = value.strip()
        out.append(fields)
    return out


def test_the_copyright_file_names_every_crate_compiled_into_the_binary_with_its_licence():
    meta = cargo_metadata()
    text = load_gen_copyright().render(meta)
    files = {p["Files"]: p for p in paragraphs(text) if "Files" in p}
    graph = binary_graph(meta)
    assert len(graph) > 100
    # The binary is the station, its window and the hub: each one's libraries are in it.
    assert {"wgpu", "evdev", "sqlx", "axum"} <= {name for name, _ in graph}
    for name, version in sorted(graph):
        para = files.get(f"vendor/rust/{name}-{version}/*")
        assert para, f"{name} {version} is compiled in but not in the copyright file"
        assert para["License"] and para["Copyright"], para
    # Nothing else: dev-dependencies and the Python extension's crates are not in the binary.
    named = {k for k in files if k.startswith("vendor/rust/")}
    assert len(named) == len(graph)
    assert not any(k.startswith(("vendor/rust/pyo3-", "vendor/rust/proptest-")) for k in named)


def test_every_licence_of_the_copyright_file_has_its_text_or_a_common_licenses_pointer():
    text = load_gen_copyright().render(cargo_metadata())
    paras = paragraphs(text)
    standalone = {p["License"] for p in paras if "Files" not in p and "Format" not in p}
    words = set()
    for p in paras:
        if "Files" in p:
            words |= set(p["License"].replace(",", " ").split()) - {"or", "and", "with"}
    assert words <= standalone, words - standalone
    assert "Apache-2.0" in standalone and "TERMS AND CONDITIONS FOR USE" not in text


def test_the_copyright_file_names_the_console_libraries_and_our_own_licence():
    text = load_gen_copyright().render(cargo_metadata())
    files = {p["Files"].split()[0]: p for p in paragraphs(text) if "Files" in p}
    assert files["*"]["License"] == "MIT or Apache-2.0"
    for lib in ("three-0.181.2", "uplot-1.6.32"):
        vendored = [v for k, v in files.items() if f"/vendor/{lib}/" in k]
        assert vendored and vendored[0]["License"] == "MIT", lib


def test_spdx_expressions_are_written_as_dep5_licence_fields():
    dep5 = load_gen_copyright().dep5_license
    assert dep5("MIT/Apache-2.0") == "MIT or Apache-2.0"
    assert dep5("(MIT OR Apache-2.0) AND Unicode-3.0") == "MIT or Apache-2.0, and Unicode-3.0"
    assert dep5("Apache-2.0 WITH LLVM-exception OR MIT") == "Apache-2.0 with LLVM-exception or MIT"
    assert dep5("MIT AND BSD-3-Clause") == "MIT and BSD-3-Clause"


def test_the_desktop_entry_validates_and_starts_the_patients_window():
    assert shutil.which("desktop-file-validate"), "desktop-file-utils missing: run scripts/setup.sh"
    entry = ROOT / "packaging" / "telerehab.desktop"
    out = subprocess.run(["desktop-file-validate", str(entry)], capture_output=True, text=True)
    assert out.returncode == 0 and not out.stdout.strip(), out.stdout + out.stderr
    text = entry.read_text()
    assert "\nExec=telerehab\n" in text and "\nIcon=telerehab\n" in text
    svg = ET.parse(ROOT / "packaging" / "telerehab.svg").getroot()
    assert svg.tag.endswith("svg") and svg.get("viewBox") == "0 0 256 256"


def test_the_maintainer_scripts_parse_and_never_enable_the_hub_service():
    for name in ("postinst", "prerm", "postrm"):
        script = ROOT / "packaging" / "debian" / name
        assert subprocess.run(["sh", "-n", str(script)]).returncode == 0, name
        text = script.read_text()
        assert "\nset -e\n" in text and "#DEBHELPER#" not in text, name
        assert not re.search(r"(systemctl|deb-systemd-helper)\s+(\S+\s+)*enable", text), name
    postrm = (ROOT / "packaging" / "debian" / "postrm").read_text()
    # A clinic's data is removed on purge only when empty (packaging/README.md, "Purge").
    assert "rm -rf /var/lib/telerehab-hub" not in postrm and "rmdir /var/lib/telerehab-hub" in postrm
