//! The patient's arm calibrated from the session's own data (thesis Chapter 4, in its 3-D
//! form `calib::arm3d`): the recorder thread keeps the segment axes measured by the IMUs and
//! the grip points while the arm is tracked, and fits shoulder position and segment lengths
//! when the session ends. During the session the recursive estimator
//! ([`calib::arm3d::OnlineArm3d`]) takes the same samples ([`OnlineArmCalibration`]), and once
//! its lengths hold still ([`ConvergenceRule`]) the pose the hub's live view draws switches to
//! them. Nothing of it runs on the haptic thread.

use calib::arm3d::{OnlineArm3d, OnlineArm3dOptions};
use calib::{Arm3dCalibration, ArmLoopOptions, ArmLoopSamples, calibrate_arm_3d};
use record::{ArmSetup, OnlineArmCalibrationSample, TickRecord};

/// The physiological range of a fitted shoulder-to-elbow length, m. Segment lengths scale
/// with stature: upper arm 0.186 H and forearm 0.146 H, hand 0.108 H (Drillis & Contini
/// 1966, as tabulated in D. A. Winter, *Biomechanics and Motor Control of Human Movement*,
/// 4th ed., Wiley 2009, Fig. 4.1). Over adult statures 1.40–2.10 m (beyond the 1st and
/// 99th percentiles of adults in anthropometric surveys such as ANSUR II, 2012) that is
/// 0.26–0.39 m; the bounds add a margin for the joint-centre estimate.
pub const UPPER_ARM_M: (f64, f64) = (0.20, 0.45);
/// The physiological range of a fitted elbow-to-grip length, m: the forearm (0.146 H,
/// 0.20–0.31 m over the same statures) plus up to half the hand (0.054 H) to the grip's
/// centre, 0.20–0.42 m, with the same margin.
pub const ELBOW_TO_GRIP_M: (f64, f64) = (0.17, 0.48);

/// A fit whose lengths lie outside the physiological bounds is rejected (never used nor
/// shown as a result): the error says which length, its value and the bounds.
pub fn check_physiological(c: Arm3dCalibration) -> Result<Arm3dCalibration, calib::CalibError> {
    check_lengths(c.params.upper_arm_m, c.params.forearm_m)?;
    Ok(c)
}

/// Whether a fitted upper arm of `upper_arm_m` and elbow-to-grip of `forearm_m` is an adult's.
fn check_lengths(upper_arm_m: f64, forearm_m: f64) -> Result<(), calib::CalibError> {
    for (argument, value, (lo, hi), allowed) in [
        (
            "fitted upper arm length (m)",
            upper_arm_m,
            UPPER_ARM_M,
            "0.20 to 0.45 m for an adult (anthropometric tables); the arm sensors' data \
             did not determine the arm (were they moved, or the session paused long?)",
        ),
        (
            "fitted elbow-to-grip length (m)",
            forearm_m,
            ELBOW_TO_GRIP_M,
            "0.17 to 0.48 m for an adult (anthropometric tables); the arm sensors' data \
             did not determine the arm (were they moved, or the session paused long?)",
        ),
    ] {
        if !(value.is_finite() && (lo..=hi).contains(&value)) {
            return Err(calib::CalibError::OutOfRange {
                argument,
                value,
                allowed,
            });
        }
    }
    Ok(())
}

/// The tick's arm sample when it is one of the fit's (tracking, one in `every` ticks, unit
/// axes, a finite grip).
fn loop_sample(rec: &TickRecord, every: u64) -> Option<record::ArmSample> {
    let arm = rec.arm?;
    let unit = |v: [f64; 3]| {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        (n - 1.0).abs() < 1e-6
    };
    (arm.setup == ArmSetup::Tracking
        && rec.tick.is_multiple_of(every)
        && unit(arm.upper_axis)
        && unit(arm.fore_axis)
        && arm.grip_m.iter().all(|x| x.is_finite()))
    .then_some(arm)
}

/// Samples kept per second of tracking.
const SAMPLES_PER_S: f64 = 50.0;
/// Most recent tracking kept for the fit, s (the fit also models heading drift over it).
const WINDOW_S: f64 = 30.0 * 60.0;

/// Collects the fit's inputs from the tick records (every tick is offered; 50 per second of
/// tracking are kept, the most recent half hour).
#[derive(Debug, Default)]
pub struct ArmLoopCollector {
    every: u64,
    max: usize,
    upper: Vec<[f64; 3]>,
    fore: Vec<[f64; 3]>,
    grip: Vec<[f64; 3]>,
    time_s: Vec<f64>,
}

impl ArmLoopCollector {
    /// A collector for a loop at `rate_hz`.
    pub fn new(rate_hz: f64) -> Self {
        Self {
            every: ((rate_hz / SAMPLES_PER_S).round() as u64).max(1),
            max: (WINDOW_S * SAMPLES_PER_S) as usize,
            ..Default::default()
        }
    }

    /// Offer one tick.
    pub fn add(&mut self, rec: &TickRecord) {
        let Some(arm) = loop_sample(rec, self.every) else {
            return;
        };
        if self.time_s.is_empty() && self.time_s.capacity() < self.max {
            // The half hour's room, resident at once (7 MB): filled as it comes, it would look
            // like growth for the session's first half hour; never reallocated after.
            let max = self.max;
            let room = |_| common::resident::resident_with_capacity(max, [1.0; 3]);
            [self.upper, self.fore, self.grip] = [0, 1, 2].map(room);
            self.time_s = common::resident::resident_with_capacity(max, 1.0);
        }
        if self.time_s.len() >= self.max {
            let half = self.max / 2;
            for v in [&mut self.upper, &mut self.fore, &mut self.grip] {
                v.drain(..half);
            }
            self.time_s.drain(..half);
        }
        self.upper.push(arm.upper_axis);
        self.fore.push(arm.fore_axis);
        self.grip.push(arm.grip_m);
        self.time_s.push(rec.t_ns as f64 * 1e-9);
    }

    /// Samples kept.
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    /// No sample kept.
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// Fit shoulder position and segment lengths (with each IMU's heading offset and drift);
    /// the error says why not (too few samples, the wheel hardly turned, a length outside
    /// the physiological bounds, …).
    pub fn calibrate(&self) -> Result<Arm3dCalibration, calib::CalibError> {
        let samples = ArmLoopSamples {
            time_s: Some(&self.time_s),
            ..ArmLoopSamples::new(&self.upper, &self.fore, &self.grip)
        };
        calibrate_arm_3d(&samples, &ArmLoopOptions::default()).and_then(check_physiological)
    }
}

/// When the calibration during the session counts as converged: estimated every
/// [`ConvergenceRule::EVERY_S`] of session time, it must be steady for
/// [`ConvergenceRule::HOLD_S`] in a row, steady meaning both lengths within the physiological
/// bounds, each length's 1σ standard error below [`ConvergenceRule::MAX_SE_M`], and each
/// changed by less than [`ConvergenceRule::MAX_STEP_M`] since the estimate before. Once
/// converged it stays so: the lengths shown switch once, and do not wander after.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ConvergenceRule {
    last: Option<[f64; 2]>,
    steady_since_s: Option<f64>,
    converged: Option<(f64, [f64; 2])>,
}

impl ConvergenceRule {
    /// Session time between two estimates, s.
    pub const EVERY_S: f64 = 5.0;
    /// Longest standard error of a length counted steady, m.
    pub const MAX_SE_M: f64 = 0.005;
    /// Largest change of a length from one estimate to the next counted steady, m.
    pub const MAX_STEP_M: f64 = 0.005;
    /// How long the estimate must be steady, s (four estimates in a row).
    pub const HOLD_S: f64 = 15.0;
    /// Session time after which an estimate that has not converged is no longer tried, s:
    /// each try solves over every sample kept so far on the recorder thread, so the tries stop
    /// while that is still some milliseconds (the end of the session's batch solve still
    /// calibrates the arm).
    pub const GIVE_UP_S: f64 = 600.0;

    /// Take the estimate at session time `t_s`: lengths (upper arm, elbow to grip) and their
    /// standard errors, m, or `None` while there is none. Returns the lengths once, the
    /// estimate on which the rule first holds.
    pub fn step(&mut self, t_s: f64, estimate: Option<([f64; 2], [f64; 2])>) -> Option<[f64; 2]> {
        if self.converged.is_some() {
            return None;
        }
        let Some((lengths, se)) = estimate else {
            self.last = None;
            self.steady_since_s = None;
            return None;
        };
        let steady = check_lengths(lengths[0], lengths[1]).is_ok()
            && se.iter().all(|s| s.is_finite() && *s < Self::MAX_SE_M)
            && self.last.is_some_and(|last| {
                (0..2).all(|i| (lengths[i] - last[i]).abs() < Self::MAX_STEP_M)
            });
        self.last = Some(lengths);
        if !steady {
            self.steady_since_s = None;
            return None;
        }
        let since = *self.steady_since_s.get_or_insert(t_s);
        if t_s - since >= Self::HOLD_S {
            self.converged = Some((t_s, lengths));
            return Some(lengths);
        }
        None
    }

    /// When it converged (session time, s) and the lengths then, m.
    pub fn converged(&self) -> Option<(f64, [f64; 2])> {
        self.converged
    }
}

/// The arm calibrated during the session, on the recorder thread. Two estimators take the
/// same samples (50 per second of tracking): the recursive one
/// ([`calib::arm3d::OnlineArm3d`], O(1) a sample, about 20 s of memory) and, every
/// [`ConvergenceRule::EVERY_S`], the batch fit of the session so far
/// ([`ArmLoopCollector::calibrate`], with each IMU's heading offset and drift). The
/// [`ConvergenceRule`] runs on the batch fit: the recursive form has no heading-drift term,
/// and the simulated consumer IMUs' heading drift takes its lengths from 0.35 to 0.05 m
/// within a minute of the default session (BENCHMARKS.md, "Arm calibration during the
/// session"), so it never holds still enough to switch to; it is kept and recorded beside
/// for the comparison. Until convergence the batch fit costs a solve every 5 s (some
/// milliseconds a minute of samples in a release build), then nothing.
#[derive(Debug)]
pub struct OnlineArmCalibration {
    recursive: OnlineArm3d,
    every: u64,
    next_estimate_s: f64,
    rule: ConvergenceRule,
    /// The estimate at convergence.
    at_convergence: Option<OnlineArmCalibrationSample>,
}

impl OnlineArmCalibration {
    /// For a loop at `rate_hz`.
    pub fn new(rate_hz: f64) -> Self {
        Self {
            recursive: OnlineArm3d::new(OnlineArm3dOptions {
                // About 20 s of memory at 50 samples a second.
                forgetting: 0.999,
                ..OnlineArm3dOptions::default()
            })
            .expect("the options are valid"),
            every: ((rate_hz / SAMPLES_PER_S).round() as u64).max(1),
            next_estimate_s: ConvergenceRule::EVERY_S,
            rule: ConvergenceRule::default(),
            at_convergence: None,
        }
    }

    /// Offer one tick, after `batch` took it; true on the tick the estimate converges (and
    /// the log says so).
    pub fn add(&mut self, rec: &TickRecord, batch: &ArmLoopCollector) -> bool {
        if let Some(arm) = loop_sample(rec, self.every) {
            // `loop_sample` checked what the estimator checks: nothing is refused.
            let _ = self
                .recursive
                .update(arm.upper_axis, arm.fore_axis, arm.grip_m);
        }
        let t_s = rec.t_ns as f64 * 1e-9;
        if t_s < self.next_estimate_s
            || t_s > ConvergenceRule::GIVE_UP_S
            || self.rule.converged().is_some()
        {
            return false;
        }
        self.next_estimate_s = t_s + ConvergenceRule::EVERY_S;
        let estimate = batch.calibrate().ok();
        let lengths = estimate.as_ref().map(|c| {
            (
                [c.params.upper_arm_m, c.params.forearm_m],
                [c.std_errors.upper_arm_m, c.std_errors.forearm_m],
            )
        });
        let (Some(_), Some(c)) = (self.rule.step(t_s, lengths), estimate) else {
            return false;
        };
        let recursive = self.recursive.estimate().ok();
        let r = |f: fn(&Arm3dCalibration) -> f64| recursive.as_ref().map_or(f64::NAN, f);
        self.at_convergence = Some(OnlineArmCalibrationSample {
            converged_at_s: t_s,
            shoulder_m: c.params.shoulder_m,
            upper_arm_m: c.params.upper_arm_m,
            forearm_m: c.params.forearm_m,
            upper_arm_se_m: c.std_errors.upper_arm_m,
            forearm_se_m: c.std_errors.forearm_m,
            rms_residual_m: c.rms_residual_m,
            samples: c.samples,
            recursive_upper_arm_m: r(|c| c.params.upper_arm_m),
            recursive_forearm_m: r(|c| c.params.forearm_m),
            recursive_rms_residual_m: r(|c| c.rms_residual_m),
        });
        tracing::info!(
            t_s,
            upper_arm_m = c.params.upper_arm_m,
            forearm_m = c.params.forearm_m,
            "arm calibrated during the session: the live pose uses these lengths now"
        );
        true
    }

    /// The lengths to draw the arm with (upper arm, elbow to grip), m, once converged.
    pub fn lengths_m(&self) -> Option<[f64; 2]> {
        self.rule.converged().map(|(_, l)| l)
    }

    /// The estimate at convergence, if it converged.
    pub fn at_convergence(&self) -> Option<&OnlineArmCalibrationSample> {
        self.at_convergence.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimate_converges_once_steady_for_the_hold_time_and_then_holds() {
        let every = ConvergenceRule::EVERY_S;
        let mut rule = ConvergenceRule::default();
        let se = [0.001, 0.001];
        // No estimate yet, then a wandering one (1 cm an estimate).
        assert_eq!(rule.step(every, None), None);
        for k in 0..5 {
            let l = 0.28 + 0.01 * f64::from(k);
            assert_eq!(
                rule.step(every * f64::from(2 + k), Some(([l, 0.33], se))),
                None
            );
        }
        // Steady from the 7th estimate on (its change from the 6th's 0.32 is 0.5 mm).
        let mut out = Vec::new();
        for k in 0..20 {
            let t = every * f64::from(7 + k);
            let l = if k == 0 { 0.32 } else { 0.3205 };
            out.push((t, rule.step(t, Some(([l, 0.33], se)))));
        }
        let first = out.iter().find(|(_, c)| c.is_some()).expect("converges");
        let steady_from_s = every * 7.0;
        assert!(
            first.0 >= steady_from_s + ConvergenceRule::HOLD_S
                && first.0 < steady_from_s + ConvergenceRule::HOLD_S + every,
            "{} s: HOLD_S after the first steady estimate",
            first.0
        );
        assert_eq!(first.1, Some([0.3205, 0.33]));
        assert_eq!(out.iter().filter(|(_, c)| c.is_some()).count(), 1);
        // Later estimates change nothing.
        assert_eq!(rule.step(1e3, Some(([0.40, 0.40], se))), None);
        assert_eq!(rule.converged(), Some((first.0, [0.3205, 0.33])));
    }

    #[test]
    fn an_uncertain_or_unphysiological_or_interrupted_estimate_does_not_converge() {
        let steady_for = |est: &dyn Fn(f64) -> Option<([f64; 2], [f64; 2])>| {
            let mut rule = ConvergenceRule::default();
            (0..40).any(|k| {
                let t = ConvergenceRule::EVERY_S * f64::from(k);
                rule.step(t, est(f64::from(k))).is_some()
            })
        };
        assert!(steady_for(&|_| Some(([0.30, 0.33], [0.001, 0.001]))));
        // Standard error above 5 mm.
        assert!(!steady_for(&|_| Some(([0.30, 0.33], [0.001, 0.006]))));
        // An upper arm of 0.1 m is no adult's.
        assert!(!steady_for(&|_| Some(([0.10, 0.33], [0.001, 0.001]))));
        // Moving 6 mm an estimate.
        assert!(!steady_for(&|t| Some((
            [0.22 + 0.006 * t, 0.33],
            [0.001; 2]
        ))));
        // No estimate every 4th time (tracking lost): never steady for long enough in a row.
        assert!(!steady_for(&|k| {
            (!(k as u64).is_multiple_of(4)).then_some(([0.30, 0.33], [0.001, 0.001]))
        }));
    }

    #[test]
    fn a_calibration_outside_physiological_bounds_is_rejected_with_its_reason() {
        assert!(check_lengths(0.30, 0.33).is_ok());
        let e = check_lengths(-0.068, 0.33).unwrap_err().to_string();
        assert!(
            e.contains("upper arm") && e.contains("-0.068") && e.contains("0.20 to 0.45"),
            "{e}"
        );
        let e = check_lengths(0.30, 0.9).unwrap_err().to_string();
        assert!(e.contains("elbow-to-grip") && e.contains("0.9"), "{e}");
        assert!(check_lengths(f64::NAN, 0.33).is_err());
    }
}
