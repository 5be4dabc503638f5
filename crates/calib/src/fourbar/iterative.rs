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
use super::eiv::{Gains, NoiseProfile};
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
    /// With the correction it is the uncorrected (weighted, gained) `Σ w·|r|²`.
    pub cost_scale: f64,
    /// What the correction took out of `jtj[(1, 1)]` and `jtj[(2, 2)]` (0 without it).
    pub correction_diag: [f64; 2],
}

/// Sums of one pass over the samples at `p` (biases `p[6], p[7]` used when `NP == 8`).
pub(crate) struct Pass<const NP: usize> {
    pub normal: Normal<NP>,
    /// Σ|r|² without weights (m²); 0 with gains (the raw residual is then not formed).
    pub ssr_unweighted: f64,
}

/// One pass: the weighted moment sums of the sample's unit vectors ([`Moments`]), from which
/// the residual's analytic derivatives give the `NP × NP` normal equations (eq. 4.2 extended
/// by the l1 and bias columns) without forming a row of the Jacobian per sample.
pub(crate) fn pass<const NP: usize>(pb: &Problem<'_>, p: &[f64; 8]) -> Pass<NP> {
    let at = At::new::<NP>(pb.l2, p);
    let mut m = Moments::default();
    let (mut rot3, mut rot4) = (Rotor::new(pb.trig, at.b3), Rotor::new(pb.trig, at.b4));
    let tr = pb.trig;
    let n = tr.len();
    // every array cut to `n` up front, so the loop indexes without bounds checks
    let (c2, s2, c3, s3, c4, s4, t) = (
        &tr.c2[..n],
        &tr.s2[..n],
        &tr.c3[..n],
        &tr.s3[..n],
        &tr.c4[..n],
        &tr.s4[..n],
        &tr.t[..n],
    );
    let w = pb.weights.map(|w| &w[..n]);
    let g = pb.gains.map(|g| (&g.g2[..n], &g.g3[..n], &g.g4[..n]));
    for k in 0..n {
        let (r3, r4) = (rot3.at(k), rot4.at(k));
        let u2 = (c2[k], s2[k]);
        let u3 = cmul((c3[k], s3[k]), r3);
        let u4 = cmul((c4[k], s4[k]), r4);
        let wk = w.map_or(1.0, |w| w[k]);
        let gk = g.map(|(g2, g3, g4)| (g2[k], g3[k], g4[k]));
        m.add_sample(&at, t[k], wk, [u2, u3, u4], gk);
    }
    m.into_pass(pb, &at)
}

/// How [`pass_reweighted`] weights each sample at the pass's own point: the noise weights of
/// its lengths (when there is a profile) times Huber factors of the standardised residual norm
/// against the threshold `huber` (m; `None`: no robust factor).
pub(crate) struct Reweight<'a> {
    pub noise: Option<&'a NoiseProfile>,
    pub huber: Option<f64>,
}

/// A pass that weighted the samples itself, and what the weights say.
pub(crate) struct Reweighted {
    pub pass: Pass<8>,
    /// Σ of the Huber factors (the effective sample count).
    pub n_eff: f64,
    /// Samples the Huber factor down-weighted.
    pub outliers: usize,
    /// Σ|r|² without weights or gains (m²).
    pub ssr: f64,
}

/// [`pass`] with bias terms whose per-sample weights are computed at `p` inside the sweep (the
/// robust reweighting and the moment sums in one pass over the samples instead of two),
/// written to `weights` for later passes at other points; `pb.weights` is ignored.
pub(crate) fn pass_reweighted(
    pb: &Problem<'_>,
    p: &[f64; 8],
    rw: &Reweight<'_>,
    weights: &mut Vec<f64>,
) -> Reweighted {
    let at = At::new::<8>(pb.l2, p);
    let mut m = Moments::default();
    let (mut rot3, mut rot4) = (Rotor::new(pb.trig, at.b3), Rotor::new(pb.trig, at.b4));
    let tr = pb.trig;
    let n = tr.len();
    let (c2, s2, c3, s3, c4, s4, t) = (
        &tr.c2[..n],
        &tr.s2[..n],
        &tr.c3[..n],
        &tr.s3[..n],
        &tr.c4[..n],
        &tr.s4[..n],
        &tr.t[..n],
    );
    let g = pb.gains.map(|g| (&g.g2[..n], &g.g3[..n], &g.g4[..n]));
    let noise = rw.noise.map(|nz| {
        (
            nz.weight_fn(pb.l2, p[1].abs(), p[2].abs()),
            &nz.var2[..n],
            &nz.var3[..n],
            &nz.var4[..n],
        )
    });
    let c = rw.huber.unwrap_or(f64::INFINITY);
    let c2_huber = c * c;
    let (mut n_eff, mut outliers, mut ssr) = (0.0, 0usize, 0.0);
    weights.clear();
    weights.resize(n, 1.0);
    let w_out = &mut weights[..n];
    // the noise weights first (their divisions two at a time), the Huber factors in the sweep
    if let Some((f, v2, v3, v4)) = noise {
        f.fill(v2, v3, v4, w_out);
    }
    for k in 0..n {
        let (r3, r4) = (rot3.at(k), rot4.at(k));
        let u2 = (c2[k], s2[k]);
        let u3 = cmul((c3[k], s3[k]), r3);
        let u4 = cmul((c4[k], s4[k]), r4);
        let r = residual(&at, u2, u3, u4);
        let r2 = r.0 * r.0 + r.1 * r.1;
        ssr += r2;
        let nw = w_out[k];
        let rho2 = r2 * nw;
        let h = if rho2 > c2_huber {
            outliers += 1;
            c / rho2.sqrt()
        } else {
            1.0
        };
        n_eff += h;
        let wk = nw * h;
        w_out[k] = wk;
        let gk = g.map(|(g2, g3, g4)| (g2[k], g3[k], g4[k]));
        m.add_sample(&at, t[k], wk, [u2, u3, u4], gk);
    }
    Reweighted {
        pass: m.into_pass(pb, &at),
        n_eff,
        outliers,
        ssr,
    }
}

/// `e^{−i·b·tₖ}` sample after sample: on a uniform time axis computed exactly (`sin_cos`)
/// every [`RESYNC`] samples and in between as that value times a power of the step,
/// `e^{−i·b·j·Δt}`, from a table computed exactly once: one complex product per sample (a
/// few ulp, ≈ 1e-16 rad) and no chain of products from one sample to the next, which had the
/// loops wait on the multiplier's latency; otherwise a `sin_cos` per sample.
pub(crate) struct Rotor<'a> {
    trig: &'a Trig,
    b: f64,
    /// `e^{−i·b·j·Δt}` for j = 0 … RESYNC − 1 on a uniform axis.
    powers: Option<[C64; RESYNC]>,
    /// The exact rotation at the last multiple of RESYNC.
    base: C64,
}

/// Samples between a [`Rotor`]'s exact evaluations.
const RESYNC: usize = 16;

impl<'a> Rotor<'a> {
    pub(crate) fn new(trig: &'a Trig, b: f64) -> Self {
        let powers = trig.uniform_dt.filter(|_| b != 0.0).map(|dt| {
            std::array::from_fn(|j| {
                let (s, c) = sin_cos(-b * dt * j as f64);
                (c, s)
            })
        });
        Self {
            trig,
            b,
            powers,
            base: (1.0, 0.0),
        }
    }

    /// The rotation at sample `k`; called for k = 0, 1, 2, … in order.
    #[inline(always)]
    pub(crate) fn at(&mut self, k: usize) -> C64 {
        if self.b == 0.0 {
            return (1.0, 0.0);
        }
        let exact = |k: usize| {
            let (s, c) = sin_cos(-self.b * self.trig.t[k]);
            (c, s)
        };
        match &self.powers {
            Some(powers) => {
                let j = k % RESYNC;
                if j == 0 {
                    self.base = exact(k);
                }
                cmul(self.base, powers[j])
            }
            None => exact(k),
        }
    }
}

/// A complex number as `(re, im)`.
pub(crate) type C64 = (f64, f64);

#[inline]
fn cmul(a: C64, b: C64) -> C64 {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

#[inline]
fn cconj_mul(a: C64, b: C64) -> C64 {
    // conj(a)·b
    (a.0 * b.0 + a.1 * b.1, a.0 * b.1 - a.1 * b.0)
}

#[inline]
fn cscale(a: C64, s: f64) -> C64 {
    (a.0 * s, a.1 * s)
}

#[inline]
fn cadd(a: C64, b: C64) -> C64 {
    (a.0 + b.0, a.1 + b.1)
}

/// The parameters of one pass as the complex coefficients of the loop
/// `r = a·A + b·B − c·C − l1` ([`Moments`]).
struct At {
    /// Wheel radius (m).
    l2: f64,
    l1: f64,
    l3: f64,
    l4: f64,
    /// Gyro biases (rad/s; 0 without bias terms).
    b3: f64,
    b4: f64,
    /// `e^{iΘ3}`, `e^{iΘ4}`.
    e3: C64,
    e4: C64,
    /// `a = l2·e^{iΘ2}`, `b = l3·e^{iΘ3}`, `c = l4·e^{iΘ4}` (m).
    a: C64,
    b: C64,
    c: C64,
}

impl At {
    fn new<const NP: usize>(l2: f64, p: &[f64; 8]) -> Self {
        let (b3, b4) = if NP > 6 { (p[6], p[7]) } else { (0.0, 0.0) };
        let (s2, c2) = sin_cos(p[3]);
        let (s3, c3) = sin_cos(p[4]);
        let (s4, c4) = sin_cos(p[5]);
        Self {
            l2,
            l1: p[0],
            l3: p[1],
            l4: p[2],
            b3,
            b4,
            e3: (c3, s3),
            e4: (c4, s4),
            a: (l2 * c2, l2 * s2),
            b: (p[1] * c3, p[1] * s3),
            c: (p[2] * c4, p[2] * s4),
        }
    }

    /// The residual's coefficient of each vector `[1, A, B, C]`.
    fn coefficients(&self) -> [C64; 4] {
        [(-self.l1, 0.0), self.a, self.b, (-self.c.0, -self.c.1)]
    }
}

/// The vectors of one sample: `1`, `A = g2·e^{iφ2}`, `B = g3·e^{i(φ3 − b3·t)}`,
/// `C = g4·e^{i(φ4 − b4·t)}` (gains `g` of the errors-in-variables correction, 1 without).
/// Every derivative of the residual `r = a·A + b·B − c·C − l1` up to second order is a constant
/// times `tᵐ·X` for one of them, so the normal equations, gradient and curvature are linear
/// combinations of `S(X, Y, m) = Σ w·tᵐ·conj(X)·Y`, m ≤ 2: 9 complex and 7 real running sums
/// per sample instead of an 8×8 outer product.
#[derive(Default)]
struct Moments {
    /// `S(X, Y, m)` for `X ≤ Y` in the order `[1, A, B, C]` (the lower half by conjugation).
    s: [[[C64; 3]; 4]; 4],
    /// `Σ w·|r|²` with the gains (m²).
    cost: f64,
    /// `Σ |r|²` without weights, only without gains (m²; with gains the raw residual is not
    /// formed: the statistics take it from the residual norms of the answer).
    ssr_u: f64,
    /// `Σ w·(gⱼ² − 1)` for j = 2, 3, 4.
    d2: f64,
    d3: f64,
    d4: f64,
}

impl Moments {
    /// Fold one sample in: time `t`, weight `w`, unit vectors `[e^{iφ2}, e^{i(φ3 − b3·t)},
    /// e^{i(φ4 − b4·t)}]` and the gains `(g2, g3, g4)` when correcting.
    #[inline(always)]
    fn add_sample(&mut self, at: &At, t: f64, w: f64, u: [C64; 3], gains: Option<(f64, f64, f64)>) {
        let [u2, u3, u4] = u;
        let (va, vb, vc) = match gains {
            Some((g2, g3, g4)) => {
                self.d2 += w * (g2 * g2 - 1.0);
                self.d3 += w * (g3 * g3 - 1.0);
                self.d4 += w * (g4 * g4 - 1.0);
                (cscale(u2, g2), cscale(u3, g3), cscale(u4, g4))
            }
            None => (u2, u3, u4),
        };
        let r = residual(at, va, vb, vc);
        let r2 = r.0 * r.0 + r.1 * r.1;
        if gains.is_none() {
            self.ssr_u += r2;
        }
        self.cost += w * r2;
        let (wt, wtt) = (w * t, w * t * t);
        let ws = [w, wt, wtt];
        // (1, 1), (1, A), (A, A): m = 0 only
        self.s[0][0][0].0 += w;
        self.s[0][1][0] = cadd(self.s[0][1][0], cscale(va, w));
        self.s[1][1][0].0 += w * (va.0 * va.0 + va.1 * va.1);
        let ab = cconj_mul(va, vb);
        let ac = cconj_mul(va, vc);
        let bc = cconj_mul(vb, vc);
        let bb = vb.0 * vb.0 + vb.1 * vb.1;
        let cc = vc.0 * vc.0 + vc.1 * vc.1;
        for (m, wm) in ws.into_iter().enumerate() {
            self.s[0][2][m] = cadd(self.s[0][2][m], cscale(vb, wm));
            self.s[0][3][m] = cadd(self.s[0][3][m], cscale(vc, wm));
            self.s[1][2][m] = cadd(self.s[1][2][m], cscale(ab, wm));
            self.s[1][3][m] = cadd(self.s[1][3][m], cscale(ac, wm));
            self.s[2][3][m] = cadd(self.s[2][3][m], cscale(bc, wm));
            self.s[2][2][m].0 += wm * bb;
            self.s[3][3][m].0 += wm * cc;
        }
    }

    /// `S(X, Y, m)` for any order of `X`, `Y`.
    fn get(&self, x: usize, y: usize, m: usize) -> C64 {
        if x <= y {
            self.s[x][y][m]
        } else {
            let v = self.s[y][x][m];
            (v.0, -v.1)
        }
    }

    /// The normal equations of the sums (the correction of the gains applied).
    fn into_pass<const NP: usize>(self, pb: &Problem<'_>, at: &At) -> Pass<NP> {
        let i = |z: C64| (-z.1, z.0);
        let neg = |z: C64| (-z.0, -z.1);
        // ∂r/∂pᵢ = κᵢ·tᵐⁱ·Xᵢ: (vector, κ, m) per parameter
        let cols: [(usize, C64, usize); 8] = [
            (0, (-1.0, 0.0), 0),
            (2, at.e3, 0),
            (3, neg(at.e4), 0),
            (1, i(at.a), 0),
            (2, i(at.b), 0),
            (3, neg(i(at.c)), 0),
            (2, neg(i(at.b)), 1),
            (3, i(at.c), 1),
        ];
        let coef = at.coefficients();
        let mut jtj = SMatrix::<f64, NP, NP>::zeros();
        let mut jtr = SVector::<f64, NP>::zeros();
        for (r, &(xr, kr, mr)) in cols.iter().enumerate().take(NP) {
            for (c, &(xc, kc, mc)) in cols.iter().enumerate().take(r + 1) {
                let v = cconj_mul(kr, kc);
                let v = cmul(v, self.get(xr, xc, mr + mc)).0;
                jtj[(r, c)] = v;
                jtj[(c, r)] = v;
            }
            // Σ w·Re(conj(∂ᵣr)·r) with r = Σ_Y coef_Y·Y
            let mut acc = (0.0, 0.0);
            for (y, cy) in coef.iter().enumerate() {
                acc = cadd(acc, cmul(*cy, self.get(xr, y, mr)));
            }
            jtr[r] = cconj_mul(kr, acc).0;
        }
        let (l2, l3, l4) = (at.l2, at.l3, at.l4);
        let (d2, d3, d4) = (self.d2, self.d3, self.d4);
        let mut cost = self.cost;
        let cost_scale = cost;
        let mut correction_diag = [0.0; 2];
        if pb.gains.is_some() {
            correction_diag = [d3, d4];
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
                correction_diag,
            },
            ssr_unweighted: self.ssr_u,
        }
    }

    /// `Σ w·Re(conj(r)·∂²r)`. ∂²r: (l3, Θ3) = i·e^{iΘ3}·B, (Θ3, Θ3) = −b·B, (Θ2, Θ2) = −a·A,
    /// (l4, Θ4) = −i·e^{iΘ4}·C, (Θ4, Θ4) = c·C, and each bias bj acts as −t·Θj.
    fn curvature<const NP: usize>(&self, at: &At) -> SMatrix<f64, NP, NP> {
        let coef = at.coefficients();
        // Σ w·Re(conj(r)·κ·tᵐ·X)
        let term = |x: usize, kappa: C64, m: usize| {
            let mut acc = (0.0, 0.0);
            for (y, cy) in coef.iter().enumerate() {
                acc = cadd(acc, cconj_mul(*cy, self.get(y, x, m)));
            }
            cmul(kappa, acc).0
        };
        let i = |z: C64| (-z.1, z.0);
        let neg = |z: C64| (-z.0, -z.1);
        let mut curv = SMatrix::<f64, NP, NP>::zeros();
        let mut set = |r: usize, c: usize, v: f64| {
            curv[(r, c)] += v;
            if r != c {
                curv[(c, r)] += v;
            }
        };
        set(3, 3, term(1, neg(at.a), 0));
        set(1, 4, term(2, i(at.e3), 0));
        set(4, 4, term(2, neg(at.b), 0));
        set(2, 5, term(3, neg(i(at.e4)), 0));
        set(5, 5, term(3, at.c, 0));
        if NP > 6 {
            set(1, 6, term(2, neg(i(at.e3)), 1));
            set(4, 6, term(2, at.b, 1));
            set(6, 6, term(2, neg(at.b), 2));
            set(2, 7, term(3, i(at.e4), 1));
            set(5, 7, term(3, neg(at.c), 1));
            set(7, 7, term(3, at.c, 2));
        }
        curv
    }
}

/// `r = a·A + b·B − c·C − l1` (m).
#[inline]
fn residual(at: &At, va: C64, vb: C64, vc: C64) -> C64 {
    let (pa, pb, pc) = (cmul(at.a, va), cmul(at.b, vb), cmul(at.c, vc));
    (pa.0 + pb.0 - pc.0 - at.l1, pa.1 + pb.1 - pc.1)
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
            correction_diag: [0.0; 2],
        }
    }
}

/// Squared loop-residual norms |ΔXₖ|² (m²) at `p` (with the bias terms), unweighted, into
/// `out`. Squared: the robust weights need the norms' median and ratios only, and a square
/// root per sample was most of this pass.
pub(crate) fn residual_norms2(trig: &Trig, l2: f64, p: &[f64; 8], out: &mut Vec<f64>) {
    let at = At::new::<8>(l2, p);
    let (mut rot3, mut rot4) = (Rotor::new(trig, p[6]), Rotor::new(trig, p[7]));
    let n = trig.len();
    // every array cut to `n` up front, so the loop indexes without bounds checks
    let (c2, s2, c3, s3, c4, s4) = (
        &trig.c2[..n],
        &trig.s2[..n],
        &trig.c3[..n],
        &trig.s3[..n],
        &trig.c4[..n],
        &trig.s4[..n],
    );
    out.clear();
    out.extend((0..n).map(|k| {
        let u2 = (c2[k], s2[k]);
        let u3 = cmul((c3[k], s3[k]), rot3.at(k));
        let u4 = cmul((c4[k], s4[k]), rot4.at(k));
        let r = residual(&at, u2, u3, u4);
        r.0 * r.0 + r.1 * r.1
    }));
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
///
/// A Newton step whose predicted relative decrease of the cost is at most `accept_relative`
/// is taken without the pass that would evaluate it (0: only the rounding criteria below):
/// from a start already near the minimum (the subset fit of `Auto`), the step after it would
/// change the answer by a small fraction of its standard error.
pub(crate) fn levenberg_marquardt<const NP: usize>(
    p0: [f64; 8],
    mut eval: impl FnMut(&[f64; 8]) -> Normal<NP>,
    max_iterations: u32,
    tol: f64,
    accept_relative: f64,
) -> (Refined, Normal<NP>) {
    let mut p = p0;
    for v in p.iter_mut().skip(NP) {
        *v = 0.0;
    }
    let mut ne = eval(&p);
    let mut mu = 1e-6;
    let mut last_newton_relative: Option<f64> = None;
    for it in 1..=max_iterations {
        let mut damping = SMatrix::<f64, NP, NP>::zeros();
        for i in 0..NP {
            damping[(i, i)] = mu * ne.jtj[(i, i)].abs().max(1e-12);
        }
        // Newton (exact Hessian: quadratic convergence even with noisy residuals) where it is
        // positive definite, else Gauss–Newton at the same damping
        let newton = (ne.jtj + ne.curv + damping).cholesky();
        let is_newton = newton.is_some();
        let chol = newton.or_else(|| (ne.jtj + damping).cholesky());
        let Some(delta) = chol.map(|c| c.solve(&(-ne.jtr))) else {
            mu *= 10.0;
            last_newton_relative = None;
            if mu > 1e12 {
                return (
                    Refined {
                        p,
                        iterations: it,
                        converged: false,
                    },
                    ne,
                );
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
        // Newton's steps near the minimum: the decrease squares each time (relative to the
        // cost, ~1e-2, 1e-5, 1e-10, 1e-20 on a noisy 6 000-sample fit), so once the last two
        // say the *next* one will be lost in rounding, this step ends it and the pass that
        // would evaluate it (and only confirm it) is skipped
        let relative = predicted / ne.cost_scale;
        let next_lost = is_newton
            && last_newton_relative
                .is_some_and(|last| relative < 1e-8 && relative * relative / last <= 1e-13);
        last_newton_relative = is_newton.then_some(relative);
        let near_enough = is_newton && relative <= accept_relative;
        if lost_in_rounding || next_lost || near_enough || step_small(&delta, &p, tol) {
            // converged whether or not the cost could tell this step from the current point
            // (a step below the tolerance, or a decrease below the cost's rounding): take it
            // without the pass that would only confirm it
            return (
                Refined {
                    p: trial,
                    iterations: it,
                    converged: true,
                },
                ne,
            );
        }
        let trial_ne = eval(&trial);
        if trial_ne.cost.is_finite() && trial_ne.cost <= ne.cost {
            let done = trial_ne.cost == 0.0;
            p = trial;
            ne = trial_ne;
            mu = (mu / 10.0).max(1e-15);
            if done {
                return (
                    Refined {
                        p,
                        iterations: it,
                        converged: true,
                    },
                    ne,
                );
            }
        } else {
            mu *= 10.0;
            last_newton_relative = None;
            if mu > 1e12 {
                // no decrease possible at any damping: a minimum to working precision
                return (
                    Refined {
                        p,
                        iterations: it,
                        converged: true,
                    },
                    ne,
                );
            }
        }
    }
    (
        Refined {
            p,
            iterations: max_iterations,
            converged: false,
        },
        ne,
    )
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
