//! Iterative refinements of the four-bar parameters: the thesis's Gauss–Newton (eq. 4.2–4.4,
//! kept as the reference) and a Levenberg–Marquardt with gyro-bias terms, per-sample weights
//! (noise and Huber) and the errors-in-variables correction of [`super::eiv`].
//!
//! Without bias terms the cost of eq. 4.3 is the quadratic form `z(p)ᵀ H z(p)` of the 7×7
//! normal matrix `H` of the loop equations ([`super::closed_form::gram`]), so the iterations
//! never touch the samples again: `J = M·∂z/∂p` gives `JᵀJ = GᵀHG` and `Jᵀr = GᵀHz` exactly
//! (one pass over the data builds `H`; each iteration is a 6×6 solve). With bias terms
//! `θj = Θj + φj − bj·t` the samples no longer factor out, and each iteration is one pass that
//! accumulates the 8×8 `JᵀWJ` and `JᵀWr` sample by sample (no Jacobian matrix, no allocation).

use nalgebra::{SMatrix, SVector};

use super::closed_form::{Mat7, dz_dp, z_of};
use super::eiv::Gains;
use super::trig::{Trig, sin_cos};
use crate::error::CalibError;

/// What the iterative methods minimise: the (weighted, optionally bias-corrected) loop cost.
#[derive(Clone, Copy)]
pub(crate) struct Problem<'a> {
    pub trig: &'a Trig,
    /// Wheel radius (m).
    pub l2: f64,
    /// Fixed per-sample weights (noise × robust); `None` = 1.
    pub weights: Option<&'a [f64]>,
    /// Errors-in-variables gains; `None` = plain least squares.
    pub gains: Option<&'a Gains>,
}

/// Normal equations of the cost at one point.
pub(crate) struct Normal<const NP: usize> {
    /// Gauss–Newton Hessian / 2 (`JᵀWJ`, minus the correction's curvature).
    pub jtj: SMatrix<f64, NP, NP>,
    /// The rest of the exact Hessian / 2: `Σ w·Re(conj(r)·∂²r)`.
    pub curv: SMatrix<f64, NP, NP>,
    /// Gradient / 2 (`JᵀWr`, minus the correction's slope).
    pub jtr: SVector<f64, NP>,
    /// The cost (m², weighted; corrected when there are gains).
    pub cost: f64,
    /// Size of the terms summed into `cost` (m²): its rounding error is about ε times this.
    pub cost_scale: f64,
}

/// Sums of one pass over the samples at `p` (biases `p[6], p[7]` used when `NP == 8`).
pub(crate) struct Pass<const NP: usize> {
    pub normal: Normal<NP>,
    /// Σ|r|² without weights (m²).
    pub ssr_unweighted: f64,
}

/// One pass: residual and analytic derivatives of each sample folded straight into the
/// `NP × NP` normal equations (eq. 4.2 extended by the l1 and bias columns).
pub(crate) fn pass<const NP: usize>(pb: &Problem<'_>, p: &[f64; 8]) -> Pass<NP> {
    let at = At::new::<NP>(pb.l2, p);
    let mut sums = Sums::<NP>::new();
    for k in 0..pb.trig.len() {
        sums.add_sample(pb, &at, k);
    }
    sums.into_pass(pb, &at)
}

/// The parameters of one pass, with the sines and cosines of its offsets.
struct At {
    /// Wheel radius (m).
    l2: f64,
    l1: f64,
    l3: f64,
    l4: f64,
    /// Offsets Θ3, Θ4 (rad).
    th3: f64,
    th4: f64,
    /// Gyro biases (rad/s; 0 without bias terms).
    b3: f64,
    b4: f64,
    /// (sin, cos) of Θ2, Θ3, Θ4.
    t2: (f64, f64),
    t3: (f64, f64),
    t4: (f64, f64),
}

impl At {
    fn new<const NP: usize>(l2: f64, p: &[f64; 8]) -> Self {
        let (b3, b4) = if NP > 6 { (p[6], p[7]) } else { (0.0, 0.0) };
        Self {
            l2,
            l1: p[0],
            l3: p[1],
            l4: p[2],
            th3: p[4],
            th4: p[5],
            b3,
            b4,
            t2: sin_cos(p[3]),
            t3: sin_cos(p[4]),
            t4: sin_cos(p[5]),
        }
    }
}

/// The running sums of one [`pass`].
struct Sums<const NP: usize> {
    a: [[f64; NP]; NP],
    g: [f64; NP],
    cost: f64,
    ssr_u: f64,
    d2: f64,
    d3: f64,
    d4: f64,
    // second-derivative sums: Σ w·g·(r·e), Σ w·g·(r·ie) and their t, t² moments
    p2: f64,
    p3: f64,
    p3t: f64,
    p3tt: f64,
    q3: f64,
    q3t: f64,
    p4: f64,
    p4t: f64,
    p4tt: f64,
    q4: f64,
    q4t: f64,
}

impl<const NP: usize> Sums<NP> {
    fn new() -> Self {
        Self {
            a: [[0.0f64; NP]; NP],
            g: [0.0f64; NP],
            cost: 0.0,
            ssr_u: 0.0,
            d2: 0.0,
            d3: 0.0,
            d4: 0.0,
            p2: 0.0,
            p3: 0.0,
            p3t: 0.0,
            p3tt: 0.0,
            q3: 0.0,
            q3t: 0.0,
            p4: 0.0,
            p4t: 0.0,
            p4tt: 0.0,
            q4: 0.0,
            q4t: 0.0,
        }
    }

    /// Fold sample `k` in: its residual, and its derivatives into the normal equations.
    fn add_sample(&mut self, pb: &Problem<'_>, at: &At, k: usize) {
        let tr = pb.trig;
        let (l1, l2, l3, l4) = (at.l1, at.l2, at.l3, at.l4);
        let ((st2, ct2), (st3, ct3), (st4, ct4)) = (at.t2, at.t3, at.t4);
        let t = tr.t[k];
        let w = pb.weights.map_or(1.0, |w| w[k]);
        let (g2, g3, g4) = pb
            .gains
            .map_or((1.0, 1.0, 1.0), |g| (g.g2[k], g.g3[k], g.g4[k]));
        // offsets Θj − bj·t as unit vectors
        let (so3, co3) = if at.b3 != 0.0 {
            sin_cos(at.th3 - at.b3 * t)
        } else {
            (st3, ct3)
        };
        let (so4, co4) = if at.b4 != 0.0 {
            sin_cos(at.th4 - at.b4 * t)
        } else {
            (st4, ct4)
        };
        let (c2, s2) = (
            ct2 * tr.c2[k] - st2 * tr.s2[k],
            st2 * tr.c2[k] + ct2 * tr.s2[k],
        );
        let (c3, s3) = (
            co3 * tr.c3[k] - so3 * tr.s3[k],
            so3 * tr.c3[k] + co3 * tr.s3[k],
        );
        let (c4, s4) = (
            co4 * tr.c4[k] - so4 * tr.s4[k],
            so4 * tr.c4[k] + co4 * tr.s4[k],
        );
        let (m2, m3, m4) = (l2 * g2, l3 * g3, l4 * g4);
        let r = [
            m2 * c2 + m3 * c3 - m4 * c4 - l1,
            m2 * s2 + m3 * s3 - m4 * s4,
        ];
        let r2 = r[0] * r[0] + r[1] * r[1];
        if pb.gains.is_some() {
            let raw = [
                l2 * c2 + l3 * c3 - l4 * c4 - l1,
                l2 * s2 + l3 * s3 - l4 * s4,
            ];
            self.ssr_u += raw[0] * raw[0] + raw[1] * raw[1];
            let (e2, e3, e4) = (g2 * g2 - 1.0, g3 * g3 - 1.0, g4 * g4 - 1.0);
            self.d2 += w * e2;
            self.d3 += w * e3;
            self.d4 += w * e4;
        } else {
            self.ssr_u += r2;
        }
        self.cost += w * r2;
        let (wg2, wg3, wg4) = (w * g2, w * g3, w * g4);
        self.p2 += wg2 * (r[0] * c2 + r[1] * s2);
        let (pp3, qq3) = (wg3 * (r[0] * c3 + r[1] * s3), wg3 * (r[1] * c3 - r[0] * s3));
        let (pp4, qq4) = (wg4 * (r[0] * c4 + r[1] * s4), wg4 * (r[1] * c4 - r[0] * s4));
        self.p3 += pp3;
        self.q3 += qq3;
        self.p4 += pp4;
        self.q4 += qq4;
        if NP > 6 {
            self.p3t += t * pp3;
            self.p3tt += t * t * pp3;
            self.q3t += t * qq3;
            self.p4t += t * pp4;
            self.p4tt += t * t * pp4;
            self.q4t += t * qq4;
        }
        let mut dre = [0.0f64; NP];
        let mut dim = [0.0f64; NP];
        dre[0] = -1.0;
        dre[1] = g3 * c3;
        dim[1] = g3 * s3;
        dre[2] = -g4 * c4;
        dim[2] = -g4 * s4;
        dre[3] = -m2 * s2;
        dim[3] = m2 * c2;
        dre[4] = -m3 * s3;
        dim[4] = m3 * c3;
        dre[5] = m4 * s4;
        dim[5] = -m4 * c4;
        if NP > 6 {
            dre[6] = -t * dre[4];
            dim[6] = -t * dim[4];
            dre[7] = -t * dre[5];
            dim[7] = -t * dim[5];
        }
        for i in 0..NP {
            let (wre, wim) = (w * dre[i], w * dim[i]);
            self.g[i] += wre * r[0] + wim * r[1];
            for j in 0..=i {
                self.a[i][j] += wre * dre[j] + wim * dim[j];
            }
        }
    }

    /// The normal equations of the sums (the correction of the gains applied).
    fn into_pass(self, pb: &Problem<'_>, at: &At) -> Pass<NP> {
        let (l2, l3, l4) = (at.l2, at.l3, at.l4);
        let (a, g) = (self.a, self.g);
        let (d2, d3, d4) = (self.d2, self.d3, self.d4);
        let mut cost = self.cost;
        let mut jtj =
            SMatrix::<f64, NP, NP>::from_fn(|i, j| if j <= i { a[i][j] } else { a[j][i] });
        let mut jtr = SVector::<f64, NP>::from_fn(|i, _| g[i]);
        let cost_scale = cost;
        if pb.gains.is_some() {
            // − Σ w·lⱼ²(gⱼ² − 1): the noise's expected share of |r|²; its slope in l3, l4, and
            // the same share taken out of the Gauss–Newton curvature of every column (so this
            // equals the normal-matrix form `GᵀHG` of `compressed` exactly)
            cost -= l2 * l2 * d2 + l3 * l3 * d3 + l4 * l4 * d4;
            jtr[1] -= l3 * d3;
            jtr[2] -= l4 * d4;
            jtj[(1, 1)] -= d3;
            jtj[(2, 2)] -= d4;
        }
        Pass {
            normal: Normal {
                jtj,
                curv: self.curvature(at),
                jtr,
                cost,
                cost_scale,
            },
            ssr_unweighted: self.ssr_u,
        }
    }

    /// `Σ w·Re(conj(r)·∂²r)`. ∂²r: (l3, Θ3) = g3·ie3, (Θ3, Θ3) = −l3g3·e3,
    /// (Θ2, Θ2) = −l2g2·e2, (l4, Θ4) = −g4·ie4, (Θ4, Θ4) = l4g4·e4, and each bias bj acts
    /// as −t·Θj.
    fn curvature(&self, at: &At) -> SMatrix<f64, NP, NP> {
        let (l2, l3, l4) = (at.l2, at.l3, at.l4);
        let mut curv = SMatrix::<f64, NP, NP>::zeros();
        let mut set = |i: usize, j: usize, v: f64| {
            curv[(i, j)] += v;
            if i != j {
                curv[(j, i)] += v;
            }
        };
        set(3, 3, -l2 * self.p2);
        set(1, 4, self.q3);
        set(4, 4, -l3 * self.p3);
        set(2, 5, -self.q4);
        set(5, 5, l4 * self.p4);
        if NP > 6 {
            set(1, 6, -self.q3t);
            set(4, 6, l3 * self.p3t);
            set(6, 6, -l3 * self.p3tt);
            set(2, 7, self.q4t);
            set(5, 7, -l4 * self.p4t);
            set(7, 7, l4 * self.p4tt);
        }
        curv
    }
}

/// The cost without bias terms as a quadratic form of `z(p)`: `z(p)ᵀHz(p)`.
pub(crate) enum Quadratic {
    /// `‖Rz‖²` with `RᵀR = H` (plain or weighted least squares: the 7 numbers `Rz` are the
    /// compressed residual vector, so the cost keeps full relative precision near zero).
    Sqrt(Mat7),
    /// `zᵀHz` for an `H` that may be indefinite (bias-corrected).
    Full(Mat7),
}

impl Quadratic {
    /// `H` itself when `corrected`, else its Cholesky factor when it has one.
    pub(crate) fn new(h: Mat7, corrected: bool) -> Self {
        if corrected {
            return Self::Full(h);
        }
        match h.cholesky() {
            Some(c) => Self::Sqrt(c.l().transpose()),
            None => Self::Full(h),
        }
    }

    /// Normal equations over `[l1, l3, l4, Θ2, Θ3, Θ4]` (no bias terms) from the 7×7 matrix
    /// alone: `JᵀJ = GᵀHG`, `Jᵀr = GᵀHz` with `G = ∂z/∂p`, plus the exact curvature.
    pub(crate) fn normal(&self, l2: f64, p: &[f64; 8]) -> Normal<6> {
        let z = z_of(p, l2);
        let g = dz_dp(p, l2);
        let (jtj, hz, cost, cost_scale) = match self {
            Self::Sqrt(r) => {
                let (rz, rg) = (r * z, r * g);
                let cost = rz.norm_squared();
                (rg.transpose() * rg, r.transpose() * rz, cost, cost)
            }
            Self::Full(h) => {
                let hz = h * z;
                let scale = z.abs().dot(&(h.abs() * z.abs()));
                (g.transpose() * (h * g), hz, z.dot(&hz), scale)
            }
        };
        // Σᵢ (Hz)ᵢ ∂²zᵢ: z = [l3 cΘ3, l3 sΘ3, l4 cΘ4, l4 sΘ4, l1, l2 cΘ2, l2 sΘ2]
        let (s2, c2) = p[3].sin_cos();
        let (s3, c3) = p[4].sin_cos();
        let (s4, c4) = p[5].sin_cos();
        let mut curv = SMatrix::<f64, 6, 6>::zeros();
        let v3 = -s3 * hz[0] + c3 * hz[1];
        curv[(1, 4)] = v3;
        curv[(4, 1)] = v3;
        curv[(4, 4)] = -p[1] * (c3 * hz[0] + s3 * hz[1]);
        let v4 = -s4 * hz[2] + c4 * hz[3];
        curv[(2, 5)] = v4;
        curv[(5, 2)] = v4;
        curv[(5, 5)] = -p[2] * (c4 * hz[2] + s4 * hz[3]);
        curv[(3, 3)] = -l2 * (c2 * hz[5] + s2 * hz[6]);
        Normal {
            jtj,
            curv,
            jtr: g.transpose() * hz,
            cost,
            cost_scale,
        }
    }
}

/// Loop-residual norms |ΔXₖ| (m) at `p` (with the bias terms), unweighted, into `out`.
pub(crate) fn residual_norms(trig: &Trig, l2: f64, p: &[f64; 8], out: &mut Vec<f64>) {
    let (st2, ct2) = sin_cos(p[3]);
    out.clear();
    let (st3, ct3) = sin_cos(p[4]);
    let (st4, ct4) = sin_cos(p[5]);
    out.extend((0..trig.len()).map(|k| {
        let t = trig.t[k];
        let (so3, co3) = if p[6] != 0.0 {
            sin_cos(p[4] - p[6] * t)
        } else {
            (st3, ct3)
        };
        let (so4, co4) = if p[7] != 0.0 {
            sin_cos(p[5] - p[7] * t)
        } else {
            (st4, ct4)
        };
        let re = l2 * (ct2 * trig.c2[k] - st2 * trig.s2[k])
            + p[1] * (co3 * trig.c3[k] - so3 * trig.s3[k])
            - p[2] * (co4 * trig.c4[k] - so4 * trig.s4[k])
            - p[0];
        let im = l2 * (st2 * trig.c2[k] + ct2 * trig.s2[k])
            + p[1] * (so3 * trig.c3[k] + co3 * trig.s3[k])
            - p[2] * (so4 * trig.c4[k] + co4 * trig.s4[k]);
        // (not `hypot`: its overflow care costs more than the rest of the pass; |ΔX| ≪ 1e150)
        (re * re + im * im).sqrt()
    }));
}

/// Median of `v` (reorders a copy in `scratch`).
pub(crate) fn median(v: &[f64], scratch: &mut Vec<f64>) -> f64 {
    scratch.clear();
    scratch.extend_from_slice(v);
    let mid = scratch.len() / 2;
    *scratch.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// Result of an iterative refinement.
pub(crate) struct Refined {
    pub p: [f64; 8],
    pub iterations: u32,
    pub converged: bool,
}

fn step_small<const NP: usize>(delta: &SVector<f64, NP>, p: &[f64; 8], tol: f64) -> bool {
    delta
        .iter()
        .zip(p)
        .all(|(d, x)| d.abs() <= tol * (x.abs() + 1e-3))
}

/// The thesis's iterated least squares (eq. 4.4): undamped Gauss–Newton on
/// `[l1, l3, l4, Θ2, Θ3, Θ4]` from `p0`, stopping when the step is below `tol` (relative).
/// `q` holds the loop's normal matrix; each iteration solves `ΦᵀΦ Δζ = −ΦᵀΔX` exactly as the
/// thesis does, with `ΦᵀΦ` and `ΦᵀΔX` formed from it.
pub(crate) fn gauss_newton(
    p0: [f64; 8],
    q: &Quadratic,
    l2: f64,
    max_iterations: u32,
    tol: f64,
) -> Result<Refined, CalibError> {
    let mut p = p0;
    p[6] = 0.0;
    p[7] = 0.0;
    for it in 1..=max_iterations {
        let ne = q.normal(l2, &p);
        let delta =
            ne.jtj
                .cholesky()
                .map(|c| c.solve(&(-ne.jtr)))
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

/// Levenberg–Marquardt (Marquardt's diagonal scaling, damping ÷10 on success, ×10 on failure)
/// on the first `NP` parameters, `eval` giving the normal equations at a point. The model
/// Hessian is the exact one (Gauss–Newton plus the residual curvature) whenever that is
/// positive definite at the current damping, which keeps the convergence quadratic when the
/// residuals are not small; elsewhere (far from the minimum) it is Gauss–Newton's.
pub(crate) fn levenberg_marquardt<const NP: usize>(
    p0: [f64; 8],
    mut eval: impl FnMut(&[f64; 8]) -> Normal<NP>,
    max_iterations: u32,
    tol: f64,
) -> Refined {
    let mut p = p0;
    for v in p.iter_mut().skip(NP) {
        *v = 0.0;
    }
    let mut ne = eval(&p);
    let mut mu = 1e-6;
    for it in 1..=max_iterations {
        let mut damping = SMatrix::<f64, NP, NP>::zeros();
        for i in 0..NP {
            damping[(i, i)] = mu * ne.jtj[(i, i)].abs().max(1e-12);
        }
        // Newton (exact Hessian: quadratic convergence even with noisy residuals) where it is
        // positive definite, else Gauss–Newton at the same damping
        let newton = (ne.jtj + ne.curv + damping).cholesky();
        let chol = newton.or_else(|| (ne.jtj + damping).cholesky());
        let Some(delta) = chol.map(|c| c.solve(&(-ne.jtr))) else {
            mu *= 10.0;
            if mu > 1e12 {
                return Refined {
                    p,
                    iterations: it,
                    converged: false,
                };
            }
            continue;
        };
        let mut trial = p;
        for i in 0..NP {
            trial[i] += delta[i];
        }
        // the step's first-order decrease; below the cost's rounding it cannot be seen
        let predicted = -delta.dot(&ne.jtr);
        let lost_in_rounding = predicted <= 1e-13 * ne.cost_scale;
        let trial_ne = eval(&trial);
        if trial_ne.cost.is_finite() && trial_ne.cost <= ne.cost {
            let done = step_small(&delta, &p, tol) || trial_ne.cost == 0.0 || lost_in_rounding;
            p = trial;
            ne = trial_ne;
            mu = (mu / 10.0).max(1e-15);
            if done {
                return Refined {
                    p,
                    iterations: it,
                    converged: true,
                };
            }
        } else {
            mu *= 10.0;
            // a rejected step this small is rounding in the cost, not a worse point
            if mu > 1e12 || step_small(&delta, &p, tol) || lost_in_rounding {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fourbar::eiv::NoiseProfile;
    use crate::fourbar::model::FourbarSamples;

    fn data() -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
        let n = 40;
        let f = |a: f64, b: f64| -> Vec<f64> {
            (0..n)
                .map(|k| a * (k as f64 * b).sin() + 0.01 * ((k * k) % 7) as f64)
                .collect()
        };
        let t = (0..n).map(|k| 0.1 * k as f64).collect();
        (f(0.9, 0.2), f(0.5, 0.3), f(-0.4, 0.25), t)
    }

    #[test]
    fn pass_gradient_and_hessian_match_finite_differences_with_weights_and_correction() {
        let (p2, p3, p4, t) = data();
        let s = FourbarSamples {
            time_s: Some(&t),
            ..FourbarSamples::new(&p2, &p3, &p4)
        };
        let trig = Trig::new(&s);
        let noise = NoiseProfile::estimate(&s);
        let gains = noise.gains();
        let w: Vec<f64> = (0..p2.len()).map(|k| 0.5 + (k % 3) as f64).collect();
        let pb = Problem {
            trig: &trig,
            l2: 0.15,
            weights: Some(&w),
            gains: Some(&gains),
        };
        let p = [0.45, 0.35, 0.3, 1.2, -0.4, 2.0, 0.01, -0.02];
        let ne = pass::<8>(&pb, &p).normal;
        for j in 0..8 {
            let h = 1e-6;
            let (mut up, mut down) = (p, p);
            up[j] += h;
            down[j] -= h;
            let fd =
                (pass::<8>(&pb, &up).normal.cost - pass::<8>(&pb, &down).normal.cost) / (4.0 * h);
            assert!(
                (fd - ne.jtr[j]).abs() < 1e-6 * (1.0 + fd.abs()),
                "col {j}: {fd} vs {}",
                ne.jtr[j]
            );
            // the exact Hessian is the derivative of the gradient
            let (gu, gd) = (
                pass::<8>(&pb, &up).normal.jtr,
                pass::<8>(&pb, &down).normal.jtr,
            );
            let hess = ne.jtj + ne.curv;
            for i in 0..8 {
                let fd = (gu[i] - gd[i]) / (2.0 * h);
                assert!(
                    (fd - hess[(i, j)]).abs() < 1e-5 * (1.0 + fd.abs()),
                    "H[{i},{j}]: {fd} vs {}",
                    hess[(i, j)]
                );
            }
        }
    }

    #[test]
    fn normal_matrix_form_equals_the_sample_pass_without_bias_terms_hessian_included() {
        let (p2, p3, p4, _) = data();
        let s = FourbarSamples::new(&p2, &p3, &p4);
        let trig = Trig::new(&s);
        let gains = NoiseProfile::estimate(&s).gains();
        let w: Vec<f64> = (0..p2.len()).map(|k| 1.0 + (k % 5) as f64).collect();
        let p = [0.45, 0.35, 0.3, 1.2, -0.4, 2.0, 0.0, 0.0];
        for g in [None, Some(&gains)] {
            let pb = Problem {
                trig: &trig,
                l2: 0.15,
                weights: Some(&w),
                gains: g,
            };
            let a = pass::<6>(&pb, &p).normal;
            let h = crate::fourbar::closed_form::gram(&trig, Some(&w), g);
            let b = Quadratic::Full(h).normal(0.15, &p);
            assert!(
                (a.cost - b.cost).abs() < 1e-12 * a.cost.abs().max(1.0),
                "{} {}",
                a.cost,
                b.cost
            );
            assert!((a.jtr - b.jtr).amax() < 1e-12, "{} {}", a.jtr, b.jtr);
            let (ha, hb) = (a.jtj + a.curv, b.jtj + b.curv);
            assert!((ha - hb).amax() < 1e-11, "{ha} {hb}");
        }
    }
}
