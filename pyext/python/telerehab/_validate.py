"""Argument checks shared by the facade modules (private).

Every public function converts its array arguments here before calling ``telerehab._native``:
C-contiguous float64 of the expected shape, finite, else a :class:`ValueError` that names the
argument (as the caller spelled it, unit suffix included) and the expected shape.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


def float_array(name: str, value: Any, ndim: int, expected: str) -> FloatArray:
    """``value`` as a C-contiguous float64 array of ``ndim`` dimensions, or ValueError."""
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as e:  # ragged nested sequences
        raise ValueError(f"{name} must be a real numeric array of shape {expected}: {e}") from None
    if arr.dtype == np.bool_ or arr.dtype.kind not in "fiu":
        raise ValueError(f"{name} must be a real numeric array of shape {expected}, got dtype {arr.dtype}")
    if arr.ndim != ndim:
        raise ValueError(f"{name} must have shape {expected}, got {arr.shape}")
    out: FloatArray = np.ascontiguousarray(arr, dtype=np.float64)
    if not np.all(np.isfinite(out)):
        bad = np.argwhere(~np.isfinite(out))[0]
        raise ValueError(
            f"{name} must be finite (shape {expected}); NaN or infinity at index {tuple(int(i) for i in bad)}"
        )
    return out


def samples(name: str, value: Any, n: Optional[int] = None, reference: str = "") -> FloatArray:
    """A (N,) array; with ``n``, its length must equal ``reference``'s."""
    expected = "(N,)" if n is None else f"({n},) like {reference}"
    arr = float_array(name, value, 1, expected)
    if n is not None and arr.shape[0] != n:
        raise ValueError(f"{name} must have shape {expected}, got {arr.shape}")
    return arr


def vectors(name: str, value: Any, n: Optional[int] = None, reference: str = "") -> FloatArray:
    """A (N, 3) array; with ``n``, its row count must equal ``reference``'s."""
    expected = "(N, 3)" if n is None else f"({n}, 3) like {reference}"
    arr = float_array(name, value, 2, expected)
    if arr.shape[1] != 3 or (n is not None and arr.shape[0] != n):
        raise ValueError(f"{name} must have shape {expected}, got {arr.shape}")
    return arr


def period_s(name: str, value: float) -> float:
    """A sample period in (0, 1] s."""
    dt = float(value)
    if not (np.isfinite(dt) and 0.0 < dt <= 1.0):
        raise ValueError(f"{name} must be in (0, 1] s, got {dt}")
    return dt
