//! The patient's arm calibrated from the session's own data (thesis Chapter 4, in its 3-D
//! form `calib::arm3d`): the recorder thread keeps the segment axes measured by the IMUs and
//! the grip points while the arm is tracked, and fits shoulder position and segment lengths
//! when the session ends. Nothing of it runs on the haptic thread.

use calib::{Arm3dCalibration, ArmLoopOptions, ArmLoopSamples, calibrate_arm_3d};
use record::{ArmSetup, TickRecord};

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
        let Some(arm) = rec.arm else { return };
        let unit = |v: [f64; 3]| {
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            (n - 1.0).abs() < 1e-6
        };
        if arm.setup != ArmSetup::Tracking
            || !rec.tick.is_multiple_of(self.every)
            || !unit(arm.upper_axis)
            || !unit(arm.fore_axis)
            || !arm.grip_m.iter().all(|x| x.is_finite())
        {
            return;
        }
        if self.time_s.is_empty() && self.time_s.capacity() < self.max {
            // The half hour's room, resident at once (7 MB): filled as it comes, it would look
            // like growth for the session's first half hour; never reallocated after.
            let max = self.max;
            let room = |_| crate::resident::resident_with_capacity(max, [1.0; 3]);
            [self.upper, self.fore, self.grip] = [0, 1, 2].map(room);
            self.time_s = crate::resident::resident_with_capacity(max, 1.0);
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

#[cfg(test)]
mod tests {
    use super::*;

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
