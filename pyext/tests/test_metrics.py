"""telerehab.metrics: the published SPARC and LDLJ values, agreement with the independent
numpy/scipy transcription (crates/metrics/tests/reference/sparc_ldlj.py), segmentation of a
two-turn movement, session measures, and the binding convention (ValueErrors naming the
argument and the sample index; lists and any real dtype accepted by the facade, float64 only
in the native layer)."""

import dataclasses
import importlib.util
from pathlib import Path

import numpy as np
import pytest

from telerehab import _native, metrics

REFERENCE = Path(__file__).resolve().parents[2] / "crates" / "metrics" / "tests" / "reference" / "sparc_ldlj.py"

# The published values are printed to 5 decimals.
PUBLISHED_REL = 1e-5
# Same definitions, another FFT (pocketfft vs rustfft): only rounding differs (~1e-15).
REFERENCE_REL = 1e-9

FS = 100.0


def gaussian():
    """exp(−5t²) for t = −1, −0.99, …, 0.99 (numpy.arange(-1, 1, 0.01): 200 samples), 100 Hz."""
    t = np.arange(-1.0, 1.0, 0.01)
    return np.exp(-5.0 * t**2)


def min_jerk():
    """1 s minimum-jerk speed 30t² − 60t³ + 30t⁴, t = 0, 0.01, …, 1 (101 samples), 100 Hz."""
    t = np.arange(0.0, 1.01, 0.01)
    return 30 * t**2 - 60 * t**3 + 30 * t**4


@pytest.fixture(scope="module")
def ref():
    """The numpy/scipy transcription of siva82kb/SPARC, monalysa's LDLJ and the speed profile."""
    pytest.importorskip("scipy", reason="SKIPPED: the reference transcription needs scipy")
    spec = importlib.util.spec_from_file_location("sparc_ldlj_reference", REFERENCE)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# --- (1) published values ----------------------------------------------------------------


@pytest.mark.parametrize(
    "signal, want_sparc, want_ldlj",
    [(gaussian, -1.41403, -5.81636), (min_jerk, -1.40583, -5.30163)],
    ids=["gaussian", "min_jerk"],
)
def test_published_sparc_and_ldlj(signal, want_sparc, want_ldlj):
    v = signal()
    assert metrics.sparc(v, FS) == pytest.approx(want_sparc, rel=PUBLISHED_REL)
    assert metrics.ldlj(v, FS) == pytest.approx(want_ldlj, rel=PUBLISHED_REL)


# --- (2) the independent transcription -----------------------------------------------------


def _reference_signals(ref):
    rng = np.random.default_rng(20260611)
    out = [("gaussian", FS, gaussian()), ("min_jerk", FS, min_jerk())]
    for fs, k, overlap in ((100.0, 2, 0.25), (100.0, 3, 0.5), (250.0, 5, 0.75)):
        _, v = ref.submovements(fs, k, 0.8, overlap)
        out.append((f"submov_k{k}_{int(fs)}hz", fs, v))
    _, v = ref.submovements(FS, 3, 1.0, 0.5, amplitude=0.6)
    out.append(("noisy_k3", FS, np.abs(v + rng.normal(0.0, 0.02 * np.max(v), size=v.shape))))
    return out


def test_sparc_and_ldlj_agree_with_the_numpy_transcription(ref):
    for name, fs, v in _reference_signals(ref):
        assert metrics.sparc(v, fs) == pytest.approx(ref.sparc(v, fs), rel=REFERENCE_REL), name
        assert metrics.ldlj(v, fs) == pytest.approx(ref.log_dimensionless_jerk(v, fs), rel=REFERENCE_REL), name


@pytest.mark.parametrize(
    "params", [dict(padlevel=0), dict(padlevel=6), dict(fc=5.0), dict(amp_th=0.2), dict(padlevel=2, fc=20.0, amp_th=0.01)]
)
def test_sparc_parameters_mean_what_the_reference_means(ref, params):
    for name, fs, v in _reference_signals(ref):
        assert metrics.sparc(v, fs, **params) == pytest.approx(ref.sparc(v, fs, **params), rel=REFERENCE_REL), name


def test_speed_profile_agrees_with_scipy_filtfilt_of_numpy_gradient(ref):
    rng = np.random.default_rng(20260612)
    for fs, lowpass_hz in ((100.0, 10.0), (250.0, 6.0)):
        t = np.arange(0.0, 4.0, 1.0 / fs)
        rate = ref.min_jerk_speed(t, 0.5, 1.0, 0.5) - ref.min_jerk_speed(t, 2.0, 1.2, 0.8)
        theta = np.cumsum(rate) / fs + rng.normal(0.0, 1e-3, size=t.shape)
        got = metrics.speed_profile(theta, fs, lowpass_hz)
        want = ref.speed_profile(theta, fs, lowpass_hz)
        assert got.shape == want.shape and got.dtype == np.float64
        np.testing.assert_allclose(got, want, rtol=0, atol=REFERENCE_REL * np.max(want))


# --- (3) segmentation ----------------------------------------------------------------------

TURN_ONSETS_S = (1.0, 3.0)
TURN_RAD = 0.6


def two_turns():
    """Two 1 s minimum-jerk turns of 0.6 rad, there (at 1 s) and back (at 3 s), 5 s at 100 Hz:
    the angle (rad) and its exact speed (rad/s)."""
    t = np.arange(500) / FS

    def s(onset):
        tau = np.clip(t - onset, 0.0, 1.0)
        return 10 * tau**3 - 15 * tau**4 + 6 * tau**5

    def ds(onset):
        tau = t - onset
        return np.where((tau >= 0) & (tau <= 1), 30 * tau**2 * (1 - tau) ** 2, 0.0)

    angle = TURN_RAD * (s(TURN_ONSETS_S[0]) - s(TURN_ONSETS_S[1]))
    speed = TURN_RAD * (ds(TURN_ONSETS_S[0]) + ds(TURN_ONSETS_S[1]))
    return angle, speed


def test_segment_finds_both_turns_with_their_start_and_duration():
    _, speed = two_turns()
    found = metrics.segment(speed, FS)
    assert len(found) == 2, found
    # Threshold max(5 % of the peak 1.875·0.6 rad/s, 0.05 rad/s); the minimum-jerk speed
    # 30τ²(1−τ)²·0.6 crosses it at τ0 and 1 − τ0.
    threshold = max(0.05 * 1.875 * TURN_RAD, 0.05)
    tau0 = (1 - np.sqrt(1 - 4 * np.sqrt(threshold / (30 * TURN_RAD)))) / 2
    above = np.flatnonzero(speed > threshold)
    for m, onset in zip(found, TURN_ONSETS_S):
        assert isinstance(m, metrics.Movement)
        assert abs(m.start_s - (onset + tau0)) <= 1 / FS
        assert abs(m.duration_s - (1 - 2 * tau0)) <= 2 / FS
        assert m.start_s == m.start_index / FS
        assert m.duration_s == pytest.approx((m.end_index - m.start_index) / FS, rel=1e-15)
        run = above[(above >= m.start_index) & (above < m.end_index)]
        assert (run[0], run[-1] + 1) == (m.start_index, m.end_index)
        assert m.peak_speed == pytest.approx(1.875 * TURN_RAD, rel=1e-3)
        assert m.n_peaks == 1 and m.discrete
        assert m.sparc is not None and -1.6 < m.sparc < -1.3
        assert m.sparc == metrics.sparc(speed[m.start_index : m.end_index], FS)
        assert m.ldlj == metrics.ldlj(speed[m.start_index : m.end_index], FS)


def test_segment_parameters_merge_and_drop():
    _, speed = two_turns()
    # A 1.2 s merge gap joins the two turns (1.1 s apart); a 1 s minimum drops both.
    (merged,) = metrics.segment(speed, FS, merge_gap_s=1.2)
    assert merged.n_peaks == 2 and merged.start_s < 1.1 and merged.duration_s > 2.8
    assert metrics.segment(speed, FS, min_duration_s=1.0) == []
    # A floor above the peak: nothing moves.
    assert metrics.segment(speed, FS, floor=2.0) == []


def test_movement_is_a_frozen_dataclass():
    (m, _) = metrics.segment(two_turns()[1], FS)
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.start_s = 0.0  # type: ignore[misc]
    assert [f.name for f in dataclasses.fields(m)] == [
        "start_index", "end_index", "start_s", "duration_s", "peak_speed", "n_peaks", "sparc", "ldlj",
        "speed_metric", "discrete",
    ]


def test_session_measures_of_two_turns():
    angle, _ = two_turns()
    elbow = 2 * angle + 0.1
    s = metrics.session_measures(angle, FS, {"elbow": elbow, "shoulder": [0.0, 0.5, 0.2]})
    assert s["fs_hz"] == FS and s["total_s"] == pytest.approx(5.0, rel=1e-15)
    movements = [metrics.Movement(**m) for m in s["movements"]]
    assert movements == metrics.segment(metrics.speed_profile(angle, FS), FS)
    assert len(movements) == 2
    assert s["active_s"] == pytest.approx(sum(m.duration_s for m in movements), rel=1e-15)
    assert s["active_fraction"] == pytest.approx(s["active_s"] / 5.0, rel=1e-15)
    assert s["peak_speed_rad_s"] == pytest.approx(1.125, abs=0.01)
    assert s["sparc"]["n"] == 2 and -1.6 < s["sparc"]["median"] < -1.3
    assert s["n_peaks"] == {"n": 2, "median": 1.0, "mean": 1.0}
    assert s["wheel_range"]["name"] == "wheel" and s["wheel_range"]["range"] == pytest.approx(TURN_RAD, abs=1e-9)
    assert [j["name"] for j in s["joints"]] == ["elbow", "shoulder"]
    assert s["joints"][0]["range"] == pytest.approx(2 * TURN_RAD, abs=1e-9)
    assert s["joints"][1] == {"name": "shoulder", "min": 0.0, "max": 0.5, "range": 0.5}
    assert metrics.session_measures(angle, FS)["joints"] == []


def test_session_measures_at_rest_has_no_movements_and_no_summaries():
    s = metrics.session_measures(np.zeros(300), FS)
    assert s["movements"] == [] and s["active_s"] == 0.0
    assert s["sparc"] == {"n": 0, "median": None, "mean": None}


# --- (4) bad input -------------------------------------------------------------------------

NAN_AT_7 = min_jerk()
NAN_AT_7[7] = np.nan


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: metrics.sparc(NAN_AT_7, FS), r"speed must be finite .*index \(7,\)"),
        (lambda: metrics.ldlj(NAN_AT_7, FS), r"speed must be finite .*index \(7,\)"),
        (lambda: metrics.segment(NAN_AT_7, FS), r"speed must be finite .*index \(7,\)"),
        (lambda: metrics.speed_profile(NAN_AT_7, FS), r"angle_rad must be finite .*index \(7,\)"),
        (lambda: metrics.session_measures(NAN_AT_7, FS), r"wheel_angle_rad must be finite .*index \(7,\)"),
        (lambda: metrics.session_measures(min_jerk(), FS, {"elbow": NAN_AT_7}), r"joints\['elbow'\] must be finite .*index \(7,\)"),
        (lambda: metrics.sparc(np.full(20, np.inf), FS), r"speed must be finite .*index \(0,\)"),
    ],
)
def test_nan_raises_value_error_naming_the_argument_and_index(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize("fs", [0.0, -100.0, np.nan, np.inf])
@pytest.mark.parametrize(
    "call",
    [metrics.sparc, metrics.ldlj, metrics.segment, metrics.speed_profile, metrics.session_measures],
    ids=lambda f: f.__name__,
)
def test_bad_sampling_rate_raises_value_error(call, fs):
    with pytest.raises(ValueError, match=r"sampling rate fs = \S+ Hz: must be finite and > 0"):
        call(min_jerk(), fs)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: metrics.sparc(min_jerk(), FS, padlevel=-1), r"`padlevel` = -1 is out of range; allowed: 0 ..= 8"),
        (lambda: metrics.sparc(min_jerk(), FS, padlevel=9), r"`padlevel` = 9 is out of range"),
        (lambda: metrics.sparc(min_jerk(), FS, fc=0.0), r"`fc` = 0 is out of range; allowed: finite and > 0 Hz"),
        (lambda: metrics.sparc(min_jerk(), FS, amp_th=1.5), r"`amp_th` = 1.5 is out of range"),
        (lambda: metrics.segment(min_jerk(), FS, merge_gap_s=-1.0), r"`merge_gap_s` = -1 is out of range"),
        (lambda: metrics.segment(min_jerk(), FS, onset_fraction=1.0), r"`onset_fraction` = 1 is out of range"),
        (lambda: metrics.segment(min_jerk(), FS, peak_fraction=np.nan), r"`peak_fraction` = NaN is out of range"),
        (lambda: metrics.speed_profile(min_jerk(), FS, lowpass_hz=0.0), r"lowpass_hz must be > 0 Hz"),
        (lambda: metrics.ldlj([1.0, 2.0], FS), r"^speed: 2 sample\(s\), at least 3 needed$"),
        (lambda: metrics.segment([], FS), r"^speed: no samples$"),
        (lambda: metrics.sparc(np.zeros(50), FS), r"speed: the spectrum is zero .*SPARC is undefined"),
        (lambda: metrics.ldlj(np.full(50, 0.5), FS), r"speed: .*LDLJ would be \+inf"),
        (lambda: metrics.session_measures([], FS), r"^wheel_angle_rad: no samples$"),
        (lambda: metrics.session_measures([0.0], FS, {"elbow": []}), r'^joints\["elbow"\]: no samples$'),
    ],
)
def test_bad_parameters_and_degenerate_signals_raise_value_error_naming_them(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: _native.metrics_sparc(NAN_AT_7, FS, 4, 10.0, 0.05), r"^speed: sample at index 7 is not finite \(NaN\)$"),
        (lambda: _native.metrics_ldlj(NAN_AT_7, FS), r"^speed: sample at index 7 is not finite"),
        (lambda: _native.metrics_segment(NAN_AT_7, FS, 0.05, 0.05, 0.1, 0.2, 0.1), r"^speed: sample at index 7"),
        (lambda: _native.metrics_speed_profile(NAN_AT_7, FS, 10.0), r"^angle_rad\[7\] is not finite"),
        (lambda: _native.metrics_session_measures(NAN_AT_7, FS, []), r"^wheel_angle_rad: sample at index 7"),
        (lambda: _native.metrics_session_measures(min_jerk(), FS, [("elbow", NAN_AT_7)]), r'^joints\["elbow"\]: sample at index 7'),
    ],
)
def test_native_layer_checks_on_its_own_and_uses_the_python_names(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# --- (5) what the facade accepts -----------------------------------------------------------


def test_lists_and_integer_arrays_are_accepted_as_float64():
    v = min_jerk()
    assert metrics.sparc(list(v), FS) == metrics.sparc(v, FS)
    assert metrics.ldlj(tuple(v), FS) == metrics.ldlj(v, FS)
    counts = np.round(100 * v).astype(np.int32)
    assert metrics.ldlj(counts, FS) == metrics.ldlj(counts.astype(np.float64), FS)
    angle, speed = two_turns()
    assert metrics.segment(list(speed), FS) == metrics.segment(speed, FS)
    np.testing.assert_array_equal(metrics.speed_profile(list(angle), FS), metrics.speed_profile(angle, FS))
    assert metrics.session_measures(list(angle), FS, {"e": list(angle)}) == metrics.session_measures(angle, FS, {"e": angle})


def test_float32_is_widened_exactly_to_float64():
    v32 = min_jerk().astype(np.float32)
    assert metrics.sparc(v32, FS) == metrics.sparc(v32.astype(np.float64), FS)
    assert metrics.ldlj(v32, FS) == metrics.ldlj(v32.astype(np.float64), FS)
    assert metrics.sparc(v32, FS) == pytest.approx(-1.40583, rel=PUBLISHED_REL)
    out = metrics.speed_profile(two_turns()[0].astype(np.float32), FS)
    assert out.dtype == np.float64


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: metrics.sparc(np.ones(20, dtype=bool), FS), r"speed must be a real numeric array of shape \(N,\), got dtype bool"),
        (lambda: metrics.ldlj(np.ones(20) + 1j, FS), r"speed must be a real numeric array .* got dtype complex128"),
        (lambda: metrics.segment(["a", "b", "c"], FS), r"speed must be a real numeric array"),
        (lambda: metrics.sparc(np.ones((20, 2)), FS), r"speed must have shape \(N,\), got \(20, 2\)"),
        (lambda: metrics.speed_profile(np.float64(1.0), FS), r"angle_rad must have shape \(N,\), got \(\)"),
        (lambda: metrics.session_measures([[0.0, 1.0], [2.0]], FS), r"wheel_angle_rad must be a real numeric array"),
        (lambda: metrics.session_measures(min_jerk(), FS, {"elbow": np.zeros((3, 3))}), r"joints\['elbow'\] must have shape \(N,\)"),
    ],
)
def test_other_dtypes_and_shapes_are_rejected_naming_the_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_native_layer_takes_float64_only():
    with pytest.raises(TypeError):
        _native.metrics_sparc(min_jerk().astype(np.float32), FS, 4, 10.0, 0.05)
    with pytest.raises(TypeError):
        _native.metrics_ldlj(list(min_jerk()), FS)  # type: ignore[arg-type]


def test_robot_measures_have_their_known_answers_on_synthetic_signals():
    # Speed metric: a constant speed 1, a whole minimum-jerk movement 1/1.875.
    assert metrics.speed_metric(np.full(50, 0.7)) == pytest.approx(1.0)
    assert metrics.speed_metric(min_jerk()) == pytest.approx(1 / 1.875, abs=0.01)
    assert metrics.speed_metric([0.0, 0.0]) is None
    # Three cycles of a 0.5 rad sine: six reversals; fixed-seed noise under the gap: none.
    t = np.arange(601) / FS
    assert metrics.steering_reversals(0.5 * np.sin(2 * np.pi * 0.5 * t)) == 6
    noise = np.random.default_rng(30).uniform(-0.015, 0.015, 2000)
    assert metrics.steering_reversals(noise) == 0
    # A step to 0.5 rad at 1 s, the wheel turning 0.3 s later in 0.8 s (minimum jerk).
    tau = np.clip((np.arange(500) / FS - 1.3) / 0.8, 0.0, 1.0)
    angle = 0.5 * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)
    (r,) = metrics.step_responses(angle, FS, [100], [0.5])
    assert r.reaction_time_s == pytest.approx(0.37, abs=0.02)
    assert r.initial_direction_error_deg == 0.0
    assert r.path_length_ratio == pytest.approx(1.0, abs=0.05)
    # The wrong way: 180°.
    (wrong,) = metrics.step_responses(angle, FS, [100], [-0.5])
    assert wrong.initial_direction_error_deg == 180.0
    with pytest.raises(ValueError, match="step_targets_rad"):
        metrics.step_responses(angle, FS, [100], [])
    with pytest.raises(ValueError, match="angle_rad"):
        metrics.steering_reversals([0.0, float("nan")])
    # The session measures carry the dose.
    m = metrics.session_measures(angle, FS)
    assert m["movements_per_min"] == pytest.approx(len(m["movements"]) * 60 / 5.0)
    assert m["speed_metric"]["n"] == len(m["movements"])
