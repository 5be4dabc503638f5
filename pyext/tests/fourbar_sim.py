"""Independent numpy simulator of the arm–wheel four-bar, for tests and the benchmark."""

import numpy as np

GEOMETRY = dict(l1=0.45, l2=0.15, l3=0.35, l4=0.30)
THETA2_0 = np.pi / 2


def simulate(n=1000, amp_deg=60.0, rate_hz=100.0, geometry=GEOMETRY, theta2_0=THETA2_0):
    """Return (phi2, phi3, phi4, time_s, truth dict): wheel swinging ±amp_deg at 0.2 Hz."""
    l1, l2, l3, l4 = (geometry[k] for k in ("l1", "l2", "l3", "l4"))
    t = np.arange(n) / rate_hz
    phi2 = np.deg2rad(amp_deg) * np.sin(2 * np.pi * 0.2 * t)
    th2 = theta2_0 + phi2
    hand = l2 * np.exp(1j * th2)
    shoulder = l1 + 0j
    d_vec = shoulder - hand
    d = np.abs(d_vec)
    a = (l3**2 - l4**2 + d**2) / (2 * d)
    h = np.sqrt(l3**2 - a**2)
    u = d_vec / d
    elbow = hand + a * u + h * (1j * u)
    th3 = np.unwrap(np.angle(elbow - hand))
    th4 = np.unwrap(np.angle(elbow - shoulder))
    truth = dict(l1=l1, l3=l3, l4=l4, theta2_0=theta2_0, theta3_0=th3[0], theta4_0=th4[0])
    return phi2, th3 - th3[0], th4 - th4[0], t, truth


def residuals(x, phi2, phi3, phi4, l2):
    """Stacked loop residuals (eq. 4.1) for x = [l1, l3, l4, Θ2, Θ3, Θ4]."""
    l1, l3, l4, t2, t3, t4 = x
    z = l2 * np.exp(1j * (t2 + phi2)) + l3 * np.exp(1j * (t3 + phi3)) - l4 * np.exp(1j * (t4 + phi4)) - l1
    return np.concatenate([z.real, z.imag])
