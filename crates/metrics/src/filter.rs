//! The speed profile of an angle signal: differentiation and a zero-phase low-pass.

use serde::{Deserialize, Serialize};

/// A second-order (biquad) IIR section, `a0 = 1`, run in transposed direct form II.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Biquad {
    /// Numerator `b0, b1, b2`.
    pub b: [f64; 3],
    /// Denominator `a1, a2` (`a0 = 1`).
    pub a: [f64; 2],
}

impl Biquad {
    /// Second-order Butterworth low-pass with cut-off `fc_hz` at `fs_hz`, by the bilinear
    /// transform with the cut-off pre-warped (the design of `scipy.signal.butter(2, fc/(fs/2))`):
    /// `K = tan(π fc / fs)`, `b = K²·[1, 2, 1]/D`, `a = [2(K² − 1), 1 − √2K + K²]/D`,
    /// `D = 1 + √2K + K²`. Unity gain at DC, −3 dB at `fc_hz`.
    ///
    /// `None` unless `0 < fc_hz < fs_hz / 2` (both finite).
    #[must_use]
    pub fn butterworth_lowpass(fc_hz: f64, fs_hz: f64) -> Option<Self> {
        if !(fc_hz.is_finite() && fs_hz.is_finite() && fc_hz > 0.0 && fc_hz < fs_hz / 2.0) {
            return None;
        }
        let k = (std::f64::consts::PI * fc_hz / fs_hz).tan();
        let s2 = std::f64::consts::SQRT_2;
        let d = 1.0 + s2 * k + k * k;
        let b0 = k * k / d;
        Some(Self {
            b: [b0, 2.0 * b0, b0],
            a: [2.0 * (k * k - 1.0) / d, (1.0 - s2 * k + k * k) / d],
        })
    }

    /// The state `[z1, z2]` of a filter that has seen the input 1 forever (`scipy.signal.
    /// lfilter_zi`): `z1 = g − b0`, `z2 = b2 − a2·g` with `g` the DC gain.
    #[must_use]
    pub fn steady_state(&self) -> [f64; 2] {
        let g = (self.b[0] + self.b[1] + self.b[2]) / (1.0 + self.a[0] + self.a[1]);
        [g - self.b[0], self.b[2] - self.a[1] * g]
    }

    /// One step: input `x`, state `z` updated in place, output returned.
    #[inline]
    pub fn step(&self, x: f64, z: &mut [f64; 2]) -> f64 {
        let y = self.b[0] * x + z[0];
        z[0] = self.b[1] * x - self.a[0] * y + z[1];
        z[1] = self.b[2] * x - self.a[1] * y;
        y
    }

    /// Zero-phase filtering, forward then backward, as `scipy.signal.filtfilt(b, a, x)` with
    /// its defaults: odd extension of `min(9, n − 1)` samples at each end (`padlen =
    /// 3·max(len(a), len(b))`), each pass started from the steady state scaled by its first
    /// input. The magnitude response is squared (a 4th-order, −6 dB at `fc` response) and the
    /// phase is zero. Signals of fewer than 2 samples are returned unchanged.
    #[must_use]
    pub fn filtfilt(&self, x: &[f64]) -> Vec<f64> {
        let n = x.len();
        if n < 2 {
            return x.to_vec();
        }
        let pad = 9.min(n - 1);
        let mut ext = Vec::with_capacity(n + 2 * pad);
        ext.extend((1..=pad).rev().map(|i| 2.0 * x[0] - x[i]));
        ext.extend_from_slice(x);
        ext.extend((1..=pad).map(|i| 2.0 * x[n - 1] - x[n - 1 - i]));
        let zi = self.steady_state();
        let mut z = zi.map(|v| v * ext[0]);
        for v in &mut ext {
            *v = self.step(*v, &mut z);
        }
        let last = ext[ext.len() - 1];
        let mut z = zi.map(|v| v * last);
        for v in ext.iter_mut().rev() {
            *v = self.step(*v, &mut z);
        }
        ext[pad..pad + n].to_vec()
    }
}

/// Derivative of `x` sampled at `fs_hz` by central differences in the interior and one-sided
/// first differences at the two ends (`numpy.gradient(x, 1/fs)`). Empty for an empty input,
/// zero for a single sample.
#[must_use]
pub fn derivative(x: &[f64], fs_hz: f64) -> Vec<f64> {
    let n = x.len();
    match n {
        0 => Vec::new(),
        1 => vec![0.0],
        _ => (0..n)
            .map(|i| {
                if i == 0 {
                    (x[1] - x[0]) * fs_hz
                } else if i == n - 1 {
                    (x[n - 1] - x[n - 2]) * fs_hz
                } else {
                    (x[i + 1] - x[i - 1]) * fs_hz / 2.0
                }
            })
            .collect(),
    }
}

/// Speed profile of an angle signal, rad/s: `|filtfilt(d/dt θ)|` — the central-difference
/// derivative ([`derivative`]), low-passed forward and backward by a 2nd-order Butterworth at
/// `lowpass_hz` ([`Biquad::filtfilt`]), then the absolute value (taken last, so the filter does
/// not smear a rectified signal). When `lowpass_hz` is not below `fs/2` no filter is applied.
#[must_use]
pub fn speed_profile(angle: &[f64], fs_hz: f64, lowpass_hz: f64) -> Vec<f64> {
    let rate = derivative(angle, fs_hz);
    let smooth = match Biquad::butterworth_lowpass(lowpass_hz, fs_hz) {
        Some(f) => f.filtfilt(&rate),
        None => rate,
    };
    smooth.into_iter().map(f64::abs).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn butterworth_has_unity_dc_gain_and_passes_a_constant() {
        let f = Biquad::butterworth_lowpass(10.0, 100.0).unwrap();
        let y = f.filtfilt(&[2.5; 50]);
        assert!(y.iter().all(|v| (v - 2.5).abs() < 1e-12), "{y:?}");
        assert!(Biquad::butterworth_lowpass(50.0, 100.0).is_none());
    }

    #[test]
    fn derivative_of_a_ramp_is_its_slope() {
        let x: Vec<f64> = (0..10).map(|i| 0.3 * f64::from(i)).collect();
        assert!(
            derivative(&x, 100.0)
                .iter()
                .all(|d| (d - 30.0).abs() < 1e-9)
        );
    }
}
