import numpy as np
import pytest

from telerehab import imu


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_integrate_constant_rate_is_exact_and_starts_at_identity():
    rates = np.tile([0.0, 0.0, 0.5], (200, 1))
    r = imu.integrate(rates, 0.01)
    assert r.shape == (201, 3, 3)
    np.testing.assert_allclose(r[0], np.eye(3), atol=1e-15)
    np.testing.assert_allclose(r[-1], rot_z(1.0), atol=1e-12)


@pytest.mark.parametrize("method", imu.METHODS)
def test_every_method_returns_rotations(method):
    rng = np.random.default_rng(3)
    r = imu.integrate(rng.normal(size=(500, 3)), 0.005, method=method)
    eye = np.einsum("nij,nkj->nik", r, r)
    np.testing.assert_allclose(eye, np.broadcast_to(np.eye(3), eye.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(r), 1.0, atol=1e-12)


def test_integrate_magnus4_beats_exp_on_coning_motion():
    beta, w = np.radians(10.0), 2 * np.pi
    dt = 1 / 286
    t = np.arange(286 * 60 + 2) * dt
    rates = w * np.stack(
        [-np.sin(beta) * np.sin(w * t), np.sin(beta) * np.cos(w * t), (np.cos(beta) - 1) * np.ones_like(t)], 1
    )
    n = 286 * 60
    c, s = np.cos(beta), np.sin(beta)
    rx = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    # Integration starts at I: the truth is the motion relative to R(0) = Rx(β).
    truth = rx.T @ rot_z(w * n * dt) @ rx @ rot_z(-w * n * dt)

    def err(r):
        return np.degrees(np.arccos(np.clip((np.trace(truth.T @ r) - 1) / 2, -1, 1)))

    e_exp = err(imu.integrate(rates, dt, method="exp")[n])
    e_m4 = err(imu.integrate(rates, dt, method="magnus4")[n])
    assert e_exp > 1e-3
    assert e_m4 < e_exp / 20


def test_fuse_static_sensor_finds_gravity_and_returns_unit_quaternions():
    n = 2000
    acc = np.tile([0.0, 9.81, 0.0], (n, 1))  # sensor y axis up
    gyr = np.tile(np.radians([0.3, -0.2, 0.1]), (n, 1))
    q = imu.fuse(gyr, acc, 0.01)
    assert q.shape == (n, 4)
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)
    w, x, y, z = q[-1]
    # Sensor y axis expressed in earth frame must be +z.
    y_earth = np.array([2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)])
    np.testing.assert_allclose(y_earth, [0, 0, 1], atol=1e-3)


def test_vqf_rest_test_learns_the_bias_of_a_sensor_carried_without_turning():
    # A sensor carried to and fro (0.4 m/s² at 0.2 Hz) without turning: the specific force tilts
    # by 2.3° at up to 3 °/s, which the station's tilt-rate test refuses as rest, while VQF's rest
    # test (rest_tilt_check=False) sees a still gyroscope and learns its vertical bias; heading
    # then drifts only until it has.
    rng = np.random.default_rng(4)
    dt, n = 0.01, 9000
    t = np.arange(n) * dt
    acc = np.zeros((n, 3))
    acc[:, 0] = 0.4 * np.sin(2 * np.pi * 0.2 * t)
    acc[:, 2] = 9.81
    acc += rng.normal(scale=0.01, size=acc.shape)
    gyr = np.radians([0.0, 0.0, 0.5]) + rng.normal(scale=np.radians(0.02), size=(n, 3))

    def heading_deg(q):
        w, x, y, z = q[-1]
        return abs(np.degrees(np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))))

    station = heading_deg(imu.fuse(gyr, acc, dt))
    vqf_rest = heading_deg(imu.fuse(gyr, acc, dt, rest_tilt_check=False))
    assert vqf_rest < 0.5 * station, (vqf_rest, station)


def test_estimate_bias_recovers_a_constant_offset():
    rng = np.random.default_rng(1)
    truth = np.radians([0.5, -0.4, 0.2])
    rates = truth + rng.normal(scale=np.radians(0.3), size=(3000, 3))
    b, frac = imu.estimate_bias(rates, 0.005)
    assert frac > 0.8
    assert np.degrees(np.linalg.norm(b - truth)) < 0.05


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: imu.integrate(np.zeros((5, 2)), 0.01), r"rates_rad_s must have shape \(N, 3\)"),
        (lambda: imu.integrate(np.zeros((5, 3)), -1.0), r"dt_s must be in \(0, 1\] s"),
        (lambda: imu.integrate(np.zeros((5, 3)), 0.01, method="euler"), r"method must be one of"),
        (lambda: imu.integrate([[0, 0, np.nan]], 0.01), r"rates_rad_s must be finite .*index \(0, 2\)"),
        (lambda: imu.fuse(np.zeros((4, 3)), np.zeros((3, 3)), 0.01), r"acc_m_s2 must have shape \(4, 3\) like gyr_rad_s, got \(3, 3\)"),
        (lambda: imu.fuse(np.zeros((4, 3)), np.zeros((4, 4)), 0.01), r"acc_m_s2 must have shape"),
        (lambda: imu.fuse(np.zeros((4, 3)), [["a", "b", "c"]] * 4, 0.01), r"acc_m_s2 must be a real numeric array"),
        (lambda: imu.estimate_bias(np.sin(np.arange(3000))[:, None] * np.ones((1, 3)), 0.01), r"no rest"),
    ],
)
def test_bad_input_raises_value_error_naming_the_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_native_layer_rechecks_shapes():
    from telerehab import _native

    with pytest.raises(ValueError, match=r"rates_rad_s must have shape \(N, 3\)"):
        _native.imu_integrate(np.zeros((3, 4)), 0.01, "exp")
