//! Iterative refinements of the four-bar parameters: the thesis's Gauss–Newton (eq. 4.2–4.4,
//! kept as the reference) and a robust Levenberg–Marquardt with gyro-bias terms.

use nalgebra::{DMatrix, DVector};

use super::model::{FourbarSamples, residual_and_jacobian};
use crate::error::CalibError;

/// Normal equations of the (weighted) loop residuals at `p` over the first `np` parameters.
pub(crate) struct Normal {
    /// JᵀWJ (np × np).
    pub jtj: DMatrix<f64>,
    /// JᵀWr.
    pub jtr: DVector<f64>,
    /// Σ w·|r|² (m²), weighted.
    pub ssr: f64,
    /// Σ w (effective sample count).
    pub w_sum: f64,
    /// Σ ρ(|r|) with the Huber loss (m²); equals `ssr` without robust weighting.
    pub cost: f64,
    /// Fraction of samples down-weighted as outliers.
    pub outlier_fraction: f64,
}

/// Huber threshold: `None` = plain least squares.
pub(crate) type Huber = Option<f64>;

/// Huber loss ×2 (so it equals r² inside the threshold) and its IRLS weight.
fn huber(r: f64, c: Huber) -> (f64, f64) {
    match c {
        Some(c) if r > c => (2.0 * c * r - c * c, c / r),
        _ => (r * r, 1.0),
    }
}

pub(crate) fn normal_equations(
    p: &[f64; 8],
    np: usize,
    l2: f64,
    s: &FourbarSamples<'_>,
    huber_c: Huber,
) -> Normal {
    // fixed-size accumulators in the hot loop; the lower triangle only
    let mut a = [[0.0f64; 8]; 8];
    let mut g = [0.0f64; 8];
    let (mut ssr, mut w_sum, mut cost, mut outliers) = (0.0, 0.0, 0.0, 0usize);
    for k in 0..s.len() {
        let (r, dre, dim) = residual_and_jacobian(p, l2, s, k);
        let norm = r[0].hypot(r[1]);
        let (rho, w) = huber(norm, huber_c);
        if w < 1.0 {
            outliers += 1;
        }
        cost += rho;
        ssr += w * norm * norm;
        w_sum += w;
        for i in 0..np {
            let (wre, wim) = (w * dre[i], w * dim[i]);
            g[i] += wre * r[0] + wim * r[1];
            for j in 0..=i {
                a[i][j] += wre * dre[j] + wim * dim[j];
            }
        }
    }
    let jtj = DMatrix::from_fn(np, np, |i, j| if j <= i { a[i][j] } else { a[j][i] });
    let jtr = DVector::from_fn(np, |i, _| g[i]);
    Normal {
        jtj,
        jtr,
        ssr,
        w_sum,
        cost,
        outlier_fraction: outliers as f64 / s.len() as f64,
    }
}

/// Result of an iterative refinement.
pub(crate) struct Refined {
    pub p: [f64; 8],
    pub iterations: u32,
    pub converged: bool,
}

fn step_small(delta: &DVector<f64>, p: &[f64; 8], tol: f64) -> bool {
    delta
        .iter()
        .zip(p)
        .all(|(d, x)| d.abs() <= tol * (x.abs() + 1e-3))
}

/// The thesis's iterated least squares (eq. 4.4): undamped Gauss–Newton on
/// `[l1, l3, l4, Θ2, Θ3, Θ4]` from `p0`, stopping when the step is below `tol` (relative).
pub(crate) fn gauss_newton(
    p0: [f64; 8],
    l2: f64,
    s: &FourbarSamples<'_>,
    max_iterations: u32,
    tol: f64,
) -> Result<Refined, CalibError> {
    let mut p = p0;
    p[6] = 0.0;
    p[7] = 0.0;
    for it in 1..=max_iterations {
        let ne = normal_equations(&p, 6, l2, s, None);
        let delta = ne
            .jtj
            .clone()
            .cholesky()
            .map(|c| c.solve(&(-&ne.jtr)))
            .ok_or(CalibError::NotConverged {
                method: "thesis",
                iterations: it as usize,
                reason: "the calibration matrix ΦᵀΦ became singular",
            })?;
        for i in 0..6 {
            p[i] += delta[i];
        }
        if p.iter().any(|v| !v.is_finite()) || p[0].abs() > 1e6 * l2 {
            return Err(CalibError::NotConverged {
                method: "thesis",
                iterations: it as usize,
                reason: "the iteration diverged",
            });
        }
        if step_small(&delta, &p, tol) {
            return Ok(Refined {
                p,
                iterations: it,
                converged: true,
            });
        }
    }
    Err(CalibError::NotConverged {
        method: "thesis",
        iterations: max_iterations as usize,
        reason: "the step did not fall below the tolerance",
    })
}

/// Robust scale of the loop residuals: Huber threshold 2.5σ̂ with σ̂ from the median residual
/// norm (for a 2-D Gaussian residual the median norm is 1.1774σ).
pub(crate) fn huber_threshold(p: &[f64; 8], l2: f64, s: &FourbarSamples<'_>) -> f64 {
    let mut norms: Vec<f64> = (0..s.len())
        .map(|k| {
            let (r, _, _) = residual_and_jacobian(p, l2, s, k);
            r[0].hypot(r[1])
        })
        .collect();
    let mid = norms.len() / 2;
    let (_, median, _) = norms.select_nth_unstable_by(mid, f64::total_cmp);
    (2.5 * *median / 1.1774).max(1e-12 * l2)
}

/// Levenberg–Marquardt (Marquardt's diagonal scaling) on the first `np` parameters (6, or 8
/// with the gyro-bias terms), minimising the Huber loss with threshold `huber_c`.
pub(crate) fn levenberg_marquardt(
    p0: [f64; 8],
    np: usize,
    l2: f64,
    s: &FourbarSamples<'_>,
    huber_c: Huber,
    max_iterations: u32,
    tol: f64,
) -> Refined {
    let mut p = p0;
    for v in p.iter_mut().skip(np) {
        *v = 0.0;
    }
    let mut ne = normal_equations(&p, np, l2, s, huber_c);
    let mut mu = 1e-3;
    for it in 1..=max_iterations {
        let mut a = ne.jtj.clone();
        for i in 0..np {
            a[(i, i)] += mu * ne.jtj[(i, i)].max(1e-12);
        }
        let Some(delta) = a.cholesky().map(|c| c.solve(&(-&ne.jtr))) else {
            mu *= 10.0;
            continue;
        };
        let mut trial = p;
        for i in 0..np {
            trial[i] += delta[i];
        }
        let trial_ne = normal_equations(&trial, np, l2, s, huber_c);
        if trial_ne.cost.is_finite() && trial_ne.cost <= ne.cost {
            let done = step_small(&delta, &p, tol) || trial_ne.cost == 0.0;
            p = trial;
            ne = trial_ne;
            mu = (mu / 3.0).max(1e-12);
            if done {
                return Refined {
                    p,
                    iterations: it,
                    converged: true,
                };
            }
        } else {
            mu *= 4.0;
            if mu > 1e12 {
                // no decrease possible at any damping: a minimum to working precision
                return Refined {
                    p,
                    iterations: it,
                    converged: true,
                };
            }
        }
    }
    Refined {
        p,
        iterations: max_iterations,
        converged: false,
    }
}
