"""Kinematic calibration of the patient's arm (thesis Jadhav 2004, Chapter 4).

- :func:`calibrate_planar_fourbar` — wheel crank, forearm, upper arm and ground link as a planar
  four-bar (§4.2.1): a closed-form global solution (no initial guess) refined by a robust
  Levenberg–Marquardt with gyro-bias terms; the thesis's Gauss–Newton is available for reference.
- :class:`OnlinePlanarFourbar` — the same estimate updated sample by sample, with forgetting.
- :func:`calibrate_arm_3d` — the spatial arm loop (eq. 4.1 in 3-D): shoulder position and
  upper-arm and forearm lengths from the IMU segment directions and the grip points, in closed
  form (no initial guess).
- :func:`calibrate_serial_chain` — SE(3) calibration of the initial frames of a serial chain
  (§4.3, eq. 4.25–4.49).

Lengths are in metres, angles in radians; argument names carry their unit (``phi2_rad``,
``l2_m``, ``grip_points_m``). Bad input raises :class:`ValueError` naming the argument and
the expected shape; the work runs with the GIL released.
"""

from __future__ import annotations

from typing import List, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from telerehab import _native
from telerehab._native import Arm3dResult, PlanarFourbarResult, SerialChainResult
from telerehab._validate import float_array, samples, vectors

__all__ = [
    "calibrate_planar_fourbar",
    "OnlinePlanarFourbar",
    "calibrate_serial_chain",
    "calibrate_arm_3d",
    "Arm3dResult",
    "PlanarFourbarResult",
    "SerialChainResult",
    "FourbarMethod",
    "HeadingModel",
    "InitialGuess",
]

#: Four-bar calibration methods accepted by :func:`calibrate_planar_fourbar`.
FourbarMethod = Literal["auto", "global", "lm", "thesis"]

#: Heading error models accepted by :func:`calibrate_arm_3d`.
HeadingModel = Literal["exact", "offset", "offset_and_drift"]

#: A start for the four-bar fit: ``{l1, l3, l4, theta2_0, theta3_0, theta4_0}`` (optionally
#: ``gyro_bias3, gyro_bias4``), a sequence of 6 or 8 values in that order, or a result.
InitialGuess = Union[Mapping[str, float], Sequence[float], npt.NDArray[np.float64], PlanarFourbarResult]

_PARAM_NAMES = ("l1", "l3", "l4", "theta2_0", "theta3_0", "theta4_0")


def _initial_vector(initial: Optional[InitialGuess]) -> Optional[List[float]]:
    if initial is None:
        return None
    if isinstance(initial, Mapping):
        missing = [k for k in _PARAM_NAMES if k not in initial]
        if missing:
            raise ValueError(f"initial is missing {missing}; expected keys {list(_PARAM_NAMES)}")
        values = [float(initial[k]) for k in _PARAM_NAMES]
        if "gyro_bias3" in initial or "gyro_bias4" in initial:
            values += [float(initial.get("gyro_bias3", 0.0)), float(initial.get("gyro_bias4", 0.0))]
        return values
    if isinstance(initial, PlanarFourbarResult):
        return [float(getattr(initial, k)) for k in _PARAM_NAMES]
    return [float(v) for v in float_array("initial", initial, 1, "(6,) or (8,)")]


def calibrate_planar_fourbar(
    phi2_rad: npt.ArrayLike,
    phi3_rad: npt.ArrayLike,
    phi4_rad: npt.ArrayLike,
    l2_m: float,
    *,
    initial: Optional[InitialGuess] = None,
    method: FourbarMethod = "auto",
    time_s: Optional[npt.ArrayLike] = None,
    gyro_bias: bool = True,
    robust: bool = True,
    max_iterations: int = 200,
    tolerance: float = 1e-12,
    smoothing_half_window: int = 0,
    errors_in_variables: bool = True,
) -> PlanarFourbarResult:
    """Calibrate the arm–wheel planar four-bar from one recording (thesis eq. 4.1–4.4).

    The loop is ``l2·e^{iθ2} + l3·e^{iθ3} − l4·e^{iθ4} − l1 = 0`` with ``θj = Θj + φj``
    (minus ``bj·t`` for the gyro-measured links when ``gyro_bias``), the ground link along +x
    from the wheel centre to the shoulder.

    Args:
        phi2_rad: (N,) wheel angle relative to the first sample (rad), from the wheel encoder.
        phi3_rad: (N,) forearm angle relative to the first sample (rad), integrated gyro.
        phi4_rad: (N,) upper-arm angle relative to the first sample (rad), integrated gyro.
        l2_m: wheel radius, grip to wheel centre (m), known.
        initial: optional start ``{l1, l3, l4, theta2_0, theta3_0, theta4_0}`` (mapping,
            sequence of 6 or 8 values, or a previous result); required by ``"thesis"`` and
            ``"lm"``, an extra start for ``"auto"``.
        method: ``"auto"`` (global closed form + robust LM with gyro bias; default),
            ``"global"`` (closed form only), ``"lm"`` (robust LM from ``initial``),
            ``"thesis"`` (the thesis's Gauss–Newton from ``initial``, reference only).
        time_s: optional (N,) sample times (s); gyro biases are then in rad/s (else rad/sample).
        gyro_bias: estimate linear drift of φ3 and φ4 (``"auto"``, ``"lm"``).
        robust: down-weight outlying samples (``"auto"``, ``"lm"``).
        max_iterations, tolerance: limits of the iterative stage.
        smoothing_half_window: half-width (samples) of a zero-phase Savitzky–Golay smoother
            applied to the angles first (0 = off, up to 500). White angle noise biases every
            least-squares fit of this loop; smoothing removes most of that bias. Keep the
            window under a quarter of the motion's period (e.g. 25 at 100 Hz). Not needed
            with ``errors_in_variables``.
        errors_in_variables: estimate each sample's angle noise from the data (``"auto"``,
            ``"lm"``), weight the samples by it and remove the bias white angle noise causes in
            every least-squares fit of this loop (thesis Table 4.1's errors). Exact data give
            the same answer either way; turn it off to minimise the plain cost of eq. 4.3.

    Returns:
        A result with ``l1, l3, l4`` (m), ``theta2_0, theta3_0, theta4_0`` (rad),
        ``gyro_bias3, gyro_bias4``, ``iterations``, ``converged``, ``rms_residual`` (m),
        ``std_errors`` (dict, 1σ), ``condition_number``, ``outlier_fraction``, ``wheel_range``
        (rad) and ``warnings`` (list of str, each with the remedy). ``std_errors`` describe
        the random spread only, not the bias angle noise causes; after smoothing they are
        optimistic (the residuals are then correlated).

    Raises:
        ValueError: wrong shape, dtype, NaN, too few samples, or data that do not determine
            the parameters (with the motion to ask the patient for).
    """
    p2 = samples("phi2_rad", phi2_rad)
    n = p2.shape[0]
    p3 = samples("phi3_rad", phi3_rad, n, "phi2_rad")
    p4 = samples("phi4_rad", phi4_rad, n, "phi2_rad")
    t = None if time_s is None else samples("time_s", time_s, n, "phi2_rad")
    return _native.calibrate_planar_fourbar(
        p2, p3, p4, float(l2_m), _initial_vector(initial), str(method), t,
        bool(gyro_bias), bool(robust), int(max_iterations), float(tolerance),
        int(smoothing_half_window), bool(errors_in_variables),
    )


class OnlinePlanarFourbar:
    """Recursive least-squares four-bar calibration with exponential forgetting.

    The square-root information form of the global method: no initial guess, nothing to
    diverge, and old samples fade with factor ``forgetting`` per sample (memory ≈
    ``1/(1 − forgetting)`` samples) so the estimate tracks changes during a session.

    Example:
        >>> est = OnlinePlanarFourbar(0.15)
        >>> est.update(phi2_rad, phi3_rad, phi4_rad)     # scalars or 1-D arrays
        >>> est.estimate.l3                  # None until identifiable
    """

    def __init__(self, l2_m: float, *, forgetting: float = 0.999) -> None:
        """``l2_m``: wheel radius (m); ``forgetting`` in [0.9, 1] (1 = never forget)."""
        self._native = _native.OnlinePlanarFourbar(float(l2_m), float(forgetting))

    def update(self, phi2_rad: npt.ArrayLike, phi3_rad: npt.ArrayLike, phi4_rad: npt.ArrayLike) -> None:
        """Absorb one sample (floats) or a batch (equal-length 1-D arrays), in order (rad)."""
        p2 = samples("phi2_rad", np.atleast_1d(phi2_rad))
        n = p2.shape[0]
        p3 = samples("phi3_rad", np.atleast_1d(phi3_rad), n, "phi2_rad")
        p4 = samples("phi4_rad", np.atleast_1d(phi4_rad), n, "phi2_rad")
        self._native.update_many(p2, p3, p4)

    @property
    def estimate(self) -> Optional[PlanarFourbarResult]:
        """The current estimate, or None while the data do not yet determine it."""
        return self._native.estimate

    @property
    def samples(self) -> int:
        """Samples absorbed so far."""
        return self._native.samples


def calibrate_serial_chain(
    nominal_frames: npt.ArrayLike,
    joint_motions: npt.ArrayLike,
    measured_end_poses: npt.ArrayLike,
    *,
    max_iterations: int = 100,
    tolerance: float = 1e-13,
) -> SerialChainResult:
    """Calibrate the initial frames of a serial chain (thesis §4.3, eq. 4.25–4.49).

    Model ``T_end = F0·Q1·F1·Q2·…·Qn·Fn`` (eq. 4.25); frame errors right-multiplicative
    ``F_i′ = F_i·exp(Δ_i)`` (eq. 4.30), residual ``log∨(T′·T⁻¹)`` (exact log map),
    ``Y = A x`` stacked over measurements (eq. 4.48) and solved by truncated-SVD least squares
    (eq. 4.49), iterated.

    Args:
        nominal_frames: (n+1, 4, 4) nominal initial frame-to-frame transforms F0 … Fn (m).
        joint_motions: (m, n, 4, 4) the relative motions Q1 … Qn of each measurement.
        measured_end_poses: (m, 4, 4) the measured end pose of each measurement.

    Returns:
        A result with ``frames`` (n+1, 4, 4), ``iterations``, ``converged``, ``rms_residual``,
        ``rms_translation`` (m), ``rms_rotation`` (rad), ``condition_number``, ``rank`` (the
        observable frame-error directions out of 6(n+1)) and ``warnings``.

    Raises:
        ValueError: wrong shape, dtype, NaN, non-rigid matrices or too few measurements.
    """
    f = float_array("nominal_frames", nominal_frames, 3, "(n+1, 4, 4)")
    if f.shape[1:] != (4, 4) or f.shape[0] < 1:
        raise ValueError(f"nominal_frames must have shape (n+1, 4, 4), got {f.shape}")
    n = f.shape[0] - 1
    t = float_array("measured_end_poses", measured_end_poses, 3, "(m, 4, 4)")
    if t.shape[1:] != (4, 4):
        raise ValueError(f"measured_end_poses must have shape (m, 4, 4), got {t.shape}")
    m = t.shape[0]
    q = float_array("joint_motions", joint_motions, 4, f"(m, n, 4, 4) = ({m}, {n}, 4, 4)")
    if q.shape != (m, n, 4, 4):
        raise ValueError(f"joint_motions must have shape (m, n, 4, 4) = ({m}, {n}, 4, 4), got {q.shape}")
    return _native.calibrate_serial_chain(f, q, t, int(max_iterations), float(tolerance))


def calibrate_arm_3d(
    upper_dirs: npt.ArrayLike,
    fore_dirs: npt.ArrayLike,
    grip_points_m: npt.ArrayLike,
    *,
    time_s: Optional[npt.ArrayLike] = None,
    heading: HeadingModel = "offset_and_drift",
    errors_in_variables: bool = True,
    max_iterations: int = 20,
) -> Arm3dResult:
    """Calibrate the patient's arm in 3-D: shoulder position and segment lengths.

    Loop closure at every sample (the thesis's eq. 4.1 written in 3-D, §4.3)::

        S + upper_arm·u_k + forearm·f_k = G_k

    which is linear in the shoulder ``S`` and the two lengths: the least-squares solution is
    global and needs no initial guess. Frame: the wheel frame (origin at the wheel centre,
    x forward, y left, z up).

    Args:
        upper_dirs: (N, 3) unit direction shoulder → elbow per sample, wheel frame (the upper-arm
            segment's x axis from the IMU orientation and its mounting).
        fore_dirs: (N, 3) unit direction elbow → grip per sample (the forearm's x axis).
        grip_points_m: (N, 3) grip point on the rim at the measured wheel angle (m).
        time_s: optional (N,) sample times (s); the heading drift is then per second, else
            per sample.
        heading: heading error of the IMU directions to estimate alongside: ``"exact"``
            (none, 5 unknowns), ``"offset"`` (a constant offset per segment) or
            ``"offset_and_drift"`` (offset and a linear drift per segment; the default: the
            orientation filter's heading drifts by tens of degrees a minute with consumer
            IMUs, which costs ~4 cm of length without it).
        errors_in_variables: estimate the white direction noise from the data and remove the
            length bias it causes (without it, 2° of noise shortens the arm by ~2 cm).
        max_iterations: passes of the exact heading re-rotation, 1..50 (stops earlier when
            converged).

    Returns:
        A result with ``shoulder_m`` (3 floats), ``upper_arm_m``, ``forearm_m``,
        ``heading_offset`` (rad, [upper, fore], at the first sample), ``heading_drift``
        (rad/s, or rad/sample without ``time_s``), ``rms_residual`` (m), ``std_errors`` (dict, 1σ), ``condition_number``,
        ``direction_noise`` (rad), ``grip_spread_m``, ``iterations``, ``converged`` and
        ``warnings`` (list of str, each with the remedy, e.g. "turn the wheel further").

    Raises:
        ValueError: wrong shape, dtype, NaN, directions that are not unit vectors, too few
            samples, or a wheel that never turned (the parameters are then not identifiable).
    """
    u = vectors("upper_dirs", upper_dirs)
    n = u.shape[0]
    f = vectors("fore_dirs", fore_dirs, n, "upper_dirs")
    g = vectors("grip_points_m", grip_points_m, n, "upper_dirs")
    t = None if time_s is None else samples("time_s", time_s, n, "upper_dirs")
    return _native.calibrate_arm_3d(u, f, g, t, str(heading), bool(errors_in_variables), int(max_iterations))
