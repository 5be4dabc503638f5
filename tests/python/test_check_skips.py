"""scripts/check_skips.py: skipped tests are counted, and in CI only allowed reasons pass."""

from __future__ import annotations

import importlib.util
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "check_skips.py"


def run(tmp_path: pathlib.Path, log: str, ci: bool) -> subprocess.CompletedProcess[str]:
    path = tmp_path / "test.log"
    path.write_text(log, encoding="utf-8")
    env = {"PATH": "/usr/bin:/bin"}
    if ci:
        env["CI"] = "true"
    return subprocess.run(
        [sys.executable, str(SCRIPT), str(path)], capture_output=True, text=True, env=env
    )


def test_an_allowed_skip_passes_in_ci_and_is_counted(tmp_path: pathlib.Path) -> None:
    log = "test a ... ok\nSKIPPED: backend: /dev/uinput is not usable here (ENOENT)\n"
    out = run(tmp_path, log, ci=True)
    assert out.returncode == 0, out.stderr
    assert "skipped tests: 1 (1 allowed)" in out.stdout


def test_a_database_that_did_not_start_fails_ci_but_not_a_developer_run(tmp_path: pathlib.Path) -> None:
    log = "SKIPPED: postgres could not start: no initdb\nSKIPPED [1] x.py:3: no display\n"
    assert run(tmp_path, log, ci=True).returncode == 1
    out = run(tmp_path, log, ci=False)
    assert out.returncode == 0
    assert "NOT ALLOWED" in out.stdout and "skipped tests: 2 (0 allowed)" in out.stdout


def test_the_allow_list_has_only_the_uinput_reason() -> None:
    spec = importlib.util.spec_from_file_location("check_skips", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.allowed_reasons() == ["/dev/uinput"]
