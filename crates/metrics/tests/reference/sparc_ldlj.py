#!/usr/bin/env python3
"""Independent reference values for crates/metrics: SPARC, LDLJ and the wheel's speed profile.

A straight transcription, in numpy, of the published algorithms:
- SPARC: Balasubramanian, Melendez-Calderon, Roby-Brami & Burdet (2015), "On the analysis of
  movement smoothness", J NeuroEng Rehabil 12:112, as in its reference code (siva82kb/SPARC,
  function `sparc`);
- LDLJ for a speed profile: Hogan & Sternad (2009); Balasubramanian et al. (2012), as in
  monalysa's `log_dimensionless_jerk(movement, fs, data_type="speed")`;
- speed profile: |scipy.signal.filtfilt(butter(2, fc/(fs/2)), numpy.gradient(theta, 1/fs))|.

Signals are generated deterministically (sums of minimum-jerk submovements with fixed
overlaps; Gaussian noise from a fixed seed) and written out with their samples, so the Rust
test reads the very same numbers.

Usage: python3 sparc_ldlj.py > expected.json   (tests/python/test_metrics_reference.py
checks that the committed expected.json is still what this prints.)
"""

from __future__ import annotations

import json
import sys

import numpy as np
from scipy import signal as sps

SEED = 20261125


def sparc(movement, fs, padlevel=4, fc=10.0, amp_th=0.05):
    """Spectral arc length (Balasubramanian 2015), as siva82kb/SPARC computes it."""
    nfft = int(pow(2, np.ceil(np.log2(len(movement))) + padlevel))
    f = np.arange(0, fs, fs / nfft)
    mf = np.abs(np.fft.fft(movement, nfft))
    mf = mf / np.max(mf)
    sel = np.nonzero(f <= fc)[0]
    f_sel = f[sel]
    mf_sel = mf[sel]
    inx = np.nonzero(mf_sel >= amp_th)[0]
    band = np.arange(inx[0], inx[-1] + 1)
    f_sel = f_sel[band]
    mf_sel = mf_sel[band]
    return float(
        -np.sum(
            np.sqrt(
                (np.diff(f_sel) / (f_sel[-1] - f_sel[0])) ** 2 + np.diff(mf_sel) ** 2
            )
        )
    )


def log_dimensionless_jerk(movement, fs):
    """LDLJ of a speed profile, as monalysa computes it (T = n/fs, numpy.diff twice)."""
    movement = np.asarray(movement, dtype=float)
    peak = np.max(np.abs(movement))
    dt = 1.0 / fs
    duration = len(movement) * dt
    jerk = np.diff(movement, 2) / dt**2
    scale = duration**3 / peak**2
    dimensionless = -scale * np.sum(jerk**2) * dt
    return float(-np.log(np.abs(dimensionless)))


def speed_profile(theta, fs, fc=10.0):
    """|filtfilt(2nd-order Butterworth at fc, d theta/dt)|, d/dt by numpy.gradient."""
    b, a = sps.butter(2, fc / (fs / 2.0))
    return np.abs(sps.filtfilt(b, a, np.gradient(theta, 1.0 / fs)))


def min_jerk_speed(t, onset, duration, amplitude):
    """Speed of a minimum-jerk point-to-point movement of `amplitude` in `duration` s."""
    tau = (t - onset) / duration
    inside = (tau >= 0.0) & (tau <= 1.0)
    return np.where(inside, amplitude / duration * 30.0 * tau**2 * (1.0 - tau) ** 2, 0.0)


def submovements(fs, k, duration, overlap, amplitude=1.0):
    """k equal minimum-jerk submovements, each starting (1 - overlap) * duration after the last."""
    step = duration * (1.0 - overlap)
    total = duration + (k - 1) * step
    t = np.arange(0.0, total + 0.5 / fs, 1.0 / fs)
    v = sum(min_jerk_speed(t, i * step, duration, amplitude) for i in range(k))
    return t, v


def cases():
    rng = np.random.default_rng(SEED)
    out = []
    t = np.arange(-1.0, 1.0, 0.01)
    out.append(("gaussian_exp_m5t2_100hz", 100.0, np.exp(-5.0 * t**2)))
    t = np.arange(0.0, 1.01, 0.01)
    out.append(("min_jerk_1s_100hz", 100.0, 30 * t**2 - 60 * t**3 + 30 * t**4))
    for fs in (100.0, 250.0):
        for k in (2, 3, 5):
            for overlap in (0.25, 0.5, 0.75):
                _, v = submovements(fs, k, 0.8, overlap)
                out.append((f"submov_k{k}_ov{int(overlap * 100)}_{int(fs)}hz", fs, v))
    for k, overlap in ((1, 0.0), (3, 0.5), (4, 0.25)):
        _, v = submovements(100.0, k, 1.0, overlap, amplitude=0.6)
        noisy = np.abs(v + rng.normal(0.0, 0.02 * np.max(v), size=v.shape))
        out.append((f"noisy_k{k}_ov{int(overlap * 100)}_100hz", 100.0, noisy))
    return out, rng


def main() -> int:
    items, rng = cases()
    result = {
        "generator": "crates/metrics/tests/reference/sparc_ldlj.py",
        "seed": SEED,
        "cases": [
            {
                "name": name,
                "fs_hz": fs,
                "speed": [float(x) for x in v],
                "sparc": sparc(v, fs),
                "ldlj": log_dimensionless_jerk(v, fs),
            }
            for name, fs, v in items
        ],
    }
    # The wheel: a 6 s angle trace of three movements with sensor noise, at 100 Hz.
    fs = 100.0
    t = np.arange(0.0, 6.0, 1.0 / fs)
    rate = (
        min_jerk_speed(t, 0.5, 1.0, 0.5)
        - min_jerk_speed(t, 2.5, 0.8, 0.8)
        + min_jerk_speed(t, 4.0, 1.2, 0.3)
    )
    theta = np.cumsum(rate) / fs + rng.normal(0.0, 1e-3, size=t.shape)
    result["speed_profile"] = {
        "fs_hz": fs,
        "lowpass_hz": 10.0,
        "angle": [float(x) for x in theta],
        "speed": [float(x) for x in speed_profile(theta, fs)],
    }
    json.dump(result, sys.stdout, indent=1)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
