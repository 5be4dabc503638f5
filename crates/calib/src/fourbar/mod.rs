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
//! With `errors_in_variables` (the default for `Auto` and `Lm`) the fit weights each sample by
//! the angle noise estimated from the data and removes the bias that noise causes ([`eiv`]).
//!
//! and [`online::OnlineFourbar`] tracks the parameters sample by sample.

pub mod closed_form;
pub mod eiv;
mod global;
mod iterative;
mod median;
pub mod model;
pub mod online;
pub mod quality;
mod scratch;
pub mod smoothing;
pub mod testdata;
pub(crate) mod trig;

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

pub use eiv::NoiseProfile;
pub use model::{FourbarGeometry, FourbarParams, FourbarSamples, MIN_SAMPLES, loop_residual};
pub use quality::FourbarStdErrors;

use crate::error::CalibError;
use closed_form::{SqrtInfo, gram};
use eiv::Gains;
use iterative::{
    Problem, Quadratic, Refined, Reweight, gauss_newton, levenberg_marquardt, pass,
    pass_reweighted, residual_norms2,
};
use median::{median_every, median_stride};
use trig::Trig;

/// Which estimator to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FourbarMethod {
    /// Global closed form, then robust LM with gyro-bias terms, both noise-weighted and
    /// corrected for the errors-in-variables bias when `errors_in_variables` (the default).
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
    /// before the fit, 0 (off) ..= 500. Reduces the errors-in-variables bias that white angle
    /// noise causes; keep the window well under a quarter of the motion's period
    /// ([`smoothing`]). Not needed with `errors_in_variables`, which removes that bias itself.
    pub smoothing_half_window: usize,
    /// Estimate the angle noise of each sample from the data (`Auto` and `Lm`), weight the
    /// samples by it and correct the errors-in-variables bias it causes ([`eiv`]). Exact,
    /// noise-free data give the same answer with or without it.
    pub errors_in_variables: bool,
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
            errors_in_variables: true,
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
    let eiv = options.errors_in_variables
        && matches!(options.method, FourbarMethod::Auto | FourbarMethod::Lm);
    if options.smoothing_half_window > 0 {
        let w = options.smoothing_half_window;
        // the noise is estimated on the raw angles and carried through the filter
        let noise = eiv.then(|| NoiseProfile::estimate(samples).smoothed(w));
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
        return calibrate_with_noise(&smoothed, l2_m, options, noise.as_ref());
    }
    let noise = eiv.then(|| NoiseProfile::estimate(samples));
    let result = calibrate_with_noise(samples, l2_m, options, noise.as_ref());
    if let Some(nz) = noise {
        nz.recycle();
    }
    result
}

/// A refinement and the weights it ended with.
struct Fit {
    refined: Refined,
    /// Final per-sample weights (noise × Huber).
    weights: Vec<f64>,
    /// Σ of the Huber factors (the effective sample count).
    n_eff: f64,
    /// Fraction of samples the Huber loss down-weighted.
    outlier_fraction: f64,
    /// The plain (unweighted, uncorrected) cost as a quadratic form, when the fit used it:
    /// then the statistics need no further pass over the samples.
    plain: Option<Quadratic>,
    /// With bias terms and robust weights: the normal matrix `JᵀWJ` (the correction's share
    /// put back) and `Σ w·|r|²` of the LM's last evaluated point, and `Σ|r|²` (unweighted) at
    /// the answer, from the residual norms the final reweighting computed there: the
    /// statistics need no further pass over the samples either.
    last_pass: Option<(DMatrix<f64>, f64, f64)>,
    /// The last Huber threshold (m; `None` without robust weighting).
    threshold: Option<f64>,
}

fn calibrate_with_noise(
    samples: &FourbarSamples<'_>,
    l2_m: f64,
    options: &FourbarOptions,
    noise: Option<&NoiseProfile>,
) -> Result<FourbarCalibration, CalibError> {
    let tol = options.tolerance;
    let max_it = options.max_iterations;
    let np = if options.gyro_bias { 8 } else { 6 };
    let need_initial = |method| {
        options
            .initial
            .ok_or(CalibError::MissingInitialGuess { method })
    };
    let trig = Trig::new(samples);
    let gains = noise.map(NoiseProfile::gains);
    let refine_on = |trig: &Trig,
                     p0: [f64; 8],
                     noise: Option<&NoiseProfile>,
                     gains: Option<&Gains>,
                     accept: f64| {
        refine(
            trig,
            l2_m,
            p0,
            np,
            noise,
            gains,
            options.robust,
            Stop {
                max_it,
                tol,
                accept,
            },
        )
    };
    let refine = |p0: [f64; 8]| refine_on(&trig, p0, noise, gains.as_ref(), 0.0);
    // The closed form's statistics come straight from its triangular factor (no second pass).
    let mut global_stats = None;
    let fit = match options.method {
        FourbarMethod::Global => {
            let info = SqrtInfo::from_samples(samples, &trig);
            let (p, cost) = info.solve(l2_m)?;
            let normal = to_dynamic(&info.normal_matrix(&p, l2_m));
            global_stats = Some(quality::fit_stats(&normal, cost, info.n_eff));
            plain_fit(p.to_vec8(), 0, true, samples.len())
        }
        FourbarMethod::Thesis => {
            let p0 = need_initial("thesis")?.to_vec8();
            let q = Quadratic::new(gram(&trig, None, None), false);
            let r = gauss_newton(p0, &q, l2_m, max_it, tol)?;
            Fit {
                plain: Some(q),
                ..plain_fit(r.p, r.iterations, r.converged, samples.len())
            }
        }
        FourbarMethod::Lm => refine(need_initial("lm")?.to_vec8()),
        FourbarMethod::Auto => {
            let mut best = auto_fit(
                samples,
                &trig,
                l2_m,
                options,
                noise,
                gains.as_ref(),
                np,
                refine_on,
            )?;
            if let Some(init) = options.initial {
                let mut other = refine(init.to_vec8());
                // compare both ends under the same cost (the global start's final weights)
                let pb = Problem {
                    trig: &trig,
                    l2: l2_m,
                    weights: Some(&best.weights),
                    gains: gains.as_ref(),
                };
                let cost = |f: &Fit| pass::<8>(&pb, &f.refined.p).normal.cost;
                if cost(&other) < cost(&best) {
                    std::mem::swap(&mut best, &mut other);
                }
                scratch::give(other.weights);
            }
            best
        }
    };
    let np_used = if matches!(options.method, FourbarMethod::Auto | FourbarMethod::Lm) {
        np
    } else {
        6
    };
    let params = FourbarParams::from_vec8(fit.refined.p);
    let stats = match global_stats {
        Some(stats) => stats,
        None => fit_statistics(samples, &trig, l2_m, &fit, np_used, &params),
    };
    let refined = fit.refined;
    let outlier_fraction = fit.outlier_fraction;
    scratch::give(fit.weights);
    trig.recycle();
    if let Some(g) = gains {
        g.recycle();
    }
    let range = samples.wheel_range_rad();
    let mut warnings = quality::warnings(&params, &stats, Some(range), samples.time_s.is_some());
    fit_warnings(&mut warnings, options.method, &refined, outlier_fraction);
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

/// The warnings about the fit itself: a refinement stopped at its iteration limit, many
/// samples down-weighted.
fn fit_warnings(
    warnings: &mut Vec<String>,
    method: FourbarMethod,
    refined: &Refined,
    outlier_fraction: f64,
) {
    if !refined.converged {
        warnings.push(format!(
            "the {} refinement stopped at its iteration limit ({}) before converging",
            method.name(),
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
}

/// `Auto`'s fit from its global start: on long recordings (≥ [`GLOBAL_DECIMATION_FROM`]
/// samples) the start, and with robust weights and bias terms the robust rounds too, on a
/// [`Subset`], then [`polish`] over every sample; otherwise the start and `refine` over every
/// sample.
#[allow(clippy::too_many_arguments)]
fn auto_fit(
    samples: &FourbarSamples<'_>,
    trig: &Trig,
    l2_m: f64,
    options: &FourbarOptions,
    noise: Option<&NoiseProfile>,
    gains: Option<&Gains>,
    np: usize,
    refine_on: impl Fn(&Trig, [f64; 8], Option<&NoiseProfile>, Option<&Gains>, f64) -> Fit,
) -> Result<Fit, CalibError> {
    let (tol, max_it) = (options.tolerance, options.max_iterations);
    let n = samples.len();
    let sub = (n >= GLOBAL_DECIMATION_FROM)
        .then(|| Subset::new(samples, trig, noise, gains, n / GLOBAL_SUBSET));
    let global = match &sub {
        Some(sub) => global::global_fit(
            &sub.samples(),
            &sub.trig,
            l2_m,
            sub.noise.as_ref(),
            sub.gains.as_ref(),
            options.robust,
        ),
        None => global::global_fit(samples, trig, l2_m, noise, gains, options.robust),
    };
    Ok(match sub {
        Some(sub) if options.robust && np == 8 => {
            // robust rounds on the subset, then the whole recording's pass(es)
            // the subset's LM may stop a Newton step early ([`SUBSET_ACCEPT`])
            let accept = SUBSET_ACCEPT / sub.trig.len() as f64;
            let coarse = global.map(|g| {
                refine_on(
                    &sub.trig,
                    g.to_vec8(),
                    sub.noise.as_ref(),
                    sub.gains.as_ref(),
                    accept,
                )
            });
            sub.recycle();
            let coarse = coarse?;
            polish(trig, l2_m, coarse, noise, gains, max_it, tol)
        }
        sub => {
            if let Some(sub) = sub {
                sub.recycle();
            }
            refine_on(trig, global?.to_vec8(), noise, gains, 0.0)
        }
    })
}

/// Recordings at least this long run [`FourbarMethod::Auto`]'s global start and, when robust
/// with bias terms (the default), its robust rounds on a subset of [`GLOBAL_SUBSET`] evenly
/// spaced samples, and then fit every sample: one pass that reweights every sample at the
/// subset's answer and sums the normal equations, and Newton steps from there. (From 2 000 samples it made the
/// thesis's 25 % noise case of the noise study worse: 500 samples pin the start less well
/// there.)
pub const GLOBAL_DECIMATION_FROM: usize = 4000;

/// Samples the subset of a long recording has (at least; every `n / GLOBAL_SUBSET`-th).
pub const GLOBAL_SUBSET: usize = 1000;

/// The fit of every sample after the subset's takes a Newton step without the pass that would evaluate it when the step's
/// predicted decrease is at most this many times `cost / n_eff`, about a squared standard
/// error: Newton's convergence is quadratic, so the step after it would move the answer by a
/// small fraction of its standard error.
pub const POLISH_ACCEPT: f64 = 40.0;

/// The robust LM rounds on the subset of a long recording ([`GLOBAL_SUBSET`] samples) take a
/// Newton step without the pass that would evaluate it when its predicted decrease is at most
/// this many times `cost / n` of the subset (n its samples): a hundredth of a squared standard
/// error of the subset's answer, which only seeds the fit of every sample (and the step after
/// it would, by Newton's quadratic convergence, be smaller by as much again). One pass of the
/// subset fewer per round.
pub const SUBSET_ACCEPT: f64 = 0.01;

/// Every `stride`-th sample of a recording and of its per-sample arrays: `Auto`'s global
/// start and robust rounds only have to put the fit of every sample in the basin of its
/// minimum and set the robust threshold, so on long recordings they run on this (their cost
/// no longer grows with the recording).
struct Subset {
    phi2: Vec<f64>,
    phi3: Vec<f64>,
    phi4: Vec<f64>,
    time_s: Option<Vec<f64>>,
    trig: Trig,
    noise: Option<NoiseProfile>,
    gains: Option<Gains>,
}

impl Subset {
    fn new(
        samples: &FourbarSamples<'_>,
        trig: &Trig,
        noise: Option<&NoiseProfile>,
        gains: Option<&Gains>,
        stride: usize,
    ) -> Self {
        let m = samples.len().div_ceil(stride);
        // by index over a range (an exact-size iterator the vector fills without a capacity
        // check per value; `step_by` is not one)
        let every = |v: &[f64]| scratch::collect((0..m).map(|j| v[j * stride]), m);
        Self {
            phi2: every(samples.phi2),
            phi3: every(samples.phi3),
            phi4: every(samples.phi4),
            time_s: samples.time_s.map(every),
            trig: Trig {
                c2: every(&trig.c2),
                s2: every(&trig.s2),
                c3: every(&trig.c3),
                s3: every(&trig.s3),
                c4: every(&trig.c4),
                s4: every(&trig.s4),
                t: every(&trig.t),
                uniform_dt: trig.uniform_dt.map(|dt| dt * stride as f64),
            },
            noise: noise.map(|nz| NoiseProfile {
                var2: every(&nz.var2),
                var3: every(&nz.var3),
                var4: every(&nz.var4),
            }),
            gains: gains.map(|g| Gains {
                g2: every(&g.g2),
                g3: every(&g.g3),
                g4: every(&g.g4),
            }),
        }
    }

    fn samples(&self) -> FourbarSamples<'_> {
        FourbarSamples {
            phi2: &self.phi2,
            phi3: &self.phi3,
            phi4: &self.phi4,
            time_s: self.time_s.as_deref(),
        }
    }

    /// Hand the arrays back to [`scratch`] for the next calibration on this thread.
    fn recycle(self) {
        for v in [self.phi2, self.phi3, self.phi4]
            .into_iter()
            .chain(self.time_s)
        {
            scratch::give(v);
        }
        self.trig.recycle();
        if let Some(nz) = self.noise {
            nz.recycle();
        }
        if let Some(g) = self.gains {
            g.recycle();
        }
    }
}

/// The fit of every sample from the robust fit of a subset (`coarse`, with bias terms):
/// one pass at its answer weights every sample (noise weights, and Huber factors under the
/// subset's last threshold, as `refine`'s final reweighting does) and sums the normal
/// equations at once; then Levenberg–Marquardt under those weights, whose first Newton step
/// usually ends it ([`POLISH_ACCEPT`]). The statistics come from the last pass: `JᵀWJ` and
/// `Σw|r|²` where it was evaluated, `Σ|r|²` at the subset's answer (one or two Newton steps
/// from the answer: a relative difference of the order of `POLISH_ACCEPT / n`).
fn polish(
    trig: &Trig,
    l2: f64,
    coarse: Fit,
    noise: Option<&NoiseProfile>,
    gains: Option<&Gains>,
    max_it: u32,
    tol: f64,
) -> Fit {
    let n = trig.len();
    let p = coarse.refined.p;
    scratch::give(coarse.weights);
    let mut u = scratch::take(n);
    let unweighted = Problem {
        trig,
        l2,
        weights: None,
        gains,
    };
    let rw = pass_reweighted(
        &unweighted,
        &p,
        &Reweight {
            noise,
            huber: coarse.threshold,
        },
        &mut u,
    );
    let accept = POLISH_ACCEPT / rw.n_eff.max(1.0);
    let mut first = Some(rw.pass.normal);
    let pb = Problem {
        weights: Some(&u),
        ..unweighted
    };
    let (mut refined, ne) = levenberg_marquardt::<8>(
        p,
        |q| first.take().unwrap_or_else(|| pass::<8>(&pb, q).normal),
        max_it,
        tol,
        accept,
    );
    refined.iterations += coarse.refined.iterations;
    let mut jtj = DMatrix::from_fn(8, 8, |i, j| ne.jtj[(i, j)]);
    jtj[(1, 1)] += ne.correction_diag[0];
    jtj[(2, 2)] += ne.correction_diag[1];
    Fit {
        refined,
        weights: u,
        n_eff: rw.n_eff,
        outlier_fraction: rw.outliers as f64 / n as f64,
        plain: None,
        last_pass: Some((jtj, ne.cost_scale, rw.ssr)),
        threshold: coarse.threshold,
    }
}

/// The statistics of `fit` (`np_used` parameters) of `samples`, but for the closed form's,
/// which come from its triangular factor.
fn fit_statistics(
    samples: &FourbarSamples<'_>,
    trig: &Trig,
    l2_m: f64,
    fit: &Fit,
    np_used: usize,
    params: &FourbarParams,
) -> quality::FitStats {
    if let Some((jtj, ssr_w, ssr)) = &fit.last_pass {
        let mut stats = quality::fit_stats(jtj, *ssr_w, fit.n_eff);
        stats.rms_residual_m = (ssr / samples.len() as f64).sqrt();
        return stats;
    }
    match &fit.plain {
        Some(q) => {
            // plain least squares without bias terms: everything from the 7×7 form
            let ne = q.normal(l2_m, &params.to_vec8());
            let jtj = DMatrix::from_fn(6, 6, |i, j| ne.jtj[(i, j)]);
            quality::fit_stats(&jtj, ne.cost.max(0.0), samples.len() as f64)
        }
        None => {
            let pb = Problem {
                trig,
                l2: l2_m,
                weights: Some(&fit.weights),
                gains: None,
            };
            let p = params.to_vec8();
            let (jtj, ssr_w, ssr) = if np_used == 8 {
                let ps = pass::<8>(&pb, &p);
                let jtj = DMatrix::from_fn(8, 8, |i, j| ps.normal.jtj[(i, j)]);
                (jtj, ps.normal.cost, ps.ssr_unweighted)
            } else {
                let ps = pass::<6>(&pb, &p);
                let jtj = DMatrix::from_fn(6, 6, |i, j| ps.normal.jtj[(i, j)]);
                (jtj, ps.normal.cost, ps.ssr_unweighted)
            };
            let mut stats = quality::fit_stats(&jtj, ssr_w, fit.n_eff);
            stats.rms_residual_m = (ssr / samples.len() as f64).sqrt();
            stats
        }
    }
}

fn plain_fit(p: [f64; 8], iterations: u32, converged: bool, n: usize) -> Fit {
    Fit {
        refined: Refined {
            p,
            iterations,
            converged,
        },
        weights: scratch::filled(n, 1.0),
        n_eff: n as f64,
        outlier_fraction: 0.0,
        plain: None,
        last_pass: None,
        threshold: None,
    }
}

/// When [`refine`]'s Levenberg–Marquardt runs stop: at `max_it` iterations, at a relative
/// step below `tol`, or (`accept` > 0) at a Newton step whose predicted relative decrease of
/// the cost is at most `accept` (see [`levenberg_marquardt`]).
#[derive(Clone, Copy)]
struct Stop {
    max_it: u32,
    tol: f64,
    accept: f64,
}

/// Huber threshold as a multiple of the robust residual scale σ̂ (median residual norm / 1.1774
/// for a 2-D Gaussian residual).
const HUBER_K: f64 = 2.5;

/// Levenberg–Marquardt on the first `np` parameters from `p0`, with weights from the noise
/// profile (when given) times Huber factors re-estimated from the residuals (when `robust`, at
/// most three rounds, until the threshold is stable): iteratively re-weighted least squares.
#[allow(clippy::too_many_arguments)]
fn refine(
    trig: &Trig,
    l2: f64,
    p0: [f64; 8],
    np: usize,
    noise: Option<&NoiseProfile>,
    gains: Option<&Gains>,
    robust: bool,
    stop: Stop,
) -> Fit {
    let Stop {
        max_it,
        tol,
        accept,
    } = stop;
    let n = trig.len();
    let mut p = p0;
    for v in p.iter_mut().skip(np) {
        *v = 0.0;
    }
    let (mut nw, mut u, mut h) = (
        scratch::filled(n, 1.0),
        scratch::filled(n, 1.0),
        scratch::filled(n, 1.0),
    );
    let (mut norms, mut sorted) = (scratch::take(n), scratch::take(n));
    // noise weights and Huber factors at p (threshold `c` re-estimated when `None`)
    // the point of the last noise weights and standardised norms: the final reweighting
    // usually happens where the last robust round's check did, and reuses them
    let mut norms_at: Option<[f64; 8]> = None;
    // Σ|r|² (unweighted, m²) there
    let mut ssr_at = 0.0;
    let mut reweight = |p: &[f64; 8], c: Option<f64>, nw: &mut Vec<f64>, h: &mut Vec<f64>| {
        let same = norms_at == Some(*p);
        if let Some(nz) = noise
            && !same
        {
            nz.weights(l2, p[1].abs(), p[2].abs(), nw);
        }
        if !robust {
            return 0.0;
        }
        // squared standardised norms ρ² (the median of ρ is the root of the median of ρ²)
        if !same {
            residual_norms2(trig, l2, p, &mut norms);
            let mut ssr = 0.0;
            for (r2, w) in norms.iter_mut().zip(nw.iter()) {
                ssr += *r2;
                *r2 *= w;
            }
            ssr_at = ssr;
            norms_at = Some(*p);
        }
        let c = c.unwrap_or_else(|| {
            (HUBER_K * median_every(&norms, median_stride(n), &mut sorted).sqrt() / 1.1774)
                .max(1e-12 * l2)
        });
        let c2 = c * c;
        for (hk, r2) in h.iter_mut().zip(&norms) {
            *hk = if *r2 > c2 { c / r2.sqrt() } else { 1.0 };
        }
        c
    };
    let mut total = 0;
    let mut refined = Refined {
        p,
        iterations: 0,
        converged: true,
    };
    let mut c_prev: Option<f64> = None;
    let mut plain = None;
    let mut last_normal = None;
    let rounds = if robust { 3 } else { 1 };
    for _ in 0..rounds {
        let c = reweight(&p, None, &mut nw, &mut h);
        if let Some(cp) = c_prev
            && (c / cp - 1.0).abs() < 0.3
        {
            break;
        }
        c_prev = Some(c);
        for k in 0..n {
            u[k] = nw[k] * h[k];
        }
        let pb = Problem {
            trig,
            l2,
            weights: Some(&u),
            gains,
        };
        refined = if np == 8 {
            let (r, ne) =
                levenberg_marquardt::<8>(p, |q| pass::<8>(&pb, q).normal, max_it, tol, accept);
            last_normal = Some(ne);
            r
        } else {
            let unweighted = noise.is_none() && !robust;
            let w = (!unweighted).then_some(u.as_slice());
            let q = Quadratic::new(gram(trig, w, gains), gains.is_some());
            let (r, _) = levenberg_marquardt::<6>(p, |x| q.normal(l2, x), max_it, tol, accept);
            if unweighted && matches!(q, Quadratic::Sqrt(_)) {
                plain = Some(q);
            }
            r
        };
        total += refined.iterations;
        p = refined.p;
    }
    refined.iterations = total;
    // the weights at the answer, under the last threshold
    reweight(&p, c_prev, &mut nw, &mut h);
    for k in 0..n {
        u[k] = nw[k] * h[k];
    }
    let outliers = h.iter().filter(|&&v| v < 1.0).count();
    let n_eff = h.iter().sum();
    // the norms at the answer are there when robust (the final reweighting computed them)
    let last_pass = last_normal
        .filter(|_| robust && norms_at == Some(p))
        .map(|ne| {
            let mut jtj = DMatrix::from_fn(8, 8, |i, j| ne.jtj[(i, j)]);
            jtj[(1, 1)] += ne.correction_diag[0];
            jtj[(2, 2)] += ne.correction_diag[1];
            (jtj, ne.cost_scale, ssr_at)
        });
    for v in [nw, h, norms, sorted] {
        scratch::give(v);
    }
    Fit {
        refined,
        weights: u,
        n_eff,
        outlier_fraction: outliers as f64 / n as f64,
        plain,
        last_pass,
        threshold: c_prev.filter(|_| robust),
    }
}

/// Normal matrix as a dynamic matrix (for [`quality::fit_stats`]).
pub(crate) fn to_dynamic(m: &nalgebra::SMatrix<f64, 6, 6>) -> DMatrix<f64> {
    DMatrix::from_fn(6, 6, |i, j| m[(i, j)])
}

#[cfg(test)]
mod tests;
