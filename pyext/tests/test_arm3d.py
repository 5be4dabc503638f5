"""telerehab.calib.calibrate_arm_3d from Python (fixed seeds, simulated recordings)."""

import numpy as np
import pytest

from telerehab import calib

from arm3d_sim import FOREARM, SHOULDER, UPPER_ARM, simulate


def rel_err(r):
    s = np.linalg.norm(np.array(r.shoulder_m) - SHOULDER) / np.linalg.norm(SHOULDER)
    return max(s, abs(r.upper_arm_m / UPPER_ARM - 1), abs(r.forearm_m / FOREARM - 1))


@pytest.mark.parametrize("heading", ["exact", "offset", "offset_and_drift"])
def test_noise_free_recording_recovers_shoulder_and_lengths_to_1e9(heading):
    u, f, g, t = simulate()
    r = calib.calibrate_arm_3d(u, f, g, time_s=t, heading=heading)
    assert rel_err(r) < 1e-9
    assert r.rms_residual < 1e-12
    assert r.warnings == []
    assert r.heading_model == heading
    assert set(r.std_errors) >= {"shoulder_m", "upper_arm_m", "forearm_m"}
    assert len(r.shoulder_m) == 3
    assert r.condition_number < 200


def test_direction_noise_of_2_deg_is_corrected_to_about_a_millimetre():
    u, f, g, _ = simulate(n=6000)
    rng = np.random.default_rng(4)

    def noisy(d):
        e = rng.normal(scale=np.radians(2.0) / np.sqrt(2.0), size=d.shape)
        e -= d * np.sum(e * d, axis=1, keepdims=True)  # tangent part only
        w = d + e
        return w / np.linalg.norm(w, axis=1, keepdims=True)

    un, fn = noisy(u), noisy(f)
    r = calib.calibrate_arm_3d(un, fn, g)
    raw = calib.calibrate_arm_3d(un, fn, g, errors_in_variables=False)
    assert abs(r.upper_arm_m - UPPER_ARM) < 3e-3
    assert abs(r.forearm_m - FOREARM) < 2e-3
    assert raw.upper_arm_m < UPPER_ARM - 5e-3  # the bias the correction removes


def test_wheel_that_never_turns_raises_and_asks_to_turn_it():
    u, f, g, _ = simulate(n=100)
    still = lambda a: np.repeat(a[:1], 100, axis=0)  # noqa: E731
    with pytest.raises(ValueError, match="turn the wheel further"):
        calib.calibrate_arm_3d(still(u), still(f), still(g))


def test_bad_shapes_and_nan_raise_value_errors_naming_the_argument():
    u, f, g, _ = simulate(n=50)
    with pytest.raises(ValueError, match="fore_dirs"):
        calib.calibrate_arm_3d(u, f[:, :2], g)
    with pytest.raises(ValueError, match=r"grip_points_m must have shape \(50, 3\) like upper_dirs"):
        calib.calibrate_arm_3d(u, f, g[:40])
    bad = u.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="upper_dirs"):
        calib.calibrate_arm_3d(bad, f, g)
    with pytest.raises(ValueError, match="upper_dirs"):
        calib.calibrate_arm_3d(u * 2.0, f, g)
    with pytest.raises(ValueError, match="time_s"):
        calib.calibrate_arm_3d(u, f, g, time_s=np.arange(49.0))
    with pytest.raises(ValueError, match="heading"):
        calib.calibrate_arm_3d(u, f, g, heading="sideways")
    with pytest.raises(ValueError, match="upper_dirs"):
        calib.calibrate_arm_3d(u[:5], f[:5], g[:5])
