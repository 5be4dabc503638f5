"""Gyro integration, gyro-bias estimation and gyro+accelerometer orientation fusion.

Thin facade over ``telerehab._native`` (the same Rust code the patient station runs). All
arrays are float64; rates in rad/s, accelerations in m/s², periods in s.
"""

from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from telerehab import _native

__all__ = ["integrate", "fuse", "estimate_bias", "METHODS"]

#: Integration methods accepted by :func:`integrate`.
METHODS = ("exp", "quat", "quat1", "coning", "magnus4")


def _vectors(name: str, x) -> np.ndarray:
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"`{name}` must be a numeric array of shape (N, 3): {e}") from None
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"`{name}` must have shape (N, 3), got {a.shape}")
    if not np.all(np.isfinite(a)):
        bad = int(np.argwhere(~np.isfinite(a))[0][0])
        raise ValueError(f"`{name}` row {bad} is not finite")
    return np.ascontiguousarray(a)


def _dt(dt) -> float:
    dt = float(dt)
    if not (np.isfinite(dt) and 0.0 < dt <= 1.0):
        raise ValueError(f"`dt` must be in (0, 1] s, got {dt}")
    return dt


def integrate(rates, dt: float, *, method: str = "exp") -> np.ndarray:
    """Integrate body-frame angular rates into orientation (thesis eq. 4.12–4.13).

    ``rates``: (N, 3) rad/s, one sample per period ``dt`` (s). Returns (N + 1, 3, 3) rotation
    matrices (body to initial frame) with ``R[0] = I`` and ``R[k+1] = R[k] @ exp([ω_k]× dt)``
    for ``method="exp"`` (Rodrigues) or ``"quat"`` (the same map as quaternions);
    ``"quat1"`` is the first-order quaternion update, ``"coning"`` the two-sample coning
    correction and ``"magnus4"`` a fourth-order Magnus step (both use the next samples).
    """
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    return _native.imu_integrate(_vectors("rates", rates), _dt(dt), method)


def fuse(gyr, acc, dt: float, *, tau_acc_s: float = 3.0) -> np.ndarray:
    """Orientation from gyroscope and accelerometer with online gyro-bias estimation.

    ``gyr``: (N, 3) rad/s and ``acc``: (N, 3) m/s², both in the sensor frame, sample period
    ``dt`` (s). Returns (N, 4) unit quaternions ``(w, x, y, z)`` of the sensor-to-earth
    orientation, earth z axis up, heading relative to the first sample. VQF-style (Laidig &
    Seel 2023): inclination from accelerations low-pass filtered in an almost-inertial frame,
    bias estimated at rest and during motion. No per-recording tuning is needed.
    """
    g = _vectors("gyr", gyr)
    a = _vectors("acc", acc)
    if g.shape[0] != a.shape[0]:
        raise ValueError(f"`gyr` has {g.shape[0]} rows but `acc` has {a.shape[0]}")
    return _native.imu_fuse(g, a, _dt(dt), float(tau_acc_s))


def estimate_bias(
    rates,
    dt: float,
    *,
    acc=None,
    rate_threshold_deg_s: float = 2.0,
    min_rest_s: float = 1.5,
) -> Tuple[np.ndarray, float]:
    """Gyro bias from the rest periods of a record.

    ``rates``: (N, 3) rad/s; optional ``acc``: (N, 3) m/s² sharpens rest detection. Returns
    ``(bias, rest_fraction)``: the mean rate (3,) rad/s over the samples detected as rest and
    the fraction of samples at rest. Raises ``ValueError`` if no rest is found.
    """
    w = _vectors("rates", rates)
    a: Optional[np.ndarray] = None
    if acc is not None:
        a = _vectors("acc", acc)
        if a.shape[0] != w.shape[0]:
            raise ValueError(f"`acc` has {a.shape[0]} rows but `rates` has {w.shape[0]}")
    return _native.imu_estimate_bias(w, _dt(dt), a, float(rate_threshold_deg_s), float(min_rest_s))
