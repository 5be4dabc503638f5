"""scripts/check_layering.py fails on an arrow that points up DESIGN.md's diagram, naming it."""

import json
import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "check_layering.py"


def dep(name, kind=None, path=None):
    return {"name": name, "kind": kind, "path": path, "rename": None}


def pkg(name, *deps):
    return {"id": f"path+file:///ws/{name}#0.1.0", "name": name, "dependencies": list(deps)}


def metadata(*packages):
    return {"packages": list(packages), "workspace_members": [p["id"] for p in packages]}


CLEAN = [
    pkg("common"),
    pkg("exercises", dep("common", path="/ws/common"), dep("nalgebra"), dep("proptest", kind="dev")),
    pkg("calib", dep("common", path="/ws/common"), dep("gyro-imu", kind="dev", path="/ws/gyro-imu")),
    pkg("gyro-imu", dep("common", path="/ws/common"), dep("hidapi")),
    pkg("netlink", dep("tokio")),
    pkg("station", dep("exercises", path="/ws/exercises"), dep("netlink", path="/ws/netlink"), dep("tokio")),
]


def run(tmp_path, meta):
    f = tmp_path / "metadata.json"
    f.write_text(json.dumps(meta))
    return subprocess.run(
        [sys.executable, str(SCRIPT), "--metadata", str(f)], capture_output=True, text=True
    )


def test_clean_graph_passes_with_one_line_summary(tmp_path):
    r = run(tmp_path, metadata(*CLEAN))
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("layering OK: 6 crates")
    assert len(r.stdout.strip().splitlines()) == 1


def test_upward_arrow_fails_naming_both_crates(tmp_path):
    bad = pkg("exercises", dep("common", path="/ws/common"), dep("station", path="/ws/station"))
    r = run(tmp_path, metadata(*CLEAN[:1], bad, *CLEAN[2:]))
    assert r.returncode == 1
    assert "exercises -> station (normal dependency)" in r.stderr
    assert "points up" in r.stderr


def test_io_crate_in_a_pure_crate_fails_naming_it(tmp_path):
    bad = pkg("calib", dep("common", path="/ws/common"), dep("tokio"))
    r = run(tmp_path, metadata(*CLEAN[:2], bad, *CLEAN[3:]))
    assert r.returncode == 1
    assert "pure crate `calib` must not depend on the I/O crate `tokio`" in r.stderr


def test_io_crate_is_denied_even_as_a_dev_dependency(tmp_path):
    bad = pkg("assist", dep("mcap", kind="dev"))
    r = run(tmp_path, metadata(*CLEAN, bad))
    assert r.returncode == 1
    assert "assist -> mcap (dev dependency)" in r.stderr


def test_unlisted_dependency_of_a_pure_crate_fails(tmp_path):
    bad = pkg("common", dep("chrono"))
    r = run(tmp_path, metadata(bad, *CLEAN[1:]))
    assert r.returncode == 1
    assert "common -> chrono" in r.stderr and "allow list" in r.stderr


def test_pyext_may_not_use_netlink(tmp_path):
    bad = pkg("telerehab-py", dep("calib", path="/ws/calib"), dep("netlink", path="/ws/netlink"))
    r = run(tmp_path, metadata(*CLEAN, bad))
    assert r.returncode == 1
    assert "telerehab-py -> netlink" in r.stderr
    assert "telerehab-py -> calib" not in r.stderr


def test_the_real_workspace_is_clean():
    r = subprocess.run([sys.executable, str(SCRIPT)], capture_output=True, text=True, cwd=SCRIPT.parents[1])
    assert r.returncode == 0, r.stderr


def test_a_pure_crate_may_not_read_the_clock(tmp_path):
    r = run(tmp_path, metadata(pkg("clock"), pkg("exercises", dep("clock", path="crates/clock"))))
    assert r.returncode == 1
    assert "exercises -> clock" in r.stderr


def test_the_hub_and_the_python_package_link_no_device_library_while_the_station_does():
    import importlib.util

    spec = importlib.util.spec_from_file_location("check_layering", SCRIPT)
    layering = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(layering)
    for package in layering.DEVICE_FREE:
        assert layering.device_libraries_of(package) == [], package
    # The walk sees device libraries where they are: the check can fail.
    assert {"evdev", "hidapi"} <= set(layering.device_libraries_of("station"))
