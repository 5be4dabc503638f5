from typing import Literal, Optional, Tuple

import numpy as np
import numpy.typing as npt

METHODS: Tuple[str, ...]

def integrate(
    rates: npt.ArrayLike,
    dt: float,
    *,
    method: Literal["exp", "quat", "quat1", "coning", "magnus4"] = "exp",
) -> npt.NDArray[np.float64]: ...
def fuse(
    gyr: npt.ArrayLike, acc: npt.ArrayLike, dt: float, *, tau_acc_s: float = 3.0
) -> npt.NDArray[np.float64]: ...
def estimate_bias(
    rates: npt.ArrayLike,
    dt: float,
    *,
    acc: Optional[npt.ArrayLike] = None,
    rate_threshold_deg_s: float = 2.0,
    min_rest_s: float = 1.5,
) -> Tuple[npt.NDArray[np.float64], float]: ...
