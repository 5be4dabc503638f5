"""Our four-bar calibration from Python vs scipy.optimize.least_squares on the same residuals.

Run manually (not in CI), after `pip install ./pyext scipy`:

    python pyext/bench/bench_vs_scipy.py

Problems: 20 seeded recordings of 2 000 samples (wheel ±60° at 0.2 Hz, 100 Hz), 0.5° of white
noise on the gyro angles. scipy minimises the loop residuals of eq. 4.1 over
[l1, l3, l4, Θ2, Θ3, Θ4] with an analytic Jacobian, from a start 10 % off the true lengths and
0.1 rad off the angles (it needs one; our global method does not). Accuracy is the max
relative length error against the truth, and the cost gap to the best cost found.
"""

import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from fourbar_sim import GEOMETRY, residuals, simulate  # noqa: E402

from telerehab import calib  # noqa: E402

L2 = GEOMETRY["l2"]


def jacobian(x, phi2, phi3, phi4, l2):
    l1, l3, l4, t2, t3, t4 = x
    e2, e3, e4 = np.exp(1j * (t2 + phi2)), np.exp(1j * (t3 + phi3)), np.exp(1j * (t4 + phi4))
    cols = [-np.ones_like(e2), e3, -e4, 1j * l2 * e2, 1j * l3 * e3, -1j * l4 * e4]
    return np.stack([np.concatenate([c.real, c.imag]) for c in cols], axis=1)


def timed(fn, repeat=5):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main():
    rows = {}
    for seed in range(20):
        rng = np.random.default_rng(seed)
        phi2, phi3, phi4, t, truth = simulate(n=2000)
        p3 = phi3 + rng.normal(0, np.deg2rad(0.5), phi3.shape)
        p4 = phi4 + rng.normal(0, np.deg2rad(0.5), phi4.shape)
        x_true = np.array([truth[k] for k in ("l1", "l3", "l4", "theta2_0", "theta3_0", "theta4_0")])
        x0 = x_true * np.array([1.1, 0.9, 1.1, 1, 1, 1]) + np.array([0, 0, 0, 0.1, -0.1, 0.1])
        args = (phi2, p3, p4, L2)

        def cost(x):
            return float(np.sum(residuals(x, *args) ** 2))

        def ours(method, **kw):
            r = calib.calibrate_planar_fourbar(phi2, p3, p4, L2, method=method, **kw)
            return np.array([r.l1, r.l3, r.l4, r.theta2_0, r.theta3_0, r.theta4_0])

        cases = {
            "telerehab global (no start)": lambda: ours("global"),
            "telerehab lm (same start, plain LS)": lambda: ours(
                "lm", initial=x0, gyro_bias=False, robust=False, errors_in_variables=False,
                tolerance=1e-10,
            ),
            "telerehab auto (default: robust + bias + noise correction)": lambda: ours("auto"),
            "scipy least_squares lm (analytic J)": lambda: least_squares(
                residuals, x0, jac=jacobian, args=args, method="lm", xtol=1e-10
            ).x,
            "scipy least_squares trf (analytic J)": lambda: least_squares(
                residuals, x0, jac=jacobian, args=args, method="trf", xtol=1e-10
            ).x,
        }
        results = {name: timed(fn) for name, fn in cases.items()}
        best_cost = min(cost(x) for _, x in results.values())
        for name, (sec, x) in results.items():
            err = np.max(np.abs(x[:3] - x_true[:3]) / x_true[:3])
            rows.setdefault(name, []).append((sec, err, cost(x) / best_cost - 1))
    scipy_time = np.median([r[0] for r in rows["scipy least_squares lm (analytic J)"]])
    print("| method | median time (ms) | speed-up vs scipy lm | mean max length error % | mean cost excess |")
    print("|---|---|---|---|---|")
    for name, vals in rows.items():
        sec = np.median([v[0] for v in vals])
        err = np.mean([v[1] for v in vals]) * 100
        excess = np.mean([v[2] for v in vals])
        print(f"| {name} | {sec * 1e3:.3f} | {scipy_time / sec:.1f}× | {err:.3f} | {excess:.1e} |")


if __name__ == "__main__":
    main()
