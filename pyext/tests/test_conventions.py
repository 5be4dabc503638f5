"""The binding convention shared by telerehab.calib, telerehab.imu and telerehab.metrics:
ValueErrors naming the argument (with its unit suffix), immutable typed results, the GIL
released. (telerehab.metrics' own cases are in test_metrics.py.)"""

import inspect
import threading

import numpy as np
import pytest

import telerehab
from telerehab import _native, calib, imu, metrics

from arm3d_sim import simulate as simulate_arm
from fourbar_sim import GEOMETRY, simulate

L2 = GEOMETRY["l2"]
Z3 = np.zeros((20, 3))


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: imu.integrate(np.ones((4, 3), dtype=bool), 0.01), r"rates_rad_s must be a real numeric array .* got dtype bool"),
        (lambda: imu.integrate([[0, 0], [0, 0, 0]], 0.01), r"rates_rad_s must be a real numeric array of shape \(N, 3\)"),
        (lambda: imu.integrate(np.zeros(3), 0.01), r"rates_rad_s must have shape \(N, 3\), got \(3,\)"),
        (lambda: imu.integrate(Z3, float("nan")), r"dt_s must be in \(0, 1\] s, got nan"),
        (lambda: imu.fuse(np.full((20, 3), np.inf), Z3, 0.01), r"gyr_rad_s must be finite .*index \(0, 0\)"),
        (lambda: imu.fuse(Z3, Z3 + 9.81j, 0.01), r"acc_m_s2 must be a real numeric array .* got dtype complex128"),
        (lambda: imu.fuse(Z3, Z3, 2.0), r"dt_s must be in \(0, 1\] s, got 2.0"),
        (lambda: imu.estimate_bias(Z3, 0.01, acc_m_s2=Z3[:5]), r"acc_m_s2 must have shape \(20, 3\) like rates_rad_s, got \(5, 3\)"),
        (lambda: imu.estimate_bias(Z3, 0.0), r"dt_s must be in \(0, 1\] s"),
        (lambda: calib.calibrate_planar_fourbar(np.zeros(20), np.zeros(20), np.array(["a"] * 20), L2), r"phi4_rad must be a real numeric array"),
        (lambda: calib.calibrate_planar_fourbar(np.zeros(20), np.zeros(20), np.zeros(20), L2, time_s=np.zeros(19)), r"time_s must have shape \(20,\) like phi2_rad, got \(19,\)"),
        (lambda: calib.OnlinePlanarFourbar(L2).update(np.zeros(3), np.zeros(3), np.zeros(2)), r"phi4_rad must have shape \(3,\) like phi2_rad, got \(2,\)"),
        (lambda: calib.OnlinePlanarFourbar(L2).update(0.0, float("nan"), 0.0), r"phi3_rad must be finite"),
        (lambda: calib.OnlinePlanarFourbar(-1.0), r"l2_m = -1 is out of range"),
        (lambda: calib.calibrate_arm_3d(Z3, Z3, np.zeros((20, 3), dtype=bool)), r"grip_points_m must be a real numeric array .* got dtype bool"),
        (lambda: calib.calibrate_arm_3d(Z3, Z3[:, :2], Z3), r"fore_dirs must have shape \(20, 3\) like upper_dirs, got \(20, 2\)"),
    ],
)
def test_bad_shapes_and_dtypes_raise_value_error_naming_the_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: _native.imu_fuse(Z3, np.zeros((19, 3)), 0.01, 3.0, False, True), r"acc_m_s2 has 19 rows but gyr_rad_s has 20"),
        (lambda: _native.imu_estimate_bias(np.full((20, 3), np.nan), 0.01, None, 2.0, 1.5), r"rates_rad_s\[0\] is not finite"),
        (lambda: _native.calibrate_arm_3d(Z3, Z3, np.zeros((20, 2)), None, "exact", True, 20), r"grip_points_m must have shape \(N, 3\)"),
        (lambda: _native.calibrate_arm_3d(Z3, Z3, np.zeros((19, 3)), None, "exact", True, 20), r"grip_points_m has 19 rows but upper_dirs has 20"),
        (lambda: _native.OnlinePlanarFourbar(L2, 0.99).update_many(np.zeros(3), np.zeros(2), np.zeros(3)), r"phi3_rad has 2 rows but phi2_rad has 3"),
        (lambda: _native.calibrate_planar_fourbar(np.zeros(5), np.zeros(5), np.zeros(5), L2, None, "global", None, True, True, 10, 1e-9, 0, True), r"phi2_rad: 5 samples given"),
    ],
)
def test_native_layer_checks_on_its_own_and_uses_the_python_names(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_public_arguments_carry_their_unit():
    names = {
        imu.integrate: ["rates_rad_s", "dt_s", "method"],
        imu.fuse: ["gyr_rad_s", "acc_m_s2", "dt_s", "tau_acc_s", "scale_estimation", "rest_tilt_check"],
        imu.estimate_bias: ["rates_rad_s", "dt_s", "acc_m_s2", "rate_threshold_deg_s", "min_rest_s"],
        calib.OnlinePlanarFourbar.__init__: ["self", "l2_m", "forgetting"],
        calib.OnlinePlanarFourbar.update: ["self", "phi2_rad", "phi3_rad", "phi4_rad"],
    }
    for fn, expected in names.items():
        assert list(inspect.signature(fn).parameters) == expected, fn
    planar = list(inspect.signature(calib.calibrate_planar_fourbar).parameters)
    assert planar[:4] == ["phi2_rad", "phi3_rad", "phi4_rad", "l2_m"]
    arm = list(inspect.signature(calib.calibrate_arm_3d).parameters)
    assert arm[:3] == ["upper_dirs", "fore_dirs", "grip_points_m"]


def test_bias_estimate_is_a_frozen_typed_result_that_still_unpacks():
    rng = np.random.default_rng(5)
    truth = np.radians([0.5, -0.4, 0.2])
    rates = truth + rng.normal(scale=np.radians(0.3), size=(3000, 3))
    est = imu.estimate_bias(rates_rad_s=rates, dt_s=0.005, acc_m_s2=np.tile([0, 0, 9.81], (3000, 1)))
    assert isinstance(est, imu.BiasEstimate)
    assert est.bias_rad_s.shape == (3,) and est.bias_rad_s.dtype == np.float64
    assert 0.8 < est.rest_fraction <= 1.0
    bias, frac = est
    np.testing.assert_array_equal(bias, est.bias_rad_s)
    assert frac == est.rest_fraction
    assert "BiasEstimate(bias_rad_s=" in repr(est)
    with pytest.raises(AttributeError):
        est.rest_fraction = 0.0  # type: ignore[misc]


def test_results_are_immutable():
    phi2, phi3, phi4, t, _ = simulate(n=200)
    r = calib.calibrate_planar_fourbar(phi2, phi3, phi4, L2)
    with pytest.raises(AttributeError):
        r.l3 = 0.0  # type: ignore[misc]
    u, f, g, _ = simulate_arm(n=100)
    a = calib.calibrate_arm_3d(u, f, g)
    with pytest.raises(AttributeError):
        a.forearm_m = 0.0  # type: ignore[misc]


def test_package_exposes_its_modules_and_the_native_stub_ships():
    assert telerehab.imu is imu and telerehab.calib is calib and telerehab.metrics is metrics
    assert set(telerehab.__all__) == {"__version__", "calib", "imu", "metrics", "session"}
    from importlib import resources

    files = {p.name for p in resources.files("telerehab").iterdir()}
    assert {"_native.pyi", "py.typed"} <= files


def _runs_with_gil_released(work):
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
        work()
        during = len(ticks) - before
    finally:
        stop.set()
        th.join()
    return during > 5


def test_imu_releases_the_gil():
    rng = np.random.default_rng(6)
    gyr = rng.normal(scale=0.1, size=(400_000, 3))
    acc = np.tile([0.0, 0.0, 9.81], (400_000, 1))
    assert _runs_with_gil_released(lambda: imu.fuse(gyr, acc, 0.005))
    assert _runs_with_gil_released(lambda: imu.integrate(gyr, 0.005, method="magnus4"))


def test_metrics_releases_the_gil():
    rng = np.random.default_rng(7)
    speed = np.abs(rng.normal(size=100_000))  # SPARC: a 2**21-point FFT
    assert _runs_with_gil_released(lambda: metrics.sparc(speed, 100.0))
