//! The strength test for the therapist's live view: in every live summary while a strength
//! test runs, the side being pushed, the patient's push the spring balances now and the
//! highest push so far of each side, N·m (the ceiling is the summary's `ceiling_nm`). The
//! recorder runs its own copy of the test (`vehicle::StrengthTest`) on the recorded ticks —
//! the wheel angle and the ceiling the haptic thread's test was given, skipping the ticks it
//! skips (paused, stopping) — so the live figures are the ones the test records.

use record::{TickRecord, Watchdog};
use vehicle::exercise::StrengthSpec;
use vehicle::{StrengthSide, StrengthTest};

/// The summary's names: the side pushed now (1 left, −1 right, 0 resting or done) …
pub const SIDE: &str = "strength_side";
/// … the push the spring balances now, in the side's direction, N·m …
pub const PUSH_NM: &str = "strength_push_nm";
/// … and the highest push so far of the left and right sides, N·m (once each side started).
pub const PEAK_NM: [&str; 2] = ["strength_peak_left_nm", "strength_peak_right_nm"];

/// The strength tests of a session as they run.
#[derive(Debug, Default)]
pub struct LiveStrength {
    /// Each exercise's strength test settings, by index (`None`: no strength test).
    specs: Vec<Option<StrengthSpec>>,
    /// One tick, s.
    dt_s: f64,
    /// The exercise in progress and its test, when it is a strength test.
    test: Option<(u32, StrengthTest)>,
    /// The side now: 1 left, −1 right, 0 neither.
    side: f64,
    /// The push now, N·m.
    push_nm: f64,
}

impl LiveStrength {
    /// For a course whose exercise `i` is a strength test of `specs[i]`, at `dt_s` a tick.
    pub fn new(specs: Vec<Option<StrengthSpec>>, dt_s: f64) -> Self {
        Self {
            specs,
            dt_s,
            ..Self::default()
        }
    }

    /// Takes one tick.
    pub fn add(&mut self, rec: &TickRecord) {
        let index = rec.score.exercise_index;
        let Some(spec) = self.specs.get(index as usize).and_then(Option::as_ref) else {
            self.test = None;
            return;
        };
        if self.test.as_ref().is_none_or(|(i, _)| *i != index) {
            let test = StrengthTest::new(
                spec.stiffness_nm_per_rad,
                spec.ramp_nm_per_s,
                spec.side_s,
                self.dt_s,
            );
            self.test = Some((index, test));
            (self.side, self.push_nm) = (0.0, 0.0);
        }
        let stopping = matches!(rec.wheel.watchdog, Watchdog::Stopping | Watchdog::Stopped);
        if rec.score.paused || stopping {
            return;
        }
        if let Some((_, test)) = self.test.as_mut() {
            let step = test.step(rec.wheel.angle_rad, rec.wheel.ceiling_nm, self.dt_s);
            self.side = step.side.map_or(0.0, StrengthSide::sign);
            self.push_nm = step.push_nm;
        }
    }

    /// The live figures while a strength test runs (none otherwise).
    pub fn extra(&self) -> Vec<(String, f64)> {
        let Some((_, test)) = &self.test else {
            return Vec::new();
        };
        let mut out = vec![
            (SIDE.to_owned(), self.side),
            (PUSH_NM.to_owned(), self.push_nm),
        ];
        let done = test.summary();
        let now = test.side_peak_nm();
        for (k, (side, result)) in [
            (StrengthSide::Left, done.left),
            (StrengthSide::Right, done.right),
        ]
        .into_iter()
        .enumerate()
        {
            let peak = result
                .map(|r| r.peak_nm)
                .or_else(|| now.filter(|(s, _)| *s == side).map(|(_, p)| p));
            if let Some(p) = peak {
                out.push((PEAK_NM[k].to_owned(), p));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use record::WheelSample;

    fn tick(exercise: u32, angle_rad: f64) -> TickRecord {
        let mut rec = TickRecord {
            wheel: WheelSample {
                angle_rad,
                ceiling_nm: 5.0,
                watchdog: Watchdog::Running,
                ..WheelSample::default()
            },
            ..TickRecord::default()
        };
        rec.score.exercise_index = exercise;
        rec
    }

    #[test]
    fn the_live_strength_says_the_side_the_push_and_each_sides_peak_of_strength_tests_only() {
        let spec = StrengthSpec {
            side_s: 3.0,
            ..StrengthSpec::default()
        };
        let k = spec.stiffness_nm_per_rad;
        let mut s = LiveStrength::new(vec![None, Some(spec)], 1e-3);
        s.add(&tick(0, 0.5));
        assert!(s.extra().is_empty(), "a road or dial: nothing");
        let get = |s: &LiveStrength, name: &str| {
            s.extra()
                .into_iter()
                .find(|(n, _)| n == name)
                .map(|(_, v)| v)
        };
        // The patient holds 1 N·m the way asked: the wheel where the spring balances it.
        let mut seen_right = false;
        for n in 0..9000 {
            let side = get(&s, SIDE).unwrap_or(1.0);
            s.add(&tick(1, side * 1.0 / k));
            if n == 2800 {
                assert_eq!(get(&s, SIDE), Some(1.0));
                assert!((get(&s, PUSH_NM).unwrap() - 1.0).abs() < 1e-9);
                assert!((get(&s, PEAK_NM[0]).unwrap() - 1.0).abs() < 1e-9);
                assert_eq!(get(&s, PEAK_NM[1]), None, "the right side has not started");
            }
            seen_right |= get(&s, SIDE) == Some(-1.0);
        }
        assert!(seen_right);
        assert!((get(&s, PEAK_NM[0]).unwrap() - 1.0).abs() < 1e-9);
        assert!((get(&s, PEAK_NM[1]).unwrap() - 1.0).abs() < 1e-9);
        // The next exercise is no strength test.
        s.add(&tick(2, 0.0));
        assert!(s.extra().is_empty());
    }
}
