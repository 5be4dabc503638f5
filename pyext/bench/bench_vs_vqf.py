"""Our arm-orientation fusion against VQF's own implementation on BROAD, side by side, one run.

Run manually (not in CI: the data are 110 MB from GitHub, and the reference is a wheel from
PyPI), after building the extension into a venv (release build):

    git clone https://github.com/dlaidig/broad /tmp/broad-repo   # the dataset, CC BY 4.0
    pip install vqf h5py                                          # VQF's C++ core; HDF5 reader
    python pyext/bench/bench_vs_vqf.py /tmp/broad-repo

BROAD (D. Laidig, M. Caruso, A. Cereatti, T. Seel, "BROAD — A Benchmark for Robust Inertial
Orientation Estimation", Data 6(7), 2021): 39 trials of one IMU (gyroscope rad/s,
accelerometer m/s², 285.7 Hz) with optical-motion-capture truth (``opt_quat``, ENU) and a mask of
the movement phases over which errors count. Each trial is read from ``data_hdf5`` or, where that
file is absent, ``data_mat`` (the two hold identical data); a trial in neither is named and left
out.

Error: BROAD's inclination RMSE (``example_code/broad_utils.py``: the error quaternion
``q_ours · q_truth⁻¹`` in the earth frame, ``2·acos(√(w² + z²))``, RMS over the movement phases,
degrees). It does not depend on heading, which a 6-D filter (gyroscope and accelerometer, as our
arm's sensors) cannot observe.

Compared, every trial with the same parameters (no per-trial tuning):
- ours: ``telerehab.imu.fuse`` (the station's ``gyro_imu::fusion::OrientationFilter`` with its
  defaults: VQF's 6-D filter plus a tilt-rate test before rest);
- ours with ``scale_estimation=True``: the same filter also estimating each gyroscope axis's
  scale-factor error while rotation dominates the motion (not in VQF; off in the station for
  now);
- ours with ``scale_estimation=True, rest_tilt_check=False``: the same with VQF's rest test
  (without the station's tilt-rate test, which a translation trips);
- VQF: ``vqf.VQF(Ts).updateBatch(gyr, acc)['quat6D']``, the causal filter, its defaults;
- offline VQF: ``vqf.offlineVQF``, forward-backward over the whole recording (not causal: an
  analyst's bound, not something a live station can run).

CPU time per sample is the calling thread's, one call per trial; the load average is printed.
"""

import argparse
import importlib.metadata
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

try:
    import h5py
    import scipy.io
    import vqf
except ImportError as e:  # a bench, not a test: say what to install
    sys.exit(f"bench_vs_vqf needs {e.name}: pip install vqf h5py scipy")

from telerehab import imu


def load(repo, name):
    """A trial's arrays and its sampling rate (Hz), or None when neither file is present."""
    h5 = repo / "data_hdf5" / f"{name}.hdf5"
    mat = repo / "data_mat" / f"{name}.mat"
    try:
        with h5py.File(h5, "r") as f:
            d = {k: f[k][()] for k in f.keys()}
            d["rate"] = float(f.attrs["sampling_rate"])
            return d
    except OSError:
        pass
    try:
        m = scipy.io.loadmat(mat, squeeze_me=True)
    except (OSError, ValueError):
        return None
    m["rate"] = float(m["sampling_rate"])
    return m


def qmul(a, b):
    w1, x1, y1, z1 = a.T
    w2, x2, y2, z2 = b.T
    return np.stack(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ],
        1,
    )


def inclination_rmse_deg(q, truth, movement):
    """BROAD's inclination RMSE over the movement phases, degrees."""
    q = q / np.linalg.norm(q, axis=1)[:, None]
    inv = truth * np.array([1.0, -1.0, -1.0, -1.0])
    inv = inv / np.linalg.norm(inv, axis=1)[:, None]
    d = qmul(q, inv)
    e = 2 * np.arccos(np.clip(np.sqrt(d[:, 0] ** 2 + d[:, 3] ** 2), 0, 1))[movement]
    return float(np.degrees(np.sqrt(np.nanmean(e**2))))


def cpu(f):
    t0 = time.thread_time()
    out = f()
    return out, time.thread_time() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("broad", type=Path, help="a clone of github.com/dlaidig/broad")
    args = ap.parse_args()
    trials = json.loads((args.broad / "data_hdf5" / "trials.json").read_text())["trials"]
    print(f"vqf {importlib.metadata.version('vqf')}, numpy {np.__version__}; load average {os.getloadavg()[0]:.2f}")
    rows, missing = [], []
    for name, info in trials.items():
        d = load(args.broad, name)
        if d is None:
            missing.append(name)
            continue
        dt = 1.0 / d["rate"]
        gyr = np.ascontiguousarray(d["imu_gyr"], dtype=float)
        acc = np.ascontiguousarray(d["imu_acc"], dtype=float)
        truth = np.asarray(d["opt_quat"], dtype=float)
        movement = np.asarray(d["movement"]).astype(bool)
        ours, t_ours = cpu(lambda: imu.fuse(gyr, acc, dt))
        scaled, t_scaled = cpu(lambda: imu.fuse(gyr, acc, dt, scale_estimation=True))
        scaled_vr = imu.fuse(gyr, acc, dt, scale_estimation=True, rest_tilt_check=False)
        ref, t_vqf = cpu(lambda: vqf.VQF(dt).updateBatch(gyr, acc)["quat6D"])
        offline = vqf.offlineVQF(gyr, acc, None, dt)["quat6D"]
        n = len(gyr)
        row = dict(
            name=name,
            groups=info["groups"],
            ours=inclination_rmse_deg(ours, truth, movement),
            scaled=inclination_rmse_deg(scaled, truth, movement),
            scaled_vr=inclination_rmse_deg(scaled_vr, truth, movement),
            vqf=inclination_rmse_deg(ref, truth, movement),
            offline=inclination_rmse_deg(offline, truth, movement),
            us_ours=1e6 * t_ours / n,
            us_scaled=1e6 * t_scaled / n,
            us_vqf=1e6 * t_vqf / n,
        )
        rows.append(row)
        print(
            f"{name:46s} ours {row['ours']:.3f}°  with scale {row['scaled']:.3f}°"
            f"  + VQF rest test {row['scaled_vr']:.3f}°  VQF {row['vqf']:.3f}°"
            f"  offline VQF {row['offline']:.3f}°   {row['us_ours']:.2f} / {row['us_scaled']:.2f} /"
            f" {row['us_vqf']:.2f} µs a sample",
            flush=True,
        )
    if missing:
        print(f"not in this copy (neither .hdf5 nor .mat): {', '.join(missing)}")
    mean = lambda key, rs: float(np.mean([r[key] for r in rs]))
    print(
        f"\nmean over {len(rows)} trials: ours {mean('ours', rows):.3f}°, with scale estimation "
        f"{mean('scaled', rows):.3f}°, with VQF's rest test {mean('scaled_vr', rows):.4f}°, VQF {mean('vqf', rows):.3f}°, offline VQF {mean('offline', rows):.3f}°; "
        f"CPU {mean('us_ours', rows):.2f} / {mean('us_scaled', rows):.2f} / {mean('us_vqf', rows):.2f} µs a sample"
    )
    print("by group (ours / with scale estimation / with VQF's rest test / VQF), 4 decimals:")
    groups = ["undisturbed", "disturbed", "rotation", "translation", "combined", "slow", "fast", "no_breaks",
              "with_breaks", "tapping", "vibration", "stationary_magnet", "attached_magnet"]
    for g in groups:
        rs = [r for r in rows if g in r["groups"]]
        if rs:
            m = {k: mean(k, rs) for k in ("ours", "scaled", "scaled_vr", "vqf")}
            verdict = "<= VQF" if m["scaled_vr"] <= m["vqf"] else "WORSE than VQF"
            print(
                f"  {g:18s} n={len(rs):2d}  {m['ours']:.4f}° / {m['scaled']:.4f}° / {m['scaled_vr']:.4f}°"
                f" / {m['vqf']:.4f}°  ({verdict})"
            )
    print(f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
