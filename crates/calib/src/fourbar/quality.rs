//! How far to trust a four-bar estimate: residual RMS, standard errors from the covariance
//! `σ²(JᵀJ)⁻¹`, the condition number of the column-equilibrated Jacobian, and warnings
//! with the remedy to suggest to the patient.

use nalgebra::DMatrix;

use super::model::FourbarParams;

/// Wheel motion below which the links are poorly excited (rad, peak to peak): ±50°.
pub const MIN_WHEEL_RANGE_RAD: f64 = 100.0 * std::f64::consts::PI / 180.0;

/// Condition number of the equilibrated Jacobian above which the estimate is flagged.
pub const MAX_CONDITION_NUMBER: f64 = 100.0;

/// Relative standard error of a length above which it is flagged.
pub const MAX_RELATIVE_STD_ERROR: f64 = 0.02;

/// Gyro bias above which the sensor is flagged (rad/s): 0.2°/s (the MG100's resolution is
/// 0.15°/s; 0.2°/s is 120° of drift in ten minutes).
pub const MAX_GYRO_BIAS_RAD_S: f64 = 0.2 * std::f64::consts::PI / 180.0;

/// The remedy for poorly excited parameters.
pub const ASK_FOR_MOTION: &str = "ask the patient for ±50–60° of wheel motion";

/// Standard errors (1σ) of the estimated parameters, in the parameters' units; `None` for a
/// parameter the method did not estimate.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct FourbarStdErrors {
    /// Ground link (m).
    pub l1_m: f64,
    /// Forearm (m).
    pub l3_m: f64,
    /// Upper arm (m).
    pub l4_m: f64,
    /// Θ2 (rad).
    pub theta2_0_rad: f64,
    /// Θ3 (rad).
    pub theta3_0_rad: f64,
    /// Θ4 (rad).
    pub theta4_0_rad: f64,
    /// Forearm gyro bias (same unit as the estimate).
    pub gyro_bias3: Option<f64>,
    /// Upper-arm gyro bias (same unit as the estimate).
    pub gyro_bias4: Option<f64>,
}

/// Statistics of a least-squares fit computed from its normal matrix.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FitStats {
    pub rms_residual_m: f64,
    pub std_errors: FourbarStdErrors,
    pub condition_number: f64,
}

/// `normal` = JᵀJ (6×6 or 8×8, order `[l1, l3, l4, Θ2, Θ3, Θ4, b3, b4]`), `ssr` = Σ|ΔX|² (m²),
/// `n_eff` = (weighted) number of samples, two equations each.
pub(crate) fn fit_stats(normal: &DMatrix<f64>, ssr: f64, n_eff: f64) -> FitStats {
    let p = normal.nrows();
    let dof = (2.0 * n_eff - p as f64).max(1.0);
    let sigma2 = ssr / dof;
    // Equilibrate columns: N_s = D⁻¹ N D⁻¹ with D = sqrt(diag N); cond(J_s) = sqrt(cond(N_s)).
    let d: Vec<f64> = (0..p)
        .map(|i| normal[(i, i)].max(f64::MIN_POSITIVE).sqrt())
        .collect();
    let scaled = DMatrix::from_fn(p, p, |i, j| normal[(i, j)] / (d[i] * d[j]));
    let eig = scaled.clone().symmetric_eigen();
    let (lo, hi) = eig
        .eigenvalues
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &e| {
            (lo.min(e), hi.max(e))
        });
    let condition_number = if lo > 0.0 {
        (hi / lo).sqrt()
    } else {
        f64::INFINITY
    };
    let var = match scaled.try_inverse() {
        Some(inv) => (0..p)
            .map(|i| sigma2 * inv[(i, i)] / (d[i] * d[i]))
            .collect::<Vec<_>>(),
        None => vec![f64::INFINITY; p],
    };
    let se = |i: usize| var[i].max(0.0).sqrt();
    FitStats {
        rms_residual_m: (ssr / n_eff.max(1.0)).sqrt(),
        std_errors: FourbarStdErrors {
            l1_m: se(0),
            l3_m: se(1),
            l4_m: se(2),
            theta2_0_rad: se(3),
            theta3_0_rad: se(4),
            theta4_0_rad: se(5),
            gyro_bias3: (p > 6).then(|| se(6)),
            gyro_bias4: (p > 7).then(|| se(7)),
        },
        condition_number,
    }
}

/// Warnings for a finished estimate. `wheel_range_rad` is `None` when unknown (online);
/// `bias_per_s` tells whether biases are in rad/s (timestamps given).
pub(crate) fn warnings(
    params: &FourbarParams,
    stats: &FitStats,
    wheel_range_rad: Option<f64>,
    bias_per_s: bool,
) -> Vec<String> {
    let mut w = Vec::new();
    if let Some(range) = wheel_range_rad
        && range < MIN_WHEEL_RANGE_RAD
    {
        w.push(format!(
            "the wheel moved only ±{:.0}°, too little to separate the arm links; {ASK_FOR_MOTION}",
            range.to_degrees() / 2.0
        ));
    }
    if stats.condition_number > MAX_CONDITION_NUMBER {
        w.push(format!(
            "the motion excites the parameters poorly (Jacobian condition number {:.0} > {:.0}); \
             {ASK_FOR_MOTION}",
            stats.condition_number, MAX_CONDITION_NUMBER
        ));
    }
    for (name, value, se) in [
        ("l1", params.l1_m, stats.std_errors.l1_m),
        ("l3", params.l3_m, stats.std_errors.l3_m),
        ("l4", params.l4_m, stats.std_errors.l4_m),
    ] {
        if se.is_nan() || se > MAX_RELATIVE_STD_ERROR * value.abs() {
            w.push(format!(
                "{name} = {:.1} mm is uncertain (standard error {:.1} mm); record a longer session \
                 or {ASK_FOR_MOTION}",
                value * 1e3,
                se * 1e3
            ));
        }
    }
    if bias_per_s {
        for (name, b) in [
            ("forearm", params.gyro_bias3),
            ("upper-arm", params.gyro_bias4),
        ] {
            if b.abs() > MAX_GYRO_BIAS_RAD_S {
                w.push(format!(
                    "the {name} gyro drifts by {:.2}°/s (estimated and removed); re-zero the gyros \
                     with the arm at rest before the next session",
                    b.to_degrees()
                ));
            }
        }
    }
    w
}
