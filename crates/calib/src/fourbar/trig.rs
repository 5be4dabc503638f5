//! A fast `sin_cos` for the calibration's hot passes, and the per-sample unit vectors
//! `e^{iφ}` of a recording computed once per call.
//!
//! The standard library computes `sin` and `cos` by two separate libm calls; the four-bar
//! passes need both for three angles per sample, and that was most of their time. Here the
//! angle is reduced to `r ∈ [−π/4, π/4]` by `x = k·π/2 + r` (Cody–Waite: π/2 split into three
//! parts so `k·P1` and `k·P2` are exact), then sin and cos of `r` come from fdlibm's minimax
//! polynomials (the kernels of the C library's own `sin` and `cos`) and the quadrant `k mod 4` picks signs. Accuracy
//! is a few ulp for |x| ≤ 1e5 rad; larger or non-finite angles fall back to the standard
//! library.

use super::model::FourbarSamples;
use super::scratch;

/// π/2 to 33 significant bits (so `k·P1` is exact for |k| < 2²⁰).
const PIO2_1: f64 = 1.570_796_326_734_125_6;
/// The next 33 bits of π/2.
const PIO2_2: f64 = 6.077_100_506_303_966e-11;
/// The rest of π/2.
const PIO2_3: f64 = 2.022_266_248_795_950_6e-21;
/// Largest |x| reduced here (rad); beyond, the standard library.
const FAST_LIMIT: f64 = 1e5;

/// The 1.5·2⁵² rounding constant: `(y + ROUNDER) − ROUNDER` rounds `y` to the nearest integer
/// (`f64::round` is a libm call on baseline x86-64), and `y + ROUNDER`'s low mantissa bits are
/// that integer (two's complement, |y| < 2⁵¹).
const ROUNDER: f64 = 6_755_399_441_055_744.0;

/// fdlibm's `__kernel_sin` coefficients (x³ … x¹³).
const S1: f64 = -0.16666666666666632;
const S2: f64 = 0.00833333333332249;
const S3: f64 = -0.0001984126982985795;
const S4: f64 = 2.7557313707070068e-06;
const S5: f64 = -2.5050760253406863e-08;
const S6: f64 = 1.58969099521155e-10;
/// fdlibm's `__kernel_cos` coefficients (x⁴ … x¹⁴).
const C1: f64 = 0.0416666666666666;
const C2: f64 = -0.001388888888887411;
const C3: f64 = 2.480158728947673e-05;
const C4: f64 = -2.7557314351390663e-07;
const C5: f64 = 2.087572321298175e-09;
const C6: f64 = -1.1359647557788195e-11;

/// `x = k·π/2 + r`: `(x·2/π + ROUNDER, sin r, cos r)` (see the module documentation).
#[inline(always)]
fn reduced(x: f64) -> (f64, f64, f64) {
    let y = x * std::f64::consts::FRAC_2_PI + ROUNDER;
    let k = y - ROUNDER;
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    let z = r * r;
    // fdlibm's minimax kernels on [−π/4, π/4] (k_sin.c, k_cos.c: error below 2⁻⁵⁸), six
    // coefficients each where the Taylor series needed nine
    let s = r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let tail = z * z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let c = w + (((1.0 - w) - hz) + tail);
    (y, s, c)
}

/// `(sin x, cos x)`, a few ulp accurate (see the module documentation).
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    // NaN and infinities go to the standard library too
    if x.is_nan() || x.abs() > FAST_LIMIT {
        return x.sin_cos();
    }
    let (y, s, c) = reduced(x);
    let k = y - ROUNDER;
    match (k as i64).rem_euclid(4) {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// [`sin_cos`] of every angle of `x`, appended to `sin` and `cos`: the same values, but the
/// quadrant is applied with bit operations instead of a branch, so the loop has none and the
/// compiler runs it two angles at a time (a recording's angles cross quadrants at random).
pub(crate) fn sin_cos_into(x: &[f64], sin: &mut Vec<f64>, cos: &mut Vec<f64>) {
    if !x.iter().all(|v| v.abs() <= FAST_LIMIT) {
        // NaN, infinities or huge angles: one at a time
        for &v in x {
            let (s, c) = sin_cos(v);
            sin.push(s);
            cos.push(c);
        }
        return;
    }
    let (s0, c0) = (sin.len(), cos.len());
    sin.resize(s0 + x.len(), 0.0);
    cos.resize(c0 + x.len(), 0.0);
    for ((&v, so), co) in x.iter().zip(&mut sin[s0..]).zip(&mut cos[c0..]) {
        let (y, s, c) = reduced(v);
        let q = y.to_bits();
        // odd quadrants swap sin and cos; q mod 4 ∈ {2, 3} negates sin, ∈ {1, 2} cos
        let swap = (q & 1).wrapping_neg();
        let (sb, cb) = (s.to_bits(), c.to_bits());
        let s1 = (sb & !swap) | (cb & swap);
        let c1 = (cb & !swap) | (sb & swap);
        *so = f64::from_bits(s1 ^ (((q >> 1) & 1) << 63));
        *co = f64::from_bits(c1 ^ ((((q + 1) >> 1) & 1) << 63));
    }
}

/// `cos φ` and `sin φ` of the three measured angles of every sample, and the time axis.
#[derive(Debug, Clone, Default)]
pub(crate) struct Trig {
    pub c2: Vec<f64>,
    pub s2: Vec<f64>,
    pub c3: Vec<f64>,
    pub s3: Vec<f64>,
    pub c4: Vec<f64>,
    pub s4: Vec<f64>,
    /// Time of each sample from the first (s, or the sample index).
    pub t: Vec<f64>,
    /// The sample interval when the samples are evenly spaced in time (to 1e-9 of it), which
    /// lets the passes rotate by the gyro drift with one complex product per sample.
    pub uniform_dt: Option<f64>,
}

impl Trig {
    pub(crate) fn new(s: &FourbarSamples<'_>) -> Self {
        let n = s.len();
        let mut out = Self {
            c2: scratch::take(n),
            s2: scratch::take(n),
            c3: scratch::take(n),
            s3: scratch::take(n),
            c4: scratch::take(n),
            s4: scratch::take(n),
            t: scratch::collect((0..n).map(|k| s.time(k)), n),
            uniform_dt: None,
        };
        // without timestamps the axis is the sample index, `k as f64` exactly: its step is 1
        // (what `uniform_step` finds, without a check of every sample)
        out.uniform_dt = match s.time_s {
            None if n >= 2 => Some(1.0),
            _ => uniform_step(&out.t),
        };
        for (phi, c, sn) in [
            (s.phi2, &mut out.c2, &mut out.s2),
            (s.phi3, &mut out.c3, &mut out.s3),
            (s.phi4, &mut out.c4, &mut out.s4),
        ] {
            sin_cos_into(phi, sn, c);
        }
        out
    }

    pub(crate) fn len(&self) -> usize {
        self.c2.len()
    }

    /// Hand the arrays back to [`scratch`] for the next calibration on this thread.
    pub(crate) fn recycle(self) {
        for v in [self.c2, self.s2, self.c3, self.s3, self.c4, self.s4, self.t] {
            scratch::give(v);
        }
    }
}

/// The common step of `t` when every sample lies within 1e-9 steps of `t₀ + k·Δt`.
pub(crate) fn uniform_step(t: &[f64]) -> Option<f64> {
    let n = t.len();
    if n < 2 {
        return None;
    }
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let tol = 1e-9 * dt.abs();
    (dt != 0.0
        && dt.is_finite()
        && t.iter()
            .enumerate()
            .all(|(k, &tk)| (tk - t[0] - k as f64 * dt).abs() <= tol))
    .then_some(dt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_sin_cos_matches_the_standard_library_to_a_few_ulp() {
        let mut worst = 0.0f64;
        let mut x = -2.0e4;
        while x < 2.0e4 {
            for y in [x, x * 1e-3, x * 1e-7] {
                let (s, c) = sin_cos(y);
                let (s0, c0) = y.sin_cos();
                worst = worst.max((s - s0).abs()).max((c - c0).abs());
            }
            x += 0.123_456_7;
        }
        assert!(worst < 1e-15, "worst abs error {worst:e}");
        // quadrant boundaries and exact values
        for k in -8..=8 {
            let y = k as f64 * std::f64::consts::FRAC_PI_2;
            let (s, c) = sin_cos(y);
            assert!((s - y.sin()).abs() < 1e-15 && (c - y.cos()).abs() < 1e-15);
        }
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        // the branch-free slice form gives the very same values, quadrant by quadrant
        let xs: Vec<f64> = (-4000..4000).map(|k| k as f64 * 0.003_7 + 1e-3).collect();
        let (mut s, mut c) = (Vec::new(), Vec::new());
        sin_cos_into(&xs, &mut s, &mut c);
        for (k, &x) in xs.iter().enumerate() {
            assert_eq!((s[k], c[k]), sin_cos(x), "x = {x}");
        }
        let (mut s, mut c) = (Vec::new(), Vec::new());
        sin_cos_into(&[0.5, 1e9, f64::NAN], &mut s, &mut c);
        assert_eq!((s[1], c[1]), 1e9f64.sin_cos());
        assert!(s[2].is_nan());
        assert!(sin_cos(f64::NAN).0.is_nan());
        assert_eq!(sin_cos(1e9), 1e9f64.sin_cos());
    }
}
