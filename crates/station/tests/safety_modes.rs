//! Safety invariants 1–3 through the station's own composition of a tick (vehicle road feel +
//! each assist mode + the regimen's effects and model → haptic chain → simulated wheel), for
//! any regimen of short exercises (so the regimen changes mid-stream), any assist mode per
//! exercise, pauses and resumes at any tick, injected wheel and IMU faults (NaN angles,
//! stalls, frozen or saturated encoders), and a stop at the end. Every tick the
//! command sent to the motor is finite, within the ceiling in force (N·m, as recorded) and
//! within the slew limit of the previous one (a ceiling a new exercise lowers holds at once);
//! while paused, and after the stop, it reaches zero within `fade_out_s + ceiling / slew`.
//!
//! The chain alone, on every wheel profile in N·m at the motor: `haptic-wheel`'s
//! `chain::tests::modes`.

use proptest::prelude::*;
use record::Watchdog;
use regimen::Regimen;
use session::config::StationConfig;
use session::course;
use session::faults::FaultSpec;
use session::plant::Plant;

const ASSIST_MODES: &[&str] = &[
    "none",
    "resist",
    "motion",
    "force",
    "hybrid",
    "assist_as_needed",
];
const EXERCISES: &[&str] = &["dial", "straight", "sine", "slalom", "haptic-sweep"];
const FAULTS: &[&str] = &[
    "wheel-nan",
    "wheel-stall",
    "wheel-frozen",
    "wheel-saturated",
    "imu-nan",
];

#[derive(Clone, Debug)]
struct ExerciseCase {
    kind: usize,
    assist: Option<usize>,
    duration_s: f64,
    ceiling_nm: Option<f64>,
    spring_nm_per_rad: Option<f64>,
    constant_nm: Option<f64>,
}

fn any_exercise() -> impl Strategy<Value = ExerciseCase> {
    (
        0..EXERCISES.len(),
        proptest::option::weighted(0.8, 0..ASSIST_MODES.len()),
        1.0f64..1.4,
        proptest::option::of(0.0f64..1.87),
        proptest::option::of(0.0f64..30.0),
        proptest::option::of(-3.0f64..3.0),
    )
        .prop_map(
            |(kind, assist, duration_s, ceiling_nm, spring_nm_per_rad, constant_nm)| ExerciseCase {
                kind,
                assist,
                duration_s,
                ceiling_nm,
                spring_nm_per_rad,
                constant_nm,
            },
        )
}

fn regimen_toml(exercises: &[ExerciseCase]) -> String {
    let mut t = String::new();
    for e in exercises {
        let kind = EXERCISES[e.kind];
        if kind == "haptic-sweep" {
            // Two levels of the spring, the case's (or a stiff one) second: the level
            // changes the model mid-stream, through the same chain.
            let k = e.spring_nm_per_rad.unwrap_or(20.0);
            t.push_str(&format!(
                "[[exercise]]\nkind = \"{kind}\"\nparameter = \"spring\"\n\
                 levels = [0.0, {k:?}]\nlevel_s = {:?}\n",
                e.duration_s
            ));
        } else {
            t.push_str(&format!(
                "[[exercise]]\nkind = \"{kind}\"\nduration_s = {:?}\n",
                e.duration_s
            ));
        }
        if let Some(c) = e.ceiling_nm {
            t.push_str(&format!("[exercise.haptic]\nceiling_nm = {c:?}\n"));
        } else {
            t.push_str("[exercise.haptic]\n");
        }
        if let Some(k) = e.spring_nm_per_rad {
            t.push_str(&format!("[exercise.haptic.model]\nk_nm_per_rad = {k:?}\n"));
        }
        if let Some(level) = e.constant_nm {
            t.push_str(&format!(
                "[[exercise.haptic.effects]]\nkind = {{ constant = {{ level_nm = {level:?} }} }}\n"
            ));
        }
        if let Some(a) = e.assist {
            t.push_str(&format!(
                "[exercise.assist.mode]\nkind = \"{}\"\n",
                ASSIST_MODES[a]
            ));
        }
        t.push('\n');
    }
    t
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    #[test]
    fn the_station_tick_keeps_ceiling_slew_and_fade_in_every_assist_mode_and_transition(
        exercises in proptest::collection::vec(any_exercise(), 1..4),
        slew in 20.0f64..500.0,
        fade in 0.02f64..0.3,
        patient_ceiling in proptest::option::of(0.05f64..1.87),
        pauses in proptest::collection::vec((0u64..3500, 1u64..400), 0..3),
        faults in proptest::collection::vec((0..FAULTS.len(), 0.0f64..2.0, 0.01f64..0.5), 0..3),
        seed in any::<u64>(),
        ticks in 1000u64..3500,
    ) {
        let mut cfg = StationConfig::default();
        cfg.session.seed = seed;
        cfg.haptic.safety.slew_nm_per_s = slew;
        cfg.haptic.safety.fade_out_s = fade;
        cfg.haptic.safety.soft_start_s = 0.05;
        cfg.haptic.safety.ceiling_nm = patient_ceiling;
        cfg.faults = faults
            .iter()
            .map(|&(k, at, d)| FaultSpec::parse(&format!("{}@{at:.3}+{d:.3}", FAULTS[k])).unwrap())
            .collect();
        cfg.validate().unwrap();
        let text = regimen_toml(&exercises);
        let regimen = Regimen::from_toml(&text, "case.toml").unwrap();
        let course = course::build(&cfg, Some(&regimen)).unwrap();
        let mut plant = Plant::simulated(&cfg, course).unwrap();
        let max_nm = cfg.sim_wheel.max_torque_nm;
        let dt = plant.dt_s();
        let allowance = slew * dt + 1e-9;

        let mut last = 0.0f64;
        let mut last_ceiling = plant.ceiling().ceiling_nm;
        let mut paused_since: Option<u64> = None;
        let mut stop_at: Option<u64> = None;
        let mut check = |plant: &mut Plant, k: u64, paused_since: Option<u64>, stop_at: Option<u64>|
         -> Result<(), TestCaseError> {
            let rec = plant.tick();
            let w = &rec.wheel;
            let cmd = w.commanded_nm;
            prop_assert!(cmd.is_finite(), "tick {k}: {cmd}");
            prop_assert!(w.ceiling_nm <= max_nm + 1e-12);
            if let Some(p) = patient_ceiling {
                prop_assert!(w.ceiling_nm <= p + 1e-12, "a regimen raised the patient's ceiling");
            }
            prop_assert!(cmd.abs() <= w.ceiling_nm + 1e-12,
                "tick {k}: {cmd} N·m over the {} N·m ceiling", w.ceiling_nm);
            let from = last.clamp(-last_ceiling.min(w.ceiling_nm), last_ceiling.min(w.ceiling_nm));
            prop_assert!((cmd - from).abs() <= allowance,
                "tick {k}: stepped {from} → {cmd} N·m, slew allows {allowance} ({:?})", w.watchdog);
            let bound_ticks = ((fade + w.ceiling_nm.max(last_ceiling) / slew) / dt).ceil() as u64 + 3;
            for (what, since) in [("pause", paused_since), ("stop", stop_at)] {
                if since.is_some_and(|s| k >= s + bound_ticks) {
                    prop_assert_eq!(cmd, 0.0, "tick {}: not at zero {} ticks after the {}", k, k - since.unwrap(), what);
                }
            }
            if stop_at.is_some_and(|s| k >= s + bound_ticks) {
                prop_assert_eq!(w.watchdog, Watchdog::Stopped);
                prop_assert!(plant.stopped());
            }
            last = cmd;
            last_ceiling = w.ceiling_nm;
            Ok(())
        };
        for k in 0..ticks {
            for &(at, len) in &pauses {
                if k == at {
                    plant.set_paused(true);
                    paused_since.get_or_insert(k);
                }
                if k == at + len {
                    plant.set_paused(false);
                    paused_since = None;
                }
            }
            check(&mut plant, k, paused_since, stop_at)?;
        }
        plant.request_stop();
        stop_at = Some(ticks);
        let stop_ticks = ((fade + max_nm / slew) / dt).ceil() as u64 + 10;
        for k in ticks..ticks + stop_ticks {
            check(&mut plant, k, paused_since, stop_at)?;
        }
        prop_assert!(plant.stopped(), "not stopped {stop_ticks} ticks after the stop");
    }
}

#[test]
fn every_assist_mode_parses_in_a_regimen() {
    for (i, mode) in ASSIST_MODES.iter().enumerate() {
        let case = ExerciseCase {
            kind: i % EXERCISES.len(),
            assist: Some(i),
            duration_s: 1.0,
            ceiling_nm: Some(0.5),
            spring_nm_per_rad: Some(1.0),
            constant_nm: Some(0.2),
        };
        let r = Regimen::from_toml(&regimen_toml(&[case]), "case.toml")
            .unwrap_or_else(|e| panic!("{mode}: {e}"));
        assert!(r.exercises[0].assist.is_some(), "{mode}");
    }
}
