"""Our calibrations from Python vs scipy.optimize.least_squares on the same problems, one run.

Run manually (not in CI), after building the extension into a venv with scipy (release build):

    python pyext/bench/bench_vs_scipy.py [--seeds 20] [--repeat 5]

Every row of the tables comes from the same run; the calls of one recording are interleaved
(each method once per round, ``--repeat`` rounds) so load on the machine hits all of them
alike. Times = medians over the recordings of the median wall time and of the median CPU time
of the calling thread over a recording's calls. scipy runs twice: with numpy's default BLAS
threads and (with ``threadpoolctl`` installed) with one; on a shared 2-core machine the threads
mostly wait for each other, so the one-thread run, compared in CPU time, is the fair reference
(ours is single-threaded). The load average before and after is printed.

Planar four-bar (thesis §4.2.1): seeded recordings of 2 000 and 6 000 samples (wheel ±60° at
0.2 Hz, 100 Hz; 6 000 is the reviewer's held-out-style case), 0.5° of white noise on the gyro
angles φ3, φ4. scipy minimises the loop residuals of eq. 4.1 over [l1, l3, l4, Θ2, Θ3, Θ4] with
an analytic Jacobian, from a start 10 % off the true lengths and 0.1 rad off the angles (it needs
one; our global method does not). Our default call is ``calibrate_planar_fourbar(phi2, phi3,
phi4, l2)``: method "auto" (robust, gyro-bias terms, errors-in-variables correction).
Accuracy: the max relative length error against the truth (mean over recordings), and the cost
excess over the best plain least-squares cost found (our default deliberately minimises a
different, bias-corrected cost).

Spatial arm loop (eq. 4.1 in 3-D, ``calibrate_arm_3d``): 6 000 samples (60 s at 100 Hz) of the
simulated arm of ``tests/arm3d_sim.py``, 1° RMS of white direction noise and a heading error of
+3° / −2° growing by +2 / −1.5 °/min (upper arm / forearm). scipy solves
``S + l_u·R_z(−ψ_u(t))·u_k + l_f·R_z(−ψ_f(t))·f_k = G_k`` with ``ψ(t) = ψ0 + ψ̇·t`` per segment, the
same nine unknowns as our default ``heading="offset_and_drift"``, with an analytic Jacobian, from
the lengths 10 % off, the shoulder 3 cm off per axis and zero heading. Accuracy: the largest
length error and the shoulder error (mm), mean over recordings.
"""

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
import arm3d_sim  # noqa: E402
from fourbar_sim import GEOMETRY, residuals, simulate  # noqa: E402

from telerehab import calib  # noqa: E402

L2 = GEOMETRY["l2"]


def jacobian(x, phi2, phi3, phi4, l2):
    l1, l3, l4, t2, t3, t4 = x
    e2, e3, e4 = np.exp(1j * (t2 + phi2)), np.exp(1j * (t3 + phi3)), np.exp(1j * (t4 + phi4))
    cols = [-np.ones_like(e2), e3, -e4, 1j * l2 * e2, 1j * l3 * e3, -1j * l4 * e4]
    return np.stack([np.concatenate([c.real, c.imag]) for c in cols], axis=1)


def interleaved(cases, repeat):
    """{name: ((median wall s, median thread-CPU s), last result)}, the calls interleaved."""
    wall = {name: [] for name in cases}
    cpu = {name: [] for name in cases}
    out = {}
    for _ in range(repeat):
        for name, fn in cases.items():
            w0, c0 = time.perf_counter(), time.thread_time()
            out[name] = fn()
            cpu[name].append(time.thread_time() - c0)
            wall[name].append(time.perf_counter() - w0)
    return {
        name: ((statistics.median(wall[name]), statistics.median(cpu[name])), out[name])
        for name in cases
    }


try:  # the library scan is slow: once, not per call
    from threadpoolctl import ThreadpoolController

    BLAS = ThreadpoolController()
except ImportError:
    BLAS = None


def one_blas_thread():
    """A context where numpy's BLAS runs one thread (threadpoolctl), or None without it."""
    return None if BLAS is None else BLAS.limit(limits=1)


def scipy_cases(fun, x0, jac, args):
    """scipy's LM with numpy's default BLAS threads and, when threadpoolctl is installed, with
    one BLAS thread (on a shared 2-core machine the default threads mostly wait for each
    other: the 6 000-sample planar fit is several times slower with them)."""
    def run():
        return least_squares(fun, x0, jac=jac, args=args, method="lm", xtol=1e-10).x

    def single():
        with one_blas_thread():
            return run()

    cases = {SCIPY_DEFAULT: run}
    if BLAS is not None:
        cases[SCIPY_ONE] = single
    return cases


SCIPY_DEFAULT = "scipy least_squares lm (analytic J), numpy's default BLAS threads"
SCIPY_ONE = "scipy least_squares lm (analytic J), one BLAS thread"


def speed_table(rows, accuracy_header, accuracy):
    """Print the rows: medians over recordings of wall and CPU time, speed-ups, accuracy.

    Speed-up vs scipy with its default BLAS threads: wall time (its threads' work is not on
    the calling thread). Speed-up vs scipy with one BLAS thread: the calling thread's CPU time
    (both single-threaded; other processes on the machine, which stretch a 10 ms call's wall
    time more often than a 1 ms one's, then count for neither).
    """
    wall = {name: np.median([v[0][0] for v in vals]) for name, vals in rows.items()}
    cpu = {name: np.median([v[0][1] for v in vals]) for name, vals in rows.items()}
    print(
        "| method | median wall time (ms) | median CPU time (ms) | speed-up vs scipy lm, default "
        f"threads (wall) | speed-up vs scipy lm, one thread (CPU) | {accuracy_header} |"
    )
    print("|---|---|---|---|---|---|---|")
    for name, vals in rows.items():
        vs_one = f"{cpu[SCIPY_ONE] / cpu[name]:.1f}×" if SCIPY_ONE in cpu else "—"
        print(
            f"| {name} | {wall[name] * 1e3:.3f} | {cpu[name] * 1e3:.3f} | "
            f"{wall[SCIPY_DEFAULT] / wall[name]:.1f}× | {vs_one} | {accuracy(vals)} |"
        )


def planar_recording(n, seed):
    """One seeded planar recording: (args of ``residuals``, true x, scipy's start x0)."""
    rng = np.random.default_rng(seed)
    phi2, phi3, phi4, t, truth = simulate(n=n)
    p3 = phi3 + rng.normal(0, np.deg2rad(0.5), phi3.shape)
    p4 = phi4 + rng.normal(0, np.deg2rad(0.5), phi4.shape)
    x_true = np.array([truth[k] for k in ("l1", "l3", "l4", "theta2_0", "theta3_0", "theta4_0")])
    x0 = x_true * np.array([1.1, 0.9, 1.1, 1, 1, 1]) + np.array([0, 0, 0, 0.1, -0.1, 0.1])
    return (phi2, p3, p4, L2), x_true, x0


def planar(n, seeds, repeat, with_trf):
    rows = {}
    for seed in range(seeds):
        args, x_true, x0 = planar_recording(n, seed)
        phi2, p3, p4, _ = args

        def cost(x):
            return float(np.sum(residuals(x, *args) ** 2))

        def ours(**kw):
            r = calib.calibrate_planar_fourbar(phi2, p3, p4, L2, **kw)
            return np.array([r.l1, r.l3, r.l4, r.theta2_0, r.theta3_0, r.theta4_0])

        cases = {
            "telerehab default call (auto: robust + gyro bias + noise correction)": lambda: ours(),
            "telerehab global (no start)": lambda: ours(method="global"),
            "telerehab lm (same start, plain LS)": lambda: ours(
                method="lm", initial=x0, gyro_bias=False, robust=False, errors_in_variables=False,
                tolerance=1e-10,
            ),
            **scipy_cases(residuals, x0, jacobian, args),
        }
        if with_trf:
            cases["scipy least_squares trf (analytic J)"] = lambda: least_squares(
                residuals, x0, jac=jacobian, args=args, method="trf", xtol=1e-10
            ).x
        results = interleaved(cases, repeat)
        best_cost = min(cost(x) for _, x in results.values())
        for name, (sec, x) in results.items():
            err = np.max(np.abs(x[:3] - x_true[:3]) / x_true[:3])
            rows.setdefault(name, []).append((sec, err, cost(x) / best_cost - 1))
    print(f"\nPlanar four-bar, {n} samples, {seeds} recordings, median of {repeat} interleaved calls:\n")
    speed_table(
        rows,
        "mean max length error % | mean cost excess",
        lambda vals: f"{np.mean([v[1] for v in vals]) * 100:.3f} | {np.mean([v[2] for v in vals]):.1e}",
    )


def rot_z(v, angle):
    """Each row of v turned about +z by the matching angle (rad)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1], v[:, 2]], axis=1)


def arm_residuals(x, u, f, g, t):
    s, lu, lf = x[:3], x[3], x[4]
    ru = rot_z(u, -(x[5] + x[7] * t))
    rf = rot_z(f, -(x[6] + x[8] * t))
    return (s + lu * ru + lf * rf - g).ravel()


def arm_jacobian(x, u, f, g, t):
    lu, lf = x[3], x[4]
    ru = rot_z(u, -(x[5] + x[7] * t))
    rf = rot_z(f, -(x[6] + x[8] * t))
    # d/dψ of R_z(−ψ)v = −e_z × (R_z(−ψ)v) = (v'_y, −v'_x, 0)
    hu = np.stack([ru[:, 1], -ru[:, 0], np.zeros_like(t)], axis=1)
    hf = np.stack([rf[:, 1], -rf[:, 0], np.zeros_like(t)], axis=1)
    n = len(t)
    jac = np.empty((n, 3, 9))
    jac[:, :, :3] = np.eye(3)
    jac[:, :, 3] = ru
    jac[:, :, 4] = rf
    jac[:, :, 5] = lu * hu
    jac[:, :, 6] = lf * hf
    jac[:, :, 7] = lu * hu * t[:, None]
    jac[:, :, 8] = lf * hf * t[:, None]
    return jac.reshape(3 * n, 9)


def arm_recording(n, seed):
    """One seeded spatial-arm recording: (args of ``arm_residuals``, scipy's start x0)."""
    u0, f0, g, t = arm3d_sim.simulate(n=n)
    offset, rate = np.radians([3.0, -2.0]), np.radians([2.0, -1.5]) / 60.0
    rng = np.random.default_rng(100 + seed)

    def noisy(d):
        e = rng.normal(scale=np.radians(1.0) / np.sqrt(2.0), size=d.shape)
        e -= d * np.sum(e * d, axis=1, keepdims=True)  # tangent part only
        w = d + e
        return w / np.linalg.norm(w, axis=1, keepdims=True)

    u = rot_z(noisy(u0), offset[0] + rate[0] * t)
    f = rot_z(noisy(f0), offset[1] + rate[1] * t)
    shoulder, lu_true, lf_true = arm3d_sim.SHOULDER, arm3d_sim.UPPER_ARM, arm3d_sim.FOREARM
    x0 = np.concatenate([shoulder + 0.03, [lu_true * 1.1, lf_true * 0.9], np.zeros(4)])
    return (u, f, g, t), x0


def arm3d(n, seeds, repeat):
    shoulder, lu_true, lf_true = arm3d_sim.SHOULDER, arm3d_sim.UPPER_ARM, arm3d_sim.FOREARM
    rows = {}
    for seed in range(seeds):
        args, x0 = arm_recording(n, seed)
        u, f, g, t = args

        def ours(**kw):
            r = calib.calibrate_arm_3d(u, f, g, time_s=t, **kw)
            return np.concatenate([r.shoulder_m, [r.upper_arm_m, r.forearm_m]])

        cases = {
            "telerehab default call (offset_and_drift + noise correction)": lambda: ours(),
            "telerehab offset_and_drift, errors_in_variables=False (scipy's cost)": lambda: ours(
                errors_in_variables=False
            ),
            **scipy_cases(arm_residuals, x0, arm_jacobian, args),
        }
        results = interleaved(cases, repeat)
        for name, (sec, x) in results.items():
            length_mm = 1e3 * max(abs(x[3] - lu_true), abs(x[4] - lf_true))
            shoulder_mm = 1e3 * np.linalg.norm(x[:3] - shoulder)
            rows.setdefault(name, []).append((sec, length_mm, shoulder_mm))
    print(
        f"\nSpatial arm loop, {n} samples, 1° white + heading drift, {seeds} recordings, "
        f"median of {repeat} interleaved calls:\n"
    )
    speed_table(
        rows,
        "mean max length error mm | mean shoulder error mm",
        lambda vals: f"{np.mean([v[1] for v in vals]):.2f} | {np.mean([v[2] for v in vals]):.2f}",
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.2f} (1 min), {os.cpu_count()} CPUs")
    planar(2000, a.seeds, a.repeat, with_trf=True)
    planar(6000, a.seeds, a.repeat, with_trf=False)
    arm3d(6000, a.seeds, a.repeat)
    print(f"\nload average after: {os.getloadavg()[0]:.2f} (1 min)")


if __name__ == "__main__":
    main()
