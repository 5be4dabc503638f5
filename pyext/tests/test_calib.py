"""Behaviour of telerehab.calib from Python (fixed seeds, simulated recordings)."""

import math
import threading

import numpy as np
import pytest

from telerehab import calib

from fourbar_sim import GEOMETRY, simulate

L2 = GEOMETRY["l2"]


def rel_err(result, truth):
    lengths = max(abs(getattr(result, k) - truth[k]) / truth[k] for k in ("l1", "l3", "l4"))
    angles = max(
        abs(math.remainder(getattr(result, k) - truth[k], 2 * math.pi))
        for k in ("theta2_0", "theta3_0", "theta4_0")
    )
    return max(lengths, angles)


def test_noise_free_recording_recovers_the_truth_to_1e9():
    phi2, phi3, phi4, t, truth = simulate()
    r = calib.calibrate_planar_fourbar(phi2, phi3, phi4, L2, time_s=t)
    assert rel_err(r, truth) < 1e-9
    assert r.rms_residual < 1e-12
    assert r.warnings == []
    assert set(r.std_errors) >= {"l1", "l3", "l4", "theta2_0", "theta3_0", "theta4_0"}
    assert r.condition_number < 100
    assert isinstance(r.iterations, int)


@pytest.mark.parametrize("method", ["global", "auto", "lm", "thesis"])
def test_every_method_is_reachable_by_name(method):
    phi2, phi3, phi4, t, truth = simulate(n=300)
    start = dict(truth, l3=0.32, l4=0.33)
    r = calib.calibrate_planar_fourbar(phi2, phi3, phi4, L2, initial=start, method=method)
    assert rel_err(r, truth) < 1e-9
    assert r.method == method


def test_noisy_recording_reports_its_uncertainty_and_noise_correction_or_smoothing_removes_bias():
    rng = np.random.default_rng(0)
    phi2, phi3, phi4, t, truth = simulate(n=2000)
    noise = np.deg2rad(0.5)
    p3 = phi3 + rng.normal(0, noise, phi3.shape)
    p4 = phi4 + rng.normal(0, noise, phi4.shape)
    raw = calib.calibrate_planar_fourbar(phi2, p3, p4, L2, time_s=t, errors_in_variables=False)
    smooth = calib.calibrate_planar_fourbar(
        phi2, p3, p4, L2, time_s=t, smoothing_half_window=25, errors_in_variables=False
    )
    corrected = calib.calibrate_planar_fourbar(phi2, p3, p4, L2, time_s=t)  # the default
    for r in (raw, smooth, corrected):
        assert all(v > 0 for v in r.std_errors.values())
        assert 0 < r.rms_residual < 0.01
    # angle noise biases the plain loop fit (errors in variables); the default's noise
    # correction removes most of it, and so does smoothing first
    assert rel_err(corrected, truth) < 0.5 * rel_err(raw, truth)
    assert rel_err(smooth, truth) < 0.5 * rel_err(raw, truth)
    assert abs(smooth.l3 - truth["l3"]) < 0.005
    assert abs(corrected.l3 - truth["l3"]) < 0.005


def test_small_wheel_motion_warns_and_says_what_to_ask_for():
    rng = np.random.default_rng(1)
    phi2, phi3, phi4, t, truth = simulate(n=2000, amp_deg=15)
    noise = np.deg2rad(0.5)
    r = calib.calibrate_planar_fourbar(
        phi2, phi3 + rng.normal(0, noise, phi3.shape), phi4 + rng.normal(0, noise, phi4.shape), L2
    )
    assert any("±50–60°" in w for w in r.warnings), r.warnings


def test_online_estimator_converges_and_accepts_scalars_and_batches():
    phi2, phi3, phi4, t, truth = simulate(n=600)
    est = calib.OnlinePlanarFourbar(L2, forgetting=1.0)
    assert est.estimate is None
    for k in range(5):
        est.update(phi2[k], phi3[k], phi4[k])
    assert est.estimate is None
    est.update(phi2[5:], phi3[5:], phi4[5:])
    assert est.samples == 600
    assert rel_err(est.estimate, truth) < 1e-9


def test_thesis_two_link_example_reaches_the_true_lengths():
    def rz(q):
        c, s = math.cos(q), math.sin(q)
        return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])

    def tx(length):
        m = np.eye(4)
        m[0, 3] = length
        return m

    rng = np.random.default_rng(2)
    truth = [np.eye(4), tx(0.6), tx(1.0)]
    nominal = np.stack([np.eye(4), tx(1.2991), tx(0.5)])
    qs = rng.uniform(-1.5, 1.5, (12, 2))
    motions = np.array([[rz(a), rz(b)] for a, b in qs])
    measured = np.array([truth[0] @ q[0] @ truth[1] @ q[1] @ truth[2] for q in motions])
    r = calib.calibrate_serial_chain(nominal, motions, measured)
    lengths = np.hypot(r.frames[1:, 0, 3], r.frames[1:, 1, 3])
    np.testing.assert_allclose(lengths, [0.6, 1.0], rtol=1e-10)
    assert r.frames.shape == (3, 4, 4)
    assert r.converged and r.rms_residual < 1e-12


@pytest.mark.parametrize(
    "args, match",
    [
        ((np.zeros((10, 2)), np.zeros(10), np.zeros(10)), r"phi2_rad must have shape \(N,\)"),
        ((np.zeros(10), np.zeros(9), np.zeros(10)), r"phi3_rad must have shape \(10,\) like phi2_rad"),
        ((np.zeros(10), np.zeros(10), np.array(["a"] * 10)), r"phi4_rad must be a real numeric array"),
        ((np.zeros(10), np.full(10, np.nan), np.zeros(10)), r"phi3_rad must be finite"),
        ((np.zeros(5), np.zeros(5), np.zeros(5)), r"phi2_rad: 5 samples given, at least 10 are needed"),
    ],
)
def test_bad_planar_input_raises_value_error_naming_the_argument(args, match):
    with pytest.raises(ValueError, match=match):
        calib.calibrate_planar_fourbar(*args, L2)


def test_bad_method_and_missing_initial_are_value_errors():
    phi2, phi3, phi4, t, truth = simulate(n=100)
    with pytest.raises(ValueError, match="method must be one of"):
        calib.calibrate_planar_fourbar(phi2, phi3, phi4, L2, method="magic")
    with pytest.raises(ValueError, match="needs an initial guess"):
        calib.calibrate_planar_fourbar(phi2, phi3, phi4, L2, method="thesis")
    with pytest.raises(ValueError, match="l2_m = -1 is out of range"):
        calib.calibrate_planar_fourbar(phi2, phi3, phi4, -1.0)


def test_bad_serial_input_raises_value_error_naming_the_argument():
    frames = np.stack([np.eye(4)] * 3)
    motions = np.stack([[np.eye(4)] * 2] * 4)
    poses = np.stack([np.eye(4)] * 4)
    with pytest.raises(ValueError, match=r"joint_motions must have shape \(m, n, 4, 4\) = \(4, 2, 4, 4\)"):
        calib.calibrate_serial_chain(frames, motions[:, :1], poses)
    with pytest.raises(ValueError, match=r"nominal_frames must have shape \(n\+1, 4, 4\)"):
        calib.calibrate_serial_chain(np.zeros((3, 3, 3)), motions, poses)
    bad = poses.copy()
    bad[2, 0, 0] = np.nan
    with pytest.raises(ValueError, match="measured_end_poses must be finite"):
        calib.calibrate_serial_chain(frames, motions, bad)
    skewed = poses.copy()
    skewed[1, 0, 0] = 3.0
    with pytest.raises(ValueError, match=r"measured_end_poses\[1\] is not a rigid transform"):
        calib.calibrate_serial_chain(frames, motions, skewed)


def test_calibration_releases_the_gil():
    phi2, phi3, phi4, t, truth = simulate(n=200000, amp_deg=30)
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.0005)

    th = threading.Thread(target=ticker)
    th.start()
    try:
        before = len(ticks)
        calib.calibrate_planar_fourbar(phi2, phi3, phi4, L2, robust=False, time_s=t)
        during = len(ticks) - before
    finally:
        stop.set()
        th.join()
    # the other thread kept running while Rust worked (it could not if the GIL were held)
    assert during > 5
