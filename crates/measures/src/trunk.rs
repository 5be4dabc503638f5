//! The trunk's measures ([`gyro_imu::trunk`]): per exercise and over the session, each axis's
//! largest and mean excursion from the start posture, the share of time beyond the therapist's
//! threshold, and the share of movements compensated with the trunk (the trunk beyond the
//! threshold during the movement), and the gentle cues to sit up the patient was given
//! (`trunk_cues`, in exercises with a cue threshold: [`arm::trunk_cue`]). Fed tick by
//! tick from the arm samples; nothing without a sternum IMU.

use arm::DEFAULT_TRUNK_THRESHOLD_DEG;
use gyro_imu::trunk::{AXES, TrunkAngles, TrunkExcursion};
use record::ArmSample;
use std::collections::BTreeMap;

/// Movements counted, those compensated with the trunk, and the cues to sit up given.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct MovementCount {
    movements: u32,
    compensated: u32,
    cues: u64,
}

/// The trunk's tallies of a session.
#[derive(Clone, Debug)]
pub struct TrunkTally {
    threshold_deg: f64,
    session: Option<TrunkExcursion>,
    session_movements: MovementCount,
    /// Each exercise's, by its index in the course.
    exercises: Vec<Option<(TrunkExcursion, MovementCount)>>,
    /// The movement in progress (`None` between movements).
    movement: Option<(u32, TrunkExcursion)>,
    /// Which exercises, by index in the course, cue the patient (their cues are counted).
    cued: Vec<bool>,
    /// The session's cue count on the last arm sample seen (`ArmSample::trunk_cues`).
    cues_seen: u64,
}

impl Default for TrunkTally {
    fn default() -> Self {
        Self::new(DEFAULT_TRUNK_THRESHOLD_DEG)
    }
}

impl TrunkTally {
    /// Tallies counting excursions beyond `threshold_deg` (a threshold out of range falls
    /// back to the default: the configuration was validated before).
    pub fn new(threshold_deg: f64) -> Self {
        let threshold_deg = if TrunkExcursion::new(threshold_deg).is_ok() {
            threshold_deg
        } else {
            DEFAULT_TRUNK_THRESHOLD_DEG
        };
        Self {
            threshold_deg,
            session: None,
            session_movements: MovementCount::default(),
            exercises: Vec::new(),
            movement: None,
            cued: Vec::new(),
            cues_seen: 0,
        }
    }

    /// The same tallies told which exercises (by index in the course) cue the patient to sit
    /// up: they count the cues (`trunk_cues`), the others do not name it.
    pub fn with_cued(mut self, cued: Vec<bool>) -> Self {
        self.cued = cued;
        self
    }

    fn is_cued(&self, exercise: u32) -> bool {
        self.cued.get(exercise as usize).copied().unwrap_or(false)
    }

    fn excursion(&self) -> TrunkExcursion {
        TrunkExcursion::new(self.threshold_deg).expect("checked in new")
    }

    /// Add one tick of `dt_s` of exercise `exercise` with the arm sample `arm`, the wheel
    /// `moving` (a movement in progress, `metrics::LiveMeasures::moving`).
    pub fn add(&mut self, arm: Option<&ArmSample>, exercise: u32, moving: bool, dt_s: f64) {
        let Some(a) = arm.filter(|a| a.trunk_tracked) else {
            self.end_movement();
            return;
        };
        let angles = TrunkAngles {
            flexion_deg: a.trunk_flexion_rad.to_degrees(),
            lean_deg: a.trunk_lean_rad.to_degrees(),
            rotation_deg: a.trunk_rotation_rad.to_degrees(),
        };
        let fresh = self.excursion();
        self.session.get_or_insert(fresh).add(&angles, dt_s);
        let i = exercise as usize;
        if self.exercises.len() <= i {
            self.exercises.resize(i + 1, None);
        }
        let new_cues = a.trunk_cues.saturating_sub(self.cues_seen);
        self.cues_seen = self.cues_seen.max(a.trunk_cues);
        self.session_movements.cues += new_cues;
        let (excursion, count) = self.exercises[i].get_or_insert((fresh, MovementCount::default()));
        excursion.add(&angles, dt_s);
        count.cues += new_cues;
        if self.movement.is_some_and(|(e, _)| e != exercise) || !moving {
            self.end_movement();
        }
        if moving {
            self.movement
                .get_or_insert((exercise, fresh))
                .1
                .add(&angles, dt_s);
        }
    }

    /// The movement in progress ended: count it.
    fn end_movement(&mut self) {
        let Some((exercise, m)) = self.movement.take() else {
            return;
        };
        let compensated = u32::from(m.compensating());
        for count in [
            Some(&mut self.session_movements),
            self.exercises
                .get_mut(exercise as usize)
                .and_then(|e| e.as_mut())
                .map(|e| &mut e.1),
        ]
        .into_iter()
        .flatten()
        {
            count.movements += 1;
            count.compensated += compensated;
        }
    }

    /// The session's trunk measures into `named` (the movement in progress counted).
    pub fn name_session(&mut self, named: &mut BTreeMap<String, f64>) {
        self.end_movement();
        let cued = self.cued.iter().any(|c| *c);
        if let Some(e) = &self.session {
            name(named, e, self.session_movements, cued);
        }
    }

    /// Exercise `index`'s trunk measures into `named`.
    pub fn name_exercise(&self, index: u32, named: &mut BTreeMap<String, f64>) {
        if let Some(Some((e, count))) = self.exercises.get(index as usize) {
            name(named, e, *count, self.is_cued(index));
        }
    }
}

/// The measures' keys: `trunk_<axis>_max_deg`, `trunk_<axis>_mean_deg` for each of
/// [`AXES`], `trunk_beyond_pct` and `trunk_compensated_movements_pct`, and `trunk_cues` when
/// the patient was `cued` (a 0 then says no cue was needed).
fn name(named: &mut BTreeMap<String, f64>, e: &TrunkExcursion, count: MovementCount, cued: bool) {
    let Some(s) = e.summary() else {
        return;
    };
    for (k, axis) in AXES.iter().enumerate() {
        named.insert(format!("trunk_{axis}_max_deg"), s.max_deg[k]);
        named.insert(format!("trunk_{axis}_mean_deg"), s.mean_deg[k]);
    }
    named.insert("trunk_beyond_pct".to_owned(), 100.0 * s.beyond_share);
    if count.movements > 0 {
        named.insert(
            "trunk_compensated_movements_pct".to_owned(),
            100.0 * f64::from(count.compensated) / f64::from(count.movements),
        );
    }
    if cued {
        named.insert("trunk_cues".to_owned(), count.cues as f64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arm(rotation_deg: f64) -> ArmSample {
        ArmSample {
            trunk_tracked: true,
            trunk_rotation_rad: rotation_deg.to_radians(),
            ..ArmSample::default()
        }
    }

    #[test]
    fn trunk_measures_count_compensated_movements_per_exercise_and_session() {
        let mut t = TrunkTally::new(10.0);
        let dt = 0.01;
        // Exercise 0: a movement to 15° (compensated), then one to 5° (not).
        for deg in [0.0, 8.0, 15.0, 8.0] {
            t.add(Some(&arm(deg)), 0, true, dt);
        }
        t.add(Some(&arm(0.0)), 0, false, dt);
        for deg in [2.0, 5.0, 2.0] {
            t.add(Some(&arm(deg)), 0, true, dt);
        }
        // Exercise 1: untracked ticks are no trunk at all, then one small movement.
        t.add(Some(&ArmSample::default()), 1, true, dt);
        t.add(None, 1, true, dt);
        t.add(Some(&arm(-4.0)), 1, true, dt);
        let mut session = BTreeMap::new();
        t.name_session(&mut session);
        assert!((session["trunk_rotation_max_deg"] - 15.0).abs() < 1e-9);
        assert!((session["trunk_compensated_movements_pct"] - 100.0 / 3.0).abs() < 1e-9);
        assert!((session["trunk_beyond_pct"] - 100.0 / 9.0).abs() < 1e-9);
        assert_eq!(session["trunk_flexion_max_deg"], 0.0);
        let mut first = BTreeMap::new();
        t.name_exercise(0, &mut first);
        assert_eq!(first["trunk_compensated_movements_pct"], 50.0);
        let mut second = BTreeMap::new();
        t.name_exercise(1, &mut second);
        assert!((second["trunk_rotation_max_deg"] - 4.0).abs() < 1e-9);
        assert_eq!(second["trunk_compensated_movements_pct"], 0.0);
        let mut none = BTreeMap::new();
        TrunkTally::default().name_session(&mut none);
        assert!(none.is_empty());
        assert!(
            !session.contains_key("trunk_cues"),
            "no cue threshold: not named"
        );
    }

    #[test]
    fn the_cues_are_counted_per_exercise_and_session_only_where_the_patient_is_cued() {
        let mut t = TrunkTally::new(10.0).with_cued(vec![true, false, true]);
        let cued = |n: u64| ArmSample {
            trunk_cues: n,
            ..arm(12.0)
        };
        // Exercise 0: two cues (the count steps up twice); exercise 1 none; exercise 2 one.
        for n in [0, 1, 1, 1, 2, 2] {
            t.add(Some(&cued(n)), 0, false, 0.01);
        }
        t.add(Some(&cued(2)), 1, false, 0.01);
        t.add(Some(&cued(2)), 2, false, 0.01);
        t.add(Some(&cued(3)), 2, false, 0.01);
        let named = |i: u32| {
            let mut m = BTreeMap::new();
            t.name_exercise(i, &mut m);
            m.get("trunk_cues").copied()
        };
        assert_eq!([named(0), named(1), named(2)], [Some(2.0), None, Some(1.0)]);
        let mut session = BTreeMap::new();
        t.name_session(&mut session);
        assert_eq!(session["trunk_cues"], 3.0);
    }
}
