//! Signal conditioning of the quantised encoder angle: the thesis moving average with
//! direct-difference derivatives (eq. 3.4, §3.3.2) and a constant-acceleration Kalman
//! estimator with far less lag.
//!
//! Both implement [`StateEstimator`]: one quantised angle in, a [`WheelState`] (angle,
//! velocity, acceleration) out, O(1) per sample and no allocation after construction.
//! The side-by-side comparison on the simulated wheel is the test
//! `kalman_tracks_true_velocity_with_less_error_and_lag_than_the_thesis_filter` and the
//! `filters` group of the criterion bench (figures in BENCHMARKS.md).

use crate::effects::WheelState;
use crate::wheel::{ConfigError, WheelError};

/// Turns a stream of quantised angles into angle, velocity and acceleration estimates.
pub trait StateEstimator {
    /// Take one angle sample `angle_rad`, `dt_s` after the previous one.
    /// A non-finite sample or `dt_s` is skipped (the previous estimate is returned).
    fn update(&mut self, angle_rad: f64, dt_s: f64) -> WheelState;
    /// Forget the history and start again at rest at `angle_rad`.
    fn reset(&mut self, angle_rad: f64);
}

/// The thesis filter: moving average over the last `M` samples (eq. 3.4,
/// `y[n] = (1/M)·Σ_{k=0}^{M−1} x[n−k]`, thesis M = 175), O(1) per sample with a running,
/// compensated (Kahan) sum; velocity and acceleration by direct differences of the
/// filtered angle as in §3.3.2. Group delay of the average alone: `(M − 1)/2` samples.
#[derive(Clone, Debug)]
pub struct MovingAverage {
    window: Box<[f64]>,
    next: usize,
    filled: usize,
    sum: f64,
    carry: f64,
    prev: Option<(f64, f64)>,
    acc: f64,
}

/// The thesis's window length (§3.3.2).
pub const THESIS_MOVING_AVERAGE_LEN: usize = 175;

impl MovingAverage {
    /// A moving average over `len` samples (1..=100 000).
    pub fn new(len: usize) -> Result<Self, WheelError> {
        if !(1..=100_000).contains(&len) {
            return Err(
                ConfigError(format!("moving_average.len = {len}, allowed [1, 100000]")).into(),
            );
        }
        Ok(Self::with_len(len))
    }

    /// The thesis filter, M = 175.
    pub fn thesis() -> Self {
        Self::with_len(THESIS_MOVING_AVERAGE_LEN)
    }

    fn with_len(len: usize) -> Self {
        Self {
            window: vec![0.0; len].into_boxed_slice(),
            next: 0,
            filled: 0,
            sum: 0.0,
            carry: 0.0,
            prev: None,
            acc: 0.0,
        }
    }

    fn add_compensated(&mut self, x: f64) {
        let y = x - self.carry;
        let t = self.sum + y;
        self.carry = (t - self.sum) - y;
        self.sum = t;
    }

    /// Push a sample and return the average of the samples seen so far (up to `M`).
    pub fn push(&mut self, x: f64) -> f64 {
        let old = self.window[self.next];
        self.window[self.next] = x;
        self.next = (self.next + 1) % self.window.len();
        if self.filled == self.window.len() {
            self.add_compensated(x - old);
        } else {
            self.filled += 1;
            self.add_compensated(x);
        }
        self.sum / self.filled as f64
    }
}

impl StateEstimator for MovingAverage {
    fn update(&mut self, angle_rad: f64, dt_s: f64) -> WheelState {
        let last = self
            .prev
            .map_or(WheelState::default(), |(a, v)| WheelState {
                angle_rad: a,
                vel_rad_s: v,
                acc_rad_s2: self.acc,
            });
        if !(angle_rad.is_finite() && dt_s.is_finite() && dt_s > 0.0) {
            return last;
        }
        let y = self.push(angle_rad);
        let (vel, acc) = match self.prev {
            Some((py, pv)) => {
                let v = (y - py) / dt_s;
                (v, (v - pv) / dt_s)
            }
            None => (0.0, 0.0),
        };
        self.prev = Some((y, vel));
        self.acc = acc;
        WheelState {
            angle_rad: y,
            vel_rad_s: vel,
            acc_rad_s2: acc,
        }
    }

    fn reset(&mut self, angle_rad: f64) {
        self.window.fill(angle_rad);
        self.filled = self.window.len();
        self.next = 0;
        self.sum = 0.0;
        self.carry = 0.0;
        for _ in 0..self.window.len() {
            self.add_compensated(angle_rad);
        }
        self.prev = Some((angle_rad, 0.0));
        self.acc = 0.0;
    }
}

/// Tuning of [`KalmanEstimator`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KalmanParams {
    /// Power spectral density of the jerk driving the constant-acceleration model,
    /// (rad/s³)²·s. Larger: faster response, noisier velocity.
    pub jerk_psd: f64,
    /// Standard deviation of the angle measurement, rad. For a quantised encoder with step
    /// `q`, `q/√12`.
    pub angle_noise_rad: f64,
}

impl KalmanParams {
    /// Tuning for an encoder with step `step_rad`: quantisation noise `q/√12` and a jerk
    /// density of 30 (rad/s³)²·s. A sweep over 0.01…1e5 on the simulated tracking task
    /// ([`compare_on_sim_wheel`]) had its minimum velocity error at 10–100 for both the
    /// thesis encoder (Ka steps) and 0.1 rad steps; 30 leaves headroom for faster motion.
    pub fn for_encoder_step(step_rad: f64) -> Self {
        let step = if step_rad.is_finite() && step_rad > 0.0 {
            step_rad
        } else {
            1e-4
        };
        Self {
            jerk_psd: 30.0,
            angle_noise_rad: step / 12f64.sqrt(),
        }
    }

    /// Tuning for the haptic loop: ten times the jerk density of
    /// [`Self::for_encoder_step`] (300 (rad/s³)²·s). Velocity lag matters more than velocity
    /// noise when the estimate drives dampers and the passivity controller: with the
    /// tracking tuning the passivity controller held a 25 N·m/rad spring on a 4 ms-delayed
    /// wheel in a ~0.04 rad limit cycle; with this one it settled within a second
    /// (test `stiff_spring_on_a_delayed_wheel_…`).
    pub fn for_haptic_loop(step_rad: f64) -> Self {
        Self {
            jerk_psd: 300.0,
            ..Self::for_encoder_step(step_rad)
        }
    }

    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if !(self.jerk_psd.is_finite() && self.jerk_psd > 0.0 && self.jerk_psd <= 1e12) {
            return Err(ConfigError(format!(
                "kalman.jerk_psd = {}, allowed (0, 1e12]",
                self.jerk_psd
            )));
        }
        if !(self.angle_noise_rad.is_finite()
            && self.angle_noise_rad > 0.0
            && self.angle_noise_rad <= 1.0)
        {
            return Err(ConfigError(format!(
                "kalman.angle_noise_rad = {}, allowed (0, 1]",
                self.angle_noise_rad
            )));
        }
        Ok(())
    }
}

/// Constant-acceleration Kalman filter on `[θ, θ̇, θ̈]` with white jerk noise (the
/// discrete Wiener-process-acceleration model) and the encoder angle as measurement.
/// Handles a variable `dt_s` (jittery loop ticks) exactly; ~60 flops per sample.
#[derive(Clone, Debug)]
pub struct KalmanEstimator {
    params: KalmanParams,
    x: [f64; 3],
    p: [[f64; 3]; 3],
    started: bool,
}

impl KalmanEstimator {
    /// A filter with validated `params`.
    pub fn new(params: KalmanParams) -> Result<Self, WheelError> {
        params.validate()?;
        Ok(Self {
            params,
            x: [0.0; 3],
            p: [[0.0; 3]; 3],
            started: false,
        })
    }

    fn state(&self) -> WheelState {
        WheelState {
            angle_rad: self.x[0],
            vel_rad_s: self.x[1],
            acc_rad_s2: self.x[2],
        }
    }

    fn predict(&mut self, dt: f64) {
        let [a, v, j] = self.x;
        self.x = [a + v * dt + 0.5 * j * dt * dt, v + j * dt, j];
        // F = [[1, dt, dt²/2], [0, 1, dt], [0, 0, 1]]
        let h = 0.5 * dt * dt;
        let f = [[1.0, dt, h], [0.0, 1.0, dt], [0.0, 0.0, 1.0]];
        let p = self.p;
        let fp: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|k| (0..3).map(|m| f[i][m] * p[m][k]).sum())
        });
        let q = self.params.jerk_psd;
        let (d2, d3, d4, d5) = (dt * dt, dt * dt * dt, dt.powi(4), dt.powi(5));
        let qm = [
            [d5 / 20.0, d4 / 8.0, d3 / 6.0],
            [d4 / 8.0, d3 / 3.0, d2 / 2.0],
            [d3 / 6.0, d2 / 2.0, dt],
        ];
        self.p = std::array::from_fn(|i| {
            std::array::from_fn(|k| {
                let fpf: f64 = (0..3).map(|m| fp[i][m] * f[k][m]).sum();
                fpf + q * qm[i][k]
            })
        });
    }

    fn correct(&mut self, z: f64) {
        let r = self.params.angle_noise_rad * self.params.angle_noise_rad;
        let s = self.p[0][0] + r;
        let k = [self.p[0][0] / s, self.p[1][0] / s, self.p[2][0] / s];
        let innov = z - self.x[0];
        for (xi, ki) in self.x.iter_mut().zip(k) {
            *xi += ki * innov;
        }
        let row0 = self.p[0];
        for (i, ki) in k.iter().enumerate() {
            for (c, r0) in row0.iter().enumerate() {
                self.p[i][c] -= ki * r0;
            }
        }
        // Keep P symmetric against rounding.
        for i in 0..3 {
            for c in (i + 1)..3 {
                let m = 0.5 * (self.p[i][c] + self.p[c][i]);
                self.p[i][c] = m;
                self.p[c][i] = m;
            }
        }
    }
}

impl StateEstimator for KalmanEstimator {
    fn update(&mut self, angle_rad: f64, dt_s: f64) -> WheelState {
        if !(angle_rad.is_finite() && dt_s.is_finite() && dt_s > 0.0) {
            return self.state();
        }
        if !self.started {
            self.reset(angle_rad);
            return self.state();
        }
        self.predict(dt_s);
        self.correct(angle_rad);
        self.state()
    }

    fn reset(&mut self, angle_rad: f64) {
        let r = self.params.angle_noise_rad * self.params.angle_noise_rad;
        self.x = [angle_rad, 0.0, 0.0];
        self.p = [[r, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 100.0]];
        self.started = true;
    }
}

/// Tracking figures of an estimator against the true velocity: see [`velocity_tracking`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackingFigures {
    /// RMS of `estimate[n] − true[n]`, rad/s.
    pub rms_error_rad_s: f64,
    /// The delay (samples) that best aligns the estimate with the truth.
    pub lag_samples: usize,
    /// RMS error after removing that delay, rad/s (what is left is noise and distortion).
    pub rms_error_at_lag_rad_s: f64,
}

/// Compare an estimate with the truth: RMS error, and the lag `d ∈ [0, max_lag]` minimising
/// `RMS(estimate[n] − truth[n − d])`. Slices of different lengths are compared over the
/// shorter one; empty input gives zeros.
pub fn velocity_tracking(estimate: &[f64], truth: &[f64], max_lag: usize) -> TrackingFigures {
    let n = estimate.len().min(truth.len());
    let rms_at = |d: usize| {
        if d >= n {
            return f64::INFINITY;
        }
        let sq: f64 = (d..n).map(|i| (estimate[i] - truth[i - d]).powi(2)).sum();
        (sq / (n - d) as f64).sqrt()
    };
    if n == 0 {
        return TrackingFigures {
            rms_error_rad_s: 0.0,
            lag_samples: 0,
            rms_error_at_lag_rad_s: 0.0,
        };
    }
    let (lag, best) = (0..=max_lag.min(n - 1))
        .map(|d| (d, rms_at(d)))
        .fold((0, f64::INFINITY), |b, c| if c.1 < b.1 { c } else { b });
    TrackingFigures {
        rms_error_rad_s: rms_at(0),
        lag_samples: lag,
        rms_error_at_lag_rad_s: best,
    }
}

/// The thesis filter and the Kalman estimator side by side on the simulated wheel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelocityComparison {
    /// Encoder step of the simulated wheel, rad.
    pub encoder_step_rad: f64,
    /// Thesis moving average (M = 175) + direct difference.
    pub moving_average: TrackingFigures,
    /// Kalman estimator with [`KalmanParams::for_encoder_step`].
    pub kalman: TrackingFigures,
}

impl std::fmt::Display for VelocityComparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (name, t) in [
            ("moving average M=175", self.moving_average),
            ("kalman", self.kalman),
        ] {
            writeln!(
                f,
                "encoder step {:.6} rad | {name:<20} | velocity RMS error {:.4} rad/s | lag {} ms | RMS after removing lag {:.4} rad/s",
                self.encoder_step_rad, t.rms_error_rad_s, t.lag_samples, t.rms_error_at_lag_rad_s
            )?;
        }
        Ok(())
    }
}

/// Run the simulated wheel at 1 kHz for `seconds` with a patient-like hand (PD tracking of a
/// 0.5 Hz, 0.6 rad sine: thesis Appendix E's tracking task), quantised to
/// `encoder_step_rad`, and compare both estimators' velocity with the true velocity
/// (first second skipped as start-up). Deterministic (fixed seed). Errors name an
/// out-of-range encoder step.
pub fn compare_on_sim_wheel(
    encoder_step_rad: f64,
    seconds: f64,
) -> Result<VelocityComparison, WheelError> {
    use crate::{SimWheel, SimWheelParams, Wheel};
    let params = SimWheelParams {
        encoder_step_rad,
        ..Default::default()
    };
    params.validate()?;
    let mut w = SimWheel::new(params);
    let dt = 1e-3;
    let n = (seconds / dt) as usize;
    let mut ma = MovingAverage::thesis();
    let mut kf = KalmanEstimator::new(KalmanParams::for_encoder_step(encoder_step_rad))?;
    let (mut v_ma, mut v_kf, mut truth) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    let wn = std::f64::consts::TAU * 0.5;
    for i in 0..n {
        let t = i as f64 * dt;
        let target = 0.6 * (wn * t).sin();
        let target_v = 0.6 * wn * (wn * t).cos();
        let hand = 4.0 * (target - w.true_angle_rad()) + 0.3 * (target_v - w.true_velocity_rad_s());
        w.advance(dt, hand);
        let angle = w.read().map_or(f64::NAN, |r| r.angle_rad);
        v_ma.push(ma.update(angle, dt).vel_rad_s);
        v_kf.push(kf.update(angle, dt).vel_rad_s);
        truth.push(w.true_velocity_rad_s());
    }
    let skip = 1000.min(n);
    Ok(VelocityComparison {
        encoder_step_rad,
        moving_average: velocity_tracking(&v_ma[skip..], &truth[skip..], 400),
        kalman: velocity_tracking(&v_kf[skip..], &truth[skip..], 400),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moving_average_matches_the_direct_sum_of_eq_3_4() {
        let mut ma = MovingAverage::new(5).unwrap();
        let xs: Vec<f64> = (0..40).map(|k| ((k * 7919) % 13) as f64 * 0.1).collect();
        for (n, &x) in xs.iter().enumerate() {
            let y = ma.push(x);
            let lo = n.saturating_sub(4);
            let direct: f64 = xs[lo..=n].iter().sum::<f64>() / (n - lo + 1) as f64;
            assert!((y - direct).abs() < 1e-12, "n={n}: {y} vs {direct}");
        }
    }

    #[test]
    fn moving_average_running_sum_does_not_drift_over_a_long_session() {
        let mut ma = MovingAverage::thesis();
        let step = crate::THESIS_KA_RAD_PER_UNIT;
        let mut y = 0.0;
        // One hour at 1 kHz of a quantised slow sweep, then hold at a known angle.
        for k in 0..3_600_000u64 {
            let x = ((k as f64 * 1e-3).sin() / step).round() * step;
            y = ma.push(x);
        }
        let _ = y;
        for _ in 0..THESIS_MOVING_AVERAGE_LEN {
            y = ma.push(0.5);
        }
        assert!((y - 0.5).abs() < 1e-12, "drift {}", y - 0.5);
    }

    #[test]
    fn moving_average_rejects_zero_length() {
        assert!(
            MovingAverage::new(0)
                .unwrap_err()
                .to_string()
                .contains("len")
        );
    }

    #[test]
    fn kalman_recovers_a_constant_velocity_exactly_in_steady_state() {
        let mut k = KalmanEstimator::new(KalmanParams::for_encoder_step(1e-3)).unwrap();
        let (mut v, mut a) = (0.0, 0.0);
        for n in 0..4000 {
            let t = n as f64 * 1e-3;
            let s = k.update(((0.8 * t) / 1e-3).round() * 1e-3, 1e-3);
            if n >= 3000 {
                v += s.vel_rad_s / 1000.0;
                a += s.acc_rad_s2 / 1000.0;
            }
        }
        assert!((v - 0.8).abs() < 0.002, "mean velocity {v}");
        assert!(a.abs() < 0.05, "mean acceleration {a}");
    }

    #[test]
    fn estimators_skip_non_finite_samples() {
        let mut k = KalmanEstimator::new(KalmanParams::for_encoder_step(1e-3)).unwrap();
        let mut m = MovingAverage::thesis();
        k.update(0.1, 1e-3);
        m.update(0.1, 1e-3);
        let ks = k.update(f64::NAN, 1e-3);
        let ms = m.update(0.2, f64::INFINITY);
        assert!(ks.angle_rad.is_finite() && ms.angle_rad.is_finite());
        assert!(
            KalmanParams {
                jerk_psd: -1.0,
                angle_noise_rad: 1e-3
            }
            .validate()
            .is_err()
        );
    }

    #[test]
    fn kalman_tracks_true_velocity_with_less_error_and_lag_than_the_thesis_filter() {
        for step in [crate::THESIS_KA_RAD_PER_UNIT, 0.1] {
            let c = compare_on_sim_wheel(step, 10.0).unwrap();
            println!("{c}");
            let (fm, fk) = (c.moving_average, c.kalman);
            // The thesis filter lags by about (M − 1)/2 = 87 samples.
            assert!((80..=95).contains(&fm.lag_samples), "{fm:?}");
            assert!(fk.lag_samples < fm.lag_samples / 4, "{fk:?} vs {fm:?}");
            assert!(
                fk.rms_error_rad_s < 0.7 * fm.rms_error_rad_s,
                "{fk:?} vs {fm:?}"
            );
        }
    }
}
