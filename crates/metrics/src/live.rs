//! Measures updated sample by sample for the live display.

use crate::error::{MetricError, check_fs};
use crate::filter::Biquad;
use crate::session::{JointRange, SessionParams};

/// Running measures of a session, updated one sample at a time in O(joints) with no
/// allocation after [`LiveMeasures::new`]: range of motion per joint and of the wheel, time
/// active, the wheel's current speed and the peak speed of the current movement.
///
/// The live values approximate the batch ones of [`crate::session_measures`], which see the
/// whole recording; they differ in these stated ways:
/// - speed is the backward difference `(θ[k] − θ[k−1])·fs` low-passed by the same 2nd-order
///   Butterworth run forward only (causal, so it lags by a few samples; the batch filter runs
///   forward and backward);
/// - a sample is active when its speed is above `max(onset_fraction · peak so far, floor)`
///   (the batch threshold uses the whole session's peak), with no gap merging and no minimum
///   duration.
///
/// Ranges of motion are exact: [`LiveMeasures::joints`] equals [`crate::range_of_motion`] of
/// the samples seen. Non-finite samples are skipped (and counted), never propagated.
#[derive(Debug, Clone)]
pub struct LiveMeasures {
    fs_hz: f64,
    params: SessionParams,
    filter: Option<Biquad>,
    state: [f64; 2],
    prev_angle: Option<f64>,
    wheel: JointRange,
    joints: Vec<JointRange>,
    samples: u64,
    active_samples: u64,
    skipped: u64,
    speed: f64,
    moving: bool,
    session_peak: f64,
    movement_peak: f64,
    movements: u64,
}

fn empty_range(name: &str) -> JointRange {
    JointRange {
        name: name.to_owned(),
        min: f64::INFINITY,
        max: f64::NEG_INFINITY,
        range: 0.0,
    }
}

fn widen(r: &mut JointRange, v: f64) {
    r.min = r.min.min(v);
    r.max = r.max.max(v);
    r.range = r.max - r.min;
}

impl LiveMeasures {
    /// Live measures of a wheel sampled at `fs_hz` and the joints named (their samples come in
    /// this order in [`update`](Self::update)). Uses `params.lowpass_hz`,
    /// `params.segment.onset_fraction` and `params.segment.floor`.
    ///
    /// # Errors
    /// `fs_hz` not finite and > 0, or parameters out of range.
    pub fn new(
        fs_hz: f64,
        joint_names: &[&str],
        params: &SessionParams,
    ) -> Result<Self, MetricError> {
        check_fs(fs_hz)?;
        params.segment.validate()?;
        Ok(Self {
            fs_hz,
            params: *params,
            filter: Biquad::butterworth_lowpass(params.lowpass_hz, fs_hz),
            state: [0.0; 2],
            prev_angle: None,
            wheel: empty_range("wheel"),
            joints: joint_names.iter().map(|n| empty_range(n)).collect(),
            samples: 0,
            active_samples: 0,
            skipped: 0,
            speed: 0.0,
            moving: false,
            session_peak: 0.0,
            movement_peak: 0.0,
            movements: 0,
        })
    }

    /// Take one sample: the wheel angle (rad) and one sample per joint, in the order of the
    /// names given to [`new`](Self::new). Non-finite values are skipped and counted.
    ///
    /// # Errors
    /// [`MetricError::JointCount`] when `joint_samples` has a different length than the
    /// joints tracked (nothing is updated then).
    pub fn update(
        &mut self,
        wheel_angle_rad: f64,
        joint_samples: &[f64],
    ) -> Result<(), MetricError> {
        if joint_samples.len() != self.joints.len() {
            return Err(MetricError::JointCount {
                expected: self.joints.len(),
                got: joint_samples.len(),
            });
        }
        self.samples += 1;
        for (r, &v) in self.joints.iter_mut().zip(joint_samples) {
            if v.is_finite() {
                widen(r, v);
            } else {
                self.skipped += 1;
            }
        }
        if !wheel_angle_rad.is_finite() {
            self.skipped += 1;
            return Ok(());
        }
        widen(&mut self.wheel, wheel_angle_rad);
        let rate = self
            .prev_angle
            .map_or(0.0, |p| (wheel_angle_rad - p) * self.fs_hz);
        self.prev_angle = Some(wheel_angle_rad);
        let smooth = match &self.filter {
            Some(f) => f.step(rate, &mut self.state),
            None => rate,
        };
        self.speed = smooth.abs();
        self.session_peak = self.session_peak.max(self.speed);
        let seg = &self.params.segment;
        let threshold = (seg.onset_fraction * self.session_peak).max(seg.floor);
        let moving = self.speed > threshold;
        if moving && !self.moving {
            self.movement_peak = 0.0;
            self.movements += 1;
        }
        if moving {
            self.active_samples += 1;
            self.movement_peak = self.movement_peak.max(self.speed);
        }
        self.moving = moving;
        Ok(())
    }

    /// The signal stops here and resumes with the next sample (an exercise paused): no speed
    /// is taken across the gap; ranges, time and counts go on.
    pub fn break_signal(&mut self) {
        self.prev_angle = None;
        self.state = [0.0; 2];
        self.speed = 0.0;
        self.moving = false;
    }

    /// Range of motion of each joint so far, in the order given; before a joint's first
    /// finite sample its `min` is +∞, `max` −∞ and `range` 0.
    #[must_use]
    pub fn joints(&self) -> &[JointRange] {
        &self.joints
    }

    /// Range of motion of the wheel so far, rad (same convention as [`joints`](Self::joints)).
    #[must_use]
    pub fn wheel_range(&self) -> &JointRange {
        &self.wheel
    }

    /// Time covered by the samples taken, `n / fs`, s.
    #[must_use]
    pub fn total_s(&self) -> f64 {
        self.samples as f64 / self.fs_hz
    }

    /// Time the wheel was moving (speed above the live threshold), s.
    #[must_use]
    pub fn active_s(&self) -> f64 {
        self.active_samples as f64 / self.fs_hz
    }

    /// The wheel's current speed (causally low-passed), rad/s.
    #[must_use]
    pub fn speed_rad_s(&self) -> f64 {
        self.speed
    }

    /// Whether the wheel is moving now.
    #[must_use]
    pub fn moving(&self) -> bool {
        self.moving
    }

    /// Peak speed of the current movement, or of the last one while at rest, rad/s.
    #[must_use]
    pub fn current_peak_speed_rad_s(&self) -> f64 {
        self.movement_peak
    }

    /// Peak speed over the session so far, rad/s.
    #[must_use]
    pub fn session_peak_speed_rad_s(&self) -> f64 {
        self.session_peak
    }

    /// Movements started so far (onsets of the live threshold).
    #[must_use]
    pub fn movements(&self) -> u64 {
        self.movements
    }

    /// Non-finite samples skipped so far (wheel and joints).
    #[must_use]
    pub fn skipped_samples(&self) -> u64 {
        self.skipped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three minimum-jerk turns of the wheel (0.5, 0.8, 0.3 rad) with rest between, 100 Hz.
    fn three_turns() -> Vec<f64> {
        let fs = 100.0;
        let turns = [(0.5, 1.0, 0.5), (2.5, 0.8, -0.8), (4.0, 1.2, 0.3)];
        (0..600)
            .map(|i| {
                let t = f64::from(i) / fs;
                turns
                    .iter()
                    .map(|&(on, d, a)| {
                        let tau = ((t - on) / d).clamp(0.0, 1.0);
                        a * (10.0 * tau.powi(3) - 15.0 * tau.powi(4) + 6.0 * tau.powi(5))
                    })
                    .sum()
            })
            .collect()
    }

    #[test]
    fn live_time_active_and_movements_track_the_batch_measures() {
        let angle = three_turns();
        let mut live = LiveMeasures::new(100.0, &[], &SessionParams::default()).unwrap();
        for &a in &angle {
            live.update(a, &[]).unwrap();
        }
        let batch = crate::session_measures(&angle, 100.0, &[]).unwrap();
        assert_eq!(batch.movements.len(), 3);
        assert_eq!(live.movements(), 3);
        assert!((live.total_s() - 6.0).abs() < 1e-12);
        // Causal vs zero-phase filter and a running vs whole-session threshold: close, not equal.
        assert!(
            (live.active_s() - batch.active_s).abs() < 0.15,
            "live {} vs batch {}",
            live.active_s(),
            batch.active_s
        );
        let rel = (live.session_peak_speed_rad_s() - batch.peak_speed_rad_s).abs()
            / batch.peak_speed_rad_s;
        assert!(rel < 0.05, "{rel}");
        assert!((live.wheel_range().range - batch.wheel_range.range).abs() < 1e-12);
        assert!(!live.moving());
        // The last movement (0.3 rad in 1.2 s) peaks at 1.875 · 0.3 / 1.2 rad/s.
        assert!((live.current_peak_speed_rad_s() - 1.875 * 0.3 / 1.2).abs() < 0.03);
    }

    #[test]
    fn non_finite_samples_are_skipped_and_a_wrong_joint_count_is_an_error() {
        let mut live = LiveMeasures::new(100.0, &["elbow"], &SessionParams::default()).unwrap();
        live.update(0.1, &[1.0]).unwrap();
        live.update(f64::NAN, &[f64::INFINITY]).unwrap();
        live.update(0.2, &[-1.0]).unwrap();
        assert_eq!(live.skipped_samples(), 2);
        assert_eq!(live.joints()[0].range, 2.0);
        assert!((live.wheel_range().range - 0.1).abs() < 1e-12);
        let err = live.update(0.0, &[]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "live measures track 1 joint(s) but got 0 sample(s)"
        );
    }
}
