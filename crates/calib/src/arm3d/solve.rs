//! The normal equations of the arm loop (module docs, eq. (1)) and their solution.
//!
//! Unknowns, in order: `[S_x, S_y, S_z, l_u, l_f, l_u ψ_u, l_f ψ_f, l_u ψ̇_u, l_f ψ̇_f]`; a fit
//! with `p` unknowns uses the first `p`. One sample contributes the 3×P block
//! `A_k = [I₃ | u | f | h(u) | h(f) | t·h(u) | t·h(f)]` with `h(v) = (v_y, −v_x, 0)`.

use nalgebra::{SMatrix, SVector, Vector3};

use super::{Arm3dParams, Arm3dStdErrors, SINGULAR_CONDITION_NUMBER};
use crate::error::CalibError;

/// Largest number of unknowns.
pub(crate) const P_MAX: usize = 9;

/// `h(v) = −e_z × v`: the change of `v` per radian of heading turned back.
#[inline]
fn h(v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.y, -v.x, 0.0)
}

/// Weighted sums `AᵀA`, `Aᵀb`, `bᵀb` and `Σw` of the first `P` columns (P = 5, 7 or 9).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Normal<const P: usize> {
    pub m: SMatrix<f64, P, P>,
    pub v: SVector<f64, P>,
    pub gg: f64,
    pub w_sum: f64,
}

/// A solution of the (corrected) normal equations.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Solution {
    /// Raw coefficients (the lengths before the errors-in-variables scale `c`); 0 beyond `p`.
    pub x: SVector<f64, P_MAX>,
    /// `c = √(1 − s)` per segment (1 without the correction).
    pub c: [f64; 2],
    /// Diagonal of the inverse of the solved matrix (per unit σ²).
    pub inv_diag: SVector<f64, P_MAX>,
    /// Condition number of the column-equilibrated `A` (over the unknowns solved for).
    pub condition_number: f64,
}

/// Statistics of a fit.
pub(crate) struct Stats {
    pub std_errors: Arm3dStdErrors,
    pub condition_number: f64,
}

impl<const P: usize> Normal<P> {
    pub fn new() -> Self {
        Self {
            m: SMatrix::zeros(),
            v: SVector::zeros(),
            gg: 0.0,
            w_sum: 0.0,
        }
    }

    /// Scale the sums by the forgetting factor `lambda`, then add one sample with weight 1.
    /// Allocation-free and O(P²).
    #[inline]
    pub fn add(
        &mut self,
        u: &Vector3<f64>,
        f: &Vector3<f64>,
        g: &Vector3<f64>,
        t: f64,
        lambda: f64,
    ) {
        let mut a = SMatrix::<f64, 3, P>::zeros();
        a[(0, 0)] = 1.0;
        a[(1, 1)] = 1.0;
        a[(2, 2)] = 1.0;
        a.set_column(3, u);
        a.set_column(4, f);
        if P >= 7 {
            let (hu, hf) = (h(u), h(f));
            a.set_column(5, &hu);
            a.set_column(6, &hf);
            if P >= 9 {
                a.set_column(7, &(hu * t));
                a.set_column(8, &(hf * t));
            }
        }
        if lambda == 1.0 {
            self.m += a.tr_mul(&a);
            self.v += a.tr_mul(g);
            self.gg += g.norm_squared();
            self.w_sum += 1.0;
        } else {
            self.m = self.m * lambda + a.tr_mul(&a);
            self.v = self.v * lambda + a.tr_mul(g);
            self.gg = self.gg * lambda + g.norm_squared();
            self.w_sum = self.w_sum * lambda + 1.0;
        }
    }

    /// RMS distance of the grip points from their (weighted) mean (m).
    pub fn grip_spread_m(&self) -> f64 {
        if self.w_sum <= 0.0 {
            return 0.0;
        }
        let mean = Vector3::new(self.v[0], self.v[1], self.v[2]) / self.w_sum;
        (self.gg / self.w_sum - mean.norm_squared()).max(0.0).sqrt()
    }

    /// Solve for the first `p` unknowns (the rest are 0). `noise2 = [s_u, s_f]` are the mean
    /// square white direction noises to correct for (0 = no correction).
    pub fn solve(&self, p: usize, noise2: [f64; 2]) -> Result<Solution, CalibError> {
        let p = p.min(P);
        // padded to P_MAX unknowns: identity rows and zero right-hand side beyond `p`
        let mut m = SMatrix::<f64, P_MAX, P_MAX>::identity();
        let mut v = SVector::<f64, P_MAX>::zeros();
        m.view_mut((0, 0), (p, p))
            .copy_from(&self.m.view((0, 0), (p, p)));
        v.rows_mut(0, p).copy_from(&self.v.rows(0, p));
        // errors in variables: remove the noise's share of Σ|u|² (see the module docs)
        m[(3, 3)] -= self.w_sum * noise2[0];
        m[(4, 4)] -= self.w_sum * noise2[1];
        let not_identifiable = |why: String| CalibError::NotIdentifiable {
            reason: format!(
                "{why}: the arm directions did not change enough while the grip moved; {}",
                super::ASK_FOR_MOTION
            ),
        };
        let d = SVector::<f64, P_MAX>::from_fn(|i, _| m[(i, i)].max(0.0).sqrt());
        if let Some(i) = d.iter().position(|x| x.is_nan() || *x <= 0.0) {
            return Err(not_identifiable(format!(
                "column {i} of the loop equations is zero"
            )));
        }
        let scaled = SMatrix::<f64, P_MAX, P_MAX>::from_fn(|i, j| m[(i, j)] / (d[i] * d[j]));
        let eig = scaled.symmetric_eigenvalues();
        let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &e| {
            (lo.min(e), hi.max(e))
        });
        let condition_number = if lo > 0.0 {
            (hi / lo).sqrt()
        } else {
            f64::INFINITY
        };
        if condition_number.is_nan() || condition_number >= SINGULAR_CONDITION_NUMBER {
            return Err(not_identifiable(format!(
                "condition number {condition_number:.3e}"
            )));
        }
        let chol = scaled
            .cholesky()
            .ok_or_else(|| not_identifiable("the normal matrix is not positive definite".into()))?;
        let rhs = v.component_div(&d);
        let x = chol.solve(&rhs).component_div(&d);
        let inv = chol.inverse();
        let inv_diag = SVector::<f64, P_MAX>::from_fn(|i, _| inv[(i, i)] / (d[i] * d[i]));
        let c = [
            (1.0 - noise2[0]).max(0.0).sqrt(),
            (1.0 - noise2[1]).max(0.0).sqrt(),
        ];
        Ok(Solution {
            x,
            c,
            inv_diag,
            condition_number,
        })
    }

    /// The sum of squared residuals at `x` from the sums alone (online; clamped at 0).
    pub fn ssr_at(&self, x: &SVector<f64, P_MAX>) -> f64 {
        let x = x.fixed_rows::<P>(0);
        (self.gg - 2.0 * x.dot(&self.v) + (self.m * x).dot(&x)).max(0.0)
    }

    /// Standard errors and conditioning of a fit of `p` unknowns with residual sum `ssr`.
    pub fn stats(&self, sol: &Solution, p: usize, ssr: f64) -> Stats {
        let dof = (3.0 * self.w_sum - p as f64).max(1.0);
        let sigma2 = ssr / dof;
        let se = |i: usize| (sigma2 * sol.inv_diag[i]).max(0.0).sqrt();
        let (lu, lf) = (sol.x[3], sol.x[4]);
        let pair = |i: usize| [se(i) / lu.abs(), se(i + 1) / lf.abs()];
        Stats {
            std_errors: Arm3dStdErrors {
                shoulder_m: [se(0), se(1), se(2)],
                upper_arm_m: se(3) * sol.c[0],
                forearm_m: se(4) * sol.c[1],
                heading_offset_rad: (p >= 7).then(|| pair(5)),
                heading_drift_rad_s: (p >= 9).then(|| pair(7)),
            },
            condition_number: sol.condition_number,
        }
    }
}

impl Solution {
    /// Shoulder and lengths (the heading fields are left at 0 for the caller).
    pub fn params(&self) -> Arm3dParams {
        Arm3dParams {
            shoulder_m: [self.x[0], self.x[1], self.x[2]],
            upper_arm_m: self.x[3] * self.c[0],
            forearm_m: self.x[4] * self.c[1],
            ..Arm3dParams::default()
        }
    }
}

/// Coefficients of the fourth difference `v_k − 4v_{k+1} + 6v_{k+2} − 4v_{k+3} + v_{k+4}`;
/// their squares sum to 70.
pub(crate) const FOURTH_DIFFERENCE: [f64; 5] = [1.0, -4.0, 6.0, -4.0, 1.0];

/// Mean square white noise `E|e|²` of unit directions, from their fourth differences (which
/// cancel smooth motion to O(dt⁴)): `E|Δ⁴e|² = 70·E|e|²`. 0 for fewer than 5 samples.
pub(crate) fn fourth_difference_noise(dirs: &[[f64; 3]]) -> f64 {
    if dirs.len() < 5 {
        return 0.0;
    }
    let sum: f64 = dirs
        .windows(5)
        .map(|w| {
            let mut d = Vector3::zeros();
            for (c, v) in FOURTH_DIFFERENCE.iter().zip(w) {
                d += Vector3::from(*v) * *c;
            }
            d.norm_squared()
        })
        .sum();
    sum / (70.0 * (dirs.len() - 4) as f64)
}
