//! Online (recursive) arm calibration for the 1 kHz station thread: the normal equations of
//! the loop (module docs of [`super`], eq. (1)) accumulated sample by sample with optional
//! exponential forgetting, solved on demand. An update is O(1) and allocation-free (a rank-3
//! update of a 5×5 or 7×7 matrix and a 4-sample history for the noise estimate); an estimate
//! is a 7×7 eigen-decomposition and Cholesky solve. No initial guess, nothing to diverge.
//!
//! The heading offset here is the linearised one (valid for offsets up to ~10°: the error of
//! the linearisation is ~ψ²/2 of the segment length); there is no re-rotation of past samples
//! and no drift term. That is enough for white noise and slow drift (2°/min), not for the
//! heading drift of consumer IMUs through the orientation filter (tens of degrees per minute
//! from an uncorrected vertical gyro bias): there the online estimate is ~4 cm off where the
//! batch [`super::calibrate_arm_3d`] with [`super::HeadingModel::OffsetAndDrift`] is ~4 mm off
//! (BENCHMARKS.md). Until the online form re-rotates, run the batch fit on a recorded window
//! off the 1 kHz thread for such sensors.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::solve::{FOURTH_DIFFERENCE, Normal};
use super::{Arm3dCalibration, HeadingModel, MIN_SAMPLES, check_vector, warnings};
use crate::error::CalibError;

/// Options of [`OnlineArm3d`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OnlineArm3dOptions {
    /// Forgetting factor λ per sample, in [0.9, 1]: the memory is about 1/(1 − λ) samples
    /// (1 = never forget). The default 0.99995 remembers about 20 s at 1 kHz.
    pub forgetting: f64,
    /// Also estimate a (linearised) heading offset per segment: seven unknowns instead of five.
    pub heading_offset: bool,
    /// Estimate the white direction noise and remove the length bias it causes.
    pub errors_in_variables: bool,
}

impl Default for OnlineArm3dOptions {
    fn default() -> Self {
        Self {
            forgetting: 0.99995,
            heading_offset: true,
            errors_in_variables: true,
        }
    }
}

impl OnlineArm3dOptions {
    /// Check every field, naming the one out of range.
    pub fn validate(&self) -> Result<(), CalibError> {
        crate::error::check_forgetting(self.forgetting)
    }
}

/// Recursive least-squares arm calibration with forgetting (see the module docs).
///
/// # Example
///
/// ```
/// use calib::arm3d::{OnlineArm3d, OnlineArm3dOptions};
/// let mut est = OnlineArm3d::new(OnlineArm3dOptions::default())?;
/// let (s, lu, lf) = ([-0.4, -0.2, 0.25], 0.3, 0.33);
/// for k in 0..200 {
///     let a = 0.01 * k as f64;
///     let u = [0.6 * a.cos(), 0.6 * a.sin(), -0.8];
///     let f = [0.8, 0.6 * a.cos(), 0.6 * a.sin()];
///     let g = std::array::from_fn(|i| s[i] + lu * u[i] + lf * f[i]);
///     est.update(u, f, g)?; // each tick: O(1), no allocation
/// }
/// let cal = est.estimate()?; // on demand (allocates the warnings)
/// assert!((cal.params.forearm_m - 0.33).abs() < 1e-6);
/// # Ok::<(), calib::CalibError>(())
/// ```
#[derive(Debug, Clone)]
pub struct OnlineArm3d {
    options: OnlineArm3dOptions,
    normal: Normal<7>,
    /// Last four directions (newest first): upper, fore.
    history: [[Vector3<f64>; 4]; 2],
    /// Forgotten sums of |Δ⁴u|², |Δ⁴f|² and their count.
    noise_sums: [f64; 3],
    count: u64,
}

impl OnlineArm3d {
    /// A fresh estimator.
    pub fn new(options: OnlineArm3dOptions) -> Result<Self, CalibError> {
        options.validate()?;
        Ok(Self {
            options,
            normal: Normal::new(),
            history: [[Vector3::zeros(); 4]; 2],
            noise_sums: [0.0; 3],
            count: 0,
        })
    }

    /// The options.
    pub fn options(&self) -> &OnlineArm3dOptions {
        &self.options
    }

    /// Absorb one sample: upper-arm and forearm unit directions (wheel frame) and the grip
    /// point (m, wheel frame). Bad input (non-finite, not unit) is rejected and leaves the
    /// estimator unchanged. O(1), allocation-free.
    pub fn update(
        &mut self,
        upper_dir: [f64; 3],
        fore_dir: [f64; 3],
        grip_m: [f64; 3],
    ) -> Result<(), CalibError> {
        let index = self.count as usize;
        check_vector("upper_dir", index, &upper_dir, true)?;
        check_vector("fore_dir", index, &fore_dir, true)?;
        check_vector("grip_m", index, &grip_m, false)?;
        let (u, f, g) = (
            Vector3::from(upper_dir),
            Vector3::from(fore_dir),
            Vector3::from(grip_m),
        );
        let lambda = self.options.forgetting;
        self.normal.add(&u, &f, &g, 0.0, lambda);
        if self.options.errors_in_variables {
            if self.count >= 4 {
                let mut d = [u * FOURTH_DIFFERENCE[0], f * FOURTH_DIFFERENCE[0]];
                for (seg, h) in self.history.iter().enumerate() {
                    for (c, v) in FOURTH_DIFFERENCE[1..].iter().zip(h) {
                        d[seg] += v * *c;
                    }
                }
                let s = &mut self.noise_sums;
                s[0] = s[0] * lambda + d[0].norm_squared();
                s[1] = s[1] * lambda + d[1].norm_squared();
                s[2] = s[2] * lambda + 1.0;
            }
            for (h, v) in self.history.iter_mut().zip([u, f]) {
                h.rotate_right(1);
                h[0] = v;
            }
        }
        self.count += 1;
        Ok(())
    }

    /// Samples absorbed so far.
    pub fn samples(&self) -> u64 {
        self.count
    }

    /// Mean square white direction noise `[upper, fore]` estimated so far (rad²).
    fn noise2(&self) -> [f64; 2] {
        let s = &self.noise_sums;
        if s[2] > 0.0 {
            [s[0] / (70.0 * s[2]), s[1] / (70.0 * s[2])]
        } else {
            [0.0; 2]
        }
    }

    /// The current estimate, or an error while the data do not determine it (too few
    /// samples, or the wheel has not turned).
    pub fn estimate(&self) -> Result<Arm3dCalibration, CalibError> {
        if (self.count as usize) < MIN_SAMPLES {
            return Err(CalibError::TooFewSamples {
                argument: "updates",
                got: self.count as usize,
                needed: MIN_SAMPLES,
            });
        }
        let heading = if self.options.heading_offset {
            HeadingModel::Offset
        } else {
            HeadingModel::Exact
        };
        let p = heading.unknowns();
        let noise2 = self.noise2();
        let sol = self.normal.solve(p, noise2)?;
        let ssr = self.normal.ssr_at(&sol.x);
        let stats = self.normal.stats(&sol, p, ssr);
        let mut params = sol.params();
        if p == 7 {
            params.heading_offset_rad = [sol.x[5] / sol.x[3], sol.x[6] / sol.x[4]];
        }
        let w = self.normal.w_sum;
        let mut cal = Arm3dCalibration {
            params,
            method: "online",
            heading,
            iterations: 0,
            converged: true,
            rms_residual_m: (ssr / w).sqrt(),
            std_errors: stats.std_errors,
            condition_number: stats.condition_number,
            direction_noise_rad: [noise2[0].sqrt(), noise2[1].sqrt()],
            grip_spread_m: self.normal.grip_spread_m(),
            samples: w,
            warnings: Vec::new(),
        };
        cal.warnings = warnings(&cal);
        Ok(cal)
    }

    /// Forget everything (a new patient or a re-seated one).
    pub fn reset(&mut self) {
        *self = Self {
            options: self.options,
            normal: Normal::new(),
            history: [[Vector3::zeros(); 4]; 2],
            noise_sums: [0.0; 3],
            count: 0,
        };
    }
}
