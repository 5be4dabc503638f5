//! Errors in variables: the angle noise estimated from the data, the sample weights it implies,
//! and the correction that removes the bias it causes in the loop fit.
//!
//! The thesis fits eq. 4.3, `Σ|ΔX|²`, treating the measured angles as exact. They are not: with
//! white noise `n ~ N(0, σ²)` on an angle, `E[e^{i(φ+n)}] = e^{−σ²/2}·e^{iφ}`, so every cross
//! term of the loop's normal matrix shrinks while the squared moduli (`|e^{iφ}|² = 1`) do not.
//! The least-squares fit then shortens the links by an amount the problem's conditioning
//! amplifies (about 1 % at 5 % noise, 19 % at 25 %), and more samples do not help.
//!
//! The corrected cost (an adjusted least-squares / corrected-score estimator) multiplies each
//! link's unit vector by the gain `g = e^{σ²/2}` and subtracts the noise's expected
//! contribution:
//!
//! `Σₖ uₖ·( |l2·g2ₖ·e^{iθ2} + l3·g3ₖ·e^{iθ3} − l4·g4ₖ·e^{iθ4} − l1|² − Σⱼ lⱼ²(gⱼₖ² − 1) )`,
//!
//! whose expectation over the noise is the noise-free cost, so its minimiser is consistent.
//! The weights `uₖ = 1/Var(ΔXₖ)` (to first order `Var(ΔXₖ) = Σⱼ lⱼ²σⱼₖ²`) make it the
//! generalised least-squares fit when the noise level changes over the recording (it does in
//! the thesis's noise model, where σ is a fraction of the angle itself).
//!
//! The per-sample variances σⱼₖ² come from the data alone: the fourth difference of each
//! channel annihilates the (slow, locally cubic) motion and leaves `70σ²` of white noise; its
//! square is capped against gross glitches and averaged over ±[`NOISE_HALF_WINDOW`] samples.

use super::median::{median_every, median_stride};
use super::model::FourbarSamples;
use super::scratch;

/// Half-width (samples) of the moving average of squared fourth differences.
pub const NOISE_HALF_WINDOW: usize = 5;

/// Σ of the squared fourth-difference coefficients (1, −4, 6, −4, 1).
const FOURTH_DIFF_GAIN: f64 = 70.0;

/// Squared differences above this multiple of their median are clipped (gross glitches,
/// ≈ 9.5σ for homoscedastic noise; loose enough for noise whose level changes ten-fold over a
/// recording), so a single spike inflates its neighbours' noise estimate less.
const CLIP_OVER_MEDIAN: f64 = 200.0;

/// Noise weights are floored at this fraction of their mean variance (so an almost noise-free
/// stretch does not take all the weight).
const VARIANCE_FLOOR: f64 = 1e-3;

/// Estimated white-noise variance of each measured angle at each sample (rad²).
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseProfile {
    /// Variance of φ2 per sample (rad²).
    pub var2: Vec<f64>,
    /// Variance of φ3 per sample (rad²).
    pub var3: Vec<f64>,
    /// Variance of φ4 per sample (rad²).
    pub var4: Vec<f64>,
}

impl NoiseProfile {
    /// Estimate the per-sample noise variances of a recording (see the module documentation).
    pub fn estimate(s: &FourbarSamples<'_>) -> Self {
        Self {
            var2: channel_variance(s.phi2),
            var3: channel_variance(s.phi3),
            var4: channel_variance(s.phi4),
        }
    }

    /// The variances after the zero-phase Savitzky–Golay smoother of half-width `half_window`
    /// ([`super::smoothing::savitzky_golay`]) has been applied to the angles.
    pub fn smoothed(&self, half_window: usize) -> Self {
        use super::smoothing::savitzky_golay_variance as sgv;
        Self {
            var2: sgv(&self.var2, half_window),
            var3: sgv(&self.var3, half_window),
            var4: sgv(&self.var4, half_window),
        }
    }

    /// Hand the arrays back to [`super::scratch`] for the next calibration on this thread.
    pub(crate) fn recycle(self) {
        for v in [self.var2, self.var3, self.var4] {
            scratch::give(v);
        }
    }

    /// Root-mean-square noise of each channel `[φ2, φ3, φ4]` (rad).
    pub fn rms_rad(&self) -> [f64; 3] {
        let rms = |v: &[f64]| (v.iter().sum::<f64>() / v.len().max(1) as f64).sqrt();
        [rms(&self.var2), rms(&self.var3), rms(&self.var4)]
    }

    /// Relative sample weights `mean(V)/max(Vₖ, floor)` for the loop residual's variance
    /// `Vₖ = l2²σ2ₖ² + l3²σ3ₖ² + l4²σ4ₖ²` (m²), written into `out`. Uniform when no noise was
    /// found.
    pub(crate) fn weights(&self, l2: f64, l3: f64, l4: f64, out: &mut Vec<f64>) {
        let (a, b, c) = (l2 * l2, l3 * l3, l4 * l4);
        out.clear();
        out.resize(self.var2.len(), 0.0);
        // slices zipped, not indexed: no bounds checks, two samples per instruction
        for (o, ((v2, v3), v4)) in out
            .iter_mut()
            .zip(self.var2.iter().zip(&self.var3).zip(&self.var4))
        {
            *o = a * v2 + b * v3 + c * v4;
        }
        let mean = out.iter().sum::<f64>() / out.len().max(1) as f64;
        if !(mean > 0.0 && mean.is_finite()) {
            out.iter_mut().for_each(|w| *w = 1.0);
            return;
        }
        let floor = VARIANCE_FLOOR * mean;
        out.iter_mut().for_each(|w| *w = mean / w.max(floor));
    }

    /// The weights of [`Self::weights`] at other lengths ([`NoiseWeights::fill`]), for a pass
    /// that reweights as it goes: the mean variance from the channels' means (the same value
    /// up to rounding; each mean summed in four interleaved partial sums, so the additions do
    /// not wait on each other).
    pub(crate) fn weight_fn(&self, l2: f64, l3: f64, l4: f64) -> NoiseWeights {
        let (a, b, c) = (l2 * l2, l3 * l3, l4 * l4);
        let n = self.var2.len().max(1) as f64;
        let mean_of = |v: &[f64]| {
            let mut lanes = [0.0; 4];
            let chunks = v.chunks_exact(4);
            let tail: f64 = chunks.remainder().iter().sum();
            for q in chunks {
                for (l, x) in lanes.iter_mut().zip(q) {
                    *l += x;
                }
            }
            ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail) / n
        };
        let mean = a * mean_of(&self.var2) + b * mean_of(&self.var3) + c * mean_of(&self.var4);
        NoiseWeights {
            coefficients: [a, b, c],
            mean,
            floor: VARIANCE_FLOOR * mean,
            uniform: !(mean > 0.0 && mean.is_finite()),
        }
    }

    /// The bias-correction gains `gⱼₖ = e^{σⱼₖ²/2}`.
    pub(crate) fn gains(&self) -> Gains {
        let g = |v: &[f64]| {
            // the series for every sample (no branch: two samples per instruction), then
            // `exp` for the rare variance outside its range
            let mut out = scratch::collect(v.iter().map(|s2| half_exp_series(*s2)), v.len());
            for (o, s2) in out.iter_mut().zip(v) {
                if !SERIES_RANGE.contains(s2) {
                    *o = (0.5 * s2).exp();
                }
            }
            out
        };
        Gains {
            g2: g(&self.var2),
            g3: g(&self.var3),
            g4: g(&self.var4),
        }
    }
}

/// `e^{x/2}` as [`NoiseProfile::gains`] computes it: for the small variances of real angle
/// noise (x < 0.01 rad²) its Taylor series to the 6th power (error below 2e-17 relative), a
/// few multiplications instead of a libm call per sample and channel; else `exp`.
#[cfg(test)]
fn half_exp(x: f64) -> f64 {
    if SERIES_RANGE.contains(&x) {
        half_exp_series(x)
    } else {
        (0.5 * x).exp()
    }
}

/// Variances (rad²) for which [`half_exp_series`] is used.
const SERIES_RANGE: std::ops::Range<f64> = 0.0..0.01;

/// `e^{x/2}` by its Taylor series to the 6th power (for x in [`SERIES_RANGE`]).
#[inline(always)]
fn half_exp_series(x: f64) -> f64 {
    let h = 0.5 * x;
    1.0 + h * (1.0 + h * (0.5 + h * (1.0 / 6.0 + h * (1.0 / 24.0 + h * (1.0 / 120.0 + h / 720.0)))))
}

/// [`NoiseProfile::weights`] of given lengths, sample by sample.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NoiseWeights {
    /// `[l2², l3², l4²]` (m²).
    coefficients: [f64; 3],
    /// Mean loop-residual variance (m²).
    mean: f64,
    /// Floor of a sample's variance (m²).
    floor: f64,
    /// No noise found: every weight 1.
    uniform: bool,
}

impl NoiseWeights {
    /// The weights of the samples whose angle variances are `v2`, `v3`, `v4` (rad²) into `out`
    /// (of their length): a loop of its own, two samples per instruction, so the pass that
    /// reads them does not wait on a division per sample.
    pub(crate) fn fill(&self, v2: &[f64], v3: &[f64], v4: &[f64], out: &mut [f64]) {
        if self.uniform {
            out.fill(1.0);
            return;
        }
        let [a, b, c] = self.coefficients;
        for (o, ((x2, x3), x4)) in out.iter_mut().zip(v2.iter().zip(v3).zip(v4)) {
            *o = self.mean / (a * x2 + b * x3 + c * x4).max(self.floor);
        }
    }
}

/// Per-sample gains `e^{σ²/2}` undoing the noise's shrinkage of `E[e^{iφ}]`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Gains {
    pub g2: Vec<f64>,
    pub g3: Vec<f64>,
    pub g4: Vec<f64>,
}

impl Gains {
    /// Hand the arrays back to [`super::scratch`] for the next calibration on this thread.
    pub(crate) fn recycle(self) {
        for v in [self.g2, self.g3, self.g4] {
            scratch::give(v);
        }
    }
}

/// Noise variance of one channel per sample (rad²): capped squared fourth differences / 70,
/// averaged over ±[`NOISE_HALF_WINDOW`] samples.
///
/// The cap only has to catch gross glitches (200× the median), so on long recordings the
/// median is taken over every [`super::median::median_stride`]-th difference: as good a
/// scale for that purpose, and a quarter of the selection's cost.
fn channel_variance(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    if n < 5 {
        return scratch::filled(n, 0.0);
    }
    let mut q = scratch::collect(
        x.windows(5).map(|w| {
            let d = w[0] - 4.0 * w[1] + 6.0 * w[2] - 4.0 * w[3] + w[4];
            d * d / FOURTH_DIFF_GAIN
        }),
        n - 4,
    );
    let mut prefix = scratch::take(n - 3);
    let median = median_every(&q, median_stride(q.len()), &mut prefix);
    let cap = CLIP_OVER_MEDIAN * median;
    if cap > 0.0 {
        q.iter_mut().for_each(|v| *v = v.min(cap));
    }
    // q[i] is centred on sample i + 2; average the centres within ±W of each sample
    // filled in place, not pushed: a `push` per sum kept the running sum in memory (the
    // vector may grow), and the loop waited on storing and reloading it (the same sums)
    prefix.clear();
    prefix.resize(q.len() + 1, 0.0);
    let mut acc = 0.0;
    for (p, v) in prefix[1..].iter_mut().zip(&q) {
        acc += v;
        *p = acc;
    }
    let last = q.len() - 1;
    let edge = |k: usize| {
        let lo = (k.saturating_sub(NOISE_HALF_WINDOW + 2)).min(last);
        let hi = ((k + NOISE_HALF_WINDOW).saturating_sub(2))
            .min(last)
            .max(lo);
        (prefix[hi + 1] - prefix[lo]) / (hi + 1 - lo) as f64
    };
    let mut out = scratch::take(n);
    // the full windows (2W + 1 centres, samples W + 2 ..= n − 3 − W) as one difference of two
    // shifted prefix slices, the few at each end one by one
    let (w, first) = (NOISE_HALF_WINDOW, NOISE_HALF_WINDOW + 2);
    let end = (n - 2).saturating_sub(w).max(first);
    out.extend((0..first.min(n)).map(edge));
    if end > first {
        let (upper, lower) = (&prefix[first + w - 1..end + w - 1], &prefix[0..end - first]);
        let width = (2 * w + 1) as f64;
        out.extend(upper.iter().zip(lower).map(|(u, l)| (u - l) / width));
    }
    out.extend((out.len()..n).map(edge));
    scratch::give(q);
    scratch::give(prefix);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, Normal};

    #[test]
    fn noise_profile_finds_white_noise_and_ignores_smooth_motion() {
        let n = 4000;
        let smooth: Vec<f64> = (0..n).map(|k| (k as f64 * 0.0126).sin()).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let noise = Normal::new(0.0, 0.02).unwrap();
        // noise level ramps from 0.01 to 0.03 rad over the recording
        let noisy: Vec<f64> = smooth
            .iter()
            .enumerate()
            .map(|(k, v)| v + (0.5 + k as f64 / n as f64) * noise.sample(&mut rng))
            .collect();
        let quiet = NoiseProfile::estimate(&FourbarSamples::new(&smooth, &smooth, &smooth));
        assert!(
            quiet.rms_rad().iter().all(|r| *r < 1e-7),
            "{:?}",
            quiet.rms_rad()
        );
        let p = NoiseProfile::estimate(&FourbarSamples::new(&noisy, &smooth, &smooth));
        let mean = |a: usize, b: usize| p.var2[a..b].iter().sum::<f64>() / (b - a) as f64;
        let early = mean(0, 400).sqrt(); // true ≈ 0.0110
        let late = mean(3600, 4000).sqrt(); // true ≈ 0.0290
        assert!((early / 0.0110 - 1.0).abs() < 0.15, "early {early}");
        assert!((late / 0.0290 - 1.0).abs() < 0.15, "late {late}");
    }

    #[test]
    fn gain_series_matches_exp_to_rounding_on_both_sides_of_its_switch() {
        for k in 0..=2000 {
            let x = k as f64 * 1e-5;
            let (ours, exact) = (half_exp(x), (0.5 * x).exp());
            assert!(
                (ours / exact - 1.0).abs() < 4e-16,
                "x={x}: {ours} vs {exact}"
            );
        }
    }

    #[test]
    fn a_glitch_does_not_inflate_the_noise_around_it() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let noise = Normal::new(0.0, 0.01).unwrap();
        let mut x: Vec<f64> = (0..1000).map(|_| noise.sample(&mut rng)).collect();
        x[500] += 0.5;
        let p = NoiseProfile::estimate(&FourbarSamples::new(&x, &x, &x));
        let peak = p.var2[490..510].iter().cloned().fold(0.0, f64::max).sqrt();
        // unclipped, the 0.5 rad spike would read as 0.15 rad of noise around it
        assert!(peak < 0.07, "noise near the glitch {peak} rad");
        let away = (p.var2[400..480].iter().sum::<f64>() / 80.0).sqrt();
        assert!(
            (away / 0.01 - 1.0).abs() < 0.2,
            "noise away from the glitch {away} rad"
        );
    }
}
