//! One pass of the batch fit over the samples: the directions turned back by the current
//! heading estimate and the normal equations of the loop (module docs, eq. (1)) accumulated
//! from their distinct running sums.
//!
//! `AᵀA` of the rows `A_k = [I₃ | u | f | h(u) | h(f) | t·h(u) | t·h(f)]` has 45 entries but,
//! with `h(v) = (v_y, −v_x, 0)`, only 17 distinct sample sums (`u·h(u) = 0`,
//! `u·h(f) = −f·h(u) = (u × f)_z`, `h(u)·h(f) = u_xy·f_xy`, …): the pass accumulates those
//! and [`Sums::normal`] lays them out, instead of a 3×9 outer product per sample.
//!
//! Its sums also give the curvature of the loop in the heading angles, `Σ tᵐ·r·v_xy` per
//! segment, at any shoulder and lengths, which turns the heading re-rotation into a Newton
//! iteration (see [`Sums::newton_normal`]).

use super::ArmLoopSamples;
use super::solve::{Normal, P_MAX};
use crate::fourbar::trig::sin_cos;

/// The running sums of one pass (wheel frame, directions turned back by the heading).
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Sums {
    n: f64,
    /// Σu, Σf, Σg.
    su: [f64; 3],
    sf: [f64; 3],
    sg: [f64; 3],
    /// Σt·u_xy, Σt·f_xy.
    tu: [f64; 2],
    tf: [f64; 2],
    /// Σ|u|², Σ|f|², Σu·f.
    uu: f64,
    ff: f64,
    uf: f64,
    /// Σ(u × f)_z and Σt·(u × f)_z.
    cz: [f64; 2],
    /// Σtᵐ|u_xy|², Σtᵐ|f_xy|², Σtᵐ u_xy·f_xy for m = 0, 1, 2.
    huu: [f64; 3],
    hff: [f64; 3],
    huf: [f64; 3],
    /// Σu·g, Σf·g.
    ug: f64,
    fg: f64,
    /// Σtᵐ h(u)·g, Σtᵐ h(f)·g for m = 0, 1.
    hug: [f64; 2],
    hfg: [f64; 2],
    /// Σ|g|².
    gg: f64,
    /// Σt²·u_xy, Σt²·f_xy.
    ttu: [f64; 2],
    ttf: [f64; 2],
    /// Σtᵐ g_xy·u_xy, Σtᵐ g_xy·f_xy for m = 0, 1, 2.
    gu: [f64; 3],
    gf: [f64; 3],
}

/// Heading of each segment at `t = 0` and its rate, `[upper, fore]` (rad, rad per time unit).
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Heading {
    pub psi: [f64; 2],
    pub rate: [f64; 2],
}

/// `(cos, sin)` of the turn back `−(ψ + ψ̇·tₖ)` of one segment, sample after sample: on a
/// uniform time axis one complex product per sample (the same turn by `ψ̇·Δt` each time),
/// recomputed exactly every [`Turner::RESYNC`] samples so rounding cannot accumulate;
/// otherwise a `sin_cos` per sample.
struct Turner {
    psi: f64,
    rate: f64,
    step: Option<(f64, f64)>,
    cur: (f64, f64),
}

impl Turner {
    /// Samples between exact evaluations.
    const RESYNC: usize = 16;

    fn new(psi: f64, rate: f64, dt: Option<f64>) -> Self {
        let step = dt.map(|dt| {
            let (s, c) = sin_cos(-rate * dt);
            (c, s)
        });
        Self {
            psi,
            rate,
            step,
            cur: (1.0, 0.0),
        }
    }

    /// The turn at sample `k` (time `t`); called for k = 0, 1, 2, … in order.
    #[inline]
    fn at(&mut self, k: usize, t: f64) -> (f64, f64) {
        match self.step {
            Some((c, s)) if !k.is_multiple_of(Self::RESYNC) => {
                let (a, b) = self.cur;
                self.cur = (a * c - b * s, a * s + b * c);
            }
            _ => {
                let (s, c) = sin_cos(-(self.psi + self.rate * t));
                self.cur = (c, s);
            }
        }
        self.cur
    }

    #[inline]
    fn apply(rot: (f64, f64), v: &[f64; 3]) -> [f64; 3] {
        let (c, s) = rot;
        [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
    }
}

impl Sums {
    /// One pass: directions `upper`, `fore` turned back by `heading` (when `turn`), grip
    /// points `grip`, times `time(k)` (evenly spaced by `dt` when `Some`).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn pass(
        upper: &[[f64; 3]],
        fore: &[[f64; 3]],
        grip: &[[f64; 3]],
        time: impl Fn(usize) -> f64,
        dt: Option<f64>,
        heading: &Heading,
        turn: bool,
    ) -> Self {
        let mut s = Self::default();
        let mut tu = Turner::new(heading.psi[0], heading.rate[0], dt);
        let mut tf = Turner::new(heading.psi[1], heading.rate[1], dt);
        for k in 0..upper.len() {
            let t = time(k);
            if turn {
                let u = Turner::apply(tu.at(k, t), &upper[k]);
                let f = Turner::apply(tf.at(k, t), &fore[k]);
                s.add(&u, &f, &grip[k], t);
            } else {
                s.add(&upper[k], &fore[k], &grip[k], t);
            }
        }
        s
    }

    #[inline]
    fn add(&mut self, u: &[f64; 3], f: &[f64; 3], g: &[f64; 3], t: f64) {
        let tt = t * t;
        self.n += 1.0;
        for i in 0..3 {
            self.su[i] += u[i];
            self.sf[i] += f[i];
            self.sg[i] += g[i];
        }
        for i in 0..2 {
            self.tu[i] += t * u[i];
            self.tf[i] += t * f[i];
        }
        let uxy = u[0] * u[0] + u[1] * u[1];
        let fxy = f[0] * f[0] + f[1] * f[1];
        let ufxy = u[0] * f[0] + u[1] * f[1];
        self.uu += uxy + u[2] * u[2];
        self.ff += fxy + f[2] * f[2];
        self.uf += ufxy + u[2] * f[2];
        let cz = u[0] * f[1] - u[1] * f[0];
        self.cz[0] += cz;
        self.cz[1] += t * cz;
        for (m, tm) in [1.0, t, tt].into_iter().enumerate() {
            self.huu[m] += tm * uxy;
            self.hff[m] += tm * fxy;
            self.huf[m] += tm * ufxy;
        }
        self.ug += u[0] * g[0] + u[1] * g[1] + u[2] * g[2];
        self.fg += f[0] * g[0] + f[1] * g[1] + f[2] * g[2];
        let hug = u[1] * g[0] - u[0] * g[1];
        let hfg = f[1] * g[0] - f[0] * g[1];
        self.hug[0] += hug;
        self.hug[1] += t * hug;
        self.hfg[0] += hfg;
        self.hfg[1] += t * hfg;
        self.gg += g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
        let (gu, gf) = (g[0] * u[0] + g[1] * u[1], g[0] * f[0] + g[1] * f[1]);
        for (m, tm) in [1.0, t, tt].into_iter().enumerate() {
            self.gu[m] += tm * gu;
            self.gf[m] += tm * gf;
        }
        for i in 0..2 {
            self.ttu[i] += tt * u[i];
            self.ttf[i] += tt * f[i];
        }
    }

    /// The normal equations `AᵀA`, `Aᵀb` of all nine columns.
    pub(crate) fn normal(&self) -> Normal<P_MAX> {
        let mut nm = Normal::<P_MAX>::new();
        let h = |v: [f64; 2]| [v[1], -v[0], 0.0];
        let (hu, hf) = (h([self.su[0], self.su[1]]), h([self.sf[0], self.sf[1]]));
        let (htu, htf) = (h(self.tu), h(self.tf));
        let m = &mut nm.m;
        for i in 0..3 {
            m[(i, i)] = self.n;
            for (j, col) in [self.su, self.sf, hu, hf, htu, htf].iter().enumerate() {
                m[(i, 3 + j)] = col[i];
            }
        }
        m[(3, 3)] = self.uu;
        m[(3, 4)] = self.uf;
        m[(4, 4)] = self.ff;
        // u·h(u) = f·h(f) = 0; u·h(f) = (u × f)_z = −f·h(u)
        m[(3, 6)] = self.cz[0];
        m[(4, 5)] = -self.cz[0];
        m[(3, 8)] = self.cz[1];
        m[(4, 7)] = -self.cz[1];
        m[(5, 5)] = self.huu[0];
        m[(5, 6)] = self.huf[0];
        m[(6, 6)] = self.hff[0];
        m[(5, 7)] = self.huu[1];
        m[(5, 8)] = self.huf[1];
        m[(6, 7)] = self.huf[1];
        m[(6, 8)] = self.hff[1];
        m[(7, 7)] = self.huu[2];
        m[(7, 8)] = self.huf[2];
        m[(8, 8)] = self.hff[2];
        for i in 0..P_MAX {
            for j in 0..i {
                m[(i, j)] = m[(j, i)];
            }
        }
        let v = [
            self.sg[0],
            self.sg[1],
            self.sg[2],
            self.ug,
            self.fg,
            self.hug[0],
            self.hfg[0],
            self.hug[1],
            self.hfg[1],
        ];
        nm.v = nalgebra::SVector::<f64, P_MAX>::from(v);
        nm.gg = self.gg;
        nm.w_sum = self.n;
        nm
    }

    /// The normal equations with the loop's curvature in the heading unknowns added to their
    /// block, at the shoulder and lengths `x = [S, l_u, l_f]`: with `x₅ = l_u·δψ_u`,
    /// `∂²r/∂x₅² = −u_xy / l_u` (and `t`, `t²` times it for the drift), so the Hessian of
    /// `½Σ|r|²` gains `−Σ tᵐ r·u_xy / l_u`, which the sums give at any `x` (`r·u_xy` is
    /// `S_xy·u_xy + l_u·|u_xy|² + l_f·u_xy·f_xy − g_xy·u_xy`). Only the heading block
    /// changes, and the heading unknowns are zero at the fixed point of the re-rotation, so
    /// the answer is the same; the passes converge quadratically instead of linearly (the
    /// Gauss–Newton block alone counts the direction noise as curvature). `None` when a length
    /// is zero.
    pub(crate) fn newton_normal(&self, x: [f64; 5], p: usize) -> Option<Normal<P_MAX>> {
        let mut nm = self.normal();
        let (lu, lf) = (x[3], x[4]);
        if !(lu.abs() > 0.0 && lf.abs() > 0.0) {
            return None;
        }
        let moments =
            |v: [[f64; 2]; 3], own: &[f64; 3], cross: &[f64; 3], g: &[f64; 3], l_own, l_cross| {
                let mut c = [0.0; 3];
                for m in 0..3 {
                    c[m] = x[0] * v[m][0] + x[1] * v[m][1] + l_own * own[m] + l_cross * cross[m]
                        - g[m];
                }
                c
            };
        let su = [[self.su[0], self.su[1]], self.tu, self.ttu];
        let sf = [[self.sf[0], self.sf[1]], self.tf, self.ttf];
        let cu = moments(su, &self.huu, &self.huf, &self.gu, lu, lf);
        let cf = moments(sf, &self.hff, &self.huf, &self.gf, lf, lu);
        let m = &mut nm.m;
        m[(5, 5)] -= cu[0] / lu;
        m[(6, 6)] -= cf[0] / lf;
        if p >= 9 {
            m[(5, 7)] -= cu[1] / lu;
            m[(7, 5)] -= cu[1] / lu;
            m[(7, 7)] -= cu[2] / lu;
            m[(6, 8)] -= cf[1] / lf;
            m[(8, 6)] -= cf[1] / lf;
            m[(8, 8)] -= cf[2] / lf;
        }
        Some(nm)
    }
}

/// `Σ|S + l_u·u + l_f·f − G|²` (m²) over the samples with the directions turned back by
/// `heading` (when `turn`), at `x = [S, l_u, l_f]`.
pub(crate) fn ssr(
    samples: &ArmLoopSamples<'_>,
    time: impl Fn(usize) -> f64,
    dt: Option<f64>,
    heading: &Heading,
    turn: bool,
    x: [f64; 5],
) -> f64 {
    let mut tu = Turner::new(heading.psi[0], heading.rate[0], dt);
    let mut tf = Turner::new(heading.psi[1], heading.rate[1], dt);
    let mut ssr = 0.0;
    for k in 0..samples.len() {
        let (u0, f0, g) = (
            &samples.upper_dirs[k],
            &samples.fore_dirs[k],
            &samples.grip_points_m[k],
        );
        let (u, f) = if turn {
            let t = time(k);
            (
                Turner::apply(tu.at(k, t), u0),
                Turner::apply(tf.at(k, t), f0),
            )
        } else {
            (*u0, *f0)
        };
        for i in 0..3 {
            let r = x[i] + x[3] * u[i] + x[4] * f[i] - g[i];
            ssr += r * r;
        }
    }
    ssr
}

/// `[S, l_u, l_f]` of a solution vector.
pub(crate) fn head(x: &nalgebra::SVector<f64, P_MAX>) -> [f64; 5] {
    [x[0], x[1], x[2], x[3], x[4]]
}
