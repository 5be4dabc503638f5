//! Zero-phase Savitzky–Golay smoothing of the measured angles before a fit.
//!
//! Angle noise enters the loop through `e^{iφ}`, whose mean shrinks by `e^{−σ²/2}`: white
//! noise biases every least-squares fit of eq. 4.3 (errors in variables), not only spreads it.
//! Arm motion is slow (< 2 Hz) against 100 Hz and faster sampling, so a local cubic fit removes
//! most of the noise while leaving the motion itself (error of order (ωT)⁴) untouched.

/// Quadratic/cubic Savitzky–Golay smoothing with a centred window of `2·half_window + 1`
/// samples; near the ends the window shrinks symmetrically (so the filter stays zero-phase).
pub fn savitzky_golay(x: &[f64], half_window: usize) -> Vec<f64> {
    apply_window(x, half_window, |c| c)
}

/// Variance of [`savitzky_golay`]'s output when its input carries independent noise of
/// per-sample variance `var`: `Σⱼ cⱼ²·var[k+j]` with the same (edge-shrunk) windows.
pub fn savitzky_golay_variance(var: &[f64], half_window: usize) -> Vec<f64> {
    apply_window(var, half_window, |c| c * c)
}

/// `Σⱼ weight(cⱼ)·x[k+j]` over the Savitzky–Golay window at every `k`, where `cⱼ` are the
/// quadratic/cubic smoothing coefficients of the (edge-shrunk) window; windows under five
/// samples pass the sample through.
fn apply_window(x: &[f64], half_window: usize, weight: impl Fn(f64) -> f64) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|k| {
            let m = half_window.min(k).min(n - 1 - k);
            if m < 2 {
                return x[k];
            }
            let mf = m as f64;
            let norm = (2.0 * mf - 1.0) * (2.0 * mf + 1.0) * (2.0 * mf + 3.0);
            let mut acc = 0.0;
            for j in -(m as isize)..=(m as isize) {
                let jf = j as f64;
                let c = 3.0 * (3.0 * mf * mf + 3.0 * mf - 1.0 - 5.0 * jf * jf) / norm;
                acc += weight(c) * x[(k as isize + j) as usize];
            }
            acc
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_signals_pass_unchanged() {
        let x: Vec<f64> = (0..200)
            .map(|k| {
                let t = k as f64 * 0.01;
                1.0 - 2.0 * t + 0.5 * t * t - 0.3 * t * t * t
            })
            .collect();
        let y = savitzky_golay(&x, 25);
        for (a, b) in x.iter().zip(&y) {
            assert!((a - b).abs() < 1e-12);
        }
    }

    #[test]
    fn white_noise_variance_drops() {
        // deterministic pseudo-noise: alternating signs with varying magnitude
        let x: Vec<f64> = (0..1000)
            .map(|k| if k % 2 == 0 { 1.0 } else { -1.0 } * (1.0 + (k % 7) as f64 * 0.1))
            .collect();
        let y = savitzky_golay(&x, 25);
        let power = |v: &[f64]| v[25..975].iter().map(|a| a * a).sum::<f64>() / 950.0;
        assert!(power(&y) < 0.05 * power(&x));
    }

    #[test]
    fn smoothed_noise_variance_is_the_sum_of_squared_coefficients() {
        // interior of a ±25 cubic filter: Σc² = c₀ = 3(3m²+3m−1)/((2m−1)(2m+1)(2m+3))
        let v = savitzky_golay_variance(&vec![2.0; 200], 25);
        let c0 = 3.0 * (3.0 * 625.0 + 75.0 - 1.0) / (49.0 * 51.0 * 53.0);
        assert!((v[100] - 2.0 * c0).abs() < 1e-12, "{}", v[100]);
        assert_eq!(v[0], 2.0);
    }
}
