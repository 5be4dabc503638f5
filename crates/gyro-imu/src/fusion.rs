//! Gyro + accelerometer orientation fusion with online gyro-bias estimation.
//!
//! The structure follows VQF (Laidig & Seel, *Information Fusion* 2023): the gyro is
//! strapdown-integrated (eq. 4.12/4.13) into an almost-inertial frame `I`; the accelerometer is
//! rotated into `I` and low-pass filtered there (second-order Butterworth, time constant
//! `tau_acc_s`), which removes the linear acceleration of ordinary motion without lagging the
//! orientation; the filtered gravity direction then drives an inclination correction `I → E`.
//! The gyro bias is estimated at rest (rest detector, averaging) and during motion from the
//! inclination correction it causes (the two horizontal components); estimates are clipped.
//! Heading is not observable without a magnetometer: it drifts only by the residual vertical
//! bias, which rest phases remove. Earth frame `E`: z up, heading = the sensor's initial one.

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::bias::{RestConfig, RestDetector};
use crate::error::{ImuError, check_range};
use crate::so3;

/// Fusion settings; the defaults need no per-recording tuning.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FusionConfig {
    /// Time constant of the accelerometer low-pass in the almost-inertial frame (s).
    pub tau_acc_s: f64,
    /// Time constant of bias estimation during motion (s); 0 disables it.
    pub motion_bias_tau_s: f64,
    /// Time constant of bias estimation at rest (s).
    pub rest_bias_tau_s: f64,
    /// Largest bias magnitude the motion estimator may reach (deg/s); a larger bias measured
    /// at rest is kept.
    pub bias_clip_deg_s: f64,
    /// Rest detection settings.
    pub rest: RestConfig,
}

impl Default for FusionConfig {
    fn default() -> Self {
        Self {
            tau_acc_s: 3.0,
            motion_bias_tau_s: 40.0,
            rest_bias_tau_s: 10.0,
            bias_clip_deg_s: 2.0,
            rest: RestConfig::default(),
        }
    }
}

impl FusionConfig {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        check_range("tau_acc_s", self.tau_acc_s, 0.05, 60.0, "[0.05, 60] s")?;
        check_range(
            "motion_bias_tau_s",
            self.motion_bias_tau_s,
            0.0,
            3600.0,
            "0 (off) or [10, 3600] s",
        )?;
        if self.motion_bias_tau_s > 0.0 && self.motion_bias_tau_s < 10.0 {
            return Err(ImuError::InvalidConfig {
                field: "motion_bias_tau_s",
                value: self.motion_bias_tau_s,
                allowed: "0 (off) or [10, 3600] s",
            });
        }
        check_range(
            "rest_bias_tau_s",
            self.rest_bias_tau_s,
            0.1,
            600.0,
            "[0.1, 600] s",
        )?;
        check_range(
            "bias_clip_deg_s",
            self.bias_clip_deg_s,
            0.0,
            50.0,
            "[0, 50] deg/s",
        )?;
        self.rest.validate()
    }
}

/// Second-order Butterworth low-pass on a 3-vector (bilinear transform, direct form I),
/// cutoff `√2 / (2π·tau)` as in VQF; coefficients follow the actual `dt` of each step.
#[derive(Debug, Clone, Copy, Default)]
struct Butter2 {
    x1: Vector3<f64>,
    x2: Vector3<f64>,
    y1: Vector3<f64>,
    y2: Vector3<f64>,
}

impl Butter2 {
    fn reset(&mut self, x: Vector3<f64>) {
        *self = Self {
            x1: x,
            x2: x,
            y1: x,
            y2: x,
        };
    }

    fn step(&mut self, x: Vector3<f64>, tau_s: f64, dt_s: f64) -> Vector3<f64> {
        let fc = std::f64::consts::SQRT_2 / (std::f64::consts::TAU * tau_s);
        let k = (std::f64::consts::PI * fc * dt_s).min(1.5).tan();
        let norm = 1.0 / (1.0 + std::f64::consts::SQRT_2 * k + k * k);
        let b0 = k * k * norm;
        let a1 = 2.0 * (k * k - 1.0) * norm;
        let a2 = (1.0 - std::f64::consts::SQRT_2 * k + k * k) * norm;
        let y = (x + self.x1 * 2.0 + self.x2) * b0 - self.y1 * a1 - self.y2 * a2;
        self.x2 = self.x1;
        self.x1 = x;
        self.y2 = self.y1;
        self.y1 = y;
        y
    }
}

/// VQF-style 6-D orientation filter (see the module docs). Allocation-free per sample.
#[derive(Debug, Clone, Copy)]
pub struct OrientationFilter {
    cfg: FusionConfig,
    q_gyr: UnitQuaternion<f64>,
    q_inc: UnitQuaternion<f64>,
    acc_lp: Butter2,
    bias_rad_s: Vector3<f64>,
    rest: RestDetector,
    rest_time_s: f64,
    started: bool,
}

impl OrientationFilter {
    /// A filter with validated settings.
    pub fn new(cfg: FusionConfig) -> Result<Self, ImuError> {
        cfg.validate()?;
        Ok(Self {
            cfg,
            q_gyr: UnitQuaternion::identity(),
            q_inc: UnitQuaternion::identity(),
            acc_lp: Butter2::default(),
            bias_rad_s: Vector3::zeros(),
            rest: RestDetector::new(cfg.rest)?,
            rest_time_s: 0.0,
            started: false,
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
        let acc = acc_m_s2.filter(|a| a.iter().all(|x| x.is_finite()) && a.norm() > 1e-3);
        // Rest: average the raw rate into the bias.
        if self.rest.update(gyr_rad_s, acc, dt_s) {
            // A running mean over the rest phase, then an exponential average (time constant
            // `rest_bias_tau_s`), so even a short pause yields a full estimate.
            self.rest_time_s += dt_s;
            let k = (dt_s / self.rest_time_s.min(self.cfg.rest_bias_tau_s)).min(1.0);
            self.bias_rad_s += (gyr_rad_s - self.bias_rad_s) * k;
        } else {
            self.rest_time_s = 0.0;
        }
        // Strapdown integration (eq. 4.12, 4.13).
        let w = gyr_rad_s - self.bias_rad_s;
        self.q_gyr =
            UnitQuaternion::new_normalize(*(self.q_gyr * so3::exp_quat(&(w * dt_s))).quaternion());
        let Some(acc) = acc else {
            return self.orientation();
        };
        let a_i = self.q_gyr * acc;
        let first = !self.started;
        if first {
            self.started = true;
            self.acc_lp.reset(a_i);
        }
        let a_lp = self.acc_lp.step(a_i, self.cfg.tau_acc_s, dt_s);
        let a_e = (self.q_inc * a_lp).normalize();
        // The rotation taking the filtered gravity direction onto +z.
        let axis = a_e.cross(&Vector3::z());
        let s = axis.norm();
        if s > 1e-15 {
            let corr = axis * (s.atan2(a_e.z) / s);
            self.q_inc =
                UnitQuaternion::new_normalize(*(so3::exp_quat(&corr) * self.q_inc).quaternion());
            // The first correction is the initial alignment, not evidence of bias.
            if self.cfg.motion_bias_tau_s > 0.0 && !self.rest.is_rest() && !first {
                // corr ≈ −R_ES·(b − b̂)_horizontal·dt (first order): step b̂ toward b.
                let r_es = self.q_inc * self.q_gyr;
                let db = r_es.inverse() * corr * (-1.0 / self.cfg.motion_bias_tau_s);
                // Motion may not push the bias beyond the clip (or beyond what rest measured).
                let clip = self
                    .cfg
                    .bias_clip_deg_s
                    .to_radians()
                    .max(self.bias_rad_s.norm());
                let b = self.bias_rad_s + db;
                self.bias_rad_s = if b.norm() > clip {
                    b * (clip / b.norm())
                } else {
                    b
                };
            }
        }
        self.orientation()
    }

    /// Restart integration from orientation `q` (sensor-to-earth): e.g. a known initial pose
    /// for a gyro-only sensor. The accelerometer still corrects inclination afterwards.
    pub fn set_orientation(&mut self, q: UnitQuaternion<f64>) {
        self.q_gyr = q;
        self.q_inc = UnitQuaternion::identity();
        self.started = false;
    }

    /// The current sensor-to-earth orientation.
    pub fn orientation(&self) -> UnitQuaternion<f64> {
        self.q_inc * self.q_gyr
    }

    /// The current gyro-bias estimate (rad/s, sensor frame).
    pub fn bias_rad_s(&self) -> Vector3<f64> {
        self.bias_rad_s
    }

    /// Whether the rest detector currently declares rest.
    pub fn is_rest(&self) -> bool {
        self.rest.is_rest()
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
