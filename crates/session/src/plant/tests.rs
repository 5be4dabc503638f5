//! The plant meeting the wheel's faults (`session::faults`'s faulty wheel under a simulated
//! session): a wheel unplugged and plugged back, refused torque commands, a saturated
//! encoder — what the exercise, the torque and the recorded ticks do about each.

use super::Plant;
use crate::config::StationConfig;
use crate::config::faults::FaultSpec;
use crate::faults::Stallable;
use haptic_wheel::{SimWheel, SimWheelParams, WheelFault};

fn plant_with(faults: &[&str], grace_s: f64) -> Plant {
    let mut cfg = StationConfig::default();
    cfg.session.exercise = "sine-road".into();
    cfg.session.duration_s = 20.0;
    cfg.session.seed = 7;
    cfg.haptic.replug_grace_s = grace_s;
    cfg.faults = faults
        .iter()
        .map(|f| FaultSpec::parse(f).unwrap())
        .collect();
    cfg.validate().unwrap();
    let course = crate::course::build(&cfg, None).unwrap();
    Plant::simulated(&cfg, course).unwrap()
}

#[test]
fn a_wheel_plugged_back_within_the_grace_resumes_the_paused_exercise_with_a_soft_start() {
    // The sine road's first bend (and its torque) comes after 3 s.
    let mut plant = plant_with(&["wheel-unplug@4", "wheel-replug@5"], 30.0);
    let ticks: Vec<_> = (0..8000).map(|_| plant.tick()).collect();
    let torque = |i: usize| ticks[i].wheel.commanded_nm;
    assert!(
        (3500..4000).all(|i| torque(i).abs() > 0.0),
        "torque before the unplug"
    );
    // Away: no torque, the exercise paused (its clock stands still).
    for t in &ticks[4200..5000] {
        assert_eq!(t.wheel.commanded_nm, 0.0, "tick {}", t.tick);
        assert!(t.score.paused, "tick {}", t.tick);
    }
    assert_eq!(ticks[4200].score.active_s, ticks[4999].score.active_s);
    // Back: still paused until the supervisor's fault clears, then a soft start: the
    // torque grows from zero (by no more than the slew limit) and the exercise resumes.
    let resumed = (5000..8000)
        .find(|&i| !ticks[i].score.paused)
        .expect("resumed");
    assert!(resumed > 5000, "not at once: {resumed}");
    assert_eq!(torque(resumed - 1), 0.0);
    assert_eq!(ticks[resumed].wheel.watchdog.to_string(), "soft-start");
    assert!((6000..8000).any(|i| torque(i).abs() > 0.0), "torque again");
    assert_eq!(plant.wheel_fault(), None);
    assert_eq!(plant.wheel_replugs(), 1);
}

#[test]
fn refused_commands_are_counted_and_recorded_and_a_run_past_20_ms_is_a_fault() {
    // A 10 ms refusal at 4 s: counted and recorded, no fault; a 200 ms one at 6 s: a
    // fault 20 ms in (the haptic loop ends the session on it, as here).
    let mut plant = plant_with(&["wheel-write-fail@4+0.01", "wheel-write-fail@6"], 30.0);
    let mut ticks = Vec::new();
    while plant.wheel_fault().is_none() && ticks.len() < 7000 {
        ticks.push(plant.tick());
    }
    assert_eq!(plant.wheel_fault(), Some(WheelFault::CommandsRefused));
    let refused: Vec<u64> = ticks
        .iter()
        .filter(|t| t.raw.wheel.write_failed)
        .map(|t| t.tick)
        .collect();
    let expected: Vec<u64> = (4000..4010).chain(6000..=6020).collect();
    assert_eq!(refused, expected, "each refusal recorded on /raw/wheel");
    assert_eq!(ticks[4100].wheel.write_failures, 10, "counted on /wheel");
    assert_eq!(ticks.last().unwrap().wheel.write_failures, 31);
    assert_eq!(plant.write_failures(), 31);
    // The short refusal did not stop the exercise.
    assert!(ticks[5000].score.active_s > ticks[4000].score.active_s);
}

#[test]
fn an_unplugged_wheels_refusals_are_its_unplugging_not_counted() {
    let mut plant = plant_with(&["wheel-unplug@1", "wheel-replug@2"], 30.0);
    for _ in 0..3000 {
        plant.tick();
    }
    assert_eq!(plant.write_failures(), 0);
    assert_eq!(plant.wheel_fault(), None);
}

#[test]
fn a_wheel_not_back_within_the_grace_ends_the_session_as_unplugged() {
    let mut plant = plant_with(&["wheel-unplug@1"], 0.5);
    for _ in 0..1400 {
        plant.tick();
    }
    assert_eq!(plant.wheel_fault(), None, "within the grace");
    assert!(plant.wheel_away());
    for _ in 0..200 {
        plant.tick();
    }
    assert_eq!(plant.wheel_fault(), Some(WheelFault::Unplugged));
    // With no grace, at once (as before there was one).
    let mut plant = plant_with(&["wheel-unplug@1"], 0.0);
    for _ in 0..1000 {
        plant.tick();
    }
    assert_eq!(plant.wheel_fault(), None);
    for _ in 0..20 {
        plant.tick();
    }
    assert_eq!(plant.wheel_fault(), Some(WheelFault::Unplugged));
}

#[test]
fn a_saturated_encoder_is_no_reading_the_torque_fades_and_the_car_keeps_the_last_angle() {
    let mut plant = plant_with(&["wheel-saturated@2+0.3"], 30.0);
    let ticks: Vec<_> = (0..4000).map(|_| plant.tick()).collect();
    let half_range = SimWheel::new(SimWheelParams::default()).half_range_rad();
    assert!(
        ticks
            .iter()
            .all(|t| t.wheel.angle_rad.abs() < half_range / 2.0),
        "the end of the range never steered the car"
    );
    assert!(
        ticks[2010..2300]
            .iter()
            .all(|t| t.wheel.watchdog.to_string() == "fault-stale-reading"),
        "no reading while saturated"
    );
    assert!(
        ticks[2150..2300]
            .iter()
            .all(|t| t.wheel.commanded_nm == 0.0)
    );
    assert!(
        ticks[3000..]
            .iter()
            .any(|t| t.wheel.commanded_nm.abs() > 0.0),
        "torque again"
    );
}
