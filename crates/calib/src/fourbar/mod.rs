//! Planar four-bar calibration of the arm and wheel (thesis §4.2.1, eq. 4.1–4.4).
//!
//! Four methods share one loop model ([`model`]):
//! - [`FourbarMethod::Global`]: closed form, no initial guess, the global minimum of the
//!   thesis's least-squares cost ([`closed_form`]);
//! - [`FourbarMethod::Thesis`]: the thesis's iterated Gauss–Newton, kept as the reference;
//! - [`FourbarMethod::Lm`]: robust Levenberg–Marquardt with gyro-bias terms from a given start;
//! - [`FourbarMethod::Auto`] (default): the global solution (re-weighted against outliers when
//!   `robust`) refined by the robust LM (and, when
//!   an initial guess is given, the LM from it too, keeping the lower cost);
//!
//! and [`online::OnlineFourbar`] tracks the parameters sample by sample.

pub mod closed_form;
mod iterative;
pub mod model;
pub mod online;
pub mod quality;
pub mod smoothing;

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

pub use model::{FourbarGeometry, FourbarParams, FourbarSamples, MIN_SAMPLES, loop_residual};
pub use quality::FourbarStdErrors;

use crate::error::CalibError;
use closed_form::SqrtInfo;
use iterative::{Refined, gauss_newton, huber_threshold, levenberg_marquardt, normal_equations};

/// Which estimator to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FourbarMethod {
    /// Global closed form, then robust LM with gyro-bias terms (the default).
    #[default]
    Auto,
    /// Closed-form global least squares only (no bias terms, no robust weighting).
    Global,
    /// The thesis's iterated Gauss–Newton (eq. 4.2–4.4, with a Δl1 column added because l1 is
    /// unknown here; all samples in every iteration) from `initial` (reference; may diverge).
    Thesis,
    /// Robust Levenberg–Marquardt from `initial`.
    Lm,
}

impl FourbarMethod {
    /// The method's name as used in the Python API.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Global => "global",
            Self::Thesis => "thesis",
            Self::Lm => "lm",
        }
    }
}

/// Options of [`calibrate`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FourbarOptions {
    /// Estimator.
    pub method: FourbarMethod,
    /// Initial guess (needed by `Thesis` and `Lm`; optional extra start for `Auto`).
    pub initial: Option<FourbarParams>,
    /// Estimate linear gyro drift of φ3 and φ4 (`Auto` and `Lm`).
    pub gyro_bias: bool,
    /// Huber-robust weighting of outlying samples (`Auto` and `Lm`).
    pub robust: bool,
    /// Iteration limit of the iterative methods, 1..=10 000.
    pub max_iterations: u32,
    /// Relative step tolerance of the iterative methods, in (0, 1e-3].
    pub tolerance: f64,
    /// Half-width (samples) of a zero-phase Savitzky–Golay smoother applied to φ2, φ3, φ4
    /// before the fit, 0 (off) ..= 500. Removes the errors-in-variables bias that white angle
    /// noise causes; keep the window well under a quarter of the motion's period
    /// ([`smoothing`]).
    pub smoothing_half_window: usize,
}

impl Default for FourbarOptions {
    fn default() -> Self {
        Self {
            method: FourbarMethod::Auto,
            initial: None,
            gyro_bias: true,
            robust: true,
            max_iterations: 200,
            tolerance: 1e-12,
            smoothing_half_window: 0,
        }
    }
}

impl FourbarOptions {
    /// Check every field, naming the one out of range.
    pub fn validate(&self) -> Result<(), CalibError> {
        if !(1..=10_000).contains(&self.max_iterations) {
            return Err(CalibError::OutOfRange {
                argument: "max_iterations",
                value: self.max_iterations as f64,
                allowed: "1..=10000",
            });
        }
        if !(self.tolerance > 0.0 && self.tolerance <= 1e-3) {
            return Err(CalibError::OutOfRange {
                argument: "tolerance",
                value: self.tolerance,
                allowed: "(0, 1e-3]",
            });
        }
        if self.smoothing_half_window > 500 {
            return Err(CalibError::OutOfRange {
                argument: "smoothing_half_window",
                value: self.smoothing_half_window as f64,
                allowed: "0..=500 samples",
            });
        }
        if let Some(p) = &self.initial {
            p.validate()?;
        }
        Ok(())
    }
}

/// A calibrated four-bar and how far to trust it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FourbarCalibration {
    /// The estimate (lengths m, angles rad, frame with the ground link along +x).
    pub params: FourbarParams,
    /// The estimator that produced it (`"auto"`, `"global"`, `"thesis"`, `"lm"`, `"online"`).
    pub method: &'static str,
    /// Iterations of the iterative stage (0 for the closed form).
    pub iterations: u32,
    /// Whether the iterative stage met its tolerance (always true for the closed form).
    pub converged: bool,
    /// RMS of the loop-closure residual |ΔX| per sample (m).
    pub rms_residual_m: f64,
    /// 1σ standard errors from the covariance σ²(JᵀJ)⁻¹. They describe the random spread
    /// only, not the errors-in-variables bias angle noise causes (see [`smoothing`]); after
    /// smoothing the residuals are correlated and these are optimistic.
    pub std_errors: FourbarStdErrors,
    /// Condition number of the column-equilibrated Jacobian (identifiability; < 100 is good).
    pub condition_number: f64,
    /// Fraction of samples the robust loss down-weighted (0 without robust weighting).
    pub outlier_fraction: f64,
    /// Peak-to-peak wheel motion in the data (rad), `None` for the online estimator.
    pub wheel_range_rad: Option<f64>,
    /// Human-readable warnings, each with the remedy.
    pub warnings: Vec<String>,
}

fn check_l2(l2_m: f64) -> Result<(), CalibError> {
    if l2_m.is_finite() && l2_m > 0.0 {
        Ok(())
    } else {
        Err(CalibError::OutOfRange {
            argument: "l2",
            value: l2_m,
            allowed: "a finite wheel radius > 0 m",
        })
    }
}

/// Calibrate the planar four-bar from one recording. `l2_m` is the known wheel radius (grip
/// to wheel centre, m).
pub fn calibrate(
    samples: &FourbarSamples<'_>,
    l2_m: f64,
    options: &FourbarOptions,
) -> Result<FourbarCalibration, CalibError> {
    check_l2(l2_m)?;
    samples.validate()?;
    options.validate()?;
    if options.smoothing_half_window > 0 {
        let w = options.smoothing_half_window;
        let (p2, p3, p4) = (
            smoothing::savitzky_golay(samples.phi2, w),
            smoothing::savitzky_golay(samples.phi3, w),
            smoothing::savitzky_golay(samples.phi4, w),
        );
        let smoothed = FourbarSamples {
            phi2: &p2,
            phi3: &p3,
            phi4: &p4,
            time_s: samples.time_s,
        };
        let unsmoothed = FourbarOptions {
            smoothing_half_window: 0,
            ..*options
        };
        return calibrate(&smoothed, l2_m, &unsmoothed);
    }
    let tol = options.tolerance;
    let max_it = options.max_iterations;
    let np = if options.gyro_bias { 8 } else { 6 };
    let need_initial = |method| {
        options
            .initial
            .ok_or(CalibError::MissingInitialGuess { method })
    };
    // The closed form's statistics come straight from its triangular factor (no second pass).
    let mut global_stats = None;
    let (refined, robust_c) = match options.method {
        FourbarMethod::Global => {
            let info = SqrtInfo::from_samples(samples);
            let (p, cost) = info.solve(l2_m)?;
            let normal = to_dynamic(&info.normal_matrix(&p, l2_m));
            global_stats = Some(quality::fit_stats(&normal, cost, info.n_eff));
            (
                Refined {
                    p: p.to_vec8(),
                    iterations: 0,
                    converged: true,
                },
                None,
            )
        }
        FourbarMethod::Thesis => {
            let p0 = need_initial("thesis")?.to_vec8();
            (gauss_newton(p0, l2_m, samples, max_it, tol)?, None)
        }
        FourbarMethod::Lm => {
            let p0 = need_initial("lm")?.to_vec8();
            robust_lm(p0, np, l2_m, samples, options.robust, max_it, tol)
        }
        FourbarMethod::Auto => {
            let global = if options.robust {
                closed_form::robust_global(samples, l2_m)?
            } else {
                SqrtInfo::from_samples(samples).solve(l2_m)?.0
            };
            let mut best = robust_lm(
                global.to_vec8(),
                np,
                l2_m,
                samples,
                options.robust,
                max_it,
                tol,
            );
            if let Some(init) = options.initial {
                let other = robust_lm(
                    init.to_vec8(),
                    np,
                    l2_m,
                    samples,
                    options.robust,
                    max_it,
                    tol,
                );
                // compare both ends under the same loss (the global start's threshold)
                let c = best.1;
                let cost = |r: &(Refined, Option<f64>)| {
                    normal_equations(&r.0.p, np, l2_m, samples, c).cost
                };
                if cost(&other) < cost(&best) {
                    best = other;
                }
            }
            best
        }
    };
    let np_used = if matches!(options.method, FourbarMethod::Auto | FourbarMethod::Lm) {
        np
    } else {
        6
    };
    let params = FourbarParams::from_vec8(refined.p);
    let (stats, outlier_fraction) = match global_stats {
        Some(stats) => (stats, 0.0),
        None => {
            let ne = normal_equations(&params.to_vec8(), np_used, l2_m, samples, robust_c);
            let outliers = if robust_c.is_some() {
                ne.outlier_fraction
            } else {
                0.0
            };
            (quality::fit_stats(&ne.jtj, ne.ssr, ne.w_sum), outliers)
        }
    };
    let range = samples.wheel_range_rad();
    let mut warnings = quality::warnings(&params, &stats, Some(range), samples.time_s.is_some());
    if !refined.converged {
        warnings.push(format!(
            "the {} refinement stopped at its iteration limit ({}) before converging",
            options.method.name(),
            refined.iterations
        ));
    }
    if outlier_fraction > 0.2 {
        warnings.push(format!(
            "{:.0}% of the samples do not fit the arm model (down-weighted); check that the \
             torso stayed still and the gyros stayed on the arm",
            100.0 * outlier_fraction
        ));
    }
    Ok(FourbarCalibration {
        params,
        method: options.method.name(),
        iterations: refined.iterations,
        converged: refined.converged,
        rms_residual_m: stats.rms_residual_m,
        std_errors: stats.std_errors,
        condition_number: stats.condition_number,
        outlier_fraction,
        wheel_range_rad: Some(range),
        warnings,
    })
}

/// LM with Huber weighting whose threshold is re-estimated from the residuals until stable
/// (at most three passes). Returns the refinement and the final threshold.
fn robust_lm(
    p0: [f64; 8],
    np: usize,
    l2: f64,
    s: &FourbarSamples<'_>,
    robust: bool,
    max_it: u32,
    tol: f64,
) -> (Refined, Option<f64>) {
    if !robust {
        return (levenberg_marquardt(p0, np, l2, s, None, max_it, tol), None);
    }
    let mut c = huber_threshold(&p0, l2, s);
    let mut total = 0;
    let mut refined = levenberg_marquardt(p0, np, l2, s, Some(c), max_it, tol);
    total += refined.iterations;
    for _ in 0..2 {
        let c_new = huber_threshold(&refined.p, l2, s);
        if (c_new / c - 1.0).abs() < 0.3 {
            break;
        }
        c = c_new;
        refined = levenberg_marquardt(refined.p, np, l2, s, Some(c), max_it, tol);
        total += refined.iterations;
    }
    refined.iterations = total;
    (refined, Some(c))
}

/// Normal matrix as a dynamic matrix (for [`quality::fit_stats`]).
pub(crate) fn to_dynamic(m: &nalgebra::SMatrix<f64, 6, 6>) -> DMatrix<f64> {
    DMatrix::from_fn(6, 6, |i, j| m[(i, j)])
}

#[cfg(test)]
mod tests;
