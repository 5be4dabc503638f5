//! Smoothness of one discrete movement's speed profile: SPARC and LDLJ.
//!
//! Both follow the published reference implementations exactly, so their numbers can be
//! compared with the literature: SPARC with siva82kb/SPARC's `sparc` (Balasubramanian,
//! Melendez-Calderon, Roby-Brami & Burdet 2015, "On the analysis of movement smoothness",
//! J NeuroEng Rehabil 12:112), LDLJ with monalysa's `log_dimensionless_jerk` for speed input
//! (Balasubramanian, Melendez-Calderon & Burdet 2012, IEEE TBME 59(8); Hogan & Sternad 2009,
//! J Mot Behav 41(6)). Both expect one movement (speed from rest to rest); segment a
//! continuous recording first ([`segment`](fn@crate::segment)).

use rustfft::{FftPlanner, num_complex::Complex};
use serde::{Deserialize, Serialize};

use crate::error::{MetricError, check_fs, check_signal};

/// Fewest samples SPARC and LDLJ accept (LDLJ's second difference needs three).
pub const MIN_SAMPLES: usize = 3;

/// Largest zero-padding level accepted: the FFT length is `2^(ceil(log2 n) + padlevel)`.
pub const MAX_PADLEVEL: u32 = 8;

/// Parameters of [`sparc`]; the defaults are those of Balasubramanian et al. 2015.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SparcParams {
    /// Zero-padding level: the FFT has `2^(ceil(log2 n) + padlevel)` points. Default 4;
    /// at most [`MAX_PADLEVEL`].
    pub padlevel: u32,
    /// Upper cut-off of the spectrum considered, Hz (`f_c`). Default 10 Hz. When it lies above
    /// the Nyquist frequency `fs/2`, `fs/2` is used (the reference would read the mirrored
    /// half of the spectrum there).
    pub fc_hz: f64,
    /// Amplitude threshold on the normalised magnitude spectrum (`V̄`), in (0, 1).
    /// Default 0.05.
    pub amp_th: f64,
}

impl Default for SparcParams {
    fn default() -> Self {
        Self {
            padlevel: 4,
            fc_hz: 10.0,
            amp_th: 0.05,
        }
    }
}

impl SparcParams {
    /// Check every field against its allowed range.
    ///
    /// # Errors
    /// [`MetricError::BadParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), MetricError> {
        let bad = |field, value, allowed| MetricError::BadParameter {
            context: "SparcParams",
            field,
            value,
            allowed,
        };
        if self.padlevel > MAX_PADLEVEL {
            return Err(bad("padlevel", f64::from(self.padlevel), "0 ..= 8"));
        }
        if !(self.fc_hz.is_finite() && self.fc_hz > 0.0) {
            return Err(bad("fc_hz", self.fc_hz, "finite and > 0 Hz"));
        }
        if !(self.amp_th > 0.0 && self.amp_th < 1.0) {
            return Err(bad("amp_th", self.amp_th, "0 < amp_th < 1"));
        }
        Ok(())
    }
}

/// SPectral ARC length (SPARC) of a speed profile: a dimensionless smoothness score, ≤ 0,
/// closer to 0 is smoother (Balasubramanian et al. 2015, eq. 4–5).
///
/// `speed` is one movement's speed profile in any unit (m/s, rad/s: SPARC is invariant to
/// amplitude), sampled at `fs_hz`. As in the reference code (siva82kb/SPARC):
///
/// 1. `V(f) = |FFT(speed, N)|` with `N = 2^(ceil(log2 n) + padlevel)` (zero-padded),
///    at `f_k = k·fs/N`;
/// 2. `V̂(f) = V(f) / max V` (for a speed profile, which is ≥ 0, the maximum is the DC value);
/// 3. keep the bins with `f_k ≤ f_c`, then only those from the first to the last bin with
///    `V̂ ≥ amp_th` (the adaptive cut-off `ω_c`);
/// 4. `SPARC = −Σ sqrt( (Δf / (f_last − f_first))² + (ΔV̂)² )` over that band: the arc length
///    of the spectrum with frequency normalised by the band's width (which is `ω_c` when, as
///    for any speed profile, the band starts at DC).
///
/// # Errors
/// Fewer than [`MIN_SAMPLES`] samples, a non-finite sample (its index is named), `fs_hz`
/// not finite and > 0, parameters out of range, or a spectrum that is zero (all-zero input)
/// or has a single bin above the threshold.
///
/// # Example
/// ```
/// // A 1 s minimum-jerk movement at 100 Hz (Balasubramanian 2015 reference value −1.40583).
/// let v: Vec<f64> = (0..=100)
///     .map(|i| {
///         let t = f64::from(i) * 0.01;
///         30.0 * t.powi(2) - 60.0 * t.powi(3) + 30.0 * t.powi(4)
///     })
///     .collect();
/// let s = metrics::sparc(&v, 100.0, metrics::SparcParams::default()).unwrap();
/// assert!((s - -1.40583).abs() < 1e-5);
/// ```
pub fn sparc(speed: &[f64], fs_hz: f64, params: SparcParams) -> Result<f64, MetricError> {
    check_fs(fs_hz)?;
    params.validate()?;
    check_signal("speed", speed, MIN_SAMPLES)?;
    let n = speed.len();
    // 2^(ceil(log2 n) + padlevel): next_power_of_two is 2^ceil(log2 n) for n ≥ 1.
    let nfft = n.next_power_of_two() << params.padlevel;
    let mut buf: Vec<Complex<f64>> = speed
        .iter()
        .map(|&v| Complex::new(v, 0.0))
        .chain(std::iter::repeat(Complex::new(0.0, 0.0)))
        .take(nfft)
        .collect();
    FftPlanner::new().plan_fft_forward(nfft).process(&mut buf);

    let df = fs_hz / nfft as f64;
    let fc = params.fc_hz.min(fs_hz / 2.0);
    // Bins k with k·df ≤ fc (the reference compares the frequencies themselves).
    let kept = buf
        .iter()
        .enumerate()
        .take_while(|&(k, _)| k as f64 * df <= fc)
        .count();
    let peak = buf.iter().map(|c| c.norm()).fold(0.0, f64::max);
    if peak <= 0.0 {
        return Err(MetricError::Degenerate {
            signal: "speed".into(),
            why: "the spectrum is zero (all samples 0): SPARC is undefined",
        });
    }
    let mag: Vec<f64> = buf[..kept].iter().map(|c| c.norm() / peak).collect();
    let (Some(first), Some(last)) = (
        mag.iter().position(|&m| m >= params.amp_th),
        mag.iter().rposition(|&m| m >= params.amp_th),
    ) else {
        return Err(MetricError::Degenerate {
            signal: "speed".into(),
            why: "no spectral bin up to fc reaches the amplitude threshold",
        });
    };
    if last == first {
        return Err(MetricError::Degenerate {
            signal: "speed".into(),
            why: "a single spectral bin reaches the amplitude threshold: no arc to measure",
        });
    }
    // Frequencies are k·df, so Δf/(f_last − f_first) = 1/(last − first) for every step.
    let step = 1.0 / (last - first) as f64;
    let arc: f64 = mag[first..=last]
        .windows(2)
        .map(|w| step.hypot(w[1] - w[0]))
        .sum();
    Ok(-arc)
}

/// Log dimensionless jerk (LDLJ) of a speed profile: a smoothness score, < 0 for real
/// movements, closer to 0 is smoother (Hogan & Sternad 2009; Balasubramanian et al. 2012,
/// 2015; monalysa's `log_dimensionless_jerk` with `data_type="speed"`).
///
/// `LDLJ = −ln( T³ / v_peak² · ∫ (d²v/dt²)² dt )` with, exactly as in monalysa:
/// - `T = n / fs` (the number of samples times the sample period, not `(n−1)/fs`), s;
/// - `v_peak = max |v|`;
/// - `d²v/dt²` by the second forward difference `(v[i+2] − 2v[i+1] + v[i]) / dt²`
///   (`numpy.diff(v, 2) / dt**2`, `n − 2` values);
/// - `∫ … dt` by the rectangle rule `Σ (d²v/dt²)² · dt`.
///
/// Invariant to the amplitude of `speed`; its unit does not matter.
///
/// # Errors
/// Fewer than [`MIN_SAMPLES`] samples, a non-finite sample (its index is named), `fs_hz`
/// not finite and > 0, an all-zero profile (no peak) or one with zero jerk everywhere
/// (LDLJ would be +∞).
pub fn ldlj_speed(speed: &[f64], fs_hz: f64) -> Result<f64, MetricError> {
    check_fs(fs_hz)?;
    check_signal("speed", speed, MIN_SAMPLES)?;
    let dt = 1.0 / fs_hz;
    let peak = speed.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if peak <= 0.0 {
        return Err(MetricError::Degenerate {
            signal: "speed".into(),
            why: "the speed is zero everywhere: LDLJ is undefined",
        });
    }
    let duration = speed.len() as f64 * dt;
    let jerk_sq: f64 = speed
        .windows(3)
        .map(|w| {
            let d2 = (w[2] - 2.0 * w[1] + w[0]) / (dt * dt);
            d2 * d2
        })
        .sum();
    let dimensionless = duration.powi(3) / (peak * peak) * jerk_sq * dt;
    if dimensionless <= 0.0 || !dimensionless.is_finite() {
        return Err(MetricError::Degenerate {
            signal: "speed".into(),
            why: "the speed profile has no jerk (a straight line): LDLJ would be +inf",
        });
    }
    Ok(-dimensionless.ln())
}
