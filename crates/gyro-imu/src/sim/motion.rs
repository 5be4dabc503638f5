//! A deterministic, arm-like random rigid-body motion for exercising integrators and filters:
//! smooth multi-sine rotation rates and translation, interrupted by rest phases.

use nalgebra::{UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::so3;

/// Standard gravity (m/s²).
pub const GRAVITY_M_S2: f64 = 9.81;

/// The truth at one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthSample {
    /// Time (s).
    pub t_s: f64,
    /// Sensor-to-earth orientation (earth z up).
    pub orientation: UnitQuaternion<f64>,
    /// Body-frame angular rate (rad/s).
    pub rate_rad_s: Vector3<f64>,
    /// Specific force in the sensor frame (m/s²): `Rᵀ(p̈ + g·ẑ)`.
    pub specific_force_m_s2: Vector3<f64>,
}

#[derive(Debug, Clone, Copy)]
struct Sine {
    amp: Vector3<f64>,
    freq_hz: f64,
    phase: f64,
}

/// Multi-sine motion (components between 0.2 Hz and ~1 Hz, so rotations swing back and forth
/// over tens of degrees like an arm's) with rest phases (`rest_s` still out of every `period_s`).
#[derive(Debug, Clone)]
pub struct RandomMotion {
    rot: Vec<Sine>,
    pos: Vec<Sine>,
    period_s: f64,
    rest_s: f64,
    q: UnitQuaternion<f64>,
    t_s: f64,
}

impl RandomMotion {
    /// Motion with peak rates of roughly `rate_scale_deg_s` and displacements of roughly
    /// `pos_scale_m`, still for `rest_s` out of every `period_s` seconds; seeded.
    pub fn new(
        seed: u64,
        rate_scale_deg_s: f64,
        pos_scale_m: f64,
        period_s: f64,
        rest_s: f64,
    ) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut sines = |n: usize, scale: f64, fmax: f64| -> Vec<Sine> {
            (0..n)
                .map(|_| Sine {
                    amp: Vector3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    ) * (scale / n as f64 * 1.5),
                    freq_hz: rng.random_range(0.2..fmax),
                    phase: rng.random_range(0.0..std::f64::consts::TAU),
                })
                .collect()
        };
        let rot = sines(5, rate_scale_deg_s.to_radians(), 1.2);
        let pos = sines(4, pos_scale_m, 1.0);
        let q0 = so3::exp_quat(&Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-3.0..3.0),
        ));
        Self {
            rot,
            pos,
            period_s,
            rest_s,
            q: q0,
            t_s: 0.0,
        }
    }

    /// Smooth activity envelope in [0, 1]: 0 during rest (which starts each period).
    fn envelope(&self, t: f64) -> f64 {
        if self.rest_s <= 0.0 {
            return 1.0;
        }
        let ph = t.rem_euclid(self.period_s);
        let ramp = 1.0;
        if ph < self.rest_s {
            0.0
        } else if ph < self.rest_s + ramp {
            let x = (ph - self.rest_s) / ramp;
            x * x * (3.0 - 2.0 * x)
        } else if ph > self.period_s - ramp {
            let x = (self.period_s - ph) / ramp;
            x * x * (3.0 - 2.0 * x)
        } else {
            1.0
        }
    }

    fn rate(&self, t: f64) -> Vector3<f64> {
        let s: Vector3<f64> = self
            .rot
            .iter()
            .map(|c| c.amp * (std::f64::consts::TAU * c.freq_hz * t + c.phase).sin())
            .sum();
        s * self.envelope(t)
    }

    fn position(&self, t: f64) -> Vector3<f64> {
        let s: Vector3<f64> = self
            .pos
            .iter()
            .map(|c| c.amp * (std::f64::consts::TAU * c.freq_hz * t + c.phase).sin())
            .sum();
        s * self.envelope(t)
    }

    /// The truth now; then advance by `dt_s` (orientation integrated with 8 midpoint substeps).
    pub fn next(&mut self, dt_s: f64) -> TruthSample {
        let t = self.t_s;
        let h = 1e-3;
        let acc = (self.position(t + h) - self.position(t) * 2.0 + self.position(t - h)) / (h * h);
        let f_e = acc + Vector3::z() * GRAVITY_M_S2;
        let out = TruthSample {
            t_s: t,
            orientation: self.q,
            rate_rad_s: self.rate(t),
            specific_force_m_s2: self.q.inverse() * f_e,
        };
        let n = 8;
        let hs = dt_s / n as f64;
        for i in 0..n {
            let w = self.rate(t + (i as f64 + 0.5) * hs);
            self.q =
                UnitQuaternion::new_normalize(*(self.q * so3::exp_quat(&(w * hs))).quaternion());
        }
        self.t_s += dt_s;
        out
    }
}
