//! The patient's arm calibrated from the session's own data (thesis Chapter 4, in its 3-D
//! form `calib::arm3d`): the recorder thread keeps the segment axes measured by the IMUs and
//! the grip points while the arm is tracked, and fits shoulder position and segment lengths
//! when the session ends. Nothing of it runs on the haptic thread.

use calib::{Arm3dCalibration, ArmLoopOptions, ArmLoopSamples, calibrate_arm_3d};
use record::{ArmSetup, TickRecord};

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
    /// the error says why not (too few samples, the wheel hardly turned, …).
    pub fn calibrate(&self) -> Result<Arm3dCalibration, calib::CalibError> {
        let samples = ArmLoopSamples {
            time_s: Some(&self.time_s),
            ..ArmLoopSamples::new(&self.upper, &self.fore, &self.grip)
        };
        calibrate_arm_3d(&samples, &ArmLoopOptions::default())
    }
}
