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
