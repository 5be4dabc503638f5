//! Test–retest reliability of a measure: how much of its spread between patients is real and
//! how large a change must be to be more than measurement noise (issue 42).
//!
//! From a table of scores — `n` subjects, each measured on the same `k` occasions — a two-way
//! analysis of variance gives:
//!
//! - **ICC(2,1)**: the intraclass correlation, two-way random effects, absolute agreement, a
//!   single measurement (Shrout & Fleiss 1979, Psychol Bull 86:420, Table 1 case 2; McGraw &
//!   Wong 1996 "ICC(A,1)"):
//!   `ICC = (MSR − MSE) / (MSR + (k − 1)·MSE + k·(MSC − MSE)/n)`, with MSR the mean square
//!   between subjects, MSC between occasions and MSE the residual.
//! - **SEM**, the standard error of measurement, `SD·√(1 − ICC)` with SD the standard deviation
//!   of all scores (Weir 2005, J Strength Cond Res 19:231, eq. 6), in the measure's unit.
//! - **MDC95**, the minimal detectable change at 95 % confidence, `1.96·√2·SEM` (Weir 2005
//!   eq. 8): a change between two measurements of one patient smaller than this is within
//!   measurement noise. The "smallest real difference" of the rehabilitation literature is
//!   the same quantity.

use crate::MetricError;

/// `z` of the two-sided 95 % interval.
const Z_95: f64 = 1.96;

/// A measure's test–retest reliability.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Reliability {
    /// ICC(2,1), in [−1, 1] (1: every difference between scores is a difference between
    /// subjects).
    pub icc: f64,
    /// Standard error of measurement, in the measure's unit.
    pub sem: f64,
    /// Minimal detectable change (95 %), in the measure's unit.
    pub mdc95: f64,
    /// The mean of all scores, in the measure's unit (to state MDC95 as a share of it).
    pub grand_mean: f64,
    /// Subjects in the table.
    pub subjects: usize,
    /// Occasions (sessions) per subject.
    pub occasions: usize,
}

impl Reliability {
    /// MDC95 as a share of the mean score (0.23 = 23 %); `None` when the mean is 0.
    pub fn mdc95_relative(&self) -> Option<f64> {
        (self.grand_mean != 0.0).then(|| self.mdc95 / self.grand_mean.abs())
    }
}

/// The test–retest reliability of `scores`: `scores[i][j]` is subject `i` on occasion `j`.
/// Needs at least two subjects and two occasions, every row the same length, every score
/// finite.
pub fn test_retest(scores: &[Vec<f64>]) -> Result<Reliability, MetricError> {
    let n = scores.len();
    let k = scores.first().map_or(0, Vec::len);
    let too_few = |what: &str, len: usize| MetricError::TooShort {
        signal: format!("test-retest table: {what}"),
        len,
        min: 2,
    };
    if n < 2 {
        return Err(too_few("subjects", n));
    }
    if k < 2 {
        return Err(too_few("occasions of subject 0", k));
    }
    for (i, row) in scores.iter().enumerate() {
        if row.len() != k {
            return Err(MetricError::BadParameter {
                context: "test-retest table",
                field: "occasions per subject",
                value: row.len() as f64,
                allowed: "the same count for every subject (the first subject's)",
            });
        }
        if let Some((j, v)) = row.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(MetricError::NonFinite {
                signal: format!("test-retest table: subject {i}"),
                index: j,
                value: *v,
            });
        }
    }
    let (nf, kf) = (n as f64, k as f64);
    let grand_mean = scores.iter().flatten().sum::<f64>() / (nf * kf);
    let row_means: Vec<f64> = scores.iter().map(|r| r.iter().sum::<f64>() / kf).collect();
    let col_means: Vec<f64> = (0..k)
        .map(|j| scores.iter().map(|r| r[j]).sum::<f64>() / nf)
        .collect();
    let sq = |x: f64| x * x;
    let ss_total: f64 = scores.iter().flatten().map(|v| sq(v - grand_mean)).sum();
    let ss_rows = kf * row_means.iter().map(|m| sq(m - grand_mean)).sum::<f64>();
    let ss_cols = nf * col_means.iter().map(|m| sq(m - grand_mean)).sum::<f64>();
    let ss_err = (ss_total - ss_rows - ss_cols).max(0.0);
    let ms_rows = ss_rows / (nf - 1.0);
    let ms_cols = ss_cols / (kf - 1.0);
    let ms_err = ss_err / ((nf - 1.0) * (kf - 1.0));
    let denominator = ms_rows + (kf - 1.0) * ms_err + kf * (ms_cols - ms_err) / nf;
    // Every score equal: no spread to attribute, and no noise either.
    let icc = if denominator > 0.0 {
        (ms_rows - ms_err) / denominator
    } else {
        1.0
    };
    let sd = (ss_total / (nf * kf - 1.0)).sqrt();
    let sem = sd * (1.0 - icc.min(1.0)).sqrt();
    Ok(Reliability {
        icc,
        sem,
        mdc95: Z_95 * std::f64::consts::SQRT_2 * sem,
        grand_mean,
        subjects: n,
        occasions: k,
    })
}

/// Repeats of one patient's measure before their own noise replaces the cohort's (five
/// differences between successive repeats).
pub const OWN_NOISE_MIN_REPEATS: usize = 6;

/// The minimal detectable change (95 %) of one patient's measure from their own repeats
/// `values` (oldest first), in the measure's unit: `1.96·SD(Δ)` with Δ the differences
/// between successive repeats ([`OwnNoise`], which reads the repeats one at a time). `None`
/// with fewer than [`OWN_NOISE_MIN_REPEATS`] finite repeats.
pub fn own_mdc95(values: &[f64]) -> Option<f64> {
    let mut noise = OwnNoise::default();
    values.iter().for_each(|v| noise.push(*v));
    noise.mdc95()
}

/// One patient's own measurement noise, read one repeat at a time (oldest first) in constant
/// memory: a running mean and sum of squares (Welford 1962, Technometrics 4:419) of the
/// differences Δ between successive repeats.
///
/// Why successive differences: a difference of two repeats has variance `2·SEM²` whatever slow
/// change the patient makes, so `SD(Δ) = √2·SEM` and the MDC95 `1.96·√2·SEM = 1.96·SD(Δ)` (the
/// mean square successive difference, von Neumann et al. 1941, Ann Math Stat 12:153). A steady
/// trend of `b` a repeat adds only `b` to every Δ, which the SD removes; a trend that bends —
/// recovery after stroke is fast early and levels off (Kwakkel, Kollen & Twisk 2006, Stroke
/// 37:2348) — only changes `b` from one repeat to the next, which widens the band a little (on
/// the side of fewer false changes). Residuals about ONE straight line through the whole
/// history would count the bend as noise and widen it far more: on a steep simulated recovery
/// (gain 15 noise SDs in 12 weeks) successive differences overstate the true MDC95 by about a
/// quarter, one line by about 90 % (the `own_noise_of_a_recovery_curve_…` test). Second
/// differences (the variate difference method, Tintner 1940) would be unbiased there but
/// scatter about 25 % more from patient to patient, which matters with six repeats.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct OwnNoise {
    /// Finite repeats read.
    repeats: usize,
    /// The last finite repeat, in the measure's unit.
    previous: f64,
    /// The running mean of Δ.
    mean: f64,
    /// The running sum of squared deviations of Δ from their mean.
    m2: f64,
}

impl OwnNoise {
    /// Reads the next repeat (a non-finite value is skipped).
    pub fn push(&mut self, value: f64) {
        if !value.is_finite() {
            return;
        }
        if self.repeats > 0 {
            let d = value - self.previous;
            let n = self.repeats as f64; // differences after this one
            let delta = d - self.mean;
            self.mean += delta / n;
            self.m2 += delta * (d - self.mean);
        }
        self.previous = value;
        self.repeats += 1;
    }

    /// Finite repeats read so far.
    pub fn repeats(&self) -> usize {
        self.repeats
    }

    /// `1.96·SD(Δ)` in the measure's unit, once [`OWN_NOISE_MIN_REPEATS`] repeats were read.
    pub fn mdc95(&self) -> Option<f64> {
        if self.repeats < OWN_NOISE_MIN_REPEATS {
            return None;
        }
        let differences = (self.repeats - 1) as f64;
        Some(Z_95 * (self.m2.max(0.0) / (differences - 1.0)).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shrout & Fleiss (1979) Table 2: six targets rated by four judges; their ICC(2,1) is
    /// 0.29 (ICC(1,1) 0.17 and ICC(3,1) 0.71 would be the other forms).
    fn shrout_fleiss() -> Vec<Vec<f64>> {
        [
            [9.0, 2.0, 5.0, 8.0],
            [6.0, 1.0, 3.0, 2.0],
            [8.0, 4.0, 6.0, 8.0],
            [7.0, 1.0, 2.0, 6.0],
            [10.0, 5.0, 6.0, 9.0],
            [6.0, 2.0, 4.0, 7.0],
        ]
        .iter()
        .map(|r| r.to_vec())
        .collect()
    }

    #[test]
    fn icc_2_1_matches_shrout_and_fleiss_table_2() {
        let r = test_retest(&shrout_fleiss()).unwrap();
        assert!((r.icc - 0.29).abs() < 0.005, "ICC(2,1) {}", r.icc);
        assert_eq!((r.subjects, r.occasions), (6, 4));
    }

    #[test]
    fn mdc95_is_1_96_root_2_sem_and_sem_follows_icc() {
        let r = test_retest(&shrout_fleiss()).unwrap();
        let all: Vec<f64> = shrout_fleiss().into_iter().flatten().collect();
        let mean = all.iter().sum::<f64>() / all.len() as f64;
        let sd = (all.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 23.0).sqrt();
        assert!((r.sem - sd * (1.0 - r.icc).sqrt()).abs() < 1e-12);
        assert!((r.mdc95 - 1.96 * 2f64.sqrt() * r.sem).abs() < 1e-12);
        assert!((r.mdc95_relative().unwrap() - r.mdc95 / mean).abs() < 1e-12);
    }

    #[test]
    fn repeats_that_agree_exactly_give_icc_one_and_no_detectable_noise() {
        let scores = vec![
            vec![1.0, 1.0, 1.0],
            vec![3.0, 3.0, 3.0],
            vec![7.0, 7.0, 7.0],
        ];
        let r = test_retest(&scores).unwrap();
        assert!((r.icc - 1.0).abs() < 1e-12);
        assert!(r.mdc95.abs() < 1e-12);
    }

    #[test]
    fn noise_between_occasions_lowers_icc_and_widens_mdc_to_its_size() {
        // Eight subjects 0..7 measured four times: exactly, then with an alternating ±2.
        let clean: Vec<Vec<f64>> = (0..8).map(|i| vec![f64::from(i); 4]).collect();
        let noisy: Vec<Vec<f64>> = clean
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let sign = |j: usize| if (i + j).is_multiple_of(2) { 1.0 } else { -1.0 };
                r.iter()
                    .enumerate()
                    .map(|(j, v)| v + 2.0 * sign(j))
                    .collect()
            })
            .collect();
        let (a, b) = (test_retest(&clean).unwrap(), test_retest(&noisy).unwrap());
        assert!((a.icc - 1.0).abs() < 1e-12 && a.mdc95 < 1e-9, "{a:?}");
        assert!(b.icc < 0.8, "{b:?}");
        // Residual SD 2 (≈ 2.3 with the table's degrees of freedom): MDC95 ≈ 2.77·SEM.
        assert!(b.mdc95 > 4.0 && b.mdc95 < 9.0, "{b:?}");
    }

    #[test]
    fn a_table_too_small_ragged_or_with_nan_is_refused_by_name() {
        assert!(matches!(
            test_retest(&[vec![1.0, 2.0]]),
            Err(MetricError::TooShort { len: 1, .. })
        ));
        assert!(matches!(
            test_retest(&[vec![1.0], vec![2.0]]),
            Err(MetricError::TooShort { len: 1, .. })
        ));
        let ragged = test_retest(&[vec![1.0, 2.0], vec![2.0]]).unwrap_err();
        assert!(
            ragged.to_string().contains("occasions per subject"),
            "{ragged}"
        );
        let nan = test_retest(&[vec![1.0, 2.0], vec![2.0, f64::NAN]]).unwrap_err();
        assert!(nan.to_string().contains("subject 1"), "{nan}");
    }

    #[test]
    fn own_noise_needs_six_repeats_and_ignores_a_steady_trend() {
        assert_eq!(own_mdc95(&[1.0, 2.0, 3.0, 4.0, 5.0]), None);
        // A patient improving by exactly 1 a repeat, without noise: no noise at all.
        let trend: Vec<f64> = (0..8).map(f64::from).collect();
        assert!(own_mdc95(&trend).unwrap().abs() < 1e-12);
        // The same trend with an alternating ±0.5: every Δ is 1 ± 1, SD(Δ) ≈ 1.07.
        let noisy: Vec<f64> = trend
            .iter()
            .enumerate()
            .map(|(i, v)| v + if i.is_multiple_of(2) { 0.5 } else { -0.5 })
            .collect();
        let mdc = own_mdc95(&noisy).unwrap();
        assert!((mdc - 1.96 * (8.0f64 / 7.0).sqrt()).abs() < 1e-9, "{mdc}");
    }

    /// A deterministic standard normal sequence (splitmix64 and Box–Muller), fixed seed.
    fn normals(seed: u64, n: usize) -> Vec<f64> {
        let mut state = seed;
        let mut uniform = move || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let (u1, u2) = (uniform().max(1e-300), uniform());
                (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
            })
            .collect()
    }

    /// The choice `OwnNoise` documents, measured: 2000 simulated patients recovering along
    /// `30·(1 − e^(−week/4))` (fast early, levelling off) over 12 weekly repeats with noise of
    /// SD 2, whose true MDC95 is `1.96·√2·2 ≈ 5.54`. Successive differences come within 15 %
    /// of it on average; residuals about one straight line through the history take the
    /// bend for noise and overstate it by more than a third.
    #[test]
    fn own_noise_of_a_recovery_curve_is_nearer_the_truth_from_successive_differences_than_about_one_line()
     {
        let (patients, weeks, sd) = (2000, 12, 2.0);
        let truth = Z_95 * std::f64::consts::SQRT_2 * sd;
        let noise = normals(20261206, patients * weeks);
        let (mut successive, mut about_line) = (0.0, 0.0);
        for p in 0..patients {
            let values: Vec<f64> = (0..weeks)
                .map(|w| {
                    let wf = w as f64;
                    30.0 * (1.0 - (-wf / 4.0).exp()) + sd * noise[p * weeks + w]
                })
                .collect();
            successive += own_mdc95(&values).unwrap();
            // Least squares line through (week, value); residual SD with n − 2 freedoms.
            let n = weeks as f64;
            let mx = (n - 1.0) / 2.0;
            let my = values.iter().sum::<f64>() / n;
            let sxy: f64 = values
                .iter()
                .enumerate()
                .map(|(w, v)| (w as f64 - mx) * (v - my))
                .sum();
            let sxx: f64 = (0..weeks).map(|w| (w as f64 - mx).powi(2)).sum();
            let b = sxy / sxx;
            let rss: f64 = values
                .iter()
                .enumerate()
                .map(|(w, v)| (v - my - b * (w as f64 - mx)).powi(2))
                .sum();
            about_line += Z_95 * std::f64::consts::SQRT_2 * (rss / (n - 2.0)).sqrt();
        }
        let (successive, about_line) = (successive / patients as f64, about_line / patients as f64);
        println!(
            "true MDC95 {truth:.2}; own from successive differences {successive:.2}, about one line {about_line:.2}"
        );
        assert!(
            (1.0..1.3).contains(&(successive / truth)),
            "{successive} vs {truth}"
        );
        assert!(about_line / truth > 1.6, "{about_line} vs {truth}");
        assert!((successive - truth).abs() < (about_line - truth).abs());
    }

    #[test]
    fn own_noise_read_one_at_a_time_is_own_mdc95_of_the_slice() {
        let values: Vec<f64> = normals(7, 40).iter().map(|z| 3.0 + 0.5 * z).collect();
        let mut noise = OwnNoise::default();
        for (i, v) in values.iter().enumerate() {
            noise.push(*v);
            assert_eq!(noise.repeats(), i + 1);
        }
        // The two-pass SD of the differences, computed here afresh.
        let d: Vec<f64> = values.windows(2).map(|w| w[1] - w[0]).collect();
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let sd = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (d.len() - 1) as f64).sqrt();
        assert!((noise.mdc95().unwrap() - 1.96 * sd).abs() < 1e-12);
        assert_eq!(noise.mdc95(), own_mdc95(&values));
    }
}
