//! The 1 kHz haptic thread allocates nothing after start-up, on every exercise, in every
//! assist mode and through the simulated faults: a counting global allocator counts every
//! allocation made on the thread that runs the loop (`support/counting_alloc.rs`), over whole
//! simulated sessions run as fast as the machine allows while a second thread drains the
//! recorder ring like the recorder does. (The real wheel's faults, on the kernel backend:
//! `real_wheel_session.rs`.)
#[path = "support/counting_alloc.rs"]
mod counting_alloc;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use record::TickRecord;
use session::config::StationConfig;
use session::haptic::{self, Pacing};
use session::plant::Plant;
use session::{Controls, course};

/// Run `cfg`'s session for `seconds` of simulated time at full speed and return the
/// allocations made on the haptic thread and the ticks it ran.
fn allocations_in(cfg: &StationConfig, seconds: f64) -> (u64, u64) {
    allocations_paced(cfg, seconds, Pacing::Max)
}

/// The same, paced by `pacing` (real time: the loop sleeps to each absolute deadline).
fn allocations_paced(cfg: &StationConfig, seconds: f64, pacing: Pacing) -> (u64, u64) {
    let course = course::build(cfg, None).unwrap();
    let mut plant = Plant::simulated(cfg, course).unwrap();
    allocations_of_plant(&mut plant, cfg, seconds, pacing)
}

/// Run `plant` for `seconds` of `cfg`'s loop and return the allocations made on the haptic
/// thread and the ticks it ran.
fn allocations_of_plant(
    plant: &mut Plant,
    cfg: &StationConfig,
    seconds: f64,
    pacing: Pacing,
) -> (u64, u64) {
    let (mut producer, mut consumer) = rtrb::RingBuffer::<TickRecord>::new(4096);
    let done = Arc::new(AtomicBool::new(false));
    let drain = {
        let done = done.clone();
        std::thread::spawn(move || {
            while !done.load(Ordering::Acquire) {
                while consumer.pop().is_ok() {}
                std::thread::yield_now();
            }
        })
    };
    let total_ticks = (seconds * cfg.session.loop_rate_hz) as u64;
    let controls = Controls::default();
    let clock = clock::Clock::real();
    let (outcome, allocations) = counting_alloc::allocations_of(|| {
        haptic::run(
            plant,
            &mut producer,
            total_ticks,
            pacing,
            false,
            &controls,
            &clock,
        )
    });
    done.store(true, Ordering::Release);
    drain.join().unwrap();
    (allocations, outcome.ticks)
}

fn config(exercise: &str, assist: Option<&str>) -> StationConfig {
    let mut cfg = StationConfig::default();
    cfg.session.exercise = exercise.into();
    cfg.session.seed = 11;
    cfg.assist = assist.map(|kind| {
        serde_json::from_value(serde_json::json!({ "mode": { "kind": kind } })).unwrap()
    });
    cfg
}

#[test]
fn the_haptic_thread_allocates_nothing_on_any_exercise() {
    let mut offenders = Vec::new();
    for name in exercises::exercise::EXERCISE_NAMES {
        let (allocs, ticks) = allocations_in(&config(name, None), 6.0);
        eprintln!("{name}: {allocs} allocations in {ticks} ticks");
        assert!(ticks >= 6000, "{name} ran {ticks} ticks");
        if allocs > 0 {
            offenders.push((name, allocs));
        }
    }
    assert!(
        offenders.is_empty(),
        "allocations on the haptic thread: {offenders:?}"
    );
}

#[test]
fn the_haptic_thread_allocates_nothing_with_a_sternum_imu_on_the_trunk() {
    // The trunk's simulation and estimate run beside the arm's on the 1 kHz path; 8 s lets
    // its fusion settle and take the start posture.
    let mut cfg = config("sine-road", None);
    cfg.arm.sternum = true;
    let (allocs, ticks) = allocations_in(&cfg, 8.0);
    eprintln!("sine-road with a sternum IMU: {allocs} allocations in {ticks} ticks");
    assert!(ticks >= 8000, "ran {ticks} ticks");
    assert_eq!(
        allocs, 0,
        "allocations on the haptic thread with a sternum IMU"
    );
}

#[test]
fn the_haptic_thread_allocates_nothing_while_it_cues_the_trunk() {
    // A weak arm holding far dial steps leans past the regimen's cue threshold: the cue's
    // watch, its dwell and its cues run on the 1 kHz path.
    let mut cfg = config("dial-sine", None);
    cfg.arm.sternum = true;
    cfg.sim_patient.weakness = 0.6;
    // The set-up's hold-still gives the trunk's fusion the rest it starts from.
    cfg.arm.sim_mounting = arm::MountingMode::Guided;
    // (Seed 7: with the others' seed, 11, this patient's trunk gave no cue in 60 s.)
    cfg.session.seed = 7;
    let text = "[trunk]\ncue_deg = 5.0\n[[exercise]]\nkind = \"dial\"\nduration_s = 60.0\n\
                [exercise.reference]\nsignal = \"step\"\namplitude_deg = 70.0\nhold_s = 4.0\n";
    let regimen = regimen::Regimen::from_toml(text, "cued").unwrap();
    let course = course::build(&cfg, Some(&regimen)).unwrap();
    let mut plant = Plant::simulated(&cfg, course).unwrap();
    let (allocs, ticks) = allocations_of_plant(&mut plant, &cfg, 90.0, Pacing::Max);
    eprintln!(
        "a cued dial with a sternum IMU: {allocs} allocations in {ticks} ticks, {} cues",
        plant.trunk_cues()
    );
    assert!(
        plant.trunk_cues() >= 1,
        "the cue ran: {} cues",
        plant.trunk_cues()
    );
    assert_eq!(allocs, 0, "allocations on the haptic thread while cueing");
}

#[test]
fn the_haptic_thread_allocates_nothing_in_any_assist_mode() {
    let mut offenders = Vec::new();
    for kind in [
        "none",
        "resist",
        "motion",
        "force",
        "hybrid",
        "assist_as_needed",
    ] {
        for exercise in ["sine-road", "slalom", "dial-step"] {
            let (allocs, ticks) = allocations_in(&config(exercise, Some(kind)), 4.0);
            eprintln!("{kind} on {exercise}: {allocs} allocations in {ticks} ticks");
            // A loop that stopped at once would allocate nothing too.
            assert!(ticks >= 4000, "{kind} on {exercise} ran {ticks} ticks");
            if allocs > 0 {
                offenders.push((kind, exercise, allocs));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "allocations on the haptic thread: {offenders:?}"
    );
}

#[test]
fn the_haptic_thread_allocates_nothing_through_every_simulated_fault() {
    use session::config::faults::{FaultKind, FaultSpec};
    let mut offenders = Vec::new();
    for kind in FaultKind::ALL {
        for exercise in ["sine-road", "slalom", "dial-sine"] {
            let mut cfg = config(exercise, Some("motion"));
            // Each fault at 1 s, and the one it ends (a replug, a hub back) a second later.
            cfg.faults = vec![FaultSpec {
                kind,
                at_s: 1.0,
                duration_s: None,
            }];
            let follow = match kind {
                FaultKind::WheelReplug => Some(FaultKind::WheelUnplug),
                FaultKind::ImuReplug => Some(FaultKind::ImuUnplug),
                FaultKind::HubUp => Some(FaultKind::HubDown),
                _ => None,
            };
            if let Some(first) = follow {
                cfg.faults.insert(
                    0,
                    FaultSpec {
                        kind: first,
                        at_s: 0.5,
                        duration_s: None,
                    },
                );
            }
            let (allocs, ticks) = allocations_in(&cfg, 3.0);
            eprintln!("{kind:?} on {exercise}: {allocs} allocations in {ticks} ticks");
            // The fault at 1 s was reached and played (a fault that ends the session ends it
            // after that, within a fade-out).
            assert!(ticks > 1050, "{kind:?} on {exercise} ran {ticks} ticks");
            if allocs > 0 {
                offenders.push((kind, exercise, allocs));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "allocations on the haptic thread: {offenders:?}"
    );
}

/// The real-time path too: the loop sleeping to each absolute deadline allocates nothing
/// (1 s of a road and of the dial, each tick waited for on the wall clock).
#[test]
fn the_haptic_thread_allocates_nothing_while_it_sleeps_to_its_deadlines() {
    for exercise in ["sine-road", "dial-sine"] {
        let (allocs, ticks) =
            allocations_paced(&config(exercise, Some("motion")), 1.0, Pacing::RealTime);
        eprintln!("real time on {exercise}: {allocs} allocations in {ticks} ticks");
        assert!(ticks >= 1000, "{exercise} ran {ticks} ticks");
        assert_eq!(
            allocs, 0,
            "allocations on the haptic thread in real time on {exercise}"
        );
    }
}
