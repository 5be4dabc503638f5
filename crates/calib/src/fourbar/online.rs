//! Online (recursive) four-bar calibration: the square-root information form of the global
//! method ([`super::closed_form`]) updated one sample at a time with exponential forgetting, so
//! the estimate tracks slow changes during a session (a slipping grip, gyro drift, the patient
//! shifting in the seat). Each update is a 9×7 QR; each estimate a 2×2 SVD and a 5×5
//! triangular solve. No initial guess is needed and there is nothing to diverge.

use serde::{Deserialize, Serialize};

use super::closed_form::SqrtInfo;
use super::quality::{fit_stats, warnings};
use super::{FourbarCalibration, check_l2, to_dynamic};
use crate::error::CalibError;

/// Options of the online estimator.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OnlineOptions {
    /// Forgetting factor λ per sample, in [0.9, 1]: the memory is about 1/(1−λ) samples
    /// (1 = never forget).
    pub forgetting: f64,
}

impl Default for OnlineOptions {
    fn default() -> Self {
        Self { forgetting: 0.999 }
    }
}

impl OnlineOptions {
    /// Check every field, naming the one out of range.
    pub fn validate(&self) -> Result<(), CalibError> {
        crate::error::check_forgetting(self.forgetting)
    }
}

/// Recursive least-squares four-bar calibration with forgetting.
#[derive(Debug, Clone)]
pub struct OnlineFourbar {
    l2_m: f64,
    options: OnlineOptions,
    info: SqrtInfo,
}

impl OnlineFourbar {
    /// A fresh estimator for wheel radius `l2_m` (m).
    pub fn new(l2_m: f64, options: OnlineOptions) -> Result<Self, CalibError> {
        check_l2(l2_m)?;
        options.validate()?;
        Ok(Self {
            l2_m,
            options,
            info: SqrtInfo::new(),
        })
    }

    /// Absorb one sample of relative angles (rad). A non-finite sample is rejected and leaves
    /// the estimator unchanged.
    pub fn update(&mut self, phi2: f64, phi3: f64, phi4: f64) -> Result<(), CalibError> {
        for (argument, v) in [("phi2", phi2), ("phi3", phi3), ("phi4", phi4)] {
            if !v.is_finite() {
                return Err(CalibError::NonFinite {
                    argument,
                    index: self.info.count as usize,
                });
            }
        }
        self.info.update(phi2, phi3, phi4, self.options.forgetting);
        Ok(())
    }

    /// Samples absorbed so far.
    pub fn samples(&self) -> u64 {
        self.info.count
    }

    /// The current estimate, or an error while the data do not yet determine it.
    pub fn estimate(&self) -> Result<FourbarCalibration, CalibError> {
        let needed = super::MIN_SAMPLES;
        if (self.info.count as usize) < needed {
            return Err(CalibError::TooFewSamples {
                argument: "updates",
                got: self.info.count as usize,
                needed,
            });
        }
        let (params, cost) = self.info.solve(self.l2_m)?;
        let normal = to_dynamic(&self.info.normal_matrix(&params, self.l2_m));
        let stats = fit_stats(&normal, cost, self.info.n_eff);
        let warnings = warnings(&params, &stats, None, false);
        Ok(FourbarCalibration {
            params,
            method: "online",
            iterations: 0,
            converged: true,
            rms_residual_m: stats.rms_residual_m,
            std_errors: stats.std_errors,
            condition_number: stats.condition_number,
            outlier_fraction: 0.0,
            wheel_range_rad: None,
            warnings,
        })
    }
}
