"""A simulated arm on the wheel for the spatial calibration tests.

The same geometry as ``gyro_imu::arm`` (wheel frame: x forward, y left, z up; default patient:
shoulder (-0.42, -0.17, 0.25) m, upper arm 0.30 m, forearm 0.33 m, 0.14 m rim tilted 20°): the
grip on the tilted rim at the wheel angle, the elbow on the circle of points at the segment
lengths from shoulder and grip, swung by the elbow swivel about the shoulder–grip line.
"""

import numpy as np

SHOULDER = np.array([-0.42, -0.17, 0.25])
UPPER_ARM = 0.30
FOREARM = 0.33
RIM = 0.14
TILT = np.radians(20.0)


def grip(wheel):
    right = np.array([0.0, -1.0, 0.0])
    up = np.array([-np.sin(TILT), 0.0, np.cos(TILT)])
    return RIM * (np.cos(wheel)[:, None] * right + np.sin(wheel)[:, None] * up)


def simulate(n=2000, rate_hz=100.0, scale=1.0):
    """Directions (N, 3) of upper arm and forearm, grip points (N, 3), times (N,)."""
    t = np.arange(n) / rate_hz
    wheel = scale * (0.8 * np.sin(2 * np.pi * 0.2 * t) + 0.25 * np.sin(2 * np.pi * 0.45 * t + 1.0))
    swivel = 0.35 + 0.2 * wheel + 0.15 * np.sin(2 * np.pi * 0.07 * t)
    g = grip(wheel)
    d_vec = g - SHOULDER
    d = np.linalg.norm(d_vec, axis=1, keepdims=True)
    nrm = d_vec / d
    a = (UPPER_ARM**2 - FOREARM**2 + d**2) / (2 * d)
    h = np.sqrt(UPPER_ARM**2 - a**2)
    down = np.array([0.0, 0.0, -1.0])
    e1 = down - nrm * (nrm @ down)[:, None]
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(e1, nrm)
    elbow = SHOULDER + nrm * a + (e1 * np.cos(swivel)[:, None] + e2 * np.sin(swivel)[:, None]) * h
    upper = (elbow - SHOULDER) / UPPER_ARM
    fore = (g - elbow) / FOREARM
    return upper, fore, g, t
