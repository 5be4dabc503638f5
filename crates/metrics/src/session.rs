//! Measures of a whole session: the wheel's movements and their smoothness, ranges of motion,
//! time active.

use serde::{Deserialize, Serialize};

use crate::error::{MetricError, check_fs, check_signal};
use crate::filter::speed_profile;
use crate::robot::steering_reversals;
use crate::segment::{Movement, SegmentParams, segment};

/// Parameters of [`session_measures_with`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SessionParams {
    /// Cut-off of the 2nd-order Butterworth low-pass run forward and backward on the wheel's
    /// angular rate before taking its absolute value, Hz. Default 10 Hz (voluntary arm
    /// movement lies below ~5 Hz; SPARC looks no higher than 10 Hz). Not applied when not
    /// below `fs/2`.
    pub lowpass_hz: f64,
    /// Segmentation of the wheel's speed (rad/s).
    pub segment: SegmentParams,
    /// Gap of the steering reversals ([`crate::steering_reversals`]), rad. Default 2°
    /// (0.0349 rad; Markkula & Engström 2006 study gaps of 0.1° to 10°).
    #[serde(default = "default_reversal_gap_rad")]
    pub reversal_gap_rad: f64,
}

fn default_reversal_gap_rad() -> f64 {
    2.0_f64.to_radians()
}

impl Default for SessionParams {
    fn default() -> Self {
        Self {
            lowpass_hz: 10.0,
            segment: SegmentParams::default(),
            reversal_gap_rad: default_reversal_gap_rad(),
        }
    }
}

/// Median and mean of one per-movement measure over a session's movements.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// How many movements had the measure defined.
    pub n: usize,
    /// Median (mean of the two middle values for an even count); `None` when `n = 0`.
    pub median: Option<f64>,
    /// Arithmetic mean; `None` when `n = 0`.
    pub mean: Option<f64>,
}

impl Summary {
    /// No values: `n = 0`, no median, no mean.
    #[must_use]
    pub fn empty() -> Self {
        Self::of([])
    }

    /// Median and mean of the values (NaN-free by construction of the callers).
    #[must_use]
    pub fn of(values: impl IntoIterator<Item = f64>) -> Self {
        let mut v: Vec<f64> = values.into_iter().collect();
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n == 0 {
            return Self {
                n,
                median: None,
                mean: None,
            };
        }
        let median = if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        };
        Self {
            n,
            median: Some(median),
            mean: Some(v.iter().sum::<f64>() / n as f64),
        }
    }
}

/// Range of motion of one joint (or of the wheel) over a session.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointRange {
    /// The joint's name as given.
    pub name: String,
    /// Smallest sample, in the joint's unit (rad for angles).
    pub min: f64,
    /// Largest sample, in the joint's unit.
    pub max: f64,
    /// `max − min`, in the joint's unit.
    pub range: f64,
}

/// Range of motion of one signal: `max − min` of its samples.
///
/// # Errors
/// An empty signal or a non-finite sample (its index is named).
pub fn range_of_motion(name: &str, samples: &[f64]) -> Result<JointRange, MetricError> {
    check_signal(&format!("joint {name:?}"), samples, 1)?;
    let (min, max) = samples
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    Ok(JointRange {
        name: name.to_owned(),
        min,
        max,
        range: max - min,
    })
}

/// Movement measures of a session; serialises to JSON for the therapist's report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SessionMeasures {
    /// Sampling rate of the wheel angle, Hz.
    pub fs_hz: f64,
    /// Length of the recording, `n / fs`, s.
    pub total_s: f64,
    /// Time inside movements (the sum of their durations), s.
    pub active_s: f64,
    /// `active_s / total_s`, in [0, 1].
    pub active_fraction: f64,
    /// The wheel's peak speed over the session (after the low-pass), rad/s.
    pub peak_speed_rad_s: f64,
    /// The speed threshold the segmentation used, rad/s.
    pub threshold_rad_s: f64,
    /// The wheel's movements, in time order.
    pub movements: Vec<Movement>,
    /// How many of them are discrete ([`Movement::discrete`]: from rest to rest, bounded).
    #[serde(default)]
    pub discrete_movements: usize,
    /// SPARC over the discrete movements only (dimensionless, ≤ 0): smoothness is defined on
    /// discrete movements (Balasubramanian et al. 2015), so a continuous task has none.
    pub sparc: Summary,
    /// LDLJ over the discrete movements only (dimensionless).
    pub ldlj: Summary,
    /// Peak speed of each movement, rad/s.
    pub movement_peak_speed_rad_s: Summary,
    /// Duration of each movement, s.
    pub movement_time_s: Summary,
    /// Number of speed peaks of each movement.
    pub n_peaks: Summary,
    /// Speed metric of each movement, mean over peak speed ([`crate::speed_metric`]).
    #[serde(default = "Summary::empty")]
    pub speed_metric: Summary,
    /// Steering reversals of the wheel over every run ([`crate::steering_reversals`] with
    /// `reversal_gap_rad`).
    #[serde(default)]
    pub reversals: usize,
    /// The dose: movements per active minute, an active minute being a minute of the
    /// recording given (the exercise running: the station leaves pauses out), 1/min.
    #[serde(default)]
    pub movements_per_min: f64,
    /// The dose: steering reversals per active minute, 1/min.
    #[serde(default)]
    pub reversals_per_min: f64,
    /// The wheel's range of motion, rad.
    pub wheel_range: JointRange,
    /// Range of motion of each joint given, in the joint's unit, in the order given.
    pub joints: Vec<JointRange>,
}

/// [`session_measures_with`] with [`SessionParams::default`].
///
/// # Errors
/// As [`session_measures_with`].
pub fn session_measures(
    wheel_angle_rad: &[f64],
    fs_hz: f64,
    joints: &[(&str, &[f64])],
) -> Result<SessionMeasures, MetricError> {
    session_measures_with(wheel_angle_rad, fs_hz, joints, &SessionParams::default())
}

/// Movement measures of a session from the wheel angle (rad, sampled at `fs_hz`) and joint
/// signals (any unit, any length; only their ranges are used).
///
/// The wheel's speed is `|filtfilt(dθ/dt)|` ([`crate::speed_profile`] at
/// `params.lowpass_hz`), rad/s; it is segmented by [`segment`] and each movement scored, the
/// discrete ones for smoothness too ([`crate::segment`](mod@crate::segment)). Time active is
/// the sum of the movements' durations.
///
/// # Errors
/// `fs_hz` not finite and > 0, an empty wheel or joint signal, a non-finite sample (the signal
/// and index are named), or parameters out of range.
pub fn session_measures_with(
    wheel_angle_rad: &[f64],
    fs_hz: f64,
    joints: &[(&str, &[f64])],
    params: &SessionParams,
) -> Result<SessionMeasures, MetricError> {
    session_measures_of_runs(&[wheel_angle_rad], fs_hz, joints, params)
}

/// [`session_measures_with`] for a session recorded in several runs (an exercise paused and
/// resumed): the speed profile is taken within each run (no derivative across a pause, where
/// the angle jumps), the runs' speeds are joined and segmented with one threshold, so the
/// movements' indices and times count the joined samples; ranges of motion span every run.
///
/// # Errors
/// As [`session_measures_with`]; an empty run is refused like an empty signal.
pub fn session_measures_of_runs(
    wheel_angle_runs_rad: &[&[f64]],
    fs_hz: f64,
    joints: &[(&str, &[f64])],
    params: &SessionParams,
) -> Result<SessionMeasures, MetricError> {
    check_fs(fs_hz)?;
    for run in wheel_angle_runs_rad {
        check_signal("wheel angle", run, 1)?;
    }
    let wheel_angle_rad = wheel_angle_runs_rad.concat();
    check_signal("wheel angle", &wheel_angle_rad, 1)?;
    let joints = joints
        .iter()
        .map(|(name, x)| range_of_motion(name, x))
        .collect::<Result<Vec<_>, _>>()?;
    let mut wheel_range = range_of_motion("wheel", &wheel_angle_rad)?;
    wheel_range.name = "wheel".to_owned();

    let speed: Vec<f64> = wheel_angle_runs_rad
        .iter()
        .flat_map(|run| speed_profile(run, fs_hz, params.lowpass_hz))
        .collect();
    let movements = segment(&speed, fs_hz, params.segment)?;
    let total_s = wheel_angle_rad.len() as f64 / fs_hz;
    let mut reversals = 0;
    for run in wheel_angle_runs_rad {
        reversals += steering_reversals(run, params.reversal_gap_rad)?;
    }
    let per_min = 60.0 / total_s;
    let active_s: f64 = movements.iter().map(|m| m.duration_s).sum();
    Ok(SessionMeasures {
        fs_hz,
        total_s,
        active_s,
        active_fraction: active_s / total_s,
        peak_speed_rad_s: speed.iter().copied().fold(0.0, f64::max),
        threshold_rad_s: crate::segment::threshold(&speed, &params.segment),
        discrete_movements: movements.iter().filter(|m| m.discrete).count(),
        sparc: Summary::of(movements.iter().filter_map(|m| m.sparc)),
        ldlj: Summary::of(movements.iter().filter_map(|m| m.ldlj)),
        movement_peak_speed_rad_s: Summary::of(movements.iter().map(|m| m.peak_speed)),
        movement_time_s: Summary::of(movements.iter().map(|m| m.duration_s)),
        n_peaks: Summary::of(movements.iter().map(|m| m.n_peaks as f64)),
        speed_metric: Summary::of(movements.iter().map(|m| m.speed_metric)),
        reversals,
        movements_per_min: movements.len() as f64 * per_min,
        reversals_per_min: reversals as f64 * per_min,
        movements,
        wheel_range,
        joints,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_are_differentiated_apart_so_a_jump_between_them_is_no_movement() {
        let fs = 100.0;
        let still_at = |a: f64| vec![a; 200];
        let (first, second) = (still_at(0.0), still_at(1.0));
        let m = session_measures_of_runs(&[&first, &second], fs, &[], &SessionParams::default())
            .unwrap();
        assert!(m.movements.is_empty(), "{:?}", m.movements);
        assert!((m.wheel_range.range - 1.0).abs() < 1e-12);
        assert!((m.total_s - 4.0).abs() < 1e-12);
        assert_eq!(m.peak_speed_rad_s, 0.0);
        // Joined into one signal, the jump would be a burst of speed.
        let joined = [first, second].concat();
        assert!(session_measures(&joined, fs, &[]).unwrap().peak_speed_rad_s > 1.0);
    }

    /// Issue 42: a 60 s slalom is one long movement with many speed peaks; smoothness is not
    /// defined on it, so the session reports none (it was SPARC −6.44 over a 55.5 s
    /// "movement").
    #[test]
    fn a_continuous_slalom_reports_no_smoothness() {
        let fs = 100.0;
        // Weaving ±0.5 rad every 4 s with a faster wobble: the speed never rests for 60 s.
        let angle: Vec<f64> = (0..6000)
            .map(|i| {
                let t = f64::from(i) / fs;
                0.5 * (std::f64::consts::TAU * t / 4.0).sin() + 0.05 * (7.0 * t).sin()
            })
            .collect();
        let m = session_measures(&angle, fs, &[]).unwrap();
        assert!(!m.movements.is_empty());
        assert_eq!(m.discrete_movements, 0, "{:?}", m.movements);
        assert_eq!((m.sparc.n, m.ldlj.n), (0, 0));
        assert!(m.sparc.median.is_none() && m.ldlj.median.is_none());
        // Movement time, speed peaks and the dose are still reported.
        assert!(m.movement_time_s.n > 0 && m.reversals > 20);
    }

    #[test]
    fn summary_median_of_even_and_odd_counts() {
        assert_eq!(Summary::of([3.0, 1.0, 2.0]).median, Some(2.0));
        assert_eq!(Summary::of([4.0, 1.0, 2.0, 3.0]).median, Some(2.5));
        assert_eq!(Summary::of([]).mean, None);
    }

    #[test]
    fn session_measures_round_trip_through_json_and_add_up() {
        // Two 1 s minimum-jerk turns of 0.6 rad, there and back, 1 s of rest around each.
        let fs = 100.0;
        let angle: Vec<f64> = (0..500)
            .map(|i| {
                let t = f64::from(i) / fs;
                let s = |on: f64| {
                    let tau = (t - on).clamp(0.0, 1.0);
                    10.0 * tau.powi(3) - 15.0 * tau.powi(4) + 6.0 * tau.powi(5)
                };
                0.6 * (s(1.0) - s(3.0))
            })
            .collect();
        let elbow: Vec<f64> = angle.iter().map(|a| 2.0 * a + 0.1).collect();
        let m = session_measures(&angle, fs, &[("elbow", &elbow)]).unwrap();
        assert_eq!(m.movements.len(), 2);
        assert_eq!((m.discrete_movements, m.sparc.n, m.ldlj.n), (2, 2, 2));
        // A clean minimum-jerk movement: one peak, SPARC near −1.4 (the reference −1.40583
        // is for the whole profile; the segment is cut at 5 % of the peak).
        assert!(m.movements.iter().all(|mv| mv.n_peaks == 1));
        let s = m.sparc.median.unwrap();
        assert!((-1.6..-1.3).contains(&s), "{s}");
        // Peak speed 1.875 · 0.6 rad / 1 s.
        assert!(
            (m.peak_speed_rad_s - 1.125).abs() < 0.01,
            "{}",
            m.peak_speed_rad_s
        );
        assert!((m.wheel_range.range - 0.6).abs() < 1e-9);
        assert!((m.joints[0].range - 1.2).abs() < 1e-9);
        let sum: f64 = m.movements.iter().map(|mv| mv.duration_s).sum();
        assert!((m.active_s - sum).abs() < 1e-12);
        assert!((m.total_s - 5.0).abs() < 1e-12);
        // The dose: 2 movements and 1 reversal (out, then back) in 5 s.
        assert!((m.movements_per_min - 24.0).abs() < 1e-9);
        assert_eq!(m.reversals, 1);
        assert!((m.reversals_per_min - 12.0).abs() < 1e-9);
        // Cut at 5 % of the peak, a minimum-jerk movement's mean over peak is a little above
        // the whole one's 1/1.875.
        let sm = m.speed_metric.median.unwrap();
        assert!((0.53..0.62).contains(&sm), "{sm}");
        let json = serde_json::to_string(&m).unwrap();
        let back: SessionMeasures = serde_json::from_str(&json).unwrap();
        assert_eq!(back, m);
    }
}
