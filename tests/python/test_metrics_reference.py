"""crates/metrics' reference values cannot drift silently: re-running the numpy/scipy
transcription (crates/metrics/tests/reference/sparc_ldlj.py) still prints the committed
expected.json, which the Rust test `metrics --test reference` compares against."""

import json
import math
import subprocess
import sys
from pathlib import Path

REF = Path(__file__).resolve().parents[2] / "crates" / "metrics" / "tests" / "reference"

# Same algorithm, same inputs: only a different numpy/scipy build's rounding may differ. The
# minimum-jerk speed 30t²−60t³+30t⁴ cancels near t = 1, so its last samples move by a few
# 1e-12 relative between numpy releases (2.4e-12 at speed[99] with numpy 2.4): 1e-9 still
# catches any change of algorithm or input, which moves values by far more.
REL_TOL = 1e-9


def close(a, b, where):
    if isinstance(a, dict):
        assert a.keys() == b.keys(), where
        for k in a:
            close(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), f"{where}: length {len(a)} vs {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            close(x, y, f"{where}[{i}]")
    elif isinstance(a, float):
        assert math.isclose(a, b, rel_tol=REL_TOL, abs_tol=1e-15), f"{where}: {a} vs {b}"
    else:
        assert a == b, f"{where}: {a!r} vs {b!r}"


def test_reference_script_still_prints_expected_json():
    out = subprocess.run(
        [sys.executable, str(REF / "sparc_ldlj.py")], check=True, capture_output=True, text=True
    )
    fresh = json.loads(out.stdout)
    committed = json.loads((REF / "expected.json").read_text())
    close(fresh, committed, "expected")


def test_reference_reproduces_the_published_values():
    committed = json.loads((REF / "expected.json").read_text())
    by_name = {c["name"]: c for c in committed["cases"]}
    g, mj = by_name["gaussian_exp_m5t2_100hz"], by_name["min_jerk_1s_100hz"]
    assert abs(g["sparc"] - -1.41403) < 1e-5 and abs(g["ldlj"] - -5.81636) < 1e-5
    assert abs(mj["sparc"] - -1.40583) < 1e-5 and abs(mj["ldlj"] - -5.30163) < 1e-5
