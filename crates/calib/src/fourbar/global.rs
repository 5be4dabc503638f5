//! The global solution that starts the four-bar's `Auto` method without an initial guess:
//! the closed form ([`super::closed_form`]), weighted and corrected for noise, then
//! re-weighted against outliers with the residuals of the iterative methods
//! ([`super::iterative`]). Its own module so that the closed form and the iterations do not
//! depend on each other.

use super::closed_form::{SqrtInfo, gram, solve_gram};
use super::eiv::{Gains, NoiseProfile};
use super::iterative::residual_norms2;
use super::median::median;
use super::model::{FourbarParams, FourbarSamples};
use super::scratch;
use super::trig::Trig;
use crate::error::CalibError;

/// The global solution used to start [`super::FourbarMethod::Auto`], still needing no initial
/// guess:
/// 1. the plain closed form ([`SqrtInfo::solve`]);
/// 2. with a noise profile: re-solved twice with the noise weights at the current lengths and
///    the errors-in-variables correction ([`super::eiv`], [`solve_gram`]);
/// 3. when `robust`: iteratively re-weighted with Cauchy factors `1/(1 + (ρ/c)²)` of the
///    standardised residual norms ρ, `c = 2.385σ̂` from their median (at most 5 rounds: the
///    LM refinement that follows finishes the job), so
///    gross outliers (a slipped gyro strap) lose their pull on the fit.
pub(crate) fn global_fit(
    s: &FourbarSamples<'_>,
    trig: &Trig,
    l2: f64,
    noise: Option<&NoiseProfile>,
    gains: Option<&Gains>,
    robust: bool,
) -> Result<FourbarParams, CalibError> {
    let (mut p, _) = SqrtInfo::from_samples(s, trig).solve(l2)?;
    let n = s.len();
    let mut nw = scratch::filled(n, 1.0);
    // a corrected normal matrix can lose definiteness when the noise rivals the motion: then
    // keep the weighted, uncorrected solution
    let solve = |w: &[f64]| {
        solve_gram(&gram(trig, Some(w), gains), l2)
            .or_else(|_| solve_gram(&gram(trig, Some(w), None), l2))
    };
    if let Some(nz) = noise {
        for _ in 0..2 {
            nz.weights(l2, p.l3_m, p.l4_m, &mut nw);
            p = solve(&nw)?.0;
        }
    }
    if !robust {
        scratch::give(nw);
        return Ok(p);
    }
    let (mut norms, mut scratch, mut w) =
        (scratch::take(n), scratch::take(n), scratch::filled(n, 1.0));
    for _ in 0..5 {
        // squared standardised norms ρ²: the Cauchy factor needs no root
        residual_norms2(trig, l2, &p.to_vec8(), &mut norms);
        for (r2, wn) in norms.iter_mut().zip(&nw) {
            *r2 *= wn;
        }
        let median = median(&norms, &mut scratch).sqrt();
        let c = (2.385 * median / 1.1774).max(1e-12 * l2);
        let inv_c2 = 1.0 / (c * c);
        for ((wk, r2), wn) in w.iter_mut().zip(&norms).zip(&nw) {
            *wk = wn / (1.0 + r2 * inv_c2);
        }
        let next = solve(&w)?.0;
        let change = (next.to_vec8().iter().zip(p.to_vec8()))
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        p = next;
        if change < 1e-7 * l2 {
            break;
        }
    }
    for v in [nw, norms, scratch, w] {
        scratch::give(v);
    }
    Ok(p)
}
