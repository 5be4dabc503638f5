//! Spatial arm calibration from segment directions: the patient's shoulder position and the
//! upper-arm and forearm lengths, in closed form (the 3-D form of the thesis's loop, eq. 4.1).
//!
//! # Model
//!
//! The station's arm model (`gyro_imu::arm`): wheel frame `W` (origin at the wheel centre,
//! x forward, y left, z up), a spherical shoulder at the unknown point `S`, the upper arm of
//! unknown length `l_u` from the shoulder to the elbow along the upper-arm frame's **x axis**
//! (`u = R_upper·e_x`), the forearm of unknown length `l_f` from the elbow to the grip along
//! the forearm frame's **x axis** (`f = R_fore·e_x`; the forearm's pronation turns it about
//! that axis, so `f` does not depend on it), and the hand on the rim of the tilted wheel at
//! the grip point `G(θ)` (`gyro_imu::arm::ArmGeometry::grip`: radius `r`, rim angle
//! `φ = φ₀ + θ`, `G = r·(−e_y·cos φ + (−sin τ, 0, cos τ)·sin φ)` for a wheel tilted by `τ`).
//! Going round the loop shoulder → elbow → grip closes it at every sample `k`:
//!
//! ```text
//!     S + l_u·u_k + l_f·f_k = G(θ_k)                                   (1)
//! ```
//!
//! This is eq. 4.1 of the thesis written in 3-D: there the planar loop is closed through the
//! ground link and the wheel crank with *angles* measured relative to unknown initial angles,
//! which makes the fit nonlinear (eq. 4.2–4.4 linearise and iterate). Here the segment
//! *directions* are measured in the wheel frame (the IMU orientations once the mounting is
//! known, `gyro_imu::mounting`; §4.3 makes the same point: the gyros give each segment's
//! full orientation, whatever the joints in between), the grip point is known geometry, and
//! (1) is **linear** in `x = (S, l_u, l_f)`: three equations per sample, five unknowns. Stacking
//! the samples as in eq. 4.3, `A x = b` with `A_k = [I₃ | u_k | f_k]`, `b_k = G_k`, the
//! least-squares solution (eq. 4.4) `x = (AᵀA)⁻¹Aᵀb` is the global minimum of
//! `Σ|S + l_u u_k + l_f f_k − G_k|²` with no initial guess and nothing to diverge. `AᵀA` is
//! 5×5 and a sum over samples, so the online form ([`online::OnlineArm3d`]) only accumulates
//! it.
//!
//! Eliminating `S` (the normal equations' first block row) leaves
//! `l_u (u_k − ū) + l_f (f_k − f̄) = G_k − Ḡ`: the lengths come from how the directions
//! *change* as the grip moves, which is why the wheel must turn.
//!
//! # Heading drift
//!
//! An IMU orientation filter has a drift-free inclination but its heading (rotation about
//! the vertical) drifts: the measured direction is `u_meas = R_z(ψ_u(t))·u`. To first order
//! `u = u_meas + ψ_u·h(u_meas)` with `h(v) = −e_z × v = (v_y, −v_x, 0)`, so with
//! `ψ_u(t) = ψ_u0 + ψ̇_u·t` the loop (1) gains the columns `h(u_k)`, `t_k·h(u_k)` (and the same
//! for the forearm) with coefficients `l_u ψ_u0`, `l_u ψ̇_u`: still linear
//! ([`HeadingModel`]). The batch solver then rotates the directions back by the estimated
//! heading exactly and solves again until the correction vanishes (the linearisation error
//! goes away; a few Newton passes).
//!
//! # Direction noise
//!
//! Noise in the directions is noise in the regressors (errors in variables): it inflates
//! the spread of `u_k − ū` and so shrinks the lengths. With white noise of mean square
//! angle `s` (estimated from the data's fourth differences, which cancel smooth motion),
//! `E[u_meas] = c·u` with `c = √(1 − s)` and `E[Σ|u_meas − c·u|²] = n·s`; subtracting `n·s`
//! from the `u` diagonal of `AᵀA` and multiplying the fitted coefficient by `c` removes the
//! bias ([`ArmLoopOptions::errors_in_variables`]).

mod batch;
pub mod online;
mod solve;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::CalibError;
pub use online::{OnlineArm3d, OnlineArm3dOptions};

/// Smallest number of samples a fit accepts (and at least one more than the unknowns / 3).
pub const MIN_SAMPLES: usize = 10;

/// Largest deviation of a direction's norm from 1 that is accepted.
pub const UNIT_TOLERANCE: f64 = 1e-6;

/// Condition number (column-equilibrated) above which the estimate is flagged.
pub const MAX_CONDITION_NUMBER: f64 = 200.0;

/// Condition number above which the data do not determine the parameters at all (an error).
pub const SINGULAR_CONDITION_NUMBER: f64 = 1e10;

/// Relative standard error of a length above which it is flagged.
pub const MAX_RELATIVE_STD_ERROR: f64 = 0.02;

/// RMS distance of the grip from its mean position below which the motion is flagged (m):
/// a 0.14 m rim turned ±25°.
pub const MIN_GRIP_SPREAD_M: f64 = 0.04;

/// Heading offset above which the IMU filters are flagged (rad): 5°.
pub const MAX_HEADING_OFFSET_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// The heading re-rotation stops when its correction falls below this (rad; 1e-10 rad moves a
/// 0.3 m segment's end by 3e-11 m), or when the next correction predicted from the last two
/// is. The passes are Newton steps (the loop's curvature in the heading added, `batch`) and
/// converge quadratically: 3 passes on 1° of white noise with drift, where the Gauss–Newton
/// passes alone shrank the correction only ×0.1 per pass.
pub const HEADING_TOLERANCE_RAD: f64 = 1e-10;

/// The remedy for poorly excited parameters.
pub const ASK_FOR_MOTION: &str = "turn the wheel further (±50–60°), left and right";

/// How the heading (rotation about the vertical) of the measured directions may be wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HeadingModel {
    /// Directions are taken as measured: five unknowns.
    Exact,
    /// A constant heading offset per segment: seven unknowns.
    Offset,
    /// An offset and a constant drift rate per segment: nine unknowns. The drift is per second
    /// with `time_s`, else per sample.
    #[default]
    OffsetAndDrift,
}

impl HeadingModel {
    /// Number of unknowns.
    pub fn unknowns(self) -> usize {
        match self {
            Self::Exact => 5,
            Self::Offset => 7,
            Self::OffsetAndDrift => 9,
        }
    }

    /// The name used in the Python API and reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::Offset => "offset",
            Self::OffsetAndDrift => "offset_and_drift",
        }
    }
}

/// A recording for [`calibrate_arm_3d`]: per sample, the upper-arm and forearm unit
/// directions (shoulder → elbow and elbow → grip, wheel frame) and the grip point (m, wheel
/// frame) at the measured wheel angle.
#[derive(Debug, Clone, Copy)]
pub struct ArmLoopSamples<'a> {
    /// Upper-arm unit directions `u_k` (wheel frame).
    pub upper_dirs: &'a [[f64; 3]],
    /// Forearm unit directions `f_k` (wheel frame).
    pub fore_dirs: &'a [[f64; 3]],
    /// Grip points `G(θ_k)` (m, wheel frame), e.g. `ArmGeometry::grip(θ_k)` of `gyro_imu`.
    pub grip_points_m: &'a [[f64; 3]],
    /// Sample times (s), used by [`HeadingModel::OffsetAndDrift`] (without them the drift is
    /// per sample).
    pub time_s: Option<&'a [f64]>,
}

impl<'a> ArmLoopSamples<'a> {
    /// Samples without timestamps.
    pub fn new(
        upper_dirs: &'a [[f64; 3]],
        fore_dirs: &'a [[f64; 3]],
        grip_points_m: &'a [[f64; 3]],
    ) -> Self {
        Self {
            upper_dirs,
            fore_dirs,
            grip_points_m,
            time_s: None,
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.upper_dirs.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.upper_dirs.is_empty()
    }

    /// Check lengths, finiteness and unit norms, naming the offending argument and index.
    pub fn validate(&self) -> Result<(), CalibError> {
        let n = self.upper_dirs.len();
        for (argument, len) in [
            ("fore_dirs", self.fore_dirs.len()),
            ("grip_points_m", self.grip_points_m.len()),
            ("time_s", self.time_s.map_or(n, <[f64]>::len)),
        ] {
            if len != n {
                return Err(CalibError::LengthMismatch {
                    argument,
                    got: len,
                    expected: n,
                    reference: "upper_dirs",
                });
            }
        }
        if n < MIN_SAMPLES {
            return Err(CalibError::TooFewSamples {
                argument: "upper_dirs",
                got: n,
                needed: MIN_SAMPLES,
            });
        }
        check_vectors("upper_dirs", self.upper_dirs, true)?;
        check_vectors("fore_dirs", self.fore_dirs, true)?;
        check_vectors("grip_points_m", self.grip_points_m, false)?;
        if let Some(t) = self.time_s {
            crate::error::check_finite("time_s", t)?;
        }
        Ok(())
    }
}

/// Check finiteness (and unit norm when `unit`) of 3-vectors.
fn check_vectors(argument: &'static str, v: &[[f64; 3]], unit: bool) -> Result<(), CalibError> {
    for (index, x) in v.iter().enumerate() {
        check_vector(argument, index, x, unit)?;
    }
    Ok(())
}

pub(crate) fn check_vector(
    argument: &'static str,
    index: usize,
    x: &[f64; 3],
    unit: bool,
) -> Result<(), CalibError> {
    if !x.iter().all(|c| c.is_finite()) {
        return Err(CalibError::NonFinite { argument, index });
    }
    if unit {
        let norm = Vector3::from(*x).norm();
        if (norm - 1.0).abs() > UNIT_TOLERANCE {
            return Err(CalibError::NotUnitVector {
                argument,
                index,
                norm,
            });
        }
    }
    Ok(())
}

/// Options of [`calibrate_arm_3d`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ArmLoopOptions {
    /// Which heading errors of the directions to estimate alongside.
    pub heading: HeadingModel,
    /// Estimate the white direction noise from the data and remove the length bias it causes.
    /// Exact data give the same answer with or without it.
    pub errors_in_variables: bool,
    /// Passes of the exact heading re-rotation (with a heading model), 1..=50; stops earlier
    /// when the correction is below [`HEADING_TOLERANCE_RAD`].
    pub max_iterations: u32,
}

impl Default for ArmLoopOptions {
    fn default() -> Self {
        Self {
            heading: HeadingModel::OffsetAndDrift,
            errors_in_variables: true,
            max_iterations: 20,
        }
    }
}

impl ArmLoopOptions {
    /// Check every field, naming the one out of range.
    pub fn validate(&self) -> Result<(), CalibError> {
        if !(1..=50).contains(&self.max_iterations) {
            return Err(CalibError::OutOfRange {
                argument: "max_iterations",
                value: self.max_iterations as f64,
                allowed: "1..=50",
            });
        }
        Ok(())
    }
}

/// The arm's parameters (m, rad, wheel frame).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Arm3dParams {
    /// Shoulder joint centre `S` (m, wheel frame).
    pub shoulder_m: [f64; 3],
    /// Shoulder-to-elbow length `l_u` (m).
    pub upper_arm_m: f64,
    /// Elbow-to-grip length `l_f` (m).
    pub forearm_m: f64,
    /// Heading error of the measured directions at the first sample, `[upper, fore]` (rad,
    /// positive = measured turned counter-clockwise seen from above); 0 when not estimated.
    pub heading_offset_rad: [f64; 2],
    /// Heading drift rate `[upper, fore]` (rad/s, or rad/sample without `time_s`); 0 when not
    /// estimated.
    pub heading_drift_rad_s: [f64; 2],
}

/// Standard errors (1σ) of the estimate, in the parameters' units; `None` where not estimated.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Arm3dStdErrors {
    /// Shoulder position (m).
    pub shoulder_m: [f64; 3],
    /// Upper arm (m).
    pub upper_arm_m: f64,
    /// Forearm (m).
    pub forearm_m: f64,
    /// Heading offsets (rad).
    pub heading_offset_rad: Option<[f64; 2]>,
    /// Heading drift rates (rad/s).
    pub heading_drift_rad_s: Option<[f64; 2]>,
}

/// A calibrated arm and how far to trust it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Arm3dCalibration {
    /// The estimate.
    pub params: Arm3dParams,
    /// `"batch"` or `"online"`.
    pub method: &'static str,
    /// The heading model fitted.
    pub heading: HeadingModel,
    /// Exact heading re-rotation passes run (0: the closed form alone, no heading model).
    pub iterations: u32,
    /// Whether the heading passes met their tolerance (always true for the closed form).
    pub converged: bool,
    /// RMS loop-closure residual `|S + l_u u + l_f f − G|` per sample (m).
    pub rms_residual_m: f64,
    /// 1σ standard errors from the covariance `σ²(AᵀA)⁻¹`, `σ² = SSR / (3n − p)`. They assume
    /// independent samples: with noise correlated in time (filtered IMU orientations) they
    /// are optimistic.
    pub std_errors: Arm3dStdErrors,
    /// Condition number of the column-equilibrated `A` (identifiability; < 200 is good).
    pub condition_number: f64,
    /// RMS white direction noise estimated from the data, `[upper, fore]` (rad).
    pub direction_noise_rad: [f64; 2],
    /// RMS distance of the grip points from their mean (m): how far the wheel turned.
    pub grip_spread_m: f64,
    /// Samples (batch) or effective samples under forgetting (online).
    pub samples: f64,
    /// Human-readable warnings, each with the remedy.
    pub warnings: Vec<String>,
}

/// Calibrate the arm from one recording: shoulder position and segment lengths (and the
/// heading errors of the directions when `options.heading` asks for them).
///
/// # Example
///
/// ```
/// use calib::arm3d::{ArmLoopOptions, ArmLoopSamples, calibrate_arm_3d};
/// // a made-up arm: shoulder (-0.4, -0.2, 0.25), upper arm 0.3 m, forearm 0.33 m
/// let (s, lu, lf) = ([-0.4, -0.2, 0.25], 0.3, 0.33);
/// let (mut u, mut f, mut g) = (vec![], vec![], vec![]);
/// for k in 0..50 {
///     let a = 0.05 * k as f64;
///     let ud = [0.6 * a.cos(), 0.6 * a.sin(), -0.8];
///     let fd = [0.8, 0.6 * a.cos(), 0.6 * a.sin()];
///     g.push(std::array::from_fn(|i| s[i] + lu * ud[i] + lf * fd[i]));
///     u.push(ud);
///     f.push(fd);
/// }
/// let cal = calibrate_arm_3d(&ArmLoopSamples::new(&u, &f, &g), &ArmLoopOptions::default())?;
/// assert!((cal.params.upper_arm_m - 0.3).abs() < 1e-9);
/// assert!((cal.params.forearm_m - 0.33).abs() < 1e-9);
/// # Ok::<(), calib::CalibError>(())
/// ```
pub fn calibrate_arm_3d(
    samples: &ArmLoopSamples<'_>,
    options: &ArmLoopOptions,
) -> Result<Arm3dCalibration, CalibError> {
    samples.validate()?;
    options.validate()?;
    let model = options.heading;
    let n = samples.len();
    let p = model.unknowns();
    // Times (the sample index without `time_s`) relative to their mean keep the drift
    // columns well scaled; the offset is moved back to the first sample at the end.
    let t_mean = samples
        .time_s
        .map_or((n - 1) as f64 / 2.0, |t| t.iter().sum::<f64>() / n as f64);
    let time = |k: usize| samples.time_s.map_or(k as f64, |t| t[k]) - t_mean;
    let noise2 = if options.errors_in_variables {
        [
            solve::fourth_difference_noise(samples.upper_dirs),
            solve::fourth_difference_noise(samples.fore_dirs),
        ]
    } else {
        [0.0; 2]
    };
    // Heading of each segment (rad) at t − t_mean = 0, and its rate, accumulated over passes.
    let mut heading = batch::Heading::default();
    // evenly spaced samples let the passes turn the directions with a product per sample
    let dt = samples
        .time_s
        .map_or(Some(1.0), crate::fourbar::trig::uniform_step);
    let turn = p > 5;
    let passes = if p == 5 { 1 } else { options.max_iterations };
    let mut converged = p == 5;
    let mut iterations = 0;
    let mut last = None;
    let mut last_step: Option<f64> = None;
    for _ in 0..passes {
        let sums = batch::Sums::pass(
            samples.upper_dirs,
            samples.fore_dirs,
            samples.grip_points_m,
            time,
            dt,
            &heading,
            turn,
        );
        let normal = sums.normal();
        let sol = normal.solve(p, noise2)?;
        if p == 5 {
            last = Some((normal, sol));
            break;
        }
        iterations += 1;
        // The step: Newton's (the heading's curvature at this pass's own shoulder and
        // lengths) where that curvature keeps it definite.
        let newton_step = sums
            .newton_normal(batch::head(&sol.x), p)
            .and_then(|nm| nm.solve(p, noise2).ok());
        let newton = newton_step.is_some();
        if !newton {
            last_step = None;
        }
        let step = newton_step.unwrap_or(sol);
        // the heading columns' coefficients are l·δψ and l·δψ̇
        let (lu, lf) = (step.x[3], step.x[4]);
        let d = [step.x[5] / lu, step.x[6] / lf];
        let dr = if p == 9 {
            [step.x[7] / lu, step.x[8] / lf]
        } else {
            [0.0; 2]
        };
        for i in 0..2 {
            heading.psi[i] += d[i];
            heading.rate[i] += dr[i];
        }
        let step = d[0].abs().max(d[1].abs()) + 60.0 * dr[0].abs().max(dr[1].abs());
        last = Some((normal, sol));
        // Newton's steps shrink quadratically, `next ≈ C·step²` with `C` from the last two:
        // when that is below the tolerance the pass that would only confirm it is skipped
        // (this pass's linear heading terms already carry the update to O(step²))
        let next = last_step.map_or(f64::INFINITY, |ls: f64| step / (ls * ls) * step * step);
        last_step = newton.then_some(step);
        if step < HEADING_TOLERANCE_RAD || (step < 1e-4 && next < HEADING_TOLERANCE_RAD) {
            converged = true;
            break;
        }
    }
    let (normal, sol) = last.expect("at least one pass");
    let (psi, psi_dot) = (heading.psi, heading.rate);
    // exact loop residuals with the directions turned back by the final heading
    let ssr = batch::ssr(samples, time, dt, &heading, turn, batch::head(&sol.x));
    let t0 = time(0);
    let stats = normal.stats(&sol, p, ssr);
    let mut params = sol.params();
    params.heading_offset_rad = [psi[0] + psi_dot[0] * t0, psi[1] + psi_dot[1] * t0];
    params.heading_drift_rad_s = psi_dot;
    let mut cal = Arm3dCalibration {
        params,
        method: "batch",
        heading: model,
        iterations,
        converged,
        rms_residual_m: (ssr / n as f64).sqrt(),
        std_errors: stats.std_errors,
        condition_number: stats.condition_number,
        direction_noise_rad: [noise2[0].sqrt(), noise2[1].sqrt()],
        grip_spread_m: normal.grip_spread_m(),
        samples: n as f64,
        warnings: Vec::new(),
    };
    cal.warnings = warnings(&cal);
    if !converged {
        cal.warnings.push(format!(
            "the heading re-rotation stopped after {iterations} passes before converging; the \
             IMU headings are far off: re-zero them (hold still, wheel centred) and record again"
        ));
    }
    Ok(cal)
}

/// Warnings for a finished estimate, each with the remedy.
pub(crate) fn warnings(cal: &Arm3dCalibration) -> Vec<String> {
    let mut w = Vec::new();
    if cal.grip_spread_m < MIN_GRIP_SPREAD_M {
        w.push(format!(
            "the grip moved only {:.0} mm (RMS) about its mean, too little to separate the arm \
             segments; {ASK_FOR_MOTION}",
            cal.grip_spread_m * 1e3
        ));
    }
    if cal.condition_number > MAX_CONDITION_NUMBER {
        w.push(format!(
            "the motion excites the parameters poorly (condition number {:.0} > {:.0}); \
             {ASK_FOR_MOTION}",
            cal.condition_number, MAX_CONDITION_NUMBER
        ));
    }
    let p = &cal.params;
    for (name, value, se) in [
        ("upper arm", p.upper_arm_m, cal.std_errors.upper_arm_m),
        ("forearm", p.forearm_m, cal.std_errors.forearm_m),
    ] {
        if se.is_nan() || se > MAX_RELATIVE_STD_ERROR * value.abs() {
            w.push(format!(
                "the {name} length {:.1} mm is uncertain (standard error {:.1} mm); record a \
                 longer session or {ASK_FOR_MOTION}",
                value * 1e3,
                se * 1e3
            ));
        }
        if !(0.1..=0.7).contains(&value) {
            w.push(format!(
                "the {name} length {:.1} mm is not a human one; check that each IMU is on the \
                 segment it is assigned to and that the mounting calibration is current",
                value * 1e3
            ));
        }
    }
    for (name, psi) in [
        ("upper-arm", p.heading_offset_rad[0]),
        ("forearm", p.heading_offset_rad[1]),
    ] {
        if psi.abs() > MAX_HEADING_OFFSET_RAD {
            w.push(format!(
                "the {name} IMU heading is off by {:.1}° (estimated and removed); re-zero the IMU \
                 headings (hold still, wheel centred) before the next session",
                psi.to_degrees()
            ));
        }
    }
    w
}

#[cfg(test)]
mod tests;
