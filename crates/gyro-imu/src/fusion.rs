//! Gyro + accelerometer orientation fusion with online gyro-bias estimation.
//!
//! A port of the 6-D part of VQF (D. Laidig and T. Seel, "VQF: Highly accurate IMU orientation
//! estimation with bias estimation and magnetic disturbance rejection", *Information Fusion* 91,
//! 2023, §3–4; reference implementation `vqf` 2.1, © 2021 Daniel Laidig, MIT licence — the math is
//! re-expressed here in Rust, not copied):
//!
//! - **Strapdown integration** of the bias-corrected rate (eq. 4.12/4.13 of the thesis, VQF
//!   eq. 2) gives `q_gyr`, the sensor orientation in an almost-inertial frame `I`.
//! - **Accelerometer low-pass in `I`**: the specific force is rotated into `I` and low-pass
//!   filtered there (second-order Butterworth, time constant `tau_acc_s`, cutoff
//!   `√2 / (2π·tau_acc_s)`), which removes the linear acceleration of ordinary motion without
//!   lagging the orientation. The filtered direction, rotated by the current inclination
//!   correction `q_inc`, is turned onto `+z` by the shortest rotation: `q_inc ← Δq · q_inc`.
//!   Output `q_inc · q_gyr` (sensor-to-earth, earth z up, heading = the first sample's).
//! - **Gyro bias** `b` is the state of a 3-state Kalman filter whose covariance `P` grows by
//!   `V` per sample up to its initial value (bias forgetting: `(0.1 °/s)²` per
//!   `bias_forgetting_time_s`). Each sample gives one measurement update:
//!   - *at rest* (rest detector below): `y = gyr_lp − b`, measurement matrix `I`, noise from
//!     `bias_sigma_rest_deg_s`;
//!   - *in motion*: the inclination correction it just applied, divided by `dt`, is the
//!     horizontal part of `R·(b_true − b)` (`R` = sensor-to-earth rotation). Both the
//!     correction's inputs and `R` are low-pass filtered with the same filter as the
//!     accelerometer, so the measurement is `y = [−a_y/dt, a_x/dt]` + `LP(R·b)` against the
//!     model `LP(R)·b`; the vertical row is a pseudo-measurement `0` with a much larger noise
//!     (`bias_vertical_forgetting_factor`), which only keeps the unobservable vertical component
//!     from wandering. Noise from `bias_sigma_motion_deg_s`.
//!
//!   The innovation and the estimate are clipped to `±bias_clip_deg_s` per axis.
//! - **Rest detection**: the rate and the specific force are low-pass filtered (second-order
//!   Butterworth, `rest.filter_tau_s`); rest is declared when, for `rest.min_duration_s`, every
//!   sample's deviation from its low-passed value stays below `rest.rate_threshold_deg_s` and
//!   `rest.acc_threshold_m_s2`, and no axis of the low-passed rate exceeds the bias clip.
//!
//! - **Scale estimation** (`FusionConfig::gyro_scale_estimation`, off by default; not in VQF):
//!   a gyroscope axis that reads `(1 + s)` times the true rate turns a rotation at `ω` into a
//!   drift of `R·diag(ω)·s` in the earth frame, exactly as a bias `b` drifts by `R·b`. On
//!   BROAD's IMU the optical truth shows `s` of 0.1–0.8 % per axis at rates up to 1 450 °/s:
//!   5 °/s of drift at 1 000 °/s, which the accelerometer's slow correction removes only late.
//!   The strapdown rate becomes `ω − b − diag(ω)·s`, and `s` joins `b` in the Kalman filter
//!   (six states, covariance in SI units): the motion measurement gains the columns
//!   `LP(R·diag(ω))` for its horizontal rows and `LP(R·diag(ω)·s)` on its left side, both low-
//!   passed like `R` and `R·b`; at rest `s` is not observable (ω ≈ 0) and only the bias is
//!   updated. `s` starts at 0 with `scale_sigma_init_percent`, forgets by 0.1 % per
//!   `scale_forgetting_time_s`, and is clipped to ±3 %. It is observable whenever the rotation
//!   axis varies; under rotation about one fixed axis it stays where it is.
//!
//!   *Translation gate.* The motion measurement also carries the error that linear
//!   acceleration leaves in the low-passed gravity direction; it grows with the acceleration,
//!   while the drift a scale error causes grows with the rotation rate. So `s` is learned only
//!   while rotation dominates: the RMS linear acceleration `a_rms` (the specific force's
//!   magnitude minus that of the low-passed specific force, ≈ g) and the RMS rate `ω_rms`,
//!   both over the accelerometer low-pass, must satisfy `a_rms ≤ v·ω_rms`, with
//!   `v = scale_translation_speed_m_s` (2 m/s). The ratio is a speed: a point turning at radius
//!   `r` about a still centre has `a/ω ≈ r·ω`, its tangential speed (2 m/s: 0.4 m from the
//!   elbow at 5 rad/s), while a sensor carried about or tapped has acceleration with little
//!   rotation. On BROAD it lets the scale be learned in 57–72 % of the samples of the
//!   rotation, combined and magnet trials and in 7–45 % of the translation trials' (where,
//!   learned throughout, the scale states fitted the acceleration's error and made trial 18
//!   worse: 0.614° → 0.630°). Beyond the gate the scale states are *considered,
//!   not estimated* (a Schmidt–Kalman step): the current `s` still corrects the rate, the
//!   measurement updates the bias with `s` held, and `s` and its variance stay as they are.
//!
//! All low-pass filters start with the running mean of their input for one time constant, then
//! switch to the Butterworth recursion from that steady state (as VQF does). Heading is not
//! observable without a magnetometer: it drifts only by the residual vertical bias, which rest
//! phases remove.
//!
//! Departures from the reference: by default rest also requires the gravity direction to be
//! still (`FusionConfig::rest_tilt_check`, see there; [`FusionConfig::reference_vqf`] turns it
//! off and then matches the `vqf` package to rounding). Where VQF has no answer: a sample
//! without accelerometer data (`None`) still runs rest detection (on the gyro alone) and the
//! rest update of the bias; and `dt` may change from sample to sample (the coefficients follow
//! it).

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector2, Vector3};
use serde::{Deserialize, Serialize};

use crate::bias::{RestConfig, lp_gain};
use crate::error::{ImuError, check_range};
use crate::so3;

/// Fusion settings (VQF's parameters and defaults); the defaults need no per-recording tuning.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FusionConfig {
    /// Time constant of the accelerometer low-pass in the almost-inertial frame (s).
    pub tau_acc_s: f64,
    /// Estimate the gyro bias during motion (from the inclination correction).
    pub motion_bias_estimation: bool,
    /// Estimate the gyro bias at rest (and detect rest).
    pub rest_bias_estimation: bool,
    /// Standard deviation of the initial bias estimate (deg/s); also the ceiling of the bias
    /// uncertainty that forgetting can reach.
    pub bias_sigma_init_deg_s: f64,
    /// Time for the bias uncertainty to grow from 0 to 0.1 deg/s without measurements (s).
    pub bias_forgetting_time_s: f64,
    /// Largest bias magnitude per axis (deg/s): estimate and innovation are clipped to it, and
    /// a low-passed rate above it is not rest.
    pub bias_clip_deg_s: f64,
    /// Bias uncertainty that motion alone keeps up (deg/s): sets the motion measurement noise.
    pub bias_sigma_motion_deg_s: f64,
    /// Ratio of the motion noise to the noise of the vertical pseudo-measurement (which holds
    /// the unobservable vertical bias component still during motion); 1e-4 in VQF.
    pub bias_vertical_forgetting_factor: f64,
    /// Bias uncertainty that rest keeps up (deg/s): sets the rest measurement noise.
    pub bias_sigma_rest_deg_s: f64,
    /// Rest detection: `filter_tau_s`, `rate_threshold_deg_s`, `acc_threshold_m_s2` and
    /// `min_duration_s` are used as in VQF; the largest believed bias is the smaller of
    /// `max_bias_deg_s` and `bias_clip_deg_s`; `tilt_rate_threshold_deg_s` is used when
    /// `rest_tilt_check` is on.
    pub rest: RestConfig,
    /// Also require the gravity direction to stay still (`rest.tilt_rate_threshold_deg_s`)
    /// before declaring rest. Not in VQF: it keeps slow real rotations (a drifting elbow,
    /// which the rate-deviation test cannot see) out of the bias. `false` is reference VQF.
    pub rest_tilt_check: bool,
    /// Also estimate each gyroscope axis's scale-factor error during motion (not in VQF; see
    /// the module docs, "Scale estimation"). Off by default: the station's recordings replay
    /// bit for bit with the filter they were made with, and a format version has to say which
    /// one that was before the station can switch it on. Absent from a settings file: off.
    #[serde(default)]
    pub gyro_scale_estimation: bool,
    /// Standard deviation of the initial scale-error estimate (%), also the ceiling forgetting
    /// can raise it to; a consumer MEMS gyroscope's datasheet gives 1–3 %.
    #[serde(default = "default_scale_sigma_init_percent")]
    pub scale_sigma_init_percent: f64,
    /// Time for the scale-error uncertainty to grow from 0 to 0.1 % without motion to observe it
    /// (s).
    #[serde(default = "default_scale_forgetting_time_s")]
    pub scale_forgetting_time_s: f64,
    /// Translation gate of the scale estimation (m/s): the scale errors are learned only while
    /// the RMS linear acceleration stays below this speed times the RMS rotation rate (rad/s),
    /// both over `tau_acc_s` (module docs, "Translation gate").
    #[serde(default = "default_scale_translation_speed_m_s")]
    pub scale_translation_speed_m_s: f64,
}

fn default_scale_translation_speed_m_s() -> f64 {
    2.0
}

fn default_scale_sigma_init_percent() -> f64 {
    1.0
}

fn default_scale_forgetting_time_s() -> f64 {
    100.0
}

/// Largest scale-factor error per axis the estimate may reach (3 %).
const SCALE_CLIP: f64 = 0.03;

/// One unit of the bias Kalman filter's variances, (0.01 deg/s)², in (rad/s)².
fn bias_unit2_rad2_s2() -> f64 {
    (0.01f64).to_radians().powi(2)
}

impl Default for FusionConfig {
    fn default() -> Self {
        Self {
            tau_acc_s: 3.0,
            motion_bias_estimation: true,
            rest_bias_estimation: true,
            bias_sigma_init_deg_s: 0.5,
            bias_forgetting_time_s: 100.0,
            bias_clip_deg_s: 2.0,
            bias_sigma_motion_deg_s: 0.1,
            bias_vertical_forgetting_factor: 1e-4,
            bias_sigma_rest_deg_s: 0.03,
            rest: RestConfig::default(),
            rest_tilt_check: true,
            gyro_scale_estimation: false,
            scale_sigma_init_percent: default_scale_sigma_init_percent(),
            scale_forgetting_time_s: default_scale_forgetting_time_s(),
            scale_translation_speed_m_s: default_scale_translation_speed_m_s(),
        }
    }
}

impl FusionConfig {
    /// The reference VQF's 6-D filter with its default parameters (our defaults without the
    /// tilt-rate rest test); its output matches the `vqf` package to rounding.
    pub fn reference_vqf() -> Self {
        Self {
            rest_tilt_check: false,
            ..Self::default()
        }
    }
}

impl FusionConfig {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        check_range("tau_acc_s", self.tau_acc_s, 0.05, 60.0, "[0.05, 60] s")?;
        check_range(
            "scale_sigma_init_percent",
            self.scale_sigma_init_percent,
            0.01,
            3.0,
            "[0.01, 3] %",
        )?;
        check_range(
            "scale_forgetting_time_s",
            self.scale_forgetting_time_s,
            1.0,
            1e5,
            "[1, 1e5] s",
        )?;
        check_range(
            "scale_translation_speed_m_s",
            self.scale_translation_speed_m_s,
            0.01,
            1e3,
            "[0.01, 1000] m/s",
        )?;
        check_range(
            "bias_sigma_init_deg_s",
            self.bias_sigma_init_deg_s,
            1e-3,
            50.0,
            "[0.001, 50] deg/s",
        )?;
        check_range(
            "bias_forgetting_time_s",
            self.bias_forgetting_time_s,
            1.0,
            1e5,
            "[1, 1e5] s",
        )?;
        check_range(
            "bias_clip_deg_s",
            self.bias_clip_deg_s,
            0.01,
            50.0,
            "[0.01, 50] deg/s",
        )?;
        check_range(
            "bias_sigma_motion_deg_s",
            self.bias_sigma_motion_deg_s,
            1e-3,
            10.0,
            "[0.001, 10] deg/s",
        )?;
        check_range(
            "bias_vertical_forgetting_factor",
            self.bias_vertical_forgetting_factor,
            1e-10,
            1.0,
            "[1e-10, 1]",
        )?;
        check_range(
            "bias_sigma_rest_deg_s",
            self.bias_sigma_rest_deg_s,
            1e-4,
            10.0,
            "[0.0001, 10] deg/s",
        )?;
        self.rest.validate()
    }
}

/// Second-order Butterworth low-pass coefficients `(b, a)` (`a0 = 1` omitted) for time constant
/// `tau_s` at step `dt_s`: cutoff `√2 / (2π·tau_s)`, bilinear transform (VQF `filterCoeffs`).
/// Below `tau_s < dt_s / 2` the filter passes its input through.
fn butter2_coeffs(tau_s: f64, dt_s: f64) -> ([f64; 3], [f64; 2]) {
    if tau_s < dt_s / 2.0 {
        return ([1.0, 0.0, 0.0], [0.0, 0.0]);
    }
    let fc = std::f64::consts::SQRT_2 / (std::f64::consts::TAU * tau_s);
    let c = (std::f64::consts::PI * fc * dt_s).tan();
    let d = c * c + std::f64::consts::SQRT_2 * c + 1.0;
    let b0 = c * c / d;
    (
        [b0, 2.0 * b0, b0],
        [
            2.0 * (c * c - 1.0) / d,
            (1.0 - std::f64::consts::SQRT_2 * c + c * c) / d,
        ],
    )
}

/// A second-order low-pass on `N` channels that outputs the running mean of its input during
/// its first `tau` seconds and then starts the recursion from that mean as a steady state (VQF
/// `filterVec`). Direct form I (past inputs and outputs), so a steady signal stays exactly
/// steady when the coefficients change with `dt`; VQF's transposed form gives the same output
/// for a fixed `dt`.
#[derive(Debug, Clone, Copy)]
struct LowPass<const N: usize> {
    /// Past inputs `x[k−1], x[k−2]` and outputs `y[k−1], y[k−2]`; while averaging, `y1` holds
    /// the running sum.
    x1: [f64; N],
    x2: [f64; N],
    y1: [f64; N],
    y2: [f64; N],
    /// Samples averaged so far.
    count: f64,
    running: bool,
}

impl<const N: usize> LowPass<N> {
    const NEW: Self = Self {
        x1: [0.0; N],
        x2: [0.0; N],
        y1: [0.0; N],
        y2: [0.0; N],
        count: 0.0,
        running: false,
    };

    fn step(
        &mut self,
        x: &[f64; N],
        tau_s: f64,
        dt_s: f64,
        b: &[f64; 3],
        a: &[f64; 2],
    ) -> [f64; N] {
        let mut y = [0.0; N];
        if !self.running {
            self.count += 1.0;
            for i in 0..N {
                self.y1[i] += x[i];
                y[i] = self.y1[i] / self.count;
            }
            if self.count * dt_s >= tau_s {
                // Steady state at the mean: input and output history equal to it.
                self.x1 = y;
                self.x2 = y;
                self.y1 = y;
                self.y2 = y;
                self.running = true;
            }
            return y;
        }
        for i in 0..N {
            y[i] = b[0] * x[i] + b[1] * self.x1[i] + b[2] * self.x2[i]
                - a[0] * self.y1[i]
                - a[1] * self.y2[i];
        }
        self.x2 = self.x1;
        self.x1 = *x;
        self.y2 = self.y1;
        self.y1 = y;
        y
    }
}

/// Coefficients that depend on `dt`; recomputed only when `dt` changes.
#[derive(Debug, Clone, Copy)]
struct Coeffs {
    dt_s: f64,
    acc_b: [f64; 3],
    acc_a: [f64; 2],
    rest_b: [f64; 3],
    rest_a: [f64; 2],
    /// Covariance growth per sample ((0.01 deg/s)² units, as VQF).
    bias_v: f64,
    bias_motion_w: f64,
    bias_vertical_w: f64,
    bias_rest_w: f64,
    /// Gains of the tilt-rate test's fast and slow first-order low-passes (time constants 0.2
    /// and 0.7 × `rest.filter_tau_s`): an `exp` each, taken when `dt` changes, not per sample.
    tilt_fast_gain: f64,
    tilt_slow_gain: f64,
}

impl Coeffs {
    fn new(cfg: &FusionConfig, dt_s: f64) -> Self {
        let (acc_b, acc_a) = butter2_coeffs(cfg.tau_acc_s, dt_s);
        let (rest_b, rest_a) = butter2_coeffs(cfg.rest.filter_tau_s, dt_s);
        // Covariances in (0.01 deg/s)²: V raises P from 0 to (0.1 deg/s)² in the forgetting
        // time; W is chosen so that P settles at sigma² under one update per sample
        // (steady state of P ← P + V − P²/(P + W)).
        let bias_v = (0.1f64 * 100.0).powi(2) * dt_s / cfg.bias_forgetting_time_s;
        let p_motion = (cfg.bias_sigma_motion_deg_s * 100.0).powi(2);
        let bias_motion_w = p_motion * p_motion / bias_v + p_motion;
        let p_rest = (cfg.bias_sigma_rest_deg_s * 100.0).powi(2);
        Self {
            dt_s,
            acc_b,
            acc_a,
            rest_b,
            rest_a,
            bias_v,
            bias_motion_w,
            bias_vertical_w: bias_motion_w / cfg.bias_vertical_forgetting_factor.max(1e-10),
            bias_rest_w: p_rest * p_rest / bias_v + p_rest,
            tilt_fast_gain: lp_gain(0.2 * cfg.rest.filter_tau_s, dt_s),
            tilt_slow_gain: lp_gain(0.7 * cfg.rest.filter_tau_s, dt_s),
        }
    }
}

/// VQF 6-D orientation filter (see the module docs). Allocation-free per sample.
#[derive(Debug, Clone, Copy)]
pub struct OrientationFilter {
    cfg: FusionConfig,
    k: Coeffs,
    /// Initial bias covariance, (0.01 deg/s)².
    bias_p0: f64,
    q_gyr: UnitQuaternion<f64>,
    q_inc: UnitQuaternion<f64>,
    acc_lp: LowPass<3>,
    bias_rad_s: Vector3<f64>,
    /// Bias covariance, (0.01 deg/s)².
    bias_p: Matrix3<f64>,
    r_lp: LowPass<9>,
    rb_lp: LowPass<2>,
    rest_gyr_lp: LowPass<3>,
    rest_acc_lp: LowPass<3>,
    /// Fast and slow first-order low-passes of the specific force for the tilt-rate test.
    rest_tilt_lp: Option<(Vector3<f64>, Vector3<f64>)>,
    rest_gyr_lp_rad_s: Vector3<f64>,
    rest_time_s: f64,
    rest: bool,
    /// Scale estimation (`gyro_scale_estimation`): each axis's scale-factor error
    /// (dimensionless, +0.01 = reads 1 % high).
    scale: Vector3<f64>,
    /// Covariance of (bias rad/s, scale error) in SI units, in place of `bias_p` when scale
    /// estimation is on.
    p6: nalgebra::SMatrix<f64, 6, 6>,
    /// Low-passed horizontal rows of `R·diag(ω)` and of `R·diag(ω)·scale`.
    rw_lp: LowPass<6>,
    rws_lp: LowPass<2>,
    /// Low-passed squares of the linear acceleration's magnitude ((m/s²)²) and of the rate
    /// ((rad/s)²), for the translation gate.
    excitation_lp: LowPass<2>,
    /// Whether the translation gate lets the scale be learned from this sample.
    scale_observable: bool,
}

/// `m` row-major, as its rows pair with the earth-frame components.
fn rows(m: &Matrix3<f64>) -> [f64; 9] {
    [
        m[(0, 0)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 0)],
        m[(1, 1)],
        m[(1, 2)],
        m[(2, 0)],
        m[(2, 1)],
        m[(2, 2)],
    ]
}

fn arr3(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl OrientationFilter {
    /// A filter with validated settings.
    pub fn new(cfg: FusionConfig) -> Result<Self, ImuError> {
        cfg.validate()?;
        let bias_p0 = (cfg.bias_sigma_init_deg_s * 100.0).powi(2);
        Ok(Self {
            cfg,
            k: Coeffs::new(&cfg, 0.01),
            bias_p0,
            q_gyr: UnitQuaternion::identity(),
            q_inc: UnitQuaternion::identity(),
            acc_lp: LowPass::NEW,
            bias_rad_s: Vector3::zeros(),
            bias_p: Matrix3::identity() * bias_p0,
            r_lp: LowPass::NEW,
            rb_lp: LowPass::NEW,
            rest_gyr_lp: LowPass::NEW,
            rest_acc_lp: LowPass::NEW,
            rest_tilt_lp: None,
            rest_gyr_lp_rad_s: Vector3::zeros(),
            rest_time_s: 0.0,
            rest: false,
            scale: Vector3::zeros(),
            p6: nalgebra::SMatrix::<f64, 6, 6>::from_diagonal(&nalgebra::SVector::from([
                bias_p0 * bias_unit2_rad2_s2(),
                bias_p0 * bias_unit2_rad2_s2(),
                bias_p0 * bias_unit2_rad2_s2(),
                (cfg.scale_sigma_init_percent / 100.0).powi(2),
                (cfg.scale_sigma_init_percent / 100.0).powi(2),
                (cfg.scale_sigma_init_percent / 100.0).powi(2),
            ])),
            rw_lp: LowPass::NEW,
            rws_lp: LowPass::NEW,
            excitation_lp: LowPass::NEW,
            scale_observable: false,
        })
    }

    /// Feed one sample: body rate `gyr_rad_s` (rad/s), specific force `acc_m_s2` (m/s², sensor
    /// frame, or `None` for a gyro-only sensor) and the sample period `dt_s`. Returns the
    /// sensor-to-earth orientation. Non-finite inputs are ignored (the orientation holds).
    pub fn update(
        &mut self,
        gyr_rad_s: &Vector3<f64>,
        acc_m_s2: Option<&Vector3<f64>>,
        dt_s: f64,
    ) -> UnitQuaternion<f64> {
        if !(dt_s.is_finite() && dt_s > 0.0 && gyr_rad_s.iter().all(|x| x.is_finite())) {
            return self.orientation();
        }
        if dt_s != self.k.dt_s {
            self.k = Coeffs::new(&self.cfg, dt_s);
        }
        let acc = acc_m_s2.filter(|a| a.iter().all(|x| x.is_finite()) && a.norm() > 1e-3);
        let clip = self.cfg.bias_clip_deg_s.to_radians();
        let rest_enabled = self.cfg.rest_bias_estimation;

        // Rest detection, gyro part: deviation from the low-passed rate, and the low-passed
        // rate itself must look like a believable bias.
        if rest_enabled {
            let lp = self.rest_gyr_lp.step(
                &arr3(gyr_rad_s),
                self.cfg.rest.filter_tau_s,
                dt_s,
                &self.k.rest_b,
                &self.k.rest_a,
            );
            let lp = Vector3::from(lp);
            let dev2 = (gyr_rad_s - lp).norm_squared();
            let max_bias = clip.min(self.cfg.rest.max_bias_deg_s.to_radians());
            if dev2 >= self.cfg.rest.rate_threshold_deg_s.to_radians().powi(2)
                || lp.amax() > max_bias
            {
                self.rest_time_s = 0.0;
                self.rest = false;
            } else if acc.is_none() {
                self.count_rest(dt_s);
            }
            self.rest_gyr_lp_rad_s = lp;
        }

        // Strapdown integration with the current bias estimate (eq. 4.12, 4.13).
        let w = if self.cfg.gyro_scale_estimation {
            gyr_rad_s - self.bias_rad_s - gyr_rad_s.component_mul(&self.scale)
        } else {
            gyr_rad_s - self.bias_rad_s
        };
        self.q_gyr =
            UnitQuaternion::new_normalize(*(self.q_gyr * so3::exp_quat(&(w * dt_s))).quaternion());

        let Some(acc) = acc else {
            if rest_enabled {
                self.bias_update(None, gyr_rad_s);
            }
            return self.orientation();
        };

        // Rest detection, accelerometer part.
        if rest_enabled {
            let lp = self.rest_acc_lp.step(
                &arr3(acc),
                self.cfg.rest.filter_tau_s,
                dt_s,
                &self.k.rest_b,
                &self.k.rest_a,
            );
            // Tilt rate (our addition): under a steady rotation of the gravity direction at
            // rate r, first-order low-passes with time constants 0.2 and 0.7 × filter_tau_s
            // differ in direction by r · 0.5 × filter_tau_s.
            let tau = self.cfg.rest.filter_tau_s;
            let (fast, slow) = self.rest_tilt_lp.get_or_insert((*acc, *acc));
            *fast += (acc - *fast) * self.k.tilt_fast_gain;
            *slow += (acc - *slow) * self.k.tilt_slow_gain;
            let tilting = self.cfg.rest_tilt_check
                && fast.angle(slow) / (0.5 * tau)
                    >= self.cfg.rest.tilt_rate_threshold_deg_s.to_radians();
            if (acc - Vector3::from(lp)).norm_squared() >= self.cfg.rest.acc_threshold_m_s2.powi(2)
                || tilting
            {
                self.rest_time_s = 0.0;
                self.rest = false;
            } else {
                self.count_rest(dt_s);
            }
        }

        // Low-pass in the almost-inertial frame, then the inclination correction onto +z.
        let a_i = self.q_gyr * acc;
        let a_lp = self.acc_lp.step(
            &arr3(&a_i),
            self.cfg.tau_acc_s,
            dt_s,
            &self.k.acc_b,
            &self.k.acc_a,
        );
        if self.cfg.gyro_scale_estimation {
            let lin = acc.norm() - Vector3::from(a_lp).norm();
            let (tau, kb, ka) = (self.cfg.tau_acc_s, self.k.acc_b, self.k.acc_a);
            let [a2, w2] = self.excitation_lp.step(
                &[lin * lin, gyr_rad_s.norm_squared()],
                tau,
                dt_s,
                &kb,
                &ka,
            );
            self.scale_observable = a2 <= self.cfg.scale_translation_speed_m_s.powi(2) * w2;
        }
        let a_e = (self.q_inc * Vector3::from(a_lp)).normalize();
        let qw = ((a_e.z + 1.0) * 0.5).sqrt();
        let corr = if qw > 1e-6 {
            Quaternion::new(qw, 0.5 * a_e.y / qw, -0.5 * a_e.x / qw, 0.0)
        } else {
            Quaternion::new(0.0, 1.0, 0.0, 0.0)
        };
        self.q_inc = UnitQuaternion::new_normalize(corr * *self.q_inc.quaternion());

        if rest_enabled || self.cfg.motion_bias_estimation {
            self.bias_update(Some(&a_e), gyr_rad_s);
        }
        self.orientation()
    }

    fn count_rest(&mut self, dt_s: f64) {
        self.rest_time_s += dt_s;
        if self.rest_time_s >= self.cfg.rest.min_duration_s {
            self.rest = true;
        }
    }

    /// One Kalman-filter step of the bias. `a_e`: the normalised, low-passed gravity direction
    /// in the earth frame before this sample's inclination correction (`None`: no accelerometer,
    /// so no motion measurement); `gyr_rad_s`: this sample's measured rate.
    fn bias_update(&mut self, a_e: Option<&Vector3<f64>>, gyr_rad_s: &Vector3<f64>) {
        if self.cfg.gyro_scale_estimation {
            return self.bias_scale_update(a_e, gyr_rad_s);
        }
        let clip = self.cfg.bias_clip_deg_s.to_radians();
        let dt_s = self.k.dt_s;
        let b = self.bias_rad_s;
        let motion = a_e.map(|a_e| {
            let (_, r_lp, rb_lp) = self.rotation_lowpasses();
            (r_lp, rb_lp, *a_e)
        });
        let meas = if self.rest && self.cfg.rest_bias_estimation {
            let w = self.k.bias_rest_w;
            Some((
                self.rest_gyr_lp_rad_s - b,
                Matrix3::identity(),
                Vector3::new(w, w, w),
            ))
        } else if let (true, Some((r_lp, rb_lp, a_e))) = (self.cfg.motion_bias_estimation, motion) {
            let rb = r_lp * b;
            let e = Vector3::new(
                -a_e.y / dt_s + rb_lp.x - rb.x,
                a_e.x / dt_s + rb_lp.y - rb.y,
                -rb.z,
            );
            let (wm, wv) = (self.k.bias_motion_w, self.k.bias_vertical_w);
            Some((e, r_lp, Vector3::new(wm, wm, wv)))
        } else {
            None
        };
        // Prediction: forgetting raises the variance, up to its initial value.
        for i in 0..3 {
            if self.bias_p[(i, i)] < self.bias_p0 {
                self.bias_p[(i, i)] += self.k.bias_v;
            }
        }
        let Some((e, h, w)) = meas else {
            return;
        };
        // The clip also bounds the harm of the first (aligning) inclination correction.
        let e = e.map(|x| x.clamp(-clip, clip));
        let pht = self.bias_p * h.transpose();
        let s = Matrix3::from_diagonal(&w) + h * pht;
        let Some(s_inv) = s.try_inverse() else {
            return;
        };
        let gain = pht * s_inv;
        self.bias_rad_s = (b + gain * e).map(|x| x.clamp(-clip, clip));
        self.bias_p -= gain * h * self.bias_p;
    }

    /// The rotation matrix `R` (sensor-to-earth) now, and the low-passes of `R` and of `R·b`'s
    /// horizontal part (the motion measurement's model and offset), kept running in every phase.
    fn rotation_lowpasses(&mut self) -> (Matrix3<f64>, Matrix3<f64>, Vector2<f64>) {
        let r = self.orientation().to_rotation_matrix().into_inner();
        let rb = r * self.bias_rad_s;
        let (tau, dt_s, kb, ka) = (self.cfg.tau_acc_s, self.k.dt_s, self.k.acc_b, self.k.acc_a);
        let rl = self.r_lp.step(&rows(&r), tau, dt_s, &kb, &ka);
        let rbl = self.rb_lp.step(&[rb.x, rb.y], tau, dt_s, &kb, &ka);
        (r, Matrix3::from_row_slice(&rl), Vector2::from(rbl))
    }

    /// [`Self::bias_update`] with the scale-factor errors as three more states (module docs,
    /// "Scale estimation"), in SI units.
    fn bias_scale_update(&mut self, a_e: Option<&Vector3<f64>>, gyr_rad_s: &Vector3<f64>) {
        use nalgebra::{SMatrix, SVector};
        let clip = self.cfg.bias_clip_deg_s.to_radians();
        let dt_s = self.k.dt_s;
        let k2 = bias_unit2_rad2_s2();
        let b = self.bias_rad_s;
        let sc = self.scale;
        let motion = a_e.map(|a_e| {
            let (r, r_lp, rb_lp) = self.rotation_lowpasses();
            // The horizontal rows of R·diag(ω) and of R·diag(ω)·s, low-passed alike.
            let rw = r * Matrix3::from_diagonal(gyr_rad_s);
            let rws = rw * sc;
            let (tau, kb, ka) = (self.cfg.tau_acc_s, self.k.acc_b, self.k.acc_a);
            let mut rw_rows = [0.0; 6];
            rw_rows.copy_from_slice(&rows(&rw)[..6]);
            let rwl = self.rw_lp.step(&rw_rows, tau, dt_s, &kb, &ka);
            let rwsl = self.rws_lp.step(&[rws.x, rws.y], tau, dt_s, &kb, &ka);
            (r_lp, rb_lp, rwl, Vector2::from(rwsl), *a_e)
        });
        let v_b = self.k.bias_v * k2;
        let v_s = (0.001f64).powi(2) * dt_s / self.cfg.scale_forgetting_time_s;
        let p0b = self.bias_p0 * k2;
        let p0s = (self.cfg.scale_sigma_init_percent / 100.0).powi(2);
        for i in 0..3 {
            if self.p6[(i, i)] < p0b {
                self.p6[(i, i)] += v_b;
            }
            if self.p6[(i + 3, i + 3)] < p0s {
                self.p6[(i + 3, i + 3)] += v_s;
            }
        }
        let (e, h, w, learn_scale): (Vector3<f64>, SMatrix<f64, 3, 6>, Vector3<f64>, bool) =
            if self.rest && self.cfg.rest_bias_estimation {
                let w = self.k.bias_rest_w * k2;
                let mut h = SMatrix::<f64, 3, 6>::zeros();
                h.fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(&Matrix3::identity());
                (self.rest_gyr_lp_rad_s - b, h, Vector3::new(w, w, w), false)
            } else if let (true, Some((r_lp, rb_lp, rwl, rws_lp, a_e))) =
                (self.cfg.motion_bias_estimation, motion)
            {
                let rb = r_lp * b;
                let rw_lp = nalgebra::Matrix2x3::from_row_slice(&rwl);
                let rws = rw_lp * sc;
                let e = Vector3::new(
                    -a_e.y / dt_s + rb_lp.x - rb.x + rws_lp.x - rws.x,
                    a_e.x / dt_s + rb_lp.y - rb.y + rws_lp.y - rws.y,
                    -rb.z,
                );
                let mut h = SMatrix::<f64, 3, 6>::zeros();
                h.fixed_view_mut::<3, 3>(0, 0).copy_from(&r_lp);
                if self.scale_observable {
                    h.fixed_view_mut::<2, 3>(0, 3).copy_from(&rw_lp);
                }
                let (wm, wv) = (self.k.bias_motion_w * k2, self.k.bias_vertical_w * k2);
                (e, h, Vector3::new(wm, wm, wv), self.scale_observable)
            } else {
                return;
            };
        let e = e.map(|x| x.clamp(-clip, clip));
        let pht = self.p6 * h.transpose();
        let s = Matrix3::from_diagonal(&w) + h * pht;
        let Some(s_inv) = s.try_inverse() else {
            return;
        };
        let mut gain = pht * s_inv;
        // Rest, or motion beyond the translation gate: a Schmidt–Kalman step that considers
        // the scale states without estimating them (their gain rows are zero). The bias block
        // and the bias–scale cross-covariance are updated as in the full step; the scale block
        // keeps its value.
        if !learn_scale {
            gain.fixed_rows_mut::<3>(3).fill(0.0);
        }
        let dx: SVector<f64, 6> = gain * e;
        self.bias_rad_s = (b + dx.fixed_rows::<3>(0)).map(|x| x.clamp(-clip, clip));
        self.scale = (sc + dx.fixed_rows::<3>(3)).map(|x| x.clamp(-SCALE_CLIP, SCALE_CLIP));
        self.p6 -= gain * h * self.p6;
        if !learn_scale {
            let cross = self.p6.fixed_view::<3, 3>(0, 3).transpose();
            self.p6.fixed_view_mut::<3, 3>(3, 0).copy_from(&cross);
        }
    }

    /// Restart integration from orientation `q` (sensor-to-earth): e.g. a known initial pose
    /// for a gyro-only sensor. The accelerometer still corrects inclination afterwards; the
    /// bias estimate is kept.
    pub fn set_orientation(&mut self, q: UnitQuaternion<f64>) {
        self.q_gyr = q;
        self.q_inc = UnitQuaternion::identity();
        self.acc_lp = LowPass::NEW;
        self.r_lp = LowPass::NEW;
        self.rb_lp = LowPass::NEW;
        self.rw_lp = LowPass::NEW;
        self.rws_lp = LowPass::NEW;
        self.excitation_lp = LowPass::NEW;
    }

    /// The current sensor-to-earth orientation.
    pub fn orientation(&self) -> UnitQuaternion<f64> {
        self.q_inc * self.q_gyr
    }

    /// The current gyro-bias estimate (rad/s, sensor frame).
    pub fn bias_rad_s(&self) -> Vector3<f64> {
        self.bias_rad_s
    }

    /// The standard deviation of the bias estimate in its worst direction (rad/s): the
    /// square root of a Gershgorin bound on the covariance's largest eigenvalue, capped at
    /// `bias_sigma_init_deg_s`.
    pub fn bias_sigma_rad_s(&self) -> f64 {
        let cov = if self.cfg.gyro_scale_estimation {
            self.p6.fixed_view::<3, 3>(0, 0) / bias_unit2_rad2_s2()
        } else {
            self.bias_p
        };
        let p = (0..3)
            .map(|i| cov.row(i).abs().sum())
            .fold(0.0, f64::max)
            .min(self.bias_p0);
        (p.sqrt() / 100.0).to_radians()
    }

    /// The estimated scale-factor error of each gyroscope axis (dimensionless, +0.01 = the
    /// axis reads 1 % high); zero unless `gyro_scale_estimation` is on.
    pub fn gyro_scale_error(&self) -> Vector3<f64> {
        self.scale
    }

    /// Whether the translation gate lets the scale errors be learned from the current sample
    /// (module docs, "Translation gate"); always `false` without `gyro_scale_estimation`.
    pub fn scale_observable(&self) -> bool {
        self.scale_observable
    }

    /// Whether the rest detector currently declares rest.
    pub fn is_rest(&self) -> bool {
        self.rest
    }
}

/// Run an [`OrientationFilter`] over a whole record (`gyr` and `acc` the same length).
pub fn fuse(
    gyr_rad_s: &[Vector3<f64>],
    acc_m_s2: &[Vector3<f64>],
    dt_s: f64,
    cfg: FusionConfig,
) -> Result<Vec<UnitQuaternion<f64>>, ImuError> {
    check_range("dt_s", dt_s, 1e-6, 1.0, "[1e-6, 1] s")?;
    if gyr_rad_s.len() != acc_m_s2.len() {
        return Err(ImuError::InvalidInput(format!(
            "gyr has {} samples but acc has {}",
            gyr_rad_s.len(),
            acc_m_s2.len()
        )));
    }
    let mut f = OrientationFilter::new(cfg)?;
    Ok(gyr_rad_s
        .iter()
        .zip(acc_m_s2)
        .map(|(g, a)| f.update(g, Some(a), dt_s))
        .collect())
}

#[cfg(test)]
mod tests;
