//! The prescription, exactly: every exercise runs for its prescribed duration (its road
//! continued as long as needed, never driven off its end) and the session's active time is
//! the sum of the prescription.

use super::{Controls, SessionObserver, SessionOptions};
use crate::config::StationConfig;
use record::{TickRecord, Watchdog};
use regimen::Regimen;

/// Active (unpaused) time per exercise, s, and the furthest the car got along each road, m.
#[derive(Default)]
struct PerExercise {
    active_ticks: Vec<u64>,
    furthest_m: Vec<f64>,
}

impl SessionObserver for PerExercise {
    fn on_tick(&mut self, record: &TickRecord) {
        let i = record.score.exercise_index as usize;
        if self.active_ticks.len() <= i {
            self.active_ticks.resize(i + 1, 0);
            self.furthest_m.resize(i + 1, 0.0);
        }
        // The fade-out after the last exercise is not exercise time.
        if !record.score.paused
            && matches!(
                record.wheel.watchdog,
                Watchdog::SoftStart | Watchdog::Running
            )
        {
            self.active_ticks[i] += 1;
        }
        if let Some(v) = record.vehicle {
            self.furthest_m[i] = self.furthest_m[i].max(v.s_m);
        }
    }
}

/// The patient, who presses a wheel button when "Ready?" shows after a rest (the next
/// exercise waits for them), around what the test observes.
struct ReadyAfterRests<'a> {
    controls: &'a Controls,
    seen: &'a mut PerExercise,
}

impl SessionObserver for ReadyAfterRests<'_> {
    fn on_tick(&mut self, record: &TickRecord) {
        if self.controls.break_now().kind == super::BreakKind::Ready {
            super::buttons::space(self.controls);
        }
        self.seen.on_tick(record);
    }
}

/// Run `regimen` simulated as fast as possible at `loop_rate_hz`; each exercise's active
/// time, s, and how far short of its road's end the car stopped, m.
fn run_regimen(regimen: &Regimen, loop_rate_hz: f64) -> Vec<(f64, f64)> {
    let mut cfg = StationConfig::default();
    cfg.session.loop_rate_hz = loop_rate_hz;
    // As `telerehab run --regimen` does: the duration is only a safety cap.
    cfg.session.duration_s = 4.0 * 3600.0;
    cfg.validate().unwrap();
    let opts = SessionOptions {
        regimen: Some(regimen.clone()),
        ..SessionOptions::simulated(cfg.clone())
    };
    let mut seen = PerExercise::default();
    let controls = Controls::default();
    let mut patient = ReadyAfterRests {
        controls: &controls,
        seen: &mut seen,
    };
    let report = super::run(&opts, &controls, &mut patient).unwrap();
    assert!(!report.haptic.stopped_early, "{:?}", report.haptic);
    let lengths: Vec<f64> = super::course::entries(&cfg, Some(regimen))
        .unwrap()
        .iter()
        .map(|e| e.exercise.build().unwrap().length_m)
        .collect();
    assert_eq!(seen.active_ticks.len(), lengths.len());
    seen.active_ticks
        .iter()
        .zip(&seen.furthest_m)
        .zip(lengths)
        .map(|((ticks, furthest), length)| (*ticks as f64 / loop_rate_hz, length - furthest))
        .collect()
}

/// Check every exercise of `regimen` ran its prescription within 1 s, on the road.
fn assert_runs_as_prescribed(regimen: &Regimen, loop_rate_hz: f64, origin: &str) {
    let ran = run_regimen(regimen, loop_rate_hz);
    let mut total_s = 0.0;
    // A haptic sweep runs one exercise per level.
    let entries: Vec<_> = regimen
        .exercises
        .iter()
        .flat_map(regimen::RegimenEntry::expand)
        .collect();
    assert_eq!(ran.len(), entries.len(), "{origin}");
    for ((active_s, left_m), entry) in ran.iter().zip(&entries) {
        let planned_s = entry.exercise.build().unwrap().planned_duration_s();
        let name = entry.exercise.name();
        assert!(
            (active_s - planned_s).abs() <= 1.0,
            "{origin}: {name} ran {active_s:.2} s of {planned_s} s prescribed"
        );
        if !entry.exercise.build().unwrap().is_dial() {
            assert!(
                *left_m > exercises::exercise::LEAD_OUT_M,
                "{origin}: {name} reached its road's end ({left_m:.1} m left)"
            );
        }
        total_s += active_s;
    }
    let planned = regimen.planned_duration_s().unwrap();
    assert!(
        (total_s - planned).abs() <= 1.0,
        "{origin}: {total_s:.2} s active of {planned} s"
    );
}

#[test]
fn every_exercise_kind_runs_its_prescribed_duration_past_the_end_of_its_shape() {
    // Each shape as short and fast as allowed, prescribed for longer than it lasts.
    let text = r#"
[[exercise]]
kind = "straight"
length_m = 10.0
speed_m_s = 25.0
duration_s = 6.0
[[exercise]]
kind = "sine"
wavelength_m = 40.0
amplitude_m = 1.0
periods = 1
speed_m_s = 20.0
duration_s = 6.0
[[exercise]]
kind = "triangle"
wavelength_m = 40.0
amplitude_m = 1.0
corner_radius_m = 5.0
periods = 1
speed_m_s = 20.0
duration_s = 6.0
[[exercise]]
kind = "clothoid"
length_m = 20.0
end_curvature_1_m = 0.02
unwind_m = 10.0
speed_m_s = 20.0
duration_s = 6.0
[[exercise]]
kind = "sharp-turns"
count = 1
straight_m = 10.0
radius_m = 20.0
angle_deg = 30.0
speed_m_s = 20.0
duration_s = 6.0
[[exercise]]
kind = "s-bend"
radius_m = 20.0
angle_deg = 20.0
speed_m_s = 20.0
duration_s = 6.0
[[exercise]]
kind = "lane-change"
count = 1
offset_m = 1.0
transition_m = 20.0
hold_m = 5.0
speed_m_s = 20.0
duration_s = 6.0
[[exercise]]
kind = "slalom"
cone_count = 1
cone_spacing_m = 10.0
weave_m = 0.5
lane_width_m = 4.0
speed_m_s = 12.0
duration_s = 6.0
[[exercise]]
kind = "dial"
duration_s = 3.0
[[exercise]]
kind = "haptic-sweep"
levels = [0.0, 0.5]
level_s = 2.0
"#;
    let regimen = Regimen::from_toml(text, "every kind").unwrap();
    // Every road here is continued: prescribed for 1 s it would be shorter.
    for e in &regimen.exercises {
        let built = e.exercise.build().unwrap();
        let short = e.exercise.with_duration_s(1.0).build().unwrap();
        assert!(
            built.is_dial() || built.length_m > short.length_m,
            "{}",
            e.exercise.name()
        );
    }
    assert_runs_as_prescribed(&regimen, 250.0, "every kind");
}

/// A shipped regimen (regimens/NAME.toml) at 100 Hz: its real durations, about 10 s of CPU.
fn shipped_regimen_runs_as_prescribed(name: &str) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../regimens")
        .join(format!("{name}.toml"));
    let regimen = Regimen::load(&path).unwrap();
    assert_runs_as_prescribed(&regimen, 100.0, &path.display().to_string());
}

#[test]
fn the_shipped_easy_regimen_runs_its_prescribed_durations() {
    shipped_regimen_runs_as_prescribed("easy");
}

#[test]
fn the_shipped_medium_regimen_runs_its_prescribed_durations() {
    shipped_regimen_runs_as_prescribed("medium");
}

#[test]
fn the_shipped_hard_regimen_runs_its_prescribed_durations() {
    shipped_regimen_runs_as_prescribed("hard");
}

#[test]
fn the_shipped_pedals_regimen_runs_its_prescribed_durations() {
    shipped_regimen_runs_as_prescribed("pedals");
}

/// Appendix E's sweeps (22 minutes as shipped) with 2 s levels: each level one exercise of
/// its prescribed time, the sweeps' levels and models as shipped.
#[test]
fn the_shipped_appendix_e_regimen_runs_every_level_for_its_time_when_shortened() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../regimens/appendix-e.toml");
    let mut regimen = Regimen::load(&path).unwrap();
    for e in &mut regimen.exercises {
        if let exercises::ExerciseSpec::HapticSweep(s) = &mut e.exercise {
            s.level_s = 2.0;
        }
    }
    assert_eq!(regimen.planned_duration_s().unwrap(), 44.0);
    assert_runs_as_prescribed(&regimen, 100.0, "appendix-e, 2 s levels");
}

#[test]
fn every_shipped_regimen_is_tested() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../regimens");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["appendix-e", "easy", "hard", "medium", "pedals"],
        "add a test for each"
    );
}

/// The dial's target as a session runs it: (exercise time, s; target, rad) of every
/// unpaused tick.
#[derive(Default)]
struct DialTargets(Vec<(f64, f64)>);

impl SessionObserver for DialTargets {
    fn on_tick(&mut self, record: &TickRecord) {
        if !record.score.paused {
            self.0
                .push((record.score.active_s, record.wheel.target_rad));
        }
    }
}

#[test]
fn a_dials_target_drifts_into_the_right_neglected_side_over_the_exercise() {
    // No sine around the centre: the target is the drifting centre itself.
    let regimen = Regimen::from_toml(
        "[patient]\nneglected_side = \"right\"\n\n[[exercise]]\nkind = \"dial\"\n\
         duration_s = 10.0\ndrift_deg = 40.0\n\
         reference = { signal = \"sine\", amplitude_deg = 0.0, frequency_rad_s = 1.0 }\n",
        "drift",
    )
    .unwrap();
    let mut cfg = StationConfig::default();
    cfg.session.duration_s = 60.0;
    cfg.validate().unwrap();
    let opts = SessionOptions {
        regimen: Some(regimen),
        ..SessionOptions::simulated(cfg)
    };
    let mut targets = DialTargets::default();
    let report = super::run(&opts, &Controls::default(), &mut targets).unwrap();
    assert!(!report.haptic.stopped_early, "{:?}", report.haptic);
    let at = |t_s: f64| {
        targets
            .0
            .iter()
            .find(|(t, _)| *t >= t_s)
            .map(|(_, target)| target.to_degrees())
            .unwrap()
    };
    // Negative angles are the patient's right: 0 → −20° → −40°, evenly.
    assert!(at(0.0).abs() < 0.5, "{}", at(0.0));
    assert!((at(5.0) + 20.0).abs() < 0.5, "{}", at(5.0));
    assert!((at(9.9) + 40.0).abs() < 0.5, "{}", at(9.9));
}
