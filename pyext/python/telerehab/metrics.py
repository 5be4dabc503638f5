"""Movement measures of a rehabilitation session: smoothness, segmentation, speed, range.

- :func:`sparc` — SPectral ARC length of one movement's speed profile (Balasubramanian et al.
  2015, as their reference code siva82kb/SPARC computes it); dimensionless, ≤ 0, closer to 0
  is smoother.
- :func:`ldlj` — log dimensionless jerk of one movement's speed profile (Hogan & Sternad 2009;
  as monalysa's ``log_dimensionless_jerk(..., data_type="speed")``); dimensionless.
- :func:`segment` — the discrete movements of a continuous speed profile, each scored
  (:class:`Movement`).
- :func:`speed_profile` — the speed (rad/s) of an angle signal (rad): derivative, zero-phase
  Butterworth low-pass, absolute value.
- :func:`session_measures` — a session's movements, their smoothness, speed, time and peaks,
  ranges of motion and time active, as the station's report computes them.
- :func:`speed_metric`, :func:`steering_reversals`, :func:`step_responses` — the robot-grade
  measures (InMotion, Kinarm: Rohrer et al. 2002, Coderre et al. 2010, Markkula & Engström
  2006), as the crate ``metrics``' module ``robot`` defines them.

Thin facade over ``telerehab._native`` (the same Rust code the patient station runs, crate
``metrics``). Sampling rates ``fs`` are in Hz; times carry their unit (``merge_gap_s``); angles
are in rad, the wheel's speed in rad/s. SPARC and LDLJ are invariant to the amplitude of the
speed, so its unit does not matter to them. Bad input raises :class:`ValueError` naming the
argument (and, for NaN or infinity, the index of the sample); the work runs with the GIL
released.
"""

from __future__ import annotations

import json
import operator
from dataclasses import dataclass
from typing import Any, Dict, List, Mapping, Optional

import numpy.typing as npt

from telerehab import _native
from telerehab._validate import FloatArray, samples

__all__ = [
    "sparc",
    "ldlj",
    "segment",
    "Movement",
    "speed_profile",
    "session_measures",
    "speed_metric",
    "steering_reversals",
    "StepResponse",
    "step_responses",
]


def sparc(
    speed: npt.ArrayLike, fs: float, *, padlevel: int = 4, fc: float = 10.0, amp_th: float = 0.05
) -> float:
    """SPectral ARC length (SPARC) of one movement's speed profile; dimensionless, ≤ 0.

    ``speed``: (N,) speed samples of one movement, from rest to rest (segment a continuous
    recording first: :func:`segment`), in any unit (m/s, rad/s: SPARC is invariant to the
    amplitude); at least 3 samples. ``fs``: sampling rate, Hz. Closer to 0 is smoother; a
    minimum-jerk movement scores −1.406.

    As in Balasubramanian, Melendez-Calderon, Roby-Brami & Burdet (2015), J NeuroEng Rehabil
    12:112, and their reference code: the magnitude of the FFT, zero-padded to
    ``2**(ceil(log2 N) + padlevel)`` points (``padlevel`` in 0..8, default 4), normalised to its
    maximum; its arc length over the band from DC up to ``fc`` Hz (default 10 Hz; ``fs/2`` if
    lower), narrowed to the bins at or above ``amp_th`` (in (0, 1), default 0.05) of the
    maximum, with frequency normalised by the band's width.

    Raises ``ValueError`` for fewer than 3 samples, a NaN or infinite sample (its index is
    named), ``fs`` not finite and > 0, a parameter out of range, or a spectrum with no arc (an
    all-zero profile).
    """
    return _native.metrics_sparc(
        samples("speed", speed), float(fs), operator.index(padlevel), float(fc), float(amp_th)
    )


def ldlj(speed: npt.ArrayLike, fs: float) -> float:
    """Log dimensionless jerk (LDLJ) of one movement's speed profile; dimensionless.

    ``speed``: (N,) speed samples of one movement, from rest to rest, in any unit (LDLJ is
    invariant to the amplitude); at least 3 samples. ``fs``: sampling rate, Hz. Negative for
    real movements, closer to 0 is smoother; a minimum-jerk movement sampled at 100 Hz scores
    −5.30.

    ``LDLJ = −ln(T³ / v_peak² · Σ (Δ²v / dt²)² · dt)`` with ``T = N / fs`` s, ``v_peak =
    max |v|`` and ``Δ²`` the second difference, exactly as monalysa's
    ``log_dimensionless_jerk(speed, fs, data_type="speed")`` (Hogan & Sternad 2009;
    Balasubramanian et al. 2012).

    Raises ``ValueError`` for fewer than 3 samples, a NaN or infinite sample (its index is
    named), ``fs`` not finite and > 0, an all-zero profile or one without jerk (a straight
    line, where LDLJ would be +∞).
    """
    return _native.metrics_ldlj(samples("speed", speed), float(fs))


@dataclass(frozen=True)
class Movement:
    """One movement found by :func:`segment`; the samples ``speed[start_index:end_index]``."""

    #: Index of its first sample (the first above the threshold).
    start_index: int
    #: One past its last sample (the first back at or below the threshold, or N).
    end_index: int
    #: Its start time from the first sample, ``start_index / fs``, s.
    start_s: float
    #: Its duration ``(end_index − start_index) / fs``, s.
    duration_s: float
    #: Its peak speed, in the unit of the speed given (rad/s for the wheel).
    peak_speed: float
    #: Local maxima of the speed within it at or above ``peak_fraction`` of its peak: 1 for
    #: a single smooth submovement.
    n_peaks: int
    #: SPARC of its speed samples (:func:`sparc`, default parameters), or None if undefined
    #: or not ``discrete``.
    sparc: Optional[float]
    #: LDLJ of its speed samples (:func:`ldlj`), or None if undefined or not ``discrete``.
    ldlj: Optional[float]
    #: Mean over peak speed of its samples (:func:`speed_metric`), in (0, 1].
    speed_metric: float
    #: A discrete movement: at least 0.2 s of rest before and after it inside the signal and
    #: at most 5 s long (Hogan & Sternad 2007); only these are scored for smoothness.
    discrete: bool = False


def segment(
    speed: npt.ArrayLike,
    fs: float,
    *,
    onset_fraction: float = 0.05,
    floor: float = 0.05,
    merge_gap_s: float = 0.1,
    min_duration_s: float = 0.2,
    peak_fraction: float = 0.1,
) -> List[Movement]:
    """The movements in a continuous speed profile, in time order, each scored.

    ``speed``: (N,) speed samples, ≥ 0 (e.g. :func:`speed_profile` of the wheel angle, rad/s),
    already smoothed (each movement is scored on the samples as given). ``fs``: sampling
    rate, Hz.

    1. threshold ``max(onset_fraction · max(speed), floor)`` (``onset_fraction`` in [0, 1),
       default 5 %; ``floor`` in the unit of the speed, default 0.05 — rad/s for the wheel);
    2. a movement runs from the first sample above the threshold to the first back at or
       below it;
    3. movements separated by less than ``merge_gap_s`` (s, default 0.1) are merged;
    4. movements shorter than ``min_duration_s`` (s, default 0.2) are dropped;
    5. a movement with 0.2 s of rest (speed at or below the threshold) before and after it
       inside the signal, at most 5 s long, is ``discrete`` (Hogan & Sternad 2007).

    Each :class:`Movement` carries its indices, start and duration (s), peak speed, the number
    of its speed peaks at or above ``peak_fraction`` (in [0, 1), default 10 %) of that peak,
    and, when discrete, its SPARC and LDLJ (None where undefined or not discrete).

    Raises ``ValueError`` for an empty signal, a NaN or infinite sample (its index is named),
    ``fs`` not finite and > 0, or a parameter out of range.
    """
    found = _native.metrics_segment(
        samples("speed", speed),
        float(fs),
        float(onset_fraction),
        float(floor),
        float(merge_gap_s),
        float(min_duration_s),
        float(peak_fraction),
    )
    return [Movement(*m) for m in found]


def speed_profile(angle_rad: npt.ArrayLike, fs: float, lowpass_hz: float = 10.0) -> FloatArray:
    """Speed (rad/s) of an angle signal (rad) sampled at ``fs`` Hz, as the station computes it.

    ``angle_rad``: (N,) angle samples, rad. Returns (N,) speeds ≥ 0, rad/s:
    ``|filtfilt(dθ/dt)|`` — the central-difference derivative (``numpy.gradient(θ, 1/fs)``),
    low-passed forward and backward by a 2nd-order Butterworth with cut-off ``lowpass_hz``
    (Hz, default 10; ``scipy.signal.filtfilt(*butter(2, lowpass_hz / (fs / 2)), ...)`` with its
    default padding), then the absolute value. At or above ``fs/2`` no filter is applied.

    Raises ``ValueError`` for a NaN or infinite sample (its index is named), ``fs`` not finite
    and > 0, or ``lowpass_hz`` not > 0.
    """
    return _native.metrics_speed_profile(samples("angle_rad", angle_rad), float(fs), float(lowpass_hz))


def session_measures(
    wheel_angle_rad: npt.ArrayLike,
    fs: float,
    joints: Optional[Mapping[str, npt.ArrayLike]] = None,
) -> Dict[str, Any]:
    """Movement measures of a session, as the station's report computes them.

    ``wheel_angle_rad``: (N,) wheel angle, rad, sampled at ``fs`` Hz. ``joints``: optional
    joint signals by name, each (M,) of any length, in the joint's unit (rad for angles); only
    their ranges are used.

    The wheel's speed is :func:`speed_profile` (10 Hz low-pass), rad/s, segmented by
    :func:`segment` with its defaults. Returns a dict (the Rust ``SessionMeasures`` as JSON):

    - ``fs_hz``, ``total_s`` (``N / fs``, s), ``active_s`` (sum of the movements' durations, s),
      ``active_fraction``, ``peak_speed_rad_s``, ``threshold_rad_s`` (the segmentation's
      threshold);
    - ``movements``: a list of dicts with the fields of :class:`Movement`;
    - ``sparc``, ``ldlj``, ``movement_peak_speed_rad_s``, ``movement_time_s`` (s), ``n_peaks``:
      each ``{"n", "median", "mean"}`` over the movements (``median``/``mean`` None when
      ``n`` is 0);
    - ``speed_metric`` (mean over peak speed) the same over the movements; ``reversals``
      (:func:`steering_reversals`, 2° gap), ``movements_per_min`` and ``reversals_per_min``
      (the dose, per minute of the signal given);
    - ``wheel_range`` (rad) and ``joints`` (a list, in the order given): each ``{"name",
      "min", "max", "range"}``.

    Raises ``ValueError`` for an empty wheel or joint signal, a NaN or infinite sample (the
    signal and index are named), or ``fs`` not finite and > 0.
    """
    wheel = samples("wheel_angle_rad", wheel_angle_rad)
    named = [(name, samples(f"joints[{name!r}]", x)) for name, x in (joints or {}).items()]
    measures: Dict[str, Any] = json.loads(_native.metrics_session_measures(wheel, float(fs), named))
    return measures


def speed_metric(speed: npt.ArrayLike) -> Optional[float]:
    """Mean speed over peak speed of one movement's speed profile, in (0, 1] (Rohrer et al.
    2002, J Neurosci 22:8297): 1 for a constant speed, 1/1.875 ≈ 0.533 for a whole
    minimum-jerk movement; None for an empty or all-zero profile.

    Raises ``ValueError`` for a NaN or infinite sample (its index is named).
    """
    return _native.metrics_speed_metric(samples("speed", speed))


def steering_reversals(angle_rad: npt.ArrayLike, gap_rad: float = 0.03490658503988659) -> int:
    """Steering reversals of an angle signal (rad) with a gap (default 2°; Markkula & Engström
    2006): after the angle has moved ``gap_rad`` one way, each return by at least ``gap_rad``
    from its furthest point is one reversal. A sine of amplitude ≥ the gap over k whole cycles
    has 2k.

    Raises ``ValueError`` for a NaN or infinite sample or ``gap_rad`` not finite and > 0.
    """
    return _native.metrics_steering_reversals(samples("angle_rad", angle_rad), float(gap_rad))


@dataclass(frozen=True)
class StepResponse:
    """The wheel's response to one step of the target (Coderre et al. 2010, for one angle)."""

    #: Index of the step (the first sample with the new target).
    step_index: int
    #: The new target, rad.
    target_rad: float
    #: From the step to the response's onset (the first run of the speed above 10 % of the
    #: response's peak that starts after the step and lasts 0.1 s: a movement still going at
    #: the step, or a shorter burst, is no onset), s.
    reaction_time_s: Optional[float]
    #: 0° when the first movement (onset to first speed peak) goes towards the target, 180°
    #: when it goes the other way (a 1-D angle has nothing in between).
    initial_direction_error_deg: Optional[float]
    #: Path travelled by the angle from onset to the end of the movement over the distance
    #: needed, ``|target − angle at the step|``; 1 for a direct movement.
    path_length_ratio: Optional[float]


def step_responses(
    angle_rad: npt.ArrayLike,
    fs: float,
    step_indices: List[int],
    step_targets_rad: List[float],
) -> List[StepResponse]:
    """The wheel's response to each step of the target in one continuous angle signal (rad,
    sampled at ``fs`` Hz): the steps at ``step_indices`` (in time order) to
    ``step_targets_rad``. A step's window runs to the next step, 4 s, or the signal's end.

    Raises ``ValueError`` for a NaN or infinite angle, ``fs`` not finite and > 0, steps out of
    order or past the signal, or lists of different lengths.
    """
    rows = _native.metrics_step_responses(
        samples("angle_rad", angle_rad),
        float(fs),
        [operator.index(i) for i in step_indices],
        [float(t) for t in step_targets_rad],
    )
    return [StepResponse(*row) for row in rows]
