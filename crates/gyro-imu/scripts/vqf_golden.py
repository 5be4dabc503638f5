"""Print the reference-VQF checkpoints used by `fusion::tests::matches_reference_vqf_on_golden_signal`.

Not a test (``vqf`` is not a dependency). Usage, in a virtualenv: ``pip install vqf`` then
``python crates/gyro-imu/scripts/vqf_golden.py``. The signal is built from closed-form sines with
the scalar ``math`` module in the same order as the Rust test builds it, so both sides feed the
filter the same samples (to the last bit or an ulp): 120 s at 100 Hz, motion for 20 s, still for
10 s, then 90 s of motion without a pause; a constant gyro bias of (0.9, −0.7, 0.5) deg/s.
"""
import math

import numpy as np
from vqf import VQF, PyVQF

DT = 0.01
N = 12000
BIAS = (math.radians(0.9), math.radians(-0.7), math.radians(0.5))


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1*w2 - x1*x2 - y1*y2 - z1*z2, w1*x2 + x1*w2 + y1*z2 - z1*y2,
            w1*y2 - x1*z2 + y1*w2 + z1*x2, w1*z2 + x1*y2 - y1*x2 + z1*w2)


def rot_t(q, v):  # rotate v by the inverse of q (earth -> sensor)
    w, x, y, z = q
    x, y, z = -x, -y, -z
    vx, vy, vz = v
    return ((1 - 2*y*y - 2*z*z)*vx + 2*(x*y - w*z)*vy + 2*(x*z + w*y)*vz,
            2*(x*y + w*z)*vx + (1 - 2*x*x - 2*z*z)*vy + 2*(y*z - w*x)*vz,
            2*(x*z - w*y)*vx + 2*(y*z + w*x)*vy + (1 - 2*x*x - 2*y*y)*vz)


def signal():
    q = (math.cos(0.3), math.sin(0.3)*0.6, math.sin(0.3)*0.8, 0.0)
    gyr, acc = [], []
    for k in range(N):
        t = k*DT
        m = 0.0 if 20.0 <= t < 30.0 else 1.0
        w = (m*(1.1*math.sin(1.3*t) + 0.4*math.sin(3.1*t + 0.5)),
             m*(-0.9*math.sin(0.7*t + 1.0) + 0.3*math.cos(2.3*t)),
             m*(0.8*math.cos(0.9*t) + 0.5*math.sin(1.7*t + 2.0)))
        a_e = (m*0.8*math.sin(2.0*t), m*0.6*math.cos(1.5*t), 9.81 + m*0.5*math.sin(1.1*t))
        f = rot_t(q, a_e)
        n = 1e-3*math.sin(37.0*k)
        gyr.append((w[0] + BIAS[0] + n, w[1] + BIAS[1] - n, w[2] + BIAS[2] + 0.5*n))
        acc.append((f[0] + 10*n, f[1] - 10*n, f[2] + 5*n))
        h = 0.5*DT
        th = math.sqrt(w[0]*w[0] + w[1]*w[1] + w[2]*w[2])
        if th > 0.0:
            s = math.sin(h*th)/th
            q = qmul(q, (math.cos(h*th), s*w[0], s*w[1], s*w[2]))
            nq = math.sqrt(sum(c*c for c in q))
            q = tuple(c/nq for c in q)
    return np.array(gyr), np.array(acc)


gyr, acc = signal()
out = VQF(DT).updateBatch(gyr, acc)
py = PyVQF(DT).updateBatch(gyr, acc)
assert np.abs(out["quat6D"] - py["quat6D"]).max() < 1e-9
print("// (sample, [w, x, y, z], [bx, by, bz] rad/s, rest): reference VQF 2.1 (C++), default params.")
for k in list(range(999, N, 1000)):
    q = out["quat6D"][k]
    b = out["bias"][k]
    f = lambda xs: ", ".join(repr(float(x)) for x in xs)  # shortest round-trip form
    print(f"({k}, [{f(q)}], [{f(b)}], {str(bool(out['restDetected'][k])).lower()}),")
