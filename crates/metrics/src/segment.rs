//! Splitting a continuous speed profile into movements, and which of them are *discrete*.
//!
//! Smoothness (SPARC, LDLJ) is defined and validated on discrete movements, from rest to rest
//! (Balasubramanian et al. 2015, J NeuroEng Rehabil 12:112; Rohrer et al. 2002, J Neurosci
//! 22:8297, who segment reaches by a speed threshold): a continuous task (a slalom, a sine
//! road) gives long stretches above the threshold whose "smoothness" is not the published
//! measure. A movement here is discrete ([`Movement::discrete`]) when, after Hogan & Sternad
//! 2007 ("On rhythmic and discrete movements: reflections, definitions and implications for
//! motor control", Exp Brain Res 181:13–30: a discrete movement is preceded and followed by
//! a posture, a rest of non-zero duration):
//!
//! 1. its onset and offset are the crossings of the segmentation threshold ([`threshold`]);
//! 2. the speed stays at or below that threshold for at least
//!    [`rest_s`](SegmentParams::rest_s) before its onset and after its offset, inside the
//!    recording (a movement cut by the recording's start or end is not discrete);
//! 3. it lasts at most [`max_discrete_s`](SegmentParams::max_discrete_s) (the bound is ours:
//!    a patient's slowest single reach in Rohrer et al. 2002 took a few seconds).
//!
//! Only discrete movements get a SPARC and an LDLJ.

use serde::{Deserialize, Serialize};

use crate::error::{MetricError, check_fs, check_signal};
use crate::smoothness::{SparcParams, ldlj_speed, sparc};

/// Parameters of [`segment`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentParams {
    /// The speed threshold is this fraction of the whole signal's peak speed, or
    /// [`floor`](Self::floor), whichever is larger. Default 0.05 (5 %), in [0, 1).
    pub onset_fraction: f64,
    /// Absolute floor of the threshold, in the unit of the speed (rad/s for the wheel): below
    /// it nothing counts as moving, however quiet the session. Default 0.05 rad/s (≈ 2.9 °/s).
    pub floor: f64,
    /// Runs above the threshold separated by a gap shorter than this are one movement, s.
    /// Default 0.1 s.
    pub merge_gap_s: f64,
    /// Movements shorter than this (after merging) are dropped, s. Default 0.2 s.
    pub min_duration_s: f64,
    /// A local maximum counts in [`Movement::n_peaks`] only at or above this fraction of the
    /// movement's peak speed. Default 0.1 (10 %).
    pub peak_fraction: f64,
    /// SPARC parameters for each movement.
    pub sparc: SparcParams,
    /// Rest a discrete movement needs before its onset and after its offset (speed at or
    /// below the threshold), s. Default 0.2 s (Hogan & Sternad 2007 ask for a rest of
    /// non-zero duration; 0.2 s is twice the gap merged into one movement).
    #[serde(default = "default_rest_s")]
    pub rest_s: f64,
    /// Longest discrete movement, s. Default 5 s.
    #[serde(default = "default_max_discrete_s")]
    pub max_discrete_s: f64,
}

fn default_rest_s() -> f64 {
    0.2
}

fn default_max_discrete_s() -> f64 {
    5.0
}

impl Default for SegmentParams {
    fn default() -> Self {
        Self {
            onset_fraction: 0.05,
            floor: 0.05,
            merge_gap_s: 0.1,
            min_duration_s: 0.2,
            peak_fraction: 0.1,
            sparc: SparcParams::default(),
            rest_s: default_rest_s(),
            max_discrete_s: default_max_discrete_s(),
        }
    }
}

impl SegmentParams {
    /// Check every field against its allowed range.
    ///
    /// # Errors
    /// [`MetricError::BadParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), MetricError> {
        let check = |field, value: f64, ok: bool, allowed| {
            if ok {
                Ok(())
            } else {
                Err(MetricError::BadParameter {
                    context: "SegmentParams",
                    field,
                    value,
                    allowed,
                })
            }
        };
        let f = self.onset_fraction;
        check("onset_fraction", f, (0.0..1.0).contains(&f), "0 <= x < 1")?;
        let f = self.floor;
        check("floor", f, f.is_finite() && f >= 0.0, "finite and >= 0")?;
        let g = self.merge_gap_s;
        check(
            "merge_gap_s",
            g,
            g.is_finite() && g >= 0.0,
            "finite and >= 0 s",
        )?;
        let d = self.min_duration_s;
        check(
            "min_duration_s",
            d,
            d.is_finite() && d >= 0.0,
            "finite and >= 0 s",
        )?;
        let p = self.peak_fraction;
        check("peak_fraction", p, (0.0..1.0).contains(&p), "0 <= x < 1")?;
        let r = self.rest_s;
        check("rest_s", r, r.is_finite() && r >= 0.0, "finite and >= 0 s")?;
        let m = self.max_discrete_s;
        check(
            "max_discrete_s",
            m,
            m.is_finite() && m > 0.0,
            "finite and > 0 s",
        )?;
        self.sparc.validate()
    }
}

/// One discrete movement found by [`segment`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Movement {
    /// Index of its first sample (the first above the threshold).
    pub start_index: usize,
    /// One past its last sample (the first back below the threshold, or the signal's length):
    /// the movement is `speed[start_index..end_index]`.
    pub end_index: usize,
    /// Its start time from the first sample, s.
    pub start_s: f64,
    /// Its duration `(end_index − start_index) / fs`, s.
    pub duration_s: f64,
    /// Its peak speed, in the unit of the speed (rad/s for the wheel).
    pub peak_speed: f64,
    /// Local maxima of the speed within the movement at or above `peak_fraction` of its peak
    /// (a sample, or a plateau of equal samples, higher than both neighbours; a plateau counts
    /// once, a shelf on the way up or down not at all). 1 for a single smooth submovement.
    pub n_peaks: usize,
    /// Mean speed over peak speed ([`crate::speed_metric`], Rohrer et al. 2002), in (0, 1].
    #[serde(default)]
    pub speed_metric: f64,
    /// Whether it is a discrete movement (the module's definition: rest before and after,
    /// bounded duration); only discrete movements are scored for smoothness.
    #[serde(default)]
    pub discrete: bool,
    /// SPARC of the movement's speed ([`sparc`]); `None` if undefined or not
    /// [`discrete`](Self::discrete).
    pub sparc: Option<f64>,
    /// LDLJ of the movement's speed ([`ldlj_speed`]); `None` if undefined or not
    /// [`discrete`](Self::discrete).
    pub ldlj: Option<f64>,
}

/// The threshold [`segment`] uses on `speed`: `max(onset_fraction · max(speed), floor)`.
#[must_use]
pub fn threshold(speed: &[f64], params: &SegmentParams) -> f64 {
    let peak = speed.iter().copied().fold(0.0, f64::max);
    (params.onset_fraction * peak).max(params.floor)
}

/// Find the discrete movements in a speed profile sampled at `fs_hz` (speed ≥ 0, e.g. rad/s).
///
/// 1. threshold `v_th = max(onset_fraction · max(speed), floor)` ([`threshold`]);
/// 2. a movement starts at the first sample with `speed > v_th` and ends at the first sample
///    back at or below it (one threshold both ways; the gap merging of step 3 is the
///    hysteresis, in time rather than in speed);
/// 3. movements separated by fewer than `merge_gap_s · fs` samples are merged;
/// 4. movements shorter than `min_duration_s` are dropped;
/// 5. a movement is [`discrete`](Movement::discrete) with at least `rest_s` of speed at or
///    below `v_th` on both sides inside the signal (a dropped blip breaks the rest) and at most
///    `max_discrete_s` long (the module's definition).
///
/// Each movement gets its peak speed, number of peaks and speed metric; a discrete one also
/// its SPARC and LDLJ, computed on the samples inside it as given (smooth the speed first:
/// [`crate::speed_profile`]).
///
/// # Errors
/// An empty signal, a non-finite sample (its index is named), `fs_hz` not finite and > 0, or
/// parameters out of range.
pub fn segment(
    speed: &[f64],
    fs_hz: f64,
    params: SegmentParams,
) -> Result<Vec<Movement>, MetricError> {
    check_fs(fs_hz)?;
    params.validate()?;
    check_signal("speed", speed, 1)?;
    let v_th = threshold(speed, &params);
    // Runs above the threshold, half-open [start, end).
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut start = None;
    for (i, &v) in speed.iter().enumerate() {
        match (start, v > v_th) {
            (None, true) => start = Some(i),
            (Some(s), false) => {
                runs.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        runs.push((s, speed.len()));
    }
    let merge_gap = params.merge_gap_s * fs_hz;
    let mut merged: Vec<(usize, usize)> = Vec::with_capacity(runs.len());
    for run in runs {
        match merged.last_mut() {
            Some(last) if ((run.0 - last.1) as f64) < merge_gap => last.1 = run.1,
            _ => merged.push(run),
        }
    }
    let min_len = params.min_duration_s * fs_hz;
    let rest = params.rest_s * fs_hz;
    let max_len = params.max_discrete_s * fs_hz;
    Ok(merged
        .iter()
        .enumerate()
        .filter(|&(_, &(s, e))| (e - s) as f64 >= min_len)
        .map(|(k, &(s, e))| {
            // Rest: from the previous run above the threshold (or the signal's start) to the
            // onset, and from the offset to the next run (or the signal's end).
            let before = s - k.checked_sub(1).map_or(0, |p| merged[p].1);
            let after = merged.get(k + 1).map_or(speed.len(), |n| n.0) - e;
            let rested = s > 0 && e < speed.len() && before as f64 >= rest && after as f64 >= rest;
            let discrete = rested && (e - s) as f64 <= max_len;
            movement(speed, s, e, fs_hz, discrete, &params)
        })
        .collect())
}

/// The movement `speed[s..e]` (from its first sample above a threshold to the first back at
/// or below it), measured: duration, peak speed, speed peaks, speed metric, and for a
/// `discrete` one SPARC and LDLJ; also [`crate::StepResponse::movement`]'s.
pub(crate) fn movement(
    speed: &[f64],
    s: usize,
    e: usize,
    fs_hz: f64,
    discrete: bool,
    params: &SegmentParams,
) -> Movement {
    let v = &speed[s..e];
    let peak = v.iter().copied().fold(0.0, f64::max);
    Movement {
        start_index: s,
        end_index: e,
        start_s: s as f64 / fs_hz,
        duration_s: (e - s) as f64 / fs_hz,
        peak_speed: peak,
        n_peaks: count_peaks(v, params.peak_fraction * peak),
        speed_metric: speed_metric(v).unwrap_or(0.0),
        discrete,
        sparc: discrete
            .then(|| sparc(v, fs_hz, params.sparc).ok())
            .flatten(),
        ldlj: discrete.then(|| ldlj_speed(v, fs_hz).ok()).flatten(),
    }
}

/// A movement's speed metric: mean speed over peak speed, in (0, 1]; `None` for an empty or
/// all-zero profile (Rohrer et al. 2002).
#[must_use]
pub fn speed_metric(speed: &[f64]) -> Option<f64> {
    let peak = speed.iter().copied().fold(0.0, f64::max);
    if speed.is_empty() || peak <= 0.0 || !peak.is_finite() {
        return None;
    }
    let mean = speed.iter().sum::<f64>() / speed.len() as f64;
    Some(mean / peak)
}

/// Local maxima of `v` at or above `min_height`: a sample (or a plateau of equal samples)
/// higher than the samples on both sides of it; an end of the signal counts as a maximum when
/// higher than its one neighbour (a movement cut at the edge of the recording). A plateau
/// counts once (a constant signal is one plateau: one peak); a shelf on the way up or down
/// does not count.
fn count_peaks(v: &[f64], min_height: f64) -> usize {
    let n = v.len();
    let mut count = 0;
    let mut i = 0;
    while i < n {
        // The plateau v[i..=j] of samples equal to v[i].
        let mut j = i;
        while j + 1 < n && v[j + 1] == v[i] {
            j += 1;
        }
        let left_lower = i == 0 || v[i - 1] < v[i];
        let right_lower = j + 1 == n || v[j + 1] < v[i];
        if left_lower && right_lower && v[i] >= min_height {
            count += 1;
        }
        i = j + 1;
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_speed_has_speed_metric_one_and_minimum_jerk_1_over_1_875() {
        assert!((speed_metric(&[0.7; 50]).unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(speed_metric(&[0.0; 5]), None);
        assert_eq!(speed_metric(&[]), None);
        // The speed of a minimum-jerk movement: 30 τ² (1 − τ)², peak 1.875 at τ = ½.
        let n = 10_000;
        let v: Vec<f64> = (0..=n)
            .map(|i| {
                let t = f64::from(i) / f64::from(n);
                30.0 * t * t * (1.0 - t) * (1.0 - t)
            })
            .collect();
        let s = speed_metric(&v).unwrap();
        assert!((s - 1.0 / 1.875).abs() < 1e-3, "{s}");
    }

    #[test]
    fn peaks_count_plateaus_once_and_ignore_small_bumps() {
        assert_eq!(count_peaks(&[0.0, 1.0, 2.0, 2.0, 1.0, 0.0], 0.2), 1);
        assert_eq!(count_peaks(&[0.0, 1.0, 0.5, 1.0, 0.0], 0.1), 2);
        assert_eq!(count_peaks(&[0.0, 1.0, 0.01, 0.05, 0.0], 0.1), 1);
        assert_eq!(count_peaks(&[1.0, 0.5, 0.0], 0.1), 1);
        assert_eq!(count_peaks(&[0.0, 2.0, 2.0, 3.0, 0.0], 0.1), 1);
        assert_eq!(count_peaks(&[0.0, 3.0, 2.0, 2.0, 0.0], 0.1), 1);
        assert_eq!(count_peaks(&[1.0, 1.0, 1.0], 0.1), 1);
    }

    #[test]
    fn short_gaps_merge_and_short_blips_drop() {
        let fs = 100.0;
        let mut v = vec![0.0; 200];
        // Two 0.3 s runs 0.05 s apart (merged), then a 0.05 s blip (dropped).
        v[10..40].fill(1.0);
        v[45..75].fill(1.0);
        v[150..155].fill(1.0);
        let m = segment(&v, fs, SegmentParams::default()).unwrap();
        assert_eq!(m.len(), 1, "{m:?}");
        assert_eq!((m[0].start_index, m[0].end_index), (10, 75));
        assert!((m[0].duration_s - 0.65).abs() < 1e-12);
        // Only 0.1 s of rest before it (it starts at 0.1 s): not discrete, not scored.
        assert!(!m[0].discrete && m[0].sparc.is_none(), "{m:?}");
    }

    /// A speed profile at `fs` of bell-shaped bursts `(onset_s, duration_s)` on rest.
    fn bursts(fs: f64, total_s: f64, at: &[(f64, f64)]) -> Vec<f64> {
        (0..(total_s * fs) as usize)
            .map(|i| {
                let t = i as f64 / fs;
                at.iter()
                    .map(|&(on, d)| {
                        let tau = (t - on) / d;
                        if (0.0..=1.0).contains(&tau) {
                            30.0 * tau.powi(2) * (1.0 - tau).powi(2) / d
                        } else {
                            0.0
                        }
                    })
                    .sum()
            })
            .collect()
    }

    #[test]
    fn only_movements_from_rest_to_rest_within_the_bound_are_discrete_and_scored() {
        let fs = 100.0;
        let p = SegmentParams::default();
        // A 1 s reach with 1 s of rest on both sides: discrete, scored.
        let m = segment(&bursts(fs, 3.0, &[(1.0, 1.0)]), fs, p).unwrap();
        assert_eq!(m.len(), 1);
        assert!(m[0].discrete && m[0].sparc.is_some() && m[0].ldlj.is_some());
        // Cut by the recording's start (no rest observed before it): not discrete.
        let m = segment(&bursts(fs, 3.0, &[(-0.5, 1.0)]), fs, p).unwrap();
        assert_eq!(m.len(), 1);
        assert!(!m[0].discrete && m[0].sparc.is_none() && m[0].ldlj.is_none());
        // Longer than 5 s: not discrete however restful around it.
        let m = segment(&bursts(fs, 10.0, &[(1.0, 7.0)]), fs, p).unwrap();
        assert!(!m[0].discrete, "{m:?}");
        // Two reaches 0.05 s apart (the threshold is crossed between them, beyond the merge
        // gap): two movements, neither rested on the side facing the other.
        let v = bursts(fs, 5.0, &[(1.0, 1.0), (2.05, 1.0)]);
        let m = segment(&v, fs, p).unwrap();
        assert_eq!(m.len(), 2, "{m:?}");
        assert!(m.iter().all(|mv| !mv.discrete && mv.sparc.is_none()));
    }

    #[test]
    fn discrete_bounds_out_of_range_are_named() {
        let p = SegmentParams {
            max_discrete_s: 0.0,
            ..SegmentParams::default()
        };
        let e = segment(&[0.0; 10], 100.0, p).unwrap_err().to_string();
        assert!(e.contains("max_discrete_s"), "{e}");
        let p = SegmentParams {
            rest_s: -1.0,
            ..SegmentParams::default()
        };
        let e = segment(&[0.0; 10], 100.0, p).unwrap_err().to_string();
        assert!(e.contains("rest_s"), "{e}");
    }
}
