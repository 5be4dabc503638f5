//! The gentle cue to sit up (issue 42): when the trunk's excursion from the exercise's start
//! posture — its flexion, lean or rotation from the sternum IMU ([`super::trunk`]) — stays
//! beyond the therapist's threshold (the regimen's `[trunk] cue_deg`) for [`DWELL_S`], the
//! patient's screen shows a short sentence for [`SHOWN_S`] and the voice says it.
//!
//! Gentle by construction: one cue per excursion (it comes again only once the trunk was back
//! within [`HYSTERESIS_DEG`] of the threshold, so it never flickers), at most one every
//! [`MIN_INTERVAL_S`], only while an exercise runs (not paused, not in a break, not during the
//! arm's set-up) and never during the standard assessment (its segments carry no threshold:
//! `session::course`). It writes the two cue fields of the tick's arm sample and nothing else:
//! the torque never changes with it. Without a sternum IMU the trunk is never tracked and no
//! cue comes. Allocation-free: a few numbers per tick on the haptic thread.

use record::ArmSample;

/// How long the trunk must stay beyond the threshold before the cue, s: a reach that passes
/// the threshold for a moment is not a posture.
pub const DWELL_S: f64 = 1.0;
/// How far back within the threshold the trunk must come before a new excursion may bring a
/// new cue, deg (the estimate's 2° RMS and the sway must not re-arm it).
pub const HYSTERESIS_DEG: f64 = 3.0;
/// What the rotation about the vertical must exceed beyond the threshold to count, deg. Tilt
/// (flexion, lean) is held by gravity (0.1–0.2° RMS); the rotation only by rests, and between
/// them it drifts by the residual gyro bias (3.4° RMS over a 40-s road without a rest,
/// 4.5° off at a wrong cue measured in `session::trunk_cue_tests` before this allowance): a
/// cue from drift would tell a patient who sits well that they do not.
pub const ROTATION_ALLOWANCE_DEG: f64 = 5.0;
/// The least time between two cues, s: at most three a minute, however the patient moves.
pub const MIN_INTERVAL_S: f64 = 20.0;
/// How long the cue's sentence stays on the screen, s (about twice its reading time).
pub const SHOWN_S: f64 = 4.0;

/// The cue's state through a session.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrunkCue {
    /// The exercise's threshold, deg (`None`: no cue in this exercise).
    threshold_deg: Option<f64>,
    /// How long the trunk has stayed beyond it, s.
    beyond_s: f64,
    /// The trunk came back within the hysteresis since the last cue.
    armed: bool,
    /// Time since the last cue, s (infinite before the first).
    since_last_s: f64,
    /// Time the sentence stays on the screen, s.
    shown_left_s: f64,
    /// Cues given so far.
    cues: u64,
}

impl TrunkCue {
    /// A session's cue, for a first exercise with `threshold_deg` (`None`: no cue).
    pub fn new(threshold_deg: Option<f64>) -> Self {
        Self {
            threshold_deg,
            beyond_s: 0.0,
            armed: true,
            since_last_s: f64::INFINITY,
            shown_left_s: 0.0,
            cues: 0,
        }
    }

    /// A new exercise starts (its start posture taken again) with `threshold_deg`: the
    /// excursion starts afresh; the rate limit carries on.
    pub fn next_exercise(&mut self, threshold_deg: Option<f64>) {
        self.threshold_deg = threshold_deg;
        self.beyond_s = 0.0;
        self.armed = true;
    }

    /// Cues given so far.
    pub fn cues(&self) -> u64 {
        self.cues
    }

    /// One tick of `dt_s`: the trunk in `arm` (tracked or not), the exercise `running`; the
    /// cue's fields written into `arm`. Returns whether a cue was given on this tick.
    pub fn step(&mut self, arm: Option<&mut ArmSample>, running: bool, dt_s: f64) -> bool {
        let dt_s = if dt_s.is_finite() { dt_s.max(0.0) } else { 0.0 };
        self.since_last_s += dt_s;
        self.shown_left_s = (self.shown_left_s - dt_s).max(0.0);
        let Some(arm) = arm else {
            self.beyond_s = 0.0;
            return false;
        };
        let given = self.watch(arm, running, dt_s);
        arm.trunk_cues = self.cues;
        arm.trunk_cue_shown = self.shown_left_s > 0.0;
        given
    }

    fn watch(&mut self, arm: &ArmSample, running: bool, dt_s: f64) -> bool {
        let Some(threshold_deg) = self.threshold_deg.filter(|_| running && arm.trunk_tracked)
        else {
            self.beyond_s = 0.0;
            return false;
        };
        let excursion_deg = excursion_deg(arm);
        if !excursion_deg.is_finite() {
            self.beyond_s = 0.0;
            return false;
        }
        if excursion_deg > threshold_deg {
            self.beyond_s += dt_s;
        } else {
            self.beyond_s = 0.0;
            if excursion_deg < threshold_deg - HYSTERESIS_DEG {
                self.armed = true;
            }
        }
        // A hair under the dwell counts: ticks of 1 ms add up to 0.999999… s.
        let due = self.beyond_s >= DWELL_S - 1e-9 && self.since_last_s >= MIN_INTERVAL_S - 1e-9;
        if !(self.armed && due) {
            return false;
        }
        self.cues += 1;
        self.armed = false;
        self.since_last_s = 0.0;
        self.shown_left_s = SHOWN_S;
        true
    }
}

/// The trunk's excursion the cue reads, deg: the largest of |flexion|, |lean| and |rotation|
/// less [`ROTATION_ALLOWANCE_DEG`] (non-finite when an angle is).
pub fn excursion_deg(arm: &ArmSample) -> f64 {
    let [flexion, lean, rotation] = [
        arm.trunk_flexion_rad,
        arm.trunk_lean_rad,
        arm.trunk_rotation_rad,
    ]
    .map(|a| a.abs().to_degrees());
    if !(flexion.is_finite() && lean.is_finite() && rotation.is_finite()) {
        return f64::NAN;
    }
    flexion.max(lean).max(rotation - ROTATION_ALLOWANCE_DEG)
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 0.001;

    /// A tracked trunk leaning `lean_deg` sideways.
    fn trunk(lean_deg: f64) -> ArmSample {
        ArmSample {
            trunk_tracked: true,
            trunk_lean_rad: lean_deg.to_radians(),
            ..ArmSample::default()
        }
    }

    /// Runs `cue` for `s` seconds with the trunk at `deg`, running or not; the cues given.
    fn hold(cue: &mut TrunkCue, deg: f64, s: f64, running: bool) -> u64 {
        let before = cue.cues();
        for _ in 0..(s / DT).round() as usize {
            cue.step(Some(&mut trunk(deg)), running, DT);
        }
        cue.cues() - before
    }

    #[test]
    fn the_cue_comes_after_a_second_beyond_the_threshold_and_not_for_a_shorter_reach() {
        let mut cue = TrunkCue::new(Some(10.0));
        assert_eq!(hold(&mut cue, 12.0, 0.9, true), 0, "a short reach");
        assert_eq!(hold(&mut cue, 5.0, 0.1, true), 0);
        assert_eq!(hold(&mut cue, 12.0, 0.99, true), 0);
        assert_eq!(hold(&mut cue, 12.0, 0.02, true), 1, "a second beyond");
        let mut shown = trunk(12.0);
        cue.step(Some(&mut shown), true, DT);
        assert!(shown.trunk_cue_shown && shown.trunk_cues == 1, "{shown:?}");
        // Shown for SHOWN_S, then gone.
        hold(&mut cue, 12.0, SHOWN_S, true);
        let mut later = trunk(12.0);
        cue.step(Some(&mut later), true, DT);
        assert!(!later.trunk_cue_shown && later.trunk_cues == 1);
    }

    #[test]
    fn a_trunk_that_stays_leant_or_hovers_at_the_threshold_is_cued_once() {
        let mut cue = TrunkCue::new(Some(10.0));
        assert_eq!(
            hold(&mut cue, 15.0, 120.0, true),
            1,
            "one cue per excursion"
        );
        // Back to just under the threshold and out again: within the hysteresis, no new cue.
        for _ in 0..20 {
            hold(&mut cue, 8.0, 1.0, true);
            assert_eq!(hold(&mut cue, 12.0, 2.0, true), 0);
        }
        // Back upright, out again: the next excursion is cued.
        hold(&mut cue, 2.0, 1.0, true);
        assert_eq!(hold(&mut cue, 12.0, 2.0, true), 1);
    }

    #[test]
    fn cues_come_at_most_once_in_twenty_seconds_however_often_the_trunk_leans() {
        let mut cue = TrunkCue::new(Some(10.0));
        let mut at_s = Vec::new();
        let mut t_s = 0.0;
        // Lean 1.5 s, sit up 0.5 s, for five minutes: an excursion every 2 s.
        for _ in 0..150 {
            for (deg, s) in [(20.0, 1.5), (0.0, 0.5)] {
                for _ in 0..(s / DT).round() as usize {
                    if cue.step(Some(&mut trunk(deg)), true, DT) {
                        at_s.push(t_s);
                    }
                    t_s += DT;
                }
            }
        }
        assert!(at_s.len() >= 14, "{at_s:?}");
        assert!(
            at_s.len() as f64 <= 300.0 / MIN_INTERVAL_S + 1.0,
            "{at_s:?}"
        );
        for pair in at_s.windows(2) {
            assert!(pair[1] - pair[0] >= MIN_INTERVAL_S - 1e-6, "{at_s:?}");
        }
    }

    #[test]
    fn no_cue_without_a_threshold_a_tracked_trunk_or_a_running_exercise() {
        let mut none = TrunkCue::new(None);
        assert_eq!(hold(&mut none, 30.0, 30.0, true), 0, "no [trunk] table");
        let mut paused = TrunkCue::new(Some(10.0));
        assert_eq!(
            hold(&mut paused, 30.0, 30.0, false),
            0,
            "paused or in a break"
        );
        let mut untracked = TrunkCue::new(Some(10.0));
        for _ in 0..30_000 {
            let mut a = ArmSample {
                trunk_tracked: false,
                trunk_lean_rad: 0.5,
                ..ArmSample::default()
            };
            untracked.step(Some(&mut a), true, DT);
            assert!(!a.trunk_cue_shown);
            untracked.step(None, true, DT);
        }
        assert_eq!(untracked.cues(), 0, "no sternum IMU");
        let mut nan = TrunkCue::new(Some(10.0));
        for _ in 0..30_000 {
            nan.step(Some(&mut trunk(f64::NAN)), true, DT);
        }
        assert_eq!(nan.cues(), 0, "a non-finite estimate is no excursion");
        // The assessment's segments carry no threshold: switching to one ends the watch.
        let mut cue = TrunkCue::new(Some(10.0));
        hold(&mut cue, 30.0, 0.9, true);
        cue.next_exercise(None);
        assert_eq!(hold(&mut cue, 30.0, 30.0, true), 0);
    }

    #[test]
    fn every_axis_counts_and_a_new_exercise_starts_the_dwell_afresh() {
        // The rotation, which drifts between rests, counts beyond its allowance only.
        let cued = [
            (12.0, 0.0, 0.0),
            (0.0, -12.0, 0.0),
            (0.0, 0.0, -16.0),
            (0.0, 0.0, 14.0),
        ];
        for ((f, l, r), expected) in cued.into_iter().zip([1, 1, 1, 0]) {
            let mut cue = TrunkCue::new(Some(10.0));
            let mut n = 0;
            for _ in 0..1500 {
                let mut a = ArmSample {
                    trunk_tracked: true,
                    trunk_flexion_rad: f64::to_radians(f),
                    trunk_lean_rad: f64::to_radians(l),
                    trunk_rotation_rad: f64::to_radians(r),
                    ..ArmSample::default()
                };
                n += u64::from(cue.step(Some(&mut a), true, DT));
            }
            assert_eq!(n, expected, "{f} {l} {r}");
        }
        let mut cue = TrunkCue::new(Some(10.0));
        hold(&mut cue, 12.0, 0.9, true);
        cue.next_exercise(Some(10.0));
        assert_eq!(
            hold(&mut cue, 12.0, 0.9, true),
            0,
            "the dwell starts afresh"
        );
    }
}
