"""Compare ``telerehab.imu.fuse`` with the reference VQF (Laidig & Seel 2023, PyPI ``vqf``, 6-D
output) on the same simulated arm-like motion with consumer-MEMS errors.

Not a test (``vqf`` is not a dependency). Usage, in a virtualenv with the package installed:
    pip install vqf && python crates/gyro-imu/scripts/compare_vqf.py
runs the scenarios below (seeds 1–3, with and without pauses). With ``--table DIR`` it instead
reads the records of the Rust fusion error table, written by
``cargo run -p gyro-imu --release --example fusion_table_data -- DIR``, and runs both filters on
exactly those samples.

Motion: five random sines of body rate (0.2–1.2 Hz, ~120 deg/s peaks), four of position
(±0.15 m), an optional 6 s pause every 40 s; 5 minutes at 200 Hz; truth integrated with the
midpoint rule. Sensor: 0.3 % gyro scale error, gyro bias (1, −0.8, 0.6) deg/s, 0.014 deg/s/√Hz
gyro noise, 5 mg (1σ) accelerometer bias, 180 µg/√Hz accelerometer noise. Errors after 10 s;
"total" removes the heading offset at 10 s (heading is unobservable without a magnetometer).
"""
import os
import sys

import numpy as np
from vqf import VQF
from telerehab import imu

def qmul(a, b):
    w1, x1, y1, z1 = a.T; w2, x2, y2, z2 = b.T
    return np.stack([w1*w2-x1*x2-y1*y2-z1*z2, w1*x2+x1*w2+y1*z2-z1*y2, w1*y2-x1*z2+y1*w2+z1*x2, w1*z2+x1*y2-y1*x2+z1*w2], -1)

def qexp(v):
    th = np.linalg.norm(v, axis=-1, keepdims=True)
    s = np.where(th > 1e-12, np.sin(th/2)/np.maximum(th, 1e-300), 0.5)
    return np.concatenate([np.cos(th/2), v*s], -1)

def rot(q, v):  # rotate v by q (sensor->earth)
    w = q[:, :1]; u = q[:, 1:]
    t = 2*np.cross(u, v)
    return v + w*t + np.cross(u, t)

def run(seed, minutes=5, fs=200.0, bias_dps=1.0, pause=True):
    rng = np.random.default_rng(seed)
    dt = 1/fs; n = int(minutes*60*fs); t = np.arange(n)*dt
    env = np.ones(n)
    if pause:
        ph = t % 40
        env = np.clip((ph-6)/1, 0, 1) * np.clip((40-ph)/1, 0, 1)
        env = env*env*(3-2*env)
    w = np.zeros((n, 3)); p = np.zeros((n, 3))
    for _ in range(5):
        a = rng.uniform(-1, 1, 3)*np.radians(120)/5*1.5; f = rng.uniform(0.2, 1.2); ph0 = rng.uniform(0, 2*np.pi)
        w += a*np.sin(2*np.pi*f*t+ph0)[:, None]
    for _ in range(4):
        a = rng.uniform(-1, 1, 3)*0.15/4*1.5; f = rng.uniform(0.2, 1.0); ph0 = rng.uniform(0, 2*np.pi)
        p += a*np.sin(2*np.pi*f*t+ph0)[:, None]
    w *= env[:, None]; p *= env[:, None]
    acc_e = np.gradient(np.gradient(p, dt, axis=0), dt, axis=0) + [0, 0, 9.81]
    q = np.zeros((n, 4)); q[0] = qexp(rng.uniform(-1, 1, 3)[None])[0]
    for k in range(n-1):  # midpoint
        q[k+1] = qmul(q[k:k+1], qexp(((w[k]+w[k+1])/2*dt)[None]))[0]
        q[k+1] /= np.linalg.norm(q[k+1])
    qinv = q*[1, -1, -1, -1]
    f_s = rot(qinv, acc_e)
    b = np.radians(bias_dps)*np.array([1, -0.8, 0.6])
    gyr = w*(1.003) + b + rng.normal(scale=np.radians(0.014)/np.sqrt(dt), size=(n, 3))
    acc = f_s + rng.normal(scale=0.05, size=3) + rng.normal(scale=180e-6*9.81/np.sqrt(dt), size=(n, 3))
    return q, gyr, acc, dt

def incl_err(q_true, q_est):
    up_t = rot(q_true*[1, -1, -1, -1], np.tile([0, 0, 1.0], (len(q_true), 1)))
    up_e = rot(q_est*[1, -1, -1, -1], np.tile([0, 0, 1.0], (len(q_true), 1)))
    return np.degrees(np.arccos(np.clip((up_t*up_e).sum(1), -1, 1)))

def total_err(q_true, q_est, k0):
    # remove heading offset at k0: d = q_true * q_est^-1 yaw
    d = qmul(q_true[k0:k0+1], q_est[k0:k0+1]*[1, -1, -1, -1])[0]
    yaw = np.arctan2(2*(d[0]*d[3]+d[1]*d[2]), 1-2*(d[2]**2+d[3]**2))
    off = np.array([np.cos(yaw/2), 0, 0, np.sin(yaw/2)])
    qe = qmul(np.tile(off, (len(q_est), 1)), q_est)
    dq = qmul(q_true*[1, -1, -1, -1], qe)
    return np.degrees(2*np.arccos(np.clip(np.abs(dq[:, 0]), -1, 1)))

def rms_rows(qt, ours, v, dt):
    """Inclination and total RMS (deg) of our output and VQF's; outputs after sample k against
    truth `qt[k]` (the truth after that sample); errors from t = 10 s."""
    k0 = int(10/dt); s = slice(k0, None)
    rms = lambda e: np.sqrt(np.mean(e[s]**2))
    return (rms(incl_err(qt, ours)), rms(incl_err(qt, v)),
            rms(total_err(qt, ours, k0)), rms(total_err(qt, v, k0)))

VQF_PARAMS = {"default": {}, "no_motion_bias": {"motionBiasEstEnabled": False},
              "no_bias": {"motionBiasEstEnabled": False, "restBiasEstEnabled": False}}

def table(dirname):
    """The fusion error table's records, written by the `fusion_table_data` example."""
    print("| row | ours incl RMS | VQF incl RMS | ours total RMS | VQF total RMS |")
    print("|---|---|---|---|---|")
    for line in open(os.path.join(dirname, "rows.txt")):
        name, _pauses, cfg = line.split()
        d = np.fromfile(os.path.join(dirname, name + ".f64"), "<f8").reshape(-1, 10)
        gyr, acc, qt = [np.ascontiguousarray(d[:, a:b]) for a, b in ((0, 3), (3, 6), (6, 10))]
        dt = 1/200
        ours = imu.fuse(gyr, acc, dt) if cfg == "default" else None
        v = VQF(dt, **VQF_PARAMS[cfg]).updateBatch(gyr, acc)["quat6D"]
        if ours is None:  # only the defaults are reachable from Python; the Rust test prints ours
            r = rms_rows(qt, v, v, dt)
            print(f"| {name} ({cfg}) | see test | {r[1]:.3f} | see test | {r[3]:.3f} |")
        else:
            r = rms_rows(qt, ours, v, dt)
            print(f"| {name} | {r[0]:.3f} | {r[1]:.3f} | {r[2]:.3f} | {r[3]:.3f} |")

def scenarios():
    print("| seed | pauses | ours incl RMS | VQF incl RMS | ours total RMS | VQF total RMS |")
    print("|---|---|---|---|---|---|")
    for pause in (True, False):
        for seed in (1, 2, 3):
            q, gyr, acc, dt = run(seed, pause=pause)
            ours = imu.fuse(gyr, acc, dt)
            v = VQF(dt).updateBatch(np.ascontiguousarray(gyr), np.ascontiguousarray(acc))["quat6D"]
            # compare output after sample k with truth at k+1
            r = rms_rows(q[1:], ours[:-1], v[:-1], dt)
            print(f"| {seed} | {pause} | {r[0]:.3f} | {r[1]:.3f} | {r[2]:.3f} | {r[3]:.3f} |")

if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--table":
        table(sys.argv[2])
    else:
        scenarios()
