//! The gentle cue to sit up in whole simulated sessions (issue 42): the simulated patient's
//! trunk leans and twists more the weaker the arm (`gyro_imu::sim::trunk`), a sternum IMU
//! measures it, and the regimen's `[trunk] cue_deg` sets when the station cues.

use super::{Controls, SessionObserver, SessionOptions, SessionReport};
use crate::config::StationConfig;
use arm::MountingMode;
use arm::trunk_cue::{DWELL_S, MIN_INTERVAL_S, SHOWN_S, excursion_deg};
use record::TickRecord;

/// What a test needs of each tick (a whole `TickRecord` per tick would be 80 MB a minute).
#[derive(Clone, Copy, Debug)]
struct Seen {
    t_s: f64,
    exercise: u32,
    cues: u64,
    shown: bool,
    /// The estimated trunk's excursion as the cue reads it, deg (`None`: not tracked).
    excursion_deg: Option<f64>,
    /// The simulated truth's, deg.
    true_excursion_deg: f64,
    commanded_nm: f64,
}

#[derive(Default)]
struct KeepSeen(Vec<Seen>);

impl SessionObserver for KeepSeen {
    fn on_tick(&mut self, r: &TickRecord) {
        let arm = r.arm.unwrap_or_default();
        self.0.push(Seen {
            t_s: r.t_ns as f64 * 1e-9,
            exercise: r.score.exercise_index,
            cues: arm.trunk_cues,
            shown: arm.trunk_cue_shown,
            excursion_deg: arm.trunk_tracked.then(|| excursion_deg(&arm)),
            true_excursion_deg: [
                arm.true_trunk_flexion_rad,
                arm.true_trunk_lean_rad,
                arm.true_trunk_rotation_rad,
            ]
            .iter()
            .fold(0.0_f64, |m, a| m.max(a.abs().to_degrees())),
            commanded_nm: r.wheel.commanded_nm,
        });
    }
}

/// The session's simulated station: a patient whose arm lost `weakness` of its strength,
/// wearing a sternum IMU when `sternum`, set up as with real IMUs (the hold-still first).
fn config(weakness: f64, sternum: bool) -> StationConfig {
    let mut cfg = StationConfig::default();
    cfg.session.exercise = "dial-sine".into();
    cfg.session.duration_s = 600.0;
    cfg.session.seed = 7;
    cfg.sim_patient.weakness = weakness;
    cfg.arm.sternum = sternum;
    cfg.arm.sim_mounting = MountingMode::Guided;
    cfg.validate().unwrap();
    cfg
}

/// Runs `regimen` (TOML) on `cfg`: the report and what was seen of each tick.
fn run(cfg: StationConfig, regimen: Option<regimen::Regimen>) -> (SessionReport, Vec<Seen>) {
    let opts = SessionOptions {
        regimen,
        ..SessionOptions::simulated(cfg)
    };
    let mut keep = KeepSeen::default();
    let report = super::run(&opts, &Controls::default(), &mut keep).unwrap();
    (report, keep.0)
}

/// A dial of 90 s whose target steps between ±70° every 4 s (the wheel held far over, where
/// a weak arm leans), cued at `cue_deg` (`None`: no `[trunk]` table).
fn far_steps(cue_deg: Option<f64>) -> regimen::Regimen {
    let trunk = cue_deg.map_or(String::new(), |d| format!("[trunk]\ncue_deg = {d}\n"));
    let text = format!("{trunk}{FAR_STEPS}");
    regimen::Regimen::from_toml(&text, "test").unwrap()
}

/// The exercise of [`far_steps`].
const FAR_STEPS: &str = "[[exercise]]\nkind = \"dial\"\nduration_s = 90.0\n\
                         [exercise.reference]\nsignal = \"step\"\namplitude_deg = 70.0\nhold_s = 4.0\n";

/// The session times of the cues: where the count steps up.
fn cue_times_s(seen: &[Seen]) -> Vec<f64> {
    seen.windows(2)
        .filter(|w| w[1].cues > w[0].cues)
        .map(|w| w[1].t_s)
        .collect()
}

#[test]
fn a_weak_patient_who_leans_is_cued_after_a_second_beyond_at_most_once_in_20_s_and_a_strong_one_never()
 {
    let cue_deg = 8.0;
    let (report, seen) = run(config(0.6, true), Some(far_steps(Some(cue_deg))));
    let at_s = cue_times_s(&seen);
    // Measured (seed 7): the weak arm's trunk leans past 8° at the far steps; the rate limit
    // then spaces the cues.
    let most = (90.0 / MIN_INTERVAL_S) as usize + 1;
    assert!(
        (2..=most).contains(&at_s.len()),
        "{} cues at {at_s:?} s",
        at_s.len()
    );
    for pair in at_s.windows(2) {
        assert!(pair[1] - pair[0] >= MIN_INTERVAL_S - 1e-6, "{at_s:?}");
    }
    // Each cue came after the estimate had stayed beyond the threshold for the dwell, and the
    // true trunk was there too (within the estimate's 2° bound): no cue from drift alone.
    let dwell_ticks = (DWELL_S * 1000.0) as usize;
    for (i, w) in seen.windows(2).enumerate() {
        if w[1].cues > w[0].cues {
            let before = &seen[i + 2 - dwell_ticks..=i + 1];
            assert!(
                before
                    .iter()
                    .all(|s| s.excursion_deg.is_some_and(|e| e > cue_deg)),
                "a cue at {} s without a second beyond {cue_deg}°",
                w[1].t_s
            );
            assert!(
                before.iter().all(|s| s.true_excursion_deg > cue_deg - 2.0),
                "a cue at {} s the true trunk did not call for",
                w[1].t_s
            );
        }
    }
    // Shown for 4 s after each cue (the last one until the session ends), never otherwise.
    let end_s = seen.last().unwrap().t_s;
    let expected_s: f64 = at_s.iter().map(|t| (end_s - t + 1e-3).min(SHOWN_S)).sum();
    let shown_s = seen.iter().filter(|s| s.shown).count() as f64 * 1e-3;
    eprintln!("weak arm, cue at {cue_deg}°: cues at {at_s:?} s, shown {shown_s:.3} s");
    assert!((shown_s - expected_s).abs() < 0.01, "{shown_s} s shown");
    let named = &report.recorder.measures.named;
    assert_eq!(named["trunk_cues"], at_s.len() as f64);
    assert_eq!(
        report.recorder.exercises[0].scores["trunk_cues"],
        at_s.len() as f64
    );
    // A strong arm does not lean: not one cue even at the lowest threshold, over the
    // estimate's drift about the vertical.
    let lowest = regimen::trunk::MIN_CUE_DEG;
    let (strong, seen) = run(config(0.0, true), Some(far_steps(Some(lowest))));
    assert_eq!(cue_times_s(&seen), Vec::<f64>::new());
    assert_eq!(strong.recorder.measures.named["trunk_cues"], 0.0);
}

#[test]
fn the_cue_never_changes_the_torque() {
    let (_, cued) = run(config(0.6, true), Some(far_steps(Some(10.0))));
    let (_, plain) = run(config(0.6, true), Some(far_steps(None)));
    assert!(cued.last().unwrap().cues > 0, "the cued session gave cues");
    assert_eq!(cued.len(), plain.len());
    for (a, b) in cued.iter().zip(&plain) {
        assert_eq!(
            a.commanded_nm.to_bits(),
            b.commanded_nm.to_bits(),
            "torque differs at {} s",
            a.t_s
        );
    }
    assert!(plain.iter().all(|s| s.cues == 0 && !s.shown));
}

#[test]
fn without_a_sternum_imu_a_cued_regimen_runs_with_no_cue_and_no_error() {
    let (report, seen) = run(config(0.6, false), Some(far_steps(Some(10.0))));
    assert!(seen.iter().all(|s| s.cues == 0 && !s.shown));
    assert!(seen.iter().all(|s| s.excursion_deg.is_none()));
    assert!(!report.recorder.measures.named.contains_key("trunk_cues"));
}

#[test]
fn no_cue_during_the_standard_assessment_however_the_patient_leans() {
    let text = format!("[assessment]\nevery_days = 7\n[trunk]\ncue_deg = 5.0\n{FAR_STEPS}");
    let mut regimen = Some(regimen::Regimen::from_toml(&text, "test").unwrap());
    crate::assessment::Planned::plan(&mut regimen, None, "p1", 1_800_000_000_000, 11).unwrap();
    let course = super::course::build(&config(0.9, true), regimen.as_ref()).unwrap();
    let parts = exercises::AssessmentPart::ALL.len();
    assert_eq!(course.len(), parts + 1);
    assert!(course[..parts].iter().all(|s| s.trunk_cue_deg.is_none()));
    assert_eq!(course[parts].trunk_cue_deg, Some(5.0));
    // A very weak patient leans through the assessment: no cue in it, cues after it.
    let (report, seen) = run(config(0.9, true), regimen);
    let in_assessment: Vec<&Seen> = seen
        .iter()
        .filter(|s| (s.exercise as usize) < parts)
        .collect();
    assert!(
        in_assessment
            .iter()
            .any(|s| s.excursion_deg.is_some_and(|e| e > 5.0 + 3.0)),
        "the trunk leant in the assessment"
    );
    assert!(in_assessment.iter().all(|s| s.cues == 0 && !s.shown));
    assert!(seen.last().unwrap().cues > 0, "the dial after it cues");
    let assessment = &report.recorder.exercises[0].scores;
    assert!(!assessment.contains_key("trunk_cues"), "{assessment:?}");
}
