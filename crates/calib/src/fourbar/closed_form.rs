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

use super::eiv::Gains;
use super::model::{FourbarParams, FourbarSamples};
use super::trig::Trig;
use crate::error::CalibError;

/// Number of real unknowns in `z`.
pub(crate) const NZ: usize = 7;

pub(crate) type Mat7 = SMatrix<f64, NZ, NZ>;

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

    /// Absorb a whole recording without forgetting.
    pub(crate) fn from_samples(s: &FourbarSamples<'_>, trig: &Trig) -> Self {
        Self::from_gram(s, trig, None)
    }

    /// `R` of the (per-sample weighted) loop equations.
    ///
    /// Fast path: the 7×7 normal matrix from [`gram`] and its Cholesky factor (the loop matrix
    /// is well scaled — every row has unit-modulus entries — so squaring its condition number
    /// costs little); if that factorisation fails or is nearly singular, fall back to a
    /// Householder QR of the rows themselves.
    pub(crate) fn from_gram(s: &FourbarSamples<'_>, trig: &Trig, weights: Option<&[f64]>) -> Self {
        let a = gram(trig, weights, None);
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
        Ok((params_from_z(&w, &a), cost))
    }

    /// Normal matrix `JᵀJ` of the six non-linear parameters `[l1, l3, l4, Θ2, Θ3, Θ4]` at `p`,
    /// through the chain rule `J = M·∂z/∂p`, so `JᵀJ = GᵀRᵀRG`.
    pub(crate) fn normal_matrix(&self, p: &FourbarParams, l2: f64) -> SMatrix<f64, 6, 6> {
        let rg = self.r * dz_dp(&p.to_vec8(), l2);
        rg.transpose() * rg
    }
}

/// The linear unknowns `z = [Re b, Im b, Re c, Im c, l1, Re a, Im a]` at parameters
/// `p = [l1, l3, l4, Θ2, Θ3, Θ4, …]` (eq. 4.1 with `a = l2·e^{iΘ2}`, `b = l3·e^{iΘ3}`,
/// `c = l4·e^{iΘ4}`).
pub(crate) fn z_of(p: &[f64; 8], l2: f64) -> SVector<f64, NZ> {
    let (s2, c2) = p[3].sin_cos();
    let (s3, c3) = p[4].sin_cos();
    let (s4, c4) = p[5].sin_cos();
    SVector::<f64, NZ>::from([
        p[1] * c3,
        p[1] * s3,
        p[2] * c4,
        p[2] * s4,
        p[0],
        l2 * c2,
        l2 * s2,
    ])
}

/// `∂z/∂p` (7×6) for `p = [l1, l3, l4, Θ2, Θ3, Θ4]`.
pub(crate) fn dz_dp(p: &[f64; 8], l2: f64) -> SMatrix<f64, NZ, 6> {
    let mut g = SMatrix::<f64, NZ, 6>::zeros();
    let (s2, c2) = p[3].sin_cos();
    let (s3, c3) = p[4].sin_cos();
    let (s4, c4) = p[5].sin_cos();
    g[(0, 1)] = c3;
    g[(0, 4)] = -p[1] * s3;
    g[(1, 1)] = s3;
    g[(1, 4)] = p[1] * c3;
    g[(2, 2)] = c4;
    g[(2, 5)] = -p[2] * s4;
    g[(3, 2)] = s4;
    g[(3, 5)] = p[2] * c4;
    g[(4, 0)] = 1.0;
    g[(5, 3)] = -l2 * s2;
    g[(6, 3)] = l2 * c2;
    g
}

fn params_from_z(w: &SVector<f64, 5>, a: &Vector2<f64>) -> FourbarParams {
    FourbarParams::from_vec8([
        w[4],
        w[0].hypot(w[1]),
        w[2].hypot(w[3]),
        a[1].atan2(a[0]),
        w[1].atan2(w[0]),
        w[3].atan2(w[2]),
        0.0,
        0.0,
    ])
}

/// The normal matrix `H` (7×7) of the loop equations `M z = 0`, per-sample weighted by
/// `weights` and, with `gains`, bias-corrected for angle noise ([`super::eiv`]): each unit
/// vector `e^{iφⱼ}` scaled by its gain `gⱼ`, and the diagonal blocks put back to `Σw`, which is
/// what `Σ w·|gⱼe^{iφⱼ}|² − Σ w·(gⱼ² − 1)` equals. `zᵀHz` is the (corrected) cost of eq. 4.3.
///
/// One pass over the samples with 13 running sums: every 2×2 block between two links is
/// `[[Re w, Im w], [−Im w, Re w]]` with `w = Σ uᵢ·conj(uⱼ)` (`u = e^{iφ3}, −e^{iφ4}, e^{iφ2}`).
pub(crate) fn gram(trig: &Trig, weights: Option<&[f64]>, gains: Option<&Gains>) -> Mat7 {
    let n = trig.len();
    // [Σw, Σ w·u_b (re, im), Σ w·u_c, Σ w·u_a, w_bc, w_ba, w_ca]
    let mut acc = [0.0f64; 13];
    for k in 0..n {
        let w = weights.map_or(1.0, |w| w[k]);
        let (g2, g3, g4) = gains.map_or((1.0, 1.0, 1.0), |g| (g.g2[k], g.g3[k], g.g4[k]));
        let (c2, s2) = (trig.c2[k], trig.s2[k]);
        let (c3, s3) = (trig.c3[k], trig.s3[k]);
        let (c4, s4) = (trig.c4[k], trig.s4[k]);
        let (w2, w3, w4) = (w * g2, w * g3, w * g4);
        acc[0] += w;
        acc[1] += w3 * c3;
        acc[2] += w3 * s3;
        acc[3] += w4 * c4;
        acc[4] += w4 * s4;
        acc[5] += w2 * c2;
        acc[6] += w2 * s2;
        let w34 = w3 * g4;
        acc[7] += w34 * (c3 * c4 + s3 * s4);
        acc[8] += w34 * (s3 * c4 - c3 * s4);
        let w32 = w3 * g2;
        acc[9] += w32 * (c3 * c2 + s3 * s2);
        acc[10] += w32 * (s3 * c2 - c3 * s2);
        let w42 = w4 * g2;
        acc[11] += w42 * (c4 * c2 + s4 * s2);
        acc[12] += w42 * (s4 * c2 - c4 * s2);
    }
    let mut h = Mat7::zeros();
    for i in [0, 1, 2, 3, 4, 5, 6] {
        h[(i, i)] = acc[0];
    }
    // l1 couples to each link through −Re(x·u): (l1, Re x) = −Σ Re u, (l1, Im x) = Σ Im u
    let l1_row = [
        (0, -acc[1]),
        (1, acc[2]),
        (2, acc[3]),
        (3, -acc[4]),
        (5, -acc[5]),
        (6, acc[6]),
    ];
    for (j, v) in l1_row {
        h[(4, j)] = v;
        h[(j, 4)] = v;
    }
    // pairs (b, c): u_b·conj(u_c) = −e^{i(φ3−φ4)}; (b, a): e^{i(φ3−φ2)}; (c, a): −e^{i(φ4−φ2)}
    for (i, j, wr, wi) in [
        (0, 2, -acc[7], -acc[8]),
        (0, 5, acc[9], acc[10]),
        (2, 5, -acc[11], -acc[12]),
    ] {
        let block = [[wr, wi], [-wi, wr]];
        for (di, row) in block.iter().enumerate() {
            for (dj, v) in row.iter().enumerate() {
                h[(i + di, j + dj)] = *v;
                h[(j + dj, i + di)] = *v;
            }
        }
    }
    h
}

/// The global minimiser of `zᵀHz` under `|a| = l2` for a symmetric `H` that need not be
/// positive definite (a bias-corrected normal matrix): Schur complement of the 5×5 block of
/// `[b, c, l1]` (which must be positive definite) and the 2×2 eigenvector of its smallest
/// eigenvalue. Returns the parameters and the minimum cost.
pub(crate) fn solve_gram(h: &Mat7, l2: f64) -> Result<(FourbarParams, f64), CalibError> {
    let not_identifiable = || CalibError::NotIdentifiable {
        reason: "the arm angles barely changed, so forearm, upper-arm and ground links \
                 cannot be told apart; ask the patient for ±50–60° of wheel motion"
            .into(),
    };
    let h_ww = h.fixed_view::<5, 5>(0, 0).into_owned();
    let h_wa = h.fixed_view::<5, 2>(0, 5).into_owned();
    let scale = h_ww.diagonal().amax();
    let chol = h_ww
        .cholesky()
        .filter(|c| scale > 0.0 && c.l_dirty().diagonal().amin() > 1e-6 * scale.sqrt())
        .ok_or_else(not_identifiable)?;
    let x = chol.solve(&h_wa); // H_ww⁻¹ H_wa
    let s: Matrix2<f64> = h.fixed_view::<2, 2>(5, 5).into_owned() - h_wa.transpose() * x;
    let s = (s + s.transpose()) * 0.5;
    let eig = s.symmetric_eigen();
    let (imin, imax) = if eig.eigenvalues[0] <= eig.eigenvalues[1] {
        (0, 1)
    } else {
        (1, 0)
    };
    let (emin, emax) = (eig.eigenvalues[imin], eig.eigenvalues[imax]);
    let gap = emax - emin;
    if gap.is_nan() || gap <= 1e-9 * emax.abs().max(f64::MIN_POSITIVE) {
        return Err(CalibError::NotIdentifiable {
            reason: "the initial wheel angle Θ2 is not determined by these data; ask the \
                     patient for ±50–60° of wheel motion"
                .into(),
        });
    }
    let mut a: Vector2<f64> = eig.eigenvectors.column(imin) * l2;
    let mut w = -(x * a);
    if w[4] < 0.0 {
        a = -a;
        w = -w;
    }
    Ok((params_from_z(&w, &a), emin * l2 * l2))
}
