//! The global method: the loop of eq. 4.1 is linear in the complex constants
//! `a = l2·e^{iΘ2}`, `b = l3·e^{iΘ3}`, `c = l4·e^{iΘ4}` and the real `l1`:
//!
//! `a·e^{iφ2} + b·e^{iφ3} − c·e^{iφ4} − l1 = 0`  for every sample.
//!
//! With `z = [Re b, Im b, Re c, Im c, l1, Re a, Im a]` this is `M z = 0` (two real rows per
//! sample). The thesis's least-squares cost `Σ|ΔX|²` (eq. 4.3) equals `‖M z‖²`, so its global
//! minimum under the one non-linear constraint `|a| = l2` is found without any initial guess:
//! with the triangular factor `R` of `M` (a square-root information matrix),
//! `‖Mz‖² = ‖R_ww w + R_wa a‖² + ‖R_aa a‖²`, so `a = l2·v_min(R_aa)` (a 2×2 SVD) and
//! `w = −R_ww⁻¹ R_wa a`. The sign is fixed by `l1 > 0` (ground link along +x).
//!
//! The same factor, updated one sample at a time with exponential forgetting, is the online
//! estimator ([`super::online`]).

use nalgebra::{Matrix2, SMatrix, SVector, Vector2};

use super::model::{FourbarParams, FourbarSamples};
use crate::error::CalibError;

/// Number of real unknowns in `z`.
pub(crate) const NZ: usize = 7;

type Mat7 = SMatrix<f64, NZ, NZ>;

/// The two real rows of `M` for one sample: `[re; im]`.
pub(crate) fn sample_rows(phi2: f64, phi3: f64, phi4: f64) -> [[f64; NZ]; 2] {
    let (s2, c2) = phi2.sin_cos();
    let (s3, c3) = phi3.sin_cos();
    let (s4, c4) = phi4.sin_cos();
    [
        [c3, -s3, -c4, s4, -1.0, c2, -s2],
        [s3, c3, -s4, -c4, 0.0, s2, c2],
    ]
}

/// Square-root information `R` (upper triangular, `RᵀR = Σ λ^age MₖᵀMₖ`) of the linear loop
/// equations, with the effective (forgetting-weighted) number of samples.
#[derive(Debug, Clone)]
pub(crate) struct SqrtInfo {
    r: Mat7,
    /// Σ λ^age over the samples absorbed.
    pub n_eff: f64,
    /// Samples absorbed (not weighted).
    pub count: u64,
}

/// Samples folded into `R` per QR in batch mode.
const CHUNK: usize = 64;

impl SqrtInfo {
    pub(crate) fn new() -> Self {
        Self {
            r: Mat7::zeros(),
            n_eff: 0.0,
            count: 0,
        }
    }

    /// Absorb one sample after discounting the past by `forgetting` (λ ∈ (0, 1]).
    pub(crate) fn update(&mut self, phi2: f64, phi3: f64, phi4: f64, forgetting: f64) {
        let mut stacked = SMatrix::<f64, { NZ + 2 }, NZ>::zeros();
        stacked
            .fixed_view_mut::<NZ, NZ>(0, 0)
            .copy_from(&(self.r * forgetting.sqrt()));
        let rows = sample_rows(phi2, phi3, phi4);
        for (i, row) in rows.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                stacked[(NZ + i, j)] = *v;
            }
        }
        self.r = stacked.qr().r();
        self.n_eff = self.n_eff * forgetting + 1.0;
        self.count += 1;
    }

    /// Absorb a whole recording without forgetting (batch QR in chunks).
    pub(crate) fn from_samples(s: &FourbarSamples<'_>) -> Self {
        Self::from_weighted_samples(s, None)
    }

    /// As [`Self::from_samples`] with per-sample weights (rows scaled by √w).
    ///
    /// Fast path: accumulate the 7×7 normal matrix and take its Cholesky factor (the loop
    /// matrix is well scaled — every row has unit-modulus entries — so squaring its condition
    /// number costs little); if that factorisation fails or is nearly singular, fall back to a
    /// Householder QR of the rows themselves.
    pub(crate) fn from_weighted_samples(s: &FourbarSamples<'_>, weights: Option<&[f64]>) -> Self {
        let mut a = Mat7::zeros();
        for j in 0..s.len() {
            let w = weights.map_or(1.0, |w| w[j]);
            for row in sample_rows(s.phi2[j], s.phi3[j], s.phi4[j]) {
                for (c, vc) in row.iter().enumerate() {
                    let wc = w * vc;
                    for (d, vd) in row.iter().enumerate().take(c + 1) {
                        a[(c, d)] += wc * vd;
                    }
                }
            }
        }
        a.fill_upper_triangle_with_lower_triangle();
        let n_eff = weights.map_or(s.len() as f64, |w| w.iter().sum());
        let scale = a.diagonal().amax();
        let chol = a
            .cholesky()
            .filter(|c| c.l_dirty().diagonal().amin() > 1e-6 * scale.sqrt());
        let r = match chol {
            Some(c) => c.l().transpose(),
            None => Self::qr_factor(s, weights),
        };
        Self {
            r,
            n_eff,
            count: s.len() as u64,
        }
    }

    /// `R` by Householder QR of the stacked rows, in chunks.
    fn qr_factor(s: &FourbarSamples<'_>, weights: Option<&[f64]>) -> Mat7 {
        let mut r_acc = Mat7::zeros();
        let mut k = 0;
        while k < s.len() {
            let end = (k + CHUNK).min(s.len());
            let mut stacked = nalgebra::DMatrix::<f64>::zeros(NZ + 2 * (end - k), NZ);
            stacked.view_mut((0, 0), (NZ, NZ)).copy_from(&r_acc);
            for (i, j) in (k..end).enumerate() {
                let rows = sample_rows(s.phi2[j], s.phi3[j], s.phi4[j]);
                let sw = weights.map_or(1.0, |w| w[j].sqrt());
                for (h, row) in rows.iter().enumerate() {
                    for (c, v) in row.iter().enumerate() {
                        stacked[(NZ + 2 * i + h, c)] = *v * sw;
                    }
                }
            }
            let r = stacked.qr().r();
            r_acc.copy_from(&r.view((0, 0), (NZ, NZ)));
            k = end;
        }
        r_acc
    }

    /// The global least-squares solution for wheel radius `l2` (m): parameters and the
    /// minimum cost `Σ λ^age |ΔX|²` (m²).
    pub(crate) fn solve(&self, l2: f64) -> Result<(FourbarParams, f64), CalibError> {
        let r = &self.r;
        let scale = r.diagonal().amax();
        let r_ww = r.fixed_view::<5, 5>(0, 0).into_owned();
        let min_diag = r_ww.diagonal().abs().min();
        if scale.is_nan() || scale <= 0.0 || min_diag <= 1e-11 * scale {
            return Err(CalibError::NotIdentifiable {
                reason: "the arm angles barely changed, so forearm, upper-arm and ground links \
                         cannot be told apart; ask the patient for ±50–60° of wheel motion"
                    .into(),
            });
        }
        let r_wa = r.fixed_view::<5, 2>(0, 5).into_owned();
        let r_aa: Matrix2<f64> = r.fixed_view::<2, 2>(5, 5).into_owned();
        let svd = r_aa.svd(false, true);
        let v_t = svd.v_t.expect("requested V");
        let (imin, imax) = if svd.singular_values[0] <= svd.singular_values[1] {
            (0, 1)
        } else {
            (1, 0)
        };
        let (smin, smax) = (svd.singular_values[imin], svd.singular_values[imax]);
        if smax.is_nan() || smax <= 0.0 || smin >= smax * (1.0 - 1e-9) {
            return Err(CalibError::NotIdentifiable {
                reason: "the initial wheel angle Θ2 is not determined by these data; ask the \
                         patient for ±50–60° of wheel motion"
                    .into(),
            });
        }
        let mut a: Vector2<f64> = v_t.row(imin).transpose() * l2;
        let solve_w = |a: &Vector2<f64>| -> Option<SVector<f64, 5>> {
            r_ww.solve_upper_triangular(&(-(r_wa * a)))
        };
        let mut w = solve_w(&a).ok_or_else(|| CalibError::NotIdentifiable {
            reason: "singular loop equations".into(),
        })?;
        if w[4] < 0.0 {
            a = -a;
            w = -w;
        }
        let cost = (smin * l2).powi(2);
        let params = FourbarParams::from_vec8([
            w[4],
            w[0].hypot(w[1]),
            w[2].hypot(w[3]),
            a[1].atan2(a[0]),
            w[1].atan2(w[0]),
            w[3].atan2(w[2]),
            0.0,
            0.0,
        ]);
        Ok((params, cost))
    }

    /// Normal matrix `JᵀJ` of the six non-linear parameters `[l1, l3, l4, Θ2, Θ3, Θ4]` at `p`,
    /// through the chain rule `J = M·∂z/∂p`, so `JᵀJ = GᵀRᵀRG`.
    pub(crate) fn normal_matrix(&self, p: &FourbarParams, l2: f64) -> SMatrix<f64, 6, 6> {
        let mut g = SMatrix::<f64, NZ, 6>::zeros();
        let (s2, c2) = p.theta2_0_rad.sin_cos();
        let (s3, c3) = p.theta3_0_rad.sin_cos();
        let (s4, c4) = p.theta4_0_rad.sin_cos();
        g[(0, 1)] = c3;
        g[(0, 4)] = -p.l3_m * s3;
        g[(1, 1)] = s3;
        g[(1, 4)] = p.l3_m * c3;
        g[(2, 2)] = c4;
        g[(2, 5)] = -p.l4_m * s4;
        g[(3, 2)] = s4;
        g[(3, 5)] = p.l4_m * c4;
        g[(4, 0)] = 1.0;
        g[(5, 3)] = -l2 * s2;
        g[(6, 3)] = l2 * c2;
        let rg = self.r * g;
        rg.transpose() * rg
    }
}

/// Outlier-resistant global solution: the closed form re-solved with Cauchy weights
/// `1/(1 + (|ΔX|/c)²)`, `c = 2.385σ̂` from the median residual (iteratively reweighted least
/// squares, at most 30 rounds). Starts from the plain global solution, so still needs no
/// initial guess; gross outliers (a slipped gyro strap) lose their pull on the fit.
pub(crate) fn robust_global(s: &FourbarSamples<'_>, l2: f64) -> Result<FourbarParams, CalibError> {
    let (mut p, _) = SqrtInfo::from_samples(s).solve(l2)?;
    let mut w = vec![1.0; s.len()];
    for _ in 0..30 {
        let norms: Vec<f64> = (0..s.len())
            .map(|k| {
                let r = super::model::loop_residual(
                    [p.l1_m, l2, p.l3_m, p.l4_m],
                    p.theta2_0_rad + s.phi2[k],
                    p.theta3_0_rad + s.phi3[k],
                    p.theta4_0_rad + s.phi4[k],
                );
                r[0].hypot(r[1])
            })
            .collect();
        let mut sorted = norms.clone();
        let mid = sorted.len() / 2;
        let (_, median, _) = sorted.select_nth_unstable_by(mid, f64::total_cmp);
        let c = (2.385 * *median / 1.1774).max(1e-12 * l2);
        for (wk, r) in w.iter_mut().zip(&norms) {
            *wk = 1.0 / (1.0 + (r / c).powi(2));
        }
        let (next, _) = SqrtInfo::from_weighted_samples(s, Some(&w)).solve(l2)?;
        let change = (next.to_vec8().iter().zip(p.to_vec8()))
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        p = next;
        if change < 1e-12 {
            break;
        }
    }
    Ok(p)
}
