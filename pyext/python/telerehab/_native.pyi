"""Type stubs for the private native module ``telerehab._native`` (pyo3, ``pyext/src``).

The public API is the facade (:mod:`telerehab.calib`, :mod:`telerehab.imu`,
:mod:`telerehab.metrics`, :mod:`telerehab.session`), which converts
and checks its arguments before calling these functions: arrays here are C-contiguous
float64 of the documented shape. Checked against the built module by ``mypy.stubtest`` in
``scripts/test.sh``.
"""

import os
from typing import Any, Dict, Iterator, List, Optional, Tuple, Union, final

import numpy as np
import numpy.typing as npt

_F64 = npt.NDArray[np.float64]

__all__ = [
    "__version__",
    "calibrate_planar_fourbar",
    "calibrate_serial_chain",
    "PlanarFourbarResult",
    "OnlinePlanarFourbar",
    "SerialChainResult",
    "calibrate_arm_3d",
    "Arm3dResult",
    "imu_integrate",
    "imu_fuse",
    "imu_estimate_bias",
    "BiasEstimate",
    "metrics_sparc",
    "metrics_ldlj",
    "metrics_segment",
    "metrics_speed_profile",
    "metrics_session_measures",
    "metrics_speed_metric",
    "metrics_steering_reversals",
    "metrics_step_responses",
    "session_info",
    "session_read",
]

__version__: str

# --- calib -------------------------------------------------------------------------------

@final
class PlanarFourbarResult:
    """A calibrated planar four-bar (lengths m, angles rad, ground link along +x)."""

    @property
    def l1(self) -> float: ...
    @property
    def l3(self) -> float: ...
    @property
    def l4(self) -> float: ...
    @property
    def theta2_0(self) -> float: ...
    @property
    def theta3_0(self) -> float: ...
    @property
    def theta4_0(self) -> float: ...
    @property
    def gyro_bias3(self) -> float: ...
    @property
    def gyro_bias4(self) -> float: ...
    @property
    def method(self) -> str: ...
    @property
    def iterations(self) -> int: ...
    @property
    def converged(self) -> bool: ...
    @property
    def rms_residual(self) -> float: ...
    @property
    def condition_number(self) -> float: ...
    @property
    def outlier_fraction(self) -> float: ...
    @property
    def wheel_range(self) -> Optional[float]: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def std_errors(self) -> Dict[str, float]: ...

def calibrate_planar_fourbar(
    phi2_rad: _F64,
    phi3_rad: _F64,
    phi4_rad: _F64,
    l2_m: float,
    initial: Optional[List[float]],
    method: str,
    time_s: Optional[_F64],
    gyro_bias: bool,
    robust: bool,
    max_iterations: int,
    tolerance: float,
    smoothing_half_window: int,
    errors_in_variables: bool,
) -> PlanarFourbarResult: ...

@final
class OnlinePlanarFourbar:
    """Recursive least-squares four-bar calibration with forgetting."""

    def __new__(cls, l2_m: float, forgetting: float) -> OnlinePlanarFourbar: ...
    def update_many(self, phi2_rad: _F64, phi3_rad: _F64, phi4_rad: _F64) -> None: ...
    @property
    def estimate(self) -> Optional[PlanarFourbarResult]: ...
    @property
    def samples(self) -> int: ...

@final
class SerialChainResult:
    """Calibrated frames of a serial chain and how far to trust them."""

    @property
    def frames(self) -> _F64: ...
    @property
    def iterations(self) -> int: ...
    @property
    def converged(self) -> bool: ...
    @property
    def rms_residual(self) -> float: ...
    @property
    def rms_translation(self) -> float: ...
    @property
    def rms_rotation(self) -> float: ...
    @property
    def condition_number(self) -> float: ...
    @property
    def rank(self) -> int: ...
    @property
    def warnings(self) -> List[str]: ...

def calibrate_serial_chain(
    nominal_frames: _F64,
    joint_motions: _F64,
    measured_end_poses: _F64,
    max_iterations: int,
    tolerance: float,
) -> SerialChainResult: ...

@final
class Arm3dResult:
    """A calibrated spatial arm (m, rad, wheel frame) and how far to trust it."""

    @property
    def shoulder_m(self) -> List[float]: ...
    @property
    def upper_arm_m(self) -> float: ...
    @property
    def forearm_m(self) -> float: ...
    @property
    def heading_offset(self) -> List[float]: ...
    @property
    def heading_drift(self) -> List[float]: ...
    @property
    def heading_model(self) -> str: ...
    @property
    def iterations(self) -> int: ...
    @property
    def converged(self) -> bool: ...
    @property
    def rms_residual(self) -> float: ...
    @property
    def condition_number(self) -> float: ...
    @property
    def direction_noise(self) -> List[float]: ...
    @property
    def grip_spread_m(self) -> float: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def std_errors(self) -> Dict[str, Union[float, List[float]]]: ...

def calibrate_arm_3d(
    upper_dirs: _F64,
    fore_dirs: _F64,
    grip_points_m: _F64,
    time_s: Optional[_F64],
    heading: str,
    errors_in_variables: bool,
    max_iterations: int,
) -> Arm3dResult: ...

# --- imu ---------------------------------------------------------------------------------

def imu_integrate(rates_rad_s: _F64, dt_s: float, method: str) -> _F64: ...
def imu_fuse(gyr_rad_s: _F64, acc_m_s2: _F64, dt_s: float, tau_acc_s: float, scale_estimation: bool, rest_tilt_check: bool) -> _F64: ...

@final
class BiasEstimate:
    """A constant gyro bias from the rest periods; unpacks as ``(bias_rad_s, rest_fraction)``."""

    @property
    def bias_rad_s(self) -> _F64: ...
    @property
    def rest_fraction(self) -> float: ...
    def __iter__(self) -> Iterator[Union[_F64, float]]: ...

def imu_estimate_bias(
    rates_rad_s: _F64,
    dt_s: float,
    acc_m_s2: Optional[_F64],
    rate_threshold_deg_s: float,
    min_rest_s: float,
) -> BiasEstimate: ...

# --- metrics -----------------------------------------------------------------------------

def metrics_sparc(speed: _F64, fs: float, padlevel: int, fc: float, amp_th: float) -> float: ...
def metrics_ldlj(speed: _F64, fs: float) -> float: ...

# (start_index, end_index, start_s, duration_s, peak_speed, n_peaks, sparc, ldlj, speed_metric)
_MovementTuple = Tuple[int, int, float, float, float, int, Optional[float], Optional[float], float]

def metrics_segment(
    speed: _F64,
    fs: float,
    onset_fraction: float,
    floor: float,
    merge_gap_s: float,
    min_duration_s: float,
    peak_fraction: float,
) -> List[_MovementTuple]: ...
def metrics_speed_profile(angle_rad: _F64, fs: float, lowpass_hz: float) -> _F64: ...
def metrics_session_measures(
    wheel_angle_rad: _F64, fs: float, joints: List[Tuple[str, _F64]]
) -> str: ...
def metrics_speed_metric(speed: _F64) -> Optional[float]: ...
def metrics_steering_reversals(angle_rad: _F64, gap_rad: float) -> int: ...

# (step_index, target_rad, reaction_time_s, initial_direction_error_deg, path_length_ratio)
_ResponseTuple = Tuple[int, float, Optional[float], Optional[float], Optional[float]]

def metrics_step_responses(
    angle_rad: _F64, fs: float, step_indices: List[int], step_targets_rad: List[float]
) -> List[_ResponseTuple]: ...

# --- session -----------------------------------------------------------------------------

# A high-rate channel's column: float64, uint64 or bool, (N,) or (N, elements); an enum label
# column as (uint32 codes, distinct labels).
_Column = Union[npt.NDArray[Any], Tuple[npt.NDArray[np.uint32], List[str]]]

def session_read(
    path: Union[str, "os.PathLike[str]"],
    channels: Optional[List[str]] = None,
    start_s: Optional[float] = None,
    end_s: Optional[float] = None,
) -> Tuple[
    Dict[str, str],
    Dict[str, Dict[str, _Column]],
    Dict[str, Dict[str, str]],
    Dict[str, Tuple[bytes, List[bytes]]],
]: ...

# (topic, encoding, schema, readable, messages, first_s, last_s)
_ChannelInfoTuple = Tuple[str, str, str, bool, int, Optional[float], Optional[float]]

def session_info(
    path: Union[str, "os.PathLike[str]"],
) -> Tuple[Dict[str, str], int, bool, List[_ChannelInfoTuple]]: ...
