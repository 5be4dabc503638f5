//! Whole exercises driven: the preview driver and the cruise control through every road of
//! the exercise library, on the pure model and in the world (free car against rapier's solver),
//! scored. Test-only, above `driver`, `exercise`, `world` and `score`, which it uses together
//! (none of them uses another's tests).

use crate::driver::{PreviewDriver, SpeedController};
use crate::exercise::{EXERCISE_NAMES, Exercise, ExerciseSpec, SineSpec};
use crate::model::{DriverInput, Vehicle, VehicleParams, VehicleState};
use crate::score::{DrivingScore, DrivingSummary};
use crate::world::{Side, World, WorldEvent};

/// Drive `ex` with the preview driver and cruise control on the pure model at 200 Hz.
fn drive(ex: &Exercise, driver: &PreviewDriver) -> DrivingSummary {
    let p = VehicleParams::default();
    let road = ex.road.as_ref().expect("road exercise");
    let mut car = Vehicle::new(p.clone(), ex.start_state());
    let mut score = DrivingScore::default();
    let dt = 0.005;
    let mut s_hint = 0.0;
    let mut t = 0.0;
    while t < 600.0 {
        let st = *car.state();
        let here = road.project(st.x_m, st.y_m, s_hint);
        s_hint = here.s_m;
        if ex.is_finished(t, here.s_m) {
            score.complete(t);
            break;
        }
        score.update(&here, st.yaw_rad, road.lane_width_m(), dt);
        let steer = driver.desired_steer_rad(&p, &st, &here, road.as_ref());
        let cruise = SpeedController {
            target_m_s: ex.target_speed_m_s(here.s_m),
            gain_n_per_m_s: 3000.0,
            max_force_n: 8000.0,
        };
        car.step(cruise.input(st.ux_m_s, steer), dt);
        t += dt;
    }
    score.summary()
}

#[test]
fn preview_driver_completes_every_road_exercise_mostly_in_lane() {
    for name in EXERCISE_NAMES.iter() {
        let ex = ExerciseSpec::from_name(name).unwrap().build().unwrap();
        if ex.road.is_none() {
            continue;
        }
        let s = drive(&ex, &PreviewDriver::default());
        eprintln!("{name}: {s:?}");
        assert!(s.completion_time_s.is_some(), "{name} not completed: {s:?}");
        assert!(s.pct_in_lane >= 95.0, "{name}: {s:?}");
        assert!(s.rms_lateral_m < 0.25, "{name}: {s:?}");
    }
}

#[test]
fn larger_sine_amplitude_scores_monotonically_worse() {
    let mut last = 0.0;
    for amplitude_m in [1.0, 3.0, 6.0, 10.0, 15.0] {
        let spec = ExerciseSpec::Sine(SineSpec {
            amplitude_m,
            ..Default::default()
        });
        let s = drive(&spec.build().unwrap(), &PreviewDriver::default());
        eprintln!("A = {amplitude_m}: {s:?}");
        assert!(
            s.rms_lateral_m > last,
            "A = {amplitude_m}: {s:?} not worse than {last}"
        );
        last = s.rms_lateral_m;
    }
}

fn bits(s: &VehicleState) -> [u64; 6] {
    [s.x_m, s.y_m, s.yaw_rad, s.ux_m_s, s.uy_m_s, s.r_rad_s].map(f64::to_bits)
}

/// Step a free world and the same world moved by rapier's pipeline side by side over
/// `seconds` of a drive along the road that weaves across its edges (and through cones)
/// and return the events seen (asserting every step equal, to the bit).
fn free_against_rapier(name: &str, seconds: f64) -> Vec<WorldEvent> {
    let ex = ExerciseSpec::from_name(name).unwrap().build().unwrap();
    let road = ex.road.as_ref().unwrap();
    let new = || {
        World::new(
            VehicleParams::default(),
            ex.start_state(),
            ex.track_layout(),
        )
    };
    let mut free = new().unwrap();
    assert!(free.moves_free(), "{name}");
    let mut rapier = new().unwrap().with_rapier_pipeline();
    let (driver, params) = (PreviewDriver::default(), free.params().clone());
    let mut events = Vec::new();
    let mut s_hint = 0.0;
    for i in 0..(seconds * 1000.0) as usize {
        let t = i as f64 * 1e-3;
        let st = free.state();
        let here = road.project(st.x_m, st.y_m, s_hint);
        s_hint = here.s_m;
        let weave = (0.1 + 0.01 * t) * (std::f64::consts::TAU * 0.3 * t).sin();
        let steer = driver.desired_steer_rad(&params, &st, &here, road.as_ref()) + weave;
        let input = SpeedController {
            target_m_s: 8.0 + 4.0 * (0.2 * t).sin(),
            gain_n_per_m_s: 3000.0,
            max_force_n: 8000.0,
        }
        .input(st.ux_m_s, steer);
        free.step(input, 1e-3);
        rapier.step(input, 1e-3);
        let (a, b) = (free.state(), rapier.state());
        assert!(
            bits(&a) == bits(&b),
            "{name}, step {i}: free {a:?}, rapier {b:?}"
        );
        let fe: Vec<_> = free.drain_events().collect();
        let re: Vec<_> = rapier.drain_events().collect();
        assert_eq!(fe, re, "{name}, step {i}");
        events.extend(fe);
    }
    assert_eq!(free.cone_hits(), rapier.cone_hits());
    events
}

#[test]
fn the_free_car_moves_bit_for_bit_as_rapiers_solver_moves_it() {
    let mut seen = Vec::new();
    for name in EXERCISE_NAMES {
        let ex = ExerciseSpec::from_name(name).unwrap().build().unwrap();
        if ex.track_layout().left_edge.is_empty() {
            continue;
        }
        let events = free_against_rapier(name, 30.0);
        eprintln!("{name}: {} events, identical", events.len());
        seen.extend(events);
    }
    // The drive met every kind of sensor event the exercises have.
    assert!(seen.iter().any(|e| matches!(e, WorldEvent::ConeHit { .. })));
    assert!(
        seen.iter()
            .any(|e| matches!(e, WorldEvent::EdgeTouched { .. }))
    );
    assert!(
        seen.iter()
            .any(|e| matches!(e, WorldEvent::EdgeCleared { off_road: true, .. }))
    );
    assert!(seen.iter().any(|e| matches!(
        e,
        WorldEvent::EdgeCleared {
            off_road: false,
            ..
        }
    )));
}

#[test]
fn driving_through_slalom_cones_reports_each_hit_once() {
    let ex = ExerciseSpec::from_name("slalom").unwrap().build().unwrap();
    let mut layout = ex.track_layout();
    // Put the cones on the straight line the car will drive.
    for c in &mut layout.cones {
        c[1] = 0.0;
    }
    let n = layout.cones.len();
    let start = VehicleState {
        ux_m_s: 10.0,
        ..Default::default()
    };
    let mut world = World::new(VehicleParams::default(), start, layout).unwrap();
    let mut events = Vec::new();
    for _ in 0..20_000 {
        world.step(DriverInput::default(), 1e-3);
        events.extend(world.drain_events());
    }
    let hits: Vec<usize> = events
        .iter()
        .filter_map(|e| match e {
            WorldEvent::ConeHit { cone } => Some(*cone),
            _ => None,
        })
        .collect();
    assert_eq!(hits, (0..n).collect::<Vec<_>>());
    assert_eq!(world.cone_hits(), n);
    // Cones are sensors: the car drives through them unslowed.
    assert!((world.state().ux_m_s - 10.0).abs() < 1e-4);
}

#[test]
fn leaving_the_road_reports_edge_touched_then_off_road() {
    let ex = ExerciseSpec::from_name("straight-road")
        .unwrap()
        .build()
        .unwrap();
    let start = ex.start_state();
    let mut world = World::new(VehicleParams::default(), start, ex.track_layout()).unwrap();
    let mut events = Vec::new();
    for i in 0..6000 {
        let steer = if i < 1500 { 0.02 } else { 0.0 };
        world.step(
            DriverInput {
                steer_rad: steer,
                ..Default::default()
            },
            1e-3,
        );
        events.extend(world.drain_events());
    }
    assert_eq!(
        events,
        vec![
            WorldEvent::EdgeTouched { side: Side::Left },
            WorldEvent::EdgeCleared {
                side: Side::Left,
                off_road: true
            }
        ]
    );
}
